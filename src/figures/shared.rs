//! What several study figures share: the fractiles they draw, the paper's
//! equation of each, the grid's middle block, what 1/η is of, the capacity
//! points of one fractile and a fractile's law evaluated at (p, ε).

use crate::fit::{curve, polyval};
use crate::fragility::FractileLaw;
use crate::plot::Hue;
use crate::study::StudyData;
use crate::tables::reduce::CapacityFractileRow;

/// The block drawn in the single-block figures: the middle p and ε of the
/// grid; of named blocks (whose p and ε seldom make one), the middle one
/// in order of p, ε and name, whatever order they are listed in.
pub(super) fn middle(d: &StudyData) -> (usize, f64, f64) {
    let (ps, es) = d.ps_and_eps();
    let (p, e) = (ps[ps.len() / 2], es[es.len() / 2]);
    let blocks = &d.records_plan().blocks;
    let by_order = || {
        let mut order: Vec<usize> = (0..blocks.len()).collect();
        order.sort_by(|&i, &j| {
            let (a, b) = (&blocks[i], &blocks[j]);
            (a.p.total_cmp(&b.p))
                .then(a.eps.total_cmp(&b.eps))
                .then(a.name.cmp(&b.name))
        });
        order[order.len() / 2]
    };
    let bi = match d.is_grid() {
        true => blocks
            .iter()
            .position(|b| b.p == p && b.eps == e)
            .unwrap_or_else(by_order),
        false => by_order(),
    };
    (bi, blocks[bi].p, blocks[bi].eps)
}

/// The block [`middle`] picks, in words: the grid's middle block, or a
/// study of named blocks' block by its name.
pub(super) fn middle_name(d: &StudyData, bi: usize) -> String {
    match d.is_grid() {
        true => "the grid's middle block".to_string(),
        false => format!("block `{}`", d.records_plan().blocks[bi].name),
    }
}

/// What 1/η is of in a study's η tables: the ground's PGA, or on a
/// building's floor (`[floor]`) the floor motion's peak, PFA.
pub(super) fn one_over_eta(d: &StudyData) -> &'static str {
    match (d.records_plan().floor.is_some(), d.peak()) {
        (true, _) => "PFA / (α g) = 1/η, on the floor",
        (false, crate::im::Im::Pfa) => "PFA / (α g) = 1/η, the text records' own peak",
        _ => "PGA / (α g) = 1/η",
    }
}

pub(super) const Q_NAMES: [&str; 3] = ["16 %", "50 %", "84 %"];
pub(super) const Q_VALUES: [f64; 3] = [0.16, 0.5, 0.84];
/// The paper's equation of each fractile's law: Eq. 11 (16 %), Eq. 10
/// (median), Eq. 12 (84 %).
pub const PAPER_EQ: [usize; 3] = [11, 10, 12];

/// (p, η_c) of one fractile at one ε, from capacity_fractiles.
pub(super) fn capacity_points(
    rows: &[CapacityFractileRow],
    e: f64,
    q: f64,
    value: fn(&CapacityFractileRow) -> Option<f64>,
) -> Vec<(f64, f64)> {
    rows.iter()
        .filter(|r| r.eps == e && r.quantile == q)
        .map(|r| (r.p, value(r).unwrap_or(f64::NAN)))
        .collect()
}

/// The fractile's law evaluated at (p, ε).
pub(super) fn law_at(law: &FractileLaw, p: f64, e: f64) -> f64 {
    curve(
        polyval(&law.a, e),
        polyval(&law.b, e),
        polyval(&law.c, e),
        p,
    )
}

/// The description of a capacity axis: `name` (η_c, η_c,50…) and what it
/// is: of the peak of the motion the blocks stand on ([`StudyData::peak`]).
pub(super) fn eta_axis(d: &StudyData, name: &str) -> String {
    format!("{name} = α g / {} (dimensionless)", d.peak().short())
}

/// The colour of `v`, one of the grid's `values` (its ε or p), on the
/// ramp: by its place among them, so a value has one colour in every
/// figure of a study.
pub(super) fn ramp(values: &[f64], v: f64) -> Hue {
    let k = values.iter().position(|&x| x == v).unwrap_or(0);
    Hue::Ramp(if values.len() > 1 {
        k as f64 / (values.len() - 1) as f64
    } else {
        0.0
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Named blocks: the middle by p whatever their order (the first
    /// listed was drawn, and the guide said the middle), here the urn
    /// (p = 3.7 1/s, between the rack's 2.7 and the vase's 4.2).
    #[test]
    fn the_middle_named_block_is_the_middle_p_in_any_order() {
        for names in [["vase", "urn", "rack"], ["rack", "vase", "urn"]] {
            let d = crate::figures::fixture::three_blocks_study(names);
            let (bi, _, _) = middle(&d);
            assert_eq!(middle_name(&d, bi), "block `urn`", "{names:?}");
        }
        // Twins of one p and ε: by name, in either order listed.
        for names in [["rack", "urn", "urn2"], ["urn2", "rack", "urn"]] {
            let d = crate::figures::fixture::three_blocks_study(names);
            let (bi, _, _) = middle(&d);
            assert_eq!(middle_name(&d, bi), "block `urn`", "{names:?}");
        }
    }
}
