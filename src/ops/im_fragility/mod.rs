//! A block's fragility in an IM other than PGA (docs/MODEL.md §14): from
//! the records' capacities (`--direct`), or carried over p and ε from a
//! study's `im_efficiency` table; likewise a damage state's in any IM from
//! its `damage_states` table (§15).
//!
//! A study gives, for each block of its grid, the median capacity in the
//! IM's dimensionless form (p·PGV/(αg), SA/(αg), …) and the dispersion β.
//! Both vary smoothly with p and ε (the paper's regression rests on the
//! same smoothness for η_c), so for a real block they are interpolated
//! bilinearly in (ln p, ε) between the four grid blocks around it, the
//! median on a log scale; outside the grid the nearest edge is used and the
//! user is told the fragility is stretched there. The dimensionless median
//! then becomes the block's own through its α and p.

use std::path::Path;
use std::path::PathBuf;

use crate::block::Block;
use crate::damage::{FitMethod, LimitState};
use crate::im::Im;
use crate::tables::damage::DamageStateRow;
use crate::tables::ims::EfficiencyRow;

mod grid;

use grid::{Gap, Grid, Node};

/// Why a study's IM table gives no fragility for a block.
#[derive(Debug, thiserror::Error)]
pub enum ImTableError {
    #[error(
        "{path} does not exist: the study of {pipeline} has no {what} yet; run \
         `rocking run {pipeline}`, or use --direct", path = .path.display()
    )]
    Missing {
        what: &'static str,
        pipeline: String,
        path: PathBuf,
    },
    #[error(
        "damage state `{state}` ({criterion}) is not one of the study's ({have}); set \
         `[damage] states` in {pipeline} and run it, or use --direct"
    )]
    NoState {
        state: String,
        criterion: String,
        have: String,
        pipeline: String,
    },
    #[error(
        "{what} by the {method} method: the study's blocks around this one ({corners}) have no \
         fit (too few records reach the state), so it cannot be carried here; try --method \
         {other}, or --direct"
    )]
    StateHoles {
        /// The state and the IM: "damage state `overturned` in pga".
        what: String,
        method: &'static str,
        other: &'static str,
        /// The grid's blocks the block's fit would be carried from that
        /// have none.
        corners: String,
    },
    #[error(
        "{what} of {pipeline}: the study's blocks ({blocks}) are not a grid of p × ε, so they \
         carry over to no other block (a study of `[blocks] p` and `eps` does); ask for one of \
         them (its b, h and ε), or use --direct"
    )]
    NotAGrid {
        what: String,
        pipeline: String,
        blocks: String,
    },
    #[error(
        "{what} of {pipeline}: the study has {values}: its capacity would be another block's; \
         run this block (--direct), or a study of several p around it"
    )]
    OneP {
        what: String,
        pipeline: String,
        /// "one p = 2.654 1/s, and the block asked has p = 8.394 1/s".
        values: String,
    },
    #[error(
        "{what} of {pipeline}: the study's block `{block}` ran sliding on its base (mu = {mu}), \
         and its fits are of that friction; use --direct (with --mu) to run this block"
    )]
    Slides {
        what: String,
        pipeline: String,
        block: String,
        mu: f64,
    },
    #[error(
        "{what}: the study's block `{block}` has no fit of it (too few of its records reach \
         it); {try_instead}"
    )]
    OwnNoFit {
        /// What was asked, and of which study.
        what: String,
        block: String,
        try_instead: String,
    },
    #[error("the study's IM table: {0}")]
    Bad(String),
    #[error(
        "{} has no {im}: {}",
        path.display(),
        match im.strip_prefix("sa(") {
            Some(_) => format!(
                "a study's records carry SA at {} s only (docs/MODEL.md §14); ask for one of \
                 them, or run the block through the records (--direct), which computes SA at any \
                 period",
                crate::im::PERIODS_S.map(crate::im::period_text).join(", ")
            ),
            None => "run the study's ims stage again, or use --direct".to_string(),
        }
    )]
    NotInStudy { im: String, path: PathBuf },
    #[error("{0} has no dimensionless form to carry a study's capacities to another block; use --direct")]
    NoDimensionless(String),
}

/// A lognormal capacity in an IM: median (in the IM's unit) and β.
#[derive(Debug, Clone, PartialEq)]
pub struct Lognormal {
    pub median: f64,
    pub beta: f64,
    /// Where it is stretched (outside the study's grid).
    pub warnings: Vec<String>,
}

/// A study's capacities in one IM, read once, to carry to any block.
pub struct ImTable {
    im: Im,
    pipeline: String,
    table: Table,
}

impl ImTable {
    /// The table of `im` in the study folder `dir` (its
    /// `im_efficiency.parquet`); `study` names the pipeline in messages.
    /// `study_block(name)`: what the study says of its block of that name.
    pub fn load(
        dir: &Path,
        study: &str,
        im: Im,
        study_block: &dyn Fn(&str) -> StudyBlock,
    ) -> Result<ImTable, ImTableError> {
        let name = im.name();
        if im.dimensionless(1.0, 1.0).is_none() {
            return Err(ImTableError::NoDimensionless(name));
        }
        let path = dir.join("im_efficiency.parquet");
        let rows: Vec<EfficiencyRow> = study_table(&path, "IM table", study)?;
        let nodes: Vec<(&str, Node)> = rows
            .iter()
            .filter(|r| r.im == name)
            .map(|r| {
                (
                    &r.block[..],
                    (r.p, r.eps, r.median_dimensionless, Some(r.beta)),
                )
            })
            .collect();
        if nodes.is_empty() {
            return Err(ImTableError::NotInStudy { im: name, path });
        }
        Ok(ImTable {
            im,
            pipeline: study.to_string(),
            table: Table::of(&nodes, study_block),
        })
    }

    /// The block's lognormal capacity, its median in the IM's unit.
    pub fn capacity(&self, block: &Block) -> Result<Lognormal, ImTableError> {
        let (p, eps) = (block.p(), block.eps);
        let (factor, _) = self
            .im
            .dimensionless(block.alpha(), p)
            .ok_or_else(|| ImTableError::NoDimensionless(self.im.name()))?;
        let (ln_median, beta, warnings) =
            self.table.at(p, eps, Some(block.alpha())).map_err(|gap| {
                gap.error(
                    (
                        format!("the capacity in {}", self.im.name()),
                        &self.pipeline,
                    ),
                    &self.table,
                    (
                        |corners| {
                            ImTableError::Bad(format!(
                                "the study's blocks around this one ({corners}) have no median in \
                             {}, so it cannot be carried here; use --direct",
                                self.im.name()
                            ))
                        },
                        "use --direct".to_string(),
                    ),
                )
            })?;
        Ok(Lognormal {
            median: ln_median.exp() / factor,
            beta,
            warnings,
        })
    }
}

/// A study's damage-state fits in one IM by one method (its
/// `damage_states.parquet`), to carry to any block as [`ImTable`] does.
pub struct DamageTable {
    im: Im,
    pipeline: String,
    /// Each state's name, criterion and blocks.
    states: Vec<(String, String, Table)>,
    method: FitMethod,
}

impl DamageTable {
    /// The fits of `im` by `method` in the study folder `dir`; `study`
    /// names the pipeline in messages.
    /// `study_block(name)` as [`ImTable::load`]'s.
    pub fn load(
        dir: &Path,
        study: &str,
        (im, method): (Im, FitMethod),
        study_block: &dyn Fn(&str) -> StudyBlock,
    ) -> Result<Self, ImTableError> {
        if im.dimensionless(1.0, 1.0).is_none() {
            return Err(ImTableError::NoDimensionless(im.name()));
        }
        let path = dir.join(crate::stages::damage::STATES);
        let rows: Vec<DamageStateRow> = study_table(&path, "damage table", study)?;
        let name = im.name();
        if !rows.iter().any(|r| r.im == name) {
            return Err(ImTableError::NotInStudy { im: name, path });
        }
        let mut states: Vec<(String, String, Table)> = Vec::new();
        for r in rows.iter().filter(|r| r.im == name && r.method == method) {
            if !states.iter().any(|s| s.0 == r.state) {
                let nodes: Vec<(&str, Node)> = rows
                    .iter()
                    .filter(|o| o.im == name && o.method == method && o.state == r.state)
                    .map(|o| (&o.block[..], (o.p, o.eps, o.median_dimensionless, o.beta)))
                    .collect();
                states.push((
                    r.state.clone(),
                    r.criterion.clone(),
                    Table::of(&nodes, study_block),
                ));
            }
        }
        Ok(DamageTable {
            im,
            pipeline: study.to_string(),
            states,
            method,
        })
    }

    /// The study's blocks of `state`: by name and criterion (overturning by
    /// its criterion alone: a study's one overturning state under any name).
    fn of_state(&self, state: &LimitState) -> Option<&Table> {
        let criterion = state.describe();
        let overturning = state.criterion == crate::damage::Criterion::Overturned;
        self.states
            .iter()
            .find(|s| s.0 == state.name && s.1 == criterion)
            .or_else(|| {
                let by_criterion = self.states.iter().find(|s| s.1 == criterion);
                by_criterion.filter(|_| overturning)
            })
            .map(|s| &s.2)
    }

    /// Whether the study fitted `state` ([`DamageTable::capacity`] finds it).
    pub fn holds(&self, state: &LimitState) -> bool {
        self.of_state(state).is_some()
    }

    /// The block's lognormal capacity for `state`, its median in the IM's
    /// unit; the state must be the study's ([`DamageTable::holds`]).
    pub fn capacity(&self, block: &Block, state: &LimitState) -> Result<Lognormal, ImTableError> {
        let Some(table) = self.of_state(state) else {
            let criterion = state.describe();
            let have: Vec<String> = self
                .states
                .iter()
                .map(|s| format!("{}: {}", s.0, s.1))
                .collect();
            return Err(ImTableError::NoState {
                state: state.name.clone(),
                criterion,
                have: have.join(", "),
                pipeline: self.pipeline.clone(),
            });
        };
        let (factor, _) = self
            .im
            .dimensionless(block.alpha(), block.p())
            .ok_or_else(|| ImTableError::NoDimensionless(self.im.name()))?;
        let (ln_median, beta, warnings) = table
            .at(block.p(), block.eps, Some(block.alpha()))
            .map_err(|gap| {
                gap.error(
                    (
                        format!("damage state `{}` in {}", state.name, self.im.name()),
                        &self.pipeline,
                    ),
                    table,
                    (
                        |corners| ImTableError::StateHoles {
                            what: format!("damage state `{}` in {}", state.name, self.im.name()),
                            method: self.method.name(),
                            other: self.method.other().name(),
                            corners,
                        },
                        format!("try --method {}, or --direct", self.method.other().name()),
                    ),
                )
            })?;
        Ok(Lognormal {
            median: ln_median.exp() / factor,
            beta,
            warnings,
        })
    }
}

/// What a study says of its block of a name beyond its table's row.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StudyBlock {
    /// The friction it ran sliding on (the slide-rock model), if it did.
    pub slid: Option<f64>,
    /// Its slenderness α (rad); none for the p × ε grid.
    pub alpha: Option<f64>,
}

/// A study's table `what` at `path`, refused as missing (the study has not
/// run the stage) or unreadable.
fn study_table<T: crate::tables::Table>(
    path: &Path,
    what: &'static str,
    study: &str,
) -> Result<Vec<T>, ImTableError> {
    if !path.exists() {
        return Err(ImTableError::Missing {
            what,
            pipeline: study.to_string(),
            path: path.to_path_buf(),
        });
    }
    crate::tables::read(path).map_err(|e| ImTableError::Bad(e.to_string()))
}

/// Whether a block's p, ε or α is a study block's own: to four digits, as
/// the tool prints them (`--eps 0.9294` for Housner's 0.92948…, b and h
/// as measured), where it had to be the same to the bit.
pub(crate) fn own_value(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-4 * a.abs().max(b.abs())
}

/// A study's blocks in one IM: their nodes, named, and the grid they make
/// when they make one.
struct Table {
    /// Each block's name, node and what the study says of it.
    nodes: Vec<(String, Node, StudyBlock)>,
    /// `None`: the blocks are not a full p × ε grid, or some have no fit.
    grid: Option<Grid>,
}

impl Table {
    /// The study's blocks; `study_block(name)` what the study says of the
    /// block of that name.
    /// Named blocks (`[[block]]`) are no grid, whatever their p and ε:
    /// they answer for themselves only (a study of one such block gave its
    /// capacity to any block of its p, of another ε or shape too).
    fn of(nodes: &[(&str, Node)], study_block: &dyn Fn(&str) -> StudyBlock) -> Table {
        let bare: Vec<Node> = nodes.iter().map(|n| n.1).collect();
        let named = nodes.iter().any(|(b, _)| !b.is_empty());
        Table {
            nodes: nodes
                .iter()
                .map(|(b, n)| (b.to_string(), *n, study_block(b)))
                .collect(),
            grid: if named { None } else { Grid::of(&bare) },
        }
    }

    /// The study's own block at `(p, ε)` (to rounding) with its fit, as it
    /// is; else the grid's value there ([`Grid::at`]).
    fn at(&self, p: f64, eps: f64, alpha: Option<f64>) -> Result<(f64, f64, Vec<String>), Gap> {
        let same = own_value;
        // Its own block: p and ε, and α where both have one (two blocks of
        // one R and ε, but of other shapes, share p and ε).
        let own = self.nodes.iter().find(|(_, (np, ne, ..), sb)| {
            same(*np, p) && same(*ne, eps) && sb.alpha.zip(alpha).is_none_or(|(a, b)| same(a, b))
        });
        if let Some((block, (_, _, median, beta), sb)) = own {
            return match (&sb.slid, median.zip(*beta)) {
                (Some(mu), _) => Err(Gap::Slides {
                    block: block.clone(),
                    mu: *mu,
                }),
                (None, Some((m, b))) => Ok((m.ln(), b, Vec::new())),
                (None, None) => Err(Gap::Unfitted {
                    block: block.clone(),
                }),
            };
        }
        match &self.grid {
            Some(g) => g.at(p, eps),
            None => Err(Gap::NotAGrid),
        }
    }

    /// The study's blocks, for a refusal: `name (p = …, ε = …)`.
    fn blocks(&self) -> String {
        let mut seen: Vec<String> = Vec::new();
        for (name, (p, e, ..), _) in &self.nodes {
            let b = format!("{name} at p = {p:.3} 1/s, ε = {e:.3}");
            if !seen.contains(&b) {
                seen.push(b);
            }
        }
        seen.join("; ")
    }
}

impl Gap {
    /// The refusal of `what` from the study `pipeline` for this gap in
    /// `table`; a grid's holes are `holes()`.
    fn error(
        self,
        (what, pipeline): (String, &str),
        table: &Table,
        (holes, try_instead): (impl FnOnce(String) -> ImTableError, String),
    ) -> ImTableError {
        let pipeline = pipeline.to_string();
        match self {
            Gap::Holes(corners) => holes(corners),
            Gap::NotAGrid => ImTableError::NotAGrid {
                what,
                pipeline,
                blocks: table.blocks(),
            },
            Gap::OneP(only, p) => ImTableError::OneP {
                what,
                pipeline,
                values: format!("one p = {only:.4} 1/s, and the block asked has p = {p:.4} 1/s"),
            },
            Gap::Slides { block, mu } => ImTableError::Slides {
                what,
                pipeline,
                block,
                mu,
            },
            Gap::Unfitted { block } => ImTableError::OwnNoFit {
                what: format!("{what} of {pipeline}"),
                block,
                try_instead,
            },
        }
    }
}

/// The lognormal of the finite `thresholds`: exp(mean ln), sd ln (n − 1).
pub fn lognormal_of(thresholds: &[f64]) -> Option<(f64, f64)> {
    let logs: Vec<f64> = thresholds
        .iter()
        .filter(|t| t.is_finite())
        .map(|t| t.ln())
        .collect();
    (logs.len() >= 3).then(|| {
        let (m, s) = crate::stats::mean_sd(&logs);
        (m.exp(), s)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(p: f64, eps: f64, median: f64, beta: f64) -> EfficiencyRow {
        EfficiencyRow {
            block_index: 0,
            block: String::new(),
            p,
            eps,
            im: "pgv".into(),
            unit: "cm/s".into(),
            n: 44,
            median: None,
            median_dimensionless: Some(median),
            dimensionless: Some("p·PGV/(αg)".into()),
            beta,
            lilliefors_p: None,
            rank: Some(1),
            slope: None,
        }
    }

    fn nodes(rows: &[EfficiencyRow]) -> Vec<Node> {
        rows.iter()
            .map(|r| (r.p, r.eps, r.median_dimensionless, Some(r.beta)))
            .collect()
    }

    /// Values that are exactly bilinear in (ln p, ε) (ln median) are given
    /// back between the nodes; outside, the edge and a warning.
    #[test]
    fn bilinear_in_ln_p_and_eps() {
        let f = |p: f64, e: f64| (0.3 + 0.5 * p.ln() - 0.8 * e, 0.4 + 0.1 * p.ln() + 0.2 * e);
        let rows: Vec<EfficiencyRow> = [0.5, 1.0, 2.0, 4.0]
            .iter()
            .flat_map(|&p| [0.5, 0.7, 0.9].map(move |e| (p, e)))
            .map(|(p, e)| row(p, e, f(p, e).0.exp(), f(p, e).1))
            .collect();
        let refs = nodes(&rows);
        let g = Grid::of(&refs).unwrap();
        for (p, e) in [(0.7, 0.55), (1.3, 0.81), (3.9, 0.5), (0.5, 0.9)] {
            let (m, b, w) = g.at(p, e).unwrap();
            let (wm, wb) = f(p, e);
            assert!((m - wm).abs() < 1e-12 && (b - wb).abs() < 1e-12, "{p} {e}");
            assert!(w.is_empty());
        }
        let (m, _, w) = g.at(8.0, 0.95).unwrap();
        assert!((m - f(4.0, 0.9).0).abs() < 1e-12);
        assert_eq!(w.len(), 2, "{w:?}");
        // A grid missing a block is not a grid.
        assert!(Grid::of(&refs[1..]).is_none());
        // A block without a fit leaves the cells it is no corner of as
        // they were: (0.5, 0.5) has none, and (2, 0.6), (3.9, 0.8) and
        // (1, 0.7), on its cell's far edge, are answered to the bit; a
        // block whose cell it is a corner of is refused, naming it.
        let mut holed = refs.clone();
        holed[0].2 = None;
        let h = Grid::of(&holed).unwrap();
        for (p, e) in [(2.0, 0.6), (3.9, 0.8), (1.0, 0.7)] {
            assert_eq!(h.at(p, e), g.at(p, e).map_err(|_| Gap::NotAGrid), "{p} {e}");
        }
        assert_eq!(
            h.at(0.7, 0.55),
            Err(Gap::Holes("p = 0.500 1/s, ε = 0.500".into()))
        );
    }

    /// One p carries nothing to another: a study of one block (a 1 × 1
    /// grid) gave its capacity to any block, a tenth of its size too, with
    /// a warning; now another p is refused, its own answered (one ε is
    /// used at another with a warning: `one_eps_is_used_as_it_is`). A grid
    /// of one p and three ε carries along ε only.
    #[test]
    fn an_axis_of_one_value_carries_nothing() {
        let one = Grid::of(&[(2.0, 0.7, Some(1.3), Some(0.2))]).unwrap();
        assert_eq!(one.at(2.0, 0.7), Ok((1.3f64.ln(), 0.2, Vec::new())));
        let ten = 2.0 * 10f64.sqrt();
        assert_eq!(one.at(ten, 0.7), Err(Gap::OneP(2.0, ten)));
        // A measured block of that p to four digits, or within 5 % with a
        // warning, is answered; at 6 % refused.
        assert_eq!(one.at(2.00003, 0.7), Ok((1.3f64.ln(), 0.2, Vec::new())));
        let (m, _, w) = one.at(2.08, 0.7).unwrap();
        assert!(m == 1.3f64.ln() && w.len() == 1 && w[0].contains("only p = 2.0000"));
        assert_eq!(one.at(2.12, 0.7), Err(Gap::OneP(2.0, 2.12)));
        let (m, _, w) = one.at(2.0, 0.5).unwrap();
        assert!(m == 1.3f64.ln() && w.len() == 1 && w[0].contains("only ε = 0.7000"));
        let along: Vec<Node> = [0.5, 0.7, 0.9]
            .iter()
            .map(|&e| (2.0, e, Some(1.0 + e), Some(0.2)))
            .collect();
        let g = Grid::of(&along).unwrap();
        let (m, _, w) = g.at(2.0, 0.6).unwrap();
        assert!((m - (0.5 * 1.5f64.ln() + 0.5 * 1.7f64.ln())).abs() < 1e-12 && w.is_empty());
        assert_eq!(g.at(2.5, 0.6), Err(Gap::OneP(2.0, 2.5)));
    }

    /// A study of named blocks is no grid: a block asked is answered by
    /// the study's own block at its p and ε, as the study fitted it, and
    /// refused as not a grid elsewhere; a grid with a block that has no fit
    /// is refused for its holes, not as not a grid.
    #[test]
    fn named_blocks_answer_for_themselves() {
        let none = |_: &str| StudyBlock::default();
        let named = Table::of(
            &[
                ("statue", (2.8245, 0.9294, Some(1.3), Some(0.12))),
                ("cabinet", (2.6542, 0.75, Some(1.7), Some(0.19))),
                ("vase", (3.1, 0.8, None, None)),
            ],
            &none,
        );
        assert_eq!(
            named.at(2.8245, 0.9294, None),
            Ok((1.3f64.ln(), 0.12, Vec::new()))
        );
        assert_eq!(named.at(2.7, 0.8, None), Err(Gap::NotAGrid));
        // Its own block as printed, to four digits (Housner's ε 0.92948…
        // given as 0.9294 was refused).
        assert_eq!(
            named.at(2.8246, 0.92948, None),
            Ok((1.3f64.ln(), 0.12, Vec::new()))
        );
        assert_eq!(
            named.blocks(),
            "statue at p = 2.825 1/s, ε = 0.929; cabinet at p = 2.654 1/s, ε = 0.750; \
             vase at p = 3.100 1/s, ε = 0.800"
        );
        // Its own block without a fit, named; a block that ran sliding is
        // not answered for a block asked (its fits are of its friction).
        assert_eq!(
            named.at(3.1, 0.8, None),
            Err(Gap::Unfitted {
                block: "vase".into()
            })
        );
        let slid = |b: &str| StudyBlock {
            slid: (b == "statue").then_some(0.15),
            alpha: None,
        };
        let sliding = Table::of(
            &[("statue", (2.8245, 0.9294, Some(1.3), Some(0.12)))],
            &slid,
        );
        assert_eq!(
            sliding.at(2.8245, 0.9294, None),
            Err(Gap::Slides {
                block: "statue".into(),
                mu: 0.15
            })
        );
        let holed = Table::of(
            &[
                ("", (1.0, 0.5, Some(1.0), Some(0.3))),
                ("", (1.0, 0.9, None, None)),
                ("", (4.0, 0.5, Some(2.0), Some(0.3))),
                ("", (4.0, 0.9, Some(3.0), Some(0.3))),
            ],
            &none,
        );
        assert_eq!(
            holed.at(2.0, 0.7, None),
            Err(Gap::Holes("p = 1.000 1/s, ε = 0.900".into()))
        );
        assert_eq!(holed.at(4.0, 0.9, None), Ok((3f64.ln(), 0.3, Vec::new())));
        // One named block is no 1 × 1 grid: another ε, or another p near
        // its own, is refused (it was given the statue's capacity).
        let one = Table::of(
            &[("statue", (2.8245, 0.9294, Some(1.3), Some(0.12)))],
            &none,
        );
        assert_eq!(one.at(2.8245, 0.5, None), Err(Gap::NotAGrid));
        assert_eq!(one.at(2.83, 0.9294, None), Err(Gap::NotAGrid));
        // Named blocks of a full 2 × 2 of p and ε are no grid either.
        let four = Table::of(
            &[
                ("a", (1.0, 0.5, Some(1.0), Some(0.3))),
                ("b", (1.0, 0.9, Some(1.5), Some(0.3))),
                ("c", (4.0, 0.5, Some(2.0), Some(0.3))),
                ("d", (4.0, 0.9, Some(3.0), Some(0.3))),
            ],
            &none,
        );
        assert_eq!(four.at(2.0, 0.7, None), Err(Gap::NotAGrid));
        assert_eq!(four.at(4.0, 0.9, None), Ok((3f64.ln(), 0.3, Vec::new())));
    }

    /// Two named blocks of one R and ε (so one p) but other shapes: each
    /// answers for the block of its own α, neither for a third α (the
    /// first of them answered for every block of that p and ε).
    #[test]
    fn twins_of_one_p_and_eps_answer_by_their_alpha() {
        let alpha = |b: &str| StudyBlock {
            slid: None,
            alpha: Some(if b == "a" { 0.2 } else { 0.5 }),
        };
        let twins = Table::of(
            &[
                ("a", (2.7, 0.8, Some(1.3), Some(0.12))),
                ("c", (2.7, 0.8, Some(2.1), Some(0.3))),
            ],
            &alpha,
        );
        assert_eq!(
            twins.at(2.7, 0.8, Some(0.2)),
            Ok((1.3f64.ln(), 0.12, Vec::new()))
        );
        assert_eq!(
            twins.at(2.7, 0.8, Some(0.5)),
            Ok((2.1f64.ln(), 0.3, Vec::new()))
        );
        assert_eq!(twins.at(2.7, 0.8, Some(0.3)), Err(Gap::NotAGrid));
    }

    /// A study of one ε: linear in ln p along it, its value at any ε, and a
    /// warning where the block's ε is not the study's.
    #[test]
    fn one_eps_is_used_as_it_is() {
        let f = |p: f64| (0.3 + 0.5 * p.ln(), 0.4 + 0.1 * p.ln());
        let rows: Vec<EfficiencyRow> = [1.0, 4.0]
            .iter()
            .map(|&p| row(p, 0.7, f(p).0.exp(), f(p).1))
            .collect();
        let refs = nodes(&rows);
        let g = Grid::of(&refs).unwrap();
        let (m, b, w) = g.at(2.0, 0.7).unwrap();
        assert!((m - f(2.0).0).abs() < 1e-12 && (b - f(2.0).1).abs() < 1e-12);
        assert!(w.is_empty(), "{w:?}");
        let (m, _, w) = g.at(2.0, 0.75).unwrap();
        assert!((m - f(2.0).0).abs() < 1e-12);
        assert_eq!(w.len(), 1);
        assert!(w[0].contains("only ε = 0.7000"), "{w:?}");
    }

    #[test]
    fn lognormal_of_finite_thresholds() {
        let (m, s) = lognormal_of(&[1.0, 10.0, 100.0, f64::INFINITY]).unwrap();
        assert!((m - 10.0).abs() < 1e-12 && (s - 10f64.ln()).abs() < 1e-12);
        assert!(lognormal_of(&[1.0, f64::INFINITY]).is_none());
    }
}
