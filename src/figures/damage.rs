//! The damage states' fragility curves of one block: each limit state's
//! lognormal in PGA/(αg) (the paper's fractile method) over the share of
//! records that reach it (on a building's floor, in the ground's PGA, as
//! the fits are).

use super::figure::Figure;
use super::shared::{middle, middle_name};
use crate::damage::{FitMethod, Lognormal};
use crate::im::Im;
use crate::plot::{Chart, Hue, Line, Scale, Style};
use crate::study::{DamageData, StudyData};
use crate::tables::damage::{DamageStateRow, StateCapacityRow};

/// The block the damage figure and table show, with its rows in PGA.
pub struct Shown<'a> {
    /// Which block, in words.
    pub which: String,
    pub p: f64,
    pub eps: f64,
    /// The states' names, lightest first.
    pub names: Vec<String>,
    /// Its fits in PGA, both methods.
    pub fits: Vec<&'a DamageStateRow>,
    pub capacities: Vec<&'a StateCapacityRow>,
    /// On a building's floor: each record's PFA/PGA, which turns the
    /// floor's η of its state capacities into the ground's (the fits'); empty
    /// on the ground.
    pub pfa_over_pga: Vec<(&'a str, f64)>,
    /// The level (PGA/(αg), the fits' unit) below which the block cannot
    /// move, every state's P 0 as the commands count it
    /// ([`crate::cut::zero_below`]; α → 0 on the grid without α: η = 1);
    /// none on a floor that moves otherwise than the ground.
    pub cut: Option<f64>,
    /// The peak the fits are in: PGA (the ground's, on a `[floor]` too), or
    /// PFA on text records stood on, whose tables name their measures so.
    pub peak: String,
}

impl Shown<'_> {
    /// The probability of `l` at `x`, 0 below the cut.
    pub fn probability(&self, l: &Lognormal, x: f64) -> f64 {
        let f = crate::risk::Fragility::Lognormal {
            median: l.median,
            beta: l.beta,
        };
        crate::cut::probability_above(&f, x, self.cut)
    }

    /// The lognormal of `state` by `method`, in PGA/(αg).
    pub fn lognormal(&self, state: &str, method: FitMethod) -> Option<Lognormal> {
        let r = self
            .fits
            .iter()
            .find(|r| r.state == state && r.method == method)?;
        Some(Lognormal {
            median: r.median_dimensionless?,
            beta: r.beta?,
        })
    }

    /// The record's PFA/PGA on a floor (1 on the ground).
    fn ratio(&self, record: &str) -> f64 {
        self.pfa_over_pga
            .iter()
            .find(|(r, _)| *r == record)
            .map_or(1.0, |r| r.1)
    }

    /// The fit row of `state` (any method: the counts are the same).
    pub fn row(&self, state: &str) -> Option<&DamageStateRow> {
        self.fits.iter().copied().find(|r| r.state == state)
    }

    /// The capacities (PGA/(αg), the ground's) of the records that reach
    /// `state`, ascending, and how many records there are.
    pub fn reached(&self, state: &str) -> (Vec<f64>, usize) {
        let of_state: Vec<&&StateCapacityRow> = self
            .capacities
            .iter()
            .filter(|c| c.state == state)
            .collect();
        let mut v: Vec<f64> = of_state
            .iter()
            .filter(|c| c.reached)
            .map(|c| 1.0 / c.eta / self.ratio(&c.record_id))
            .collect();
        v.sort_by(f64::total_cmp);
        (v, of_state.len())
    }
}

/// The example block's damage rows when the pipeline names one, else the
/// grid's middle block's; `None` without damage tables.
pub fn shown(d: &StudyData) -> Option<Shown<'_>> {
    let (which, spec, data, index): (_, _, &DamageData, Option<i64>) = match &d.example {
        Some(x) => (
            "the pipeline's example block".to_string(),
            &x.block,
            &x.damage,
            None,
        ),
        None => {
            let (bi, _, _) = middle(d);
            let spec = &d.records_plan().blocks[bi];
            (middle_name(d, bi), spec, &d.damage, Some(bi as i64))
        }
    };
    let (p, eps) = (spec.p, spec.eps);
    let caps = d.example.as_ref().map_or(&d.caps, |x| &x.caps);
    let pfa_over_pga = caps
        .iter()
        .filter_map(|c| Some((c.record_id.as_str(), c.pfa_over_pga?)))
        .collect();
    let of_block = move |i: i64| index.is_none_or(|b| b == i);
    let peak = d.named(Im::Pga);
    let fits: Vec<&DamageStateRow> = data
        .states
        .iter()
        .filter(|r| of_block(r.block_index) && r.im == peak.name())
        .collect();
    if fits.is_empty() {
        return None;
    }
    Some(Shown {
        which,
        p,
        eps,
        names: d
            .records_plan()
            .damage
            .states()
            .iter()
            .map(|s| s.name.clone())
            .collect(),
        fits,
        capacities: data
            .capacities
            .iter()
            .filter(|c| of_block(c.block_index))
            .collect(),
        pfa_over_pga,
        cut: cut_of(d, spec),
        peak: peak.short(),
    })
}

/// [`Shown::cut`] of the block `spec`.
fn cut_of(d: &StudyData, spec: &crate::pipeline::BlockSpec) -> Option<f64> {
    let floor = d.records_plan().floor.as_ref();
    let Some(alpha) = spec.alpha_rad else {
        // The grid's α → 0: the linearised block lifts at η = 1.
        return floor.is_none_or(|b| b.moves_as_ground()).then_some(1.0);
    };
    let block =
        crate::block::Block::of_p_alpha(spec.p, alpha, crate::block::Restitution::Value(spec.eps))
            .ok()?;
    let mu = spec.run.model.equation.friction().map(|f| f.mu_s);
    crate::cut::zero_below(&block, Im::Pga, floor, mu).map(|g| g / alpha)
}

/// The states' fragility curves of the shown block.
pub(super) fn damage_states(d: &StudyData) -> Vec<Figure> {
    let Some(s) = shown(d) else {
        return Vec::new();
    };
    let n = s.names.len();
    let fitted: Vec<(usize, Lognormal)> = (0..n)
        .filter_map(|j| Some((j, s.lognormal(&s.names[j], FitMethod::Fractile)?)))
        .collect();
    // To the 97.7 % point of the heaviest fitted state.
    let x_max = fitted
        .iter()
        .map(|(_, l)| l.median * (2.0 * l.beta).exp())
        .fold(0.0, f64::max);
    if !(x_max > 0.0 && x_max.is_finite()) {
        return Vec::new();
    }
    let mut lines = Vec::new();
    for (j, name) in s.names.iter().enumerate() {
        let hue = Hue::Ramp(if n > 1 {
            j as f64 / (n - 1) as f64
        } else {
            0.0
        });
        let (reached, total) = s.reached(name);
        let criterion = s.row(name).map_or(String::new(), |r| r.criterion.clone());
        if !reached.is_empty() {
            lines.push(Line {
                name: None,
                points: reached
                    .iter()
                    .enumerate()
                    .filter(|(_, &x)| x <= x_max)
                    .map(|(k, &x)| (x, (k + 1) as f64 / total as f64))
                    .collect(),
                style: Style::Points,
                hue,
            });
        }
        if let Some((_, l)) = fitted.iter().find(|(k, _)| *k == j) {
            lines.push(Line {
                name: Some(if criterion == "overturned" || criterion.is_empty() {
                    name.clone()
                } else {
                    format!("{name} ({criterion})")
                }),
                points: (1..=200)
                    .map(|i| {
                        let x = x_max * i as f64 / 200.0;
                        (x, s.probability(l, x))
                    })
                    .collect(),
                style: Style::Line,
                hue,
            });
        }
    }
    vec![Figure {
        file: "damage_states.svg".into(),
        chart: Chart {
            title: format!(
                "Damage-state fragility of {} (p = {:.2} 1/s, ε = {:.2})",
                s.which, s.p, s.eps
            ),
            x_desc: match s.pfa_over_pga.is_empty() {
                true => format!("{}/(αg) = 1/η (dimensionless)", s.peak),
                false => "the ground's PGA/(αg) (dimensionless)".into(),
            },
            y_desc: format!("P(state reached | {})", s.peak),
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
            x_range: Some((0.0, x_max)),
            y_range: Some((0.0, 1.0)),
            x_ticks: None,
            lines,
        },
        caption: format!(
            "Each limit state of `[damage]` for {}: the points are the records' own capacities \
             (the share of the {} records whose first crossing of the state lies at or below \
             that intensity; `state_capacities.parquet`{}), the line its lognormal by the \
             paper's fractile method (`damage_states.parquet`, which also holds the censored \
             maximum likelihood fit and every other IM). In {} multiply the axis by αg.",
            s.which,
            s.capacities.len() / n.max(1),
            match s.pfa_over_pga.is_empty() {
                true => "",
                false =>
                    ", whose η is the floor's: here each is divided by its record's \
                          PFA/PGA, into the ground's PGA as the fits are",
            },
            s.peak,
        ),
    }]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::figures::fixture::grid_study;

    fn cap(state: &str, eta: f64, reached: bool) -> StateCapacityRow {
        StateCapacityRow {
            block_index: 0,
            block: String::new(),
            p: 1.0,
            eps: 0.5,
            record_id: "r".into(),
            state: state.into(),
            eta,
            reached,
        }
    }

    fn fit(state: &str, method: FitMethod, median: f64, beta: f64) -> DamageStateRow {
        DamageStateRow {
            block_index: 0,
            block: String::new(),
            p: 1.0,
            eps: 0.5,
            state: state.into(),
            criterion: "θmax/α ≥ 0.1".into(),
            threshold: Some(0.1),
            im: "pga".into(),
            unit: "g".into(),
            method,
            n_records: 4,
            n_reached: 3,
            median: None,
            median_dimensionless: Some(median),
            dimensionless: Some("PGA/(αg)".into()),
            beta: Some(beta),
            lognormal_p: None,
        }
    }

    /// Records' shares step by 1/n at their capacities (1/η), one record
    /// censored never counts; the lognormal is ½ at its median; the axis
    /// ends at the heaviest fitted state's median·e^(2β).
    #[test]
    fn points_are_the_records_and_lines_their_lognormals() {
        let mut d = grid_study(&[1.0], &[0.5]);
        d.damage.capacities = vec![
            cap("rocking", 0.5, true),
            cap("rocking", 0.25, true),
            cap("rocking", 1.0, true),
            cap("rocking", 0.1, false),
        ];
        d.damage.states = vec![
            fit("rocking", FitMethod::Fractile, 2.0, 0.5),
            fit("rocking", FitMethod::MaxLikelihood, 2.2, 0.6),
        ];
        let figs = damage_states(&d);
        assert_eq!(figs.len(), 1);
        let c = &figs[0].chart;
        let x_max = 2.0 * 1.0f64.exp();
        assert_eq!(c.x_range, Some((0.0, x_max)));
        // The default states: rocking has points and a line, the others no fit.
        assert_eq!(
            c.lines[0].points,
            vec![(1.0, 0.25), (2.0, 0.5), (4.0, 0.75)]
        );
        for &(x, y) in &c.lines[1].points {
            assert_eq!(y > 0.5, x > 2.0, "{x}: {y}");
        }
        // The other default states have neither capacities nor fits.
        assert_eq!(c.lines.len(), 2);
        assert!(damage_states(&grid_study(&[1.0], &[0.5])).is_empty());
    }

    /// The curves are 0 below the PGA that lifts the block, g·tan α (in
    /// PGA/(αg): tan α/α), as every command counts them, and the state's
    /// lognormal above it (Φ by statrs); the grid's α → 0 block lifts at 1.
    #[test]
    fn the_curves_are_cut_where_the_block_cannot_move() {
        use statrs::distribution::{ContinuousCDF, Normal};
        let mut d = crate::figures::fixture::block_study();
        let alpha = (0.1f64 / 0.4).atan();
        d.damage.states = vec![fit("rocking", FitMethod::Fractile, 1.05, 0.5)];
        let s = shown(&d).unwrap();
        let cut = s.cut.unwrap();
        assert!((cut - 0.25 / alpha).abs() < 1e-12, "{cut}");
        let figs = damage_states(&d);
        let line = &figs[0].chart.lines[0].points;
        let phi = Normal::new(0.0, 1.0).unwrap();
        let (mut below, mut above) = (0, 0);
        for &(x, y) in line {
            let want = if x < cut {
                below += 1;
                0.0
            } else {
                above += 1;
                phi.cdf((x / 1.05).ln() / 0.5)
            };
            assert!((y - want).abs() < 1e-12, "{x}: {y} vs {want}");
        }
        assert!(below > 0 && above > 0);
        assert_eq!(shown(&grid_with_fit()).unwrap().cut, Some(1.0));
    }

    fn grid_with_fit() -> StudyData {
        let mut d = grid_study(&[1.0], &[0.5]);
        d.damage.states = vec![fit("rocking", FitMethod::Fractile, 2.0, 0.5)];
        d
    }

    /// On a building's floor the state capacities' η is the floor's and
    /// the fits are in the ground's PGA: the points were drawn as the
    /// floor's PFA/(αg) under the ground's lognormal, on an axis that said
    /// PGA. Each point is now its record's capacity over its PFA/PGA (by
    /// hand: 1/η ÷ ratio), and the axis and the block's name say so.
    #[test]
    fn on_a_floor_the_points_are_in_the_grounds_pga() {
        use crate::figures::fixture::{cap as capacity, floor_study};
        let mut d = floor_study();
        let records = [(0.5, 2.0), (0.25, 4.0), (0.2, 2.5)];
        d.caps = records
            .iter()
            .enumerate()
            .map(|(i, &(_, ratio))| crate::tables::sweep::CapacityRow {
                pfa_over_pga: Some(ratio),
                ..capacity(i as i64, None)
            })
            .collect();
        d.damage.capacities = records
            .iter()
            .enumerate()
            .map(|(i, &(eta, _))| StateCapacityRow {
                record_id: format!("r{i}"),
                ..cap("rocking", eta, true)
            })
            .collect();
        d.damage.states = vec![fit("rocking", FitMethod::Fractile, 1.0, 0.5)];
        let figs = damage_states(&d);
        let c = &figs[0].chart;
        // 1/0.5/2 = 1, 1/0.25/4 = 1, 1/0.2/2.5 = 2.
        assert_eq!(
            c.lines[0].points,
            vec![(1.0, 1.0 / 3.0), (1.0, 2.0 / 3.0), (2.0, 1.0)]
        );
        assert_eq!(c.x_desc, "the ground's PGA/(αg) (dimensionless)");
        assert!(figs[0].caption.contains("divided by its record's PFA/PGA"));
        assert!(c.title.contains("block `rack`"), "{}", c.title);
    }
}
