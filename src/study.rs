//! A study's results as typed rows: what the figures ([`crate::figures`])
//! and the report ([`crate::report`]) are made from. Pure data; the report
//! stage loads it from the tables.

use crate::fragility::FractileLaw;
use crate::pipeline::{BlockSpec, Plan, RecordsPlan};
use crate::tables::convergence::ConvergenceRow;
use crate::tables::damage::{DamageStateRow, StateCapacityRow};
use crate::tables::fit::{BandCurve, FitBandRow, FitStep1Row};
use crate::tables::reduce::{CapacityBandRow, CapacityFractileRow, HorizontalRow, LognormalRow};
use crate::tables::sweep::{CapacityRow, IdaRow};

/// Everything the figures and the report are drawn from.
#[derive(Debug, Clone)]
pub struct StudyData {
    pub plan: Plan,
    /// The pipeline file's name, as the report shows it.
    pub pipeline: String,
    /// The version of rocking that made the tables, as the report shows it.
    pub version: String,
    pub caps: Vec<CapacityRow>,
    pub ida: Vec<IdaRow>,
    pub horizontal: Vec<HorizontalRow>,
    pub capacity_fractiles: Vec<CapacityFractileRow>,
    pub lognormal: Vec<LognormalRow>,
    /// Empty when the pipeline has no fit.
    pub fit_step1: Vec<FitStep1Row>,
    pub laws: Vec<FractileLaw>,
    pub convergence: Option<Vec<ConvergenceRow>>,
    /// Bootstrap bands of the capacity fractiles, when the pipeline asks.
    pub bands: Option<Vec<CapacityBandRow>>,
    /// Bootstrap bands of the fitted curves, when the pipeline asks and
    /// has a fit.
    pub fit_bands: Option<FitBands>,
    /// The example block's runs, when the pipeline names one.
    pub example: Option<ExampleData>,
    /// Each block's capacity dispersion in every IM (the ims stage).
    pub efficiency: Vec<crate::tables::ims::EfficiencyRow>,
    /// The records' measures (the ims stage's `record_ims`), read for a
    /// study over orientations only (empty otherwise).
    pub record_ims: Vec<crate::tables::ims::RecordImRow>,
    /// Every block's limit-state capacities and fits (the damage stage).
    pub damage: DamageData,
    /// The example block's capacities on each branch of the tree (the tree
    /// stage's, cases numbered record × branch), when the pipeline has one.
    pub tree_caps: Option<Vec<CapacityRow>>,
    /// Seconds each stage took when it last ran, in run order.
    pub stage_seconds: Vec<(String, Option<f64>)>,
    /// The blocks stand on the records themselves, text columns with no
    /// building ([`crate::records::stood_on`]): the tables' measures are
    /// the floor's (PFA, PFV, FSA(T)).
    pub stood_on: bool,
}

/// The report's example block (`[example]`) over every record: its runs,
/// its capacities (cases numbered by record: 0, 1, …) and its horizontal
/// fractiles.
#[derive(Debug, Clone)]
pub struct ExampleData {
    pub block: BlockSpec,
    pub caps: Vec<CapacityRow>,
    pub ida: Vec<IdaRow>,
    pub horizontal: Vec<HorizontalRow>,
    /// Its limit-state capacities and fits.
    pub damage: DamageData,
}

/// Limit-state capacities and their lognormals (`state_capacities`,
/// `damage_states`), of some blocks.
#[derive(Debug, Clone, Default)]
pub struct DamageData {
    pub states: Vec<DamageStateRow>,
    pub capacities: Vec<StateCapacityRow>,
}

/// The fit's bootstrap bands and how the refits went.
#[derive(Debug, Clone)]
pub struct FitBands {
    pub rows: Vec<FitBandRow>,
    /// Step-1 refits that converged, of how many.
    pub step1_converged: (usize, usize),
    /// Resamples whose refit gave all three laws, of how many.
    pub laws_complete: (usize, usize),
}

impl FitBands {
    /// The rows of one fractile's η_c band at one ε, along p.
    pub fn eta_c(&self, q: f64, eps: f64) -> Vec<&FitBandRow> {
        self.rows
            .iter()
            .filter(|r| r.curve == BandCurve::EtaC && r.quantile == Some(q) && r.eps == eps)
            .collect()
    }

    /// The example fragility's rows, along PGA.
    pub fn fragility(&self) -> Vec<&FitBandRow> {
        self.rows
            .iter()
            .filter(|r| r.curve == BandCurve::Fragility)
            .collect()
    }
}

impl StudyData {
    /// The records study the tables come from (the report stage builds a
    /// `StudyData` for records studies only; a pulse map has [`PulseData`]).
    pub fn records_plan(&self) -> &RecordsPlan {
        self.plan
            .records_study()
            .expect("StudyData is built for records studies")
    }

    /// The peak of the motion the blocks stand on, which the study's η is
    /// of: PFA on a building's floor (`[floor]`) or on text records stood
    /// on ([`crate::records::stood_on`]), else the ground's PGA.
    pub fn peak(&self) -> crate::im::Im {
        if self.stood_on || self.records_plan().floor.is_some() {
            crate::im::Im::Pfa
        } else {
            crate::im::Im::Pga
        }
    }

    /// The name the study's IM and damage tables give a measure of its
    /// records: the floor's (PFA for PGA, FSA(T) for SA(T)) where the
    /// blocks stand on them ([`crate::im::Im::felt`]), else its own.
    pub fn named(&self, im: crate::im::Im) -> crate::im::Im {
        match self.stood_on {
            true => im.felt().unwrap_or(im),
            false => im,
        }
    }

    /// The measures a block's capacity is stated in by the ims and damage
    /// stages: the floor's (PFA, PFV, FSA(T)) where the blocks stand on
    /// the records ([`crate::records::stood_on`]), else the ground's.
    pub fn capacity_measures(&self) -> Vec<crate::im::Im> {
        crate::im::Im::capacity_measures_of(self.stood_on)
    }

    /// Whether the blocks are the dimensionless p × ε grid (not physical blocks).
    pub fn is_grid(&self) -> bool {
        self.records_plan().is_grid()
    }

    /// The distinct p and ε of the blocks, ascending.
    pub fn ps_and_eps(&self) -> (Vec<f64>, Vec<f64>) {
        let d = |v: Vec<f64>| crate::stats::distinct(v);
        (
            d(self.records_plan().blocks.iter().map(|b| b.p).collect()),
            d(self.records_plan().blocks.iter().map(|b| b.eps).collect()),
        )
    }

    /// Records per block.
    pub fn n_records(&self) -> usize {
        self.caps.len() / self.records_plan().blocks.len().max(1)
    }
}

/// A pulse map's results (`[pulses]` pipelines): what its figures and
/// report are made from.
#[derive(Debug, Clone)]
pub struct PulseData {
    pub plan: Plan,
    pub pipeline: String,
    pub version: String,
    pub walls: Vec<crate::tables::pulse::PulseWallRow>,
    pub cells: Vec<crate::tables::pulse::PulseCellRow>,
    pub stage_seconds: Vec<(String, Option<f64>)>,
}

impl PulseData {
    /// The families (pulse shape's β, ε) in table order, with a label.
    pub fn families(&self) -> Vec<(Option<f64>, f64, String)> {
        let mut out: Vec<(Option<f64>, f64, String)> = Vec::new();
        let n_eps = crate::stats::distinct(self.walls.iter().map(|w| w.eps).collect()).len();
        for w in &self.walls {
            if !out.iter().any(|(b, e, _)| *b == w.beta && *e == w.eps) {
                let label = match (w.beta, n_eps > 1) {
                    (Some(b), true) => format!("β = {b}, ε = {:.2}", w.eps),
                    (Some(b), false) => format!("β = {b}"),
                    (None, _) => format!("ε = {:.2}", w.eps),
                };
                out.push((w.beta, w.eps, label));
            }
        }
        out
    }

    /// The walls of one family, in f order.
    pub fn walls_of(
        &self,
        beta: Option<f64>,
        eps: f64,
    ) -> impl Iterator<Item = &crate::tables::pulse::PulseWallRow> {
        self.walls
            .iter()
            .filter(move |w| w.beta == beta && w.eps == eps)
    }

    /// The map cells of one family.
    pub fn cells_of(
        &self,
        beta: Option<f64>,
        eps: f64,
    ) -> impl Iterator<Item = &crate::tables::pulse::PulseCellRow> {
        self.cells
            .iter()
            .filter(move |c| c.beta == beta && c.eps == eps)
    }
}
