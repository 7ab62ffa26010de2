//! The IDA figures: every record's IDA curve of one block with the
//! horizontal fractiles (paper Fig. 5), and the median IDA curves across p
//! (paper Fig. 6).

use super::figure::Figure;
use super::shared::{middle, Q_NAMES};
use crate::ida::RunKind;
use crate::plot::{Chart, Line, Scale, Style};
use crate::study::StudyData;
use crate::tables::reduce::HorizontalRow;

/// Horizontal fractile curve q (0, 1, 2) of a block as (EDP, 1/η), ending at
/// EDP = 1 where the fractile becomes +∞.
fn fractile_curve(rows: &[HorizontalRow], p: f64, e: f64, qi: usize) -> Vec<(f64, f64)> {
    let mut pts = vec![(0.0, 1.0)];
    for r in rows.iter().filter(|r| r.p == p && r.eps == e) {
        let edp = [r.edp_q16, r.edp_q50, r.edp_q84][qi];
        if edp.is_infinite() || edp >= 1.0 {
            pts.push((1.0, 1.0 / r.eta));
            break;
        }
        pts.push((edp, 1.0 / r.eta));
    }
    pts
}

/// Fig. 5: every record's IDA curve for one block, and the fractiles.
pub(super) fn ida_curves(d: &StudyData) -> Vec<Figure> {
    // The pipeline's example block when it names one, else the grid's middle.
    let (p_mid, e_mid, caps, ida, horizontal, which) = match &d.example {
        Some(x) => (
            x.block.p,
            x.block.eps,
            x.caps.iter().collect::<Vec<_>>(),
            &x.ida,
            &x.horizontal,
            "the pipeline's example block (`[example]`)",
        ),
        None => {
            let n_blocks = d.plan.blocks.len();
            let (bi, p, e) = middle(d);
            let caps = d
                .caps
                .iter()
                .filter(|c| c.case_id as usize % n_blocks == bi)
                .collect();
            (p, e, caps, &d.ida, &d.horizontal, "the grid's middle block")
        }
    };
    let mut lines = Vec::new();
    let mut cap_max: f64 = 0.0;
    for c in &caps {
        let mut pts = vec![(0.0, 1.0)];
        for r in ida
            .iter()
            .filter(|r| r.case_id == c.case_id && r.run_kind == RunKind::Level)
        {
            if r.overturned {
                break;
            }
            pts.push((r.edp, r.pga_scale));
        }
        if let Some(ec) = c.eta_c {
            pts.push((1.0, 1.0 / ec));
        }
        lines.push(Line {
            name: None,
            points: pts,
            style: Style::Faint,
            color: 0,
        });
    }
    for (qi, q_name) in Q_NAMES.iter().enumerate() {
        let pts = fractile_curve(horizontal, p_mid, e_mid, qi);
        cap_max = cap_max.max(pts.last().map_or(0.0, |p| p.1));
        lines.push(Line {
            name: Some(format!("{q_name} fractile")),
            points: pts,
            style: Style::Line,
            color: qi + 1,
        });
    }
    vec![Figure {
        file: "fig05_ida_curves.svg".into(),
        chart: Chart {
            title: format!(
                "IDA curves of {} records, p = {p_mid:.3} 1/s, ε = {e_mid:.2}",
                caps.len()
            ),
            x_desc: "θmax / α".into(),
            y_desc: "A_g / (α g) = 1/η".into(),
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
            x_range: Some((0.0, 1.05)),
            y_range: Some((0.0, 1.4 * cap_max.max(1.0))),
            lines,
        },
        caption: format!(
            "Every record's IDA curve for {which} (grey: θmax/α against the intensity until the \
             first overturning, which is drawn at θmax/α = 1) and the 16/50/84 % horizontal \
             fractiles under the resurrection rule (paper Fig. 5)."
        ),
    }]
}

/// Fig. 6: median IDA curves across p.
pub(super) fn median_ida_across_p(d: &StudyData) -> Vec<Figure> {
    if !d.is_grid() {
        return Vec::new();
    }
    let (ps, _) = d.ps_and_eps();
    let (_, _, e_mid) = middle(d);
    let lines = ps
        .iter()
        .enumerate()
        .map(|(k, &p)| Line {
            name: Some(format!("p = {p:.2} 1/s")),
            points: fractile_curve(&d.horizontal, p, e_mid, 1),
            style: Style::Line,
            color: k,
        })
        .collect();
    vec![Figure {
        file: "fig06_median_ida_across_p.svg".into(),
        chart: Chart {
            title: format!("Median IDA curves across p, ε = {e_mid:.2}"),
            x_desc: "θmax / α (50 % fractile)".into(),
            y_desc: "A_g / (α g) = 1/η".into(),
            x_scale: Scale::Linear,
            y_scale: Scale::Log,
            x_range: Some((0.0, 1.05)),
            y_range: None,
            lines,
        },
        caption: "The 50 % horizontal fractile IDA curve for each p at the middle ε (paper \
                  Fig. 6): smaller blocks (larger p) overturn at lower intensity."
            .into(),
    }]
}
