//! The Parquet layer: round trips, atomic writes, refusal of foreign files.

use rocking::manifest::RecordMeta;
use rocking::tables::records::{read, schema, to_batch, write, RecordRow, KIND};
use rocking::tables::{self, read_table, AtomicTableWriter, TableError, TableKind};

use crate::util::tempdir;

fn row(id: &str, accel_g: Vec<f64>, meta: RecordMeta) -> RecordRow {
    RecordRow {
        record_id: id.into(),
        source: format!("x/{id}.AT2"),
        sha256: "ab".repeat(32),
        dt_s: 0.01,
        pga_g: 0.5,
        pga_time_s: 0.02,
        duration_s: 0.03,
        header: ["h1".into(), "h2".into(), "h3".into(), "h4".into()],
        header_layout: "keyed".into(),
        meta,
        accel_g,
    }
}

#[test]
fn round_trip_keeps_every_field_and_bit() {
    let dir = tempdir();
    let path = dir.path().join("sub/records.parquet");
    let full = RecordMeta {
        set: Some("far-field".into()),
        pair: Some("3".into()),
        pair_component: Some("a".into()),
        rsn: Some(1602),
        event: Some("Duzce, Turkey".into()),
        year: Some(1999),
        magnitude: Some(7.1),
        station: Some("Bolu".into()),
        component: Some("DUZCE/BOL000".into()),
        pga_max_pair_g: Some(0.82),
        pgv_max_pair_cm_s: Some(62.0),
        normalization_factor: Some(0.63),
        site_class: Some("D".into()),
        vs30_m_s: Some(326.0),
        fault_type: Some("Strike-slip".into()),
        r_jb_km: Some(12.0),
        r_rup_km: Some(12.0),
        lowest_usable_freq_hz: Some(0.06),
    };
    // Awkward doubles (subnormal, negative zero, 0.1) must survive bit for bit.
    let rows: Vec<RecordRow> = (0..40)
        .map(|k| {
            let meta = if k % 2 == 0 {
                full.clone()
            } else {
                RecordMeta::default()
            };
            row(&format!("R{k}"), vec![0.1, -0.0, 5e-324, k as f64], meta)
        })
        .collect();
    write(&path, &rows, &[("rocking.test".into(), "yes".into())]).unwrap();
    let back = read(&path).unwrap();
    assert_eq!(back.len(), rows.len());
    for (a, b) in rows.iter().zip(&back) {
        assert_eq!(a, b);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&a.accel_g), bits(&b.accel_g));
    }
    let contents = read_table(&path, KIND).unwrap();
    assert_eq!(contents.meta("rocking.test"), Some("yes"));
    assert_eq!(contents.meta(tables::META_TABLE), Some("records"));
    // Nothing but the table is left in the folder.
    let names: Vec<_> = std::fs::read_dir(path.parent().unwrap()).unwrap().collect();
    assert_eq!(names.len(), 1);
}

#[test]
fn dropped_writer_leaves_nothing() {
    let dir = tempdir();
    let path = dir.path().join("records.parquet");
    {
        let mut w = AtomicTableWriter::create(&path, KIND, schema(), &[]).unwrap();
        w.write(&to_batch(&[row("A", vec![1.0], RecordMeta::default())]).unwrap())
            .unwrap();
    }
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

#[test]
fn refuses_another_table() {
    let dir = tempdir();
    let path = dir.path().join("x.parquet");
    let other = TableKind {
        name: "ida_points",
        schema_version: 1,
    };
    let w = AtomicTableWriter::create(&path, other, schema(), &[]).unwrap();
    w.commit().unwrap();
    let e = read(&path).unwrap_err();
    assert!(matches!(e, TableError::WrongTable { .. }), "{e}");
}

/// A table handed on in memory (Python's batches) is the file `write`
/// writes, byte for byte: the same schema, metadata and compression; read
/// back, the same rows.
#[test]
fn a_table_in_memory_is_the_file_written() {
    use rocking::tables::ims::RecordImRow;
    let rows: Vec<RecordImRow> = (0..3)
        .map(|k| RecordImRow {
            record_id: format!("r{k}"),
            im: if k == 2 {
                "sa(1.0)".into()
            } else {
                "pga".into()
            },
            unit: "g".into(),
            period_s: (k == 2).then_some(1.0),
            value: 0.1 * f64::from(k) + 1e-17,
        })
        .collect();
    let settings = vec![("rocking.test".to_string(), "x".to_string())];
    let bytes = tables::to_bytes(&rows, &settings).unwrap();
    let dir = tempdir();
    let path = dir.path().join("t.parquet");
    tables::write(&path, &rows, &settings).unwrap();
    assert_eq!(std::fs::read(&path).unwrap(), bytes);
    assert_eq!(tables::read::<RecordImRow>(&path).unwrap(), rows);
}
