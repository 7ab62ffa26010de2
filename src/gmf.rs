//! OpenQuake's event-based ground-motion fields as its `--exports csv`
//! writes them (pure: text in, values out): `gmf-data_N.csv` (`event_id,
//! gmv_<IMT>…, custom_site_id`), `events_N.csv` (`event_id, rup_id, rlz_id,
//! year, ses_id`), `sitemesh_N.csv` (`custom_site_id, lon, lat`), each after
//! one metadata line; and the effective investigation time from the job.
//! Units are OpenQuake's: PGA and SA in g, PGV in cm/s (docs/MODEL.md §20).

use std::collections::HashMap;

use crate::im::Im;

/// A problem in one of the files, with its line (1-based) and column.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{file}:{line}{}: {message}", .column.as_ref().map_or(String::new(), |c| format!(", column `{c}`")))]
pub struct GmfError {
    pub file: String,
    pub line: usize,
    pub column: Option<String>,
    pub message: String,
}

/// A site of the fields.
#[derive(Debug, Clone, PartialEq)]
pub struct GmfSite {
    pub id: String,
    pub lon: f64,
    pub lat: f64,
}

/// The fields: the sites, the IMs, every event (with its realisation), and
/// each (event, site)'s values where OpenQuake wrote them (above its
/// minimum intensity; elsewhere the motion is below it, taken as 0).
#[derive(Debug, Clone, PartialEq)]
pub struct Fields {
    pub sites: Vec<GmfSite>,
    pub ims: Vec<Im>,
    /// Every event id of `events_N.csv`, ascending, and its realisation.
    pub events: Vec<(u64, u32)>,
    /// (event index into `events`, site index into `sites`, values in the
    /// order of `ims`).
    pub values: Vec<(usize, usize, Vec<f64>)>,
}

/// The lines after the metadata line (`#,…`), with their 1-based numbers.
fn data_lines<'a>(text: &'a str) -> impl Iterator<Item = (usize, &'a str)> + 'a {
    text.lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim_end_matches('\r')))
        .filter(|(_, l)| !l.starts_with('#') && !l.trim().is_empty())
}

/// The header's columns, refused unless `want` are among them: their
/// positions.
fn header<'a>(
    file: &str,
    lines: &mut impl Iterator<Item = (usize, &'a str)>,
    want: &[&str],
) -> Result<(usize, Vec<&'a str>, Vec<usize>), GmfError> {
    let (n, h) = lines.next().ok_or_else(|| GmfError {
        file: file.into(),
        line: 1,
        column: None,
        message: "no header line".into(),
    })?;
    let cols: Vec<&str> = h.split(',').map(str::trim).collect();
    let pos = want
        .iter()
        .map(|w| {
            cols.iter().position(|c| c == w).ok_or_else(|| GmfError {
                file: file.into(),
                line: n,
                column: Some((*w).into()),
                message: format!("the header `{h}` has no `{w}` column"),
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok((n, cols, pos))
}

/// A data line's cells, refused unless there are as many as the header's
/// columns (a line cut short, as a truncated file ends, is named as one).
fn cells<'a>(file: &str, line: usize, l: &'a str, width: usize) -> Result<Vec<&'a str>, GmfError> {
    let cells: Vec<&str> = l.split(',').collect();
    if cells.len() != width {
        return Err(GmfError {
            file: file.into(),
            line,
            column: None,
            message: format!(
                "{} cells where the header has {width} columns (a line cut short?)",
                cells.len()
            ),
        });
    }
    Ok(cells)
}

fn number<T: std::str::FromStr>(
    file: &str,
    line: usize,
    column: &str,
    cell: Option<&str>,
) -> Result<T, GmfError> {
    let cell = cell.map(str::trim).unwrap_or("");
    cell.parse().map_err(|_| GmfError {
        file: file.into(),
        line,
        column: Some(column.into()),
        message: format!("`{cell}` is not a number"),
    })
}

/// `sitemesh_N.csv`: the sites in the file's order.
pub fn parse_sites(text: &str, file: &str) -> Result<Vec<GmfSite>, GmfError> {
    let mut lines = data_lines(text);
    let (_, cols, pos) = header(file, &mut lines, &["custom_site_id", "lon", "lat"])?;
    let mut seen: HashMap<String, usize> = HashMap::new();
    lines
        .map(|(n, l)| {
            let cells = cells(file, n, l, cols.len())?;
            let id = cells.get(pos[0]).map_or("", |c| c.trim()).to_string();
            if let Some(first) = seen.insert(id.clone(), n) {
                return Err(GmfError {
                    file: file.into(),
                    line: n,
                    column: Some("custom_site_id".into()),
                    message: format!("site `{id}` is listed twice (lines {first} and {n})"),
                });
            }
            let lon: f64 = number(file, n, "lon", cells.get(pos[1]).copied())?;
            let lat: f64 = number(file, n, "lat", cells.get(pos[2]).copied())?;
            // As the hazard files' sites are checked.
            for (column, v) in [("lon", lon), ("lat", lat)] {
                if let Some(why) = crate::hazard::off_the_globe(column, v) {
                    return Err(GmfError {
                        file: file.into(),
                        line: n,
                        column: Some(column.into()),
                        message: why,
                    });
                }
            }
            Ok(GmfSite { id, lon, lat })
        })
        .collect()
}

/// `events_N.csv`: every event id and its realisation, ascending.
pub fn parse_events(text: &str, file: &str) -> Result<Vec<(u64, u32)>, GmfError> {
    let mut lines = data_lines(text);
    let (_, cols, pos) = header(file, &mut lines, &["event_id", "rlz_id"])?;
    let mut seen: HashMap<u64, usize> = HashMap::new();
    let mut out = lines
        .map(|(n, l)| {
            let cells = cells(file, n, l, cols.len())?;
            let id: u64 = number(file, n, "event_id", cells.get(pos[0]).copied())?;
            if let Some(first) = seen.insert(id, n) {
                return Err(GmfError {
                    file: file.into(),
                    line: n,
                    column: Some("event_id".into()),
                    message: format!("event {id} is listed twice (lines {first} and {n})"),
                });
            }
            Ok((id, number(file, n, "rlz_id", cells.get(pos[1]).copied())?))
        })
        .collect::<Result<Vec<(u64, u32)>, GmfError>>()?;
    out.sort_unstable();
    Ok(out)
}

/// The largest `ses_id` of `events_N.csv` (the stochastic event set each
/// event is in, 1 to `ses_per_logic_tree_path`), where the file has the
/// column (OpenQuake 3.x writes it).
pub fn last_event_set(text: &str, file: &str) -> Result<Option<u64>, GmfError> {
    largest(text, file, "ses_id")
}

/// The largest `year` of `events_N.csv` (the year within its realisation's
/// investigation_time × ses_per_logic_tree_path each event falls in), where
/// the file has the column: the effective time is at least that.
pub fn last_year(text: &str, file: &str) -> Result<Option<u64>, GmfError> {
    largest(text, file, "year")
}

/// The largest whole number in column `column` of `text`, if it has it.
fn largest(text: &str, file: &str, column: &str) -> Result<Option<u64>, GmfError> {
    let mut lines = data_lines(text);
    let (_, cols, _) = header(file, &mut lines, &[])?;
    let Some(at) = cols.iter().position(|c| *c == column) else {
        return Ok(None);
    };
    let mut last = None;
    for (n, l) in lines {
        let cells = cells(file, n, l, cols.len())?;
        let v: u64 = number(file, n, column, cells.get(at).copied())?;
        last = last.max(Some(v));
    }
    Ok(last)
}

/// The job's `ses_per_logic_tree_path` (1 where it is not given, as
/// OpenQuake's default).
pub fn event_sets_of_job(job_ini: &str) -> Result<f64, String> {
    Ok(job_number(job_ini, "ses_per_logic_tree_path")?.unwrap_or(1.0))
}

/// The IM of a `gmv_<IMT>` column: PGA, PGV or SA(T).
fn im_of_column(col: &str) -> Option<Im> {
    let imt = col.strip_prefix("gmv_")?;
    imt.parse::<Im>().ok().filter(|im| im.hazard())
}

/// `gmf-data_N.csv` over `sites` and `events`: its IMs and every value.
pub fn parse_fields(
    text: &str,
    file: &str,
    sites: Vec<GmfSite>,
    events: Vec<(u64, u32)>,
) -> Result<Fields, GmfError> {
    let mut lines = data_lines(text);
    let (head, cols, pos) = header(file, &mut lines, &["event_id", "custom_site_id"])?;
    let gmv: Vec<(usize, Im)> = cols
        .iter()
        .enumerate()
        .filter(|(_, c)| c.starts_with("gmv_"))
        .map(|(k, c)| {
            im_of_column(c).map(|im| (k, im)).ok_or_else(|| GmfError {
                file: file.into(),
                line: head,
                column: Some((*c).into()),
                message: "an IMT the tool does not know (PGA, PGV, SA(T))".into(),
            })
        })
        .collect::<Result<_, _>>()?;
    if gmv.is_empty() {
        return Err(GmfError {
            file: file.into(),
            line: head,
            column: None,
            message: "no `gmv_<IMT>` column".into(),
        });
    }
    // One column an IM: a second was read past, the first's values used.
    for (k, &(col, im)) in gmv.iter().enumerate() {
        if let Some(&(first, _)) = gmv[..k].iter().find(|g| g.1 == im) {
            return Err(GmfError {
                file: file.into(),
                line: head,
                column: Some(cols[col].into()),
                message: format!("the same IM as column `{}`", cols[first]),
            });
        }
    }
    let site_of: HashMap<&str, usize> = sites
        .iter()
        .enumerate()
        .map(|(k, s)| (s.id.as_str(), k))
        .collect();
    let event_of: HashMap<u64, usize> = events.iter().enumerate().map(|(k, e)| (e.0, k)).collect();
    let mut values = Vec::new();
    let mut written: HashMap<(usize, usize), usize> = HashMap::new();
    for (n, l) in lines {
        let cells = cells(file, n, l, cols.len())?;
        let eid: u64 = number(file, n, "event_id", cells.get(pos[0]).copied())?;
        let sid = cells.get(pos[1]).map_or("", |c| c.trim());
        let bad = |column: &str, message: String| GmfError {
            file: file.into(),
            line: n,
            column: Some(column.into()),
            message,
        };
        let e = *event_of
            .get(&eid)
            .ok_or_else(|| bad("event_id", format!("event {eid} is not in the events file")))?;
        let s = *site_of.get(sid).ok_or_else(|| {
            bad(
                "custom_site_id",
                format!("site `{sid}` is not in the site mesh"),
            )
        })?;
        if let Some(first) = written.insert((e, s), n) {
            return Err(bad(
                "custom_site_id",
                format!("event {eid} at site `{sid}` is written twice (lines {first} and {n})"),
            ));
        }
        let v = gmv
            .iter()
            .map(|&(k, _)| {
                let x: f64 = number(file, n, cols[k], cells.get(k).copied())?;
                if x.is_finite() && x >= 0.0 {
                    Ok(x)
                } else {
                    Err(bad(
                        cols[k],
                        format!("{x}: a ground motion is finite and not negative"),
                    ))
                }
            })
            .collect::<Result<Vec<_>, _>>()?;
        values.push((e, s, v));
    }
    Ok(Fields {
        sites,
        ims: gmv.into_iter().map(|(_, im)| im).collect(),
        events,
        values,
    })
}

/// The effective investigation time (years) of an event-based job:
/// `investigation_time × ses_per_logic_tree_path × R`, R the number of
/// realisations (`number_of_logic_tree_samples` when sampled, else
/// `realizations`); `ses_per_logic_tree_path` defaults to 1, as
/// OpenQuake's. A key is read as Python's configparser reads it (OpenQuake
/// reads job.ini so): `key = value` or `key: value`, the key in any case.
/// Refused, naming the key, when `investigation_time` is missing, a key is
/// not a number, the time is not positive and finite, or the stochastic
/// event sets per path are not a whole number from 1.
pub fn eff_years_of_job(job_ini: &str, realizations: usize) -> Result<f64, String> {
    let samples = samples_of_job(job_ini)?;
    let time = job_number(job_ini, "investigation_time")?.ok_or("no `investigation_time`")?;
    if !(time.is_finite() && time > 0.0) {
        return Err(format!(
            "`investigation_time = {time}`: give a positive number of years"
        ));
    }
    let ses = event_sets_of_job(job_ini)?;
    if !(ses >= 1.0 && ses.fract() == 0.0 && ses.is_finite()) {
        return Err(format!(
            "`ses_per_logic_tree_path = {ses}`: give a whole number of event sets, 1 or more"
        ));
    }
    if let Some(n) = samples.filter(|n| n.fract() != 0.0 || !n.is_finite()) {
        return Err(format!(
            "`number_of_logic_tree_samples = {n}`: give a whole number of samples"
        ));
    }
    Ok(time * ses * samples.unwrap_or(realizations as f64))
}

/// A number of a job.ini, read as Python's configparser reads it: `key =
/// value` or `key: value`, the key in any case, a `#` comment after it.
fn job_number(job_ini: &str, name: &str) -> Result<Option<f64>, String> {
    let Some(v) = job_ini.lines().find_map(|l| {
        let at = l.find(['=', ':'])?;
        let (k, v) = (&l[..at], &l[at + 1..]);
        (k.trim().eq_ignore_ascii_case(name))
            .then(|| v.split('#').next().unwrap_or("").trim().to_string())
    }) else {
        return Ok(None);
    };
    v.parse()
        .map(Some)
        .map_err(|_| format!("`{name} = {v}` is not a number"))
}

/// The job's `number_of_logic_tree_samples` where it samples (> 0).
pub fn samples_of_job(job_ini: &str) -> Result<Option<f64>, String> {
    Ok(job_number(job_ini, "number_of_logic_tree_samples")?.filter(|&s| s > 0.0))
}

/// `realizations_N.csv`: each realisation's weight (`rlz_id, branch_path,
/// weight`).
pub fn parse_weights(text: &str, file: &str) -> Result<Vec<f64>, GmfError> {
    let mut lines = data_lines(text);
    let (_, _, pos) = header(file, &mut lines, &["rlz_id", "weight"])?;
    lines
        .map(|(n, l)| {
            let cells: Vec<&str> = l.split(',').collect();
            number(file, n, "weight", cells.get(pos[1]).copied())
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Python's configparser (OpenQuake's reader) takes `:` as `=` and keys
    /// in any case: `ses_per_logic_tree_path: 2000` was read as absent (1),
    /// every rate 2000× too high.
    #[test]
    fn a_job_is_read_as_configparser_reads_it() {
        let job = "[general]\ninvestigation_time = 50.0\nSES_per_logic_tree_path: 2000\n";
        assert_eq!(eff_years_of_job(job, 3), Ok(50.0 * 2000.0 * 3.0));
        let sampled = "investigation_time=1 # years\nnumber_of_logic_tree_samples : 10\n";
        assert_eq!(eff_years_of_job(sampled, 3), Ok(10.0));
    }

    /// A site off the globe, an IM given twice: refused, naming the column.
    #[test]
    fn a_site_off_the_globe_and_an_im_twice_are_refused() {
        let e = parse_sites("custom_site_id,lon,lat\na,500,38\n", "sitemesh.csv").unwrap_err();
        assert_eq!((e.line, e.column.as_deref()), (2, Some("lon")), "{e:?}");
        let sites = parse_sites("custom_site_id,lon,lat\na,21.7,38.2\n", "s").unwrap();
        let text = "event_id,custom_site_id,gmv_PGA,gmv_PGA\n0,a,0.1,0.2\n";
        let e = parse_fields(text, "gmf-data.csv", sites, vec![(0, 0)]).unwrap_err();
        assert!(
            e.message.contains("the same IM as column `gmv_PGA`"),
            "{e:?}"
        );
    }

    /// A time of 0 gave infinite rates, -1 negative ones, NaN and inf NaN
    /// and 0; half an event set, or none, is no job.
    #[test]
    fn a_job_without_a_time_to_divide_by_is_refused_by_its_key() {
        for t in ["0", "-1", "nan", "inf"] {
            let e = eff_years_of_job(&format!("investigation_time = {t}\n"), 1).unwrap_err();
            assert!(
                e.contains("investigation_time") && e.contains("positive"),
                "{t}: {e}"
            );
        }
        for n in ["0", "2.5", "-3"] {
            let job = format!("investigation_time = 50\nses_per_logic_tree_path = {n}\n");
            let e = eff_years_of_job(&job, 1).unwrap_err();
            assert!(e.contains("ses_per_logic_tree_path"), "{n}: {e}");
        }
        let job = "investigation_time = 50\nnumber_of_logic_tree_samples = 2.5\n";
        assert!(eff_years_of_job(job, 1)
            .unwrap_err()
            .contains("number_of_logic_tree_samples"));
    }
}
