//! Records as pairs: two components of one station, matched by the
//! manifest's set and pair number (`record_id`) and component (`a`, `b`),
//! and the pair's component at any angle as a record of its own
//! (docs/MODEL.md §18).

use std::collections::BTreeMap;

use crate::pair::Pair;
use crate::tables::records::RecordRow;

/// A pair's two records and their samples as a [`Pair`].
pub struct RowPair {
    pub a: RecordRow,
    pub b: RecordRow,
    pub pair: Pair,
}

/// The records as pairs, in the order of their first component's first
/// appearance; refused, saying why, where a record has no pair, a pair
/// lacks a component, or its components differ in sample step.
pub fn pair_up(rows: Vec<RecordRow>) -> Result<Vec<RowPair>, String> {
    let mut found: BTreeMap<(String, String), [Option<RecordRow>; 2]> = BTreeMap::new();
    let mut order = Vec::new();
    for r in rows {
        let (Some(number), Some(component)) = (r.meta.pair.clone(), r.meta.pair_component.clone())
        else {
            return Err(format!(
                "record {} has no pair: the records' manifest gives each its pair (`record_id`) \
                 and component (`component_id`, a or b)",
                r.record_id
            ));
        };
        let key = (r.meta.set.clone().unwrap_or_default(), number);
        let slot = match component.as_str() {
            "a" => 0,
            "b" => 1,
            other => {
                return Err(format!(
                    "record {}: component `{other}`; a pair's components are a and b",
                    r.record_id
                ))
            }
        };
        let entry = found.entry(key.clone()).or_insert_with(|| {
            order.push(key);
            [None, None]
        });
        entry[slot] = Some(r);
    }
    order
        .into_iter()
        .map(|key| {
            let [a, b] = found.remove(&key).expect("every key was found");
            let (Some(a), Some(b)) = (a, b) else {
                return Err(format!(
                    "pair {} of {} has one component among the records: a pair needs both",
                    key.1,
                    if key.0.is_empty() {
                        "the records"
                    } else {
                        &key.0
                    }
                ));
            };
            let pair = Pair::new(a.accel_g.clone(), a.dt_s, b.accel_g.clone(), b.dt_s)
                .map_err(|e| format!("{} and {}: {e}", a.record_id, b.record_id))?;
            Ok(RowPair { a, b, pair })
        })
        .collect()
}

/// Each pair's component at each of `angles_deg`, as a record named
/// `<a>@<θ>`: its samples, peak and duration its own, its manifest facts
/// component a's but for the component (`a@θ`), its fingerprint of both
/// files' and the angle.
pub fn rotated_rows(pairs: &[RowPair], angles_deg: &[f64]) -> Vec<RecordRow> {
    pairs
        .iter()
        .flat_map(|p| angles_deg.iter().map(move |&theta| rotated(p, theta)))
        .collect()
}

fn rotated(p: &RowPair, theta: f64) -> RecordRow {
    let accel_g = p.pair.rotated(theta);
    let dt_s = p.pair.dt_s;
    let peak = crate::motion::peak(&accel_g, dt_s);
    let mut meta = p.a.meta.clone();
    meta.pair_component = Some(format!("a@{theta}"));
    RecordRow {
        record_id: crate::pair::angled_id(&p.a.record_id, theta),
        source: format!("{} and {} at {theta}°", p.a.source, p.b.source),
        sha256: crate::hash::sha256_hex(
            format!("{} {} {theta}", p.a.sha256, p.b.sha256).as_bytes(),
        ),
        dt_s,
        pga_g: peak.map_or(0.0, |p| p.pga_g),
        pga_time_s: peak.map_or(0.0, |p| p.time_s),
        duration_s: crate::motion::duration_s(accel_g.len(), dt_s),
        header: p.a.header.clone(),
        header_layout: p.a.header_layout.clone(),
        meta,
        accel_g,
    }
}
