//! pelicun's fragility CSV (one row per component: its demand, then
//! `LSk-Family`, `LSk-Theta_0`, `LSk-Theta_1` per limit state) and the
//! metadata JSON beside it (descriptions of each component and damage
//! state), as pelicun 3.10's damage model reads them.
//!
//! A state is a `lognormal` (Theta_0 the median, Theta_1 β) or, for the
//! records' curve, a `multilinear_CDF` (Theta_0 `"x₁,…,xₙ|0,…,1"`, the
//! levels and their probabilities, as the DLML writes its curves; pelicun
//! interpolates linearly between them). The columns are FEMA P-58's
//! contents components' (the DLML's E.20.22): the demand type, its unit
//! (`g`, or `cmps` where FEMA's rows say `mps`: pelicun converts), and
//! `Demand-Offset` 0. `Demand-Directional` is 1 where FEMA's contents say
//! 0: FEMA's non-directional components are compared with 1.2 × the larger
//! of the two directions' demands (pelicun's `NonDirectionalMultipliers`),
//! but a block's capacity is of the component in its plane; placed in
//! direction 1 (or 2, or `1,2` for one facing each way), it sees that
//! direction's demand as the records shook it.

use std::fmt::Write;

use serde_json::{json, Map, Value};

use super::{Entry, ExportError, Shape};
use crate::im::Im;

pub const CSV_FILE: &str = "fragility.csv";
pub const JSON_FILE: &str = "fragility.json";

/// pelicun's demand type and unit for the IM: its demand vocabulary
/// (`pelicun.base.EDP_TYPES`) and unit names (`settings/default_units.json`).
pub fn demand(im: Im) -> Result<(String, &'static str), ExportError> {
    im.pelicun().ok_or_else(|| ExportError::Im {
        format: "pelicun",
        im: im.name(),
        why: "pelicun's damage model has no demand type for it".into(),
        valid: Im::listed(|im| im.pelicun().is_some(), true),
    })
}

/// The CSV: one component per block, one limit state per damage state.
pub fn fragility_csv(entries: &[Entry], n_states: usize, im: Im) -> Result<String, ExportError> {
    super::check_entries(entries)?;
    let (demand, unit) = demand(im)?;
    let mut x =
        String::from("ID,Incomplete,Demand-Type,Demand-Unit,Demand-Offset,Demand-Directional");
    for k in 1..=n_states {
        let _ = write!(
            x,
            ",LS{k}-Family,LS{k}-Theta_0,LS{k}-Theta_1,LS{k}-DamageStateWeights"
        );
    }
    x.push('\n');
    for e in entries {
        // Directional: the capacity is of one horizontal component, as the
        // records are; 0 would make pelicun take the larger of two
        // directions times its non-directional multiplier (1.2 by default).
        let _ = write!(x, "{},0,{demand},{unit},0,1", e.id);
        match &e.states {
            Shape::Lognormal(states) => {
                for l in states {
                    let _ = write!(x, ",lognormal,{:e},{:e},", l.median, l.beta);
                }
            }
            Shape::Curve(curves) => {
                for c in curves {
                    let (xs, ps): (Vec<String>, Vec<String>) = c
                        .points()
                        .map(|(a, p)| (format!("{a:e}"), format!("{p}")))
                        .unzip();
                    let _ = write!(
                        x,
                        ",multilinear_CDF,\"{}|{}\",,",
                        xs.join(","),
                        ps.join(",")
                    );
                }
            }
        }
        x.push('\n');
    }
    Ok(x)
}

/// The metadata: each component described, and its damage states named.
pub fn metadata_json(
    entries: &[Entry],
    limit_states: &[(String, String)],
    description: &str,
) -> Result<String, ExportError> {
    super::check_entries(entries)?;
    let mut root = Map::new();
    root.insert(
        "_GeneralInformation".into(),
        json!({
            "ShortName": "rocking blocks",
            "Description": description,
            "Version": env!("CARGO_PKG_VERSION"),
        }),
    );
    for e in entries {
        let mut states = Map::new();
        for (k, (name, criterion)) in limit_states.iter().enumerate() {
            states.insert(
                format!("LS{}", k + 1),
                json!({ format!("DS{}", k + 1): { "Description": format!("{name}: {criterion}") } }),
            );
        }
        root.insert(
            e.id.clone(),
            json!({
                "Description": e.description,
                "SuggestedComponentBlockSize": "1 EA",
                "RoundUpToIntegerQuantity": "True",
                "LimitStates": Value::Object(states),
            }),
        );
    }
    Ok(serde_json::to_string_pretty(&Value::Object(root)).expect("JSON of strings") + "\n")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::damage::Lognormal;

    #[test]
    fn one_row_per_block_with_median_and_beta_per_state() {
        let e = Entry {
            id: "statue".into(),
            description: "a statue".into(),
            no_damage_limit: None,
            states: Shape::Lognormal(vec![
                Lognormal {
                    median: 0.25,
                    beta: 0.4,
                },
                Lognormal {
                    median: 0.5,
                    beta: 0.3,
                },
            ]),
        };
        let csv = fragility_csv(std::slice::from_ref(&e), 2, Im::Pga).unwrap();
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(lines[0].split(',').count(), 6 + 2 * 4);
        assert_eq!(
            lines[1],
            "statue,0,Peak Ground Acceleration,g,0,1,lognormal,2.5e-1,4e-1,,lognormal,5e-1,3e-1,"
        );
        assert!(fragility_csv(std::slice::from_ref(&e), 2, Im::Sa(1.0))
            .unwrap()
            .contains("Spectral Acceleration|1.0,g"));
        assert!(fragility_csv(&[e], 2, Im::AvgSa).is_err());
    }

    /// The records' curve as the DLML writes its curves: one quoted cell
    /// of levels and probabilities (a hand-worked three-record curve: P =
    /// 0, 1/2, 1 at its capacities).
    #[test]
    fn a_records_curve_is_a_multilinear_cdf() {
        let e = Entry {
            id: "rack".into(),
            description: "a rack".into(),
            no_damage_limit: None,
            states: Shape::Curve(vec![crate::damage::Curve::of_capacities(&[
                25.0, 40.0, 70.0,
            ])]),
        };
        let csv = fragility_csv(&[e], 1, Im::Pfv).unwrap();
        assert_eq!(
            csv.lines().nth(1).unwrap(),
            r#"rack,0,Peak Floor Velocity,cmps,0,1,multilinear_CDF,"2.5e1,4e1,7e1|0,0.5,1",,"#
        );
    }
}
