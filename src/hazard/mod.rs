//! Seismic hazard curves in any IM of [`crate::im::Im`] (pure: text in,
//! curves out).
//!
//! Two formats:
//!
//! - **OpenQuake** hazard-curve CSV (`hazard_curve-<kind>-<IMT>_<id>.csv`):
//!   a first line `#,,,,,"generated_by='OpenQuake engine …', …, kind='mean',
//!   investigation_time=50.0, imt='PGA'"`, a header `lon,lat,depth,poe-<iml>,…`
//!   and one row per site. `poe` is the probability of exceedance of the IML
//!   within `investigation_time` years, so under the Poisson assumption the
//!   annual rate of exceedance is `λ = −ln(1 − poe) / T`. The IMT is `PGA`
//!   (g), `PGV` (cm/s), `SA(T)` (g) or `AvgSA` (g), OpenQuake's units.
//! - **Plain**: a header `<im>_<unit>,annual_rate` (`pga_g`, `pgv_cm_s`,
//!   `sa(1.0)_g`, `avgsa_g`, …) and one row per IML, one site; lines
//!   starting with `#` are comments (a first line is OpenQuake's only with
//!   its keys: `generated_by=`, `imt=`, `investigation_time=`, `kind=`).
//!
//! Refused, naming the line (and the column): an IMT this tool has no
//! capacities in, a
//! missing or non-positive `investigation_time`, a cell that is not a
//! number, a probability outside [0, 1], a negative rate, IMLs that do not
//! increase, a curve that rises with the IML.
//!
//! A curve keeps its points with a finite, positive rate: `poe = 1` at small
//! IMLs (an infinite rate) is common and those points are dropped from the
//! start; a rate of 0 ends the curve there (`ends_at`).

use std::fmt;

use crate::im::Im;

mod curve;
mod notes;
pub use curve::HazardCurve;
pub use notes::{levels_slip, plausibility, statistic_note, unit_slip};

/// A hazard file that cannot be used, and where.
#[derive(Debug, Clone, PartialEq)]
pub struct HazardError {
    /// 1-based line of the file, when the problem is on one line.
    pub line: Option<usize>,
    pub message: String,
}

impl fmt::Display for HazardError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(l) => write!(f, "line {l}: {}", self.message),
            None => f.write_str(&self.message),
        }
    }
}

impl std::error::Error for HazardError {}

fn err(line: usize, message: impl Into<String>) -> HazardError {
    HazardError {
        line: Some(line),
        message: message.into(),
    }
}

/// Parses either format (told apart by the first line).
pub fn parse(text: &str) -> Result<Vec<HazardCurve>, HazardError> {
    let first = text
        .lines()
        .next()
        .unwrap_or("")
        .trim_start_matches('\u{feff}');
    if openquake_meta(first) {
        parse_openquake(text)
    } else {
        parse_plain(text).map(|c| vec![c])
    }
}

/// Whether a file's first line is OpenQuake's metadata line (`#,,,,,
/// "generated_by=…, imt=…"`), not a plain CSV's comment (`# my site`).
fn openquake_meta(first: &str) -> bool {
    first.trim_start().starts_with('#')
        && ["generated_by", "imt", "investigation_time", "kind"]
            .iter()
            .any(|key| meta_value(first, key).is_some())
}

/// The `investigation_time` (years) of an OpenQuake hazard-curve file's
/// metadata line; `None` for a plain CSV.
pub fn investigation_time(text: &str) -> Option<f64> {
    let meta = text.lines().next()?;
    meta_value(meta, "investigation_time")?.parse().ok()
}

/// The value of `key=…` (or `key = …`) in OpenQuake's metadata line,
/// quotes stripped; `key` as a whole word.
fn meta_value<'a>(line: &'a str, key: &str) -> Option<&'a str> {
    let word = |c: char| c.is_alphanumeric() || c == '_';
    let mut from = 0;
    while let Some(i) = line[from..].find(key) {
        let at = from + i;
        from = at + key.len();
        if line[..at].chars().next_back().is_some_and(word) {
            continue;
        }
        let Some(rest) = line[from..].trim_start().strip_prefix('=') else {
            continue;
        };
        let rest = rest.trim_start();
        let (quoted, rest) = match rest.strip_prefix('\'') {
            Some(r) => (true, r),
            None => (false, rest),
        };
        let end = if quoted {
            rest.find('\'').unwrap_or(rest.len())
        } else {
            rest.find([',', '"']).unwrap_or(rest.len())
        };
        return Some(rest[..end].trim());
    }
    None
}

/// Splits a CSV line; a cell's surrounding double quotes (as spreadsheets
/// write headers) are dropped. Cells hold no commas in these files.
fn cells(line: &str) -> Vec<&str> {
    line.split(',')
        .map(|c| c.trim().trim_matches('"').trim())
        .collect()
}

fn number(line: usize, column: &str, cell: &str) -> Result<f64, HazardError> {
    match cell.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(err(
            line,
            format!("column `{column}`: `{cell}` is not a number"),
        )),
    }
}

/// OpenQuake's hazard-curve CSV: every site of the file.
pub fn parse_openquake(text: &str) -> Result<Vec<HazardCurve>, HazardError> {
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l));
    let (_, meta) = lines.next().ok_or_else(|| err(1, "the file is empty"))?;
    let imt = meta_value(meta, "imt").ok_or_else(|| {
        err(
            1,
            format!(
                "no `imt=` in the metadata line; expected the IMT of a hazard curve: {}",
                Im::listed(Im::hazard, true)
            ),
        )
    })?;
    let im = match imt.parse::<Im>() {
        Ok(im) if im.hazard() => im,
        _ => {
            return Err(err(
                1,
                format!(
                    "imt = '{imt}': this tool's hazard curves are in {}; give the hazard curves of one of them (hazard_curve-…-PGA_….csv)",
                    Im::listed(Im::hazard, true)
                ),
            ))
        }
    };
    let t = meta_value(meta, "investigation_time")
        .ok_or_else(|| {
            err(
                1,
                "no `investigation_time=` in the metadata line: the probabilities of exceedance cannot be turned into rates",
            )
        })?
        .parse::<f64>()
        .ok()
        .filter(|t| *t > 0.0 && t.is_finite())
        .ok_or_else(|| err(1, "investigation_time is not a positive number of years"))?;
    let kind = meta_value(meta, "kind").map(str::to_string);
    let (header_line, header) = lines
        .find(|(_, l)| !l.trim().is_empty())
        .ok_or_else(|| err(2, "no header line `lon,lat,depth,poe-<iml>,…`"))?;
    let header = cells(header);
    let col = |name: &str| header.iter().position(|h| *h == name);
    once_each(header_line, &header)?;
    let (lon_c, lat_c) = (col("lon"), col("lat"));
    let imls = header_imls(header_line, &header)?;
    let mut sites = Vec::new();
    let mut located = Located::new();
    for (line, row) in lines {
        if row.trim().is_empty() {
            continue;
        }
        let cells = cells(row);
        if cells.len() != header.len() {
            return Err(err(
                line,
                format!("{} cells, but the header has {}", cells.len(), header.len()),
            ));
        }
        let mut points = Vec::with_capacity(imls.len());
        for &(i, iml) in &imls {
            let poe = number(line, header[i], cells[i])?;
            if !(0.0..=1.0).contains(&poe) {
                return Err(err(
                    line,
                    format!(
                        "column `{}`: probability of exceedance {poe} is outside [0, 1]",
                        header[i]
                    ),
                ));
            }
            points.push((iml, -(-poe).ln_1p() / t));
        }
        let mut curve = curve_of(
            im,
            &points,
            |_| line,
            |k| format!("column `{}`", header[imls[k].0]),
        )?;
        let coordinate =
            |c: Option<usize>, name: &str| c.map(|c| coordinate(line, name, cells[c])).transpose();
        curve.lon = coordinate(lon_c, "lon")?;
        curve.lat = coordinate(lat_c, "lat")?;
        curve.kind = kind.clone();
        new_site(line, &mut located, sites.len(), &curve)?;
        sites.push(curve);
    }
    if sites.is_empty() {
        return Err(err(header_line, "no site rows after the header"));
    }
    Ok(sites)
}

/// An OpenQuake hazard-curve file (one [`parse_openquake`] takes) as
/// OpenQuake's own `hazard_curves_csv` input reads it: its metadata line,
/// then `lon,lat,depth,poe-…` and each site's cells as the file writes
/// them. That reader takes the columns after the third as the poes, so a
/// column it does not read (the `custom_site_id` that OpenQuake's own
/// exports lead with) is dropped, and a missing depth is written as 0.
/// `None` where the file has no `lon`, `lat` or `poe-` columns.
pub fn openquake_input(text: &str) -> Option<String> {
    let mut lines = text.lines().filter(|l| !l.trim().is_empty());
    let meta = lines.next()?;
    let header = cells(lines.next()?);
    let col = |name: &str| header.iter().position(|h| *h == name);
    let (lon, lat, depth) = (col("lon")?, col("lat")?, col("depth"));
    let poes: Vec<usize> = (0..header.len())
        .filter(|&i| header[i].starts_with("poe-"))
        .collect();
    if poes.is_empty() {
        return None;
    }
    let row = |c: &[&str], no_depth: &str| {
        let mut out = vec![c[lon], c[lat], depth.map_or(no_depth, |d| c[d])];
        out.extend(poes.iter().map(|&i| c[i]));
        out.join(",")
    };
    let mut out = format!("{meta}\n{}\n", row(&header, "depth"));
    for line in lines {
        let c = cells(line);
        if c.len() != header.len() {
            return None;
        }
        out.push_str(&row(&c, "0.0"));
        out.push('\n');
    }
    Some(out)
}

/// A header's columns, each once: of a column given twice the first was
/// read, the second passed over.
fn once_each(line: usize, header: &[&str]) -> Result<(), HazardError> {
    let mut seen = std::collections::HashSet::new();
    match header.iter().find(|h| !seen.insert(**h)) {
        Some(h) => Err(err(line, format!("column `{h}` is given twice"))),
        None => Ok(()),
    }
}

/// The sites read so far by their lon and lat (bits, −0 as 0), to the
/// first site's index.
type Located = std::collections::HashMap<(Option<u64>, Option<u64>), usize>;

/// One curve a site: a second at the same lon and lat would be counted as
/// another site. `located` holds the sites before it, `index` is its own.
fn new_site(
    line: usize,
    located: &mut Located,
    index: usize,
    curve: &HazardCurve,
) -> Result<(), HazardError> {
    let here = (curve.lon, curve.lat);
    let bits = |c: Option<f64>| c.map(|x| (x + 0.0).to_bits());
    let first = *located.entry((bits(here.0), bits(here.1))).or_insert(index);
    match (first != index).then_some(first) {
        Some(k) if here.0.is_some() => Err(err(
            line,
            format!(
                "the site at lon {}, lat {} is given twice (site {k} is there already)",
                here.0.unwrap_or(f64::NAN),
                here.1.unwrap_or(f64::NAN)
            ),
        )),
        _ => Ok(()),
    }
}

/// The `poe-<iml>` columns of an OpenQuake header: (column, IML), the IMLs
/// positive and increasing.
fn header_imls(header_line: usize, header: &[&str]) -> Result<Vec<(usize, f64)>, HazardError> {
    let mut imls: Vec<(usize, f64)> = Vec::new();
    for (i, h) in header.iter().enumerate() {
        if let Some(v) = h.strip_prefix("poe-") {
            let iml = number(header_line, h, v)?;
            if iml <= 0.0 {
                return Err(err(
                    header_line,
                    format!("column `{h}`: the IML {iml} must be positive"),
                ));
            }
            imls.push((i, iml));
        }
    }
    if imls.is_empty() {
        return Err(err(header_line, "no `poe-<iml>` columns"));
    }
    if let Some(w) = imls.windows(2).find(|w| w[1].1 <= w[0].1) {
        return Err(err(
            header_line,
            format!(
                "the IMLs must increase: poe-{} follows poe-{}",
                w[1].1, w[0].1
            ),
        ));
    }
    Ok(imls)
}

/// A site's longitude or latitude (degrees), within ±`limit`.
fn coordinate(line: usize, name: &str, cell: &str) -> Result<f64, HazardError> {
    let v = number(line, name, cell)?;
    match off_the_globe(name, v) {
        None => Ok(v),
        Some(why) => Err(err(line, why)),
    }
}

/// Why `v` in column `name` (`lon`, within ±180°, or `lat`, ±90°) places
/// no site on the globe; `None` where it does. The one rule of every file
/// that places sites (hazard curves, OpenQuake's site mesh).
pub fn off_the_globe(name: &str, v: f64) -> Option<String> {
    let limit = if name == "lat" { 90.0 } else { 180.0 };
    (v.is_nan() || v.abs() > limit)
        .then(|| format!("column `{name}`: {v}° is not a {name} (it lies within ±{limit}°)"))
}

/// The IM of a plain file's first header cell: its key (`pga_g`,
/// `pgv_cm_s`, `sa(1.0)_g`, [`Im::key`]), for an IM a hazard may be in.
fn plain_im(cell: &str) -> Option<Im> {
    Im::from_key(cell).filter(|im| im.hazard())
}

/// The first columns a plain file may have, for messages: `pga_g`,
/// `pgv_cm_s`, `avgsa_g`, `sa(T)_g`.
fn hazard_columns() -> String {
    Im::kinds()
        .into_iter()
        .filter(|im| im.hazard())
        .map(|im| match im {
            Im::Sa(_) => "`sa(T)_g`".to_string(),
            im => format!("`{}`", im.key()),
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// A plain `<im>_<unit>,annual_rate` file: one site.
pub fn parse_plain(text: &str) -> Result<HazardCurve, HazardError> {
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l))
        .filter(|(_, l)| {
            let l = l.trim().trim_start_matches('\u{feff}');
            !l.is_empty() && !l.starts_with('#')
        });
    let (hl, header) = lines.next().ok_or_else(|| err(1, "the file is empty"))?;
    let header = cells(header.trim_start_matches('\u{feff}'));
    let im = match header[..] {
        [first, "annual_rate"] => plain_im(first),
        _ => None,
    };
    let Some(im) = im else {
        return Err(err(
            hl,
            format!(
                "header `{}`: expected `pga_g,annual_rate` (or another IM's column first: {}; or an OpenQuake hazard-curve file)",
                header.join(","),
                hazard_columns()
            ),
        ));
    };
    let column = header[0].to_string();
    let mut points = Vec::new();
    let mut line_of = Vec::new();
    for (line, row) in lines {
        let c = cells(row);
        if c.len() != 2 {
            return Err(err(line, format!("{} cells, expected 2", c.len())));
        }
        let (iml, rate) = (
            number(line, &column, c[0])?,
            number(line, "annual_rate", c[1])?,
        );
        if iml <= 0.0 {
            return Err(err(line, format!("{column} = {iml} must be positive")));
        }
        if rate < 0.0 {
            return Err(err(
                line,
                format!("annual_rate = {rate} must not be negative"),
            ));
        }
        if let Some(&(prev, _)) = points.last() {
            if iml <= prev {
                return Err(err(
                    line,
                    format!("{column} must increase: {iml} follows {prev}"),
                ));
            }
        }
        points.push((iml, rate));
        line_of.push(line);
    }
    if points.is_empty() {
        return Err(err(hl, "no rows after the header"));
    }
    curve_of(
        im,
        &points,
        |k| line_of[k],
        |_| "column `annual_rate`".to_string(),
    )
}

/// One site's curve from its levels (in `im`'s unit) and annual rates of
/// exceedance, checked as a plain file's rows are (positive, increasing
/// levels; finite rates, not negative, never rising); a problem names the
/// point (from 1) where a file would name the line.
pub fn from_arrays(im: Im, levels: &[f64], rates: &[f64]) -> Result<HazardCurve, HazardError> {
    if !im.hazard() {
        return Err(HazardError {
            line: None,
            message: format!(
                "a hazard curve in {im}: this tool's hazard curves are in {}",
                Im::listed(Im::hazard, false)
            ),
        });
    }
    if levels.len() != rates.len() || levels.is_empty() {
        return Err(HazardError {
            line: None,
            message: format!(
                "{} levels and {} rates: give one annual rate for each level",
                levels.len(),
                rates.len()
            ),
        });
    }
    let point = |k: usize, m: String| HazardError {
        line: None,
        message: format!("point {}: {m}", k + 1),
    };
    for (k, (&iml, &rate)) in levels.iter().zip(rates).enumerate() {
        if !(iml > 0.0 && iml.is_finite()) {
            return Err(point(k, format!("level {iml} must be positive and finite")));
        }
        if !(rate >= 0.0 && rate.is_finite()) {
            return Err(point(
                k,
                format!("annual rate {rate} must be finite and not negative"),
            ));
        }
        if k > 0 && iml <= levels[k - 1] {
            return Err(point(
                k,
                format!("levels must increase: {iml} follows {}", levels[k - 1]),
            ));
        }
    }
    let points: Vec<(f64, f64)> = levels.iter().copied().zip(rates.iter().copied()).collect();
    // The points are not lines of a file: the message names the point.
    curve_of(im, &points, |k| k + 1, |k| format!("point {}", k + 1))
        .map_err(|e| HazardError { line: None, ..e })
}

/// A curve from (IML, rate) points in increasing IML: checks that the rate
/// never rises, drops infinite rates at the start, ends at the first zero.
/// `line_of(k)` and `name(k)` say where point k is, for messages.
fn curve_of(
    im: Im,
    points: &[(f64, f64)],
    line_of: impl Fn(usize) -> usize,
    name: impl Fn(usize) -> String,
) -> Result<HazardCurve, HazardError> {
    for (k, w) in points.windows(2).enumerate() {
        if w[1].1 > w[0].1 {
            return Err(err(
                line_of(k + 1),
                format!(
                    "{}: the hazard curve rises with the IML ({} at {} {unit} after {} at {} {unit}); a rate of exceedance cannot",
                    name(k + 1),
                    w[1].1,
                    w[1].0,
                    w[0].1,
                    w[0].0,
                    unit = im.unit()
                ),
            ));
        }
    }
    let dropped = points.iter().take_while(|p| p.1.is_infinite()).count();
    let mut curve = HazardCurve {
        im,
        lon: None,
        lat: None,
        iml: Vec::new(),
        annual_rate: Vec::new(),
        ends_at: None,
        infinite: points[..dropped].iter().map(|p| p.0).collect(),
        kind: None,
    };
    for &(iml, rate) in &points[dropped..] {
        if rate == 0.0 {
            curve.ends_at = Some(iml);
            break;
        }
        curve.iml.push(iml);
        curve.annual_rate.push(rate);
    }
    if curve.iml.is_empty() {
        return Err(err(
            line_of(0),
            "no IML with a finite, positive rate: every probability of exceedance is 1 or 0",
        ));
    }
    Ok(curve)
}

#[cfg(test)]
mod tests {
    use super::*;

    const OQ: &str = "#,,,,,\"generated_by='OpenQuake engine 3.16.0', start_date='2023-01-01T00:00:00', checksum=1, kind='mean', investigation_time=50.0, imt='PGA'\"\n\
lon,lat,depth,poe-0.01,poe-0.1,poe-0.5,poe-1.0\n\
23.7,37.9,0.0,1.0,0.5,0.05,0.0\n\
21.7,38.2,0.0,0.9,0.3,0.02,0.002\n";

    /// A site given twice was counted as two; a column given twice was
    /// read once, the other passed over.
    #[test]
    fn a_site_or_a_column_twice_is_refused() {
        let twice = format!("{OQ}23.7,37.9,0.0,0.9,0.4,0.01,0.0\n");
        let e = parse(&twice).unwrap_err();
        assert_eq!(e.line, Some(5), "{e}");
        assert!(e.message.contains("given twice (site 0"), "{e}");
        let e = parse(&OQ.replace("lon,lat,depth", "lon,lat,lon")).unwrap_err();
        assert!(e.message.contains("column `lon` is given twice"), "{e}");
    }

    /// A plain CSV with comment lines of its own (`# site A, from …`) was
    /// read as OpenQuake's and refused for a missing `imt=`; its comments
    /// are passed over, its lines still counted in the file's numbering.
    #[test]
    fn a_plain_csv_may_carry_comments() {
        let text = "# museum site, from the PSHA of 2024\npga_g,annual_rate\n# low\n0.1,0.01\n0.3,0.001\nx,1\n";
        let e = parse(text).unwrap_err();
        assert_eq!(e.line, Some(6), "{e}");
        let c = &parse(&text.replace("x,1\n", "")).unwrap()[0];
        assert_eq!(
            (c.iml.clone(), c.annual_rate.clone()),
            (vec![0.1, 0.3], vec![0.01, 0.001])
        );
        assert!(c.lon.is_none());
        // OpenQuake's line is told by its keys, wherever they are.
        let e = parse(&OQ.replace("imt='PGA'", "")).unwrap_err();
        assert!(e.message.contains("no `imt=`"), "{e}");
    }

    /// OpenQuake's own exports lead with `custom_site_id`, which its
    /// `hazard_curves_csv` reader takes for a poe (and fails on): the
    /// job's file keeps lon, lat, depth and the poes, as written.
    #[test]
    fn the_jobs_hazard_file_is_what_openquake_reads() {
        let own = OQ
            .replace("lon,lat,depth,", "custom_site_id,lon,lat,depth,")
            .replace("23.7,37.9,", "7zzyzgxf,23.7,37.9,")
            .replace("21.7,38.2,", "8abcdefg,21.7,38.2,");
        assert_eq!(openquake_input(&own).as_deref(), Some(OQ));
        let no_depth = OQ
            .replace(",depth", "")
            .replace(",0.0,1.0", ",1.0")
            .replace(",0.0,0.9", ",0.9");
        assert_eq!(openquake_input(&no_depth).as_deref(), Some(OQ));
        assert_eq!(parse(&openquake_input(&own).unwrap()), parse(OQ));
    }

    /// Risk integrates the curve it is given: a quantile's or a
    /// realisation's rate passed for the mean's without a word.
    #[test]
    fn a_curve_other_than_the_mean_is_named() {
        let note = |kind: &str| statistic_note(&parse(&OQ.replace("'mean'", kind)).unwrap()[0]);
        assert_eq!(note("'mean'"), None);
        let q = note("'quantile-0.975'").unwrap();
        assert!(
            q.starts_with("the hazard file is the 97.5 % quantile"),
            "{q}"
        );
        let r = note("'rlz-003'").unwrap();
        assert!(
            r.contains("one realisation of OpenQuake's logic tree (`rlz-003`)"),
            "{r}"
        );
        // A plain CSV states no statistic.
        let plain = parse("pga_g,annual_rate\n0.1,0.01\n0.3,0.001\n").unwrap();
        assert_eq!(statistic_note(&plain[0]), None);
    }

    #[test]
    fn openquake_probabilities_become_annual_rates() {
        let sites = parse(OQ).unwrap();
        assert_eq!(sites.len(), 2);
        let a = &sites[0];
        assert_eq!((a.lon, a.lat), (Some(23.7), Some(37.9)));
        // poe = 1 at 0.01 g is dropped; poe = 0 at 1 g ends the curve.
        assert_eq!(a.iml, vec![0.1, 0.5]);
        assert_eq!(a.infinite, [0.01]);
        assert_eq!(a.ends_at, Some(1.0));
        // λ = −ln(1 − poe)/T: poe 0.5 in 50 years is ln 2 / 50 per year.
        assert!((a.annual_rate[0] - 2f64.ln() / 50.0).abs() < 1e-15);
        let b = &sites[1];
        assert_eq!(b.iml.len(), 4);
        assert!((b.annual_rate[3] - -(0.998f64.ln()) / 50.0).abs() < 1e-18);
    }

    #[test]
    fn refusals_name_the_line_and_the_problem() {
        let cases = [
            (OQ.replace("imt='PGA'", "imt='CAV'"), 1, "imt = 'CAV'"),
            (OQ.replace("imt='PGA'", "imt='SA(-1)'"), 1, "imt = 'SA(-1)'"),
            (
                OQ.replace("investigation_time=50.0, ", ""),
                1,
                "investigation_time",
            ),
            (OQ.replace("0.9,0.3", "0.9,1.3"), 4, "outside [0, 1]"),
            (OQ.replace("0.9,0.3", "0.9,abc"), 4, "`abc` is not a number"),
            (
                OQ.replace("0.9,0.3,0.02", "0.9,0.3,0.4"),
                4,
                "rises with the IML",
            ),
            (
                OQ.replace("poe-0.5,poe-1.0", "poe-0.5,poe-0.4"),
                2,
                "must increase",
            ),
        ];
        for (text, line, what) in cases {
            let e = parse(&text).unwrap_err();
            assert_eq!(e.line, Some(line), "{what}: {e}");
            assert!(e.to_string().contains(what), "{e}");
        }
        let e = parse("pga_g,annual_rate\n0.1,0.01\n0.2,0.02\n").unwrap_err();
        assert_eq!(e.line, Some(3), "{e}");
        assert!(e.message.contains("rises"), "{e}");
        let e = parse("pga,rate\n0.1,0.01\n").unwrap_err();
        assert_eq!(e.line, Some(1));
        // An SA's period as a user writes it: `sa(1)`, `SA(0.30)`.
        for header in ["sa(1)_g", "SA(1.0)_g", "sa(1.00)_G"] {
            let c = parse(&format!("{header},annual_rate\n0.1,0.01\n0.2,0.002\n")).unwrap();
            assert_eq!(c[0].im, Im::Sa(1.0), "{header}");
        }
        assert!(parse("sa(1)_cm,annual_rate\n0.1,0.01\n").is_err());
        let e = parse("pga_g,annual_rate\n0.1,x\n").unwrap_err();
        assert_eq!(e.line, Some(2));
    }

    /// The IMs OpenQuake writes and the plain headers of each, in their units.
    #[test]
    fn hazard_in_pgv_sa_and_avgsa() {
        for (imt, im) in [
            ("PGV", Im::Pgv),
            ("SA(1.0)", Im::Sa(1.0)),
            ("SA(0.3)", Im::Sa(0.3)),
            ("AvgSA", Im::AvgSa),
        ] {
            let curves = parse(&OQ.replace("imt='PGA'", &format!("imt='{imt}'"))).unwrap();
            assert!(curves.iter().all(|c| c.im == im), "{imt}");
        }
        for (header, im) in [
            ("pga_g", Im::Pga),
            ("pgv_cm_s", Im::Pgv),
            ("sa(1.0)_g", Im::Sa(1.0)),
            ("avgsa_g", Im::AvgSa),
        ] {
            let c = parse(&format!("{header},annual_rate\n1,0.01\n2,0.001\n")).unwrap();
            assert_eq!(c[0].im, im, "{header}");
        }
        // A unit that is not the IM's is refused, naming the header.
        let e = parse("pgv_g,annual_rate\n1,0.01\n").unwrap_err();
        assert!(e.to_string().contains("header `pgv_g,annual_rate`"), "{e}");
    }
}
