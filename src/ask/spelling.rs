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
            Spelling::Python => key.to_string(),
        }
    }

    /// The option `key` set to `value`: `--eps housner`, or `eps="housner"`.
    pub fn set(self, key: &str, value: &str) -> String {
        match self {
            Spelling::Cli => format!("{} {value}", self.key(key)),
            Spelling::Python => format!("{key}={value:?}"),
        }
    }

    /// The option `key` set to a number: `--alpha -0.1`, or `alpha=-0.1`
    /// (unquoted, as Python writes a number).
    pub fn set_number(self, key: &str, value: impl std::fmt::Display) -> String {
        match self {
            Spelling::Cli => format!("{} {value}", self.key(key)),
            Spelling::Python => format!("{key}={value}"),
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
}
