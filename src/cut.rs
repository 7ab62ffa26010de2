//! Where a block cannot move, so that no damage state has a probability:
//! below its uplift in PGA or PFA (or where it slides first, μg). One
//! definition for `fragility`, `risk`, the exports and the report's
//! figures.

use crate::block::Block;
use crate::floor::Building;
use crate::im::Im;
use crate::risk::Fragility;

/// The IM level below which every state's probability is 0, the same for
/// `risk` and the OpenQuake export (its `noDamageLimit`): a block on the
/// ground cannot move below its uplift PGA, g·tan α, nor any block below a
/// PFA of g·tan α (in PGA and PFA only; on a floor that moves otherwise
/// than the ground, the ground's PGA at uplift varies record to record,
/// and other IMs have no such level: no cut).
/// docs/MODEL.md §13.
/// A block whose runs slid on a base of friction `slides_on_mu` moves from
/// the smaller of g·tan α and μg (it slides first up to b/h).
pub fn zero_below(
    block: &Block,
    im: Im,
    floor: Option<&Building>,
    slides_on_mu: Option<f64>,
) -> Option<f64> {
    let moves = slides_on_mu.map_or(block.uplift_pga_g(), |mu| mu.min(block.uplift_pga_g()));
    match im {
        // The motion the block feels lifts it at g·tan α, floor or not.
        Im::Pfa => Some(moves),
        Im::Pga if floor.is_none_or(Building::moves_as_ground) => Some(moves),
        _ => None,
    }
}

/// P(state | IM = x) of a fragility cut below `cut` ([`zero_below`]): what
/// `fragility` prints at a level, as `risk` and the OpenQuake export count it.
pub fn probability_above(f: &Fragility, x: f64, cut: Option<f64>) -> f64 {
    if cut.is_some_and(|c| x < c) {
        0.0
    } else {
        f.probability(x)
    }
}
