//! Raw sections → the plan: one checker per section, each message naming
//! the key it is about.

use std::path::{Path, PathBuf};

use super::checks::{block_run, check_eps, convergence, grid, model, values, Unresolved};
use super::plan::*;
use super::raw::*;
use crate::block::{Block, BlockError, Restitution};
use crate::damage::DamageStates;
use crate::ida::Trace;
use crate::physics::{ModelChoice, Overturn};
use crate::stats::{FractileDef, ResampleUnit};

/// Parses and resolves a pipeline file's text. `path` names the file in
/// errors and anchors relative paths (they are relative to its folder).
pub fn load_str(text: &str, path: &Path) -> Result<Plan, PipelineError> {
    let err = |message: String| PipelineError {
        path: path.to_path_buf(),
        message,
    };
    let raw: RawPipeline = toml::from_str(text).map_err(|e| {
        let mut message = e.to_string().trim_end().to_string();
        // `[block]` where `[[block]]` is meant: a table for a list of them.
        let at = e.span().and_then(|s| text.get(s)).unwrap_or("");
        if message.ends_with("expected a sequence") && at.starts_with('[') && !at.starts_with("[[")
        {
            let name = at.trim_matches(|c| c == '[' || c == ']');
            message.push_str(&format!(
                "\n`{at}` is one table; a list of them is written `[[{name}]]`, one per item"
            ));
        }
        err(message)
    })?;
    resolve(raw, path)
}

/// `model.alpha` is the slenderness of blocks given by p (the grid, an
/// example by p): beside physical blocks only, it would be read and do
/// nothing.
fn alpha_is_used(
    model: &RawModel,
    blocks: &RawBlocks,
    example: Option<&RawExample>,
) -> Result<(), String> {
    let by_p = blocks.p.is_some() || example.is_some_and(|e| e.p.is_some());
    if model.alpha.is_some() && !by_p {
        return Err(
            "`model.alpha` is the slenderness of blocks given by p (`[blocks]`, an \
                    `[example]` by p); each `[[block]]` has its own from b and h: remove it"
                .into(),
        );
    }
    Ok(())
}

/// Checks every value of a raw pipeline and builds the plan. Each section
/// has its own checker; their messages name the key.
pub fn resolve(raw: RawPipeline, path: &Path) -> Result<Plan, PipelineError> {
    let err = |message: String| PipelineError {
        path: path.to_path_buf(),
        message,
    };
    let base = path.parent().unwrap_or(Path::new("."));
    let name = name_of(raw.name.as_deref(), path).map_err(err)?;
    if raw.pulses.is_some() {
        return super::pulse_map::resolve(raw, name, base).map_err(err);
    }
    let Some(raw_records) = raw.records else {
        return Err(err(
            "a pipeline needs `[records]` (the records to run), or `[pulses]` for a pulse map"
                .into(),
        ));
    };
    let records = records(&raw_records, base).map_err(err)?;
    let random_orientation = orientation(&raw_records).map_err(err)?;
    let (model, overturn, solver) = model(&raw.model, Overturn::Static).map_err(err)?;
    alpha_is_used(&raw.model, &raw.blocks, raw.example.as_ref()).map_err(err)?;
    let blocks = blocks(&raw.blocks, &raw.block, raw.model.alpha).map_err(err)?;
    let example = raw
        .example
        .as_ref()
        .map(|e| example(e, raw.model.alpha))
        .transpose()
        .map_err(err)?;
    if model == ModelChoice::Nonlinear
        && blocks.iter().chain(&example).any(|b| b.alpha_rad.is_none())
    {
        return Err(err(
            "`model.kind` = \"nonlinear\" needs `model.alpha` (or physical `[[block]]` entries, \
             and b and h in `[example]`)"
                .into(),
        ));
    }
    let grid = grid(&raw.im).map_err(err)?;
    let fractile = FractileDef::parse(&raw.reduce.fractile).ok_or_else(|| {
        err(format!(
            "`reduce.fractile` = \"{}\"; valid: {}",
            raw.reduce.fractile,
            FractileDef::NAMES
        ))
    })?;
    let convergence = convergence(raw.convergence.as_ref()).map_err(err)?;
    let damage = damage(raw.damage.as_ref()).map_err(err)?;
    let uncertainty = uncertainty(raw.uncertainty.as_ref()).map_err(err)?;
    let floor = raw.floor.as_ref().map(floor).transpose().map_err(err)?;
    if floor.is_some() && raw_records.ground.is_some() {
        return Err(err(TEXT_FLOOR_TWICE.into()));
    }
    if let Some(u) = &uncertainty {
        check_uncertainty(u, &records, blocks.len()).map_err(err)?;
    }
    let auto_tol = raw.model.auto_tol;
    let run = |b: Unresolved| block_run(b, model, solver, auto_tol, overturn);
    let blocks = blocks.into_iter().map(run).collect::<Result<Vec<_>, _>>();
    let blocks = blocks.map_err(err)?;
    slides_need_sliding(&damage, &blocks).map_err(err)?;
    let tree = raw
        .tree
        .map(|t| super::tree::tree_plan(t, example.as_ref(), model, solver, auto_tol, overturn))
        .transpose()
        .map_err(err)?;
    let example = example
        .map(run)
        .transpose()
        .map_err(|e| err(format!("`[example]`: {e}")))?;
    Ok(Plan {
        name,
        description: raw.description.unwrap_or_default(),
        model,
        solver,
        auto_tol,
        overturn,
        study: StudyKind::Records(Box::new(RecordsPlan {
            records,
            sets: raw_records.sets,
            ids: raw_records.ids,
            blocks,
            grid,
            tol: raw.im.tol,
            trace: if raw.im.trace_past_first {
                Trace::AllLevels
            } else {
                Trace::StopAtFirst
            },
            fractile,
            convergence,
            uncertainty,
            example,
            damage,
            floor,
            random_orientation,
            tree,
        })),
        base: base.to_path_buf(),
    })
}

/// `[damage]` states on the slide need every block run by the slide-rock
/// model (a rocking model's runs never slide).
fn slides_need_sliding(damage: &DamageStates, blocks: &[BlockSpec]) -> Result<(), String> {
    let Some(state) = damage.states().iter().find(|s| s.slide_m().is_some()) else {
        return Ok(());
    };
    match blocks
        .iter()
        .find(|b| b.run.model.equation.friction().is_none())
    {
        Some(b) => Err(format!(
            "`damage.states`: `{}` is on the slide, but {} runs the {} (give it `mu`, \
             with `[model] kind = \"auto\"` or `\"slide-rock\"`)",
            state.name,
            match b.name.is_empty() {
                // A grid block has no name: its p and ε.
                true => format!("the block of p = {} 1/s, ε = {}", b.p, b.eps),
                false => format!("block `{}`", b.name),
            },
            b.run.model.equation.kind().describe()
        )),
        None => Ok(()),
    }
}

/// `[damage]`: the limit states, or the default (overturning alone).
fn damage(raw: Option<&crate::pipeline::raw::RawDamage>) -> Result<DamageStates, String> {
    match raw {
        None => Ok(DamageStates::default()),
        Some(d) => DamageStates::parse(&d.states)
            .map_err(|e| format!("`damage.states` = \"{}\": {e}", d.states)),
    }
}

/// `[records] orientation` and `angle_step`: the angle step of the random
/// orientation, or `None` as recorded.
fn orientation(raw: &crate::pipeline::raw::RawRecords) -> Result<Option<f64>, String> {
    use crate::label::Label;
    use crate::pair::Orientation;
    let o = match &raw.orientation {
        None => Orientation::AsRecorded,
        Some(text) => {
            Orientation::parse_label(text).map_err(|e| format!("`records.orientation`: {e}"))?
        }
    };
    let step = raw.angle_step.unwrap_or(crate::pair::ANGLE_STEP_DEG);
    match o {
        Orientation::AsRecorded if raw.angle_step.is_some() => Err(
            "`records.angle_step` is the random orientation's: give `orientation = \"random\"`"
                .into(),
        ),
        Orientation::AsRecorded => Ok(None),
        Orientation::Random if crate::pair::ANGLE_STEPS_DEG.contains(&step) => Ok(Some(step)),
        Orientation::Random => Err(format!(
            "`records.angle_step` = {step}: the angle step is in degrees, in [1, 180]"
        )),
        Orientation::Worst => Err(
            "`records.orientation` = \"worst\": a study holds every motion's capacity, and the \
             worst angle is a fragility's rule: run the study with `orientation = \"random\"`, \
             or use `rocking fragility --from THIS.toml --direct --orientation worst`"
                .into(),
        ),
    }
}

/// `[floor]`: the floor's modes, each `[T, ζ, Γφ]`, or a building's modes
/// `[T, ζ, Γ, φ1, …, φn]` and the floor's `level`, checked.
/// Relative floor motions given with their ground are a floor's motions,
/// which a `[floor]` would run through the building a second time.
const TEXT_FLOOR_TWICE: &str = "`records.ground` makes the text records relative floor \
    motions, the floor's own once their ground is added, and `[floor]` runs records through \
    the building as its ground motions: they would go through it twice; drop `[floor]`, or \
    give the ground motions as the records (`at2`) with `[floor]`";

fn floor(raw: &crate::pipeline::raw::RawFloor) -> Result<crate::floor::Building, String> {
    use crate::building::BuildingError as E;
    let modes = raw
        .modes
        .iter()
        .enumerate()
        .map(|(i, m)| match m[..] {
            [period_s, zeta, gamma_phi] => Ok(crate::floor::Mode {
                period_s,
                zeta,
                gamma_phi,
            }),
            _ => Err(format!(
                "`floor.modes[{i}]` has {} numbers; a mode is [T (s), ζ, Γφ], e.g. [0.5, 0.05, 1.3]",
                m.len()
            )),
        })
        .collect::<Result<Vec<_>, _>>()?;
    let key = if raw.building.is_empty() {
        "modes"
    } else {
        "building"
    };
    let modes =
        crate::building::floor_modes(&modes, &raw.building, raw.level).map_err(|e| match e {
            E::Both => "`floor.modes` and `floor.building` both place the blocks: give one".into(),
            E::Alone => "`floor.level` picks a floor of `floor.building`: give both".into(),
            E::NoLevel(n) => {
                format!("`floor.building` has floors 1–{n}: give the blocks' `floor.level`")
            }
            E::Level { level, floors } => {
                format!("`floor.level` = {level}: the building has floors 1–{floors}")
            }
            other => format!("`floor.{key}`: {other}"),
        })?;
    crate::floor::Building::new(modes).map_err(|e| format!("`floor.{key}`: {e}"))
}

/// `name`, or the file's stem: a plain folder name.
fn name_of(name: Option<&str>, path: &Path) -> Result<String, String> {
    let name = match name {
        Some(n) => n.to_string(),
        None => path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default(),
    };
    if name.is_empty() || name.contains(['/', '\\']) || name.starts_with('.') {
        return Err(format!("`name` = {name:?} must be a plain folder name"));
    }
    Ok(name)
}

/// `[uncertainty]` against the records (pairs need a manifest) and the
/// number of blocks.
fn check_uncertainty(u: &Uncertainty, records: &RecordSource, blocks: usize) -> Result<(), String> {
    let no_manifest = matches!(
        records,
        RecordSource::At2 { manifest: None, .. } | RecordSource::Text { manifest: None, .. }
    );
    if u.unit == ResampleUnit::Pair && no_manifest {
        return Err(
            "`uncertainty.unit` = \"pair\" resamples the manifest's pairs, and `[records]` \
             gives no manifest: add `manifest`, or set unit = \"record\""
                .into(),
        );
    }
    if u.resamples.saturating_mul(blocks) > MAX_RESAMPLED_BLOCKS {
        return Err(format!(
            "`uncertainty.resamples` = {} over {blocks} blocks: resamples × blocks may be at most \
             {MAX_RESAMPLED_BLOCKS} (every resample's fractiles are kept); ask for fewer",
            u.resamples
        ));
    }
    Ok(())
}

/// `[records]`: a table, AT2 paths or text paths, relative to the
/// pipeline's folder.
fn records(raw: &RawRecords, base: &Path) -> Result<RecordSource, String> {
    let rel = |p: &str| -> PathBuf {
        let p = PathBuf::from(p);
        if p.is_absolute() {
            p
        } else {
            base.join(p)
        }
    };
    let texts = raw.unit.is_some() || raw.column.is_some() || raw.ground.is_some();
    if let Some(paths) = &raw.text {
        if raw.table.is_some() || raw.at2.is_some() {
            return Err("`records`: give one of `table`, `at2` or `text`".into());
        }
        if paths.is_empty() {
            return Err("`records.text` is an empty list".into());
        }
        use crate::label::Label;
        let Some(unit) = &raw.unit else {
            return Err(format!(
                "`records.text` needs `unit`, the unit of its accelerations; valid: {}",
                crate::columns::AccelUnit::labels()
            ));
        };
        let unit = crate::columns::AccelUnit::parse_label(unit)
            .map_err(|e| format!("`records.unit`: {e}"))?;
        let column = raw.column.unwrap_or(1);
        if column == 0 {
            return Err(
                "`records.column` = 0: value columns are counted from 1 (the first after time)"
                    .into(),
            );
        }
        return Ok(RecordSource::Text {
            paths: paths.iter().map(|p| rel(p)).collect(),
            manifest: raw.manifest.as_deref().map(rel),
            unit,
            column,
            ground: raw.ground.as_deref().map(rel),
        });
    }
    if texts {
        return Err("`records.unit`, `column` and `ground` go with `records.text`".into());
    }
    match (&raw.table, &raw.at2) {
        (Some(t), None) => {
            if raw.manifest.is_some() {
                return Err("`records.manifest` goes with `records.at2`; a table already holds the metadata".into());
            }
            Ok(RecordSource::Table(rel(t)))
        }
        (None, Some(paths)) if !paths.is_empty() => Ok(RecordSource::At2 {
            paths: paths.iter().map(|p| rel(p)).collect(),
            manifest: raw.manifest.as_deref().map(rel),
        }),
        (None, Some(_)) => Err("`records.at2` is an empty list".into()),
        (None, None) => Err(
            "`records` needs `table` (a records table from `rocking ingest`) or `at2` (AT2 files or folders)".into(),
        ),
        (Some(_), Some(_)) => Err("`records`: give `table` or `at2`, not both".into()),
    }
}

/// `[blocks]` (the p × ε grid, p outer) or `[[block]]` entries, not both.
fn blocks(
    grid: &RawBlocks,
    physical: &[RawBlock],
    model_alpha: Option<f64>,
) -> Result<Vec<Unresolved>, String> {
    match (&grid.p, &grid.eps, physical.is_empty()) {
        (Some(p), Some(eps), true) => {
            let ps = values("blocks.p", p)?;
            let epss = values("blocks.eps", eps)?;
            for &pv in &ps {
                crate::physics::check_p(pv).map_err(|e| format!("`blocks.p`: {e}"))?;
            }
            for &e in &epss {
                check_eps("blocks.eps", e)?;
            }
            if ps.len().saturating_mul(epss.len()) > MAX_BLOCKS {
                return Err(format!(
                    "`blocks`: {} values of p × {} of ε is more than {MAX_BLOCKS} blocks",
                    ps.len(),
                    epss.len()
                ));
            }
            Ok(ps
                .iter()
                .flat_map(|&p| {
                    epss.iter().map(move |&eps| Unresolved {
                        name: String::new(),
                        p,
                        eps,
                        alpha_rad: model_alpha,
                        mu: None,
                        mu_k: None,
                    })
                })
                .collect())
        }
        (None, None, false) => {
            let blocks = physical
                .iter()
                .enumerate()
                .map(|(i, b)| physical_block(i, b))
                .collect::<Result<Vec<_>, _>>()?;
            // The tables and the report tell blocks apart by name.
            for (i, b) in blocks.iter().enumerate() {
                if let Some(j) = blocks[..i].iter().position(|a| a.name == b.name) {
                    return Err(format!(
                        "`block[{i}]` is named \"{}\" as `block[{j}]` is; give each block its own \
                         `name` (an unnamed block is named by b and h)",
                        b.name
                    ));
                }
            }
            Ok(blocks)
        }
        (None, None, true) => Err(
            "no blocks: give `[blocks]` with `p` and `eps`, or `[[block]]` entries with b, h, eps"
                .into(),
        ),
        (Some(_), None, _) => Err("`blocks.p` without `blocks.eps`".into()),
        (None, Some(_), _) => Err("`blocks.eps` without `blocks.p`".into()),
        (_, _, false) => {
            Err("give either `[blocks]` (a p × ε grid) or `[[block]]` entries, not both".into())
        }
    }
}

/// `[example]`: p and ε (α from `model.alpha`), or b, h and ε as a
/// physical block.
fn example(e: &RawExample, model_alpha: Option<f64>) -> Result<Unresolved, String> {
    match (e.p, e.b, e.h) {
        (Some(_), None, None) if e.mu.is_some() || e.mu_k.is_some() => Err(
            "`example.mu`: friction is a physical block's (its b and h decide whether it slides \
             first); give `[example]` b and h instead of p"
                .into(),
        ),
        (Some(p), None, None) => {
            crate::physics::check_p(p).map_err(|e| format!("`example.p`: {e}"))?;
            let eps = match &e.eps {
                toml::Value::Float(x) => *x,
                toml::Value::Integer(x) => *x as f64,
                other => {
                    return Err(format!(
                        "`example.eps` = {other:?}; give a number in (0, 1] (\"housner\" needs b and h)"
                    ))
                }
            };
            check_eps("example.eps", eps)?;
            Ok(Unresolved {
                name: e.name.clone().unwrap_or_default(),
                p,
                eps,
                alpha_rad: model_alpha,
                mu: None,
                mu_k: None,
            })
        }
        (None, Some(b), Some(h)) => physical(
            "example",
            &RawBlock {
                name: e.name.clone(),
                b,
                h,
                eps: e.eps.clone(),
                mu: e.mu,
                mu_k: e.mu_k,
            },
        ),
        _ => {
            Err("`[example]` takes `p` and `eps`, or a physical block's `b`, `h` and `eps`".into())
        }
    }
}

/// One `[[block]]`: b, h (m) → α and p; ε a number or Housner's bound.
fn physical_block(i: usize, b: &RawBlock) -> Result<Unresolved, String> {
    physical(&format!("block[{i}]"), b)
}

/// A physical block under the key `key`: b, h (m) and ε (a number or
/// `"housner"`) through [`Block::new`].
fn physical(key: &str, b: &RawBlock) -> Result<Unresolved, String> {
    let eps = match &b.eps {
        toml::Value::Float(e) => Restitution::Value(*e),
        toml::Value::Integer(e) => Restitution::Value(*e as f64),
        toml::Value::String(s) => s
            .parse()
            .map_err(|_| format!("`{key}.eps` = {s:?}; give a number in (0, 1] or \"housner\""))?,
        other => {
            return Err(format!(
                "`{key}.eps` = {other:?}; give a number in (0, 1] or \"housner\""
            ));
        }
    };
    let block = Block::new(b.b, b.h, eps).map_err(|e| match e {
        BlockError::Size { .. } => format!("`{key}`: b and h must be positive (m)"),
        BlockError::Eps(e) => format!("`{key}.eps` holds ε = {e}; ε must be in (0, 1]"),
        other => format!("`{key}.eps`: {other}"),
    })?;
    let mu =
        b.mu.map(crate::block::check_mu)
            .transpose()
            .map_err(|e| format!("`{key}.mu`: {e}"))?;
    if b.mu_k.is_some() && mu.is_none() {
        return Err(format!(
            "`{key}.mu_k` is the kinetic friction beside `mu`: give both"
        ));
    }
    Ok(Unresolved {
        name: b
            .name
            .clone()
            .unwrap_or_else(|| format!("b{}xh{}", b.b, b.h)),
        p: block.p(),
        eps: block.eps,
        alpha_rad: Some(block.alpha()),
        mu,
        mu_k: b.mu_k,
    })
}

fn uncertainty(raw: Option<&RawUncertainty>) -> Result<Option<Uncertainty>, String> {
    use crate::label::Label;
    let Some(u) = raw else {
        return Ok(None);
    };
    if !(10..=MAX_RESAMPLES).contains(&u.resamples) {
        return Err(format!(
            "`uncertainty.resamples` = {}: give 10 to {MAX_RESAMPLES}",
            u.resamples
        ));
    }
    if !(u.level >= 0.5 && u.level <= 0.999) {
        return Err(format!(
            "`uncertainty.level` = {}: give a two-sided level from 0.5 to 0.999, e.g. 0.90",
            u.level
        ));
    }
    let unit = ResampleUnit::from_label(&u.unit).ok_or_else(|| {
        format!(
            "`uncertainty.unit` = \"{}\"; valid: {}",
            u.unit,
            ResampleUnit::labels()
        )
    })?;
    Ok(Some(Uncertainty {
        resamples: u.resamples,
        level: u.level,
        unit,
        seed: u.seed,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    const MINIMAL: &str = r#"
        [records]
        at2 = ["../records/fema-p695"]
        manifest = "../records/fema-p695/manifest.csv"
        sets = ["far-field"]
        [blocks]
        p = { from = 0.33, to = 10.0, count = 12, spacing = "log" }
        eps = [0.5, 0.95]
    "#;

    /// Keys read and then unused: an integrator or its tolerance beside
    /// the linearised model, and `model.alpha` where no block is given by p.
    /// Each is refused naming the key; where they are used they are taken.
    #[test]
    fn keys_that_would_do_nothing_are_refused() {
        let physical =
            "[records]\nat2 = [\"r\"]\n[[block]]\nname = \"s\"\nb = 0.2\nh = 0.9\neps = 0.8\n";
        for (model, says) in [
            (
                "integrator = \"dp5\"",
                "`model.integrator` is the nonlinear model's",
            ),
            ("rtol = 1e-8", "`model.rtol` is the nonlinear model's"),
            (
                "kind = \"nonlinear\"\nalpha = 0.2",
                "`model.alpha` is the slenderness of blocks given by p",
            ),
        ] {
            let text = format!("{physical}[model]\n{model}\n");
            let e = load_str(&text, Path::new("x.toml"))
                .unwrap_err()
                .to_string();
            assert!(e.contains(says), "{model}: {e}");
        }
        let taken = format!("{MINIMAL}[model]\nkind = \"nonlinear\"\nalpha = 0.2\nrtol = 1e-8\n");
        assert!(load_str(&taken, Path::new("x.toml")).is_ok());
        let physical_nonlinear =
            format!("{physical}[model]\nkind = \"nonlinear\"\nintegrator = \"dp5\"\n");
        assert!(load_str(&physical_nonlinear, Path::new("x.toml")).is_ok());
    }

    /// `im.tol` is Δη, the capacity's refinement: 10 was taken (no
    /// refinement at all, without a word); as wide as the grid (η from
    /// 0.001 to 1) it is refused naming the key.
    #[test]
    fn a_refinement_past_the_grid_is_refused() {
        for (tol, ok) in [
            ("1e-4", true),
            ("0.05", true),
            ("0.999", false),
            ("10", false),
        ] {
            let text = format!("{MINIMAL}[im]\ntol = {tol}\n");
            match load_str(&text, Path::new("x.toml")) {
                Ok(_) => assert!(ok, "{tol} taken"),
                Err(e) => {
                    assert!(!ok, "{tol}: {e}");
                    let says = format!("`im.tol` = {tol}: a refinement");
                    assert!(e.to_string().contains(&says), "{e}");
                }
            }
        }
    }

    /// Relative text floor motions with their ground are the floor's: a
    /// `[floor]` beside them would run them through the building again.
    #[test]
    fn a_floor_beside_relative_text_records_is_refused() {
        let text = "[records]\ntext = [\"t\"]\nunit = \"g\"\nground = \"g\"\n\
             [floor]\nmodes = [[0.5, 0.05, 1.3]]\n\
             [[block]]\nname = \"s\"\nb = 0.2\nh = 0.9\neps = 0.8\n";
        let e = load_str(text, Path::new("x.toml")).unwrap_err().to_string();
        assert!(e.contains("they would go through it twice"), "{e}");
        let without = text.replace("ground = \"g\"\n", "");
        assert!(load_str(&without, Path::new("x.toml")).is_ok());
    }

    #[test]
    fn resolves_grids_and_paths() {
        let plan = load_str(MINIMAL, Path::new("pipelines/x.toml")).unwrap();
        assert_eq!(plan.name, "x");
        assert_eq!(plan.blocks().len(), 24);
        assert_eq!(plan.blocks()[0].p, 0.33);
        assert_eq!(plan.blocks()[23].p, 10.0);
        assert!(
            (plan.blocks()[2].p / plan.blocks()[0].p - (10.0f64 / 0.33).powf(1.0 / 11.0)).abs()
                < 1e-12
        );
        assert_eq!((plan.blocks()[0].eps, plan.blocks()[1].eps), (0.5, 0.95));
        let rs = plan.records_study().unwrap();
        assert_eq!(
            rs.records,
            RecordSource::At2 {
                paths: vec![PathBuf::from("pipelines/../records/fema-p695")],
                manifest: Some(PathBuf::from("pipelines/../records/fema-p695/manifest.csv")),
            }
        );
        assert_eq!(rs.grid, crate::ida::ImGrid::default());
        assert_eq!(rs.fractile, FractileDef::Type7);
    }

    #[test]
    fn physical_blocks_get_p_alpha_and_housner_eps() {
        let text = r#"
            [records]
            table = "r.parquet"
            [[block]]
            name = "cabinet"
            b = 0.3
            h = 1.0
            eps = "housner"
        "#;
        let plan = load_str(text, Path::new("p.toml")).unwrap();
        let b = &plan.blocks()[0];
        let alpha = 0.3f64.atan();
        assert!((b.alpha_rad.unwrap() - alpha).abs() < 1e-15);
        assert!((b.p - (3.0 * crate::block::G / (4.0 * 1.09f64.sqrt())).sqrt()).abs() < 1e-12);
        assert!((b.eps - (1.0 - 1.5 * alpha.sin().powi(2))).abs() < 1e-15);
    }

    /// `auto` picks the model per block when the plan is built: the
    /// linearised equation's error 0.45·α² is 0.45 % at b/h = 0.1 (below the
    /// 1 % default) and 9.7 % at b/h = 0.5 (above it).
    #[test]
    fn each_block_carries_its_resolved_and_checked_run() {
        use crate::physics::EquationKind;
        let text = r#"
            [records]
            table = "r.parquet"
            [model]
            kind = "auto"
            overturn = "escape"
            [[block]]
            name = "slender"
            b = 0.1
            h = 1.0
            eps = 0.9
            [[block]]
            name = "stocky"
            b = 0.5
            h = 1.0
            eps = 0.8
        "#;
        let plan = load_str(text, Path::new("p.toml")).unwrap();
        let [slender, stocky] = plan.blocks() else {
            panic!("two blocks")
        };
        assert_eq!(slender.run.model.equation.kind(), EquationKind::Linearized);
        assert_eq!(stocky.run.model.equation.kind(), EquationKind::Nonlinear);
        for b in [slender, stocky] {
            assert_eq!((b.run.p, b.run.eps, b.run.eta), (b.p, b.eps, 1.0));
            assert_eq!(b.run.overturn, Overturn::Escape);
            assert!(b.run.validate().is_ok());
            assert!(!b.model_why.is_empty());
        }
        assert_ne!(slender.model_why, stocky.model_why);
    }

    #[test]
    fn a_table_written_for_a_list_of_tables_is_named_with_the_fix() {
        let text =
            "name = \"x\"\n[records]\nat2 = [\"r\"]\n[block]\nb = 0.2\nh = 0.9\neps = 0.85\n";
        let e = load_str(text, Path::new("p.toml")).unwrap_err().to_string();
        assert!(e.contains("line 4"), "{e}");
        assert!(
            e.contains("`[block]` is one table; a list of them is written `[[block]]`"),
            "{e}"
        );
        // Where a table is right, no such hint.
        let e = load_str("name = \"x\"\n[records]\nat2 = 3\n", Path::new("p.toml"))
            .unwrap_err()
            .to_string();
        assert!(!e.contains("a list of them"), "{e}");
    }

    #[test]
    fn errors_name_the_key_and_the_choices() {
        let block =
            |name: &str| format!("[[block]]\nname = \"{name}\"\nb = 0.2\nh = 1.0\neps = 0.9\n");
        let records = "[records]\ntable = \"r.parquet\"\n";
        let cases = [
            // Repeats, once accepted: they repeated rows, and two blocks
            // named alike showed the first one's fractiles on both rows.
            (
                MINIMAL.replace("eps = [0.5, 0.95]", "eps = [0.5, 0.5, 0.95]"),
                "`blocks.eps` holds 0.5 twice",
            ),
            (
                MINIMAL.replace(
                    "eps = [0.5, 0.95]",
                    "eps = { from = 0.5, to = 0.5, count = 3 }",
                ),
                "`blocks.eps` holds 0.5 twice",
            ),
            (
                format!("{MINIMAL}\n[convergence]\nlevels = [60, 60]\n"),
                "`convergence.levels` holds 60 twice",
            ),
            // The physics' `--alpha` said in the file's keys.
            (
                format!(
                    "{MINIMAL}\n[example]\np = 2.0\neps = 0.7\n[[tree.model]]\nname = \"nonlinear\"\nweight = 1.0\n"
                ),
                "slenderness α (its `b` and `h`, or `model.alpha`)",
            ),
            // A grid block has no name: named by its p and ε.
            (
                format!("{MINIMAL}\n[damage]\nstates = \"walks=0.05m,overturned=overturned\"\n"),
                "but the block of p = 0.33 1/s, ε = 0.5 runs the",
            ),
            (
                format!("{records}{}{}", block("a"), block("a")),
                "`block[1]` is named \"a\" as `block[0]` is",
            ),
            (
                "[model]\nkind = \"linearized\"\n[pulses]\nshape = \"exp\"\nbeta = [1.0, 1.0]\n\
                 f = [1.0]\neta = [0.5]\neps = [0.9]\n"
                    .to_string(),
                "`pulses.beta` holds 1.0 twice",
            ),
            (
                MINIMAL.replace("count = 12", "count = -3"),
                "count a whole number ≥ 1: invalid value: integer `-3`",
            ),
            (
                MINIMAL.replace("spacing = \"log\"", "spacing = \"cubic\""),
                "unknown spacing `cubic`; valid: log, linear",
            ),
            (
                MINIMAL.replace("eps = [0.5, 0.95]", "eps = [0.5, \"a\"]"),
                "a list of numbers holds a string",
            ),
            (
                format!("{MINIMAL}\n[uncertainty]\nunit = \"pair\"\n")
                    .replace("manifest = ", "# manifest = "),
                "gives no manifest",
            ),
            (
                "[model]\nkind = \"linearized\"\n[pulses]\nshape = \"rect\"\n\
                 f = [1e6]\neta = [0.5]\neps = [0.9]\n"
                    .to_string(),
                "`pulses.f`: f = p·t_d = 1000000 is outside [0.01, 1000]",
            ),
            (
                "[model]\nkind = \"linearized\"\n[pulses]\nshape = \"rect\"\n\
                 f = [0.5, 1.0, 0.5]\neta = [0.5]\neps = [0.9]\n"
                    .to_string(),
                "`pulses.f` holds 0.5 twice",
            ),
            (MINIMAL.replace("sets =", "setz ="), "setz"),
            (
                MINIMAL.replace("eps = [0.5, 0.95]", "eps = [0.5, 1.5]"),
                "ε must be in (0, 1]",
            ),
            (MINIMAL.replace("from = 0.33", "from = -1.0"), "log spacing"),
            (
                MINIMAL.replace(
                    "p = { from = 0.33, to = 10.0, count = 12, spacing = \"log\" }",
                    "p = [0.0]",
                ),
                "p = 0 1/s is outside [0.01, 1000] 1/s",
            ),
            (
                format!("{MINIMAL}\n[model]\nkind = \"quadratic\"\n"),
                "valid: linearized, nonlinear, auto",
            ),
            (
                format!("{MINIMAL}\n[model]\nkind = \"nonlinear\"\n"),
                "model.alpha",
            ),
            (
                format!("{MINIMAL}\n[reduce]\nfractile = \"type9\"\n"),
                "valid: type7",
            ),
            (format!("{MINIMAL}\n[im]\neta_min = 2.0\n"), "`im`"),
            (
                format!("{MINIMAL}\n[uncertainty]\nunit = \"site\"\n"),
                "`uncertainty.unit` = \"site\"; valid: pair, record",
            ),
            (
                format!("{MINIMAL}\n[uncertainty]\nresamples = 3\n"),
                "`uncertainty.resamples` = 3",
            ),
            (
                format!("{MINIMAL}\n[uncertainty]\nresamples = 20000\n"),
                "give 10 to 10000",
            ),
            (
                format!(
                    "{}\n[uncertainty]\nresamples = 10000\n",
                    MINIMAL.replace("count = 12", "count = 1000")
                ),
                "resamples × blocks may be at most 4000000",
            ),
            (
                format!("{MINIMAL}\n[uncertainty]\nlevel = 1.5\n"),
                "`uncertainty.level` = 1.5",
            ),
            (
                format!("{MINIMAL}\n[uncertainty]\nlevels = 0.9\n"),
                "levels",
            ),
        ];
        for (text, expected) in cases {
            let e = load_str(&text, Path::new("pipelines/bad.toml"))
                .unwrap_err()
                .to_string();
            assert!(e.contains(expected), "expected `{expected}` in: {e}");
            assert!(e.starts_with("pipelines/bad.toml"), "{e}");
        }
    }
}
