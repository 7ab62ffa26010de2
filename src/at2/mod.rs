//! Reader for PEER AT2 ground-motion files (pure: bytes in, samples out).
//!
//! An AT2 file is four header lines followed by the acceleration samples:
//!
//! ```text
//! line 1  free text (database, processing)
//! line 2  free text (event, station, component)
//! line 3  units line: must say acceleration in units of g
//! line 4  NPTS and DT, in one of two layouts:
//!           NPTS=   2999, DT=   .0100 SEC[, trailing text]   ("keyed": NGA-West2, PEER/CDMG)
//!           2999    0.0100    NPTS, DT                        ("positional": old NGA)
//! line 5… the NPTS values, any number per line, whitespace separated
//! ```
//!
//! Numbers may lack a leading zero (`-.2483657E-03`) and may use a Fortran `D`
//! exponent; line endings may be LF or CRLF; the last line may be short.
//! Every decimal in the file maps to the nearest double, exactly as any
//! other correct reader would: the usual samples by an exact fast path
//! ([`crate::decimal`]), anything else by Rust's correctly rounded `f64`
//! parser.
//!
//! Refused, with the 1-based line number: an empty file, fewer than four
//! header lines, a units line that is not acceleration in g (PEER puts velocity
//! `.VT2` and displacement `.DT2` files of the same layout beside the `.AT2`
//! files), a missing or unreadable NPTS or DT, NPTS = 0, DT ≤ 0, a token that is
//! not a number, NaN or infinity, and fewer or more values than NPTS.
//!
//! This module does no I/O: the caller reads the file and adds its path to
//! the error.

use crate::decimal::decimal_prefix;
pub use crate::motion::{MAX_ACCEL_G, MAX_DT_S, MIN_DT_S};

mod error;
use error::err;
pub use error::{At2Error, At2ErrorKind, HEADER_LINES};

/// Layout of the NPTS/DT line (line 4).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HeaderLayout {
    /// `NPTS=   2999, DT=   .0100 SEC` (NGA-West2 and PEER/CDMG downloads).
    Keyed,
    /// `  2999    0.0100    NPTS, DT` (old NGA flatfile downloads).
    Positional,
}

impl HeaderLayout {
    /// Name stored in the records table.
    pub fn as_str(self) -> &'static str {
        match self {
            HeaderLayout::Keyed => "keyed",
            HeaderLayout::Positional => "positional",
        }
    }
}

/// A parsed AT2 file.
#[derive(Debug, Clone, PartialEq)]
pub struct At2 {
    /// The four header lines, without line terminators or trailing blanks.
    pub header: [String; HEADER_LINES],
    pub layout: HeaderLayout,
    /// Time step (s), > 0.
    pub dt_s: f64,
    /// Ground acceleration samples in units of g; `accel_g.len()` is NPTS.
    pub accel_g: Vec<f64>,
}

/// Parses an AT2 file from its bytes. Non-UTF-8 bytes in the header (old
/// files carry Latin-1 station names) are replaced, not refused.
pub fn parse(bytes: &[u8]) -> Result<At2, At2Error> {
    // The strict check is the fast one for the usual (ASCII) file.
    match std::str::from_utf8(bytes) {
        Ok(text) => parse_str(text),
        Err(_) => parse_str(&String::from_utf8_lossy(bytes)),
    }
}

/// Parses an AT2 file from text; see [`parse`].
pub fn parse_str(text: &str) -> Result<At2, At2Error> {
    if text.trim().is_empty() {
        return Err(err(1, At2ErrorKind::Empty));
    }
    // Lines end at '\n'; the '\r' of CRLF files is trimmed with the blanks.
    let mut rest = text;
    let mut header: [String; HEADER_LINES] = Default::default();
    for (i, slot) in header.iter_mut().enumerate() {
        if rest.is_empty() {
            return Err(err(i, At2ErrorKind::ShortHeader { lines: i }));
        }
        let (line, next) = rest.split_once('\n').unwrap_or((rest, ""));
        *slot = line.trim_end().to_string();
        rest = next;
    }
    check_units(&header[2]).map_err(|kind| err(3, kind))?;
    let (npts, dt_s, layout) = parse_npts_dt(&header[3]).map_err(|kind| err(4, kind))?;
    // A DOS end-of-file mark (Ctrl-Z), and NUL padding, after the last
    // sample end the file.
    let rest = rest.trim_end_matches(|c: char| c == '\u{1a}' || c == '\0' || c.is_whitespace());
    let accel_g = parse_samples(rest, npts)?;
    check_motion(&accel_g, rest)?;
    Ok(At2 {
        header,
        layout,
        dt_s,
        accel_g,
    })
}

/// The length of the separator (white space other than '\n', or a comma)
/// starting at byte `i` of `text`, 0 if none.
#[inline]
fn separator_at(text: &str, i: usize) -> usize {
    match text.as_bytes()[i] {
        b' ' | b'\t' | b'\r' | b',' | b'\x0b' | b'\x0c' => 1,
        b if b < 0x80 || !text.is_char_boundary(i) => 0,
        _ => text[i..]
            .chars()
            .next()
            .filter(|c| c.is_whitespace())
            .map_or(0, char::len_utf8),
    }
}

/// More values than NPTS, found at `line_no`: blamed on the first decimal
/// comma if the samples hold one (a value `1,5E-04` among values separated
/// by spaces), which made the extra values, or else on `line_no`.
fn too_many(body: &str, line_no: usize, npts: usize) -> At2Error {
    let decimal_comma = |token: &&&str| crate::decimal::comma_between_digits(token);
    let found = body.split('\n').enumerate().find_map(|(k, line)| {
        let tokens: Vec<&str> = line.split_whitespace().collect();
        let token = tokens
            .iter()
            .filter(|_| tokens.len() >= 2)
            .find(decimal_comma)?;
        Some((HEADER_LINES + 1 + k, token.to_string()))
    });
    if let Some((line, token)) = found {
        return err(line, At2ErrorKind::DecimalComma { token, npts });
    }
    // The first token past the samples: text (`END OF DATA`, a Ctrl-Z, NUL
    // padding) is named as what follows them, not as more values.
    let extra = body
        .split(|c: char| c.is_whitespace() || c == ',')
        .filter(|t| !t.is_empty())
        .nth(npts);
    match extra {
        Some(token) if parse_value(token).is_err() => {
            // The text to the end of its line (`END OF DATA`, not `END`).
            let at = token.as_ptr() as usize - body.as_ptr() as usize;
            let line = body[at..].lines().next().unwrap_or(token).trim_end();
            err(
                line_no,
                At2ErrorKind::AfterSamples {
                    token: line.to_string(),
                    npts,
                },
            )
        }
        _ => err(line_no, At2ErrorKind::TooManyValues { npts }),
    }
}

/// The samples after the header (`body` starts on line 5): exactly `npts`
/// tokens separated by blanks (any Unicode white space) or commas, any
/// number per line. A byte scan: the files are ASCII but for the rare
/// non-ASCII separator, which is decoded where met.
fn parse_samples(body: &str, npts: usize) -> Result<Vec<f64>, At2Error> {
    let bytes = body.as_bytes();
    // Each value takes a byte and a separator: a header's NPTS (4e9, or
    // 2⁶¹) reserves no more than the file can hold.
    let mut accel_g = Vec::with_capacity(npts.min(bytes.len() / 2 + 1));
    let mut line_no = HEADER_LINES + 1;
    let mut i = 0;
    while i < bytes.len() {
        let b = bytes[i];
        if b == b' ' {
            i += 1;
            continue;
        }
        if b == b'\n' {
            line_no += 1;
            i += 1;
            continue;
        }
        if let len @ 1.. = separator_at(body, i) {
            i += len;
            continue;
        }
        // The usual token, read in the one pass that finds its end: the
        // same value `parse_value` gives it (`exact_decimal`'s arithmetic).
        if let Some((value, len)) = decimal_prefix(&bytes[i..]) {
            if bytes.get(i + len).is_none_or(|&b| {
                matches!(b, b'\n' | b' ' | b'\t' | b'\r' | b',' | b'\x0b' | b'\x0c')
            }) {
                if accel_g.len() == npts {
                    return Err(too_many(body, line_no, npts));
                }
                accel_g.push(value);
                i += len;
                continue;
            }
        }
        let start = i;
        i += 1;
        while i < bytes.len() {
            let b = bytes[i];
            // Printable ASCII but the comma: inside the token, the common case.
            if b > b' ' && b != b',' && b < 0x7f {
                i += 1;
            } else if b == b'\n' || separator_at(body, i) > 0 {
                break;
            } else {
                i += 1;
            }
        }
        if accel_g.len() == npts {
            return Err(too_many(body, line_no, npts));
        }
        // Separators are whole characters, so the token is too.
        accel_g.push(parse_value(&body[start..i]).map_err(|kind| err(line_no, kind))?);
    }
    if accel_g.len() < npts {
        // The last line there is (a final '\n' ends it; it starts none).
        let last_line = if body.is_empty() {
            HEADER_LINES
        } else {
            line_no - usize::from(body.ends_with('\n'))
        };
        return Err(err(
            last_line,
            At2ErrorKind::TooFewValues {
                npts,
                found: accel_g.len(),
            },
        ));
    }
    Ok(accel_g)
}

/// Parses one sample: a finite decimal, `D` accepted as exponent marker.
fn parse_value(token: &str) -> Result<f64, At2ErrorKind> {
    match crate::decimal::read_number(token) {
        // Rust also accepts "inf", "NaN" and overflowing exponents: refuse those.
        Some(v) if v.is_finite() => Ok(v),
        Some(_) => Err(At2ErrorKind::NotFinite {
            token: token.to_string(),
        }),
        None => Err(At2ErrorKind::NotANumber {
            token: token.to_string(),
        }),
    }
}

/// Line 3 must describe acceleration in units of g and nothing else.
fn check_units(line: &str) -> Result<(), At2ErrorKind> {
    let upper = line.to_ascii_uppercase();
    let words: Vec<&str> = upper
        .split(|c: char| !(c.is_ascii_alphanumeric() || c == '/' || c == '*' || c == '^'))
        .filter(|w| !w.is_empty())
        .collect();
    let refused = || At2ErrorKind::NotAcceleration {
        units_line: line.to_string(),
    };
    let mentions = |stem: &str| words.iter().any(|w| w.starts_with(stem));
    if !mentions("ACCEL") || mentions("VELOC") || mentions("DISPL") {
        return Err(refused());
    }
    // "… IN UNITS OF G": the word after "UNITS OF" is the unit.
    let unit = words
        .windows(3)
        .find(|w| w[0] == "UNITS" && w[1] == "OF")
        .map(|w| w[2])
        .or_else(|| words.windows(2).find(|w| w[0] == "IN").map(|w| w[1]));
    match unit {
        Some("G") => Ok(()),
        _ => Err(refused()),
    }
}

/// A record's samples (read from `body`, the text after the header) as a
/// motion: two at least, not all 0, none past [`MAX_ACCEL_G`] (the first
/// such blamed on its line, with how many there are: one is a typo, many a
/// file in gal under a units line of g).
fn check_motion(accel_g: &[f64], body: &str) -> Result<(), At2Error> {
    if accel_g.len() < 2 {
        return Err(err(4, At2ErrorKind::OneSample));
    }
    let beyond = |a: &f64| a.abs() > MAX_ACCEL_G;
    if let Some(i) = accel_g.iter().position(beyond) {
        let kind = At2ErrorKind::Implausible {
            index: i + 1,
            value: accel_g[i],
            past: accel_g.iter().filter(|a| beyond(a)).count(),
            of: accel_g.len(),
        };
        return Err(err(line_of_sample(body, i), kind));
    }
    if accel_g.iter().all(|&a| a == 0.0) {
        return Err(err(HEADER_LINES + 1, At2ErrorKind::NoMotion));
    }
    Ok(())
}

/// The file's line of the `i`-th sample (from 0) of `body`, which starts
/// on the line after the header; separators as [`parse_samples`] reads them.
fn line_of_sample(body: &str, i: usize) -> usize {
    let mut seen = 0;
    for (k, line) in body.split('\n').enumerate() {
        seen += line
            .split(|c: char| c.is_whitespace() || c == ',')
            .filter(|t| !t.is_empty())
            .count();
        if seen > i {
            return HEADER_LINES + 1 + k;
        }
    }
    HEADER_LINES + 1
}

/// Line 4: NPTS and DT in the keyed or positional layout.
fn parse_npts_dt(line: &str) -> Result<(usize, f64, HeaderLayout), At2ErrorKind> {
    let upper = line.to_ascii_uppercase();
    let (npts_tok, dt_tok, layout) = if upper.contains('=') {
        let (npts, _) = keyed_value(&upper, "NPTS").ok_or_else(|| At2ErrorKind::MissingNpts {
            text: line.to_string(),
        })?;
        let (dt, after) = keyed_value(&upper, "DT").ok_or_else(|| At2ErrorKind::MissingDt {
            text: line.to_string(),
        })?;
        // `DT= 1,5 SEC` is a decimal comma, not DT = 1 then more text.
        if after.starts_with(',') && after[1..].starts_with(|c: char| c.is_ascii_digit()) {
            let digits = after[1..].split(|c: char| !c.is_ascii_digit()).next();
            return Err(At2ErrorKind::DtComma {
                token: format!("{dt},{}", digits.unwrap_or_default()),
            });
        }
        // The unit word after DT's value, if any ("SEC"; "MSEC" is ms).
        if let Some(unit) = unit_word(after) {
            if !matches!(unit, "SEC" | "S" | "SECS" | "SECONDS" | "SECOND") {
                return Err(At2ErrorKind::DtUnit {
                    unit: unit.to_string(),
                });
            }
        }
        (npts, dt, HeaderLayout::Keyed)
    } else {
        let npts_at = word_at(&upper, "NPTS").ok_or_else(|| At2ErrorKind::MissingNpts {
            text: line.to_string(),
        })?;
        let dt_at = word_at(&upper, "DT").ok_or_else(|| At2ErrorKind::MissingDt {
            text: line.to_string(),
        })?;
        let numbers: Vec<&str> = upper[..npts_at.min(dt_at)]
            .split(|c: char| c.is_whitespace() || c == ',')
            .filter(|t| !t.is_empty())
            .collect();
        if numbers.len() != 2 {
            return Err(if npts_at < dt_at {
                At2ErrorKind::MissingNpts {
                    text: line.to_string(),
                }
            } else {
                At2ErrorKind::MissingDt {
                    text: line.to_string(),
                }
            });
        }
        // The labels give the order of the two numbers.
        let (npts, dt) = if npts_at < dt_at {
            (numbers[0], numbers[1])
        } else {
            (numbers[1], numbers[0])
        };
        (npts, dt, HeaderLayout::Positional)
    };
    let npts = match npts_tok.parse::<usize>() {
        Ok(n) if n > 0 => n,
        _ => {
            return Err(At2ErrorKind::BadNpts {
                token: npts_tok.to_string(),
            })
        }
    };
    // A unit glued to the number ("0.01SEC") is not part of it; "MSEC" is
    // another unit, refused.
    if let Some(unit) = ["MSEC", "MS"].into_iter().find(|u| dt_tok.ends_with(u)) {
        return Err(At2ErrorKind::DtUnit {
            unit: unit.to_string(),
        });
    }
    let dt_num = dt_tok
        .strip_suffix("SEC")
        .or_else(|| dt_tok.strip_suffix('S'))
        .unwrap_or(dt_tok);
    let dt = match parse_value(dt_num) {
        Ok(v) => v,
        Err(_) => {
            return Err(At2ErrorKind::BadDt {
                token: dt_tok.to_string(),
            })
        }
    };
    if dt <= 0.0 {
        return Err(At2ErrorKind::NonPositiveDt { dt });
    }
    if !dt.is_finite() || (dt > MAX_DT_S && !crate::motion::dt_accepted(dt)) {
        return Err(At2ErrorKind::CoarseDt { dt });
    }
    if !crate::motion::dt_accepted(dt) {
        return Err(At2ErrorKind::FineDt { dt });
    }
    Ok((npts, dt, layout))
}

/// The word that opens `after`, the text after a keyed value (its unit, as
/// in `DT=   .0100 SEC`), if one does before a comma.
fn unit_word(after: &str) -> Option<&str> {
    let word = after
        .trim_start()
        .split(|c: char| c.is_whitespace() || c == ',' || c == ';')
        .next()?;
    (!word.is_empty() && word.chars().all(|c| c.is_ascii_alphabetic())).then_some(word)
}

/// Byte offset of `word` standing alone (not inside a longer word).
fn word_at(upper: &str, word: &str) -> Option<usize> {
    upper.match_indices(word).map(|(i, _)| i).find(|&i| {
        let before = upper[..i].chars().next_back();
        let after = upper[i + word.len()..].chars().next();
        !before.is_some_and(|c| c.is_ascii_alphanumeric())
            && !after.is_some_and(|c| c.is_ascii_alphanumeric())
    })
}

/// The token after `KEY =`, up to the next blank, comma or semicolon, and
/// the text after it.
fn keyed_value<'a>(upper: &'a str, key: &str) -> Option<(&'a str, &'a str)> {
    upper.match_indices(key).find_map(|(i, _)| {
        if upper[..i]
            .chars()
            .next_back()
            .is_some_and(|c| c.is_ascii_alphanumeric())
        {
            return None;
        }
        let rest = upper[i + key.len()..].trim_start();
        let rest = rest.strip_prefix('=')?.trim_start();
        let end = rest
            .find(|c: char| c.is_whitespace() || c == ',' || c == ';')
            .unwrap_or(rest.len());
        let (value, after) = rest.split_at(end);
        (!value.is_empty() && value != "SEC").then_some((value, after))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const TITLE: &str =
        "PEER NGA STRONG MOTION DATABASE RECORD\nNORTHRIDGE 01/17/94, BEVERLY HILLS, 009\n";
    const UNITS: &str = "ACCELERATION TIME SERIES IN UNITS OF G\n";

    fn file(npts_line: &str, body: &str) -> String {
        format!("{TITLE}{UNITS}{npts_line}\n{body}")
    }

    fn npts_dt(npts_line: &str) -> Result<(usize, f64, HeaderLayout), At2ErrorKind> {
        parse_npts_dt(npts_line)
    }

    #[test]
    fn npts_dt_layouts_seen_in_real_downloads() {
        use HeaderLayout::*;
        let cases = [
            (
                "NPTS=   2999, DT=   .0100 SEC,   0 POLE @    30.00000 HZ,  -5 POLE @      .12000",
                (2999, 0.01, Keyed),
            ),
            ("NPTS=   2676, DT=   .0200 SEC   ", (2676, 0.02, Keyed)),
            ("NPTS=   4531, DT=  0.01000 SEC", (4531, 0.01, Keyed)),
            ("NPTS=   4531, DT=  0.00500 SEC,", (4531, 0.005, Keyed)),
            ("NPTS=  1800, DT= .02000 SEC", (1800, 0.02, Keyed)),
            ("  2999    0.0100    NPTS, DT", (2999, 0.01, Positional)),
            ("npts=100,dt=0.005sec", (100, 0.005, Keyed)),
            ("  0.0050  16000  DT, NPTS", (16000, 0.005, Positional)),
        ];
        for (line, want) in cases {
            assert_eq!(npts_dt(line), Ok(want), "{line}");
        }
    }

    /// A header claiming billions of samples is read as any short file:
    /// refused for the values it lacks (4e9 reserved 32 GB first, and
    /// aborted; 2⁶¹ overflowed the reservation and panicked).
    #[test]
    fn a_huge_npts_is_refused_for_the_values_the_file_lacks() {
        for npts in ["4000000000", "2305843009213693952", "18446744073709551615"] {
            let text = file(&format!("NPTS= {npts}, DT= .0100 SEC"), "0.1 0.2\n");
            let e = parse_str(&text).unwrap_err();
            assert!(
                matches!(e.kind, At2ErrorKind::TooFewValues { found: 2, .. }),
                "{npts}: {e}"
            );
        }
    }

    #[test]
    fn npts_dt_refusals() {
        assert!(matches!(
            npts_dt("DT= .01 SEC"),
            Err(At2ErrorKind::MissingNpts { .. })
        ));
        assert!(matches!(
            npts_dt("NPTS= 100"),
            Err(At2ErrorKind::MissingDt { .. })
        ));
        assert!(matches!(
            npts_dt("NPTS= 1x0, DT=.01"),
            Err(At2ErrorKind::BadNpts { .. })
        ));
        assert!(matches!(
            npts_dt("NPTS= 0, DT=.01"),
            Err(At2ErrorKind::BadNpts { .. })
        ));
        assert!(matches!(
            npts_dt("NPTS= -5, DT=.01"),
            Err(At2ErrorKind::BadNpts { .. })
        ));
        assert!(matches!(
            npts_dt("NPTS= 10, DT= SEC"),
            Err(At2ErrorKind::MissingDt { .. })
        ));
        assert!(matches!(
            npts_dt("NPTS= 10, DT=0"),
            Err(At2ErrorKind::NonPositiveDt { .. })
        ));
        // A header in µs or wrong: 1e-300 s was taken, and printed as a
        // 300-digit decimal.
        for fine in ["1e-300", "0.000001"] {
            let e = npts_dt(&format!("NPTS= 10, DT={fine}")).unwrap_err();
            assert!(matches!(e, At2ErrorKind::FineDt { .. }), "{fine}");
        }
        assert_eq!(
            At2ErrorKind::FineDt { dt: 1e-300 }.to_string(),
            "DT = 1e-300 s: an accelerogram is sampled every 0.001–0.05 s; below 1e-5 s the \
             header's time step is wrong"
        );
        assert!(npts_dt("NPTS= 10, DT=0.00001").is_ok());
        // A decimal comma read DT = 1 s and gave PGV 100 times too large.
        for comma in ["NPTS= 20, DT= 1,5 SEC", "NPTS= 20, DT= 0,01 SEC"] {
            let e = npts_dt(comma).unwrap_err();
            assert!(matches!(e, At2ErrorKind::DtComma { .. }), "{comma}: {e}");
            assert!(e.to_string().contains("decimal comma"), "{e}");
        }
        // The trailing text after a comma is no decimal (`DT= .01 SEC,`).
        assert!(npts_dt("NPTS= 20, DT= .01, 0 POLE").is_ok());
        // A step of 0.2 s or 1 s misses the shaking; 0.1 s is the last taken.
        assert!(npts_dt("NPTS= 20, DT= 0.1 SEC").is_ok());
        for coarse in ["0.2", "1"] {
            let e = npts_dt(&format!("NPTS= 20, DT= {coarse} SEC")).unwrap_err();
            assert!(matches!(e, At2ErrorKind::CoarseDt { .. }), "{coarse}");
        }
        assert!(matches!(
            npts_dt("NPTS= 10, DT=-.01"),
            Err(At2ErrorKind::NonPositiveDt { .. })
        ));
        assert!(matches!(
            npts_dt("2999 NPTS, DT"),
            Err(At2ErrorKind::MissingNpts { .. })
        ));
        assert!(matches!(
            npts_dt("2999 0.01"),
            Err(At2ErrorKind::MissingNpts { .. })
        ));
        // WIDTH= must not be read as DT=.
        assert!(matches!(
            npts_dt("NPTS= 10, WIDTH=3"),
            Err(At2ErrorKind::MissingDt { .. })
        ));
    }

    #[test]
    fn units_line() {
        for ok in [
            "ACCELERATION TIME SERIES IN UNITS OF G",
            "ACCELERATION TIME HISTORY IN UNITS OF G. FILTER POINTS: HP=0.07 Hz LP=23.0 Hz",
            "Acceleration in g",
        ] {
            assert_eq!(check_units(ok), Ok(()), "{ok}");
        }
        for bad in [
            "VELOCITY TIME HISTORY IN UNITS OF CM/SEC",
            "DISPLACEMENT TIME HISTORY IN UNITS OF CM",
            "ACCELERATION TIME SERIES IN UNITS OF CM/S/S",
            "ACCELERATION TIME SERIES IN UNITS OF M/S^2",
            "TIME SERIES IN UNITS OF G",
            "",
        ] {
            assert!(check_units(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn values_with_and_without_leading_zero_read_exactly() {
        let body = "  -.2483657E-03 -2.4836570E-04   .1000000E+01\r\n 1.5D-02\r\n";
        let at2 = parse_str(&file("NPTS=   4, DT=   .0100 SEC", body)).unwrap();
        // The same decimal written two ways is the same double.
        assert_eq!(at2.accel_g[0], at2.accel_g[1]);
        assert_eq!(at2.accel_g, vec![-2.483657e-4, -2.483657e-4, 1.0, 1.5e-2]);
        assert_eq!(at2.dt_s, 0.01);
    }

    #[test]
    fn crlf_short_last_line_and_any_count_per_line() {
        let text =
            "A\r\nB\r\nACCELERATION TIME HISTORY IN UNITS OF G\r\nNPTS=  7, DT= .02000 SEC\r\n\
                    1 2 3 4 5\r\n6\r\n7\r\n\r\n";
        let at2 = parse_str(text).unwrap();
        assert_eq!(at2.accel_g, vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0]);
        assert_eq!(at2.header[0], "A");
        assert_eq!(at2.header[3], "NPTS=  7, DT= .02000 SEC");
    }

    #[test]
    fn errors_name_the_line() {
        let e = |text: &str| parse_str(text).unwrap_err();
        assert_eq!(e("").kind, At2ErrorKind::Empty);
        assert_eq!(e("  \n\n").kind, At2ErrorKind::Empty);
        assert_eq!(e("A\nB\n").kind, At2ErrorKind::ShortHeader { lines: 2 });

        let bad_token = e(&file("NPTS= 4, DT= .01 SEC", "1 2\n3 x4\n"));
        assert_eq!(bad_token.line, 6);
        assert_eq!(
            bad_token.kind,
            At2ErrorKind::NotANumber { token: "x4".into() }
        );

        for token in ["NaN", "inf", "-Infinity", "1e999"] {
            let e = e(&file("NPTS= 2, DT= .01 SEC", &format!("1\n{token}\n")));
            assert_eq!(e.line, 6);
            assert_eq!(
                e.kind,
                At2ErrorKind::NotFinite {
                    token: token.into()
                }
            );
        }

        let few = e(&file("NPTS= 5, DT= .01 SEC", "1 2\n3\n"));
        assert_eq!(few.kind, At2ErrorKind::TooFewValues { npts: 5, found: 3 });
        assert_eq!(few.line, 6);

        let many = e(&file("NPTS= 3, DT= .01 SEC", "1 2\n3\n\n4\n"));
        assert_eq!(many.kind, At2ErrorKind::TooManyValues { npts: 3 });
        assert_eq!(many.line, 8);

        // A decimal comma among values separated by spaces made two values
        // of one, and the count ran over at the file's end: the comma's
        // line is named. Values separated by commas are values.
        let body = "0.1 0.2 0.3\n0.4 1,5E-04 0.6\n0.7 0.8 0.9\n";
        let comma = e(&file("NPTS= 9, DT= .01 SEC", body));
        let token = "1,5E-04".to_string();
        assert_eq!(comma.kind, At2ErrorKind::DecimalComma { token, npts: 9 });
        assert_eq!(comma.line, 6);
        assert!(comma.to_string().contains("decimal point"), "{comma}");
        let listed = parse_str(&file("NPTS= 4, DT= .01 SEC", "0.1,0.2\n0.3, 0.4\n")).unwrap();
        assert_eq!(listed.accel_g, vec![0.1, 0.2, 0.3, 0.4]);
        let many = e(&file("NPTS= 3, DT= .01 SEC", "0.1,0.2\n0.3,0.4\n"));
        assert_eq!(many.kind, At2ErrorKind::TooManyValues { npts: 3 });

        // Text after the samples is named as such, not as more values; a
        // long binary run is shown by its start.
        let after = e(&file("NPTS= 3, DT= .01 SEC", "1 2 3\nEND OF DATA\n"));
        assert!(
            matches!(after.kind, At2ErrorKind::AfterSamples { npts: 3, .. }),
            "{after}"
        );
        let says = "NPTS = 3 samples with `END OF DATA`";
        assert!(after.to_string().contains(says), "{after}");
        // A DOS end-of-file mark, and NUL padding, end the file.
        for tail in ["\u{1a}", "\u{1a}\n", "\0\0\0"] {
            let text = file("NPTS= 3, DT= .01 SEC", &format!("1 2 3\n{tail}"));
            let at2 = parse_str(&text).unwrap_or_else(|e| panic!("{tail:?}: {e}"));
            assert_eq!(at2.accel_g, vec![1.0, 2.0, 3.0]);
        }
        let junk = "\u{1}".repeat(300);
        let binary = e(&file("NPTS= 3, DT= .01 SEC", &format!("1 2 3\n{junk}\n")));
        assert!(binary.to_string().len() < 400, "{binary}");
        assert!(binary.to_string().contains("…"), "{binary}");
        let vel = e("A\nB\nVELOCITY TIME HISTORY IN UNITS OF CM/SEC\nNPTS= 1, DT= .01 SEC\n1\n");
        assert_eq!(vel.line, 3);
        assert!(vel.to_string().contains(".VT2"));

        let no_dt = e(&file("NPTS= 3", "1 2 3\n"));
        assert_eq!(no_dt.line, 4);
    }

    #[test]
    fn header_only_file_has_too_few_values() {
        let e = parse_str(&file("NPTS= 3, DT= .01 SEC", "")).unwrap_err();
        assert_eq!(e.kind, At2ErrorKind::TooFewValues { npts: 3, found: 0 });
        assert_eq!(e.line, 4);
    }

    /// Rust's parser (correctly rounded) on a token, `D` read as `E`.
    fn reference(token: &str) -> Option<f64> {
        token.replace(['D', 'd'], "E").parse::<f64>().ok()
    }

    #[test]
    fn values_read_as_rusts_parser_reads_them_or_are_refused() {
        // Every sample of the bundled records, each the same double as
        // Rust's parser gives.
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("records");
        let mut files = 0;
        let mut dirs = vec![root];
        while let Some(dir) = dirs.pop() {
            for entry in std::fs::read_dir(&dir).unwrap() {
                let path = entry.unwrap().path();
                if path.is_dir() {
                    dirs.push(path);
                } else if path.extension().is_some_and(|e| e == "AT2") {
                    files += 1;
                    let text = std::fs::read_to_string(&path).unwrap();
                    for token in text
                        .lines()
                        .skip(HEADER_LINES)
                        .flat_map(str::split_whitespace)
                    {
                        let want = reference(token).unwrap();
                        assert_eq!(parse_value(token).unwrap().to_bits(), want.to_bits());
                    }
                }
            }
        }
        assert!(files >= 44, "{files} AT2 files");

        // Tokens the fast path declines: Rust's value where finite.
        let declined = [
            "9007199254740993",
            "1234567890123456789e-3",
            "1e23",
            "1e-23",
            "12345678901234567890",
            "0.00000000000000000000001",
            "1e99999",
            "inf",
            "NaN",
        ];
        for t in declined {
            assert_eq!(
                parse_value(t).ok().map(f64::to_bits),
                reference(t).filter(|v| v.is_finite()).map(f64::to_bits),
                "{t}"
            );
        }
        // Malformed tokens: refused.
        let malformed = [
            "", ".", "-", "+", "e5", ".e5", "1e", "1e+", "1.2.3", "--1", "1e5x", "0x10", "1,0",
            "1e5.0", "1 ", "1d", "E", "+-1",
        ];
        for t in malformed {
            assert!(parse_value(t).is_err(), "{t}");
        }
    }

    /// The usual token is read in the pass that finds its end.
    /// Every form, in every place of a line and after every separator, reads
    /// as Rust's own parser reads the token alone (D as E), to the bit;
    /// forms the one pass declines (20 digits, a five-digit exponent, an
    /// exponent beyond ±22) take the general path to the same value.
    #[test]
    fn samples_read_in_one_pass_equal_each_token_read_alone() {
        let tokens = [
            "-.9269400E-05",
            ".1043030E-02",
            "+2.",
            "0.1",
            "-0",
            "7",
            "1.5D+03",
            "2.5d-3",
            "1e22",
            "1e23",
            "1.0E+0001",
            "1.0E00001",
            "9007199254740993",
            "12345678901234567890",
            "0.000000000000000000001",
            "-3.14159265358979",
        ];
        for sep in [
            " ", "  ", "\t", ",", " , ", "\x0b", "\x0c", "\u{a0}", "\u{2003}",
        ] {
            for end in ["", "\n", "\r\n", " \n"] {
                let body = format!(
                    "{}{end}",
                    tokens
                        .chunks(5)
                        .map(|line| line.join(sep))
                        .collect::<Vec<_>>()
                        .join("\r\n")
                );
                // The reader of samples alone: the tokens are numbers, not a
                // motion (1e22 g is refused as one).
                let got = parse_samples(&body, tokens.len()).unwrap();
                let want: Vec<u64> = tokens
                    .iter()
                    .map(|t| reference(t).unwrap().to_bits())
                    .collect();
                let got: Vec<u64> = got.iter().map(|v| v.to_bits()).collect();
                assert_eq!(got, want, "separator {sep:?}, end {end:?}");
            }
        }
        // A valid start followed by what no separator is: the whole token is
        // refused, on its line.
        for (body, token) in [("1 2 3.5x\n", "3.5x"), ("1\n2E5E\n3\n", "2E5E")] {
            let e = parse_str(&file("NPTS= 3, DT= .01 SEC", body)).unwrap_err();
            let line = 5 + body[..body.find(token).unwrap()].matches('\n').count();
            assert_eq!(
                (e.line, e.kind),
                (
                    line,
                    At2ErrorKind::NotANumber {
                        token: token.into()
                    }
                )
            );
        }
    }

    /// `DT= 0.5 MSEC` was read as 0.5 s, the word ignored: a record 1000×
    /// too slow. A unit other than seconds is refused; seconds in any
    /// spelling, or none, are read.
    #[test]
    fn a_time_step_in_another_unit_is_refused() {
        for line in [
            "NPTS= 3, DT= 0.5 MSEC",
            "NPTS= 3, DT= 5MSEC",
            "NPTS= 3, DT= 2 MS, X",
        ] {
            let e = parse_str(&file(line, "0.1 0.2 0.3\n")).unwrap_err();
            assert_eq!(e.line, 4, "{line}");
            assert!(matches!(e.kind, At2ErrorKind::DtUnit { .. }), "{line}: {e}");
            assert!(e.to_string().contains("in seconds (SEC)"), "{e}");
        }
        for line in [
            "NPTS= 3, DT= .01 SEC",
            "NPTS= 3, DT= .01 S",
            "NPTS= 3, DT=.01SEC",
            "NPTS= 3, DT= .01",
            "NPTS= 3, DT= .01 SEC,   0 POLE @ 30.0 HZ",
        ] {
            let a = parse_str(&file(line, "0.1 0.2 0.3\n")).unwrap();
            assert_eq!(a.dt_s, 0.01, "{line}");
        }
    }

    /// A file of one sample, of zeros, or with a sample past 10 g (a file
    /// in gal under a units line of g: 499.7 "g", or a typo) is no motion
    /// to run: each ran as a record that never overturns, or overturns on
    /// one spike. The first sample past 10 g is blamed on its own line
    /// (counted by hand: header lines 1–4, then a blank line among them).
    #[test]
    fn samples_that_are_no_ground_motion_are_refused() {
        for (npts, body, line, want) in [
            ("NPTS= 1, DT= .01 SEC", "0.3\n", 4, At2ErrorKind::OneSample),
            (
                "NPTS= 3, DT= .01 SEC",
                "0 0.0\n-0\n",
                5,
                At2ErrorKind::NoMotion,
            ),
            (
                "NPTS= 3, DT= .01 SEC",
                "0.1 -499.7 2\n",
                5,
                At2ErrorKind::Implausible {
                    index: 2,
                    value: -499.7,
                    past: 1,
                    of: 3,
                },
            ),
            (
                "NPTS= 7, DT= .01 SEC",
                "0.1, 0.2\n0.3 0.4\n\n0.5\t12.5 -30\n",
                8,
                At2ErrorKind::Implausible {
                    index: 6,
                    value: 12.5,
                    past: 2,
                    of: 7,
                },
            ),
        ] {
            let e = parse_str(&file(npts, body)).unwrap_err();
            assert_eq!((e.line, e.kind), (line, want), "{body}");
        }
        // 10 g itself, and a motion that is 0 but for one sample, are motions.
        for body in ["10 -10\n", "0 0 0.001\n"] {
            let n = body.split_whitespace().count();
            assert!(parse_str(&file(&format!("NPTS= {n}, DT= .01 SEC"), body)).is_ok());
        }
    }

    #[test]
    fn any_white_space_or_comma_separates_samples() {
        // A no-break space and an em space (Unicode white space), a tab, a
        // vertical tab and commas, in a CRLF file.
        let body = "1,2\u{a0}3\u{2003}4\t5\x0b6 ,7\r\n";
        let at2 = parse_str(&file("NPTS= 7, DT= .01 SEC", body)).unwrap();
        assert_eq!(at2.accel_g, vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0]);
        // Other characters belong to the token, which is refused whole.
        let e = parse_str(&file("NPTS= 2, DT= .01 SEC", "1\n2\u{b5}\n")).unwrap_err();
        assert_eq!(
            (e.line, e.kind),
            (
                6,
                At2ErrorKind::NotANumber {
                    token: "2\u{b5}".into()
                }
            )
        );
        let e = parse_str(&file("NPTS= 2, DT= .01 SEC", "1 2\u{0}3\n")).unwrap_err();
        assert_eq!(
            (e.line, e.kind),
            (
                5,
                At2ErrorKind::NotANumber {
                    token: "2\u{0}3".into()
                }
            )
        );
        // Latin-1 bytes in a header are replaced, not refused.
        let mut bytes = file("NPTS= 2, DT= .01 SEC", "5 6\n").into_bytes();
        bytes[3] = 0xe9;
        assert_eq!(parse(&bytes).unwrap().accel_g, vec![5.0, 6.0]);
    }
}
