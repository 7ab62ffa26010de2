//! Nonlinear capacities that do not depend on DP5's tolerance.
//! The hard cases (the issue's and the worst the tolerance study found)
//! against a tight reference of the same equation, grid and bisection (the
//! plain search at rtol 1e-12 or 1e-13); a chaotic case flagged rather than
//! answered; the exact stepper's verdicts stable under a one-ulp change of
//! the record; the certification in `capacities.parquet` and `capacity --json`.

use rocking::ida::HARD_CASES;
use rocking::ida::{
    capacity_certified, capacity_traced, decisive_runs, Certification, CertificationKind, ImGrid,
    Trace,
};
use rocking::physics::{simulate, Model, RunSpec, DEFAULT_RTOL, DEFAULT_TAYLOR_TOL};
use rocking::stages::sweep::read_capacities;

use crate::util::{bundled, rocking, root, stderr, tempdir, write_pipeline};

fn far(stem: &str) -> rocking::physics::Excitation {
    bundled(&format!("far-field/{stem}"))
}

/// Checks a chaos verdict independently of the certification: the run at
/// `eta` and the runs with η moved by ±1e-9 (relative), all with `spec`'s
/// model, do not all agree.
fn assert_chaotic_at(exc: &rocking::physics::Excitation, spec: RunSpec, eta: f64) {
    let at = |e: f64| {
        simulate(exc, &RunSpec { eta: e, ..spec })
            .unwrap()
            .overturned()
    };
    let verdicts = [at(eta * (1.0 - 1e-9)), at(eta), at(eta * (1.0 + 1e-9))];
    assert!(
        verdicts.iter().any(|&v| v != verdicts[1]),
        "η = {eta}: {verdicts:?}"
    );
}

#[test]
fn the_issues_case_at_the_default_matches_a_tight_search() {
    let c = HARD_CASES[0];
    assert_eq!(c.record, "RSN1633_MANJIL_ABBAR--L");
    let exc = far(c.record);
    let spec = |rtol| RunSpec::new(c.p, c.eps, 1.0, Model::dp5(c.alpha, rtol));
    let plain = |rtol| {
        capacity_traced(&exc, &spec(rtol), &c.grid, c.tol, Trace::StopAtFirst)
            .unwrap()
            .eta_c
            .unwrap()
    };
    let tight = plain(1e-12);
    // The old default, unchecked, overturned at a level that survives when
    // integrated more tightly: about 15 % too high.
    assert!(plain(1e-8) > 1.1 * tight, "{} vs {tight}", plain(1e-8));
    // Through the command, as the issue ran it, at the default tolerance.
    let out = rocking(
        &root(),
        &[
            "capacity",
            "--record",
            "records/fema-p695/far-field/RSN1633_MANJIL_ABBAR--L.AT2",
            "--p",
            "4",
            "--eps",
            "0.9",
            "--model",
            "nonlinear",
            "--alpha",
            "0.15",
            "--spacing",
            "linear",
            "--levels",
            "40",
            "--eta-min",
            "0.005",
            "--tol",
            "1e-5",
            "--json",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let eta_c = v["eta_c"].as_f64().unwrap();
    // Same grid and bisection: the same capacity to the refinement tolerance.
    assert!((eta_c - tight).abs() <= c.tol, "{eta_c} vs {tight}");
    // The issue found the verdicts around the answer dense; the probe finds
    // one of the bisection's verdicts chaotic, which says the capacity is
    // not certified although it is the tight search's.
    assert_eq!(v["certified"], false, "{v}");
    let got = capacity_certified(
        &exc,
        &spec(DEFAULT_RTOL),
        &c.grid,
        c.tol,
        Trace::StopAtFirst,
    )
    .unwrap();
    assert_eq!(got.capacity.eta_c, Some(eta_c));
    let Certification::Chaotic {
        rtol: Some(rtol),
        eta,
    } = got.certification
    else {
        panic!("{:?}", got.certification)
    };
    assert_eq!(rtol, DEFAULT_RTOL / 100.0);
    assert_chaotic_at(&exc, spec(rtol), eta);
}

#[test]
fn hard_cases_certify_to_the_tight_search_or_say_they_cannot() {
    let mut certified = 0;
    for c in &HARD_CASES[1..] {
        let exc = far(c.record);
        let spec = |rtol| RunSpec::new(c.p, c.eps, 1.0, Model::dp5(c.alpha, rtol));
        let reference = capacity_traced(&exc, &spec(1e-13), &c.grid, c.tol, Trace::StopAtFirst)
            .unwrap()
            .eta_c
            .unwrap();
        let got = capacity_certified(
            &exc,
            &spec(DEFAULT_RTOL),
            &c.grid,
            c.tol,
            Trace::StopAtFirst,
        )
        .unwrap();
        let eta_c = got.capacity.eta_c.unwrap();
        match &got.certification {
            Certification::Tolerance { .. } => {
                certified += 1;
                assert!(
                    (eta_c - reference).abs() <= 2.0 * c.tol,
                    "{c:?}: certified {eta_c}, tight search {reference}"
                )
            }
            Certification::Chaotic {
                eta,
                rtol: Some(rtol),
            } => {
                // A verdict that a 1e-9 change of η flips, checked here
                // independently at the tolerance the probe used.
                assert_chaotic_at(&exc, spec(*rtol), *eta);
                assert!(!got.certification.certified());
            }
            other => panic!("{c:?}: {other:?}"),
        }
    }
    // The study's worst cases at rtol 1e-8 are not all chaotic: most are
    // decided by a tight enough tolerance.
    assert!(certified >= HARD_CASES.len() / 2, "{certified} certified");
}

#[test]
fn the_exact_steppers_verdicts_do_not_hang_on_rounding() {
    // A small version of `rocking-bench --sections rounding`: the decisive
    // runs of capacities certified `exact`, rerun with every sample one ulp
    // up and one ulp down, keep their verdict.
    let grid = ImGrid::default();
    let mut exact = 0;
    for stem in [
        "RSN1111_KOBE_NIS000",
        "RSN169_IMPVALL_H-DLT352",
        "RSN1633_MANJIL_ABBAR--L",
    ] {
        let exc = far(stem);
        let moved = [exc.mapped(f64::next_up), exc.mapped(f64::next_down)];
        for (p, eps) in [(1.0, 0.9), (4.0, 0.7)] {
            let spec = RunSpec::new(p, eps, 1.0, Model::LINEARIZED);
            let got = capacity_certified(&exc, &spec, &grid, 1e-4, Trace::StopAtFirst).unwrap();
            if let Certification::Chaotic { rtol: None, eta } = got.certification {
                assert_chaotic_at(&exc, spec, eta);
                continue;
            }
            assert_eq!(got.certification, Certification::Exact);
            exact += 1;
            let decisive = decisive_runs(&got.capacity, &grid);
            // The probe reran each decisive run twice, and nothing else.
            assert_eq!(got.extra.runs, 2 * decisive.len(), "{stem} p = {p}");
            for (eta, overturned) in decisive {
                for m in &moved {
                    let out = simulate(m, &RunSpec { eta, ..spec }).unwrap();
                    assert_eq!(out.overturned(), overturned, "{stem} p = {p} η = {eta}");
                }
            }
        }
    }
    assert!(exact >= 4, "{exact} of 6 certified exact");
}

#[test]
fn where_rounding_flips_a_verdict_the_capacity_is_flagged_chaotic() {
    // The one rounding flip of the bench's 146,250 perturbed decisive runs
    // (docs/BENCHMARKS.md): record + 1 ulp turns this survivor over.
    let exc = far("RSN169_IMPVALL_H-DLT352");
    let p = 0.33 * (10.0f64 / 0.33).powf(5.0 / 11.0); // the paper grid's p ≈ 1.556
    let spec = RunSpec::new(p, 0.9, 1.0, Model::LINEARIZED);
    let grid = ImGrid::default();
    let got = capacity_certified(&exc, &spec, &grid, 1e-4, Trace::StopAtFirst).unwrap();
    let up = exc.mapped(f64::next_up);
    let flipped: Vec<f64> = decisive_runs(&got.capacity, &grid)
        .into_iter()
        .filter(|&(eta, overturned)| {
            simulate(&up, &RunSpec { eta, ..spec })
                .unwrap()
                .overturned()
                != overturned
        })
        .map(|(eta, _)| eta)
        .collect();
    assert_eq!(flipped.len(), 1, "{flipped:?}");
    assert!((flipped[0] - 0.270631).abs() < 1e-6, "{flipped:?}");
    let Certification::Chaotic { rtol: None, eta } = got.certification else {
        panic!("{:?}", got.certification)
    };
    assert_chaotic_at(&exc, spec, eta);
    assert!(!got.certification.certified());
    // The work reported is that of the probes asked for, in order (η moved
    // up, then down) up to the first verdict that changes: a probe run
    // ahead with its partner and never asked for is not counted.
    let mut asked = 0;
    'probes: for (eta, overturned) in decisive_runs(&got.capacity, &grid) {
        for moved in [eta * (1.0 + 1e-9), eta * (1.0 - 1e-9)] {
            asked += 1;
            if simulate(&exc, &RunSpec { eta: moved, ..spec })
                .unwrap()
                .overturned()
                != overturned
            {
                break 'probes;
            }
        }
    }
    assert_eq!(got.extra.runs, asked);
}

#[test]
fn capacities_say_how_they_were_certified() {
    let dir = tempdir();
    let d = dir.path();
    let body = "ids = [\"RSN1111_KOBE_NIS000\", \"RSN953_NORTHR_MUL009\"]\n\
                [model]\nkind = \"nonlinear\"\nalpha = 0.15\nINTEGRATOR\
                [blocks]\np = [2.0]\neps = [0.8]\n[im]\ncount = 60\neta_min = 0.01\n";
    // The default integrator (Taylor) and DP5, each at its default tolerance,
    // certified 100× tighter; both find the same capacities.
    let mut found = Vec::new();
    for (name, line, integrator, rtol, note) in [
        (
            "taylor",
            "",
            "taylor",
            DEFAULT_TAYLOR_TOL,
            "rtol 1e-10; decisive runs agree at 1e-12",
        ),
        (
            "dp5",
            "integrator = \"dp5\"\n",
            "dp5",
            DEFAULT_RTOL,
            "rtol 1e-10; decisive runs agree at 1e-12",
        ),
    ] {
        let pipe = write_pipeline(d, name, &body.replace("INTEGRATOR", line));
        let out = rocking(d, &["sweep", pipe.to_str().unwrap(), "--outputs", "out"]);
        assert!(out.status.success(), "{}", stderr(&out));
        let caps = read_capacities(&d.join("out").join(name)).unwrap();
        assert_eq!(caps.len(), 2);
        for c in &caps {
            assert!(c.certified, "{c:?}");
            assert_eq!(
                (c.integrator.as_str(), c.rtol),
                (integrator, Some(rtol)),
                "{c:?}"
            );
            assert_eq!(c.certification, CertificationKind::Tolerance);
            assert!(c.certification_note.starts_with(note), "{c:?}");
        }
        found.push(caps.iter().map(|c| c.eta_c).collect::<Vec<_>>());
    }
    assert_eq!(found[0], found[1]);
    // The linearised model: certified as exact, no tolerance.
    let lin = write_pipeline(
        d,
        "lin",
        "ids = [\"RSN1111_KOBE_NIS000\"]\n[blocks]\np = [2.0]\neps = [0.8]\n[im]\ncount = 60\neta_min = 0.01\n",
    );
    assert!(
        rocking(d, &["sweep", lin.to_str().unwrap(), "--outputs", "out"])
            .status
            .success()
    );
    let caps = read_capacities(&d.join("out/lin")).unwrap();
    assert!(caps[0].certified && caps[0].rtol.is_none());
    assert_eq!(caps[0].integrator, "exact");
    assert_eq!(caps[0].certification, CertificationKind::Exact);
}

#[test]
fn tolerances_too_tight_to_certify_are_refused() {
    // Capacities are checked 100× tighter, and DP5's error estimate is
    // rounding noise below 1e-14: a user's rtol below 1e-13 cannot be
    // certified, so it is refused with the key or flag named.
    let dir = tempdir();
    let d = dir.path();
    let body = "[model]\nkind = \"nonlinear\"\nalpha = 0.2\nintegrator = \"dp5\"\nrtol = 1e-14\n\
                [blocks]\np = [1.0]\neps = [0.8]\n";
    let pipe = write_pipeline(d, "tight", body);
    let out = rocking(d, &["run", pipe.to_str().unwrap(), "--outputs", "out"]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("`model.rtol`") && stderr(&out).contains("1e-13"),
        "{}",
        stderr(&out)
    );
    let record = root().join("records/fema-p695/far-field/RSN1111_KOBE_NIS000.AT2");
    let args = |rtol: &'static str| {
        [
            "capacity",
            "--record",
            record.to_str().unwrap(),
            "--p",
            "2",
            "--eps",
            "0.8",
            "--model",
            "nonlinear",
            "--alpha",
            "0.2",
            "--levels",
            "20",
            "--integrator",
            "dp5",
            "--rtol",
            rtol,
            "--json",
        ]
        .map(String::from)
    };
    let out = rocking(
        d,
        &args("1e-14").iter().map(String::as_str).collect::<Vec<_>>(),
    );
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("nonlinear tolerance 1e-14"),
        "{}",
        stderr(&out)
    );
    // At the tightest allowed, the check is clamped to 1e-14, not 1e-15.
    let out = rocking(
        d,
        &args("1e-13").iter().map(String::as_str).collect::<Vec<_>>(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let note = v["certification"].as_str().unwrap();
    assert!(note.contains("1e-14") && !note.contains("1e-15"), "{v}");
    // The Taylor stepper likewise: its tightest check is 1e-16, so 1e-16
    // itself is refused (its check was the run again, "agreeing at
    // 1e-16"), and 1e-15 is checked at 1e-16.
    let taylor = |rtol: &'static str| {
        let mut a = args(rtol);
        a[a.iter().position(|x| x == "dp5").unwrap()] = "taylor".into();
        rocking(d, &a.iter().map(String::as_str).collect::<Vec<_>>())
    };
    let out = taylor("1e-16");
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("tolerance 1e-16 must be in [1e-15, 0.01)"),
        "{}",
        stderr(&out)
    );
    let out = taylor("1e-15");
    assert!(out.status.success(), "{}", stderr(&out));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let note = v["certification"].as_str().unwrap();
    assert!(note.contains("1e-16"), "{v}");
}

/// The convergence study shares one record's runs between its
/// grids. Sharing must change nothing but the work: each grid's certified
/// capacity through a shared memo equals the one found alone, and the
/// nested log grids (100 … 1600 levels between the same ends) do share
/// levels to the bit, so the memo saves simulations.
#[test]
fn grids_sharing_runs_find_what_each_finds_alone() {
    use rocking::ida::{capacity_certified_in, Runs};
    let exc = far("RSN1111_KOBE_NIS000");
    let spec = RunSpec::new(2.0, 0.7, 1.0, Model::LINEARIZED);
    let grid = |count| ImGrid {
        count,
        ..ImGrid::default()
    };
    let fine = grid(1600).levels().unwrap();
    for count in [100, 200, 400, 800] {
        let coarse = grid(count).levels().unwrap();
        let step = 1600 / count;
        for (i, eta) in coarse.iter().enumerate() {
            assert_eq!(eta.to_bits(), fine[(i + 1) * step - 1].to_bits(), "{count}");
        }
    }
    let mut shared = Runs::new(&exc);
    let mut alone_runs = 0;
    for count in [1600, 800, 400, 200, 100] {
        let via = capacity_certified_in(&mut shared, &spec, &grid(count), 1e-4, Trace::StopAtFirst)
            .unwrap();
        let alone =
            capacity_certified(&exc, &spec, &grid(count), 1e-4, Trace::StopAtFirst).unwrap();
        assert_eq!(via.capacity, alone.capacity, "{count} levels");
        assert_eq!(via.certification, alone.certification, "{count} levels");
        alone_runs += alone.capacity.runs() + alone.extra.runs;
    }
    // Alone, the scans cost 1 + 1/2 + 1/4 + 1/8 + 1/16 ≈ 1.94 finest scans;
    // shared, one, plus the coarser grids' own refinements and probes.
    let done = shared.work().runs;
    assert!(
        10 * done < 6 * alone_runs,
        "{done} simulations shared vs {alone_runs} alone"
    );
}

/// Alone, a search runs the grid levels two at a time, each with the next,
/// in step. That must change nothing but the time: each level's outcome is
/// the one `simulate` gives alone, to the bit, the levels run are the
/// grid's up to the first overturning, and the work counts those alone
/// (the level after it, run in vain, is not counted). The exact stepper and
/// the Taylor stepper, both of which pair their runs.
#[test]
fn levels_run_in_pairs_are_the_levels_run_alone() {
    use rocking::ida::{capacity_in, RunKind, Runs};
    let grid = ImGrid::default();
    let levels = grid.levels().unwrap();
    let mut depths = Vec::new();
    for model in [Model::LINEARIZED, Model::taylor(0.25, DEFAULT_TAYLOR_TOL)] {
        for stem in [
            "RSN1111_KOBE_NIS000",
            "RSN848_LANDERS_CLW-LN",
            "RSN953_NORTHR_MUL009",
        ] {
            let exc = far(stem);
            let spec = RunSpec::new(2.0, 0.7, 1.0, model);
            let mut runs = Runs::new(&exc);
            let cap = capacity_in(&mut runs, &spec, &grid, 1e-4, Trace::StopAtFirst).unwrap();
            let scanned: Vec<_> = cap
                .points
                .iter()
                .filter(|q| q.kind == RunKind::Level)
                .collect();
            // The definition, level by level, each run alone, up to the
            // first that overturns.
            let mut alone = Vec::new();
            for &eta in &levels {
                let out = simulate(&exc, &RunSpec { eta, ..spec }).unwrap();
                alone.push((eta, out));
                if out.overturned() {
                    break;
                }
            }
            assert!(
                alone.last().unwrap().1.overturned(),
                "overturns within the grid"
            );
            assert_eq!(scanned.len(), alone.len(), "{stem} {model:?}");
            for (q, (eta, out)) in scanned.iter().zip(&alone) {
                assert_eq!(q.eta.to_bits(), eta.to_bits());
                assert_eq!(
                    format!("{:?}", q.outcome),
                    format!("{out:?}"),
                    "{stem} η = {eta}"
                );
            }
            assert_eq!(runs.work().runs, cap.points.len(), "{stem} {model:?}");
            depths.push(alone.len() - 1);
        }
    }
    // Scans of dozens of levels each: many pairs, rocking alike and apart.
    assert!(depths.iter().all(|&d| d > 40), "{depths:?}");
}

/// `capacity` scans the grid levels on every core, each worker
/// taking the next level as soon as it is free, runs the exact stepper's
/// chaos probes on the other workers while the bisection goes on, and the
/// rest at once (`ops::record::capacity_certified_parallel`). The
/// sequential search is the definition: the same capacity, points and
/// certification, for the exact stepper (one case chaotic, one survivor of
/// the whole grid) and for DP5 (a tolerance search that is redone). Run
/// ahead or not, the certification counts the runs it asks for, each once
/// with the sample intervals it takes alone, whatever the number of
/// workers: every probe of every decisive run where none flips, and those
/// up to the first that does where one does (those run ahead past it, in
/// vain, are not counted, as they are not alone).
#[test]
fn the_parallel_search_finds_what_the_sequential_one_finds() {
    use rocking::ops::pool::capacity_certified_parallel;
    let p_flip = 0.33 * (10.0f64 / 0.33).powf(5.0 / 11.0);
    let lin = |p, eps| RunSpec::new(p, eps, 1.0, Model::LINEARIZED);
    let nonlinear = RunSpec::new(2.0, 0.8, 1.0, Model::dp5(0.2, DEFAULT_RTOL));
    let cases = [
        ("RSN953_NORTHR_MUL009", lin(2.0, 0.7), 200),
        ("RSN1111_KOBE_NIS000", lin(5.0, 0.9), 200),
        // The chaotic capacity of the test above.
        ("RSN169_IMPVALL_H-DLT352", lin(p_flip, 0.9), 200),
        // p = 10 with the grid stopped at η = 0.7: no level overturns it.
        ("RSN1787_HECTOR_HEC000", lin(10.0, 0.7), 40),
        ("RSN960_NORTHR_LOS000", nonlinear, 60),
    ];
    let mut chaotic = 0;
    let mut survivors = 0;
    for (stem, spec, count) in cases {
        let exc = far(stem);
        let grid = ImGrid {
            count,
            eta_min: if count == 40 { 0.7 } else { 1e-3 },
            ..ImGrid::default()
        };
        let seq = capacity_certified(&exc, &spec, &grid, 1e-4, Trace::StopAtFirst).unwrap();
        // One worker (no scan), two (the `capacity` command's pool on this
        // machine) and three (the scan with two others).
        for threads in [1, 2, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let par = pool.install(|| {
                capacity_certified_parallel(&exc, &spec, &grid, 1e-4, Trace::StopAtFirst).unwrap()
            });
            assert_eq!(par.capacity, seq.capacity, "{stem}, {threads} threads");
            assert_eq!(par.certification, seq.certification, "{stem}");
            assert_eq!(par.model, seq.model, "{stem}");
            // The certification's runs are those it asked for, however they
            // were scheduled: a batch's prefetched probes past a chaotic
            // verdict were counted (a chaotic record gave 28 runs in a batch,
            // 36 alone).
            assert_eq!(
                (par.extra.runs, par.extra.intervals),
                (seq.extra.runs, seq.extra.intervals),
                "{stem}, {threads} threads"
            );
            let chaos = matches!(seq.certification, Certification::Chaotic { .. });
            if spec.model == Model::LINEARIZED && !chaos {
                // Each probe counted once, with the intervals it takes alone.
                let (mut runs, mut intervals) = (0, 0);
                for (eta, _) in decisive_runs(&par.capacity, &grid) {
                    for moved in [eta * (1.0 + 1e-9), eta * (1.0 - 1e-9)] {
                        runs += 1;
                        intervals += simulate(&exc, &RunSpec { eta: moved, ..spec })
                            .unwrap()
                            .intervals;
                    }
                }
                assert_eq!(
                    (par.extra.runs, par.extra.intervals),
                    (runs, intervals),
                    "{stem}, {threads} threads"
                );
            }
        }
        chaotic += usize::from(matches!(seq.certification, Certification::Chaotic { .. }));
        survivors += usize::from(seq.capacity.eta_c.is_none());
    }
    assert_eq!((chaotic, survivors), (1, 1), "the cases cover both");
}
