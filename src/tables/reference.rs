//! The tables' reference, `docs/tables.md`, generated from their
//! definitions: each table's doc comment, and per column its name, its
//! Arrow type, whether it may be empty, the labels a closed set's column
//! holds and its doc comment. [`CATALOG`] lists every table; a test holds
//! it to the `table!` definitions there are and the committed file to
//! [`markdown`].

use arrow_schema::{DataType, Schema};

use super::table::Table;

/// One table's reference, as its definition states it.
pub struct TableDoc {
    pub name: &'static str,
    pub version: u32,
    pub doc: &'static [&'static str],
    pub schema: std::sync::Arc<Schema>,
    pub columns: &'static [(&'static str, &'static [&'static str])],
    /// The labels each text column of a closed set may hold.
    pub values: Vec<Option<String>>,
}

/// The reference of table `T`.
pub fn of<T: Table>() -> TableDoc {
    TableDoc {
        name: T::KIND.name,
        version: T::KIND.schema_version,
        doc: T::DOC,
        schema: T::schema(),
        columns: T::COLUMN_DOCS,
        values: T::column_values(),
    }
}

/// Every table the tool writes, in the order of the pipeline that writes
/// them (records, sweep, convergence, reduce, ims, damage, fit, pulses),
/// then the commands' own (risk, history).
pub fn catalog() -> Vec<TableDoc> {
    use super::*;
    vec![
        of::<records::RecordRow>(),
        of::<sweep::IdaRow>(),
        of::<sweep::CapacityRow>(),
        of::<convergence::ConvergenceRow>(),
        of::<convergence::ConvergenceCaseRow>(),
        of::<reduce::BlockRow>(),
        of::<reduce::HorizontalRow>(),
        of::<reduce::VerticalRow>(),
        of::<reduce::CapacityFractileRow>(),
        of::<reduce::LognormalRow>(),
        of::<reduce::OverturnFractionRow>(),
        of::<reduce::CapacityBandRow>(),
        of::<reduce::CapacityResampleRow>(),
        of::<ims::RecordImRow>(),
        of::<ims::EfficiencyRow>(),
        of::<damage::StateCapacityRow>(),
        of::<damage::DamageStateRow>(),
        of::<fit::FitStep1Row>(),
        of::<fit::FitCoefficientRow>(),
        of::<fit::FitComparisonRow>(),
        of::<fit::FitBandRow>(),
        of::<pulse::PulseWallRow>(),
        of::<pulse::PulseCellRow>(),
        of::<risk::RiskRow>(),
        of::<history::HistoryRow>(),
    ]
}

/// A doc comment's lines as one paragraph (the leading space of `///`
/// text dropped; a blank line starts a new paragraph).
fn paragraph(lines: &[&str]) -> String {
    let mut out = String::new();
    for line in lines {
        let line = line.strip_prefix(' ').unwrap_or(line).trim_end();
        if line.is_empty() {
            out.push_str("\n\n");
        } else {
            if !(out.is_empty() || out.ends_with('\n')) {
                out.push(' ');
            }
            out.push_str(line);
        }
    }
    out
}

/// An Arrow type as the reference names it.
fn type_name(t: &DataType) -> String {
    match t {
        DataType::Float64 => "float64".into(),
        DataType::Int64 => "int64".into(),
        DataType::Int8 => "int8".into(),
        DataType::Boolean => "bool".into(),
        DataType::Utf8 => "string".into(),
        DataType::List(item) => format!("list<{}>", type_name(item.data_type())),
        other => other.to_string(),
    }
}

/// `docs/tables.md`.
pub fn markdown() -> String {
    let mut s = String::from(
        "# Tables\n\n\
         <!-- Generated from the tables' definitions (src/tables/, `table!`) by\n\
         `rocking::tables::reference::markdown`; a test holds this file to it.\n\
         Rewrite it with `ROCKING_BLESS=1 cargo test --release tables::`. -->\n\n\
         Every table is Parquet with zstd compression and key-value metadata:\n\
         `rocking.table` (its name), `rocking.schema_version`, `rocking.crate_version`,\n\
         and the settings that produced it, where the stage has any. Tables are written to a temporary\n\
         file and renamed, so a crash never leaves a half-written table. A reader\n\
         refuses a file of another table or schema version. Types are Arrow's;\n\
         `?` marks a column that may be empty (null).\n\n",
    );
    let tables = catalog();
    for t in &tables {
        s.push_str(&format!("- [`{0}`](#{0})\n", t.name));
    }
    for t in &tables {
        s.push_str(&format!(
            "\n## {}\n\nSchema version {}. {}\n\n| column | type | meaning |\n|---|---|---|\n",
            t.name,
            t.version,
            paragraph(t.doc)
        ));
        for (k, field) in t.schema.fields().iter().enumerate() {
            let doc = t
                .columns
                .iter()
                .find(|(name, _)| name == field.name())
                .map_or(String::new(), |(_, d)| paragraph(d).replace('\n', " "));
            let values = match t.values.get(k).cloned().flatten() {
                Some(v) => format!(
                    " One of: {}.",
                    v.split(", ")
                        .map(|l| format!("`{l}`"))
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
                None => String::new(),
            };
            s.push_str(&format!(
                "| `{}` | {}{} | {}{} |\n",
                field.name(),
                type_name(field.data_type()),
                if field.is_nullable() { "?" } else { "" },
                doc.replace('|', "\\|"),
                values
            ));
        }
    }
    s
}
