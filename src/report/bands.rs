//! How sure the study's results are: the bootstrap bands of the capacity
//! fractiles and of the regression, each against the paper's curves.

use std::fmt::Write as _;

use crate::fragility;
use crate::study::StudyData;

/// The bootstrap bands against the paper's Eqs. 10–12: how often the
/// paper's curve lies inside this study's band, and how wide the bands are.
pub(super) fn bands(w: &mut String, d: &StudyData) {
    let Some(bands) = d.bands.as_ref().filter(|b| !b.is_empty() && d.is_grid()) else {
        return;
    };
    let first = &bands[0];
    let _ = writeln!(
        w,
        "## How sure are the capacity fractiles?
"
    );
    let _ = writeln!(
        w,
        "{:.0} % percentile bootstrap bands from {} resamples of whole {}s \
         (`capacity_bands.parquet`). Where the paper's curve lies outside a band, the \
         difference is more than the sampling error of this record set explains.\n",
        100.0 * first.level,
        first.resamples,
        crate::label::Label::label(first.unit)
    );
    let _ = writeln!(
        w,
        "| fractile | paper's curve | blocks (p ≥ 0.5 1/s) | paper inside the band | median band width / η_c |\n|---|---|---:|---:|---:|"
    );
    let mut widest: f64 = 0.0;
    for (qi, q) in [0.16, 0.5, 0.84].into_iter().enumerate() {
        let rows: Vec<BandPoint> = bands
            .iter()
            .filter(|b| b.quantile == q && b.p >= 0.5)
            .map(|b| (b.p, b.eps, b.eta_c, b.lo, b.hi))
            .collect();
        widest = widest.max(paper_against_band(w, qi, &rows));
    }
    wide_band_caveat(w, widest);
    let _ = writeln!(w);
}

/// A point of a band: (p, ε, this study's value, lo, hi).
type BandPoint = (f64, f64, f64, f64, f64);

/// One row of a "paper against the band" table for fractile `qi` (16, 50,
/// 84 %): the points, how many hold the paper's law inside their band, and
/// the median band width relative to the value. Nothing without points.
/// Returns that median width (0 without points).
fn paper_against_band(w: &mut String, qi: usize, rows: &[BandPoint]) -> f64 {
    if rows.is_empty() {
        return 0.0;
    }
    let law = &fragility::paper()[qi];
    let inside = rows
        .iter()
        .filter(|&&(p, e, _, lo, hi)| (lo..=hi).contains(&law.eta_c(p, e)))
        .count();
    let mut widths: Vec<f64> = rows
        .iter()
        .filter(|r| r.2 > 0.0)
        .map(|r| (r.4 - r.3) / r.2)
        .collect();
    widths.sort_by(|a, b| a.total_cmp(b));
    let median =
        crate::stats::fractile(&widths, 0.5, crate::stats::FractileDef::Type7).unwrap_or(f64::NAN);
    let _ = writeln!(
        w,
        "| η_c,{:.0} | Eq. {} | {} | {} ({:.0} %) | {:.0} % |",
        100.0 * law.quantile,
        crate::figures::PAPER_EQ[qi],
        rows.len(),
        inside,
        100.0 * inside as f64 / rows.len() as f64,
        100.0 * median
    );
    median
}

/// After a band table: a caveat when some band is wider than the value.
fn wide_band_caveat(w: &mut String, widest: f64) {
    if widest > 1.0 {
        let _ = writeln!(
            w,
            "\nA band wider than the value itself (here a median of {:.0} %) says this record \
             set cannot pin that fractile down: the paper's curve then lies inside the band \
             almost whatever it is, so \"inside\" carries little information there. More \
             records narrow it.",
            100.0 * widest
        );
    }
}

/// The regression's bootstrap bands: how the refits went, how often the
/// paper's curves lie inside this fit's bands, and the example fragility's
/// median PGA with its band.
pub(super) fn fit_bands(w: &mut String, d: &StudyData) {
    let Some(b) = d.fit_bands.as_ref().filter(|b| !b.rows.is_empty()) else {
        return;
    };
    let share = |(k, n): (usize, usize)| 100.0 * k as f64 / n.max(1) as f64;
    let _ = writeln!(
        w,
        "## How sure is the regression?
"
    );
    let _ = writeln!(
        w,
        "Every bootstrap resample of the capacity fractiles refitted through both steps \
         (`fit_bands.parquet`): step 1 converged in {} of {} refits ({:.1} %), and {} of {} \
         resamples ({:.1} %) gave all three laws; the {:.0} % bands are over those.\n",
        b.step1_converged.0,
        b.step1_converged.1,
        share(b.step1_converged),
        b.laws_complete.0,
        b.laws_complete.1,
        share(b.laws_complete),
        100.0 * b.rows[0].level
    );
    let _ = writeln!(
        w,
        "| fractile | paper's curve | points (p ≥ 0.5 1/s, every ε) | paper inside the fit's band | median band width / η_c |\n|---|---|---:|---:|---:|"
    );
    let mut widest: f64 = 0.0;
    for (qi, q) in [0.16, 0.5, 0.84].into_iter().enumerate() {
        let rows: Vec<BandPoint> = b
            .rows
            .iter()
            .filter(|r| r.quantile == Some(q) && r.p >= 0.5)
            .filter_map(|r| Some((r.p, r.eps, r.value?, r.lo?, r.hi?)))
            .collect();
        widest = widest.max(paper_against_band(w, qi, &rows));
    }
    wide_band_caveat(w, widest);
    let paper = fragility::paper();
    // The example fragility's median PGA: where each curve crosses 1/2.
    let frag = b.fragility();
    let crossing = |f: &dyn Fn(&crate::tables::fit::FitBandRow) -> Option<f64>| {
        frag.windows(2).find_map(|w| {
            let (g0, g1) = (w[0].pga_g?, w[1].pga_g?);
            let (y0, y1) = (f(w[0])?, f(w[1])?);
            (y0 < 0.5 && y1 >= 0.5).then(|| g0 + (0.5 - y0) / (y1 - y0) * (g1 - g0))
        })
    };
    let block = fragility::example_block();
    let paper_median =
        fragility::median_beta(&paper, block.p(), block.eps).map(|(m, _)| block.alpha() / m);
    // A floor study's fit is in its floor's peak, not the paper's PGA, and
    // text records' in their own peak.
    let on_ground = d.peak() == crate::im::Im::Pga;
    if let (true, Some(mid), Some(lo), Some(hi)) = (
        on_ground,
        crossing(&|r| r.value),
        crossing(&|r| r.hi),
        crossing(&|r| r.lo),
    ) {
        let _ = writeln!(
            w,
            "\nThe example block (half-width b = 0.25 m, half-height h = 1 m, Housner's ε) overturns with probability 1/2 \
             at PGA {mid:.3} g by this study's fit (band {lo:.3}–{hi:.3} g){}.",
            paper_median.map_or(String::new(), |g| format!("; by the paper's, at {g:.3} g"))
        );
    }
    let _ = writeln!(w);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 292 %-wide band gets one paragraph of caveat, its width stated;
    /// a band narrower than its value gets none.
    #[test]
    fn a_band_wider_than_its_value_gets_a_caveat() {
        let mut w = String::new();
        wide_band_caveat(&mut w, 2.92);
        assert!(w.starts_with("\nA band wider than the value itself (here a median of 292 %)"));
        assert_eq!(
            w.lines().count(),
            2,
            "a blank line, then one paragraph: {w:?}"
        );
        assert!(!w.contains("  "), "{w:?}");
        let mut none = String::new();
        wide_band_caveat(&mut none, 0.9);
        assert!(none.is_empty());
    }
}
