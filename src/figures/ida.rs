//! The IDA figures: every record's IDA curve of one block with the
//! horizontal fractiles (paper Fig. 5), and the median IDA curves across p
//! (paper Fig. 6).

use super::figure::Figure;
use super::shared::{middle, middle_name, one_over_eta, ramp, Q_NAMES};
use crate::ida::RunKind;
use crate::plot::{Chart, Hue, Line, Scale, Style};
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
            "the pipeline's example block (`[example]`)".to_string(),
        ),
        None => {
            let n_blocks = d.records_plan().blocks.len();
            let (bi, p, e) = middle(d);
            let caps = d
                .caps
                .iter()
                .filter(|c| c.case_id as usize % n_blocks == bi)
                .collect();
            (p, e, caps, &d.ida, &d.horizontal, middle_name(d, bi))
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
            hue: Hue::Ink,
        });
    }
    for (qi, q_name) in Q_NAMES.iter().enumerate() {
        let pts = fractile_curve(horizontal, p_mid, e_mid, qi);
        cap_max = cap_max.max(pts.last().map_or(0.0, |p| p.1));
        lines.push(Line {
            name: Some(format!("{q_name} fractile")),
            points: pts,
            style: Style::Line,
            hue: Hue::Fractile(qi),
        });
    }
    // Room above the fractiles for the legend, and never below a point: the
    // strongest record's capacity can lie far above the 84 % fractile's end.
    let highest = lines
        .iter()
        .flat_map(|l| l.points.iter().map(|q| q.1))
        .fold(1.0, f64::max);
    let y_top = (1.4 * cap_max.max(1.0)).max(1.05 * highest);
    vec![Figure {
        file: "fig05_ida_curves.svg".into(),
        chart: Chart {
            title: format!(
                "IDA curves of {} records, p = {p_mid:.3} 1/s, ε = {e_mid:.2}",
                caps.len()
            ),
            x_desc: "θmax / α".into(),
            y_desc: one_over_eta(d).into(),
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
            x_range: Some((0.0, 1.05)),
            y_range: Some((0.0, y_top)),
            x_ticks: None,
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
        .map(|&p| Line {
            name: Some(format!("p = {p:.2} 1/s")),
            points: fractile_curve(&d.horizontal, p, e_mid, 1),
            style: Style::Line,
            hue: ramp(&ps, p),
        })
        .collect();
    vec![Figure {
        file: "fig06_median_ida_across_p.svg".into(),
        chart: Chart {
            title: format!("Median IDA curves across p, ε = {e_mid:.2}"),
            x_desc: "θmax / α (50 % fractile)".into(),
            y_desc: one_over_eta(d).into(),
            x_scale: Scale::Linear,
            y_scale: Scale::Log,
            x_range: Some((0.0, 1.05)),
            y_range: None,
            x_ticks: None,
            lines,
        },
        caption: "The 50 % horizontal fractile IDA curve for each p at the middle ε (paper \
                  Fig. 6): smaller blocks (larger p) overturn at lower intensity."
            .into(),
    }]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::figures::fixture::{block_study, cap, grid_study, horizontal, run};

    /// p = 1, 2, 4 × ε = 0.5, 0.9: the middle block is (2, 0.9), block 3 of
    /// 6, whose records are cases 3 and 9.
    fn study() -> StudyData {
        let mut d = grid_study(&[1.0, 2.0, 4.0], &[0.5, 0.9]);
        d.caps = vec![cap(3, Some(0.5)), cap(9, None), cap(0, Some(0.8))];
        let mut refinement = run(3, 0.7, 0.5, false);
        refinement.run_kind = RunKind::Refinement;
        d.ida = vec![
            run(3, 0.5, 0.1, false),
            refinement,
            run(3, 1.0, 0.4, false),
            run(3, 2.0, 1.0, true),
            run(3, 4.0, 1.0, true),
            run(9, 0.5, 0.2, false),
            run(0, 0.5, 0.3, false),
        ];
        let inf = f64::INFINITY;
        d.horizontal = vec![
            horizontal(2.0, 0.9, 2.0, [0.1, 0.2, 0.3]),
            horizontal(2.0, 0.9, 1.0, [0.3, 0.6, inf]),
            horizontal(2.0, 0.9, 0.5, [1.0, inf, inf]),
            horizontal(1.0, 0.5, 2.0, [0.7, 0.8, 0.9]),
        ];
        d
    }

    #[test]
    fn fig5_draws_each_record_of_the_middle_block_until_it_overturns() {
        let figs = ida_curves(&study());
        assert_eq!(figs.len(), 1);
        let c = &figs[0].chart;
        assert_eq!(figs[0].file, "fig05_ida_curves.svg");
        assert_eq!(c.title, "IDA curves of 2 records, p = 2.000 1/s, ε = 0.90");
        assert_eq!((c.x_scale, c.y_scale), (Scale::Linear, Scale::Linear));
        assert_eq!(c.lines.len(), 5);
        // Case 3: its grid levels (not the refinement run) until the first
        // overturning, then its capacity η_c = 0.5 at θmax/α = 1 (1/η = 2).
        assert_eq!(
            c.lines[0].points,
            [(0.0, 1.0), (0.1, 0.5), (0.4, 1.0), (1.0, 2.0)]
        );
        assert_eq!(
            (c.lines[0].style, c.lines[0].name.clone()),
            (Style::Faint, None)
        );
        // Case 9 never overturned: no capacity point.
        assert_eq!(c.lines[1].points, [(0.0, 1.0), (0.2, 0.5)]);
        // The fractiles along the block's levels, ending where EDP reaches 1.
        let names: Vec<_> = c.lines[2..]
            .iter()
            .map(|l| l.name.clone().unwrap())
            .collect();
        assert_eq!(names, ["16 % fractile", "50 % fractile", "84 % fractile"]);
        assert_eq!(
            c.lines[2].points,
            [(0.0, 1.0), (0.1, 0.5), (0.3, 1.0), (1.0, 2.0)]
        );
        assert_eq!(
            c.lines[3].points,
            [(0.0, 1.0), (0.2, 0.5), (0.6, 1.0), (1.0, 2.0)]
        );
        assert_eq!(c.lines[4].points, [(0.0, 1.0), (0.3, 0.5), (1.0, 1.0)]);
        // The intensity axis reaches 40 % above the highest fractile's end (1/η = 2).
        assert_eq!(c.y_range, Some((0.0, 2.8)));
        assert_eq!(c.x_range, Some((0.0, 1.05)));
    }

    /// The strongest record's capacity (1/η_c = 14.7, far above the 84 %
    /// fractile's end at 2) lies inside the frame, not clamped to its top
    /// (the paper study's Fig. 5 once cut its axis at 12.3).
    #[test]
    fn fig5_frame_holds_every_point() {
        let mut d = study();
        d.caps.push(cap(15, Some(1.0 / 14.7)));
        let c = &ida_curves(&d)[0].chart;
        let (x_range, y_range) = (c.x_range.unwrap(), c.y_range.unwrap());
        for l in &c.lines {
            for &(x, y) in &l.points {
                assert!(
                    x >= x_range.0 && x <= x_range.1,
                    "x = {x} outside {x_range:?}"
                );
                assert!(
                    y >= y_range.0 && y <= y_range.1,
                    "y = {y} outside {y_range:?}"
                );
            }
        }
        assert!(y_range.1 < 1.1 * 14.7, "no more room than 5 %: {y_range:?}");
        assert!(!c.y_desc.contains('_'), "{}", c.y_desc);
    }

    /// With `[example]`, Fig. 5 draws the example block's own runs (cases
    /// numbered by record), not the grid's.
    #[test]
    fn fig5_draws_the_example_block_when_the_pipeline_names_one() {
        let mut d = study();
        let mut block = d.records_plan().blocks[0].clone();
        (block.p, block.eps) = (3.0, 0.6);
        d.example = Some(crate::study::ExampleData {
            block,
            caps: vec![cap(0, Some(0.25))],
            ida: vec![run(0, 1.0, 0.5, false)],
            horizontal: vec![horizontal(3.0, 0.6, 1.0, [0.25, 0.5, 0.75])],
            damage: Default::default(),
        });
        let figs = ida_curves(&d);
        let c = &figs[0].chart;
        assert_eq!(c.title, "IDA curves of 1 records, p = 3.000 1/s, ε = 0.60");
        assert!(figs[0].caption.contains("`[example]`"));
        assert_eq!(c.lines[0].points, [(0.0, 1.0), (0.5, 1.0), (1.0, 4.0)]);
        assert_eq!(c.lines[2].points, [(0.0, 1.0), (0.5, 1.0)]);
    }

    #[test]
    fn fig6_draws_the_median_curve_of_every_p_at_the_middle_eps() {
        let figs = median_ida_across_p(&study());
        assert_eq!(figs.len(), 1);
        let c = &figs[0].chart;
        assert_eq!(c.title, "Median IDA curves across p, ε = 0.90");
        assert_eq!(c.y_scale, Scale::Log);
        let names: Vec<_> = c.lines.iter().map(|l| l.name.clone().unwrap()).collect();
        assert_eq!(names, ["p = 1.00 1/s", "p = 2.00 1/s", "p = 4.00 1/s"]);
        // Only (2, 0.9) has levels at ε = 0.9; the others start and stop at rest.
        assert_eq!(c.lines[0].points, [(0.0, 1.0)]);
        assert_eq!(
            c.lines[1].points,
            [(0.0, 1.0), (0.2, 0.5), (0.6, 1.0), (1.0, 2.0)]
        );
        assert_eq!(c.lines[2].points, [(0.0, 1.0)]);
    }

    #[test]
    fn fig6_needs_the_grid() {
        assert!(median_ida_across_p(&block_study()).is_empty());
    }

    /// A study of named blocks has no "grid's middle block", and on a
    /// building's floor 1/η is the floor's PFA over αg, not the PGA the
    /// axis named.
    #[test]
    fn fig5_names_the_block_and_what_one_over_eta_is_of() {
        let ground = &ida_curves(&block_study())[0];
        assert_eq!(ground.chart.y_desc, "PGA / (α g) = 1/η");
        assert!(
            ground.caption.contains("for block `vase`"),
            "{}",
            ground.caption
        );
        let floor = &ida_curves(&crate::figures::fixture::floor_study())[0];
        assert_eq!(floor.chart.y_desc, "PFA / (α g) = 1/η, on the floor");
    }
}
