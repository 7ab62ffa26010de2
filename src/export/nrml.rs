//! OpenQuake's NRML 0.5: a `fragilityModel` of the contents loss category
//! (free-standing blocks are a building's contents; OpenQuake reads
//! structural, nonstructural, contents and business_interruption), each
//! block's function a continuous lognormal or, for the records' curve, a
//! discrete one (OpenQuake interpolates its levels linearly and holds the
//! last value beyond them); an `exposureModel` placing each block at each
//! site, valued in contents; and a `job.ini` for a `classical_damage`
//! calculation on precomputed hazard curves.
//!
//! OpenQuake's `logncdf` takes the mean and standard deviation of the IML
//! itself, not of its logarithm: for a median θ and dispersion β,
//! mean = θ·exp(β²/2) and stddev = mean·√(exp(β²) − 1)
//! (`openquake.risklib.scientific.FragilityFunctionContinuous`).

use std::fmt::Write;

use super::{iml_range, merged_levels, openquake_imt, Entry, ExportError, Shape, Site};
use crate::damage::Lognormal;
use crate::im::Im;

/// The file names the job refers to.
pub const FRAGILITY_FILE: &str = "fragility_model.xml";
pub const EXPOSURE_FILE: &str = "exposure_model.xml";
pub const ASSETS_FILE: &str = "assets.csv";
pub const HAZARD_FILE: &str = "hazard_curves.csv";
pub const JOB_FILE: &str = "job.ini";

/// OpenQuake's (mean, stddev) of the IML for a median and a β.
pub fn mean_stddev(l: &Lognormal) -> (f64, f64) {
    let mean = l.median * (0.5 * l.beta * l.beta).exp();
    (mean, mean * (l.beta * l.beta).exp_m1().sqrt())
}

/// XML text with its five special characters escaped.
fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
        .replace('\'', "&apos;")
}

/// The fragility model: one `fragilityFunction` per block.
pub fn fragility_model(
    entries: &[Entry],
    limit_states: &[String],
    im: Im,
    description: &str,
) -> Result<String, ExportError> {
    super::check_entries(entries)?;
    let imt = openquake_imt(im)?;
    let mut x = String::new();
    let _ = writeln!(x, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(x, r#"<nrml xmlns="http://openquake.org/xmlns/nrml/0.5">"#);
    let _ = writeln!(
        x,
        r#"<fragilityModel id="rocking" assetCategory="buildings" lossCategory="contents">"#
    );
    let _ = writeln!(x, "  <description>{}</description>", escape(description));
    let _ = writeln!(x, "  <limitStates>{}</limitStates>", limit_states.join(" "));
    for e in entries {
        let _ = writeln!(
            x,
            "  <!-- {} -->",
            escape(&e.description).replace("--", "- -")
        );
        let no_damage = e
            .no_damage_limit
            .map_or(String::new(), |v| format!(r#" noDamageLimit="{v:e}""#));
        match &e.states {
            Shape::Lognormal(states) => {
                let _ = writeln!(
                    x,
                    r#"  <fragilityFunction id="{}" format="continuous" shape="logncdf">"#,
                    escape(&e.id)
                );
                let (lo, hi) = iml_range(states);
                let _ = writeln!(
                    x,
                    r#"    <imls imt="{imt}"{no_damage} minIML="{lo:e}" maxIML="{hi:e}"/>"#
                );
                for (ls, l) in limit_states.iter().zip(states) {
                    let (mean, stddev) = mean_stddev(l);
                    let _ = writeln!(
                        x,
                        r#"    <params ls="{ls}" mean="{mean:e}" stddev="{stddev:e}"/>"#
                    );
                }
            }
            Shape::Curve(curves) => {
                let _ = writeln!(
                    x,
                    r#"  <fragilityFunction id="{}" format="discrete">"#,
                    escape(&e.id)
                );
                let levels = merged_levels(curves);
                let _ = writeln!(
                    x,
                    r#"    <imls imt="{imt}"{no_damage}>{}</imls>"#,
                    spaced(levels.iter().copied())
                );
                for (ls, c) in limit_states.iter().zip(curves) {
                    let poes = levels.iter().map(|&a| c.probability(a));
                    let _ = writeln!(x, r#"    <poes ls="{ls}">{}</poes>"#, spaced(poes));
                }
            }
        }
        let _ = writeln!(x, "  </fragilityFunction>");
    }
    let _ = writeln!(x, "</fragilityModel>");
    let _ = writeln!(x, "</nrml>");
    Ok(x)
}

/// Values separated by spaces, each in its shortest exact form.
fn spaced(values: impl Iterator<Item = f64>) -> String {
    values
        .map(|v| format!("{v:e}"))
        .collect::<Vec<_>>()
        .join(" ")
}

/// The exposure: one asset (number 1, value 1) of each block at each site,
/// with id `<block>_<site>`, listed in `ASSETS_FILE`. Returns the model
/// and its assets' CSV.
pub fn exposure_model(entries: &[Entry], sites: &[Site]) -> Result<(String, String), ExportError> {
    super::check_entries(entries)?;
    let mut x = String::new();
    let _ = writeln!(x, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(x, r#"<nrml xmlns="http://openquake.org/xmlns/nrml/0.5">"#);
    let _ = writeln!(
        x,
        r#"<exposureModel id="rocking_blocks" category="buildings" taxonomySource="rocking">"#
    );
    let _ = writeln!(
        x,
        "  <description>Free-standing rigid blocks, one of each at each site</description>"
    );
    let _ = writeln!(x, "  <conversions>");
    let _ = writeln!(x, "    <costTypes>");
    let _ = writeln!(
        x,
        r#"      <costType name="contents" type="per_asset" unit="block"/>"#
    );
    let _ = writeln!(x, "    </costTypes>");
    let _ = writeln!(x, "  </conversions>");
    let _ = writeln!(x, "  <tagNames/>");
    let _ = writeln!(x, "  <assets>{ASSETS_FILE}</assets>");
    let _ = writeln!(x, "</exposureModel>");
    let _ = writeln!(x, "</nrml>");
    let mut csv = String::from("id,lon,lat,taxonomy,number,contents\n");
    for (k, site) in sites.iter().enumerate() {
        for e in entries {
            let _ = writeln!(csv, "{}_{k},{},{},{},1,1", e.id, site.lon, site.lat, e.id);
        }
    }
    Ok((x, csv))
}

/// The job: `classical_damage` on the hazard curves of `HAZARD_FILE`,
/// damage over `years` (the risk investigation time).
/// OpenQuake's taxonomy mapping of a logic tree: each taxonomy (block)
/// mapped to its branches' fragility functions with their weights
/// (`taxonomy,risk_id,weight`; OpenQuake checks that a taxonomy's weights
/// sum to 1 and averages the damage over them).
pub fn taxonomy_mapping(rows: &[(String, String, f64)]) -> String {
    let mut x = String::from("taxonomy,risk_id,weight\n");
    for (taxonomy, id, weight) in rows {
        let _ = writeln!(x, "{taxonomy},{id},{weight:?}");
    }
    x
}

/// The taxonomy mapping's file name.
pub const TAXONOMY_MAPPING_FILE: &str = "taxonomy_mapping.csv";

pub fn job_ini(years: f64, hazard_investigation_time: f64, mapping: bool) -> String {
    // A logic tree's branches, weighted per taxonomy.
    let mapping = match mapping {
        true => format!("taxonomy_mapping_csv = {TAXONOMY_MAPPING_FILE}\n"),
        false => String::new(),
    };
    format!(
        "[general]\n\
         description = Damage states of free-standing rigid blocks (rocking export)\n\
         calculation_mode = classical_damage\n\
         \n\
         [exposure]\n\
         exposure_file = {EXPOSURE_FILE}\n\
         \n\
         [fragility]\n\
         contents_fragility_file = {FRAGILITY_FILE}\n\
         {mapping}\
         \n\
         [hazard]\n\
         hazard_curves_csv = {HAZARD_FILE}\n\
         investigation_time = {hazard_investigation_time}\n\
         \n\
         [risk]\n\
         risk_investigation_time = {years}\n"
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn entry(id: &str) -> Entry {
        Entry {
            id: id.into(),
            description: "a 0.4 m × 1.8 m statue -- \"ε\" & <α>".into(),
            no_damage_limit: Some(0.22),
            states: Shape::Lognormal(vec![
                Lognormal {
                    median: 0.3,
                    beta: 0.4,
                },
                Lognormal {
                    median: 0.5,
                    beta: 0.35,
                },
            ]),
        }
    }

    /// The moments of a lognormal: E = θ e^(β²/2), Var = E²(e^(β²) − 1);
    /// for β = 0.5, mean 1.1331485 θ and stddev 0.6039 θ (√(e^0.25 − 1)
    /// = 0.5329404).
    #[test]
    fn mean_and_stddev_are_those_of_the_iml() {
        let (m, s) = mean_stddev(&Lognormal {
            median: 2.0,
            beta: 0.5,
        });
        assert!((m - 2.0 * 1.133_148_453_066_826_3).abs() < 1e-14);
        assert!((s / m - 0.532_940_350_027_788_2).abs() < 1e-14);
    }

    #[test]
    fn the_model_lists_each_state_of_each_block() {
        let ls = vec!["rocking".to_string(), "overturned".to_string()];
        let x = fragility_model(&[entry("a"), entry("b")], &ls, Im::Pga, "d & e").unwrap();
        assert!(x.contains("<limitStates>rocking overturned</limitStates>"));
        assert_eq!(x.matches("<fragilityFunction ").count(), 2);
        assert_eq!(x.matches(r#"<params ls="overturned""#).count(), 2);
        assert!(x.contains(r#"imt="PGA" noDamageLimit="2.2e-1""#), "{x}");
        assert!(x.contains("d &amp; e") && !x.contains("<α>"));
        // Comments may not hold "--".
        assert!(!x
            .lines()
            .any(|l| l.contains("<!--") && l[6..l.len() - 3].contains("--")));
        let e = fragility_model(&[entry("a b")], &ls, Im::Pga, "").unwrap_err();
        assert!(e.to_string().contains("`a b`"));
        let e = fragility_model(&[entry("a")], &ls, Im::Cav, "").unwrap_err();
        assert!(e.to_string().contains("cav"));
        let e = fragility_model(&[entry("a"), entry("a")], &ls, Im::Pga, "").unwrap_err();
        assert!(e.to_string().contains("twice"));
    }

    /// Two states' curves on one list of levels, each read linearly at
    /// the other's points (hand-worked, in levels binary fractions hold
    /// exactly): A rises 0 → 1 over 0.125–0.375 g, B over 0.25–0.5 g; at
    /// 0.25 g A is halfway, at 0.375 g B is.
    #[test]
    fn the_records_curves_are_one_discrete_function() {
        use crate::damage::Curve;
        let e = Entry {
            id: "a".into(),
            description: String::new(),
            no_damage_limit: Some(0.05),
            states: Shape::Curve(vec![
                Curve::of_capacities(&[0.125, 0.375]),
                Curve::of_capacities(&[0.25, 0.5]),
            ]),
        };
        let ls = vec!["rocking".to_string(), "overturned".to_string()];
        let x = fragility_model(&[e], &ls, Im::Pga, "").unwrap();
        assert!(
            x.contains(r#"<fragilityFunction id="a" format="discrete">"#),
            "{x}"
        );
        assert!(
            x.contains(
                r#"<imls imt="PGA" noDamageLimit="5e-2">1.25e-1 2.5e-1 3.75e-1 5e-1</imls>"#
            ),
            "{x}"
        );
        assert!(
            x.contains(r#"<poes ls="rocking">0e0 5e-1 1e0 1e0</poes>"#),
            "{x}"
        );
        assert!(
            x.contains(r#"<poes ls="overturned">0e0 0e0 5e-1 1e0</poes>"#),
            "{x}"
        );
        assert!(x.contains(r#"lossCategory="contents""#));
        // A curve that stops below 1 (a record never reaching the state).
        let short = Entry {
            id: "b".into(),
            description: String::new(),
            no_damage_limit: None,
            states: Shape::Curve(vec![Curve::of_capacities(&[0.1, 0.3, f64::INFINITY])]),
        };
        let err = fragility_model(&[short], &ls[..1], Im::Pga, "").unwrap_err();
        assert!(
            err.to_string().contains("does not rise from 0 to 1"),
            "{err}"
        );
    }

    #[test]
    fn the_exposure_places_each_block_at_each_site() {
        let sites = [
            Site {
                lon: 21.73,
                lat: 38.25,
            },
            Site {
                lon: 22.0,
                lat: 38.0,
            },
        ];
        let (x, csv) = exposure_model(&[entry("a"), entry("b")], &sites).unwrap();
        assert!(x.contains("<assets>assets.csv</assets>"));
        assert_eq!(csv.lines().count(), 1 + 4);
        assert!(csv.contains("\nb_1,22,38,b,1,1\n"), "{csv}");
        assert!(csv.contains("\na_0,21.73,38.25,a,1,1\n"), "{csv}");
    }
}
