//! The blocks `risk` and `export` assess: one block, or an inventory CSV
//! `name,b,h[,eps][,mu]` read with every error naming its line. Other
//! columns are the user's own and are not read; one that looks like a
//! known column misspelt or renamed (`epsilon`, `Mu`, `friction`) is
//! refused, since reading past it would silently use a default.

use std::path::Path;

use super::error::RiskError;
use super::request::Blocks;
use crate::block::{Block, BlockError, Restitution};
use crate::csv_rows;

/// One inventory entry.
#[derive(Debug, Clone, PartialEq)]
pub struct InventoryBlock {
    pub name: String,
    pub b_m: f64,
    pub h_m: f64,
    pub eps: Restitution,
    /// The base's friction coefficient (column `mu`, optional).
    pub mu: Option<f64>,
    /// Line in the file (1-based).
    pub line: u64,
}

/// Reads an inventory CSV: a header with `name`, `b`, `h` and optionally
/// `eps` (a number, or empty or `housner` for Housner's bound) and `mu`
/// (the base's friction coefficient; empty: not known).
pub fn read_inventory(path: &Path) -> Result<Vec<InventoryBlock>, RiskError> {
    let bytes = std::fs::read(path).map_err(|source| RiskError::Read {
        path: path.into(),
        source,
    })?;
    let bad = |line: u64, message: String| RiskError::Inventory {
        path: path.into(),
        line,
        message,
    };
    let mut csv = csv::ReaderBuilder::new().from_reader(bytes.as_slice());
    let headers = csv
        .headers()
        .map_err(|e| bad(1, csv_rows::message(&e)))?
        .clone();
    if let Some(message) = repeated_column(&headers) {
        return Err(bad(1, message));
    }
    if let Some(message) = misnamed_column(&headers) {
        return Err(bad(1, message));
    }
    let col = |name: &str| headers.iter().position(|h| h.trim() == name);
    let (Some(cn), Some(cb), Some(ch)) = (col("name"), col("b"), col("h")) else {
        let comment = bytes.trim_ascii_start().starts_with(b"#");
        return Err(bad(
            1,
            format!(
                "the header needs `name`, `b` and `h` (half-width and half-height, m), and may \
                 have `eps`{}",
                if comment {
                    "; an inventory's first line is its header (a `#` comment line is not \
                     skipped: remove it)"
                } else {
                    ""
                }
            ),
        ));
    };
    let ce = col("eps");
    let cm = col("mu");
    let mut out: Vec<InventoryBlock> = Vec::new();
    let mut names = std::collections::HashSet::new();
    let lines = csv_rows::Lines::new(&bytes);
    for row in csv.records() {
        let row = row.map_err(|e| {
            bad(
                csv_rows::error_line(&bytes, &e).unwrap_or(0),
                csv_rows::message(&e),
            )
        })?;
        let line = row.position().map_or(0, |p| lines.line_at(p.byte()));
        let cell = |c: usize| row.get(c).map(str::trim).unwrap_or("");
        let num = |c: usize, what: &str| -> Result<f64, RiskError> {
            cell(c)
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| bad(line, format!("`{what}` = `{}` is not a number", cell(c))))
        };
        let name = cell(cn).to_string();
        if name.is_empty() {
            return Err(bad(line, "a block needs a name".into()));
        }
        if !names.insert(name.clone()) {
            return Err(bad(line, format!("block `{name}` is listed twice")));
        }
        let eps = restitution(ce.map(cell)).map_err(|m| bad(line, m))?;
        let (b_m, h_m) = (num(cb, "b")?, num(ch, "h")?);
        let mu = match cm.map(cell) {
            None | Some("") => None,
            Some(_) => {
                let mu = num(cm.unwrap_or_default(), "mu")?;
                crate::block::check_mu(mu)
                    .map_err(|e| bad(line, format!("block `{name}`: `mu`: {e}")))?;
                Some(mu)
            }
        };
        // Checked here, so that the message names the file, line and column.
        Block::new(b_m, h_m, eps).map_err(|e| {
            let column = match e {
                BlockError::Size { .. } => "`b`, `h`",
                _ => "`eps`",
            };
            bad(line, format!("block `{name}`: {column}: {e}"))
        })?;
        out.push(InventoryBlock {
            name,
            b_m,
            h_m,
            eps,
            mu,
            line,
        });
    }
    if out.is_empty() {
        return Err(bad(1, "no blocks after the header".into()));
    }
    Ok(out)
}

/// The blocks asked: one (named by its dimensions) or an inventory's.
pub(super) fn entries(blocks: &Blocks) -> Result<Vec<InventoryBlock>, RiskError> {
    Ok(match blocks {
        Blocks::One { b_m, h_m, eps, mu } => vec![InventoryBlock {
            name: format!("half-width {b_m} m × half-height {h_m} m"),
            b_m: *b_m,
            h_m: *h_m,
            eps: *eps,
            mu: *mu,
            line: 0,
        }],
        Blocks::Inventory(path) => read_inventory(path)?,
    })
}

/// A column given twice is ambiguous (which `b` is the block's?): the
/// message naming it and where.
fn repeated_column(headers: &csv::StringRecord) -> Option<String> {
    let names: Vec<&str> = headers.iter().map(str::trim).collect();
    names.iter().enumerate().find_map(|(k, h)| {
        let first = names[..k].iter().position(|o| o == h)?;
        Some(format!(
            "column `{h}` is given twice (columns {} and {})",
            first + 1,
            k + 1
        ))
    })
}

/// The columns the reader knows, and names a user may give one of them
/// (after lower-casing and dropping all but letters and digits).
const KNOWN: [(&str, &[&str]); 5] = [
    ("name", &["id", "block", "blockname", "label"]),
    ("b", &["halfwidth", "bm", "width"]),
    ("h", &["halfheight", "hm", "height"]),
    (
        "eps",
        &["epsilon", "restitution", "cor", "coefficientofrestitution"],
    ),
    (
        "mu",
        &[
            "μ",
            "friction",
            "frictioncoefficient",
            "coefficientoffriction",
            "mus",
        ],
    ),
];

/// A column that is not one the reader knows but looks like one (the same
/// but for case, spacing or punctuation; a usual other name; one letter
/// off a name of three or more): the message naming both. Such a column
/// would be passed over and its block given a default (Housner's ε, no
/// friction), a wrong answer without a word.
fn misnamed_column(headers: &csv::StringRecord) -> Option<String> {
    let plain = |h: &str| -> String {
        h.chars()
            .filter(|c| c.is_alphanumeric())
            .flat_map(char::to_lowercase)
            .collect()
    };
    let given: Vec<&str> = headers.iter().map(str::trim).collect();
    given.iter().find_map(|&h| {
        if KNOWN.iter().any(|(k, _)| *k == h) {
            return None;
        }
        let p = plain(h);
        if kinetic(&p) {
            return Some(format!(
                "column `{h}`: an inventory's friction is one coefficient, `mu`, static and \
                 kinetic alike; a kinetic coefficient of its own is run by `rocking capacity \
                 --mu-k` or a pipeline's `[[block]]` `mu_k`: remove the column (it would be \
                 ignored)"
            ));
        }
        let known = KNOWN
            .iter()
            .find(|(k, others)| {
                *k == p || others.contains(&p.as_str()) || (k.len() >= 3 && one_letter_off(k, &p))
            })
            .map(|(k, _)| k)
            .or_else(|| named_as(&p))?;
        // A column the file also has under its own name is the user's own.
        if given.contains(known) {
            return None;
        }
        Some(format!(
            "column `{h}`: is it `{known}`? The columns read are name, b and h (the \
             half-width and half-height, m), eps and mu; others are passed over, so this one \
             would be ignored: rename it"
        ))
    })
}

/// The known column a plain name `p` reads as by its stem: restitution
/// (`e`, `ε`, `rest`, `restitution_coefficient`, `coeff_restitution`,
/// `eps_0`) or friction (`fric`, `mu_static`, `μs`, `friction_coef`).
fn named_as(p: &str) -> Option<&'static &'static str> {
    let eps = p.contains("restitution")
        || p.starts_with("coefrest")
        || p.starts_with("coeffrest")
        || p.starts_with("eps")
        || p.starts_with('ε')
        || matches!(p, "e" | "rest");
    // `mu` then a word is the user's own (`museum`, `multiplier`), and so is
    // a friction angle (degrees) or a word holding "fric" (`african`).
    let friction = (p.starts_with("fric") || p.contains("friction")) && !p.contains("angle");
    let mu = friction || matches!(p, "mus" | "mustatic" | "mu0") || p.starts_with('μ');
    let at = |name: &str| KNOWN.iter().map(|(k, _)| k).find(|k| **k == name);
    match (eps, mu) {
        (true, false) => at("eps"),
        (false, true) => at("mu"),
        _ => None,
    }
}

/// Whether a plain column name (as `misnamed_column` compares them) is a
/// kinetic friction coefficient, which an inventory does not take: `mu`
/// with a kinetic suffix (`mu_k`, `μ_d`, `mu_dynamic`) or a friction word
/// with a kinetic one (`kinetic_friction_coefficient`, `friction_kinetic`).
fn kinetic(p: &str) -> bool {
    let of_mu = p.strip_prefix("mu").or_else(|| p.strip_prefix('μ'));
    let mu = of_mu.is_some_and(|s| {
        matches!(
            s,
            "k" | "d" | "kin" | "kinetic" | "dyn" | "dynamic" | "slide" | "sliding"
        )
    });
    let friction = (p.starts_with("fric") || p.contains("friction"))
        && ["kinetic", "dynamic", "sliding"]
            .iter()
            .any(|w| p.contains(w));
    (mu || friction) && !p.contains("angle")
}

/// Whether `a` and `b` differ by one letter changed, added or removed.
fn one_letter_off(a: &str, b: &str) -> bool {
    let (a, b): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
    let (short, long) = if a.len() <= b.len() {
        (&a, &b)
    } else {
        (&b, &a)
    };
    match long.len() - short.len() {
        0 => short.iter().zip(long).filter(|(x, y)| x != y).count() == 1,
        1 => (0..long.len()).any(|skip| {
            long.iter()
                .enumerate()
                .filter(|&(i, _)| i != skip)
                .map(|(_, c)| c)
                .eq(short.iter())
        }),
        _ => false,
    }
}

/// The `eps` cell: a number, or empty or `housner` for Housner's bound.
fn restitution(cell: Option<&str>) -> Result<Restitution, String> {
    match cell {
        None | Some("") => Ok(Restitution::Housner),
        Some(text) => text
            .parse::<Restitution>()
            .ok()
            .filter(|e| !matches!(e, Restitution::Value(v) if !v.is_finite()))
            .ok_or_else(|| format!("`eps` = `{text}`: give a number in (0, 1] or `housner`")),
    }
}
