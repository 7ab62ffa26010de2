//! The IM figures: how the dispersion β of the capacity in each IM varies
//! with p, and which SA period predicts overturning best.

use super::figure::Figure;
use super::shared::ramp;
use crate::im::Im;
use crate::plot::{Chart, Hue, Line, Scale, Style};
use crate::study::StudyData;
use crate::tables::ims::EfficiencyRow;

/// The SA periods (s) drawn against p; every other capacity measure is
/// drawn.
pub const SHOWN_PERIODS_S: [f64; 3] = [0.3, 1.0, 3.0];

/// The IMs drawn against p, in legend order: every capacity measure, SA at
/// [`SHOWN_PERIODS_S`] only.
pub fn shown() -> Vec<Im> {
    Im::capacity_measures()
        .into_iter()
        .filter(|im| match im {
            Im::Sa(t) => SHOWN_PERIODS_S.contains(t),
            _ => true,
        })
        .collect()
}

/// An IM's name as a reader writes it ([`Im::short`]: PGA, SA(1.0),
/// AvgSA, Arias, CAV), or the efficiency table's vector row in capitals.
pub fn display_name(im: &str) -> String {
    im.parse::<Im>()
        .map_or_else(|_| im.to_uppercase(), |im| im.short())
}

/// The ε the β-against-p figure is drawn at: the grid's nearest to 0.75
/// (the paper's middle value) among those whose blocks overturn (a block
/// that slides first, say, has no capacity to disperse).
pub fn shown_eps(d: &StudyData) -> Option<f64> {
    let (_, es) = d.ps_and_eps();
    es.iter()
        .copied()
        .filter(|&e| d.efficiency.iter().any(|r| r.eps == e))
        .min_by(|a, b| (a - 0.75).abs().total_cmp(&(b - 0.75).abs()))
}

/// (p, β) of one IM at ε, in increasing p.
fn series(rows: &[EfficiencyRow], im: &str, eps: f64) -> Vec<(f64, f64)> {
    let mut v: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| r.im == im && r.eps == eps)
        .map(|r| (r.p, r.beta))
        .collect();
    v.sort_by(|a, b| a.0.total_cmp(&b.0));
    v
}

/// The SA period of smallest β for each block at ε, in increasing p.
pub fn best_periods(rows: &[EfficiencyRow], eps: f64) -> Vec<(f64, f64, f64)> {
    let mut best: Vec<(f64, f64, f64)> = Vec::new();
    for r in rows.iter().filter(|r| r.eps == eps) {
        let Ok(Im::Sa(t)) = r.im.parse() else {
            continue;
        };
        match best.iter_mut().find(|b| b.0 == r.p) {
            Some(b) if r.beta < b.2 => *b = (r.p, t, r.beta),
            Some(_) => {}
            None => best.push((r.p, t, r.beta)),
        }
    }
    best.sort_by(|a, b| a.0.total_cmp(&b.0));
    best
}

/// β against p for each IM, at one ε; and the best SA period against p,
/// one line per ε.
pub(super) fn im_efficiency(d: &StudyData) -> Vec<Figure> {
    let (ps, es) = d.ps_and_eps();
    let Some(eps) = shown_eps(d) else {
        return Vec::new();
    };
    if d.efficiency.is_empty() || ps.len() < 2 {
        return Vec::new();
    }
    let mut lines: Vec<Line> = shown()
        .into_iter()
        .enumerate()
        .map(|(i, im)| Line {
            name: Some(im.short()),
            points: series(&d.efficiency, &im.name(), eps),
            style: Style::Line,
            hue: Hue::Series(i),
        })
        .filter(|l| !l.points.is_empty())
        .collect();
    lines.push(Line {
        name: Some("PGA | PGV/PGA".into()),
        points: series(&d.efficiency, crate::im::efficiency::VECTOR, eps),
        style: Style::Dashed,
        hue: Hue::Ink,
    });
    // Up to 1.2, or to the largest β (Arias's exceeds it at small p: its
    // line once ran clipped along the top of the frame).
    let top = lines
        .iter()
        .flat_map(|l| l.points.iter().map(|p| p.1))
        .fold(1.2f64, f64::max);
    let top = (top * 1.05 / 0.2).ceil() * 0.2;
    let beta = Figure {
        file: "im_efficiency.svg".into(),
        chart: Chart {
            title: format!("Dispersion of the overturning capacity in each IM, ε = {eps}"),
            x_desc: "p (1/s)".into(),
            y_desc: "β, standard deviation of ln IM at overturning (dimensionless)".into(),
            x_scale: Scale::Log,
            y_scale: Scale::Linear,
            x_range: None,
            y_range: Some((0.0, top)),
            x_ticks: None,
            lines,
        },
        caption: format!(
            "The smaller β, the better the IM predicts overturning: each record's capacity \
             converted into the IM (the record scaled to overturn the block), and β the standard \
             deviation of its logarithm over the records. ε = {eps}; SA at 5 % damping; the \
             dashed black line is PGA given the record's PGV/PGA (a two-parameter fragility)."
        ),
    };
    let periods = Figure {
        file: "im_best_sa_period.svg".into(),
        chart: Chart {
            title: "The SA period that predicts overturning best".into(),
            x_desc: "p (1/s)".into(),
            y_desc: "period T of the smallest β of SA(T) (s)".into(),
            x_scale: Scale::Log,
            y_scale: Scale::Log,
            x_range: None,
            y_range: Some((0.04, 5.0)),
            x_ticks: None,
            lines: es
                .iter()
                .map(|&e| Line {
                    name: Some(format!("ε = {e}")),
                    points: best_periods(&d.efficiency, e)
                        .into_iter()
                        .map(|(p, t, _)| (p, t))
                        .collect(),
                    style: Style::Line,
                    hue: ramp(&es, e),
                })
                .collect(),
        },
        caption: "For each block, the period among 0.05–4 s whose SA has the smallest \
                  dispersion of the capacity: larger blocks (small p) follow longer periods."
            .into(),
    };
    vec![beta, periods]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(p: f64, eps: f64, im: &str, beta: f64) -> EfficiencyRow {
        EfficiencyRow {
            block_index: 0,
            block: String::new(),
            p,
            eps,
            im: im.into(),
            unit: "g".into(),
            n: 44,
            median: None,
            median_dimensionless: None,
            dimensionless: None,
            beta,
            lilliefors_p: None,
            rank: None,
            slope: None,
        }
    }

    /// Every β drawn lies inside the frame: Arias's β of 1.6–1.7 at small
    /// p once ran clipped along the top of a frame fixed at 1.2.
    #[test]
    fn no_dispersion_is_clipped() {
        let mut d = super::super::fixture::grid_study(&[1.0, 2.0], &[0.75]);
        for (p, beta) in [(1.0, 1.67), (2.0, 0.9)] {
            d.efficiency.push(row(p, 0.75, "arias", beta));
            d.efficiency.push(row(p, 0.75, "pga", 0.4));
        }
        let figs = im_efficiency(&d);
        let chart = &figs[0].chart;
        let (lo, hi) = chart.y_range.unwrap();
        let ys = chart
            .lines
            .iter()
            .flat_map(|l| l.points.iter().map(|p| p.1));
        assert!(ys.clone().any(|y| y == 1.67));
        assert!(ys.into_iter().all(|y| (lo..=hi).contains(&y)), "{hi}");
        assert_eq!(hi, 1.8);
    }

    #[test]
    fn the_best_period_is_the_smallest_beta() {
        let rows = vec![
            row(1.0, 0.7, "sa(0.3)", 0.5),
            row(1.0, 0.7, "sa(2.0)", 0.3),
            row(4.0, 0.7, "sa(0.3)", 0.2),
            row(4.0, 0.7, "sa(2.0)", 0.4),
            row(4.0, 0.9, "sa(0.3)", 0.9),
            row(4.0, 0.7, "pgv", 0.1),
        ];
        assert_eq!(
            best_periods(&rows, 0.7),
            vec![(1.0, 2.0, 0.3), (4.0, 0.3, 0.2)]
        );
    }
}
