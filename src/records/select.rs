//! The records a pipeline selects: read from a records table (or straight
//! from AT2 files), filtered by `records.sets` and `records.ids`, sorted by
//! record id; and the motion its blocks feel under each. Shared by the
//! sweep, the convergence study, the ims stage, the bootstrap and
//! `fragility --direct`.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use super::collect::{self, CollectError, OnBad, PIPELINE_HINT};
use crate::floor::Building;
use crate::physics::{Excitation, PhysicsError};
use crate::pipeline::{NotRecords, Plan, RecordSource, RecordsPlan};
use crate::tables::records::RecordRow;
use crate::tables::{self, TableError};

#[derive(Debug, thiserror::Error)]
pub enum SelectError {
    #[error(
        "records table {0} does not exist; write it with `rocking ingest … --out {0}`, \
         or point `records.at2` of the pipeline at AT2 folders"
    )]
    MissingTable(PathBuf),
    #[error(transparent)]
    Table(#[from] TableError),
    #[error("the pipeline's AT2 records")]
    Collect(#[source] CollectError),
    #[error("`records.sets` names \"{set}\", which no record has; available: {available}")]
    UnknownSet { set: String, available: String },
    #[error("`records.ids`: no record {0}")]
    UnknownIds(String),
    #[error("the record selection is empty")]
    Empty,
    #[error("`records.orientation` = \"random\": {0}")]
    Pairs(String),
    #[error(transparent)]
    NotRecords(#[from] NotRecords),
}

/// The motion a plan's blocks feel under one record: the record itself,
/// or the floor's under it (`[floor]`), with the floor's peak over the
/// record's (PFA/PGA).
pub fn felt(
    floor: Option<&Building>,
    r: &RecordRow,
) -> Result<(Excitation, Option<f64>), PhysicsError> {
    let Some(building) = floor else {
        return Ok((Excitation::new(&r.accel_g, r.dt_s)?, None));
    };
    let f = building
        .floor_motion(&r.accel_g, r.dt_s)
        .map_err(|e| PhysicsError::BadInput(format!("its floor motion: {e}")))?;
    let ratio = f.pfa_over_pga;
    Ok((Excitation::from_samples(f.accel_g, f.dt_s)?, Some(ratio)))
}

/// The plan's records from the table at `table`, filtered and sorted.
pub fn select(plan: &Plan, table: &Path) -> Result<Vec<RecordRow>, SelectError> {
    if !table.exists() {
        return Err(SelectError::MissingTable(table.into()));
    }
    filter(plan.records_study()?, tables::records::read(table)?)
}

/// Whether the blocks stand on the records themselves, given as text
/// columns (a structural model's floor motions, each scaled itself), not
/// on the ground they shake: records read from text (`[records] text`, or
/// a records table of such rows) with no `[floor]` to run them through.
/// Their PGA, PGV and SA are then the floor's PFA, PFV and FSA(T), and the
/// ims and damage stages name them so.
pub fn stood_on(plan: &RecordsPlan, rows: &[RecordRow]) -> bool {
    plan.floor.is_none()
        && (plan.records.text().is_some()
            || rows
                .iter()
                .any(|r| r.header_layout == super::collect::TEXT_LAYOUT))
}

/// The rows [`stood_on`] needs to read: a records table's (`[records]
/// table`, the one source whose rows can be text columns without the plan
/// saying so), at `table`; none for the other sources.
pub fn rows_if_table(plan: &Plan, table: &Path) -> Vec<RecordRow> {
    match plan.records_study().map(|r| &r.records) {
        Ok(RecordSource::Table(_)) => select(plan, table).unwrap_or_default(),
        _ => Vec::new(),
    }
}

/// The plan's record pairs (the components its selection holds, before a
/// random orientation turns them), from the table at `table`.
pub fn select_pairs(plan: &Plan, table: &Path) -> Result<Vec<super::RowPair>, SelectError> {
    if !table.exists() {
        return Err(SelectError::MissingTable(table.into()));
    }
    let rows = components(plan.records_study()?, tables::records::read(table)?)?;
    super::pairs::pair_up(rows).map_err(SelectError::Pairs)
}

/// The plan's records wherever the pipeline names them (a table, or AT2
/// files read directly), filtered and sorted.
pub fn of_plan(plan: &Plan) -> Result<Vec<RecordRow>, SelectError> {
    let rs = plan.records_study()?;
    match &rs.records {
        RecordSource::Table(path) => select(plan, path),
        RecordSource::At2 { paths, manifest } => {
            let rows = collect::collect(paths, manifest.as_deref(), OnBad::Refuse(PIPELINE_HINT))
                .map_err(SelectError::Collect)?
                .rows;
            filter(rs, rows)
        }
        RecordSource::Text {
            paths, manifest, ..
        } => {
            let text = rs.records.text();
            let rows = collect::collect_as(
                paths,
                manifest.as_deref(),
                OnBad::Refuse(PIPELINE_HINT),
                text.as_ref(),
            )
            .map_err(SelectError::Collect)?
            .rows;
            filter(rs, rows)
        }
    }
}

fn filter(plan: &RecordsPlan, rows: Vec<RecordRow>) -> Result<Vec<RecordRow>, SelectError> {
    let selected = components(plan, rows)?;
    match plan.random_orientation {
        None => Ok(selected),
        // Every pair at every angle, each a record of the study.
        Some(step) => {
            let pairs = super::pairs::pair_up(selected).map_err(SelectError::Pairs)?;
            Ok(super::pairs::rotated_rows(
                &pairs,
                &crate::pair::angles(step),
            ))
        }
    }
}

/// The records the plan's sets and ids select, sorted by id.
fn components(plan: &RecordsPlan, rows: Vec<RecordRow>) -> Result<Vec<RecordRow>, SelectError> {
    let available_sets: BTreeSet<String> = rows.iter().filter_map(|r| r.meta.set.clone()).collect();
    if let Some(set) = plan.sets.iter().find(|s| !available_sets.contains(*s)) {
        return Err(SelectError::UnknownSet {
            set: set.clone(),
            available: if available_sets.is_empty() {
                "none (the records carry no set: give a manifest)".to_string()
            } else {
                available_sets.into_iter().collect::<Vec<_>>().join(", ")
            },
        });
    }
    let ids: BTreeSet<&str> = rows.iter().map(|r| r.record_id.as_str()).collect();
    let missing: Vec<&str> = plan
        .ids
        .iter()
        .map(String::as_str)
        .filter(|id| !ids.contains(id))
        .collect();
    if !missing.is_empty() {
        return Err(SelectError::UnknownIds(missing.join(", ")));
    }
    let mut selected: Vec<RecordRow> = rows
        .into_iter()
        .filter(|r| {
            plan.sets.is_empty() || r.meta.set.as_ref().is_some_and(|s| plan.sets.contains(s))
        })
        .filter(|r| plan.ids.is_empty() || plan.ids.contains(&r.record_id))
        .collect();
    if selected.is_empty() {
        return Err(SelectError::Empty);
    }
    selected.sort_by(|a, b| a.record_id.cmp(&b.record_id));
    Ok(selected)
}
