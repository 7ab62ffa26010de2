//! `--direct`: the records a block is run through, read once, and the
//! progress of their certified searches (a bar on a terminal, log lines
//! otherwise, as the sweep's).

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use rayon::prelude::*;

use super::error::FragilityError;
use super::laws::Source;
use super::model::RunModel;
use crate::block::Block;
use crate::floor::Building;
use crate::ida::{self, ImGrid};
use crate::im::{Im, RecordIms};
use crate::physics::{Excitation, RunSpec};
use crate::pipeline::Plan;
use crate::records::{self, OnBad};
use crate::stages::{Progress, Reporter};

impl RunModel {
    /// What a command runs its records with: the `[model]` of the pipeline
    /// they come from (its kind, integrator, tolerance and `auto_tol`), as
    /// the study's stages run its blocks; else `auto` at `auto_tol`.
    pub fn of_command(auto_tol: f64, records: Option<&DirectRecords>) -> Self {
        records
            .and_then(|r| r.search.model)
            .unwrap_or(RunModel::auto(auto_tol))
    }
}

/// What `--direct` says about bad files in `--records`.
const RECORDS_HINT: &str =
    "fix them, or point --records at a folder of good records (AT2 files, or text with --records-unit)";

/// Where `--direct` reports the records it has run: the CLI's reporter, or
/// nowhere (the default).
#[derive(Clone, Default)]
pub struct DirectProgress(Option<Arc<dyn Reporter + Send>>);

impl DirectProgress {
    pub fn to(reporter: Arc<dyn Reporter + Send>) -> Self {
        DirectProgress(Some(reporter))
    }
}

impl std::fmt::Debug for DirectProgress {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(if self.0.is_some() {
            "DirectProgress(reporter)"
        } else {
            "DirectProgress(none)"
        })
    }
}

/// Records run so far, in all, and the simulations they took.
#[derive(Default)]
struct Counts {
    done: AtomicU64,
    total: AtomicU64,
    runs: AtomicU64,
}

/// One record as `--direct` runs it.
struct DirectRecord {
    id: String,
    /// The motion the block feels: the ground's, or its floor's.
    exc: Excitation,
    /// On a floor: the ground's motion (its IMs are the hazard's) and the
    /// floor's peak over the ground's, PFA/PGA.
    ground: Option<(Excitation, f64)>,
    /// Which pair it is of, when the records come in pairs.
    pair: Option<usize>,
    /// Its pair's RotD measures over its own ground PGA (the ratios the
    /// normalised forcing's IMs are: [`DirectRecords::ims`]).
    pair_ims: Vec<(Im, f64)>,
    /// The pair it belongs to by its manifest (set and pair number), if
    /// the rows carry it.
    pair_key: Option<String>,
}

/// The records a block is run through with `--direct`, read once.
pub struct DirectRecords {
    records: Vec<DirectRecord>,
    /// Where they came from, as the answers name it: the folder, or the
    /// pipeline whose records they are.
    folder: String,
    /// The building whose floor the block stands on, if any.
    floor: Option<Building>,
    /// How text records were read (a structural model's floor motions).
    text: Option<crate::columns::TextRecords>,
    /// What reading the files said without refusing them (a relative text
    /// record's clock offset from its ground's).
    notes: Vec<String>,
    /// The blocks stand on the records themselves, text columns with no
    /// building to run them through ([`crate::records::stood_on`]).
    stood_on: bool,
    progress: DirectProgress,
    counts: Counts,
    /// Each record's intensity measures, in the same order, computed the
    /// first time an IM other than PGA asks for them.
    ims: std::sync::OnceLock<Vec<RecordIms>>,
    /// The same of the motion the block feels (its floor's), for PFA and
    /// PFV; the ground's own on the ground.
    felt_ims: std::sync::OnceLock<Vec<RecordIms>>,
    /// Which orientations the records are run at.
    orient: super::Orient,
    /// How many pairs, when the records come in pairs.
    pairs: usize,
    /// The manifest beside a `--records` folder (its pairs, for the
    /// bootstrap's units), if there is one.
    manifest: Option<std::path::PathBuf>,
    /// How each record's capacity is searched: a pipeline's `[im]` grid and
    /// tolerance and its `[model]`, as its study's stages search it; else
    /// the defaults of `rocking capacity`.
    search: Search,
}

/// A capacity search's grid, tolerance and overturning criterion, and
/// the model a pipeline runs its blocks with.
#[derive(Debug, Clone, Copy)]
struct Search {
    grid: ImGrid,
    tol: f64,
    overturn: crate::physics::Overturn,
    /// The pipeline's `[model]` ([`RunModel::of_command`]); none without one.
    model: Option<RunModel>,
}

impl Search {
    /// The pipeline's, where there is one with records; `capacity`'s
    /// defaults otherwise.
    fn of(plan: Option<&Plan>) -> Search {
        let study = plan.and_then(|p| p.records_study().ok());
        Search {
            grid: study.map_or_else(ImGrid::default, |r| r.grid),
            tol: study.map_or(ida::DEFAULT_TOL, |r| r.tol),
            overturn: plan.map_or(crate::physics::Overturn::Static, |p| p.overturn),
            model: plan.map(|p| RunModel {
                choice: p.model,
                solver: p.solver,
                auto_tol: p.auto_tol,
                friction: None,
                of_pipeline: true,
            }),
        }
    }
}

impl DirectRecords {
    /// The pipeline's records, or the AT2 folder of `--records`; with a
    /// building, the block stands on its floor (capacities are then stated
    /// in the ground's η and IMs).
    pub fn load(
        from: &Source,
        plan: Option<&Plan>,
        progress: DirectProgress,
        floor: Option<&Building>,
        orient: super::Orient,
    ) -> Result<Self, FragilityError> {
        let folder = match from {
            Source::Paper {
                records,
                text: None,
            } => records.display().to_string(),
            Source::Paper {
                records,
                text: Some(t),
            } => format!("{} ({t})", records.display()),
            Source::Pipeline { file, .. } => format!("the records of {}", file.display()),
        };
        let (rows, notes) = rows_of(from, plan, &orient, &folder)?;
        // Run through a building (the pipeline's or the one asked), text
        // records are its ground motions.
        let stood_on = floor.is_none()
            && match (from, plan.and_then(|p| p.records_study().ok())) {
                (Source::Pipeline { .. }, Some(rs)) => records::stood_on(rs, &rows),
                (Source::Paper { text, .. }, _) => text.is_some(),
                (Source::Pipeline { .. }, None) => false,
            };
        let (motions, pairs, rotd) = super::pairs::motions(rows, &orient)?;
        let records = motions
            .into_par_iter()
            .map(|(r, pair)| {
                let physics = |source| FragilityError::Physics {
                    record: r.record_id.clone(),
                    source,
                };
                let (exc, ratio) = records::felt(floor, &r).map_err(physics)?;
                let ground = match ratio {
                    Some(ratio) => {
                        Some((Excitation::new(&r.accel_g, r.dt_s).map_err(physics)?, ratio))
                    }
                    None => None,
                };
                // The pair's measures over this motion's own (ground) PGA.
                let pair_ims = pair
                    .and_then(|k| rotd.get(k))
                    .map(|m| {
                        m.values()
                            .into_iter()
                            .map(|(im, v)| (im, v / r.pga_g))
                            .collect()
                    })
                    .unwrap_or_default();
                let pair_key = r
                    .meta
                    .pair
                    .as_ref()
                    .map(|p| format!("{}/{p}", r.meta.set.as_deref().unwrap_or("")));
                Ok(DirectRecord {
                    pair_key,
                    id: r.record_id,
                    exc,
                    ground,
                    pair,
                    pair_ims,
                })
            })
            .collect::<Result<_, FragilityError>>()?;
        // A pipeline's text records are floor motions as `--records` text is.
        let text = match from {
            Source::Paper { text, .. } => text.clone(),
            Source::Pipeline { .. } => plan
                .and_then(|p| p.records_study().ok())
                .and_then(|r| r.records.text()),
        };
        if floor.is_some() && text.as_ref().is_some_and(|t| t.ground.is_some()) {
            return Err(FragilityError::TextFloorTwice);
        }
        Ok(DirectRecords {
            records,
            folder,
            floor: floor.cloned(),
            text,
            notes,
            stood_on,
            progress,
            counts: Counts::default(),
            ims: std::sync::OnceLock::new(),
            felt_ims: std::sync::OnceLock::new(),
            orient,
            pairs,
            manifest: match from {
                Source::Paper { records, .. } => super::pairs::manifest_of(records),
                Source::Pipeline { .. } => None,
            },
            search: Search::of(plan),
        })
    }

    /// Each fitted capacity's resampling unit (in the order of the
    /// fragility's per-record capacities) and what the units are: the
    /// records' pairs where their manifest gives them (the two components
    /// of a FEMA P695 pair share an earthquake and a station; a pair's
    /// every angle with `--orientation random`), else each record (and
    /// each pair with `worst`, one capacity a pair).
    pub fn units(&self) -> (Vec<usize>, crate::stats::ResampleUnit) {
        use crate::pair::Orientation;
        use crate::stats::ResampleUnit;
        match self.orient.orientation {
            Orientation::Worst => return ((0..self.pairs).collect(), ResampleUnit::Record),
            Orientation::Random => {
                let units = self.records.iter().map(|r| r.pair.unwrap_or(0)).collect();
                return (units, ResampleUnit::Pair);
            }
            Orientation::AsRecorded => {}
        }
        let from_manifest = || -> Option<Vec<String>> {
            let text = std::fs::read(self.manifest.as_ref()?).ok()?;
            let m = crate::manifest::read(&text[..]).ok()?;
            self.records
                .iter()
                .map(|r| {
                    let e = m.entries.get(&r.id)?;
                    let pair = e.meta.pair.as_ref()?;
                    Some(format!("{}/{pair}", e.meta.set.as_deref().unwrap_or("")))
                })
                .collect()
        };
        let keys: Option<Vec<String>> = self.records.iter().map(|r| r.pair_key.clone()).collect();
        match keys.or_else(from_manifest) {
            Some(keys) => (crate::stats::numbered_by_first(&keys), ResampleUnit::Pair),
            None => ((0..self.records.len()).collect(), ResampleUnit::Record),
        }
    }

    /// The records' IMs, from their forcing normalised to a PGA of 1 g:
    /// the ratios IM/PGA^power that convert a capacity are those of the
    /// record as recorded.
    pub fn ims(&self) -> &[RecordIms] {
        self.ims.get_or_init(|| {
            self.records
                .par_iter()
                .map(|r| {
                    let exc = r.ground.as_ref().map_or(&r.exc, |(g, _)| g);
                    let mut ims = RecordIms::of_record(&exc.psi, exc.dt_s, &[])
                        .expect("an excitation's forcing has a peak of 1");
                    ims.extend(r.pair_ims.iter().copied());
                    ims
                })
                .collect()
        })
    }

    /// The IMs of the motion each record makes the block feel (its floor's
    /// motion, normalised to a peak of 1 g): PFA and PFV are its PGA and
    /// PGV.
    pub fn felt_ims(&self) -> &[RecordIms] {
        if self.floor.is_none() {
            // On the ground the motion felt is the record: its measures
            // (a pair's beside them do not answer PFA, PFV or FSA).
            return self.ims();
        }
        self.felt_ims.get_or_init(|| {
            self.records
                .par_iter()
                .map(|r| {
                    RecordIms::of_record(&r.exc.psi, r.exc.dt_s, &[])
                        .expect("an excitation's forcing has a peak of 1")
                })
                .collect()
        })
    }

    /// The records' IMs with `im` among them: those of [`Self::ims`] (of
    /// [`Self::felt_ims`] for a floor demand), or, for SA or FSA at a period
    /// they are not computed at, computed at it too (the records are here:
    /// any period can be had).
    pub fn ims_for(
        &self,
        im: Im,
    ) -> Result<std::borrow::Cow<'_, [RecordIms]>, crate::im::RecordImsError> {
        // A floor demand is of the motion the block feels; the rest of the
        // ground's.
        let felt = im.floor();
        let standard = if felt { self.felt_ims() } else { self.ims() };
        if standard.first().is_none_or(|r| r.value(im).is_some()) {
            return Ok(std::borrow::Cow::Borrowed(standard));
        }
        let (Im::Sa(t) | Im::Fsa(t)) = im else {
            return Ok(std::borrow::Cow::Borrowed(standard));
        };
        self.records
            .par_iter()
            .map(|r| {
                let exc = match (&r.ground, felt) {
                    (Some((g, _)), false) => g,
                    _ => &r.exc,
                };
                RecordIms::try_of_record(&exc.psi, exc.dt_s, &[t])
            })
            .collect::<Result<Vec<_>, _>>()
            .map(std::borrow::Cow::Owned)
    }

    /// Where the records came from: the folder, or the pipeline's records.
    pub fn folder(&self) -> &str {
        &self.folder
    }

    pub fn len(&self) -> usize {
        self.records.len()
    }

    pub fn is_empty(&self) -> bool {
        self.records.is_empty()
    }

    /// The block's capacity η_c under every record (0 where it survives
    /// every level), with `model` (`auto` chooses for its α), by the
    /// certified search.
    /// Returns them with why that model.
    pub fn capacities(
        &self,
        block: &Block,
        model: RunModel,
    ) -> Result<(Vec<f64>, String), FragilityError> {
        let (runs, why) = self.runs(block, model, true)?;
        Ok((runs.iter().map(|c| c.eta_c.unwrap_or(0.0)).collect(), why))
    }

    /// The block's certified search under every record, its runs included,
    /// in the records' order, and why the model it used. On a floor every η
    /// is restated as the ground's, η·PFA/PGA (the building is linear),
    /// unless `in_ground` is false (a floor demand: η is then the floor
    /// motion's own).
    pub fn runs(
        &self,
        block: &Block,
        model: RunModel,
        in_ground: bool,
    ) -> Result<(Vec<ida::Capacity>, String), FragilityError> {
        let (model, why) = model.resolve(block)?;
        let spec = RunSpec {
            overturn: self.search.overturn,
            ..RunSpec::new(block.p(), block.eps, 1.0, model)
        };
        let Search { grid, tol, .. } = self.search;
        let n = self.records.len() as u64;
        let before = self.counts.done.load(Ordering::Relaxed);
        self.counts.total.fetch_max(before + n, Ordering::Relaxed);
        self.report();
        self.records
            .par_iter()
            .map(|r| {
                let c = ida::capacity_certified(&r.exc, &spec, &grid, tol, ida::Trace::StopAtFirst)
                    .map_err(|source| FragilityError::Physics {
                        record: r.id.clone(),
                        source,
                    })?;
                let runs = (c.capacity.runs() + c.extra.runs) as u64;
                self.counts.runs.fetch_add(runs, Ordering::Relaxed);
                self.counts.done.fetch_add(1, Ordering::Relaxed);
                self.report();
                Ok(match &r.ground {
                    Some((_, ratio)) if in_ground => in_ground_eta(c.capacity, *ratio),
                    _ => c.capacity,
                })
            })
            .collect::<Result<Vec<_>, FragilityError>>()
            .map(|c| (c, why))
    }

    /// The building whose floor the block stands on (`--floor`, or the
    /// study's `[floor]`); `None` on the ground.
    /// How the records were read, where they are text columns.
    pub fn text(&self) -> Option<&crate::columns::TextRecords> {
        self.text.as_ref()
    }

    /// What reading the files said without refusing them.
    pub fn notes(&self) -> &[String] {
        &self.notes
    }

    /// Whether the blocks stand on the records themselves (text columns,
    /// no building): their ground IMs are the floor's.
    pub fn stood_on(&self) -> bool {
        self.stood_on
    }

    /// The orientations the records are run at.
    pub fn orient(&self) -> super::Orient {
        self.orient
    }

    /// Which pair motion `k` is of, when the records come in pairs.
    pub fn pair_of(&self, k: usize) -> Option<usize> {
        self.records[k].pair
    }

    /// The orientations as the answers state them: `None` as recorded;
    /// `random: 22 pairs × 12 angles, every 15°`.
    pub fn orientation_text(&self) -> Option<String> {
        use crate::pair::Orientation;
        let o = self.orient;
        let n = o.angles().len();
        match o.orientation {
            Orientation::AsRecorded => None,
            Orientation::Random => Some(format!(
                "random: {} pairs × {n} angles, every {}° over [0°, 180°), equally weighted",
                self.pairs, o.step_deg
            )),
            Orientation::Worst => Some(format!(
                "worst: each of {} pairs at the smallest of its capacities at {n} angles, every {}°",
                self.pairs, o.step_deg
            )),
        }
    }

    pub fn floor(&self) -> Option<&Building> {
        self.floor.as_ref()
    }

    /// Says that `blocks` blocks will be run, so that the progress counts
    /// them all from the start.
    pub(super) fn expect_blocks(&self, blocks: usize) {
        let n = (blocks * self.records.len()) as u64;
        self.counts.total.fetch_max(n, Ordering::Relaxed);
    }

    fn report(&self) {
        if let Some(reporter) = &self.progress.0 {
            let c = &self.counts;
            reporter.progress(&Progress {
                stage: "direct",
                done: c.done.load(Ordering::Relaxed),
                total: c.total.load(Ordering::Relaxed),
                resumed: 0,
                runs: c.runs.load(Ordering::Relaxed),
            });
        }
    }
}

/// The records' rows: the pipeline's (refused with an orientation on a
/// study that already turns its pairs), or the `--records` folder's, with
/// its manifest where the orientation needs pairs; and what reading the
/// folder's files said (a pipeline's ingest says it).
fn rows_of(
    from: &Source,
    plan: Option<&Plan>,
    orient: &super::Orient,
    folder: &str,
) -> Result<(Vec<crate::tables::records::RecordRow>, Vec<String>), FragilityError> {
    Ok(match (from, plan) {
        (_, Some(plan)) => {
            let rotated = plan
                .records_study()
                .is_ok_and(|r| r.random_orientation.is_some());
            if rotated && orient.needs_pairs() {
                return Err(FragilityError::Pairs(format!(
                    "{folder}: the study's records are already its pairs at every angle \
                     (`orientation = \"random\"`); its fragility is the random \
                     orientation's as recorded, in the rotated components' own IMs: ask in \
                     one of them (--im pga, pgv, sa(T), …), or without --from for the \
                     bundled pairs (--direct --orientation random, in RotD50 too)"
                )));
            }
            (
                records::of_plan(plan).map_err(FragilityError::Records)?,
                Vec::new(),
            )
        }
        (Source::Paper { records, text }, None) => {
            if !records.is_dir() {
                return Err(FragilityError::NoRecords(records.clone()));
            }
            let manifest = match orient.needs_pairs() {
                true => Some(super::pairs::manifest_of(records).ok_or_else(|| {
                    FragilityError::Pairs(format!(
                        "{}: pairs come from the records' manifest (`manifest.csv` in the \
                         folder or its parent, as records/fema-p695 has), which gives each \
                         record its pair (`record_id`) and component (`component_id`)",
                        records.display()
                    ))
                })?),
                false => None,
            };
            let c = records::collect_as(
                std::slice::from_ref(records),
                manifest.as_deref(),
                OnBad::Refuse(RECORDS_HINT),
                text.as_ref(),
            )
            .map_err(FragilityError::Ingest)?;
            (c.rows, c.warnings)
        }
        (Source::Pipeline { .. }, None) => unreachable!("a pipeline source has a plan"),
    })
}

/// A search on a floor's motion restated in the ground's η: the floor's
/// peak is `pfa_over_pga` times the ground's at every scale, so a run at
/// the floor's η is one at the ground's η·PFA/PGA.
fn in_ground_eta(mut c: ida::Capacity, pfa_over_pga: f64) -> ida::Capacity {
    let k = pfa_over_pga;
    c.eta_c = c.eta_c.map(|e| e * k);
    c.eta_survived *= k;
    c.level_survived *= k;
    c.level_overturned = c.level_overturned.map(|e| e * k);
    for p in &mut c.points {
        p.eta *= k;
    }
    c
}
