//! Intensity measures: where a capacity in η becomes a capacity in the IM a
//! user's hazard comes in (pure; docs/MODEL.md §1 and §7).
//!
//! The IDA scales every record by one dimensionless number, the uplift
//! strength `η = α g / A_g` (A_g the scaled record's PGA): it runs, stores
//! and searches in η, whatever the IM. Every IM used here scales linearly
//! with the record, so a record scaled to PGA `A_g` has
//! `IM = (IM per g of PGA) · A_g`, and a capacity `η_c` of a block of
//! slenderness α is the IM value `(IM per g of PGA) · α / η_c`. A record's
//! IMs per g of PGA ([`RecordIms`]) are all this module needs of it.
//!
//! Adding an intensity measure: a variant of [`Im`] with its arms in
//! [`Im::name`], [`Im::unit`] and [`RecordIms::per_pga`] (the compiler
//! lists them), and the field of [`RecordIms`] that holds it, computed from
//! the record's samples in [`RecordIms::of_record`].

use std::fmt;
use std::str::FromStr;

/// An intensity measure of a ground motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Im {
    /// Peak ground acceleration (g).
    Pga,
}

impl Im {
    /// Every IM, in the order tables and reports list them.
    pub const ALL: [Im; 1] = [Im::Pga];

    /// The name used on the command line, in pipelines and in tables.
    pub fn name(self) -> &'static str {
        match self {
            Im::Pga => "pga",
        }
    }

    /// The unit its values are given in.
    pub fn unit(self) -> &'static str {
        match self {
            Im::Pga => "g",
        }
    }
}

impl fmt::Display for Im {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Im {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, String> {
        Im::ALL
            .into_iter()
            .find(|im| im.name() == text)
            .ok_or_else(|| {
                let names: Vec<_> = Im::ALL.iter().map(|im| im.name()).collect();
                format!(
                    "`{text}` is not an intensity measure; valid: {}",
                    names.join(", ")
                )
            })
    }
}

/// A record's intensity measures per g of its PGA: what converts η into
/// any IM for that record.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RecordIms {
    /// The record's own PGA (g), before any scaling.
    pub pga_g: f64,
}

impl RecordIms {
    /// The IMs of a record sampled at `dt_s` (accelerations in g); `None`
    /// for a record without a positive peak.
    pub fn of_record(accel_g: &[f64], dt_s: f64) -> Option<RecordIms> {
        let peak = crate::motion::peak(accel_g, dt_s)?;
        (peak.pga_g > 0.0).then_some(RecordIms { pga_g: peak.pga_g })
    }

    /// `im` of this record per g of its PGA.
    pub fn per_pga(&self, im: Im) -> f64 {
        match im {
            Im::Pga => 1.0,
        }
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
/// slenderness `alpha_rad`.
pub fn of_eta(im: Im, eta: f64, alpha_rad: f64, record: &RecordIms) -> f64 {
    // For the PGA the factor is 1.0, and a product by 1.0 is exact: α/η to the bit.
    record.per_pga(im) * pga_of_eta(eta, alpha_rad)
}

#[cfg(test)]
mod tests {
    use super::*;

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

    #[test]
    fn a_record_s_ims_come_from_its_samples() {
        let ims = RecordIms::of_record(&[0.0, 0.1, -0.4, 0.2], 0.01).unwrap();
        assert_eq!(ims.pga_g, 0.4);
        assert_eq!(ims.per_pga(Im::Pga), 1.0);
        assert_eq!(of_eta(Im::Pga, 0.5, 0.2, &ims), 0.4);
        assert!(RecordIms::of_record(&[0.0, 0.0], 0.01).is_none());
        assert!(RecordIms::of_record(&[], 0.01).is_none());
    }

    #[test]
    fn names_round_trip() {
        for im in Im::ALL {
            assert_eq!(im.name().parse::<Im>(), Ok(im));
        }
        assert!("pgv2".parse::<Im>().unwrap_err().contains("valid: pga"));
    }
}
