//! Where a fragility's capacities come from: the paper's regression, or a
//! pipeline's study (its fit, IM table and damage table), each checked to
//! be the pipeline's as it stands.

use std::path::PathBuf;

use super::error::FragilityError;
use crate::block::Block;
use crate::columns::TextRecords;
use crate::damage::FitMethod;
use crate::fragility::{self, FractileLaw};
use crate::im::Im;
use crate::ops::im_fragility::{DamageTable, ImTable, StudyBlock};
use crate::pipeline::Plan;
use crate::stages::fingerprint::Freshness;
use crate::stages::fit::{self, FitError};
use crate::stages::Stage as _;
use crate::stages::{damage, ims, Study};

/// Where the capacity fractiles come from.
#[derive(Debug, Clone)]
pub enum Source {
    /// The paper's published coefficients; `--direct` runs the AT2 files of
    /// `records`, or its text files read as `text` says.
    Paper {
        records: PathBuf,
        text: Option<TextRecords>,
    },
    /// A pipeline's own fit, in `<outputs>/<name>/`; `--direct` runs its records.
    Pipeline { file: PathBuf, outputs: PathBuf },
}

impl Source {
    /// The source a user names: `paper`, or a pipeline file whose study is
    /// under `outputs`; `records` for `--direct` with the paper (default:
    /// [`default_records`]).
    pub fn named(
        from: &str,
        outputs: PathBuf,
        records: Option<PathBuf>,
        text: Option<TextRecords>,
    ) -> Source {
        if from == "paper" {
            Source::Paper {
                records: records.unwrap_or_else(default_records),
                text,
            }
        } else {
            Source::Pipeline {
                file: PathBuf::from(from),
                outputs,
            }
        }
    }
}

/// The bundled far-field records: in the current directory (the repository
/// root), or else where the repository this library was built from has them.
pub fn default_records() -> PathBuf {
    let here = PathBuf::from("records/fema-p695/far-field");
    let built = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(&here);
    if !here.is_dir() && built.is_dir() {
        built
    } else {
        here
    }
}

/// The regression a fragility comes from.
#[derive(Debug, Clone)]
pub struct Laws {
    /// The fitted laws, or why a pipeline has none to use; only a PGA
    /// fragility without `--direct` needs them.
    regression: Result<Vec<FractileLaw>, NoRegression>,
    /// The pipeline's plan, for `--from PIPELINE.toml`.
    pub plan: Option<Plan>,
    /// The pipeline's study folder, for `--from PIPELINE.toml`.
    pub dir: Option<PathBuf>,
    /// `paper` or the pipeline file.
    pub name: String,
    /// Why the study's IM table is not the pipeline's as it stands, if so.
    ims_stale: Option<String>,
    /// The same of its damage table.
    damage_stale: Option<String>,
    /// The blocks stand on the pipeline's records, text columns (a
    /// structural model's floor motions; [`crate::records::stood_on`]):
    /// its tables state capacities in the floor's PFA, PFV and FSA(T), and a
    /// ground IM of them is refused as `--direct` on text records refuses it.
    stood_on: bool,
}

/// Why a pipeline's regression cannot be used.
#[derive(Debug, Clone)]
enum NoRegression {
    /// The pipeline's blocks cannot have one (why).
    NotApplicable(String),
    /// The fit on disk is not the pipeline's as it stands (why).
    Stale(String),
    /// No fit was run: the file it would have written.
    NotRun(PathBuf),
}

impl Laws {
    /// η_c,50 and β of a block.
    pub fn median_beta(&self, block: &Block) -> Result<(f64, f64), FragilityError> {
        self.ground_im(Im::Pga)?;
        let laws = self.regression.as_ref().map_err(|no| match no {
            NoRegression::NotApplicable(why) => FragilityError::NoFit {
                pipeline: PathBuf::from(&self.name),
                why: why.clone(),
            },
            NoRegression::Stale(why) => FragilityError::Stale {
                what: "fit",
                pipeline: PathBuf::from(&self.name),
                dir: self.dir.clone().unwrap_or_default(),
                why: why.clone(),
            },
            NoRegression::NotRun(path) => {
                FragilityError::Fit(FitError::NoFit(path.clone(), self.name.clone()))
            }
        })?;
        let (p, eps) = (block.p(), block.eps);
        fragility::median_beta(laws, p, eps).ok_or(FragilityError::NoFractiles { p, eps })
    }

    /// The study's capacities in `im` (not PGA), to carry to any block;
    /// the paper's regression has none.
    pub fn im_table(&self, im: Im) -> Result<ImTable, FragilityError> {
        self.ground_im(im)?;
        match &self.dir {
            Some(dir) => {
                if let Some(why) = &self.ims_stale {
                    return Err(FragilityError::Stale {
                        what: "IM table",
                        pipeline: PathBuf::from(&self.name),
                        dir: dir.clone(),
                        why: why.clone(),
                    });
                }
                Ok(ImTable::load(dir, &self.name, im, &|b| {
                    self.study_block(b)
                })?)
            }
            None => Err(FragilityError::PaperIsPga(im.name())),
        }
    }

    /// The study's damage-state fits in `im` by `method`, to carry to any
    /// block; `None` for the paper's regression, which has none.
    pub fn damage_table(
        &self,
        im: Im,
        method: FitMethod,
    ) -> Result<Option<DamageTable>, FragilityError> {
        let Some(dir) = &self.dir else {
            return Ok(None);
        };
        self.ground_im(im)?;
        if let Some(why) = &self.damage_stale {
            return Err(FragilityError::Stale {
                what: "damage table",
                pipeline: PathBuf::from(&self.name),
                dir: dir.clone(),
                why: why.clone(),
            });
        }
        Ok(Some(DamageTable::load(
            dir,
            &self.name,
            (im, method),
            &|b| self.study_block(b),
        )?))
    }

    /// Lilliefors' p of the study's own block at `block`'s p and ε (to
    /// rounding) where the study's lognormal check rejects its capacities
    /// (`lognormal.parquet`): its tables carry a lognormal where `--direct`
    /// would give the records' own curve.
    pub fn rejected_lognormal(&self, block: &Block) -> Option<f64> {
        let (dir, spec) = (self.dir.as_ref()?, self.own_block(block)?);
        let rows: Vec<crate::tables::reduce::LognormalRow> =
            crate::tables::read(&dir.join("lognormal.parquet")).ok()?;
        let own = rows
            .iter()
            .find(|r| r.block == spec.name && r.p == spec.p && r.eps == spec.eps)?;
        own.p_value.filter(|_| own.rejected_5pct)
    }

    /// [`Laws::rejected_lognormal`] in any IM: in the peak the block stands
    /// on (η_c's check, `lognormal.parquet`), in another the damage table's
    /// check of the records' overturning capacities in that IM.
    pub fn rejected_lognormal_in(&self, block: &Block, im: Im) -> Option<f64> {
        if matches!(im, Im::Pga | Im::Pfa) {
            return self.rejected_lognormal(block);
        }
        let (dir, spec) = (self.dir.as_ref()?, self.own_block(block)?);
        let rows: Vec<crate::tables::damage::DamageStateRow> =
            crate::tables::read(&dir.join("damage_states.parquet")).ok()?;
        // The overturning state's row (`criterion` as docs/tables.md has it).
        let (name, overturned) = (im.name(), "overturned");
        rows.iter()
            .find(|r| {
                r.block == spec.name
                    && r.p == spec.p
                    && r.eps == spec.eps
                    && r.criterion == overturned
                    && r.im == name
            })?
            .lognormal_p
            .filter(|&p| p < crate::damage::LOGNORMAL_CHECK_LEVEL)
    }

    /// The study's own block at `block`'s p, ε and α (to the rounding of
    /// [`crate::ops::im_fragility::own_value`]; a grid block has no α).
    fn own_block(&self, block: &Block) -> Option<&crate::pipeline::BlockSpec> {
        let same = crate::ops::im_fragility::own_value;
        self.plan.as_ref()?.blocks().iter().find(|b| {
            same(b.p, block.p())
                && same(b.eps, block.eps)
                && b.alpha_rad.is_none_or(|a| same(a, block.alpha()))
        })
    }

    /// `im` refused where the blocks stand on the study's records and it is a
    /// measure of the ground (the one rule of `--direct` on text records).
    fn ground_im(&self, im: Im) -> Result<(), FragilityError> {
        if self.stood_on && !im.floor() {
            return Err(FragilityError::TextGroundIm(im.short()));
        }
        Ok(())
    }

    /// What the study says of its block `name`: the friction it ran
    /// sliding on (the slide-rock model), if it did, and its α.
    fn study_block(&self, name: &str) -> StudyBlock {
        let Some(block) = self
            .plan
            .as_ref()
            .and_then(|p| p.blocks().iter().find(|b| b.name == name))
        else {
            return StudyBlock::default();
        };
        let sliding = matches!(
            block.run.model.equation,
            crate::physics::Equation::SlideRock { .. }
        );
        StudyBlock {
            slid: block.mu.filter(|_| sliding),
            alpha: block.alpha_rad,
        }
    }
}

/// The paper's laws or a pipeline's fitted ones.
pub fn laws(from: &Source) -> Result<Laws, FragilityError> {
    match from {
        Source::Paper { .. } => Ok(Laws {
            regression: Ok(fragility::paper().to_vec()),
            plan: None,
            dir: None,
            name: "paper".to_string(),
            ims_stale: None,
            damage_stale: None,
            stood_on: false,
        }),
        Source::Pipeline { file, outputs } => {
            let study = Study::load(file, outputs)?;
            let status = crate::stages::engine::status(&study);
            let name = file.display().to_string();
            let regression = if let Some(why) = fit::not_applicable(&study.plan) {
                Err(NoRegression::NotApplicable(why))
            } else if let Some(why) = staleness(&study, &status, fit::Fit.name(), fit::OUTPUTS[0]) {
                Err(NoRegression::Stale(why))
            } else if !study.path(fit::OUTPUTS[1]).exists() {
                Err(NoRegression::NotRun(study.path(fit::OUTPUTS[1])))
            } else {
                Ok(fit::read_laws(&study.dir, &name)?)
            };
            let ims_stale = staleness(&study, &status, ims::Ims.name(), ims::IM_EFFICIENCY);
            let damage_stale = staleness(&study, &status, damage::Damage.name(), damage::STATES);
            let stood_on = study.stood_on();
            Ok(Laws {
                regression,
                plan: Some(study.plan),
                dir: Some(study.dir),
                name,
                ims_stale,
                damage_stale,
                stood_on,
            })
        }
    }
}

/// Why a stage's tables are not this pipeline's as it stands: written by
/// another pipeline of the same `name`, by an earlier version of this one, or
/// from upstream tables that have changed since (the fingerprints say, as
/// `rocking status` does). `None` when they are, or when there are none:
/// reading them then says so, and how to make them.
fn staleness(
    study: &Study,
    status: &[(&'static str, Freshness)],
    stage: &str,
    output: &str,
) -> Option<String> {
    let (_, freshness) = status
        .iter()
        .find(|(name, _)| *name == stage)
        .expect("a stage of the engine");
    match freshness {
        Freshness::Fresh | Freshness::FreshShards(_) => None,
        _ if !study.path(output).exists() => None,
        other => Some(other.to_string()),
    }
}
