//! `[example]`: the report's Fig. 5 block, run over the records by the
//! `example` stage even when it is not one of the study's blocks. Its
//! capacities against direct `rocking capacity` calls, its horizontal
//! fractiles against a hand-worked type-7 rule with resurrection, the same
//! block on the grid against the sweep's rows, Fig. 5 drawn at it, the
//! grid left alone, reruns for the right reason, and bad `[example]`s
//! refused naming the key.

use std::path::Path;

use rocking::ida::RunKind;
use rocking::tables::read;
use rocking::tables::reduce::HorizontalRow;
use rocking::tables::sweep::{CapacityRow, IdaRow};

use crate::util::{direct_capacity, rocking, root, stderr, stdout, tempdir, write_pipeline};

const RECORDS: [&str; 5] = [
    "RSN953_NORTHR_MUL009",
    "RSN960_NORTHR_LOS000",
    "RSN1602_DUZCE_BOL000",
    "RSN1787_HECTOR_HEC000",
    "RSN1111_KOBE_NIS000",
];

/// Five records, two blocks at ε = 0.7 (p = 1 and 5), a coarse grid, and
/// the example `example`.
fn body(example: &str) -> String {
    format!(
        "ids = {RECORDS:?}\n[blocks]\np = [1.0, 5.0]\neps = [0.7]\n[im]\ncount = 60\n\
         eta_min = 0.01\n{example}"
    )
}

fn run(pipe: &Path, out: &Path) -> String {
    let r = rocking(
        &root(),
        &[
            "run",
            pipe.to_str().unwrap(),
            "--outputs",
            out.to_str().unwrap(),
        ],
    );
    assert!(r.status.success(), "{}", stderr(&r));
    stderr(&r) + &stdout(&r)
}

/// Type-7 fractile of ascending values that may end in +∞ (a record that
/// overturned): interpolation toward +∞ is +∞.
fn type7(sorted: &[f64], q: f64) -> f64 {
    let h = (sorted.len() - 1) as f64 * q;
    let (lo, g) = (h.floor() as usize, h - h.floor());
    if g == 0.0 {
        return sorted[lo];
    }
    let (a, b) = (sorted[lo], sorted[lo + 1]);
    if b.is_infinite() {
        f64::INFINITY
    } else {
        a + g * (b - a)
    }
}

#[test]
fn an_example_off_the_grid_runs_every_record_and_fig5_draws_it() {
    let dir = tempdir();
    let pipe = write_pipeline(dir.path(), "ex", &body("[example]\np = 2.0\neps = 0.7\n"));
    let out = dir.path().join("out");
    run(&pipe, &out);
    let folder = out.join("ex");

    // The grid is the study's two blocks only.
    let grid: Vec<CapacityRow> = read(&folder.join("capacities.parquet")).unwrap();
    assert_eq!(grid.len(), 10);
    assert!(grid.iter().all(|c| c.p == 1.0 || c.p == 5.0));

    // Each record's capacity is the one `rocking capacity` finds.
    let caps: Vec<CapacityRow> = read(&folder.join("example_capacities.parquet")).unwrap();
    assert_eq!(caps.len(), RECORDS.len());
    let mut ids: Vec<&str> = RECORDS.to_vec();
    ids.sort();
    for (k, c) in caps.iter().enumerate() {
        assert_eq!((c.case_id, c.record_id.as_str()), (k as i64, ids[k]));
        assert_eq!((c.p, c.eps), (2.0, 0.7));
        let record = format!("records/fema-p695/far-field/{}.AT2", c.record_id);
        let v = direct_capacity(&root(), &record, 2.0, 0.7, 60);
        assert_eq!(c.eta_c, v["eta_c"].as_f64(), "{}", c.record_id);
        assert_eq!(c.eta_survived, v["eta_survived"].as_f64().unwrap());
    }
    assert!(
        caps.iter().any(|c| c.eta_c.is_some()),
        "no record overturns the example: the fractile checks below would not see +∞"
    );

    // Horizontal fractiles: at each level, every record's EDP (+∞ at and
    // after its first overturning as η falls), sorted, and type 7.
    let ida: Vec<IdaRow> = read(&folder.join("example_ida_points.parquet")).unwrap();
    let horizontal: Vec<HorizontalRow> =
        read(&folder.join("example_fractiles_horizontal.parquet")).unwrap();
    assert_eq!(horizontal.len(), 60);
    let mut infinite_medians = 0;
    for h in &horizontal {
        let mut edp: Vec<f64> = caps
            .iter()
            .map(|c| {
                if c.level_overturned.is_some_and(|lo| lo >= h.eta) {
                    return f64::INFINITY;
                }
                let run = ida
                    .iter()
                    .find(|r| {
                        r.case_id == c.case_id && r.run_kind == RunKind::Level && r.eta == h.eta
                    })
                    .expect("a survivor was run at every level");
                assert!(!run.overturned);
                run.edp
            })
            .collect();
        edp.sort_by(f64::total_cmp);
        let n_over = edp.iter().filter(|e| e.is_infinite()).count();
        assert_eq!(h.n_overturned, n_over as i64, "η = {}", h.eta);
        assert_eq!(h.n_records, 5);
        for (got, q) in [(h.edp_q16, 0.16), (h.edp_q50, 0.5), (h.edp_q84, 0.84)] {
            let want = type7(&edp, q);
            assert!(
                got == want || (got - want).abs() <= 1e-12 * want.abs(),
                "η = {}, q = {q}: {got} against {want}",
                h.eta
            );
        }
        infinite_medians += usize::from(h.edp_q50.is_infinite());
    }
    assert!(infinite_medians > 0, "the median never reaches +∞");

    // Fig. 5 is drawn at the example, and the report says so.
    let svg = std::fs::read_to_string(folder.join("figures/fig05_ida_curves.svg")).unwrap();
    assert!(
        svg.contains("IDA curves of 5 records, p = 2.000 1/s, ε = 0.70"),
        "Fig. 5's title"
    );
    let md = std::fs::read_to_string(folder.join("report.md")).unwrap();
    assert!(md.contains("the pipeline's example block"), "{md}");

    // Moving the example reruns the example and the report only.
    let moved = write_pipeline(dir.path(), "ex", &body("[example]\np = 3.0\neps = 0.7\n"));
    let log = run(&moved, &out);
    for stage in ["ingest", "sweep", "convergence", "reduce", "fit"] {
        assert!(
            !log.lines()
                .any(|l| l.starts_with(stage) && l.contains("running")),
            "{stage} reran:\n{log}"
        );
    }
    assert!(
        log.contains("example      running: settings changed"),
        "{log}"
    );
    let caps: Vec<CapacityRow> = read(&folder.join("example_capacities.parquet")).unwrap();
    assert!(caps.iter().all(|c| c.p == 3.0));
}

#[test]
fn an_example_on_the_grid_equals_the_sweeps_block() {
    let dir = tempdir();
    let pipe = write_pipeline(dir.path(), "on", &body("[example]\np = 5.0\neps = 0.7\n"));
    let out = dir.path().join("out");
    run(&pipe, &out);
    let folder = out.join("on");
    let grid: Vec<CapacityRow> = read(&folder.join("capacities.parquet")).unwrap();
    let caps: Vec<CapacityRow> = read(&folder.join("example_capacities.parquet")).unwrap();
    let grid: Vec<&CapacityRow> = grid.iter().filter(|c| c.p == 5.0).collect();
    assert_eq!(grid.len(), caps.len());
    for (g, e) in grid.iter().zip(&caps) {
        assert_eq!(g.record_id, e.record_id);
        assert_eq!(
            (g.eta_c, g.eta_survived, g.runs, g.certified),
            (e.eta_c, e.eta_survived, e.runs, e.certified)
        );
    }
    let h: Vec<HorizontalRow> = read(&folder.join("fractiles_horizontal.parquet")).unwrap();
    let he: Vec<HorizontalRow> =
        read(&folder.join("example_fractiles_horizontal.parquet")).unwrap();
    let h: Vec<&HorizontalRow> = h.iter().filter(|r| r.p == 5.0).collect();
    assert_eq!(h.len(), he.len());
    for (a, b) in h.iter().zip(&he) {
        assert_eq!(
            (a.eta, a.edp_q16, a.edp_q50, a.edp_q84, a.n_overturned),
            (b.eta, b.edp_q16, b.edp_q50, b.edp_q84, b.n_overturned)
        );
    }
}

#[test]
fn a_pipeline_without_an_example_draws_the_grid_middle_and_skips_the_stage() {
    let dir = tempdir();
    let pipe = write_pipeline(dir.path(), "none", &body(""));
    let out = dir.path().join("out");
    let log = run(&pipe, &out);
    assert!(
        log.contains("example      skipped: not needed: the pipeline has no [example] block"),
        "{log}"
    );
    let folder = out.join("none");
    assert!(!folder.join("example_capacities.parquet").exists());
    // The grid's p are 1 and 5: the middle (upper of two) is 5.
    let svg = std::fs::read_to_string(folder.join("figures/fig05_ida_curves.svg")).unwrap();
    assert!(svg.contains("p = 5.000 1/s, ε = 0.70"), "Fig. 5's title");
}

#[test]
fn bad_examples_are_refused_naming_the_key() {
    let dir = tempdir();
    let cases = [
        (
            "[example]\np = -1.0\neps = 0.7\n",
            "`example.p`: p = -1 1/s is outside",
        ),
        ("[example]\np = 2.0\neps = 1.5\n", "`example.eps`"),
        (
            "[example]\np = 2.0\neps = \"housner\"\n",
            "\"housner\" needs b and h",
        ),
        (
            "[example]\np = 2.0\nb = 0.2\nh = 1.0\neps = 0.7\n",
            "`[example]` takes `p` and `eps`, or",
        ),
        ("[example]\np = 2.0\n", "eps"),
        (
            "[example]\np = 2.0\neps = 0.7\nq = 1\n",
            "unknown field `q`",
        ),
        (
            "[model]\nkind = \"nonlinear\"\n[example]\np = 2.0\neps = 0.7\n",
            "needs `model.alpha`",
        ),
        (
            "[example]\nb = 0.0\nh = 1.0\neps = 0.7\n",
            "`example`: b and h",
        ),
    ];
    for (k, (example, want)) in cases.iter().enumerate() {
        let name = format!("bad{k}");
        let pipe = write_pipeline(dir.path(), &name, &body(example));
        let r = rocking(&root(), &["status", pipe.to_str().unwrap()]);
        assert!(!r.status.success(), "{example} was accepted");
        let e = stderr(&r);
        assert!(
            e.contains(want) && e.contains(&format!("{name}.toml")),
            "{example}: {e}"
        );
    }
    // A physical example works beside physical blocks, and a pulse map
    // refuses an example.
    let physical = write_pipeline(
        dir.path(),
        "phys",
        &format!(
            "ids = {RECORDS:?}\n[[block]]\nb = 0.2\nh = 1.0\neps = 0.7\n\
             [example]\nname = \"cabinet\"\nb = 0.25\nh = 1.0\neps = \"housner\"\n"
        ),
    );
    let r = rocking(&root(), &["status", physical.to_str().unwrap()]);
    assert!(r.status.success(), "{}", stderr(&r));
    let pulses = dir.path().join("map.toml");
    std::fs::write(
        &pulses,
        "[pulses]\nshape = \"rect\"\ncycle = \"full\"\nf = [1.0]\neta = [0.1]\neps = [0.7]\n\
         [example]\np = 2.0\neps = 0.7\n",
    )
    .unwrap();
    let r = rocking(&root(), &["status", pulses.to_str().unwrap()]);
    assert!(!r.status.success());
    assert!(stderr(&r).contains("remove [example]"), "{}", stderr(&r));
}
