//! How well each IM predicts a block's overturning: the dispersion of its
//! capacities over the records (pure; docs/MODEL.md §14).
//!
//! A record i that overturns the block at η_c,i does so when scaled to PGA
//! αg/η_c,i, i.e. at `IM_c,i = IM_i · (α / (η_c,i PGA_i))^power` (PGA_i and
//! IM_i the unscaled record's). With ln IM_c taken as normal over the
//! records, the IM's dispersion β is the sample standard deviation of
//! ln IM_c,i: the smaller, the better the IM predicts overturning (the
//! "efficiency" of Luco & Cornell 2007). β does not depend on α (a constant
//! shift of every ln IM_c), so blocks of the linearised model, which have
//! no α, are ranked too; their medians are given in dimensionless form.

use super::{pgv_pga_s, Im, RecordIms};
use crate::stats;

/// One IM's capacities for one block.
#[derive(Debug, Clone, PartialEq)]
pub struct Efficiency {
    /// The IM's name (`pga`, `sa(1.0)`, …), or `pga | pgv/pga` for the
    /// vector of PGA and PGV/PGA.
    pub im: String,
    pub unit: &'static str,
    /// Records that overturn the block within the grid (the others are not
    /// counted).
    pub n: usize,
    /// exp(mean ln IM_c), in `unit`; `None` for a block without α.
    pub median: Option<f64>,
    /// The median in the IM's standard dimensionless form, and its name.
    pub median_dimensionless: Option<(f64, &'static str)>,
    /// Sample standard deviation of ln IM_c (n − 1); for the vector, of the
    /// residuals of ln PGA_c on ln(PGV/PGA) (n − 2).
    pub beta: f64,
    /// Lilliefors p-value of ln IM_c (of the residuals for the vector).
    pub lilliefors_p: Option<f64>,
    /// For the vector: d ln PGA_c / d ln(PGV/PGA).
    pub slope: Option<f64>,
}

/// Every IM of [`Im::capacity_measures`] for one block of frequency parameter `p` (1/s)
/// and slenderness `alpha_rad` (if it has one), from each record's η_c
/// (`None`: never overturned) and IMs, in the same order; then the vector
/// (PGA, PGV/PGA). Empty with fewer than 3 capacities.
pub fn of_block(
    eta_c: &[Option<f64>],
    records: &[RecordIms],
    p: f64,
    alpha_rad: Option<f64>,
) -> Vec<Efficiency> {
    let pairs = overturned(eta_c, records);
    let mut out = measures(&pairs, &Im::capacity_measures(), p, alpha_rad);
    if !out.is_empty() {
        out.extend(vector(&pairs));
    }
    out
}

/// Each of `ims` for one block, as [`of_block`] states them but without the
/// vector: the floor demands of [`Im::floor_measures`] from each record's
/// η_c *of the floor motion* and the floor motion's IMs (whose PGA is the
/// PFA), or a record pair's [`Im::pair_measures`] from each motion's η_c
/// and IMs (its pair's among them, unscaled). Empty with fewer than 3
/// capacities.
pub fn of_measures(
    eta_c: &[Option<f64>],
    records: &[RecordIms],
    ims: &[Im],
    p: f64,
    alpha_rad: Option<f64>,
) -> Vec<Efficiency> {
    measures(&overturned(eta_c, records), ims, p, alpha_rad)
}

/// The records that overturn the block, with their η_c.
fn overturned<'a>(eta_c: &[Option<f64>], records: &'a [RecordIms]) -> Vec<(f64, &'a RecordIms)> {
    assert_eq!(eta_c.len(), records.len(), "one η_c per record");
    eta_c
        .iter()
        .zip(records)
        .filter_map(|(e, r)| e.filter(|e| *e > 0.0).map(|e| (e, r)))
        .collect()
}

/// Each of `ims` for the overturning records `pairs` (none with fewer than 3).
fn measures(
    pairs: &[(f64, &RecordIms)],
    ims: &[Im],
    p: f64,
    alpha_rad: Option<f64>,
) -> Vec<Efficiency> {
    if pairs.len() < 3 {
        return Vec::new();
    }
    ims.iter()
        .filter_map(|&im| {
            // ln IM_c at α = 1: ln IM − power (ln PGA + ln η_c).
            let logs = pairs
                .iter()
                .map(|(eta, r)| {
                    let k = f64::from(im.power());
                    Some(r.value(im)?.ln() - k * (r.pga_g().ln() + eta.ln()))
                })
                .collect::<Option<Vec<f64>>>()?;
            let (mean, beta) = stats::mean_sd(&logs);
            let power = f64::from(im.power());
            Some(Efficiency {
                im: im.name(),
                unit: im.unit(),
                n: logs.len(),
                median: alpha_rad.map(|a| (mean + power * a.ln()).exp()),
                median_dimensionless: im
                    .dimensionless(1.0, p)
                    .map(|(factor, name)| (factor * mean.exp(), name)),
                beta,
                lilliefors_p: stats::lilliefors(&logs).map(|t| t.p_value),
                slope: None,
            })
        })
        .collect()
}

/// ln PGA_c on ln(PGV/PGA) by least squares: P(OT | PGA, PGV/PGA) is
/// lognormal in PGA with median exp(a + b ln(PGV/PGA)) and dispersion the
/// residuals' standard deviation. PGV/PGA does not change with scaling, so
/// it is a property of the record the capacity can be conditioned on.
fn vector(pairs: &[(f64, &RecordIms)]) -> Option<Efficiency> {
    let fit = vector_fit(pairs)?;
    Some(Efficiency {
        im: VECTOR.to_string(),
        unit: "g",
        n: fit.n,
        median: None,
        median_dimensionless: None,
        beta: fit.beta,
        lilliefors_p: fit.lilliefors_p,
        slope: Some(fit.slope),
    })
}

/// The two-parameter capacity of a block: ln(PGA_c/(αg)) = ln(1/η_c)
/// regressed on ln(PGV/PGA) of the record (in s, as [`Im::PgvPga`]) over the
/// records that overturn it (least squares), its residuals' β (n − 2).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct VectorFit {
    /// The means of ln(PGV/PGA) and of ln(1/η_c) over the records.
    pub mean_ln_ratio: f64,
    pub mean_ln_inv_eta: f64,
    /// d ln PGA_c / d ln(PGV/PGA).
    pub slope: f64,
    pub beta: f64,
    pub n: usize,
    pub lilliefors_p: Option<f64>,
    /// The records' smallest and largest PGV/PGA (s): beyond them the fit
    /// extrapolates.
    pub ratio_range_s: (f64, f64),
}

impl VectorFit {
    /// The median capacity in PGA (g) of a block of slenderness `alpha_rad`
    /// under a motion of PGV/PGA `ratio_s` (s: PGV in m/s over PGA in m/s²,
    /// as [`Im::PgvPga`]).
    pub fn median_pga(&self, alpha_rad: f64, ratio_s: f64) -> f64 {
        alpha_rad * (self.mean_ln_inv_eta + self.slope * (ratio_s.ln() - self.mean_ln_ratio)).exp()
    }

    /// P(overturn | PGA = `pga_g` (g), PGV = `pgv_cm_s` (cm/s)):
    /// Φ(ln(PGA/median(PGV/PGA))/β).
    pub fn probability(&self, alpha_rad: f64, pga_g: f64, pgv_cm_s: f64) -> f64 {
        if !(pga_g > 0.0 && pgv_cm_s > 0.0) {
            return 0.0;
        }
        let median = self.median_pga(alpha_rad, pgv_pga_s(pga_g, pgv_cm_s));
        crate::damage::Lognormal {
            median,
            beta: self.beta,
        }
        .cdf(pga_g)
    }
}

/// [`VectorFit`] of one block from each record's η_c (`None`: never
/// overturned) and IMs (their PGV/PGA); `None` with fewer than 4
/// overturning records or one ratio for all.
pub fn vector_of_block(eta_c: &[Option<f64>], records: &[RecordIms]) -> Option<VectorFit> {
    vector_fit(&overturned(eta_c, records))
}

fn vector_fit(pairs: &[(f64, &RecordIms)]) -> Option<VectorFit> {
    if pairs.len() < 4 {
        return None;
    }
    let x: Vec<f64> = pairs
        .iter()
        .map(|(_, r)| Some(r.value(Im::PgvPga)?.ln()))
        .collect::<Option<_>>()?;
    let y: Vec<f64> = pairs.iter().map(|(eta, _)| -eta.ln()).collect();
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxx: f64 = x.iter().map(|v| (v - mx) * (v - mx)).sum();
    if sxx <= 0.0 {
        return None;
    }
    let sxy: f64 = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let slope = sxy / sxx;
    let residuals: Vec<f64> = x
        .iter()
        .zip(&y)
        .map(|(a, b)| b - my - slope * (a - mx))
        .collect();
    let ss: f64 = residuals.iter().map(|r| r * r).sum();
    Some(VectorFit {
        mean_ln_ratio: mx,
        mean_ln_inv_eta: my,
        slope,
        beta: (ss / (n - 2.0)).sqrt(),
        n: residuals.len(),
        lilliefors_p: stats::lilliefors(&residuals).map(|t| t.p_value),
        ratio_range_s: (
            x.iter().copied().fold(f64::INFINITY, f64::min).exp(),
            x.iter().copied().fold(f64::NEG_INFINITY, f64::max).exp(),
        ),
    })
}

/// The name of the vector IM's row.
pub const VECTOR: &str = "pga | pgv/pga";

#[cfg(test)]
mod tests {
    use super::*;

    fn record(pga: f64, pgv: f64) -> RecordIms {
        let mut values: Vec<(Im, f64)> = Im::record_measures()
            .into_iter()
            .filter(|im| !matches!(im, Im::Sa(_)))
            .map(|im| (im, 1.0))
            .collect();
        values[0] = (Im::Pga, pga);
        values[1] = (Im::Pgv, pgv);
        let ratio = values.iter_mut().find(|(im, _)| *im == Im::PgvPga).unwrap();
        ratio.1 = pgv / 100.0 / (pga * super::super::G_M_S2);
        values.push((Im::Sa(1.0), 2.0 * pga));
        RecordIms::from_values(values).unwrap()
    }

    /// Capacities that are exactly a constant PGV (each record overturns
    /// the block when its PGV reaches 50 cm/s): β of PGV is 0, β of PGA is
    /// the spread of the records' PGA/PGV, the vector explains it all with
    /// slope −1, and SA(1.0) (a fixed multiple of PGA here) has PGA's β.
    #[test]
    fn a_block_that_follows_pgv() {
        let alpha = 0.2;
        let records: Vec<RecordIms> = [
            (0.2, 20.0),
            (0.5, 30.0),
            (0.3, 45.0),
            (0.4, 25.0),
            (0.25, 60.0),
        ]
        .iter()
        .map(|&(a, v)| record(a, v))
        .collect();
        // PGV_c = 50: the scale factor is 50/PGV, the PGA at overturning 50 PGA/PGV.
        let eta: Vec<Option<f64>> = records
            .iter()
            .map(|r| Some(alpha / (r.pga_g() * 50.0 / r.value(Im::Pgv).unwrap())))
            .collect();
        let all = of_block(&eta, &records, 2.0, Some(alpha));
        let get = |name: &str| all.iter().find(|e| e.im == name).unwrap();
        assert!(get("pgv").beta < 1e-12);
        assert!((get("pgv").median.unwrap() - 50.0).abs() < 1e-9);
        let ln_ratio: Vec<f64> = records
            .iter()
            .map(|r| (r.pga_g() / r.value(Im::Pgv).unwrap()).ln())
            .collect();
        let (_, sd) = stats::mean_sd(&ln_ratio);
        assert!((get("pga").beta - sd).abs() < 1e-12);
        assert!((get("sa(1.0)").beta - sd).abs() < 1e-12);
        let v = get(VECTOR);
        assert!(
            v.beta < 1e-9 && (v.slope.unwrap() + 1.0).abs() < 1e-9,
            "{v:?}"
        );
        // Without α: the same β, no dimensional median, the dimensionless one
        // p·PGV/(αg) = 2 · 0.5 m/s / (0.2 · 9.80665).
        let no_alpha = of_block(&eta, &records, 2.0, None);
        let pgv = no_alpha.iter().find(|e| e.im == "pgv").unwrap();
        assert!(pgv.median.is_none());
        let (d, _) = pgv.median_dimensionless.unwrap();
        // At α = 1 the capacities are 50/0.2 = 250 cm/s: 2·2.5/9.80665.
        assert!((d - 2.0 * 2.5 / 9.80665).abs() < 1e-12, "{d}");
    }

    /// A floor motion's demands are its own PGA, PGV and SA: the same
    /// capacities stated in PFA, PFV and FSA(1.0) of the motion the block
    /// feels equal those in PGA, PGV and SA(1.0) of that motion run as a
    /// record (FEMA's PFV of a constant-PGV block has β = 0, median 50 cm/s).
    #[test]
    fn floor_demands_are_the_felt_motions_own_measures() {
        let felt: Vec<RecordIms> = [(0.4, 35.0), (0.8, 50.0), (0.6, 90.0), (0.5, 40.0)]
            .iter()
            .map(|&(a, v)| record(a, v))
            .collect();
        let alpha = 0.25;
        let eta: Vec<Option<f64>> = felt
            .iter()
            .map(|r| Some(alpha / (r.pga_g() * 50.0 / r.value(Im::Pgv).unwrap())))
            .collect();
        let ground = of_block(&eta, &felt, 3.0, Some(alpha));
        let floor = of_measures(&eta, &felt, &Im::floor_measures(), 3.0, Some(alpha));
        let names: Vec<&str> = floor.iter().map(|e| e.im.as_str()).collect();
        assert_eq!(names, ["pfa", "pfv", "fsa(1.0)"]);
        for (f, g) in floor.iter().zip(["pga", "pgv", "sa(1.0)"]) {
            let g = ground.iter().find(|e| e.im == g).unwrap();
            assert_eq!((f.median, f.beta, f.n), (g.median, g.beta, g.n));
        }
        assert!((floor[1].median.unwrap() - 50.0).abs() < 1e-9 && floor[1].beta < 1e-12);
        assert_eq!(floor[1].unit, "cm/s");
    }

    #[test]
    fn records_that_never_overturn_are_left_out() {
        let records: Vec<RecordIms> = (0..5).map(|k| record(0.1 + 0.1 * k as f64, 30.0)).collect();
        let eta = [Some(0.5), None, Some(0.4), Some(0.3), Some(0.2)];
        let all = of_block(&eta, &records, 1.0, Some(0.1));
        assert_eq!(all[0].n, 4);
        assert!(of_block(&[None, None, Some(0.1)], &records[..3], 1.0, None).is_empty());
    }
}
