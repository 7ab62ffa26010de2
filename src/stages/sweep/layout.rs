//! The sweep's tables by name and stamp: the chunk size its part files
//! follow, the final tables' names (unsharded or one shard's), the metadata
//! keys every sweep table carries (read back as [`SweepMeta`]), and the hash
//! of everything that determines the results.

use std::path::Path;

use crate::pipeline::Plan;
use crate::stages::stage::Shard;
use crate::tables::records::RecordRow;
use crate::tables::sweep::{CapacityRow, IdaRow};
use crate::tables::{self, TableError};

/// Cases per chunk (and per part file).
pub const CHUNK_CASES: usize = 32;

/// Metadata keys of every sweep table.
pub const META_PLAN_HASH: &str = "rocking.sweep.plan_hash";
pub const META_PLAN: &str = "rocking.sweep.plan";
pub const META_SHARD: &str = "rocking.sweep.shard";
/// The settings that determine the results ([`Plan::sweep_settings`]).
pub const META_SETTINGS: &str = "rocking.sweep.settings";
/// The chunk a part file holds.
pub const META_CHUNK: &str = "rocking.sweep.chunk";
/// Each record's [`record_key`], a JSON object by record id: a rerun
/// reuses the rows of the records whose key is unchanged.
pub const META_RECORD_KEYS: &str = "rocking.sweep.record_keys";

/// What a sweep table's metadata says about how it was made.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SweepMeta {
    pub plan_hash: Option<String>,
    /// [`Plan::sweep_settings`] of the plan that made it.
    pub settings: Option<String>,
    /// The chunk a part file holds.
    pub chunk: Option<String>,
}

impl SweepMeta {
    /// Reads the metadata of a sweep table or part file (its footer only).
    pub fn read(path: &Path) -> Result<SweepMeta, TableError> {
        let kv = tables::read_metadata(path)?;
        let get = |key: &str| kv.iter().find(|(k, _)| k == key).map(|(_, v)| v.clone());
        Ok(SweepMeta {
            plan_hash: get(META_PLAN_HASH),
            settings: get(META_SETTINGS),
            chunk: get(META_CHUNK),
        })
    }
}

/// Final table names of an unsharded run or of one shard.
pub(super) fn final_names(shard: Option<Shard>) -> (String, String) {
    match shard {
        None => ("ida_points.parquet".into(), "capacities.parquet".into()),
        Some(s) => (
            format!("ida_points.{}.parquet", s.tag()),
            format!("capacities.{}.parquet", s.tag()),
        ),
    }
}

/// Hash of everything that determines one record's cases: the build of
/// the tool (its version and a hash of its sources: the physics changes
/// without the version) and the tables' schemas, the settings but for
/// which records are selected (`sets`, `ids`), the record's id and the
/// motion its blocks feel (its step and samples, bit for bit; a floor is in
/// the settings). The settings are written once for every record.
pub(in crate::stages) struct RecordKeys {
    prefix: String,
}

impl RecordKeys {
    pub(in crate::stages) fn new(plan: &Plan) -> Self {
        let mut settings = plan.sweep_settings_json();
        if let Some(o) = settings.as_object_mut() {
            o.remove("sets");
            o.remove("ids");
        }
        let prefix = format!(
            "{} {} ida_points/{} capacities/{} {settings}",
            crate::VERSION,
            crate::SOURCES,
            <IdaRow as tables::Table>::KIND.schema_version,
            <CapacityRow as tables::Table>::KIND.schema_version,
        );
        RecordKeys { prefix }
    }

    /// The metadata entry `meta_key` of the `records`' `keys` (one each,
    /// in order): a JSON object by record id.
    pub(in crate::stages) fn entry(
        meta_key: &str,
        records: &[RecordRow],
        keys: &[String],
    ) -> (String, String) {
        let map: serde_json::Map<String, serde_json::Value> = (records.iter())
            .zip(keys)
            .map(|(r, k)| (r.record_id.clone(), k.clone().into()))
            .collect();
        (
            meta_key.to_string(),
            serde_json::Value::Object(map).to_string(),
        )
    }

    /// The records' keys a table at `path` holds under `meta_key`, by
    /// record id; `None` if it holds none (written by an older version).
    pub(in crate::stages) fn written(
        path: &Path,
        meta_key: &str,
    ) -> Result<Option<std::collections::BTreeMap<String, String>>, TableError> {
        let meta = tables::read_metadata(path)?;
        Ok(meta
            .iter()
            .find(|(k, _)| k == meta_key)
            .and_then(|(_, v)| serde_json::from_str(v).ok()))
    }

    /// The key of `record`'s cases.
    pub(in crate::stages) fn of(&self, record: &RecordRow) -> String {
        let mut bytes = format!("{} {}\n", self.prefix, record.record_id).into_bytes();
        bytes.extend(record.dt_s.to_bits().to_le_bytes());
        for a in &record.accel_g {
            bytes.extend(a.to_bits().to_le_bytes());
        }
        crate::hash::sha256_hex(&bytes)
    }
}

/// Hash of everything that determines the sweep's output.
pub fn plan_hash(plan: &Plan, records: &[RecordRow]) -> String {
    // The build too: a part saved by a build of other sources is not resumed.
    let mut text = format!("{} {}", crate::VERSION, crate::SOURCES);
    text.push_str(&format!(
        "ida_points/{} capacities/{}",
        <IdaRow as tables::Table>::KIND.schema_version,
        <CapacityRow as tables::Table>::KIND.schema_version
    ));
    // Only what changes the results: not the name, where the records are, or reduce's settings.
    text.push_str(&plan.sweep_settings());
    for r in records {
        text.push_str(&r.record_id);
        text.push_str(&r.sha256);
    }
    crate::hash::sha256_hex(text.as_bytes())
}
