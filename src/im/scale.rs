//! A capacity in η as a capacity in any IM (docs/MODEL.md §14).
//!
//! The IDA scales every record by one dimensionless number, the uplift
//! strength `η = α g / A_g` (A_g the scaled record's PGA). Every IM that
//! scales ([`Im::scales`]) does so as a power of the record's amplitude,
//! so a record scaled to PGA `A_g` has `IM = IM₀ · (A_g / PGA₀)^power`,
//! and a capacity `η_c` of a block of slenderness α is the IM value of the
//! record scaled to `A_g = αg/η_c` ([`of_eta`]).

use super::measure::Im;
use super::record::RecordIms;

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
    if im.of_motion() == Im::Pga {
        // Exact: α/η to the bit (PFA too, of the motion the block feels).
        return Some(pga_of_eta(eta, alpha_rad));
    }
    let scale = pga_of_eta(eta, alpha_rad) / record.pga_g();
    Some(record.value(im)? * scale.powi(im.power()))
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

    /// Scaling a record to a capacity scales its linear IMs by the PGA's
    /// ratio, its Arias intensity by the ratio squared and leaves its
    /// properties (duration, PGV/PGA, mean period) as they are: the record
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
        let k = pga_of_eta(eta, alpha) / ims.pga_g();
        let scaled: Vec<f64> = accel.iter().map(|a| a * k).collect();
        let direct = RecordIms::of_record(&scaled, dt, &[]).unwrap();
        for im in Im::record_measures() {
            let via = of_eta(im, eta, alpha, &ims).unwrap();
            let want = direct.value(im).unwrap();
            assert!((via / want - 1.0).abs() < 1e-9, "{im}: {via} vs {want}");
        }
        assert_eq!(of_eta(Im::Pga, eta, alpha, &ims), Some(0.5));
        assert_eq!(of_eta(Im::Sa(0.33), eta, alpha, &ims), None);
    }
}
