//! What `fragility`, `risk` and `export` print of damage states: the table
//! of the states' fits; and the line they print of a block's floor.

use rocking::damage::Lognormal;
use rocking::im::level_text;
use rocking::ops::damage::DamageFragility;

/// The states' fits, one line each, indented by two spaces.
pub fn print_fits(f: &DamageFragility) {
    if f.states.len() > 1 {
        println!(
            "  {}",
            if f.dispersion == "common" {
                "one β for the states, the heaviest's, medians in order (--dispersion common)"
            } else {
                "each state its own β (--dispersion each): their curves cross somewhere"
            }
        );
    }
    if f.method == rocking::damage::FitMethod::Empirical {
        // The lognormals below are what the records were checked against.
        println!(
            "  the fragility: the records' own curve, linear between their capacities (the \
             lognormal fits are shown for comparison)"
        );
    }
    let wide = f
        .states
        .iter()
        .map(|s| s.criterion.chars().count())
        .max()
        .unwrap_or(0)
        .max(16);
    println!(
        "  {:<16} {:<wide$} {:>22} {:>22} {:>8}",
        "state", "criterion", "fractile median, β", "mle median, β", "reached"
    );
    for s in &f.states {
        let show = |l: Option<Lognormal>| {
            l.map_or("—".to_string(), |l| {
                format!("{} {}, {:.3}", level_text(l.median), f.unit, l.beta)
            })
        };
        let reached = s.reached.map_or("—".to_string(), |r| {
            format!("{r}/{}", f.records.unwrap_or(0))
        });
        println!(
            "  {:<16} {:<wide$} {:>22} {:>22} {:>8}",
            s.name,
            s.criterion,
            show(s.fractile),
            show(s.mle),
            reached
        );
    }
}

/// `, 44 records of records/far_field` (nothing without `--direct`).
pub fn records_text(records: Option<usize>, folder: Option<&str>) -> String {
    match (records, folder) {
        (Some(n), Some(dir)) => format!(", {n} records of {dir}"),
        (Some(n), None) => format!(", {n} records"),
        _ => String::new(),
    }
}

/// What `fragility` and `risk` say of a block on a floor: the building, and
/// whose levels the answer is in (the ground's, or the floor motion's own
/// for a floor demand).
pub fn floor_line(floor: &str, floor_demand: bool, what: &str) -> String {
    let whose = if floor_demand {
        "the floor motion's own (a floor demand)"
    } else {
        "the ground's"
    };
    format!(
        "on the floor of a building with modes T,ζ,Γφ = {floor}: the records run through it; \
         levels and {what} are {whose}"
    )
}
