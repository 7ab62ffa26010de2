//! Why an AT2 file was refused: the kinds of fault, each named with its
//! line, and their messages.

use std::fmt;

use crate::motion::{MAX_ACCEL_G, MAX_DT_S, MIN_DT_S};

/// Number of header lines before the samples (here, where the messages
/// that count them are).
pub const HEADER_LINES: usize = 4;

/// Why a file was refused, and on which line (1-based).
#[derive(Debug, Clone, PartialEq)]
pub struct At2Error {
    pub line: usize,
    pub kind: At2ErrorKind,
}

#[derive(Debug, Clone, PartialEq)]
pub enum At2ErrorKind {
    Empty,
    ShortHeader {
        lines: usize,
    },
    NotAcceleration {
        units_line: String,
    },
    MissingNpts {
        text: String,
    },
    MissingDt {
        text: String,
    },
    BadNpts {
        token: String,
    },
    BadDt {
        token: String,
    },
    NonPositiveDt {
        dt: f64,
    },
    FineDt {
        dt: f64,
    },
    CoarseDt {
        dt: f64,
    },
    NotANumber {
        token: String,
    },
    NotFinite {
        token: String,
    },
    TooFewValues {
        npts: usize,
        found: usize,
    },
    TooManyValues {
        npts: usize,
    },
    /// Text after the NPTS samples (`END OF DATA`, a Ctrl-Z, NUL padding).
    AfterSamples {
        token: String,
        npts: usize,
    },
    /// More values than NPTS where a token of whitespace-separated values
    /// holds a comma between digits (`1,5E-04`): a decimal comma, read as
    /// two values.
    DecimalComma {
        token: String,
        npts: usize,
    },
    /// DT written with a decimal comma (`DT= 0,01 SEC`).
    DtComma {
        token: String,
    },
    /// DT in a unit other than seconds (`MSEC`).
    DtUnit {
        unit: String,
    },
    /// One sample: no time step to run.
    OneSample,
    /// Every sample 0.
    NoMotion,
    /// A sample beyond [`MAX_ACCEL_G`] (the `index`-th, from 1), one of
    /// `past` such among `of`.
    Implausible {
        index: usize,
        value: f64,
        past: usize,
        of: usize,
    },
}

impl fmt::Display for At2Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "line {}: {}", self.line, self.kind)
    }
}

/// File content shown in a message: control characters (NUL, escape
/// sequences that would recolour or clear a terminal, stray carriage
/// returns) are written as escapes, so a hostile or broken file cannot
/// garble the error that names it.
fn shown(text: &str) -> String {
    // A binary file's "token" runs to hundreds of bytes: its start shows it.
    const SHOWN: usize = 40;
    let more = text.chars().nth(SHOWN).is_some();
    let start: String = text
        .chars()
        .take(SHOWN)
        .flat_map(|c| {
            let escaped: Vec<char> = if c.is_control() {
                c.escape_default().collect()
            } else {
                vec![c]
            };
            escaped
        })
        .collect();
    if more {
        format!("{start}…")
    } else {
        start
    }
}

impl fmt::Display for At2ErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use At2ErrorKind::*;
        match self {
            Empty => write!(f, "the file is empty"),
            ShortHeader { lines } => write!(
                f,
                "the file ends after {lines} line(s); an AT2 file has {HEADER_LINES} header lines before the samples"
            ),
            NotAcceleration { units_line } => write!(
                f,
                "the units line `{}` does not describe an acceleration history in units of g \
                 (velocity .VT2 and displacement .DT2 files share the AT2 layout; give the .AT2 file)",
                shown(units_line)
            ),
            MissingNpts { text } => write!(
                f,
                "no NPTS in `{}`; expected `NPTS=  2999, DT= .0100 SEC` or `2999  0.0100  NPTS, DT`",
                shown(text)
            ),
            MissingDt { text } => write!(
                f,
                "no DT in `{}`; expected `NPTS=  2999, DT= .0100 SEC` or `2999  0.0100  NPTS, DT`",
                shown(text)
            ),
            BadNpts { token } => write!(
                f,
                "NPTS `{}` is not a positive whole number",
                shown(token)
            ),
            BadDt { token } => write!(f, "DT `{}` is not a number", shown(token)),
            NonPositiveDt { dt } => write!(f, "DT = {dt} s; the time step must be positive"),
            FineDt { dt } => write!(
                f,
                "DT = {dt:e} s: an accelerogram is sampled every 0.001–0.05 s; below {MIN_DT_S:e} \
                 s the header's time step is wrong"
            ),
            CoarseDt { dt } => write!(
                f,
                "DT = {dt} s: an accelerogram is sampled every 0.001–0.05 s; above {MAX_DT_S} s \
                 it cannot resolve shaking (is DT in ms?)"
            ),
            NotANumber { token } => write!(f, "`{}` is not a number", shown(token)),
            NotFinite { token } => write!(f, "`{}` is not a finite number", shown(token)),
            TooFewValues { npts, found } => {
                write!(f, "the header says NPTS = {npts} but the file ends after {found} value(s)")
            }
            TooManyValues { npts } => write!(
                f,
                "more values than NPTS = {npts}: the header and the data disagree"
            ),
            AfterSamples { token, npts } => write!(
                f,
                "the file goes on after its NPTS = {npts} samples with `{}`, which is no \
                 sample: remove what follows the samples",
                shown(token)
            ),
            DecimalComma { token, npts } => write!(
                f,
                "`{}` reads as two values, and the file has more than NPTS = {npts}: is its comma \
                 a decimal point? Samples take a point (`1.5E-04`)",
                shown(token)
            ),
            DtComma { token } => write!(
                f,
                "DT `{}` has a decimal comma: write it with a point (`DT= 0.01 SEC`)",
                shown(token)
            ),
            DtUnit { unit } => write!(
                f,
                "DT is given in `{}`: an AT2 file's time step is in seconds (SEC); convert it",
                shown(unit)
            ),
            OneSample => write!(
                f,
                "NPTS = 1: a record needs two samples at least (one time step to run)"
            ),
            NoMotion => write!(f, "every sample is 0: the record has no motion"),
            Implausible {
                index,
                value,
                past,
                of,
            } => {
                write!(
                    f,
                    "sample {index} is {value:e} g, past {MAX_ACCEL_G} g: no ground motion on \
                     record comes near (the strongest, Iwate-Miyagi 2008 at IWTH25, about 4 g); "
                )?;
                if *past == 1 {
                    write!(f, "it is the only one of the {of} samples: a typo?")
                } else {
                    write!(
                        f,
                        "{past} of the {of} samples are: is the file in cm/s² (gal) under \
                         line 3's units of g?"
                    )
                }
            }
        }
    }
}

impl std::error::Error for At2Error {}

pub(super) fn err(line: usize, kind: At2ErrorKind) -> At2Error {
    At2Error { line, kind }
}
