//! The report's damage-state section: each limit state's capacity of one
//! block in PGA/(αg), by both fits, and where their curves cross.

use std::fmt::Write as _;

use crate::damage::{self, FitMethod};
use crate::figures::damage::shown;
use crate::study::StudyData;

/// `## Damage states`, when the damage stage has run.
pub(super) fn damage_section(w: &mut String, d: &StudyData) {
    let Some(s) = shown(d) else { return };
    let _ = writeln!(w, "## Damage states\n");
    let _ = writeln!(
        w,
        "A limit state is reached when the peak rotation θmax/α first reaches its threshold as \
         the intensity rises (the resurrection rule), or when the block overturns; each record's \
         capacity is that first crossing, interpolated in 1/η between the two runs around it. The \
         lognormal is fitted by the paper's fractile method (16/50/84 %, records that never \
         reach the state counting as +∞) and by maximum likelihood with those records censored \
         at their strongest run (Baker 2015). Definitions: docs/MODEL.md §15; every block, state \
         and IM in `damage_states.parquet`, every record's capacity in `state_capacities.parquet`. \
         Each state has its own β here, as the table holds them; `rocking fragility --states`, \
         `risk` and `export` give every state one β, the heaviest state's, by default \
         (`--dispersion common`: their curves never cross), and these with `--dispersion each`; \
         both are 0 below the level that lifts the block (g·tan α, or μg where it slides \
         first).\n"
    );
    let _ = writeln!(
        w,
        "For {} (p = {} 1/s, ε = {}), in {}/(αg):\n",
        s.which,
        crate::im::level_text(s.p),
        crate::im::level_text(s.eps),
        s.peak
    );
    let _ = writeln!(
        w,
        "| state | reached when | records reaching it | median, fractiles | β, fractiles | median, MLE | β, MLE |"
    );
    let _ = writeln!(w, "|---|---|---|---|---|---|---|");
    let f = |v: Option<f64>| v.map_or("—".to_string(), |v| format!("{v:.3}"));
    for name in &s.names {
        let Some(row) = s.row(name) else { continue };
        let fr = s.lognormal(name, FitMethod::Fractile);
        let ml = s.lognormal(name, FitMethod::MaxLikelihood);
        let _ = writeln!(
            w,
            "| {name} | {} | {} of {} | {} | {} | {} | {} |",
            row.criterion,
            row.n_reached,
            row.n_records,
            f(fr.map(|l| l.median)),
            f(fr.map(|l| l.beta)),
            f(ml.map(|l| l.median)),
            f(ml.map(|l| l.beta)),
        );
    }
    // As the commands warn of it: every pair, not below the level where the
    // block cannot move with the heavier state the less likely above.
    let fits: Vec<_> = s
        .names
        .iter()
        .map(|n| s.lognormal(n, FitMethod::Fractile))
        .collect();
    let crossings: Vec<String> = damage::crossed_pairs(&fits, s.cut)
        .into_iter()
        .map(|(i, j, x, p)| {
            format!(
                "`{}` and `{}` at {}/(αg) = {x:.3} (P = {:.1} %)",
                s.names[i],
                s.names[j],
                s.peak,
                100.0 * p
            )
        })
        .collect();
    let _ = writeln!(w);
    if !crossings.is_empty() {
        let _ = writeln!(
            w,
            "The fitted curves of unequal β cross: {}. On one side of each crossing the \
             heavier state's fitted probability exceeds the lighter one's, which no record does \
             (below it where the heavier state's β is the larger); an engine that takes \
             differences of the curves as damage-state shares gets a negative share there.\n",
            crossings.join("; ")
        );
    }
}
