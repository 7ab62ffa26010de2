//! What every drawing path shares: the axis scales, which values an axis
//! can show, tick labels, axis ranges and the palette of series colours.

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
