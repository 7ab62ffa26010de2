//! A block's fragility from the records' own runs (`--direct`): every
//! state's capacities, both lognormal fits and the records' curve, the
//! lognormal check, and the records' curve where the heaviest state fails
//! it.

use super::answer::{DamageFragility, StateFragility, DIRECT_FRACTILE};
use crate::block::Block;
use crate::damage::{
    self, Curve, DamageStates, Dispersion, FitMethod, StateCapacity, LOGNORMAL_CHECK_LEVEL,
};
use crate::im::{self, Im};
use crate::label::Label;
use crate::ops::fragility::{DirectRecords, FragilityError, RunModel};
use crate::pair::Orientation;

pub(super) fn from_records(
    block: &Block,
    states: &DamageStates,
    im: Im,
    records: &DirectRecords,
    model: RunModel,
) -> Result<DamageFragility, FragilityError> {
    // Text records are scaled each to its own peak and have no ground
    // measured beside them: a ground IM of them is the floor's.
    if records.stood_on() && !im.floor() {
        return Err(FragilityError::TextGroundIm(im.short().to_string()));
    }
    // A floor demand (PFA, PFV) is of the floor motion's own scale.
    let (runs, why) = records.runs(block, model, !im.floor())?;
    let alpha = block.alpha();
    let ims = (im != Im::Pga).then(|| records.ims_for(im)).transpose()?;
    let per_record: Vec<Vec<StateCapacity>> = runs
        .iter()
        .map(|c| {
            let points = c.points.iter();
            let runs = points.map(|p| damage::StateRun {
                eta: p.eta,
                edp: p.outcome.max_abs_x,
                slide_m: p.outcome.slide_max_m,
                overturned: p.outcome.overturned(),
            });
            damage::capacities(states, runs, c.eta_c)
        })
        .collect();
    let n = states.states().len();
    // Each record's capacities in the IM (the ratio IM/PGA of its own motion).
    let im_of = |k: usize, eta: f64| match &ims {
        None => Some(im::pga_of_eta(eta, alpha)),
        Some(ims) => im::of_eta(im, eta, alpha, &ims[k]),
    };
    let in_im: Vec<Vec<StateCapacity>> = per_record
        .iter()
        .enumerate()
        .map(|(k, caps)| caps.iter().map(|c| c.map(|eta| im_of(k, eta))).collect())
        .collect::<Option<_>>()
        .ok_or(FragilityError::NoPeriod(im.name()))?;
    let orient = records.orient();
    let in_im = match orient.orientation {
        Orientation::Worst => worst_by_pair(&in_im, |k| records.pair_of(k)),
        Orientation::AsRecorded | Orientation::Random => in_im,
    };
    let fits = fit_states(n, &in_im).ok_or(FragilityError::NoPeriod(im.name()))?;
    let mut warnings = few_records(states, &fits);
    warnings.extend(records.notes().iter().cloned());
    if records.stood_on() {
        warnings.push(TEXT_RECORDS_NOTE.into());
        if records.text().is_some_and(|t| t.ground.is_none()) {
            warnings.push(TEXT_ABSOLUTE_NOTE.into());
        }
    } else if records.text().is_some() && records.floor().is_some() {
        warnings.push(TEXT_AS_GROUND_NOTE.into());
    }
    let out = states
        .states()
        .iter()
        .zip(fits)
        .map(|(s, f)| StateFragility {
            name: s.name.clone(),
            criterion: s.describe(),
            threshold: s.threshold(),
            fractile: f.fractile,
            mle: f.mle,
            reached: Some(f.reached),
            fractile_kind: "fractile",
            lognormal_p: crate::damage::lognormal_p(&f.capacities),
            capacities: Some(f.capacities),
        })
        .collect();
    let (ran, _) = model.resolve(block)?;
    let slides_on_mu = ran.equation.friction().map(|f| f.mu_s);
    Ok(DamageFragility {
        im: im.name(),
        unit: im.unit(),
        source: "direct".into(),
        records: Some(in_im.len()),
        orientation: records.orientation_text(),
        records_folder: Some(records.folder().to_string()),
        floor: records.floor().map(|b| b.to_string()),
        dispersion: Dispersion::Each.label(),
        method: FitMethod::Fractile,
        model: Some(why),
        equation: Some(ran.equation.kind().label()),
        slides_on_mu,
        states: out,
        warnings,
        per_record: Some(in_im),
    })
}

/// A block run sliding whose state no record reaches up to its strongest
/// run: the state's probability is 0 at every level the records ran (their
/// curve, which has no point), so the fragility is the records' curves,
/// and a warning says so, and why where the physics says it (a block that
/// slides first never rocks under horizontal shaking: the slipping base
/// passes it at most μg, below the g·b/h that lifts a corner).
pub(super) fn never_reached(f: &mut DamageFragility, block: &Block) {
    // A rocking model's state no record reaches is refused as it was (no
    // fit); a block that slides has states it cannot reach by its physics.
    let Some(mu) = f.slides_on_mu else {
        return;
    };
    let slides_first = crate::block::slides_first(mu, block.alpha());
    let never: Vec<String> = f
        .states
        .iter()
        .filter(|s| s.reached == Some(0))
        .map(|s| format!("`{}`", s.name))
        .collect();
    if never.is_empty() {
        return;
    }
    f.method = FitMethod::Empirical;
    let why = if slides_first {
        " — the block slides before it rocks (μ ≤ b/h), and a base that slips passes it at \
         most μg, not above the g·b/h that lifts a corner (docs/MODEL.md §21)"
    } else {
        ""
    };
    f.warnings.push(format!(
        "no record's runs reach {} up to their strongest: its probability is 0 at every level \
         they ran, so the fragility is the records' own curves (--method empirical){why}",
        never.join(", ")
    ));
}

/// The states fitted to fewer than [`FEW_RECORDS`] records' capacities,
/// each warned of: one record has no dispersion, a few a rough one.
fn few_records(states: &DamageStates, fits: &[damage::StateFit]) -> Vec<String> {
    states
        .states()
        .iter()
        .zip(fits)
        .filter(|(_, f)| (1..FEW_RECORDS).contains(&f.reached))
        .map(|(s, f)| match f.reached {
            1 => format!(
                "`{}` is fitted to the capacity of one record: it has no dispersion (β = 0, a \
                 step from 0 to 1 at that record's capacity); give {FEW_RECORDS} records or more",
                s.name
            ),
            n => format!(
                "`{}` is fitted to the capacities of {n} records (fewer than {FEW_RECORDS}): its \
                 median and β are rough (β's standard error is about β/√(2n), {:.0} % here)",
                s.name,
                100.0 / (2.0 * n as f64).sqrt()
            ),
        })
        .collect()
}

/// Every state's fits of the records' capacities in the IM (`caps[k][j]`:
/// record k's of state j): the one fit of `--direct` and of its
/// bootstrap's resamples.
pub(super) fn fit_states(n: usize, caps: &[Vec<StateCapacity>]) -> Option<Vec<damage::StateFit>> {
    damage::fit_states(n, caps, |_, v| Some(v), DIRECT_FRACTILE)
}

/// Each pair's capacities at its worst angle: for each state the smallest
/// reached capacity over the pair's motions (`pair_of(k)`: motion k's
/// pair), or, where no angle reaches it, the smallest censoring level (the
/// capacity lies above it at every angle). A censored angle below the
/// smallest reached capacity leaves the pair's worst capacity between the
/// two: the reached one is taken, an upper bound.
fn worst_by_pair(
    caps: &[Vec<StateCapacity>],
    pair_of: impl Fn(usize) -> Option<usize>,
) -> Vec<Vec<StateCapacity>> {
    let mut worst: Vec<Vec<StateCapacity>> = Vec::new();
    for (k, record) in caps.iter().enumerate() {
        let p = pair_of(k).expect("the worst orientation's motions are of pairs");
        if p == worst.len() {
            worst.push(record.clone());
            continue;
        }
        for (w, c) in worst[p].iter_mut().zip(record) {
            *w = match (*w, *c) {
                (StateCapacity::Reached(a), StateCapacity::Reached(b)) => {
                    StateCapacity::Reached(a.min(b))
                }
                (StateCapacity::Reached(a), StateCapacity::NotReached(_))
                | (StateCapacity::NotReached(_), StateCapacity::Reached(a)) => {
                    StateCapacity::Reached(a)
                }
                (StateCapacity::NotReached(a), StateCapacity::NotReached(b)) => {
                    StateCapacity::NotReached(a.min(b))
                }
            };
        }
    }
    worst
}

/// What text records (a structural model's floor motions) mean for the
/// capacities (docs/MODEL.md §16).
pub const TEXT_RECORDS_NOTE: &str = "the records are motions as given (text columns), each \
    scaled itself: a capacity in PFA or PFV is of that motion's shape, which holds for a linear \
    building; a nonlinear one's floor motion changes shape with the ground's intensity, so run \
    its motions near the intensity of interest";

/// What text records without their ground motions are taken to be: an
/// engine's relative accelerations read as absolute give a capacity off
/// by the ground's part, with no sign of it in the numbers.
pub const TEXT_ABSOLUTE_NOTE: &str = "the text records were read as absolute accelerations \
    (the floor's own motion); if they are relative to the ground (an OpenSees Node recorder \
    without -timeSeries), give the ground motions they were run with (--records-ground), or \
    every capacity is of the wrong motion";

/// What text records run through a building are taken to be: its ground
/// motions; a structural model's floor motions would pass through it twice.
pub const TEXT_AS_GROUND_NOTE: &str = "the text records are run through the building (--floor \
    or --building) as its ground motions; if they are a structural model's floor motions \
    already, drop the building, or every capacity is of a floor's floor";

/// Below this many records reaching a state, its fit is warned of as
/// rough.
pub const FEW_RECORDS: usize = 10;

/// A lognormal fit made the records' curves where the heaviest state's
/// capacities fail the lognormal check (Lilliefors at 5 % on their
/// logarithms), with a warning that says why; kept, and warned of, where
/// some record never reaches a state (a curve that stops below 1). The
/// heaviest state decides for the block, as its β does for the states
/// ([`damage::common_dispersion`]): overturning's fragility is one answer
/// whether or not the lighter states are asked, and all the states are of
/// one kind, so they stay in order (each record reaches a lighter state
/// first, so its curves never cross).
pub(super) fn curve_where_not_lognormal(f: &mut DamageFragility) {
    if f.method == FitMethod::Empirical {
        return;
    }
    let Some(heaviest) = f.states.last() else {
        return;
    };
    let Some(p) = heaviest.lognormal_p.filter(|&p| p < LOGNORMAL_CHECK_LEVEL) else {
        // The heaviest passes and decides: a lighter state that fails is
        // kept lognormal, and said so (it was kept without a word, and its
        // answer changed with the states asked beside it).
        let failing: Vec<String> = f.states[..f.states.len() - 1]
            .iter()
            .filter_map(|s| {
                let p = s.lognormal_p.filter(|&p| p < LOGNORMAL_CHECK_LEVEL)?;
                Some(format!("`{}` (Lilliefors p = {p:.3})", s.name))
            })
            .collect();
        if !failing.is_empty() {
            f.warnings.push(format!(
                "the capacities of {} fail the lognormal check (p < 0.05), but the heaviest \
                 state, `{}`, decides the kind of every state's fragility and passes it: the \
                 lognormals are kept (asked alone, or by --method empirical, a state's own \
                 curve)",
                failing.join(", "),
                heaviest.name
            ));
        }
        return;
    };
    let name = heaviest.name.clone();
    let unit = f.unit;
    let short = f.states.iter().find_map(|s| {
        let Some(c) = s.capacities.as_ref() else {
            return Some(format!(
                "the records' capacities of `{}` are not known",
                s.name
            ));
        };
        Curve::of_capacities(c).shortfall(&s.name, unit, c.len())
    });
    match short {
        None => {
            let each = if f.states.len() > 1 {
                ", and so are the lighter states'"
            } else {
                ""
            };
            f.method = FitMethod::Empirical;
            f.warnings.push(format!(
                "the capacities of `{name}` fail the lognormal check (Lilliefors p = {p:.3} < \
                 0.05): its fragility is the records' own curve{each} (--method empirical; \
                 --if-not-lognormal lognormal keeps the lognormal)"
            ));
        }
        Some(why) => f.warnings.push(format!(
            "the capacities of `{name}` fail the lognormal check (Lilliefors p = {p:.3} < 0.05), \
             but {why}: the lognormal is kept"
        )),
    }
}
