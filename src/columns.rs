//! Acceleration histories as text columns (pure: text in, samples out):
//! what a structural model writes for a floor, read with the unit the user
//! declares.
//!
//! ```text
//! # comments (#, %, //) and blank lines anywhere; one header line of
//! # names at the top (its first token no number) is skipped
//! 0.01   0.0012   -0.0031   0.0008      time, then one column per value
//! 0.02   0.0025   -0.0060   0.0011
//! ```
//!
//! The first column is time (s), the others values: an OpenSees `Node`
//! recorder with `-time` (`recorder Node -file f.out -time -node 3 4 -dof 1
//! accel`) writes one per node and dof; a plain two-column file is time and
//! acceleration. Numbers are separated by blanks or commas. `column` picks
//! the value column (1 = the first after time). The time step is the
//! columns' own, their mean step: the times must be evenly spaced (each
//! step within 1 % of the first;
//! an analysis with a varying step is refused at the line where it varies:
//! resample it first); where the times start does not matter to a block
//! at rest. Values are converted from `unit` to g (g = 9.80665 m/s²).
//!
//! Refused with the 1-based line number: a token that is not a finite
//! number, a line with fewer columns than asked or than the first, times
//! that do not increase evenly, fewer than two samples, a step outside
//! 1e-5–1 s (a time column in milliseconds), a value past 10 g (a unit
//! mistaken). A motion all 0 is refused once its ground is added
//! (`records::collect`): relative to the ground, a rigid base's is 0.

use std::fmt;

use crate::block::G;
use crate::motion::{MAX_ACCEL_G, MAX_DT_S, MIN_DT_S};

/// The unit a text file's accelerations are given in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum AccelUnit {
    G,
    MPerS2,
    CmPerS2,
    MmPerS2,
    InPerS2,
    FtPerS2,
}

impl AccelUnit {
    /// The factor to g.
    pub fn to_g(self) -> f64 {
        match self {
            AccelUnit::G => 1.0,
            AccelUnit::MPerS2 => 1.0 / G,
            AccelUnit::CmPerS2 => 0.01 / G,
            AccelUnit::MmPerS2 => 0.001 / G,
            AccelUnit::InPerS2 => 0.0254 / G,
            AccelUnit::FtPerS2 => 0.3048 / G,
        }
    }

    /// A value in this unit, in g: g itself untouched (to the bit).
    pub fn in_g(self, value: f64) -> f64 {
        match self {
            AccelUnit::G => value,
            unit => value * unit.to_g(),
        }
    }
}

impl crate::label::Label for AccelUnit {
    const ALL: &'static [Self] = &[
        AccelUnit::G,
        AccelUnit::MPerS2,
        AccelUnit::CmPerS2,
        AccelUnit::MmPerS2,
        AccelUnit::InPerS2,
        AccelUnit::FtPerS2,
    ];
    const WHAT: &'static str = "acceleration unit";
    fn label(self) -> &'static str {
        match self {
            AccelUnit::G => "g",
            AccelUnit::MPerS2 => "m/s2",
            AccelUnit::CmPerS2 => "cm/s2",
            AccelUnit::MmPerS2 => "mm/s2",
            AccelUnit::InPerS2 => "in/s2",
            AccelUnit::FtPerS2 => "ft/s2",
        }
    }
    fn aliases(self) -> &'static [&'static str] {
        match self {
            AccelUnit::MPerS2 => &["m/s^2", "m/s²"],
            AccelUnit::CmPerS2 => &["cm/s^2", "cm/s²", "gal"],
            AccelUnit::MmPerS2 => &["mm/s^2", "mm/s²"],
            AccelUnit::InPerS2 => &["in/s^2", "in/s²"],
            AccelUnit::FtPerS2 => &["ft/s^2", "ft/s²"],
            AccelUnit::G => &[],
        }
    }
}

crate::deserialize_by_label!(AccelUnit);

/// How a suite of text files is read: the unit, which value column, and
/// whether they are accelerations relative to the ground.
#[derive(Debug, Clone, PartialEq)]
pub struct TextRecords {
    pub unit: AccelUnit,
    /// 1 = the first column after time.
    pub column: usize,
    /// The values are relative to the ground: the folder of the ground
    /// motions the model was shaken with (as run: AT2 in g, or text of
    /// time and acceleration in `unit`), one per record of the same stem.
    pub ground: Option<std::path::PathBuf>,
}

impl fmt::Display for TextRecords {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use crate::label::Label;
        write!(
            f,
            "text columns in {}, value column {}",
            self.unit.label(),
            self.column
        )?;
        if let Some(g) = &self.ground {
            write!(f, ", relative to the ground of {}", g.display())?;
        }
        Ok(())
    }
}

/// Adds the ground's acceleration to a relative motion: the ground given
/// by its samples (g) from time `ground_t0` every `ground_dt`, linear
/// between them and 0 outside them (as OpenSees' `Path` time series
/// applies a record), read at each of the motion's times.
pub fn add_ground(motion: &mut ColumnMotion, ground_g: &[f64], ground_t0: f64, ground_dt: f64) {
    let at = |t: f64| -> f64 {
        let x = (t - ground_t0) / ground_dt;
        if x.is_nan() || x < -1e-6 {
            return 0.0;
        }
        let x = x.max(0.0);
        let i = x.floor() as usize;
        // Within a millionth of a step of a sample: that sample (times
        // written in decimals land a rounding off the grid).
        let frac = x - i as f64;
        match (ground_g.get(i), ground_g.get(i + 1)) {
            (Some(&a), _) if frac < 1e-6 => a,
            (Some(_), None) if frac > 1.0 - 1e-6 => 0.0,
            (Some(&a), Some(&b)) => a + (b - a) * frac,
            _ => 0.0,
        }
    };
    for (a, &t) in motion.accel_g.iter_mut().zip(&motion.times) {
        *a += at(t);
    }
}

/// A text file's motion.
#[derive(Debug, Clone, PartialEq)]
pub struct ColumnMotion {
    /// The chosen column, in g.
    pub accel_g: Vec<f64>,
    /// The step (s): the mean of the times' steps.
    pub dt_s: f64,
    /// The first time (s).
    pub t0_s: f64,
    /// Every sample's time (s), as the file gives it.
    pub times: Vec<f64>,
    /// The header line of names, if the file has one.
    pub header: Option<String>,
}

/// Why a text file cannot be read, and on which line (1-based; 0 for the
/// file as a whole).
#[derive(Debug, Clone, PartialEq)]
pub struct ColumnsError {
    pub line: usize,
    pub kind: String,
}

impl fmt::Display for ColumnsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.kind)
    }
}

impl std::error::Error for ColumnsError {}

/// Reads the time and the `spec.column`-th value column of `text`.
pub fn parse(text: &str, spec: &TextRecords) -> Result<ColumnMotion, ColumnsError> {
    let err = |line: usize, kind: String| ColumnsError { line, kind };
    if spec.column == 0 {
        return Err(err(0, "value columns are counted from 1".into()));
    }
    let mut times = Vec::new();
    let mut values = Vec::new();
    let mut lines_of = Vec::new();
    let mut width = None;
    let mut header = None;
    for (k, raw) in text.lines().enumerate() {
        let line = k + 1;
        let body = raw.trim();
        if body.is_empty()
            || body.starts_with('#')
            || body.starts_with('%')
            || body.starts_with("//")
        {
            continue;
        }
        let tokens: Vec<&str> = body
            .split(|c: char| c.is_whitespace() || c == ',' || c == ';')
            .filter(|t| !t.is_empty())
            .collect();
        let parsed: Vec<Option<f64>> = tokens
            .iter()
            .map(|t| crate::decimal::read_number(t))
            .collect();
        // A first line of names is a header: its first token, where a data
        // line has its time, is no number. A first data line with a bad
        // value is refused at its line, not skipped as a header.
        if times.is_empty() && header.is_none() && parsed.first().is_some_and(Option::is_none) {
            header = Some(body.to_string());
            continue;
        }
        if let Some(token) = decimal_comma(body) {
            return Err(err(
                line,
                format!("`{token}` has a decimal comma: write the numbers with a point (`0.01`)"),
            ));
        }
        let numbers: Result<Vec<f64>, &str> = parsed
            .iter()
            .zip(&tokens)
            .map(|(v, t)| v.filter(|v| v.is_finite()).ok_or(*t))
            .collect();
        let numbers = numbers.map_err(|t| err(line, format!("`{t}` is not a finite number")))?;
        let n = numbers.len();
        if n < 2 {
            return Err(err(
                line,
                "one column: the first must be time (s), then the values".into(),
            ));
        }
        let first = *width.get_or_insert(n);
        if n != first {
            return Err(err(
                line,
                format!("{n} columns where the first line of numbers has {first}"),
            ));
        }
        if spec.column > n - 1 {
            return Err(err(
                line,
                format!(
                    "value column {} asked, but the file has {} after time",
                    spec.column,
                    n - 1
                ),
            ));
        }
        times.push(numbers[0]);
        values.push(spec.unit.in_g(numbers[spec.column]));
        lines_of.push(line);
    }
    let n = times.len();
    if n < 2 {
        return Err(err(
            0,
            format!("{n} sample(s): a motion needs two at least"),
        ));
    }
    let dt = check_motion(&times, &values, &lines_of, spec)?;
    Ok(ColumnMotion {
        accel_g: values,
        dt_s: dt,
        t0_s: times[0],
        times,
        header,
    })
}

/// The first field of `line` written with a decimal comma (`0,01` where the
/// fields are apart by blanks or semicolons and no number has a point),
/// which the comma would split into two numbers.
fn decimal_comma(line: &str) -> Option<&str> {
    let apart = line.contains(';') || line.split_whitespace().nth(1).is_some();
    if !apart || line.contains('.') {
        return None;
    }
    line.split(|c: char| c.is_whitespace() || c == ';')
        .find(|field| crate::decimal::comma_between_digits(field))
}

/// The motion's mean step (s), checked: times increasing evenly by a step
/// a motion has (seconds, not milliseconds), and values no motion passes.
fn check_motion(
    times: &[f64],
    values: &[f64],
    lines_of: &[usize],
    spec: &TextRecords,
) -> Result<f64, ColumnsError> {
    let err = |line: usize, kind: String| ColumnsError { line, kind };
    let n = times.len();
    let dt = (times[n - 1] - times[0]) / (n - 1) as f64;
    if dt <= 0.0 {
        return Err(err(lines_of[1], "the times do not increase".into()));
    }
    let first = times[1] - times[0];
    for i in 1..n {
        let step = times[i] - times[i - 1];
        if step == 0.0 {
            return Err(err(
                lines_of[i],
                format!(
                    "time {} s repeats the line before's: each line is one sample, the times \
                     increasing by one step",
                    times[i]
                ),
            ));
        }
        if (step - first).abs() > 0.01 * first {
            return Err(err(
                lines_of[i],
                format!(
                    "a time step of {step:e} s where the first is {first:e} s: the times must \
                     be evenly spaced (resample a varying analysis step first)"
                ),
            ));
        }
    }
    // The first column is seconds: a step of 5 is a time in milliseconds
    // (a record 1000 times too slow), one of 5e-6 a time in other units.
    if !crate::motion::dt_accepted(dt) {
        return Err(err(
            lines_of[1],
            format!(
                "a time step of {dt:e} s: the first column is the time in seconds, and a motion \
                 is sampled every 0.001–0.05 s (accepted: {MIN_DT_S:e} to {MAX_DT_S} s); is the \
                 time in another unit, or the first column a sample number?"
            ),
        ));
    }
    if let Some(i) = values.iter().position(|a| a.abs() > MAX_ACCEL_G) {
        return Err(err(
            lines_of[i],
            format!(
                "{:e} g, past {MAX_ACCEL_G} g: no floor or ground motion is that strong; is the \
                 unit `{}` right?",
                values[i],
                crate::label::Label::label(spec.unit)
            ),
        ));
    }
    Ok(dt)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(unit: AccelUnit, column: usize) -> TextRecords {
        TextRecords {
            unit,
            column,
            ground: None,
        }
    }

    /// A relative motion plus its ground (hand-worked): the ground 0, 0.2,
    /// −0.2 g at 0, 0.02, 0.04 s, read at 0.01 (halfway: 0.1), 0.02 (a
    /// sample), 0.05 (past its end: 0) and before it starts (0).
    #[test]
    fn the_ground_is_added_at_the_motions_times() {
        let mut m = parse("-0.01 1\n0.01 1\n0.02 1\n0.05 1\n", &spec(AccelUnit::G, 1));
        assert!(m.is_err(), "uneven times are refused first");
        let text = "0.00 0.5\n0.01 0.5\n0.02 0.5\n0.03 0.5\n";
        m = parse(text, &spec(AccelUnit::G, 1));
        let mut m = m.unwrap();
        add_ground(&mut m, &[0.0, 0.2, -0.2], 0.0, 0.02);
        let want = [0.5, 0.6, 0.7, 0.5];
        for (got, want) in m.accel_g.iter().zip(want) {
            assert!((got - want).abs() < 1e-12, "{got} vs {want}");
        }
        let mut late = parse("0.05 0.5\n0.06 0.5\n", &spec(AccelUnit::G, 1)).unwrap();
        add_ground(&mut late, &[0.0, 0.2, -0.2], 0.0, 0.02);
        assert_eq!(late.accel_g, vec![0.5, 0.5]);
        let mut early = parse("0 0.5\n0.01 0.5\n", &spec(AccelUnit::G, 1)).unwrap();
        add_ground(&mut early, &[0.3, 0.3], 0.5, 0.02);
        assert_eq!(early.accel_g, vec![0.5, 0.5]);
    }

    /// An OpenSees `Node` recorder with `-time` for two nodes, in m/s²: the
    /// second node's column, converted by hand (1.96133 m/s² = 0.2 g).
    #[test]
    fn reads_an_opensees_recorder_column_in_its_unit() {
        let text = "0.005 0.1 1.96133\n0.010 0.2 -0.980665\n0.015 0.3 0\n";
        let m = parse(text, &spec(AccelUnit::MPerS2, 2)).unwrap();
        assert!((m.dt_s - 0.005).abs() < 1e-15);
        assert_eq!(m.t0_s, 0.005);
        let want = [0.2, -0.1, 0.0];
        for (got, want) in m.accel_g.iter().zip(want) {
            assert!((got - want).abs() < 1e-15, "{got} vs {want}");
        }
        // gal (cm/s²) and g: g values are taken to the bit.
        let m = parse("0,1.5e-1\n0.01,-3e-1\n", &spec(AccelUnit::G, 1)).unwrap();
        assert_eq!(m.accel_g, vec![0.15, -0.3]);
        let m = parse("0 980.665\n0.01 0\n", &spec(AccelUnit::CmPerS2, 1)).unwrap();
        assert!((m.accel_g[0] - 1.0).abs() < 1e-15);
    }

    #[test]
    fn comments_and_a_header_line_are_skipped() {
        let text = "time,accel\n# from OpenSees\n\n0.0, 0.1\n% note\n0.02, 0.2\n";
        let m = parse(text, &spec(AccelUnit::G, 1)).unwrap();
        assert_eq!(m.accel_g, vec![0.1, 0.2]);
        assert_eq!(m.header.as_deref(), Some("time,accel"));
        assert!((m.dt_s - 0.02).abs() < 1e-15);
    }

    #[test]
    fn bad_files_are_refused_at_their_line() {
        let g = spec(AccelUnit::G, 1);
        // A first data line with a bad value was skipped as a header.
        let e = parse("0 np.float64(0.1)\n0.01 0.2\n0.02 0.1\n", &g).unwrap_err();
        assert_eq!(e.line, 1);
        assert!(e.kind.contains("`np.float64(0.1)`"), "{e}");
        let e = parse("0 0.1\n0.01 abc\n", &g).unwrap_err();
        assert_eq!(e.line, 2);
        assert!(e.kind.contains("`abc`"), "{e}");
        let e = parse("0 0.1\n0.01 0.2 0.3\n", &g).unwrap_err();
        assert_eq!(e.line, 2);
        let e = parse("0 0.1\n0.01 0.2\n0.03 0.1\n0.04 0\n", &g).unwrap_err();
        assert_eq!(e.line, 3);
        assert!(e.kind.contains("evenly spaced"), "{e}");
        let e = parse("0 0.1\n0.01 0.2\n", &spec(AccelUnit::G, 2)).unwrap_err();
        assert!(e.kind.contains("column 2"), "{e}");
        let e = parse("0.1\n0.2\n", &g).unwrap_err();
        assert!(e.kind.contains("one column"), "{e}");
        let e = parse("0 0.1\n", &g).unwrap_err();
        assert!(e.kind.contains("two at least"), "{e}");
        let e = parse("0 0.1\n0 0.2\n", &g).unwrap_err();
        assert!(e.kind.contains("do not increase"), "{e}");
        let e = parse("0 NaN\n0.01 0\n", &g).unwrap_err();
        assert_eq!(e.line, 1);
    }

    /// A time column in milliseconds (a 5 ms step written 5) made a record
    /// 1000 times too slow; values in gal read as g made a motion of
    /// hundreds of g. Both are refused at the line that shows it; the
    /// limits themselves (1 s, 1e-5 s, 10 g) are motions.
    /// European files: a decimal comma among blanks or semicolons is named
    /// (it split each number in two, and the message spoke of time steps);
    /// semicolons with points are fields apart; a repeated first time is
    /// said to repeat; Fortran's D exponent is read, as in AT2 files.
    #[test]
    fn decimal_commas_semicolons_repeats_and_fortran_exponents() {
        let g = spec(AccelUnit::G, 1);
        for text in ["0,00 0,10\n0,01 0,20\n", "0,00;0,10\n0,01;0,20\n"] {
            let e = parse(text, &g).unwrap_err();
            assert_eq!(e.line, 1, "{e}");
            assert!(e.kind.contains("`0,00` has a decimal comma"), "{e}");
        }
        let m = parse("t;a\n0.00;0.10\n0.01;0.20\n0.02;0.1\n", &g).unwrap();
        assert_eq!((m.accel_g.len(), m.header.as_deref()), (3, Some("t;a")));
        // Commas as the separator (CSV) stay fields apart.
        let m = parse("0,1\n0.01,2\n0.02, 3\n", &g).unwrap();
        assert_eq!(m.accel_g, vec![1.0, 2.0, 3.0]);
        let e = parse("0 0.1\n0 0.2\n0.01 0.1\n0.02 0.3\n", &g).unwrap_err();
        assert_eq!(e.line, 2);
        assert!(e.kind.contains("time 0 s repeats the line before's"), "{e}");
        let m = parse("0.0D+00 1.0D-02\n1.0D-02 -2.5d-02\n", &g).unwrap();
        assert_eq!(m.accel_g, vec![0.01, -0.025]);
        assert_eq!(m.dt_s, 0.01);
    }

    #[test]
    fn a_time_in_milliseconds_or_a_unit_mistaken_is_refused() {
        let g = spec(AccelUnit::G, 1);
        let e = parse("# t (ms), a\n0 0.1\n5 0.2\n10 0.1\n", &g).unwrap_err();
        assert_eq!(e.line, 3);
        assert!(
            e.kind.contains("5e0 s") && e.kind.contains("seconds"),
            "{e}"
        );
        let e = parse("0 0.1\n1e-6 0.2\n", &g).unwrap_err();
        assert!(e.kind.contains("another unit"), "{e}");
        // A sample number in the time column: a step of 1 "s".
        let e = parse("0 0.1\n1 0.2\n2 0.1\n", &g).unwrap_err();
        assert!(e.kind.contains("a sample number"), "{e}");
        assert!(parse("0 0.1\n0.1 0.2\n", &g).is_ok());
        assert!(parse("0 0.1\n1e-5 0.2\n", &g).is_ok());
        let e = parse("0 12.5\n0.01 -490.3\n0.02 3\n", &g).unwrap_err();
        assert_eq!(e.line, 1);
        assert!(
            e.kind.contains("past 10 g") && e.kind.contains("`g`"),
            "{e}"
        );
        // The same values in gal are a motion of half a g.
        let m = parse(
            "0 12.5\n0.01 -490.3\n0.02 3\n",
            &spec(AccelUnit::CmPerS2, 1),
        )
        .unwrap();
        assert!((m.accel_g[1] + 0.49997).abs() < 1e-4);
        assert!(parse("0 10\n0.01 -10\n", &g).is_ok());
    }
}
