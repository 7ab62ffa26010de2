//! The intensity measures ([`Im`]) and every fact about each: its names
//! (the tool's, a table column's, OpenQuake's, pelicun's), its unit, how it
//! scales with the record, its dimensionless form, and which doors it may
//! pass (a capacity, a hazard curve, an export). Everything that lists,
//! parses, checks or names an IM asks it here; nothing else holds a list of
//! IMs (docs/MODEL.md §14).

use std::fmt;
use std::str::FromStr;

/// Standard gravity (m/s²), the g of every IM in g: the block's
/// ([`crate::block::G`]), one value for the tool.
pub const G_M_S2: f64 = crate::block::G;

/// PGV/PGA in s (as [`Im::PgvPga`]) of a motion's PGA in g and PGV in
/// cm/s, OpenQuake's units.
pub fn pgv_pga_s(pga_g: f64, pgv_cm_s: f64) -> f64 {
    (pgv_cm_s / 100.0) / (pga_g * G_M_S2)
}

/// Damping ratio of every spectral IM.
pub const SPECTRAL_DAMPING: f64 = 0.05;

/// The periods (s) at which every record's SA is computed: the periods
/// common to OpenQuake's ground-motion models and hazard outputs.
pub const PERIODS_S: [f64; 15] = [
    0.05, 0.075, 0.1, 0.15, 0.2, 0.25, 0.3, 0.4, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 4.0,
];

/// The periods (s) whose SA AvgSA averages geometrically: those of
/// [`PERIODS_S`] from 0.1 to 2 s. A hazard in AvgSA must be computed over
/// the same periods (OpenQuake's `GenericGmpeAvgSA` takes them as a list).
pub const AVGSA_PERIODS_S: [f64; 11] = [0.1, 0.15, 0.2, 0.25, 0.3, 0.4, 0.5, 0.75, 1.0, 1.5, 2.0];

/// A measure of a ground motion: the intensity measures that scale with
/// the record (a capacity can be stated in them) and the record's
/// properties that do not (its significant duration, PGV/PGA, its mean
/// period: a capacity can be conditioned on them, not stated in them).
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
    /// Significant duration, 5 % to 95 % of the Arias intensity (s).
    D5_95,
    /// PGV/PGA (s), both in SI units.
    PgvPga,
    /// Mean period over 0.25–20 Hz (s; Rathje, Abrahamson & Bray 1998).
    Tm,
    /// Peak floor acceleration (g): the peak absolute acceleration of the
    /// motion the block stands on, its floor's (FEMA P-58's PFA); on the
    /// ground, the record's PGA. A demand of the block's own motion, not a
    /// hazard's: `--direct` only.
    Pfa,
    /// Peak floor velocity (cm/s): the peak absolute velocity of that
    /// motion (FEMA P-58's PFV); on the ground, the record's PGV.
    Pfv,
    /// Floor spectral acceleration at a period (s), in g: the 5 %-damped
    /// pseudo-spectral acceleration of the motion the block stands on (a
    /// floor response spectrum's ordinate); on the ground, SA(T).
    Fsa(f64),
    /// RotD50 of a record pair's PGA, PGV or SA(T): the median over the
    /// angles 0–179° of the rotated component's measure (Boore 2010), the
    /// component the ground-motion models behind a hazard predict. Of a
    /// pair, not of one record (docs/MODEL.md §18).
    RotD50(Rotated),
    /// RotD100: the largest over the angles.
    RotD100(Rotated),
}

/// The one-component measure a RotD percentile is taken of.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Rotated {
    Pga,
    Pgv,
    Sa(f64),
}

impl Rotated {
    /// The one-component measure.
    pub fn im(self) -> Im {
        match self {
            Rotated::Pga => Im::Pga,
            Rotated::Pgv => Im::Pgv,
            Rotated::Sa(t) => Im::Sa(t),
        }
    }

    fn of(im: Im) -> Option<Rotated> {
        match im {
            Im::Pga => Some(Rotated::Pga),
            Im::Pgv => Some(Rotated::Pgv),
            Im::Sa(t) => Some(Rotated::Sa(t)),
            _ => None,
        }
    }
}

/// One member per kind, SA at 1 s standing for every period: the order
/// every list of IMs follows (the capacity measures first).
const KINDS: [Im; 19] = [
    Im::Pga,
    Im::Pgv,
    Im::Pgd,
    Im::AvgSa,
    Im::Arias,
    Im::Cav,
    Im::Sa(1.0),
    Im::D5_95,
    Im::PgvPga,
    Im::Tm,
    Im::Pfa,
    Im::Pfv,
    Im::Fsa(1.0),
    Im::RotD50(Rotated::Pga),
    Im::RotD50(Rotated::Pgv),
    Im::RotD50(Rotated::Sa(1.0)),
    Im::RotD100(Rotated::Pga),
    Im::RotD100(Rotated::Pgv),
    Im::RotD100(Rotated::Sa(1.0)),
];

/// The longest period (s) of the NGA-West2 ground-motion models (0.01 to
/// 10 s; Bozorgnia et al. 2014, Earthquake Spectra 30(3)), and so of a
/// hazard computed from them.
pub const LONGEST_PERIOD_S: f64 = 10.0;

/// What `fragility`, `risk` and the exports may be asked for, and what the
/// record's table holds.
impl Im {
    /// The spectral period of this measure (s), if it has one: SA, FSA,
    /// and a pair's RotD of SA.
    pub fn period_s(self) -> Option<f64> {
        match self {
            Im::Sa(t) | Im::Fsa(t) => Some(t),
            Im::RotD50(Rotated::Sa(t)) | Im::RotD100(Rotated::Sa(t)) => Some(t),
            _ => None,
        }
    }

    /// A caveat for a spectral measure beyond [`LONGEST_PERIOD_S`]: no
    /// hazard model states it, and a record's spectrum there is its
    /// processing's (its high-pass filter's) more than the earthquake's.
    pub fn period_warning(self) -> Option<String> {
        let t = self.period_s().filter(|&t| t > LONGEST_PERIOD_S)?;
        Some(format!(
            "{self} is at a period of {} s, past {LONGEST_PERIOD_S} s, the longest of the \
             NGA-West2 ground-motion models (and of a hazard computed from them): a record's \
             spectrum there is its processing's (its high-pass filter's) more than the \
             earthquake's",
            period_text(t)
        ))
    }

    /// The IMs a capacity is stated and ranked in (the ims stage, the
    /// damage stage's fits): every scaling measure, SA at every period of
    /// [`PERIODS_S`].
    pub fn capacity_measures() -> Vec<Im> {
        Im::expand(|im| im.scales() && !im.floor() && !im.pair())
    }

    /// [`Im::capacity_measures`], or for blocks standing on the records
    /// themselves (text records, a structural model's floor motions;
    /// `stood_on`) the same measures' floor names, [`Im::floor_measures`].
    pub fn capacity_measures_of(stood_on: bool) -> Vec<Im> {
        if stood_on {
            Im::floor_measures()
        } else {
            Im::capacity_measures()
        }
    }

    /// The floor demands a block on a building's floor has its capacity
    /// stated in beside the ground's (a floor study's ims stage): PFA, PFV
    /// and FSA at every period of [`PERIODS_S`], each of the motion the
    /// block feels.
    pub fn floor_measures() -> Vec<Im> {
        Im::expand(|im| im.scales() && im.floor())
    }

    /// A record pair's measures (a study over orientations' ims stage):
    /// RotD50 and RotD100 of PGA, PGV and SA at every period of
    /// [`PERIODS_S`].
    pub fn pair_measures() -> Vec<Im> {
        Im::expand(|im| im.pair())
    }

    /// Every measure computed for a record (`rocking ims`, the
    /// `record_ims` table): the capacity measures, then the record's
    /// properties, then SA by period.
    pub fn record_measures() -> Vec<Im> {
        let mut out: Vec<Im> = KINDS
            .iter()
            .copied()
            .filter(|im| !matches!(im, Im::Sa(_)) && !im.floor() && !im.pair())
            .collect();
        out.extend(PERIODS_S.iter().map(|&t| Im::Sa(t)));
        out
    }

    /// One member of each kind (SA at 1 s standing for every period), in
    /// the order every list follows: to enumerate what a door accepts.
    pub fn kinds() -> [Im; 19] {
        KINDS
    }

    /// The kinds that pass `keep`, SA and FSA expanded to every period of
    /// [`PERIODS_S`] in its place.
    fn expand(keep: impl Fn(Im) -> bool) -> Vec<Im> {
        let mut out = Vec::new();
        for im in KINDS.into_iter().filter(|&im| keep(im)) {
            match im {
                Im::Sa(_) => out.extend(PERIODS_S.iter().map(|&t| Im::Sa(t))),
                Im::Fsa(_) => out.extend(PERIODS_S.iter().map(|&t| Im::Fsa(t))),
                Im::RotD50(Rotated::Sa(_)) => {
                    out.extend(PERIODS_S.iter().map(|&t| Im::RotD50(Rotated::Sa(t))))
                }
                Im::RotD100(Rotated::Sa(_)) => {
                    out.extend(PERIODS_S.iter().map(|&t| Im::RotD100(Rotated::Sa(t))))
                }
                other => out.push(other),
            }
        }
        out
    }

    /// "a, b or c": the names of the kinds that pass `keep` (SA as
    /// `sa(T)`, or `SA(T)` in OpenQuake's names), for messages.
    pub fn listed(keep: impl Fn(Im) -> bool, openquake: bool) -> String {
        let names: Vec<String> = KINDS
            .into_iter()
            .filter(|&im| keep(im))
            .map(|im| match (im, openquake) {
                (Im::Sa(_), false) => "sa(T)".to_string(),
                (Im::Sa(_), true) => "SA(T)".to_string(),
                (Im::Fsa(_), false) => "fsa(T)".to_string(),
                (Im::Fsa(_), true) => "FSA(T)".to_string(),
                (Im::RotD50(Rotated::Sa(_)), false) => "rotd50_sa(T)".to_string(),
                (Im::RotD100(Rotated::Sa(_)), false) => "rotd100_sa(T)".to_string(),
                (Im::RotD50(Rotated::Sa(_)), true) => "RotD50 SA(T)".to_string(),
                (Im::RotD100(Rotated::Sa(_)), true) => "RotD100 SA(T)".to_string(),
                (im, false) => im.name(),
                // RotD50's OpenQuake name is its measure's: say which it is.
                (im, true) if im.pair() => im.short(),
                (im, true) => im.openquake().unwrap_or_else(|| im.short()),
            })
            .collect();
        match names.split_last() {
            None => String::new(),
            Some((last, [])) => last.clone(),
            Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
        }
    }

    /// The name on the command line, in pipelines and in tables: `pga`,
    /// `pgv`, `pgd`, `sa(1.0)`, `avgsa`, `arias`, `cav`, `d5_95`,
    /// `pgv_pga`, `tm`.
    pub fn name(self) -> String {
        match self {
            Im::Pga => "pga".into(),
            Im::Pgv => "pgv".into(),
            Im::Pgd => "pgd".into(),
            Im::Sa(t) => format!("sa({})", period_text(t)),
            Im::Fsa(t) => format!("fsa({})", period_text(t)),
            Im::AvgSa => "avgsa".into(),
            Im::Arias => "arias".into(),
            Im::Cav => "cav".into(),
            Im::D5_95 => "d5_95".into(),
            Im::PgvPga => "pgv_pga".into(),
            Im::Tm => "tm".into(),
            Im::Pfa => "pfa".into(),
            Im::Pfv => "pfv".into(),
            Im::RotD50(r) => format!("rotd50_{}", r.im().name()),
            Im::RotD100(r) => format!("rotd100_{}", r.im().name()),
        }
    }

    /// The name with its unit, as a column or a JSON key: `pga_g`,
    /// `pgv_cm_s`, `sa(1.0)_g`, `cav_g_s`, `d5_95_s`.
    pub fn key(self) -> String {
        format!("{}_{}", self.name(), self.unit().replace(['/', '·'], "_"))
    }

    /// The IM whose [`Im::key`] is `key`, its name as [`Im::from_str`]
    /// reads one (`sa(1)` for `sa(1.0)`, any case) and its unit as the key
    /// writes it (`g`, `cm_s`), in any case.
    pub fn from_key(key: &str) -> Option<Im> {
        // `d5_95_s` and `pgv_pga_s` hold `_` in their names: try every split.
        key.match_indices('_')
            .filter_map(|(i, _)| Some((key[..i].parse::<Im>().ok()?, &key[i + 1..])))
            .find(|(im, unit)| unit.eq_ignore_ascii_case(&im.unit().replace(['/', '·'], "_")))
            .map(|(im, _)| im)
    }

    /// As a reader writes it in a figure's legend: PGA, SA(1.0), AvgSA,
    /// Arias, CAV, D5–95, PGV/PGA, Tm.
    pub fn short(self) -> String {
        match self {
            Im::Pga => "PGA".into(),
            Im::Pgv => "PGV".into(),
            Im::Pgd => "PGD".into(),
            Im::Sa(t) => format!("SA({})", period_text(t)),
            Im::Fsa(t) => format!("FSA({})", period_text(t)),
            Im::AvgSa => "AvgSA".into(),
            Im::Arias => "Arias".into(),
            Im::Cav => "CAV".into(),
            Im::D5_95 => "D5–95".into(),
            Im::PgvPga => "PGV/PGA".into(),
            Im::Tm => "Tm".into(),
            Im::Pfa => "PFA".into(),
            Im::Pfv => "PFV".into(),
            Im::RotD50(r) => format!("RotD50 {}", r.im().short()),
            Im::RotD100(r) => format!("RotD100 {}", r.im().short()),
        }
    }

    /// As a listing of a record's measures names it (`rocking ims`).
    pub fn title(self) -> String {
        match self {
            Im::AvgSa => "AvgSA (0.1–2 s)".into(),
            Im::Arias => "Arias intensity".into(),
            other => other.short(),
        }
    }

    /// The name as OpenQuake writes it in `imt=`, for the measures
    /// OpenQuake's hazard library defines (`openquake.hazardlib.imt`: PGA,
    /// PGV, PGD, SA(T), AvgSA, IA, CAV, RSD595).
    pub fn openquake(self) -> Option<String> {
        match self {
            Im::Pga => Some("PGA".into()),
            Im::Pgv => Some("PGV".into()),
            Im::Pgd => Some("PGD".into()),
            Im::Sa(t) => Some(format!("SA({})", period_text(t))),
            Im::AvgSa => Some("AvgSA".into()),
            Im::Arias => Some("IA".into()),
            Im::Cav => Some("CAV".into()),
            Im::D5_95 => Some("RSD595".into()),
            Im::PgvPga | Im::Tm | Im::Pfa | Im::Pfv | Im::Fsa(_) => None,
            // The ground-motion models' own component: a hazard in PGA is RotD50's.
            Im::RotD50(r) => r.im().openquake(),
            Im::RotD100(_) => None,
        }
    }

    /// pelicun's demand type and unit name, for the measures its damage
    /// model has a demand for (`pelicun.base.EDP_TYPES`, its
    /// `default_units.json`).
    pub fn pelicun(self) -> Option<(String, &'static str)> {
        match self {
            Im::Pga => Some(("Peak Ground Acceleration".into(), "g")),
            Im::Pgv => Some(("Peak Ground Velocity".into(), "cmps")),
            // FEMA P-58's contents components' demands (the DLML's E.20.22).
            Im::Pfa => Some(("Peak Floor Acceleration".into(), "g")),
            Im::Pfv => Some(("Peak Floor Velocity".into(), "cmps")),
            Im::Sa(t) => Some((format!("Spectral Acceleration|{}", period_text(t)), "g")),
            // A demand sample in RotD50 (the hazard's component) is pelicun's PGA, PGV, SA.
            Im::RotD50(r) => r.im().pelicun(),
            _ => None,
        }
    }

    /// The unit its values are given in.
    pub fn unit(self) -> &'static str {
        match self {
            Im::RotD50(r) | Im::RotD100(r) => r.im().unit(),
            Im::Pga | Im::Sa(_) | Im::AvgSa | Im::Pfa | Im::Fsa(_) => "g",
            Im::Pgv | Im::Pfv => "cm/s",
            Im::Pgd => "cm",
            Im::Arias => "m/s",
            Im::Cav => "g·s",
            Im::D5_95 | Im::PgvPga | Im::Tm => "s",
        }
    }

    /// How it scales with the record: a record scaled by `k` has this
    /// measure scaled by `k^power` (0: it does not change).
    pub fn power(self) -> i32 {
        match self {
            Im::Arias => 2,
            Im::D5_95 | Im::PgvPga | Im::Tm => 0,
            _ => 1,
        }
    }

    /// Whether it scales with the record, so that a capacity can be stated
    /// in it (`fragility --im`, the ims and damage stages).
    pub fn scales(self) -> bool {
        self.power() != 0
    }

    /// Whether a hazard curve may be stated in it (`risk --hazard`, the
    /// exports' `--hazard` and `--im`): the capacity measures OpenQuake's
    /// ground-motion models give hazard for at large (PGA, PGV, SA(T),
    /// AvgSA).
    pub fn hazard(self) -> bool {
        matches!(self, Im::Pga | Im::Pgv | Im::Sa(_) | Im::AvgSa)
    }

    /// Whether it is a demand of the motion the block itself feels (PFA,
    /// PFV: its floor's), computed from the block's own runs (`--direct`),
    /// not from a study's ground-motion tables.
    pub fn floor(self) -> bool {
        matches!(self, Im::Pfa | Im::Pfv | Im::Fsa(_))
    }

    /// Whether it is a measure of a record pair (RotD50, RotD100), had
    /// from the pair's two components (`--orientation`, `rocking ims
    /// --pair`), not from one record.
    pub fn pair(self) -> bool {
        matches!(self, Im::RotD50(_) | Im::RotD100(_))
    }

    /// The RotD50 of a one-component measure (PGA, PGV, SA(T)): the
    /// component a hazard in it is of.
    pub fn rotd50(self) -> Option<Im> {
        Rotated::of(self).map(Im::RotD50)
    }

    /// The ground-motion measure it is of the motion the block feels: PGA
    /// for PFA, PGV for PFV (itself otherwise).
    pub fn of_motion(self) -> Im {
        match self {
            Im::Pfa => Im::Pga,
            Im::Pfv => Im::Pgv,
            Im::Fsa(t) => Im::Sa(t),
            other => other,
        }
    }

    /// Whether its name says nothing of the ground (Arias intensity, CAV,
    /// D5–95, Tm): a measure of any motion, a floor's as well.
    pub fn of_any_motion(self) -> bool {
        matches!(self, Im::Arias | Im::Cav | Im::D5_95 | Im::Tm)
    }

    /// The floor demand that is this measure of the motion a block feels
    /// (PFA for PGA, PFV for PGV, FSA(T) for SA(T)): the inverse of
    /// [`Im::of_motion`]; `None` for a measure with no floor name.
    pub fn felt(self) -> Option<Im> {
        match self {
            Im::Pga => Some(Im::Pfa),
            Im::Pgv => Some(Im::Pfv),
            Im::Sa(t) => Some(Im::Fsa(t)),
            _ => None,
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
            Im::Pfa => Some((1.0 / alpha_rad, "PFA/(αg)")),
            Im::Pfv => Some((p / 100.0 / ag, "p·PFV/(αg)")),
            Im::Sa(_) => Some((1.0 / alpha_rad, "SA/(αg)")),
            Im::Fsa(_) => Some((1.0 / alpha_rad, "FSA/(αg)")),
            Im::AvgSa => Some((1.0 / alpha_rad, "AvgSA/(αg)")),
            Im::Pgv => Some((p / 100.0 / ag, "p·PGV/(αg)")),
            Im::Pgd => Some((p * p / 100.0 / ag, "p²·PGD/(αg)")),
            Im::Arias | Im::Cav | Im::D5_95 | Im::PgvPga | Im::Tm => None,
            Im::RotD50(Rotated::Pga) => Some((1.0 / alpha_rad, "RotD50 PGA/(αg)")),
            Im::RotD100(Rotated::Pga) => Some((1.0 / alpha_rad, "RotD100 PGA/(αg)")),
            Im::RotD50(Rotated::Sa(_)) => Some((1.0 / alpha_rad, "RotD50 SA/(αg)")),
            Im::RotD100(Rotated::Sa(_)) => Some((1.0 / alpha_rad, "RotD100 SA/(αg)")),
            Im::RotD50(Rotated::Pgv) => Some((p / 100.0 / ag, "p·RotD50 PGV/(αg)")),
            Im::RotD100(Rotated::Pgv) => Some((p / 100.0 / ag, "p·RotD100 PGV/(αg)")),
        }
    }
}

/// A period as text: Rust's shortest round-trip form, always with a
/// decimal point (`1.0`, `0.05`, `0.075`).
pub fn period_text(t: f64) -> String {
    // Display never uses an exponent and gives the shortest decimal that
    // reads back as `t`; whole seconds keep a `.0`.
    let text = format!("{t}");
    if text.contains(['.', 'i', 'N']) {
        text
    } else {
        format!("{text}.0")
    }
}

pub use crate::decimal::level_text;

impl fmt::Display for Im {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.name())
    }
}

impl FromStr for Im {
    type Err = String;

    /// Any case; `sa(T)` with T in seconds; OpenQuake's names (`IA`, `RSD595`).
    fn from_str(text: &str) -> Result<Self, String> {
        let lower = text.trim().to_ascii_lowercase();
        for (prefix, make) in [
            ("rotd50_", Im::RotD50 as fn(Rotated) -> Im),
            ("rotd100_", Im::RotD100),
        ] {
            if let Some(rest) = lower.strip_prefix(prefix) {
                let of = rest.parse::<Im>().map_err(|e| format!("`{text}`: {e}"))?;
                return Rotated::of(of).map(make).ok_or_else(|| {
                    format!("`{text}`: RotD is taken of pga, pgv or sa(T), not {of}")
                });
            }
        }
        for (prefix, make) in [("sa(", Im::Sa as fn(f64) -> Im), ("fsa(", Im::Fsa)] {
            if let Some(inner) = lower.strip_prefix(prefix).and_then(|r| r.strip_suffix(')')) {
                return match inner.trim().parse::<f64>() {
                    Ok(t) if t > 0.0 && t.is_finite() => Ok(make(t)),
                    _ => Err(format!(
                        "`{text}`: the period of {}T) must be a positive number of seconds, as in \
                         {prefix}1.0)",
                        prefix.to_ascii_uppercase()
                    )),
                };
            }
        }
        let found = KINDS.into_iter().find(|im| {
            !matches!(
                im,
                Im::Sa(_) | Im::Fsa(_) | Im::RotD50(Rotated::Sa(_)) | Im::RotD100(Rotated::Sa(_))
            ) && (im.name() == lower
                || im
                    .openquake()
                    .is_some_and(|o| o.to_ascii_lowercase() == lower))
        });
        found.ok_or_else(|| {
            format!(
                "`{text}` is not an intensity measure; valid: {}",
                Im::listed(|_| true, false).replace(" or ", ", ")
            )
        })
    }
}

crate::deserialize_by_from_str!(Im);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spectra_past_ten_seconds_are_warned_of() {
        for (im, warned) in [
            ("sa(10)", false),
            ("sa(10.5)", true),
            ("fsa(12)", true),
            ("rotd50_sa(20)", true),
            ("rotd100_sa(3)", false),
            ("pga", false),
        ] {
            let im: Im = im.parse().unwrap();
            assert_eq!(im.period_warning().is_some(), warned, "{im}");
        }
        let w = Im::Sa(100.0).period_warning().unwrap();
        assert!(w.contains("100.0 s, past 10 s"), "{w}");
    }

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
    fn names_and_keys_round_trip() {
        for im in Im::record_measures() {
            assert_eq!(im.name().parse::<Im>(), Ok(im));
            assert_eq!(Im::from_key(&im.key()), Some(im), "{}", im.key());
            if let Some(oq) = im.openquake() {
                assert_eq!(oq.parse::<Im>(), Ok(im), "{oq}");
            }
        }
        assert_eq!("SA(1)".parse::<Im>(), Ok(Im::Sa(1.0)));
        assert_eq!(Im::Sa(1.0).name(), "sa(1.0)");
        assert_eq!(Im::Sa(0.075).openquake().unwrap(), "SA(0.075)");
        assert_eq!("PGV".parse::<Im>(), Ok(Im::Pgv));
        assert_eq!("AvgSA".parse::<Im>(), Ok(Im::AvgSa));
        assert_eq!("IA".parse::<Im>(), Ok(Im::Arias));
        // The columns of the plain hazard file and of `rocking ims --json`.
        let keys: Vec<String> = [Im::Pga, Im::Pgv, Im::Cav, Im::Arias, Im::D5_95, Im::PgvPga]
            .iter()
            .map(|im| im.key())
            .collect();
        assert_eq!(
            keys,
            [
                "pga_g",
                "pgv_cm_s",
                "cav_g_s",
                "arias_m_s",
                "d5_95_s",
                "pgv_pga_s"
            ]
        );
        assert_eq!(Im::Sa(1.0).key(), "sa(1.0)_g");
        assert_eq!(Im::from_key("pga_cm"), None);
        assert!("pgv2".parse::<Im>().unwrap_err().contains("valid: pga"));
        assert!("sa(-1)".parse::<Im>().unwrap_err().contains("positive"));
    }

    /// A pair's measures: named `rotd50_<measure>`, in the measure's unit,
    /// RotD50 under OpenQuake's and pelicun's name of the measure (the
    /// models' component), none of the record's own sets.
    #[test]
    fn rotd_measures_are_named_after_their_measure() {
        let r = Im::RotD50(Rotated::Sa(1.0));
        assert_eq!(r.name(), "rotd50_sa(1.0)");
        assert_eq!("RotD50_SA(1)".parse::<Im>(), Ok(r));
        assert_eq!(Im::from_key(&r.key()), Some(r));
        assert_eq!(r.key(), "rotd50_sa(1.0)_g");
        assert_eq!("rotd100_pgv".parse::<Im>(), Ok(Im::RotD100(Rotated::Pgv)));
        assert_eq!(Im::RotD100(Rotated::Pgv).unit(), "cm/s");
        assert_eq!(r.openquake().as_deref(), Some("SA(1.0)"));
        assert_eq!(Im::RotD100(Rotated::Pga).openquake(), None);
        assert_eq!(Im::Pga.rotd50(), Some(Im::RotD50(Rotated::Pga)));
        assert_eq!(Im::Cav.rotd50(), None);
        assert!("rotd50_cav"
            .parse::<Im>()
            .unwrap_err()
            .contains("pga, pgv or sa(T)"));
        assert!(r.scales() && r.pair() && !r.floor() && !r.hazard());
        // Dimensionless as their measure is: RotD50 PGA/(αg) = 5 RotD50 PGA at α = 0.2.
        let (f, name) = Im::RotD50(Rotated::Pga).dimensionless(0.2, 2.0).unwrap();
        assert_eq!((0.2 * f, name), (1.0, "RotD50 PGA/(αg)"));
        let (f, _) = Im::RotD100(Rotated::Pgv).dimensionless(0.2, 2.0).unwrap();
        assert!((98.0665 * f - 1.0).abs() < 1e-14);
        assert!(!Im::capacity_measures().iter().any(|im| im.pair()));
        assert!(!Im::record_measures().iter().any(|im| im.pair()));
    }

    /// The sets by hand: 6 scalar capacity measures and 15 SA periods; the
    /// record's three properties do not scale.
    #[test]
    fn the_sets_by_their_members_answers() {
        let caps = Im::capacity_measures();
        assert_eq!(caps.len(), 6 + PERIODS_S.len());
        assert_eq!(&caps[..3], &[Im::Pga, Im::Pgv, Im::Pgd]);
        assert!(caps.iter().all(|im| im.scales()));
        let all = Im::record_measures();
        assert_eq!(all.len(), 9 + PERIODS_S.len());
        assert!(!Im::Tm.scales() && !Im::D5_95.scales() && !Im::PgvPga.scales());
        assert_eq!(Im::listed(Im::hazard, false), "pga, pgv, avgsa or sa(T)");
        assert_eq!(Im::listed(Im::hazard, true), "PGA, PGV, AvgSA or SA(T)");
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
