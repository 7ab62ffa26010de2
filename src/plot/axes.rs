//! What every drawing path shares: the axis scales, which values an axis
//! can show, where the ticks go and their labels, axis ranges, the canvas
//! and fonts, and the colours of series.

use plotters::prelude::RGBColor;

pub(super) const PALETTE: [RGBColor; 12] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(23, 190, 207),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(0, 0, 128),
    RGBColor(128, 0, 0),
];

/// Width and height (px) of every chart's canvas, so that every figure of
/// a report is scaled alike and its text reads at one size.
pub(super) const CANVAS: (u32, u32) = (1200, 620);
/// Font sizes (px): title, axis descriptions, tick labels and legend.
pub(super) const FONT_TITLE: u32 = 22;
pub(super) const FONT_DESC: u32 = 18;
pub(super) const FONT_TICK: u32 = 16;
pub(super) const FONT_LEGEND: u32 = 16;

/// What a series' colour means. A meaning has one colour in every figure:
/// a fractile always the same, a value of an ordered parameter (ε) always
/// its place on one ramp, so curves can be matched across figures.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Hue {
    /// A fractile: 0 is 16 %, 1 the median, 2 is 84 %.
    Fractile(usize),
    /// A place on an ordered parameter's range, 0 (its smallest value) to 1
    /// (its largest): a sequential ramp (viridis, dark to light green).
    Ramp(f64),
    /// The i-th of a set without an order.
    Series(usize),
    /// Black: a reference drawn beside the data (a published bound).
    Ink,
}

/// The three fractiles' colours: blue, red, green.
const FRACTILE: [RGBColor; 3] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
];

/// Viridis at eighths of its range (van der Walt & Smith, matplotlib's
/// default map: perceptually uniform, readable in grey and by most forms
/// of colour blindness).
const VIRIDIS: [(u8, u8, u8); 9] = [
    (68, 1, 84),
    (71, 44, 122),
    (59, 81, 139),
    (44, 113, 142),
    (33, 144, 141),
    (39, 173, 129),
    (92, 200, 99),
    (170, 220, 50),
    (253, 231, 37),
];

impl Hue {
    pub(super) fn rgb(self) -> RGBColor {
        match self {
            Hue::Fractile(i) => FRACTILE[i.min(2)],
            Hue::Series(i) => PALETTE[i % PALETTE.len()],
            Hue::Ink => RGBColor(0, 0, 0),
            Hue::Ramp(t) => {
                // The ramp stops at 85 %: its pale yellow end is unreadable on white.
                let x = if t.is_finite() {
                    t.clamp(0.0, 1.0)
                } else {
                    0.0
                } * 0.85
                    * 8.0;
                let k = (x.floor() as usize).min(7);
                let f = x - k as f64;
                let (a, b) = (VIRIDIS[k], VIRIDIS[k + 1]);
                let mix = |u: u8, v: u8| (u as f64 + f * (v as f64 - u as f64)).round() as u8;
                RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
            }
        }
    }
}

/// Where an axis over [lo, hi] puts its labelled ticks: "nice" steps (1,
/// 2, 2.5 or 5 times a power of ten, six to ten ticks) on a linear axis;
/// on a log axis every mantissa 1–9 of a decade when the axis spans about
/// one decade, 1, 2 and 5 up to three decades, 1 and 3 up to five, and
/// powers of ten (every k-th one past ten decades) beyond. At least two
/// ticks unless the axis is a point.
pub fn ticks(scale: Scale, lo: f64, hi: f64) -> Vec<f64> {
    if !keep(scale, lo) || !keep(scale, hi) || lo >= hi {
        return Vec::new();
    }
    match scale {
        Scale::Linear => {
            let raw = (hi - lo) / 8.0;
            let mag = 10f64.powf(raw.log10().floor());
            let step = [1.0, 2.0, 2.5, 5.0, 10.0]
                .into_iter()
                .map(|m| m * mag)
                .find(|&s| s >= raw)
                .unwrap_or(10.0 * mag);
            // Within rounding of a multiple is on it: 1.2/0.2 is 5.999….
            let first = (lo / step - 1e-9).ceil() as i64;
            let last = (hi / step + 1e-9).floor() as i64;
            // k·step, rounded to the step's precision so 0.1·3 is 0.3.
            let digits = (-step.log10().floor() + 2.0).max(0.0) as i32;
            let round = |v: f64| {
                let f = 10f64.powi(digits.min(15));
                (v * f).round() / f
            };
            (first..=last).map(|k| round(k as f64 * step)).collect()
        }
        Scale::Log => {
            let decades = (hi / lo).log10();
            let mantissas: &[f64] = match decades {
                d if d <= 1.2 => &EVERY_MANTISSA,
                d if d <= 3.2 => &[1.0, 2.0, 5.0],
                d if d <= 5.2 => &[1.0, 3.0],
                _ => &[1.0],
            };
            let every = (decades / 10.0).ceil().max(1.0) as i32;
            let out = log_values(lo, hi, mantissas, every);
            if out.len() >= 2 {
                return out;
            }
            // Too few on a short axis: every mantissa; shorter than the
            // step between two (2.65 to 2.82), a linear axis's ticks.
            let every = log_values(lo, hi, &EVERY_MANTISSA, 1);
            if every.len() >= 2 {
                every
            } else {
                ticks(Scale::Linear, lo, hi)
            }
        }
    }
}

/// Every mantissa of a decade, for a log axis's short spans and its faint lines.
pub(super) const EVERY_MANTISSA: [f64; 9] = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0];

/// The values m·10^d in [lo, hi] (to rounding) for each mantissa m and every
/// `every`-th decade d, ascending.
pub(super) fn log_values(lo: f64, hi: f64, mantissas: &[f64], every: i32) -> Vec<f64> {
    let (d0, d1) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    let mut out = Vec::new();
    for d in (d0..=d1).filter(|d| d.rem_euclid(every) == 0) {
        for &m in mantissas {
            // Parsed from text: 2e-2 is the double nearest 0.02.
            let v: f64 = format!("{m}e{d}").parse().expect("a number");
            if v >= lo * (1.0 - 1e-12) && v <= hi * (1.0 + 1e-12) {
                out.push(v);
            }
        }
    }
    out
}

/// Axis scale. Log axes are drawn as log10 of the values on a linear axis,
/// labelled with the values.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scale {
    Linear,
    Log,
}

pub(super) fn keep(scale: Scale, v: f64) -> bool {
    v.is_finite() && (scale == Scale::Linear || v > 0.0)
}

pub(super) fn tick_label(v: f64) -> String {
    let a = v.abs();
    if a != 0.0 && !(1e-3..1e4).contains(&a) {
        format!("{v:.0e}")
    } else {
        let s = format!("{v:.3}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    }
}

/// The axis range in data units: the given one, or the data's with a margin
/// (multiplicative on a log axis).
pub(super) fn axis_range(scale: Scale, given: Option<(f64, f64)>, lo: f64, hi: f64) -> (f64, f64) {
    if let Some((a, b)) = given.filter(|(a, b)| keep(scale, *a) && keep(scale, *b) && b > a) {
        return (a, b);
    }
    match scale {
        Scale::Linear => {
            let pad = if hi > lo { 0.03 * (hi - lo) } else { 0.5 };
            (lo - pad, hi + pad)
        }
        Scale::Log => {
            if hi > lo {
                let f = (hi / lo).powf(0.03);
                (lo / f, hi * f)
            } else {
                (lo / 2.0, hi * 2.0)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_by_hand() {
        let lin = ticks(Scale::Linear, 0.0, 1.0);
        assert_eq!(lin, vec![0.0, 0.2, 0.4, 0.6, 0.8, 1.0]);
        assert_eq!(
            ticks(Scale::Linear, 0.65, 0.88),
            vec![0.65, 0.7, 0.75, 0.8, 0.85]
        );
        // The example fragility's 0–1.2 g: its end a tick (1.2/0.2 = 5.999…).
        assert_eq!(
            ticks(Scale::Linear, 0.0, 1.2),
            vec![0.0, 0.2, 0.4, 0.6, 0.8, 1.0, 1.2]
        );
        assert_eq!(
            ticks(Scale::Log, 0.25, 10.0),
            vec![0.5, 1.0, 2.0, 5.0, 10.0]
        );
        assert_eq!(
            ticks(Scale::Log, 0.004, 0.7),
            vec![0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5]
        );
        assert_eq!(
            ticks(Scale::Log, 3.0, 9.5),
            vec![3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]
        );
        assert_eq!(
            ticks(Scale::Log, 1e-12, 1.0).len(),
            7,
            "every second decade"
        );
        assert!(ticks(Scale::Log, 0.0, 1.0).is_empty());
        // Shorter than the step between two mantissas (the p of a study's
        // named blocks, 2.66 to 2.82 1/s): a linear axis's ticks, the span
        // over 8 = 0.02 apart.
        assert_eq!(
            ticks(Scale::Log, 2.66, 2.82),
            vec![2.66, 2.68, 2.7, 2.72, 2.74, 2.76, 2.78, 2.8, 2.82]
        );
    }

    /// The ramp runs from viridis's dark violet; a fractile's colour is its own.
    #[test]
    fn hues() {
        assert_eq!(Hue::Ramp(0.0).rgb(), RGBColor(68, 1, 84));
        assert_ne!(Hue::Ramp(1.0).rgb(), RGBColor(253, 231, 37));
        assert_eq!(Hue::Fractile(1).rgb(), RGBColor(214, 39, 40));
    }
}
