//! The `tolerance` section: how η_c of the nonlinear model moves with the
//! integrator and its tolerance (DP5's rtol, the Taylor stepper's tail) over
//! far-field records × p × ε × α against DP5 at 1e-13, how often the
//! decisive verdicts flip, and the certified search at candidate defaults.

use std::fmt::Write as _;
use std::time::Instant;

use rayon::prelude::*;

use super::hard_cases::hard_cases_markdown;
use crate::sections::options::{BenchError, BenchOptions};
use crate::sections::records::named_records;
use rocking::ida::{self, capacity_certified, capacity_traced, decisive_runs, ImGrid, Trace};
use rocking::physics::{simulate, Equation, Excitation, Integrator, Model, RunSpec};

/// Fractile `q` of a sorted slice (nearest rank), NaN when empty.
fn at(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    sorted[((sorted.len() - 1) as f64 * q).round() as usize]
}

/// One nonlinear case of the tolerance study.
#[derive(Clone, Copy)]
struct Case {
    rec: usize,
    p: f64,
    eps: f64,
    alpha: f64,
}

/// One search's answer.
#[derive(Clone, Copy)]
struct Answer {
    eta_c: f64,
    secs: f64,
}

/// Per case: the plain searches at every tolerance, the decisive verdicts of
/// the tightest flipped at each looser one, and the certified searches.
struct CaseResult {
    case: Case,
    plain: Vec<Answer>,
    flips: Vec<usize>,
    certified: Vec<(Answer, ida::Certification, usize)>,
}

const RTOLS: [f64; 7] = [1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12];
const QUICK_RTOLS: [f64; 3] = [1e-6, 1e-8, 1e-10];
const TAYLOR_TOLS: [f64; 4] = [1e-8, 1e-10, 1e-12, 1e-14];
const QUICK_TAYLOR_TOLS: [f64; 1] = [rocking::physics::DEFAULT_TAYLOR_TOL];

/// The reference every search is compared with: DP5 at 1e-13.
pub const REFERENCE: Integrator = Integrator::Dp5 { rtol: 1e-13 };

/// The defaults whose certified search is measured: DP5 at 1e-8 and 1e-10,
/// the Taylor stepper at 1e-8, 1e-10 and 1e-12 (its default among them).
pub const CANDIDATES: [Integrator; 5] = [
    Integrator::Dp5 { rtol: 1e-8 },
    Integrator::Dp5 { rtol: 1e-10 },
    Integrator::Taylor { tol: 1e-8 },
    Integrator::Taylor { tol: 1e-10 },
    Integrator::Taylor { tol: 1e-12 },
];

/// The plain searches measured, the reference last.
fn settings(quick: bool) -> Vec<Integrator> {
    let (rtols, tails): (&[f64], &[f64]) = if quick {
        (&QUICK_RTOLS, &QUICK_TAYLOR_TOLS)
    } else {
        (&RTOLS, &TAYLOR_TOLS)
    };
    let dp5 = rtols.iter().map(|&rtol| Integrator::Dp5 { rtol });
    let taylor = tails.iter().map(|&tol| Integrator::Taylor { tol });
    dp5.chain(taylor).chain([REFERENCE]).collect()
}

/// A setting as the tables name it: `dp5 1e-10`, `taylor 1e-12`.
fn named(i: Integrator) -> String {
    format!("{} {:e}", i.name(), i.tol().unwrap_or(0.0))
}

/// η_c against DP5's tolerance over far-field records × p × ε × α, and the
/// certified search at candidate defaults.
pub fn tolerance_table(
    args: &BenchOptions,
    say: &mut impl FnMut(&str),
) -> Result<String, BenchError> {
    let named = named_records(args, if args.quick { 2 } else { 44 })?;
    let (names, recs): (Vec<String>, Vec<Excitation>) = named.into_iter().unzip();
    let settings = settings(args.quick);
    let rtols = &settings[..];
    let (ps, epss, alphas): (&[f64], &[f64], &[f64]) = if args.quick {
        (&[2.0], &[0.9], &[0.15])
    } else {
        (&[1.0, 2.0, 4.0], &[0.7, 0.9], &[0.15, 0.3])
    };
    let mut cases = Vec::new();
    for rec in 0..recs.len() {
        for &p in ps {
            for &eps in epss {
                for &alpha in alphas {
                    cases.push(Case { rec, p, eps, alpha });
                }
            }
        }
    }
    say(&format!(
        "tolerance study: {} cases × {} tolerances",
        cases.len(),
        rtols.len()
    ));
    let grid = ImGrid::default();
    let tol = 1e-4;
    let results = cases
        .par_iter()
        .map(|&c| study_case(&recs[c.rec], c, rtols, &grid, tol))
        .collect::<Result<Vec<_>, rocking::physics::PhysicsError>>()?;
    let mut md = tolerance_markdown(&results, rtols, &names, ps, epss, alphas, tol);
    say("hard cases");
    md.push_str(&hard_cases_markdown(args)?);
    Ok(md)
}

fn study_case(
    exc: &Excitation,
    case: Case,
    rtols: &[Integrator],
    grid: &ImGrid,
    tol: f64,
) -> Result<CaseResult, rocking::physics::PhysicsError> {
    let equation = Equation::Nonlinear {
        alpha_rad: case.alpha,
    };
    let spec = |integrator: Integrator| {
        RunSpec::new(
            case.p,
            case.eps,
            1.0,
            Model {
                equation,
                integrator,
            },
        )
    };
    let mut plain = Vec::new();
    let mut caps = Vec::new();
    for &rtol in rtols {
        let t = Instant::now();
        let cap = capacity_traced(exc, &spec(rtol), grid, tol, Trace::StopAtFirst)?;
        plain.push(Answer {
            eta_c: cap.eta_c.unwrap_or(0.0),
            secs: t.elapsed().as_secs_f64(),
        });
        caps.push(cap);
    }
    // The decisive runs of the tightest search, rerun at each tolerance.
    let reference = caps.last().expect("tolerances");
    let decisive = decisive_runs(reference, grid);
    let mut flips = Vec::new();
    for &rtol in rtols {
        let mut n = 0;
        for &(eta, overturned) in &decisive {
            if simulate(exc, &RunSpec { eta, ..spec(rtol) })?.overturned() != overturned {
                n += 1;
            }
        }
        flips.push(n);
    }
    let mut certified = Vec::new();
    for &rtol in &CANDIDATES {
        let t = Instant::now();
        let c = capacity_certified(exc, &spec(rtol), grid, tol, Trace::StopAtFirst)?;
        certified.push((
            Answer {
                eta_c: c.capacity.eta_c.unwrap_or(0.0),
                secs: t.elapsed().as_secs_f64(),
            },
            c.certification,
            decisive.len(),
        ));
    }
    Ok(CaseResult {
        case,
        plain,
        flips,
        certified,
    })
}

/// The tolerance section's Markdown: what was measured, then the plain searches,
/// the certified ones and the cases that move most.
fn tolerance_markdown(
    results: &[CaseResult],
    rtols: &[Integrator],
    names: &[String],
    ps: &[f64],
    epss: &[f64],
    alphas: &[f64],
    tol: f64,
) -> String {
    let last = rtols.len() - 1;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "## Nonlinear model: η_c against the integrator and its tolerance\n"
    );
    let _ = writeln!(
        s,
        "{} cases: {} far-field records × p ∈ {ps:?} 1/s × ε ∈ {epss:?} × α ∈ {alphas:?} rad, \
         default IM grid (200 log-spaced levels), refined to Δη = {tol:e}. Each case's capacity is \
         searched by DP5 at every rtol and by the Taylor stepper at every tail tolerance, and compared \
         with the search by {}; \"decisive verdicts flipped\" reruns that reference search's decisive \
         runs (`ida::decisive_runs`: the bracket before refinement, every refinement run, the near \
         misses) with the setting of the row. Generated by `rocking-bench --sections tolerance`.\n",
        results.len(),
        names.len(),
        named(rtols[last])
    );
    plain_searches(&mut s, results, rtols, tol);
    certified_searches(&mut s, results, rtols, tol);
    worst_cases(&mut s, results, rtols, names);
    let _ = writeln!(s);
    s
}

/// The plain searches at each tolerance against the tightest: how far η_c
/// moves, how many capacities change, how many decisive verdicts flip.
fn plain_searches(s: &mut String, results: &[CaseResult], rtols: &[Integrator], tol: f64) {
    let last = rtols.len() - 1;
    let _ = writeln!(
        s,
        "| integrator, tolerance | median \\|Δη_c\\| | 90 % | 99 % | max | capacities changed (> 2·Δη) | decisive verdicts flipped | mean time per capacity (s) |"
    );
    let _ = writeln!(s, "|---:|---:|---:|---:|---:|---:|---:|---:|");
    let decisive_total: usize = results.iter().map(|r| r.certified[0].2).sum();
    for (k, &rtol) in rtols.iter().enumerate() {
        let mut d: Vec<f64> = results
            .iter()
            .map(|r| (r.plain[k].eta_c - r.plain[last].eta_c).abs())
            .collect();
        d.sort_by(|a, b| a.total_cmp(b));
        let changed = d.iter().filter(|&&x| x > 2.0 * tol).count();
        let flipped: usize = results.iter().map(|r| r.flips[k]).sum();
        let secs = results.iter().map(|r| r.plain[k].secs).sum::<f64>() / results.len() as f64;
        let _ = writeln!(
            s,
            "| {} | {:.1e} | {:.1e} | {:.1e} | {:.1e} | {changed} ({:.1} %) | {flipped} of {decisive_total} ({:.2} %) | {secs:.3} |",
            named(rtol),
            at(&d, 0.5),
            at(&d, 0.9),
            at(&d, 0.99),
            at(&d, 1.0),
            100.0 * changed as f64 / d.len() as f64,
            100.0 * flipped as f64 / decisive_total.max(1) as f64,
        );
    }
}

/// The certified search from each candidate default: how it certified,
/// and how far its η_c lies from the tightest plain search's.
fn certified_searches(s: &mut String, results: &[CaseResult], rtols: &[Integrator], tol: f64) {
    let last = rtols.len() - 1;
    let _ = writeln!(
        s,
        "\n**Certified search** (`ida::capacity_certified`): after the search, its decisive runs (the bracket \
         before refinement, every refinement run, and the near misses: surviving levels before the \
         first overturning that reached θmax/α ≥ 0.5) are rerun with η moved by ±1e-9 (relative) \
         at a 100× tighter tolerance. Where a probe disagrees, the decisive runs are rerun at that \
         tolerance: a flipped verdict means the search is redone at that tolerance and checked \
         again; none flipped marks the capacity *chaotic*, decided by no tolerance.\n"
    );
    let _ = writeln!(
        s,
        "| default | certified at the first search | searched again | chaotic | flips to the tightest | max \\|Δη_c\\| of the certified vs {} | certified that differ (> 2·Δη) | max \\|Δη_c\\| of the chaotic | mean time per capacity (s) |",
        named(rtols[last])
    );
    let _ = writeln!(s, "|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    for (ci, &rtol) in CANDIDATES.iter().enumerate() {
        let (mut first, mut again, mut chaotic, mut failed) = (0, 0, 0, 0);
        let (mut worst, mut worst_chaotic) = (0.0f64, 0.0f64);
        let mut changed = 0;
        let mut secs = 0.0;
        for r in results {
            let (a, cert, _) = &r.certified[ci];
            match cert {
                ida::Certification::Tolerance { searches: 1, .. } => first += 1,
                ida::Certification::Tolerance { .. } => again += 1,
                ida::Certification::Chaotic { .. } => chaotic += 1,
                _ => failed += 1,
            }
            let d = (a.eta_c - r.plain[last].eta_c).abs();
            if cert.certified() {
                worst = worst.max(d);
                changed += usize::from(d > 2.0 * tol);
            } else {
                worst_chaotic = worst_chaotic.max(d);
            }
            secs += a.secs;
        }
        let n = results.len() as f64;
        let pct = |k: usize| 100.0 * k as f64 / n;
        let _ = writeln!(
            s,
            "| {} | {first} ({:.1} %) | {again} ({:.1} %) | {chaotic} ({:.1} %) | {failed} | {worst:.1e} | {changed} | {worst_chaotic:.1e} | {:.3} |",
            named(rtol),
            pct(first),
            pct(again),
            pct(chaotic),
            secs / n
        );
    }
}

/// The cases that move most at rtol 1e-8, with the certified search from there.
fn worst_cases(s: &mut String, results: &[CaseResult], rtols: &[Integrator], names: &[String]) {
    let last = rtols.len() - 1;
    let _ = writeln!(
        s,
        "\nThe cases that move most with DP5 at 1e-8 (plain search), against {}:\n",
        named(rtols[last])
    );
    let k8 = rtols
        .iter()
        .position(|&r| r == Integrator::Dp5 { rtol: 1e-8 })
        .unwrap_or(0);
    let mut worst: Vec<&CaseResult> = results.iter().collect();
    let delta = |r: &CaseResult| (r.plain[k8].eta_c - r.plain[last].eta_c).abs();
    worst.sort_by(|a, b| delta(b).total_cmp(&delta(a)));
    let _ = writeln!(s, "| record | p | ε | α | η_c at 1e-8 | η_c reference | certified search from 1e-8 | its certification |");
    let _ = writeln!(s, "|---:|---:|---:|---:|---:|---:|---:|---|");
    for r in worst.iter().take(8).filter(|r| delta(r) > 0.0) {
        let c = r.case;
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {:.6} | {:.6} | {:.6} | {} |",
            names[c.rec],
            c.p,
            c.eps,
            c.alpha,
            r.plain[k8].eta_c,
            r.plain[last].eta_c,
            r.certified[0].0.eta_c,
            rocking::label::Label::label(r.certified[0].1.kind())
        );
    }
}
