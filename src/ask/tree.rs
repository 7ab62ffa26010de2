//! A logic tree as asked (`tree`: a TOML file or a named tree), checked
//! against what else the request says.

use super::spelling::{AskError, Spelling};
use crate::block::Restitution;

/// The logic tree `name` names (a TOML file or a named tree), checked
/// against the block's own ε (given with a tree's ε branches, refused)
/// and `direct` (a model branch needs the records' runs).
pub fn tree(
    name: Option<&str>,
    eps: Restitution,
    direct: bool,
    sp: Spelling,
) -> Result<Option<crate::tree::Tree>, AskError> {
    let Some(name) = name else { return Ok(None) };
    let t = crate::ops::tree::load(name).map_err(|e| AskError::of(sp, "tree", e))?;
    if !t.eps.is_empty() && eps != Restitution::Housner {
        return Err(AskError(format!(
            "{} sets ε on every branch: drop {}",
            sp.set("tree", name),
            sp.key("eps")
        )));
    }
    if let (Some(b), false) = (t.model.first(), direct) {
        return Err(AskError(format!(
            "{}: a [[model]] branch ({}) runs the records: add {}",
            sp.set("tree", name),
            crate::label::Label::label(b.value),
            sp.key("direct")
        )));
    }
    Ok(Some(t))
}
