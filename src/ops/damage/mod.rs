//! A block's fragility, made once for every command ([`of_block`]): for
//! each damage state asked (overturning alone for `fragility` and `risk`),
//! in one IM, from the records' own runs (`--direct`: every state, both
//! lognormal fits and the records' curve), or from a study (`--from
//! PIPELINE.toml`: overturning from its regression or IM table, the other
//! states from its damage table); the paper's regression gives overturning
//! only. Several states share one dispersion by default, so that they never
//! cross ([`crate::damage::common_dispersion`]).

mod answer;
mod records;

pub use crate::cut::{probability_above, zero_below};
pub use answer::{DamageFragility, StateFragility, DIRECT_FRACTILE};

use super::fragility::{DirectRecords, FragilityError, Laws, Request, RunModel};
use super::im_fragility::DamageTable;
use crate::block::Block;
use crate::damage::{
    self, Criterion, DamageStates, Dispersion, FitChoice, FitMethod, IfNotLognormal, Lognormal,
};
use crate::im::Im;
use crate::label::Label;
use crate::physics::ModelChoice;
use records::{curve_where_not_lognormal, from_records};
pub use records::{FEW_RECORDS, TEXT_RECORDS_NOTE};

/// The block's fragility for each of `states` in `im`: the one function
/// every command (`fragility`, `risk`, `export`, Python) makes it with.
/// Several states share one dispersion unless `dispersion` is `each`.
pub fn of_block(
    block: &Block,
    states: &DamageStates,
    im: Im,
    laws: &Laws,
    direct: Option<&DirectRecords>,
    model: RunModel,
    fit: FitChoice,
) -> Result<DamageFragility, FragilityError> {
    let model = for_states(states, model, direct.is_some())?;
    let mut f = match direct {
        Some(records) => from_records(block, states, im, records, model)?,
        // A regression or a study's tables are of the model they were made by.
        None if model.choice != ModelChoice::Auto => {
            return Err(FragilityError::ModelNeedsRuns(model.choice.label()))
        }
        None => from_regression(block, states, im, laws, (model.auto_tol, fit.method))?,
    };
    f.method = fit.method;
    f.warnings.extend(crate::block::size_warning(block));
    f.warnings.extend(im.period_warning());
    if direct.is_some() {
        records::never_reached(&mut f, block);
    }
    if fit.if_not_lognormal == IfNotLognormal::Curve {
        curve_where_not_lognormal(&mut f);
        // The study's check of overturning's capacities in the IM (η_c's in
        // the peak the block stands on): where `--direct` checks the same.
        let overturning = states
            .states()
            .last()
            .is_some_and(|s| s.criterion == Criterion::Overturned);
        if direct.is_none() && fit.method != FitMethod::Empirical && overturning {
            let table = if matches!(im, Im::Pga | Im::Pfa) {
                "lognormal.parquet"
            } else {
                "damage_states.parquet"
            };
            f.warnings
                .extend(laws.rejected_lognormal_in(block, im).map(|p| {
                    format!(
                        "the study's capacities of this block in {} fail the lognormal check \
                     (Lilliefors p = {p:.2e} < {}, its {table}): this answer is a lognormal \
                     (the study's fit or regression), where --direct gives the records' own \
                     curve (with --direct, --if-not-lognormal lognormal keeps the lognormal)",
                        im.name(),
                        damage::LOGNORMAL_CHECK_LEVEL
                    )
                }));
        }
    }
    f.dispersion = fit.dispersion.label();
    if fit.dispersion == Dispersion::Common && f.states.len() > 1 {
        for method in FitMethod::LOGNORMAL {
            let mut fits: Vec<Option<Lognormal>> = f.states.iter().map(|s| s.by(method)).collect();
            let before = fits.clone();
            damage::common_dispersion(&mut fits);
            if method == fit.method {
                f.warnings.extend(lowered(&f, &before, &fits));
            }
            for (s, l) in f.states.iter_mut().zip(fits) {
                match method {
                    FitMethod::Fractile => s.fractile = l,
                    _ => s.mle = l,
                }
            }
        }
    }
    Ok(f)
}

/// Where keeping the states in order lowered a lighter state's median to a
/// heavier one's (their fits from different sources: overturning from the
/// regression, the lighter states from a study's table, say): said, as it
/// changes the answer.
fn lowered(
    f: &DamageFragility,
    before: &[Option<Lognormal>],
    after: &[Option<Lognormal>],
) -> Vec<String> {
    let mut said = Vec::new();
    for (i, (b, a)) in before.iter().zip(after).enumerate() {
        let (Some(b), Some(a)) = (b, a) else { continue };
        if a.median < b.median * (1.0 - 1e-9) {
            said.push(format!(
                "the median of `{}` ({} {unit}) lay above a heavier state's: it is lowered to \
                 {} {unit} to keep the states in order (a heavier state never the likelier; \
                 --dispersion each keeps each state's own fit)",
                f.states[i].name,
                crate::im::level_text(b.median),
                crate::im::level_text(a.median),
                unit = f.unit
            ));
        }
    }
    said
}

/// The model the states need: states on the slide need the records' runs
/// of the model that slides (refused without them or without μ), which
/// `auto` then is.
fn for_states(
    states: &DamageStates,
    model: RunModel,
    direct: bool,
) -> Result<RunModel, FragilityError> {
    let Some(s) = states.states().iter().find(|s| s.slide_m().is_some()) else {
        return Ok(model);
    };
    let slides = matches!(model.choice, ModelChoice::Auto | ModelChoice::SlideRock);
    if !direct || model.friction.is_none() || !slides {
        return Err(FragilityError::SlideNeedsRuns {
            state: s.name.clone(),
        });
    }
    Ok(RunModel {
        choice: ModelChoice::SlideRock,
        ..model
    })
}

/// State `state` as the records `draw` picks (indices into
/// `f.per_record`, repeats allowed) have it: one bootstrap resample, fitted
/// as the whole sample is; its fragility and its median and β are then
/// read as the whole sample's are ([`StateFragility::fragility`],
/// [`StateFragility::median_beta`] by `f`'s method). `None` without the
/// records' capacities or where the resample has no fit.
pub fn resampled(f: &DamageFragility, state: usize, draw: &[usize]) -> Option<StateFragility> {
    let all = f.per_record.as_ref()?;
    let caps: Vec<Vec<damage::StateCapacity>> = draw.iter().map(|&k| all[k].clone()).collect();
    let fit = records::fit_states(state + 1, &caps)?.swap_remove(state);
    let s = StateFragility {
        fractile: fit.fractile,
        mle: fit.mle,
        capacities: Some(fit.capacities),
        ..f.states[state].clone()
    };
    s.fragility(f.method).is_some().then_some(s)
}

/// Why `state` has no fragility by `method`, as a refusal.
pub fn no_fit(f: &DamageFragility, state: &StateFragility, method: FitMethod) -> FragilityError {
    let why = match (method, f.source.as_str()) {
        (FitMethod::Empirical, _) => "the records' curve needs their runs: add --direct",
        (FitMethod::MaxLikelihood, s) if s != "direct" => {
            "a regression has no likelihood fit; use --direct"
        }
        (FitMethod::Fractile, _) => "more than 16 % of the records never reach the state",
        _ => match state.reached {
            Some(n) if n >= 2 => "the records that reach it all reach it at one level (no spread)",
            _ => "fewer than two records reach the state",
        },
    };
    FragilityError::NoStateFit {
        state: state.name.clone(),
        method: method.name(),
        other: method.other().name(),
        why,
    }
}

/// The study's damage tables by fractiles and by likelihood, carried to
/// blocks: needed where a state other than overturning is asked, or any
/// state in an IM other than PGA (refused without them); otherwise read
/// where the study has them, for
/// overturning's likelihood fit (and its fractile fit where the study has
/// no regression), which do not depend on the other states asked (with
/// overturning alone they were "—" or refused, beside a lighter state
/// 0.80 g for one block).
fn damage_tables(
    states: &DamageStates,
    im: Im,
    laws: &Laws,
) -> Result<[Option<DamageTable>; 2], FragilityError> {
    // Overturning in an IM other than PGA is the table's too
    // ([`in_damage_table`]): a stale or missing table is said, not passed
    // over for the IM table's biased moments.
    let needed = im != Im::Pga
        || states
            .states()
            .iter()
            .any(|s| s.criterion != Criterion::Overturned);
    let table = |m| match needed {
        true => laws.damage_table(im, m),
        false => Ok(laws.damage_table(im, m).ok().flatten()),
    };
    Ok([
        table(FitMethod::Fractile)?,
        table(FitMethod::MaxLikelihood)?,
    ])
}

/// Overturning from the regression (in PGA) or the study's IM table, as
/// `fragility` and `risk` take it; the other states, and overturning's
/// maximum-likelihood fit, from the study's damage table carried to the
/// block. The paper's regression gives overturning only. The fit by
/// `method` (the fractile one for the records' curve, which a study does
/// not carry) must be there; the other is given where the study has it
/// for the block (its grid may have holes in one fit and not the other:
/// an MLE asked for was refused for the fractile fit's holes).
fn from_regression(
    block: &Block,
    states: &DamageStates,
    im: Im,
    laws: &Laws,
    (auto_tol, method): (f64, FitMethod),
) -> Result<DamageFragility, FragilityError> {
    let [fractile_table, mle_table] = damage_tables(states, im, laws)?;
    let study = laws.plan.as_ref().map(|p| p.blocks());
    let mut warnings = super::fragility::model_warning(block, study, auto_tol)
        .into_iter()
        .collect::<Vec<_>>();
    let required = match method {
        FitMethod::MaxLikelihood => FitMethod::MaxLikelihood,
        _ => FitMethod::Fractile,
    };
    let mut out = Vec::with_capacity(states.states().len());
    for s in states.states() {
        let from_table = |m: FitMethod, t: &Option<DamageTable>, w: &mut Vec<String>| {
            carried(t, block, s, m == required, w)
        };
        let (fractile, mle, kind) = match s.criterion {
            Criterion::Overturned => {
                let in_table = in_damage_table(
                    block,
                    s,
                    im,
                    &fractile_table,
                    required == FitMethod::Fractile,
                    &mut warnings,
                )?;
                let (l, kind) = match in_table {
                    Some(found) => found,
                    None => match overturning(block, im, laws, auto_tol, &mut warnings) {
                        Ok((l, kind)) => (Some(l), kind),
                        // A study too small for a regression: its damage table.
                        Err(FragilityError::NoFit { .. }) if fractile_table.is_some() => (
                            from_table(FitMethod::Fractile, &fractile_table, &mut warnings)?,
                            "fractile",
                        ),
                        // The likelihood fit asked for does not need the IM
                        // table's fractile fit (its holes refused it in PGV).
                        Err(_) if required == FitMethod::MaxLikelihood && mle_table.is_some() => {
                            (None, "fractile")
                        }
                        Err(e) => return Err(e),
                    },
                };
                // The table's overturning by maximum likelihood, where it has one.
                let mle = from_table(FitMethod::MaxLikelihood, &mle_table, &mut Vec::new())?;
                (l, mle, kind)
            }
            // States on the slide are refused before ([`for_states`]).
            Criterion::Rotation(_) | Criterion::Slide(_) => {
                if fractile_table.is_none() {
                    return Err(FragilityError::StatesNeedRecords {
                        from: laws.name.clone(),
                        state: s.name.clone(),
                    });
                }
                (
                    from_table(FitMethod::Fractile, &fractile_table, &mut warnings)?,
                    from_table(FitMethod::MaxLikelihood, &mle_table, &mut Vec::new())?,
                    "fractile",
                )
            }
        };
        out.push(StateFragility {
            name: s.name.clone(),
            criterion: s.describe(),
            threshold: s.threshold(),
            fractile,
            mle,
            reached: None,
            fractile_kind: kind,
            capacities: None,
            lognormal_p: None,
        });
    }
    warnings.sort();
    warnings.dedup();
    Ok(DamageFragility {
        im: im.name(),
        unit: im.unit(),
        source: laws.name.clone(),
        records: None,
        orientation: None,
        records_folder: None,
        floor: None,
        dispersion: Dispersion::Each.label(),
        method: FitMethod::Fractile,
        model: None,
        equation: None,
        slides_on_mu: None,
        states: out,
        warnings,
        per_record: None,
    })
}

/// State `s`'s fit for `block`, carried from a study's table where it has
/// one (its warnings into `w`); a gap refuses it only where the fit is
/// `required`.
fn carried(
    t: &Option<DamageTable>,
    block: &Block,
    s: &crate::damage::LimitState,
    required: bool,
    w: &mut Vec<String>,
) -> Result<Option<Lognormal>, FragilityError> {
    let Some(t) = t else { return Ok(None) };
    match t.capacity(block, s) {
        Ok(l) => {
            w.extend(l.warnings);
            Ok(Some(Lognormal {
                median: l.median,
                beta: l.beta,
            }))
        }
        Err(e) if required => Err(e.into()),
        Err(_) => Ok(None),
    }
}

/// Overturning in an IM other than PGA by the study's damage table's
/// fractile fit, where the study has the state: the records that never
/// overturn the block counted (above every level), as the regression counts
/// them in PGA, and a block too many of whose records never overturn left
/// without a fit, as there. `None` where the table or the state is not
/// the study's (then the IM table's moments, [`overturning`]); `Some(None)`
/// where the block has no fractile fit and it is not `required`.
fn in_damage_table(
    block: &Block,
    s: &crate::damage::LimitState,
    im: Im,
    table: &Option<DamageTable>,
    required: bool,
    w: &mut Vec<String>,
) -> Result<Option<(Option<Lognormal>, &'static str)>, FragilityError> {
    match table {
        Some(t) if im != Im::Pga && t.holds(s) => {
            Ok(Some((carried(table, block, s, required, w)?, "fractile")))
        }
        _ => Ok(None),
    }
}

/// Overturning's lognormal from the regression (PGA) or the IM table (the
/// moments of the records that overturn the block, which leave out those
/// that do not: a study without a damage table of the state), and which
/// it is.
fn overturning(
    block: &Block,
    im: Im,
    laws: &Laws,
    auto_tol: f64,
    warnings: &mut Vec<String>,
) -> Result<(Lognormal, &'static str), FragilityError> {
    if im == Im::Pga {
        let (eta50, beta) = laws.median_beta(block)?;
        let study = laws.plan.as_ref().map(|p| p.blocks());
        warnings.extend(super::fragility::warnings(block, study, auto_tol));
        Ok((
            Lognormal {
                median: block.alpha() / eta50,
                beta,
            },
            "regression",
        ))
    } else {
        let l = laws.im_table(im)?.capacity(block)?;
        warnings.extend(l.warnings);
        warnings.push(format!(
            "the study's damage table has no fit of overturning in {}: its IM table's median \
             and β are taken, over the records that overturn the block only, which overstate \
             P where some never do; run the study's damage stage, or use --direct",
            im.name()
        ));
        // The study's table rests on its model, as the regression does.
        let study = laws.plan.as_ref().map(|p| p.blocks());
        warnings.extend(super::fragility::model_warning(block, study, auto_tol));
        Ok((
            Lognormal {
                median: l.median,
                beta: l.beta,
            },
            "moments",
        ))
    }
}

/// Warnings where a heavier state's fitted curve (by `method`) rises above
/// a lighter one's where the block can move: not where they cross below
/// `cut` ([`zero_below`]: there every state's P is 0, as every command
/// counts it) with the heavier state the less likely above it.
pub fn crossings(f: &DamageFragility, method: FitMethod, cut: Option<f64>) -> Vec<String> {
    let fits: Vec<_> = f.states.iter().map(|s| s.by(method)).collect();
    crate::damage::crossed_pairs(&fits, cut)
        .into_iter()
        .map(|(i, j, x, p)| {
            format!(
                "the fitted curves of `{}` and `{}` cross at {} {} (P = {:.2} %): on one side \
                 the heavier state is the likelier, which no record is; there OpenQuake gives a \
                 state a negative share and pelicun (capacities sampled together) counts it in \
                 the heavier state",
                f.states[i].name,
                f.states[j].name,
                crate::im::level_text(x),
                f.unit,
                100.0 * p
            )
        })
        .collect()
}

/// `fragility --states`: each state's probability of being reached at
/// each level, by one method.
#[derive(Debug, Clone, serde::Serialize)]
pub struct StatesAssessment {
    pub b_m: f64,
    pub h_m: f64,
    pub alpha_rad: f64,
    pub p: f64,
    pub eps: f64,
    /// `fractile`, `mle` or `empirical`: what the probabilities use.
    pub method: &'static str,
    pub fragility: DamageFragility,
    pub points: Vec<StatesPoint>,
}

/// One level: P(state reached | IM = iml) for each state, in order; `None`
/// where the method has no fit of the state.
#[derive(Debug, Clone, serde::Serialize)]
pub struct StatesPoint {
    pub iml: f64,
    pub probabilities: Vec<Option<f64>>,
}

/// The block's damage-state fragilities at the request's levels.
pub fn assess(
    req: &Request,
    states: &DamageStates,
    method: FitMethod,
) -> Result<StatesAssessment, FragilityError> {
    let block = super::fragility::check(req)?;
    let (laws, records) = super::fragility::laws_and_records(
        &req.from,
        req.direct,
        &req.progress,
        1,
        req.floor.as_ref(),
        req.orient_for(req.im),
    )?;
    let mut fragility = of_block(
        &block,
        states,
        req.im,
        &laws,
        records.as_ref(),
        RunModel::of_command(req.auto_tol, records.as_ref()).on(req.mu),
        FitChoice {
            method,
            ..req.fit()
        },
    )?;
    let method = fragility.method;
    let cut = zero_below(
        &block,
        req.im,
        records.as_ref().and_then(|r| r.floor()),
        fragility.slides_on_mu,
    );
    let crossed = crossings(&fragility, method, cut);
    fragility.warnings.extend(crossed);
    let slip = crate::hazard::levels_slip(req.im, &req.levels);
    fragility.warnings.extend(slip);
    let sliding = fragility.unmodelled_sliding(req.mu, block.alpha());
    fragility.warnings.extend(sliding);
    let points = req
        .levels
        .iter()
        .map(|&x| StatesPoint {
            iml: x,
            probabilities: fragility
                .states
                .iter()
                .map(|s| s.fragility(method).map(|f| probability_above(&f, x, cut)))
                .collect(),
        })
        .collect();
    Ok(StatesAssessment {
        b_m: req.b_m,
        h_m: req.h_m,
        alpha_rad: block.alpha(),
        p: block.p(),
        eps: block.eps,
        method: method.name(),
        fragility,
        points,
    })
}
