//! What `fragility`, `risk` and `export` share about damage states: the
//! `--method` choice, `--states` parsing and the table of states' fits.

use clap::ValueEnum;
use rocking::damage::{DamageStates, FitMethod, Lognormal};
use rocking::im::level_text;
use rocking::ops::damage::DamageFragility;

/// The lognormal's fit.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum MethodArg {
    Fractile,
    Mle,
}

impl MethodArg {
    pub fn method(self) -> FitMethod {
        match self {
            MethodArg::Fractile => FitMethod::Fractile,
            MethodArg::Mle => FitMethod::MaxLikelihood,
        }
    }
}

/// `--states` (clap's parser).
pub fn parse_states(text: &str) -> Result<DamageStates, String> {
    DamageStates::parse(text).map_err(|e| e.to_string())
}

/// The states' fits, one line each, indented by two spaces.
pub fn print_fits(f: &DamageFragility) {
    println!(
        "  {:<16} {:<16} {:>22} {:>22} {:>8}",
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
            "  {:<16} {:<16} {:>22} {:>22} {:>8}",
            s.name,
            s.criterion,
            show(s.fractile),
            show(s.mle),
            reached
        );
    }
}
