//! How a front end spells an option, so that one check's message names it
//! as its user wrote it (`--b` on the command line, `b` in Python), and the
//! error every refusal of [`super`] is.

use std::fmt;

/// Which front end asked.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Spelling {
    /// `--b 0.2`, `--eps housner`.
    Cli,
    /// `b=0.2`, `eps="housner"`.
    Python,
}

impl Spelling {
    /// The option `key` (written as the library names it, `auto_tol`) as
    /// the user writes it: `--auto-tol`, or `auto_tol`.
    pub fn key(self, key: &str) -> String {
        match self {
            Spelling::Cli => format!("--{}", key.replace('_', "-")),
            Spelling::Python => python_keyword(key).to_string(),
        }
    }

    /// The option `key` set to `value`: `--eps housner`, or `eps="housner"`.
    pub fn set(self, key: &str, value: &str) -> String {
        match self {
            Spelling::Cli => format!("{} {value}", self.key(key)),
            Spelling::Python => format!("{}={value:?}", python_keyword(key)),
        }
    }

    /// The option `key` set to a number: `--alpha -0.1`, or `alpha=-0.1`
    /// (unquoted, as Python writes a number).
    pub fn set_number(self, key: &str, value: impl std::fmt::Display) -> String {
        match self {
            Spelling::Cli => format!("{} {value}", self.key(key)),
            Spelling::Python => format!("{}={value}", python_keyword(key)),
        }
    }

    /// Several options, as a user gives them together: `--b --h`, or `b and h`.
    pub fn keys(self, keys: &[&str]) -> String {
        let each: Vec<String> = keys.iter().map(|k| self.key(k)).collect();
        match self {
            Spelling::Cli => each.join(" "),
            Spelling::Python => each.join(" and "),
        }
    }

    /// A message of the library's, written with the command line's
    /// options (`--auto-tol`, `--direct`), in this front end's words: for
    /// Python the keyword a caller wrote, `auto_tol`, `direct=True` for a
    /// switch, `source` for `--from` (a word Python reserves). The ask
    /// layer's own refusals are spelt as they are made; this is for the
    /// rest, the errors and warnings of the commands' work.
    pub fn respell(self, text: &str) -> String {
        match self {
            Spelling::Cli => text.to_string(),
            Spelling::Python => pythonic(text),
        }
    }

    /// Every string of every `warnings` list in an answer, at any depth,
    /// [`Spelling::respell`]ed.
    pub fn respell_warnings(self, answer: &mut serde_json::Value) {
        if self == Spelling::Python {
            pythonic_warnings(answer);
        }
    }
}

/// The Python keyword of the option `key`: its own name, but `from`
/// (a word Python reserves), which Python calls `source`.
fn python_keyword(key: &str) -> &str {
    match key {
        "from" => "source",
        k => k,
    }
}

/// Command-line switches, which Python sets as `name=True`.
const SWITCHES: &[&str] = &["direct", "vector"];

/// `text` with every `--option` written as Python's keyword.
fn pythonic(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(at) = rest.find("--") {
        let (before, from) = rest.split_at(at);
        out.push_str(before);
        let starts = from[2..]
            .chars()
            .next()
            .is_some_and(|c| c.is_ascii_lowercase());
        let glued = out
            .chars()
            .last()
            .is_some_and(|c| c.is_alphanumeric() || c == '-');
        if !starts || glued {
            out.push_str("--");
            rest = &from[2..];
            continue;
        }
        let name_len = from[2..]
            .find(|c: char| !(c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-'))
            .unwrap_or(from.len() - 2);
        let name = from[2..2 + name_len].trim_end_matches('-');
        match name {
            "from" => out.push_str("source"),
            n if SWITCHES.contains(&n) => {
                out.push_str(n);
                out.push_str("=True");
            }
            n => out.push_str(&n.replace('-', "_")),
        }
        rest = &from[2 + name.len()..];
    }
    out.push_str(rest);
    out
}

fn pythonic_warnings(value: &mut serde_json::Value) {
    use serde_json::Value;
    match value {
        Value::Object(map) => {
            for (k, v) in map.iter_mut() {
                match (k.as_str(), v) {
                    ("warnings", Value::Array(items)) => {
                        for item in items {
                            if let Value::String(s) = item {
                                *s = pythonic(s);
                            } else {
                                pythonic_warnings(item);
                            }
                        }
                    }
                    (_, v) => pythonic_warnings(v),
                }
            }
        }
        Value::Array(items) => items.iter_mut().for_each(pythonic_warnings),
        _ => {}
    }
}

/// A request that cannot be resolved: what is wrong, the options named as
/// the user spelt them.
#[derive(Debug, Clone, PartialEq)]
pub struct AskError(pub String);

impl fmt::Display for AskError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for AskError {}

impl AskError {
    /// The error of option `key`: `--mu: <message>`.
    pub fn of(sp: Spelling, key: &str, e: impl fmt::Display) -> AskError {
        AskError(format!("{}: {e}", sp.key(key)))
    }
}

/// A true/false option as deserialised from Python keywords: `True` or
/// `False` alone. The default reader takes any value by its truth, so that
/// `direct="no"` ran the records. One function per keyword, so that the
/// message names it.
fn strict_bool<'de, D: serde::Deserializer<'de>>(
    d: D,
    key: &'static str,
) -> Result<bool, D::Error> {
    struct Strict(&'static str);
    impl serde::de::Visitor<'_> for Strict {
        type Value = bool;
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            write!(f, "True or False for `{}`", self.0)
        }
        fn visit_bool<E: serde::de::Error>(self, v: bool) -> Result<bool, E> {
            Ok(v)
        }
    }
    d.deserialize_any(Strict(key))
}

/// [`strict_bool`] for `direct`.
pub(super) fn strict_direct<'de, D: serde::Deserializer<'de>>(d: D) -> Result<bool, D::Error> {
    strict_bool(d, "direct")
}

/// [`strict_bool`] for `vector`.
pub(super) fn strict_vector<'de, D: serde::Deserializer<'de>>(d: D) -> Result<bool, D::Error> {
    strict_bool(d, "vector")
}

/// Levels given by `key` (`--pga`, `--at`), each a positive number, or the
/// first that is not named as given.
pub(super) fn positive_levels(
    levels: &[f64],
    key: &str,
    sp: Spelling,
) -> Result<Vec<f64>, AskError> {
    match levels.iter().find(|x| !(**x > 0.0 && x.is_finite())) {
        Some(bad) => Err(AskError(format!(
            "{}: levels must be positive",
            sp.set_number(key, bad)
        ))),
        None => Ok(levels.to_vec()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_front_end_spells_its_options() {
        assert_eq!(Spelling::Cli.key("auto_tol"), "--auto-tol");
        assert_eq!(Spelling::Python.key("auto_tol"), "auto_tol");
        assert_eq!(Spelling::Cli.set("eps", "housner"), "--eps housner");
        assert_eq!(Spelling::Python.set("eps", "housner"), "eps=\"housner\"");
        assert_eq!(Spelling::Cli.keys(&["b", "h"]), "--b --h");
        assert_eq!(Spelling::Python.keys(&["b", "h"]), "b and h");
    }

    #[test]
    fn options_become_keywords_and_the_rest_stays() {
        assert_eq!(
            pythonic("--b and --h must be positive (m); got b = -0.2"),
            "b and h must be positive (m); got b = -0.2"
        );
        assert_eq!(
            pythonic("use --direct (the nonlinear model)"),
            "use direct=True (the nonlinear model)"
        );
        assert_eq!(pythonic("--auto-tol 0: give"), "auto_tol 0: give");
        assert_eq!(pythonic("(--from paper)"), "(source paper)");
        // Not options: a range, a rule of dashes, a path, a negative number.
        for same in ["1--2", "----", "a/b--c.AT2", "-1 --", "x -- y"] {
            assert_eq!(pythonic(same), same);
        }
    }

    #[test]
    fn warnings_at_any_depth_and_nothing_else() {
        let mut v = serde_json::json!({
            "note": "--direct",
            "warnings": ["use --direct"],
            "blocks": [{"fragility": {"warnings": ["--years 5"]}}],
        });
        pythonic_warnings(&mut v);
        assert_eq!(v["note"], "--direct");
        assert_eq!(v["warnings"][0], "use direct=True");
        assert_eq!(v["blocks"][0]["fragility"]["warnings"][0], "years 5");
    }
}
