//! Intensity measures: a record's IMs, and where a capacity in η becomes a
//! capacity in the IM a user's hazard comes in (pure; docs/MODEL.md §1, §7
//! and §14).
//!
//! The IDA scales every record by one dimensionless number, the uplift
//! strength `η = α g / A_g` (A_g the scaled record's PGA): it runs, stores
//! and searches in η, whatever the IM. Every IM of [`Im`] scales with the
//! record as a power of its amplitude (the first for all but Arias
//! intensity, the second for it), so a record scaled to PGA `A_g` has
//! `IM = IM₀ · (A_g / PGA₀)^power`, and a capacity `η_c` of a block of
//! slenderness α is the IM value of the record scaled to `A_g = αg/η_c`
//! ([`of_eta`]). A record's own IMs ([`RecordIms`], computed in
//! [`record`]) are all this needs of it. The IMs that do not scale (the
//! significant duration, PGV/PGA, the mean period) are record properties
//! in [`RecordIms`] but not capacity measures.
//!
//! Adding an intensity measure: a variant of [`Im`] with its arms in
//! [`Im::name`], [`Im::unit`], [`Im::power`] and [`RecordIms::value`] (the
//! compiler lists them), and the field of [`RecordIms`] that holds it,
//! computed from the record's samples in [`RecordIms::of_record`].

pub mod efficiency;
pub mod record;

use std::fmt;
use std::str::FromStr;

pub use record::{RecordIms, AVGSA_PERIODS_S, PERIODS_S, SPECTRAL_DAMPING};

/// Standard gravity (m/s²), the g of every IM in g.
pub const G_M_S2: f64 = 9.806_65;

/// An intensity measure of a ground motion that scales with the record.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Im {
    /// Peak ground acceleration (g).
    Pga,
    /// Peak ground velocity (cm/s).
    Pgv,
    /// Peak ground displacement (cm).
    Pgd,
    /// 5 %-damped pseudo-spectral acceleration at a period (s), in g.
    Sa(f64),
    /// Geometric mean of SA over [`AVGSA_PERIODS_S`] (g).
    AvgSa,
    /// Arias intensity (m/s); scales with the square of the record.
    Arias,
    /// Cumulative absolute velocity (g·s).
    Cav,
}

impl Im {
    /// The IMs of every record's table and efficiency ranking: the scalar
    /// ones and SA at every period of [`PERIODS_S`].
    pub fn all() -> Vec<Im> {
        let mut all = vec![Im::Pga, Im::Pgv, Im::Pgd, Im::AvgSa, Im::Arias, Im::Cav];
        all.extend(PERIODS_S.iter().map(|&t| Im::Sa(t)));
        all
    }

    /// The name used on the command line, in pipelines and in tables:
    /// `pga`, `pgv`, `pgd`, `sa(1.0)`, `avgsa`, `arias`, `cav`.
    pub fn name(self) -> String {
        match self {
            Im::Pga => "pga".into(),
            Im::Pgv => "pgv".into(),
            Im::Pgd => "pgd".into(),
            Im::Sa(t) => format!("sa({})", period_text(t)),
            Im::AvgSa => "avgsa".into(),
            Im::Arias => "arias".into(),
            Im::Cav => "cav".into(),
        }
    }

    /// The name as OpenQuake writes it in `imt=` (`PGA`, `PGV`, `SA(1.0)`,
    /// `AvgSA`), for the IMs OpenQuake computes hazard for.
    pub fn openquake(self) -> Option<String> {
        match self {
            Im::Pga => Some("PGA".into()),
            Im::Pgv => Some("PGV".into()),
            Im::Pgd => Some("PGD".into()),
            Im::Sa(t) => Some(format!("SA({})", period_text(t))),
            Im::AvgSa => Some("AvgSA".into()),
            Im::Arias => Some("IA".into()),
            Im::Cav => None,
        }
    }

    /// The unit its values are given in.
    pub fn unit(self) -> &'static str {
        match self {
            Im::Pga | Im::Sa(_) | Im::AvgSa => "g",
            Im::Pgv => "cm/s",
            Im::Pgd => "cm",
            Im::Arias => "m/s",
            Im::Cav => "g·s",
        }
    }

    /// How it scales with the record: a record scaled by `k` has this IM
    /// scaled by `k^power`.
    pub fn power(self) -> i32 {
        match self {
            Im::Arias => 2,
            _ => 1,
        }
    }

    /// Its standard dimensionless form for a block of slenderness α and
    /// frequency parameter p (1/s), where there is one: the factor that
    /// multiplies the IM, and its name. PGA/(αg) is 1/η (Housner; the
    /// paper), p·PGV/(αg) and p²·PGD/(αg) follow from the similarity
    /// groups of Dimitrakopoulos & DeJong (2012), SA/(αg) as the PGA.
    pub fn dimensionless(self, alpha_rad: f64, p: f64) -> Option<(f64, &'static str)> {
        let ag = alpha_rad * G_M_S2;
        match self {
            Im::Pga => Some((1.0 / alpha_rad, "PGA/(αg)")),
            Im::Sa(_) => Some((1.0 / alpha_rad, "SA/(αg)")),
            Im::AvgSa => Some((1.0 / alpha_rad, "AvgSA/(αg)")),
            Im::Pgv => Some((p / 100.0 / ag, "p·PGV/(αg)")),
            Im::Pgd => Some((p * p / 100.0 / ag, "p²·PGD/(αg)")),
            Im::Arias | Im::Cav => None,
        }
    }
}

/// A period as text: Rust's shortest round-trip form, always with a
/// decimal point (`1.0`, `0.05`, `0.075`).
pub fn period_text(t: f64) -> String {
    format!("{t:?}")
}

/// A level of an IM as printed: four significant digits, trailing zeros
/// dropped (0.05 g, 2 g, 48.31 cm/s, 300 cm/s).
pub fn level_text(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let decimals = (3 - v.abs().log10().floor() as i32).max(0) as usize;
    let text = format!("{v:.decimals$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    }
}

impl fmt::Display for Im {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.name())
    }
}

impl FromStr for Im {
    type Err = String;

    /// Any case; `sa(T)` with T in seconds; OpenQuake's `IA` for Arias.
    fn from_str(text: &str) -> Result<Self, String> {
        let lower = text.trim().to_ascii_lowercase();
        let scalar = match lower.as_str() {
            "pga" => Some(Im::Pga),
            "pgv" => Some(Im::Pgv),
            "pgd" => Some(Im::Pgd),
            "avgsa" => Some(Im::AvgSa),
            "arias" | "ia" => Some(Im::Arias),
            "cav" => Some(Im::Cav),
            _ => None,
        };
        if let Some(im) = scalar {
            return Ok(im);
        }
        if let Some(inner) = lower.strip_prefix("sa(").and_then(|r| r.strip_suffix(')')) {
            return match inner.trim().parse::<f64>() {
                Ok(t) if t > 0.0 && t.is_finite() => Ok(Im::Sa(t)),
                _ => Err(format!(
                    "`{text}`: the period of SA(T) must be a positive number of seconds, as in sa(1.0)"
                )),
            };
        }
        Err(format!(
            "`{text}` is not an intensity measure; valid: pga, pgv, pgd, sa(T) with T in s, avgsa, arias, cav"
        ))
    }
}

/// The PGA (g) at which a block of slenderness `alpha_rad` feels the
/// uplift strength `eta`: `A_g/g = α/η`.
pub fn pga_of_eta(eta: f64, alpha_rad: f64) -> f64 {
    alpha_rad / eta
}

/// The uplift strength η at PGA `pga_g` (g) for slenderness `alpha_rad`:
/// `η = α g / A_g`.
pub fn eta_of_pga(pga_g: f64, alpha_rad: f64) -> f64 {
    alpha_rad / pga_g
}

/// `im` of a record scaled to uplift strength `eta` for a block of
/// slenderness `alpha_rad`; `None` when the record's `im` is not known (an
/// SA period not computed).
pub fn of_eta(im: Im, eta: f64, alpha_rad: f64, record: &RecordIms) -> Option<f64> {
    if im == Im::Pga {
        // Exact: α/η to the bit.
        return Some(pga_of_eta(eta, alpha_rad));
    }
    let scale = pga_of_eta(eta, alpha_rad) / record.pga_g;
    Some(record.value(im)? * scale.powi(im.power()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levels_print_with_four_significant_digits_and_no_trailing_zeros() {
        for (v, text) in [
            (0.05, "0.05"),
            (2.0, "2"),
            (300.0, "300"),
            (48.312332, "48.31"),
            (0.530449, "0.5304"),
            (12345.6, "12346"),
            (0.0, "0"),
            (-1.5, "-1.5"),
        ] {
            assert_eq!(level_text(v), text, "{v}");
        }
    }

    #[test]
    fn pga_and_eta_are_inverse_through_alpha() {
        // η = α g / A_g: a block with α = 0.25 rad uplifts at 0.25 g (η = 1)
        // and feels η = 0.5 at 0.5 g.
        assert_eq!(pga_of_eta(1.0, 0.25), 0.25);
        assert_eq!(eta_of_pga(0.5, 0.25), 0.5);
        for &eta in &[0.01, 0.3, 1.0] {
            let back = eta_of_pga(pga_of_eta(eta, 0.2), 0.2);
            assert!((back - eta).abs() <= 1e-15 * eta);
        }
    }

    /// Scaling a record to a capacity scales its linear IMs by the PGA's
    /// ratio and its Arias intensity by the ratio squared: the record
    /// recomputed at that scale gives the same values.
    #[test]
    fn a_capacity_in_any_im_is_the_scaled_record_s_im() {
        let dt = 0.01;
        let accel: Vec<f64> = (0..1500)
            .map(|k| {
                let t = k as f64 * dt;
                0.3 * (4.0 * t).sin() * (-0.3 * t).exp()
            })
            .collect();
        let ims = RecordIms::of_record(&accel, dt, &[]).unwrap();
        let (eta, alpha) = (0.4, 0.2);
        let k = pga_of_eta(eta, alpha) / ims.pga_g;
        let scaled: Vec<f64> = accel.iter().map(|a| a * k).collect();
        let direct = RecordIms::of_record(&scaled, dt, &[]).unwrap();
        for im in Im::all() {
            let via = of_eta(im, eta, alpha, &ims).unwrap();
            let want = direct.value(im).unwrap();
            assert!((via / want - 1.0).abs() < 1e-12, "{im}: {via} vs {want}");
        }
        assert_eq!(of_eta(Im::Pga, eta, alpha, &ims), Some(0.5));
        assert_eq!(of_eta(Im::Sa(0.33), eta, alpha, &ims), None);
    }

    #[test]
    fn names_round_trip() {
        for im in Im::all() {
            assert_eq!(im.name().parse::<Im>(), Ok(im));
        }
        assert_eq!("SA(1)".parse::<Im>(), Ok(Im::Sa(1.0)));
        assert_eq!(Im::Sa(1.0).name(), "sa(1.0)");
        assert_eq!(Im::Sa(0.075).openquake().unwrap(), "SA(0.075)");
        assert_eq!("PGV".parse::<Im>(), Ok(Im::Pgv));
        assert_eq!("AvgSA".parse::<Im>(), Ok(Im::AvgSa));
        assert!("pgv2".parse::<Im>().unwrap_err().contains("valid: pga"));
        assert!("sa(-1)".parse::<Im>().unwrap_err().contains("positive"));
    }

    /// The dimensionless forms by hand: α = 0.2 rad, p = 2 1/s; PGV 98.0665
    /// cm/s is 0.980665 m/s, so p·PGV/(αg) = 2·0.980665/(0.2·9.80665) = 1.
    #[test]
    fn dimensionless_forms_by_hand() {
        let (f, name) = Im::Pgv.dimensionless(0.2, 2.0).unwrap();
        assert!((98.0665 * f - 1.0).abs() < 1e-14, "{name}");
        let (f, _) = Im::Pga.dimensionless(0.2, 2.0).unwrap();
        assert_eq!(0.2 * f, 1.0);
        assert!(Im::Cav.dimensionless(0.2, 2.0).is_none());
    }
}
