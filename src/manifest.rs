//! Record manifest: a CSV of per-record metadata, keyed by the AT2 file.
//!
//! The bundled `records/fema-p695/manifest.csv` has one row per component with
//! its FEMA P695 set, pair number, PEER RSN, event, station, site data and the
//! pair's normalisation factor. A row is matched to an ingested file by the
//! file stem of its `file` column (the record id), so the same manifest works
//! for a copy of the files elsewhere.
//!
//! Only `file` is required; every other known column is optional, and an empty
//! cell is a missing value. Unknown columns are reported back to the caller,
//! not refused, so a user's own manifest may carry extra notes. Errors name the
//! CSV line and column. The reader takes any `io::Read`; opening the file is
//! the caller's business.

use crate::csv_rows;
use std::collections::BTreeMap;
use std::fmt;
use std::io::Read;
use std::path::Path;

/// Descriptive metadata of one record (all optional): what the records table
/// carries beside the samples.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RecordMeta {
    pub set: Option<String>,
    /// FEMA P695 pair number (the manifest's `record_id` column).
    pub pair: Option<String>,
    /// Component within the pair, `a` or `b` (the manifest's `component_id`).
    pub pair_component: Option<String>,
    pub rsn: Option<i64>,
    pub event: Option<String>,
    pub year: Option<i64>,
    pub magnitude: Option<f64>,
    pub station: Option<String>,
    pub component: Option<String>,
    pub pga_max_pair_g: Option<f64>,
    pub pgv_max_pair_cm_s: Option<f64>,
    pub normalization_factor: Option<f64>,
    pub site_class: Option<String>,
    pub vs30_m_s: Option<f64>,
    pub fault_type: Option<String>,
    pub r_jb_km: Option<f64>,
    pub r_rup_km: Option<f64>,
    pub lowest_usable_freq_hz: Option<f64>,
}

/// One manifest row.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ManifestEntry {
    /// CSV line the entry came from (1-based, the header is line 1).
    pub line: u64,
    /// The `file` column, as written (relative to the manifest's folder).
    pub file: String,
    /// NPTS and DT as tabulated; checked against the file at ingest.
    pub npts: Option<u64>,
    pub dt_s: Option<f64>,
    /// PGA of the component as tabulated (g); the table's `pga_g` comes from the samples.
    pub pga_g: Option<f64>,
    /// Half a unit in the last digit `pga_g` is printed to (g): how far it
    /// may lie from the file's peak (`0.42` for 0.415783: 0.005).
    pub pga_g_half_unit: Option<f64>,
    pub meta: RecordMeta,
}

impl ManifestEntry {
    /// The record id this entry describes: the stem of its `file`.
    pub fn record_id(&self) -> String {
        file_stem(&self.file)
    }
}

/// The stem of a path written with `/` or `\` separators.
pub fn file_stem(path: &str) -> String {
    let normalised = path.replace('\\', "/");
    Path::new(&normalised)
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// A parsed manifest: entries by record id, plus the columns it ignored.
#[derive(Debug, Clone, Default)]
pub struct Manifest {
    pub entries: BTreeMap<String, ManifestEntry>,
    pub ignored_columns: Vec<String>,
}

#[derive(Debug)]
pub struct ManifestError {
    /// CSV line (1-based), when the problem is on one line.
    pub line: Option<u64>,
    pub message: String,
}

impl fmt::Display for ManifestError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(line) => write!(f, "line {line}: {}", self.message),
            None => write!(f, "{}", self.message),
        }
    }
}

impl std::error::Error for ManifestError {}

/// Columns this reader understands, in the bundled manifest's order.
pub const KNOWN_COLUMNS: &[&str] = &[
    "set",
    "record_id",
    "component_id",
    "rsn",
    "event",
    "year",
    "magnitude",
    "station",
    "component",
    "npts",
    "dt",
    "pga_g",
    "pga_max_pair_g",
    "pgv_max_pair_cm_s",
    "normalization_factor",
    "site_class",
    "vs30_m_s",
    "fault_type",
    "r_jb_km",
    "r_rup_km",
    "lowest_usable_freq_hz",
    "file",
];

/// Reads a manifest CSV (header row, then one row per record). Errors give
/// the line in the file, header included.
pub fn read(mut input: impl Read) -> Result<Manifest, ManifestError> {
    let mut bytes = Vec::new();
    input.read_to_end(&mut bytes).map_err(|e| ManifestError {
        line: None,
        message: format!("cannot read: {e}"),
    })?;
    let mut csv = csv::ReaderBuilder::new()
        .has_headers(true)
        .from_reader(bytes.as_slice());
    let headers = csv
        .headers()
        .map_err(|e| ManifestError {
            line: Some(1),
            message: format!("cannot read the header: {}", csv_rows::message(&e)),
        })?
        .clone();
    let (column, ignored_columns) = columns(&headers)?;

    let mut entries: BTreeMap<String, ManifestEntry> = BTreeMap::new();
    let lines = csv_rows::Lines::new(&bytes);
    for row in csv.records() {
        let row = row.map_err(|e| ManifestError {
            line: csv_rows::error_line(&bytes, &e),
            message: csv_rows::message(&e),
        })?;
        let line = row.position().map_or(0, |p| lines.line_at(p.byte()));
        let entry = row_entry(&row, line, &column)?;
        let id = entry.record_id();
        if let Some(first) = entries.get(&id) {
            return Err(ManifestError {
                line: Some(line),
                message: format!(
                    "record `{id}` is listed twice (lines {} and {line}); record ids are file stems and must be unique",
                    first.line
                ),
            });
        }
        entries.insert(id, entry);
    }
    Ok(Manifest {
        entries,
        ignored_columns,
    })
}

/// The header row (line 1): the index of each known column (its name in
/// any case: `FILE`, `NPTS`), and the unknown columns' names. A known
/// column named twice, or no `file` column, is refused.
fn columns(
    headers: &csv::StringRecord,
) -> Result<(BTreeMap<&'static str, usize>, Vec<String>), ManifestError> {
    let mut column = BTreeMap::new();
    let mut ignored_columns = Vec::new();
    for (i, given) in headers.iter().enumerate() {
        let given = given.trim();
        let known = KNOWN_COLUMNS.iter().find(|k| k.eq_ignore_ascii_case(given));
        if let Some(&name) = known {
            if column.insert(name, i).is_some() {
                return Err(ManifestError {
                    line: Some(1),
                    message: format!("column `{name}` appears twice"),
                });
            }
        } else {
            ignored_columns.push(given.to_string());
        }
    }
    if !column.contains_key("file") {
        let semicolons = headers.len() == 1 && headers.as_slice().contains(';');
        return Err(ManifestError {
            line: Some(1),
            message: format!(
                "no `file` column{}; a manifest needs `file` (the AT2 path relative to the \
                 manifest) and may have any of: {}",
                if semicolons {
                    " (its header reads as one column: a manifest's columns are apart by commas, \
                     not semicolons)"
                } else {
                    ""
                },
                KNOWN_COLUMNS.join(", ")
            ),
        });
    }
    Ok((column, ignored_columns))
}

/// The entry of one row, on CSV line `line`, its cells found by `column`
/// (see [`columns`]): an empty cell is a missing value, a cell that does not
/// read as its column's type is refused.
fn row_entry(
    row: &csv::StringRecord,
    line: u64,
    column: &BTreeMap<&str, usize>,
) -> Result<ManifestEntry, ManifestError> {
    let cell = |name: &str| -> Option<&str> {
        column
            .get(name)
            .and_then(|&i| row.get(i))
            .map(str::trim)
            .filter(|s| !s.is_empty())
    };
    let text = |name: &str| cell(name).map(str::to_string);
    let bad = |name: &str, value: &str, what: &str| ManifestError {
        line: Some(line),
        message: format!("column `{name}`: `{value}` is not {what}"),
    };
    let int = |name: &str| -> Result<Option<i64>, ManifestError> {
        cell(name)
            .map(|v| v.parse::<i64>().map_err(|_| bad(name, v, "a whole number")))
            .transpose()
    };
    let real = |name: &str| -> Result<Option<f64>, ManifestError> {
        cell(name)
            .map(|v| match v.parse::<f64>() {
                Ok(x) if x.is_finite() => Ok(x),
                _ => Err(bad(name, v, "a finite number")),
            })
            .transpose()
    };
    let file = text("file").ok_or_else(|| ManifestError {
        line: Some(line),
        message: "the `file` cell is empty".into(),
    })?;
    let npts = match int("npts")? {
        Some(n) if n > 0 => Some(n as u64),
        Some(n) => return Err(bad("npts", &n.to_string(), "a positive whole number")),
        None => None,
    };
    let meta = RecordMeta {
        set: text("set"),
        pair: text("record_id"),
        pair_component: text("component_id"),
        rsn: int("rsn")?,
        event: text("event"),
        year: int("year")?,
        magnitude: real("magnitude")?,
        station: text("station"),
        component: text("component"),
        pga_max_pair_g: real("pga_max_pair_g")?,
        pgv_max_pair_cm_s: real("pgv_max_pair_cm_s")?,
        normalization_factor: real("normalization_factor")?,
        site_class: text("site_class"),
        vs30_m_s: real("vs30_m_s")?,
        fault_type: text("fault_type"),
        r_jb_km: real("r_jb_km")?,
        r_rup_km: real("r_rup_km")?,
        lowest_usable_freq_hz: real("lowest_usable_freq_hz")?,
    };
    Ok(ManifestEntry {
        line,
        file,
        npts,
        dt_s: real("dt")?,
        pga_g: real("pga_g")?,
        pga_g_half_unit: cell("pga_g").map(half_unit),
        meta,
    })
}

/// Half a unit in the last digit of a number as printed: `0.42` → 0.005,
/// `4.2e-1` → 0.005, `1` → 0.5.
fn half_unit(printed: &str) -> f64 {
    let (mantissa, exponent) = match printed.find(['e', 'E']) {
        Some(k) => (&printed[..k], printed[k + 1..].parse::<i32>().unwrap_or(0)),
        None => (printed, 0),
    };
    let decimals = mantissa.split_once('.').map_or(0, |(_, d)| {
        d.chars().filter(char::is_ascii_digit).count() as i32
    });
    0.5 * 10f64.powi(exponent - decimals)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_quoted_cells_and_missing_values() {
        let csv = "set,record_id,event,year,npts,dt,vs30_m_s,notes,file\n\
                   far-field,3,\"Duzce, Turkey\",1999,5590,0.01,,x,far-field/RSN1602_DUZCE_BOL000.AT2\n";
        let m = read(csv.as_bytes()).unwrap();
        let e = &m.entries["RSN1602_DUZCE_BOL000"];
        assert_eq!(e.meta.event.as_deref(), Some("Duzce, Turkey"));
        assert_eq!(e.meta.pair.as_deref(), Some("3"));
        assert_eq!(e.meta.year, Some(1999));
        assert_eq!(e.npts, Some(5590));
        assert_eq!(e.dt_s, Some(0.01));
        assert_eq!(e.meta.vs30_m_s, None);
        assert_eq!(e.line, 2);
        assert_eq!(m.ignored_columns, vec!["notes".to_string()]);
    }

    #[test]
    fn errors_name_line_and_column() {
        let e = read("year,file\n1999,a.AT2\n19x9,b.AT2\n".as_bytes()).unwrap_err();
        assert_eq!(e.line, Some(3));
        assert!(
            e.message.contains("`year`") && e.message.contains("19x9"),
            "{e}"
        );

        let e = read("set,path\nx,a.AT2\n".as_bytes()).unwrap_err();
        assert!(e.message.contains("no `file` column"), "{e}");

        let e = read("file\nA/x.AT2\nB/x.at2\n".as_bytes()).unwrap_err();
        assert_eq!(e.line, Some(3));
        assert!(e.message.contains("listed twice"), "{e}");

        let e = read("dt,file\nnan,a.AT2\n".as_bytes()).unwrap_err();
        assert!(e.message.contains("`dt`"), "{e}");
    }

    #[test]
    fn half_a_unit_in_the_last_printed_digit() {
        for (printed, half) in [
            ("0.42", 0.005),
            ("0.415783", 5e-7),
            ("4.2e-1", 0.005),
            ("1", 0.5),
            ("12.", 0.5),
        ] {
            let h = half_unit(printed);
            assert!((h - half).abs() <= 1e-12 * half, "{printed}: {h}");
        }
    }

    /// Column names in capitals are the known ones (`FILE,NPTS,DT` was "no
    /// `file` column"); a header of semicolons is said to be one.
    #[test]
    fn headers_in_any_case_and_semicolons_named() {
        let m = read(
            "FILE,NPTS,Dt
a.AT2,20,0.01
"
            .as_bytes(),
        )
        .unwrap();
        let e = &m.entries["a"];
        assert_eq!((e.npts, e.dt_s), (Some(20), Some(0.01)));
        assert!(m.ignored_columns.is_empty());
        let e = read(
            "file;npts
a.AT2;20
"
            .as_bytes(),
        )
        .unwrap_err();
        assert!(e.message.contains("not semicolons"), "{e}");
    }

    #[test]
    fn lines_count_the_header_whatever_the_line_endings() {
        // With CRLF endings or a blank line the csv crate's own
        // line numbers were one too low.
        for text in [
            "year,file\r\n1999,a.AT2\r\n19x9,b.AT2\r\n",
            "\u{feff}year,file\r\n1999,a.AT2\r\n19x9,b.AT2\r\n",
            "year,file\n1999,a.AT2\n19x9,b.AT2\n",
        ] {
            let e = read(text.as_bytes()).unwrap_err();
            assert_eq!(e.line, Some(3), "{text:?}: {e}");
        }
        let e = read("file\n\nA/x.AT2\nB/x.at2\n".as_bytes()).unwrap_err();
        assert!(e.message.contains("lines 3 and 4"), "{e}");
        assert_eq!(e.line, Some(4));
        let e = read("year,file\r\n1999,a.AT2,extra\r\n".as_bytes()).unwrap_err();
        assert_eq!(e.line, Some(2), "{e}");
        // One line number, the file's: the csv crate's own (1 here) is left out.
        assert_eq!(
            e.to_string(),
            "line 2: 3 fields where the header has 2",
            "{e}"
        );
        // A quoted cell spanning two lines: the next record starts on line 4.
        let e = read("year,file\n\"1999\",\"a\nb.AT2\"\n19x9,c.AT2\n".as_bytes()).unwrap_err();
        assert_eq!(e.line, Some(4), "{e}");
    }

    #[test]
    fn stems_ignore_folders_and_separators() {
        assert_eq!(
            file_stem("far-field/RSN953_NORTHR_MUL009.AT2"),
            "RSN953_NORTHR_MUL009"
        );
        assert_eq!(file_stem("a\\b\\RSN1.at2"), "RSN1");
    }
}
