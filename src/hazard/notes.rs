//! What a hazard curve's numbers suggest beyond their validity (pure):
//! IMLs that look like another unit, AvgSA's unstated periods, a curve
//! that is not the mean hazard.

use super::curve::HazardCurve;
use crate::im::Im;

/// A warning where a curve's IMLs look like another unit than the IM's
/// (the commonest slips: PGA or SA in cm/s² given as g, PGV in m/s given
/// as cm/s), naming the likely unit; and for AvgSA, which periods the
/// curve must be over (a hazard file does not say).
pub fn plausibility(curve: &HazardCurve) -> Option<String> {
    let (lo, hi) = (curve.iml[0], *curve.iml.last()?);
    let range = format!(
        "the hazard's IMLs run from {} to {} {}",
        crate::im::level_text(lo),
        crate::im::level_text(hi),
        curve.im.unit()
    );
    if let Some(slip) = unit_slip(curve.im, lo, hi, &range) {
        return Some(slip);
    }
    // A curve in m/s² (or cm/s²) on a usual grid starts at plausible g
    // (0.005 g × 9.81 = 0.049), but its tail runs past anything a grid in
    // g reaches (OpenQuake's go to 3–10 g).
    if matches!(curve.im, Im::Pga | Im::Sa(_) | Im::AvgSa) && hi > 20.0 {
        return Some(format!(
            "{range}: a hazard grid in g ends by about 10 g, and this one reaches {} g; are \
             they in m/s² (divide by 9.80665 for g) or cm/s² (by 980.665)?",
            crate::im::level_text(hi)
        ));
    }
    match curve.im {
        Im::AvgSa => Some(format!(
            "AvgSA: a hazard file does not state its periods; this tool's AvgSA is the geometric \
             mean of SA at {} s (docs/MODEL.md §14), and the hazard must be computed over the \
             same periods",
            crate::im::AVGSA_PERIODS_S
                .map(crate::im::period_text)
                .join(", ")
        )),
        _ => None,
    }
}

/// A warning where an OpenQuake curve is not the mean hazard (its `kind`
/// a quantile, a realisation of the logic tree, or another statistic): the
/// rate integrated over it is then that curve's, not the mean rate of
/// exceedance a risk or an expected count rests on. `None` for the mean
/// and for a plain CSV, which states no statistic.
pub fn statistic_note(curve: &HazardCurve) -> Option<String> {
    let kind = curve.kind.as_deref()?;
    let what = if kind == "mean" {
        return None;
    } else if let Some(q) = kind.strip_prefix("quantile-") {
        match q.parse::<f64>() {
            Ok(q) if (0.0..=1.0).contains(&q) => format!(
                "the {} % quantile of the hazard over OpenQuake's logic tree",
                (q * 1e6).round() / 1e4
            ),
            _ => format!("a quantile curve (`{kind}`)"),
        }
    } else if kind.starts_with("rlz-") {
        format!("one realisation of OpenQuake's logic tree (`{kind}`)")
    } else {
        format!("OpenQuake's `{kind}` curve")
    };
    Some(format!(
        "the hazard file is {what} (kind='{kind}'), not the mean hazard: the rates below are \
         that curve's, not the mean rate of exceedance; give the mean curve \
         (hazard_curve-mean-…csv) for the mean rate"
    ))
}

/// A warning where levels of `im` that start at `lo` and reach `hi` (as
/// `range` says, in words) look like another unit than the IM's: PGA or SA
/// in cm/s² given as g (nothing shakes the ground at 5 g), PGV in m/s
/// given as cm/s (all below 5 cm/s, where nothing rocks). The one rule of
/// the hazard's IMLs, OpenQuake's fields and `fragility`'s levels.
pub fn unit_slip(im: Im, lo: f64, hi: f64, range: &str) -> Option<String> {
    match im {
        Im::Pga | Im::Sa(_) | Im::AvgSa if lo >= 5.0 => Some(format!(
            "{range}: no earthquake shakes the ground at {} g and more; are they in cm/s² \
             (gal)? Divide them by 980.665 for g",
            crate::im::level_text(lo)
        )),
        Im::Pgv if hi <= 5.0 => Some(format!(
            "{range}: all below 5 cm/s, where nothing rocks; are they in m/s? Multiply them by \
             100 for cm/s"
        )),
        _ => None,
    }
}

/// Where the levels asked look like another unit than the IM's: the
/// hazard's rule ([`unit_slip`]: PGA in cm/s², PGV in m/s),
/// and PGA levels past 5 g, which no earthquake has shaken the ground at
/// (the strongest records reach about 4 g), as m/s² (a hazard curve's
/// tail may run there; levels asked of `fragility` do not).
pub fn levels_slip(im: Im, levels: &[f64]) -> Option<String> {
    let lo = levels.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = levels.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if !(lo.is_finite() && hi.is_finite()) {
        return None;
    }
    let t = crate::im::level_text;
    let range = format!("the levels {}–{} {}", t(lo), t(hi), im.unit());
    unit_slip(im, lo, hi, &range).or_else(|| {
        (im == Im::Pga && hi > 5.0).then(|| {
            format!(
                "{range}: no earthquake has shaken the ground at more than about 4 g, and these \
                 reach {} g; are they in m/s²? Divide them by 9.80665 for g",
                t(hi)
            )
        })
    })
}
