//! Limit states on a block's IDA curve ([`LimitState`], ordered in
//! [`DamageStates`]) and a record's capacity for each ([`capacities`]).

/// What reaching a limit state means.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Criterion {
    /// θmax/α at least this (0 < x < 1).
    Rotation(f64),
    /// The base slid at least this far (m) from where it stood, or the
    /// block overturned (the slide-rock model's runs).
    Slide(f64),
    /// The overturning criterion in force (the run's verdict).
    Overturned,
}

/// A named limit state.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct LimitState {
    pub name: String,
    pub criterion: Criterion,
}

impl LimitState {
    /// `name=x` (θmax/α ≥ x), `name=Xm` (a slide of X metres) or
    /// `name=overturned`.
    pub fn parse(text: &str) -> Result<LimitState, DamageError> {
        let bad = || DamageError::Syntax(text.to_string());
        let (name, what) = text.split_once('=').ok_or_else(bad)?;
        let (name, what) = (name.trim(), what.trim());
        let criterion = if what.eq_ignore_ascii_case("overturned") {
            Criterion::Overturned
        } else if let Some(metres) = what.strip_suffix('m') {
            Criterion::Slide(metres.trim().parse().map_err(|_| bad())?)
        } else {
            Criterion::Rotation(what.parse().map_err(|_| bad())?)
        };
        Ok(LimitState {
            name: name.to_string(),
            criterion,
        })
    }

    /// As [`LimitState::parse`] reads it.
    pub fn text(&self) -> String {
        match self.criterion {
            Criterion::Rotation(x) => format!("{}={x}", self.name),
            Criterion::Slide(d) => format!("{}={d}m", self.name),
            Criterion::Overturned => format!("{}=overturned", self.name),
        }
    }

    /// The θmax/α threshold; none for a slide or overturning.
    pub fn threshold(&self) -> Option<f64> {
        match self.criterion {
            Criterion::Rotation(x) => Some(x),
            Criterion::Slide(_) | Criterion::Overturned => None,
        }
    }

    /// The slide's threshold (m), for a state on the slide.
    pub fn slide_m(&self) -> Option<f64> {
        match self.criterion {
            Criterion::Slide(d) => Some(d),
            _ => None,
        }
    }

    /// The criterion in words, with its unit.
    pub fn describe(&self) -> String {
        match self.criterion {
            // Tiny thresholds in exponent form (not 300 zeros).
            Criterion::Rotation(x) if x < 1e-3 => format!("θmax/α ≥ {x:e}"),
            Criterion::Rotation(x) => format!("θmax/α ≥ {x}"),
            Criterion::Slide(d) => format!("slide ≥ {d} m, or overturned"),
            Criterion::Overturned => "overturned".to_string(),
        }
    }
}

/// Why a list of limit states cannot be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DamageError {
    #[error(
        "limit state `{0}`: write NAME=X (θmax/α ≥ X, 0 < X < 1), NAME=Xm (the base slides X \
         metres; the slide-rock model) or NAME=overturned"
    )]
    Syntax(String),
    #[error("no limit states")]
    Empty,
    #[error(
        "limit state name `{0}`: use letters, digits, `_` and `-` only (OpenQuake's NRML and \
         pelicun's CSV take it as a key)"
    )]
    Name(String),
    #[error(
        "limit state name `{0}`: OpenQuake names the state below the first `no_damage` itself \
         (its damage outputs' first column), so a state of that name breaks its job; name it \
         otherwise"
    )]
    Reserved(String),
    #[error("limit state `{0}` is given twice")]
    Repeated(String),
    #[error(
        "limit state `{name}`: θmax/α ≥ {x} must lie strictly between 0 and 1 (1 is overturning)"
    )]
    Threshold { name: String, x: f64 },
    #[error("limit state `{name}`: a slide of {d} m must be positive and finite")]
    Distance { name: String, d: f64 },
    #[error(
        "limit states must be ordered from the lightest to overturning: `{later}` ({later_is}) \
         follows `{earlier}` ({earlier_is})"
    )]
    Order {
        earlier: String,
        earlier_is: String,
        later: String,
        later_is: String,
    },
    #[error(
        "limit states `{rotation}` and `{slide}`: one is on the rotation, the other on the \
         slide, which do not nest (a block can slide far and hardly rock); damage states are \
         a chain, each reached only past the one before, so give each kind as its own list"
    )]
    Mixed { rotation: String, slide: String },
}

/// Ordered limit states, the lightest first; checked on construction.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct DamageStates(Vec<LimitState>);

/// The default states: `rocking` (θmax/α ≥ 0.1: the block has uplifted
/// and rocked visibly, enough to shift contents and strain anchors or
/// cables), `large_rocking` (≥ 0.5: halfway to the overturning angle, where
/// the restoring moment of a slender block has halved) and `overturned`.
pub const DEFAULT: &str = "rocking=0.1,large_rocking=0.5,overturned=overturned";

impl DamageStates {
    pub fn new(states: Vec<LimitState>) -> Result<DamageStates, DamageError> {
        if states.is_empty() {
            return Err(DamageError::Empty);
        }
        for (k, s) in states.iter().enumerate() {
            let key_like = |c: char| c.is_ascii_alphanumeric() || c == '_' || c == '-';
            if s.name.is_empty() || !s.name.chars().all(key_like) {
                return Err(DamageError::Name(s.name.clone()));
            }
            if s.name.eq_ignore_ascii_case("no_damage") {
                return Err(DamageError::Reserved(s.name.clone()));
            }
            if states[..k].iter().any(|o| o.name == s.name) {
                return Err(DamageError::Repeated(s.name.clone()));
            }
            if let Criterion::Rotation(x) = s.criterion {
                if !(x > 0.0 && x < 1.0) {
                    return Err(DamageError::Threshold {
                        name: s.name.clone(),
                        x,
                    });
                }
            }
            if let Criterion::Slide(d) = s.criterion {
                if !(d > 0.0 && d.is_finite()) {
                    return Err(DamageError::Distance {
                        name: s.name.clone(),
                        d,
                    });
                }
            }
            if k > 0 {
                // A chain: each state reached only past the one before.
                // Rotation and slide do not nest, so one list has one of them.
                let prev = &states[k - 1];
                let ordered = match (prev.criterion, s.criterion) {
                    (Criterion::Rotation(a), Criterion::Rotation(b)) => a < b,
                    (Criterion::Slide(a), Criterion::Slide(b)) => a < b,
                    (Criterion::Rotation(_) | Criterion::Slide(_), Criterion::Overturned) => true,
                    (Criterion::Rotation(_), Criterion::Slide(_))
                    | (Criterion::Slide(_), Criterion::Rotation(_)) => {
                        return Err(DamageError::Mixed {
                            rotation: prev.name.clone(),
                            slide: s.name.clone(),
                        })
                    }
                    (Criterion::Overturned, _) => false,
                };
                if !ordered {
                    return Err(DamageError::Order {
                        earlier: prev.name.clone(),
                        earlier_is: prev.describe(),
                        later: s.name.clone(),
                        later_is: s.describe(),
                    });
                }
            }
        }
        Ok(DamageStates(states))
    }

    /// `NAME=X,…` as the command line and the pipeline write it.
    pub fn parse(text: &str) -> Result<DamageStates, DamageError> {
        let states = text
            .split(',')
            .filter(|t| !t.trim().is_empty())
            .map(LimitState::parse)
            .collect::<Result<Vec<_>, _>>()?;
        DamageStates::new(states)
    }

    /// Whether these are the [`DEFAULT`] states.
    /// Overturning alone: the block's fragility as one state.
    pub fn overturning() -> DamageStates {
        DamageStates::parse("overturned=overturned").expect("a valid state")
    }

    pub fn is_default(&self) -> bool {
        *self == DamageStates::default()
    }

    pub fn states(&self) -> &[LimitState] {
        &self.0
    }

    /// The states as [`DamageStates::parse`] reads them.
    pub fn text(&self) -> String {
        self.0
            .iter()
            .map(LimitState::text)
            .collect::<Vec<_>>()
            .join(",")
    }
}

impl Default for DamageStates {
    fn default() -> Self {
        DamageStates::parse(DEFAULT).expect("the default states are ordered")
    }
}

/// A record's capacity for one limit state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StateCapacity {
    /// Reached at this η (αg/PGA).
    Reached(f64),
    /// Not reached by the strongest run, at this η: the capacity is below
    /// it (a right-censored capacity in intensity).
    NotReached(f64),
}

impl StateCapacity {
    /// The same capacity in another measure of intensity (`f` of η), or
    /// `None` where `f` has none.
    pub fn map(self, f: impl FnOnce(f64) -> Option<f64>) -> Option<StateCapacity> {
        Some(match self {
            StateCapacity::Reached(eta) => StateCapacity::Reached(f(eta)?),
            StateCapacity::NotReached(eta) => StateCapacity::NotReached(f(eta)?),
        })
    }

    pub fn reached(self) -> Option<f64> {
        match self {
            StateCapacity::Reached(eta) => Some(eta),
            StateCapacity::NotReached(_) => None,
        }
    }
}

/// One run as the states read it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StateRun {
    pub eta: f64,
    /// θmax/α.
    pub edp: f64,
    /// The base's largest slide (m; 0 for a model that does not slide).
    pub slide_m: f64,
    pub overturned: bool,
}

/// The record's capacity for each state, from its runs in any order and
/// its overturning capacity `eta_c` (`None`: it survived every level).
pub fn capacities(
    states: &DamageStates,
    runs: impl IntoIterator<Item = StateRun>,
    eta_c: Option<f64>,
) -> Vec<StateCapacity> {
    let mut all: Vec<StateRun> = runs.into_iter().collect();
    // Intensity rising: η falling.
    all.sort_by(|a, b| b.eta.total_cmp(&a.eta));
    let strongest = all.last().map_or(f64::NAN, |r| r.eta);
    let on = |measure: fn(&StateRun) -> f64| -> Vec<(f64, f64, bool)> {
        all.iter()
            .map(|r| (r.eta, measure(r), r.overturned))
            .collect()
    };
    let (rotation, slide) = (on(|r| r.edp), on(|r| r.slide_m));
    states
        .states()
        .iter()
        .map(|s| match s.criterion {
            Criterion::Overturned => match eta_c {
                Some(eta) => StateCapacity::Reached(eta),
                None => StateCapacity::NotReached(strongest),
            },
            Criterion::Rotation(x) => first_reaching(&rotation, x, strongest),
            Criterion::Slide(d) => first_reaching(&slide, d, strongest),
        })
        .collect()
}

/// The first crossing of a measure (θmax/α, the slide) = x along runs
/// sorted by rising intensity,
/// interpolated linearly in 1/η from the run before; an overturned run
/// reaches every state at its own η.
fn first_reaching(runs: &[(f64, f64, bool)], x: f64, strongest: f64) -> StateCapacity {
    let mut before: Option<(f64, f64)> = None;
    for &(eta, edp, overturned) in runs {
        if overturned {
            return StateCapacity::Reached(eta);
        }
        if edp >= x {
            let at = match before {
                Some((eta0, edp0)) if edp > edp0 => {
                    let (i0, i1) = (1.0 / eta0, 1.0 / eta);
                    1.0 / (i0 + (x - edp0) / (edp - edp0) * (i1 - i0))
                }
                _ => eta,
            };
            return StateCapacity::Reached(at);
        }
        before = Some((eta, edp));
    }
    StateCapacity::NotReached(strongest)
}

impl std::str::FromStr for DamageStates {
    type Err = DamageError;
    /// `NAME=X,…,NAME=overturned`, lightest first ([`DamageStates::parse`]).
    fn from_str(text: &str) -> Result<Self, DamageError> {
        DamageStates::parse(text)
    }
}

crate::deserialize_by_from_str!(DamageStates);

#[cfg(test)]
mod tests {
    use super::*;

    fn run(eta: f64, edp: f64, overturned: bool) -> StateRun {
        StateRun {
            eta,
            edp: if overturned { f64::INFINITY } else { edp },
            slide_m: 0.0,
            overturned,
        }
    }

    #[test]
    fn slide_states_are_reached_by_the_slide_or_by_overturning() {
        let d = DamageStates::parse("walks=0.05m,off=0.3m,overturned=overturned").unwrap();
        assert_eq!(d.states()[0].describe(), "slide ≥ 0.05 m, or overturned");
        assert_eq!(DamageStates::parse(&d.text()).unwrap(), d);
        let slid = |eta: f64, slide_m: f64| StateRun {
            eta,
            edp: 0.0,
            slide_m,
            overturned: false,
        };
        // The slide grows 0 → 0.1 m between η = 1 and 0.5: 0.05 m is reached
        // halfway in 1/η (1/η = 1.5); 0.3 m only by the overturning at 0.25.
        let runs = [slid(1.0, 0.0), slid(0.5, 0.1), run(0.25, 0.0, true)];
        let caps = capacities(&d, runs, Some(0.25));
        assert_eq!(caps[0], StateCapacity::Reached(1.0 / 1.5));
        assert_eq!(caps[1], StateCapacity::Reached(0.25));
        assert_eq!(caps[2], StateCapacity::Reached(0.25));
        let e = |t: &str| DamageStates::parse(t).unwrap_err().to_string();
        assert!(e("rocking=0.1,walks=0.05m").contains("do not nest"));
        assert!(e("a=0.3m,b=0.1m").contains("follows `a`"));
        assert!(e("a=-1m").contains("must be positive"));
    }

    #[test]
    fn the_default_states_are_ordered_and_read_back() {
        let d = DamageStates::default();
        assert_eq!(d.states().len(), 3);
        assert_eq!(DamageStates::parse(&d.text()).unwrap(), d);
        assert_eq!(d.states()[2].criterion, Criterion::Overturned);
    }

    #[test]
    fn refusals_name_what_is_wrong() {
        let e = |t: &str| DamageStates::parse(t).unwrap_err().to_string();
        assert!(e("a=0.5,b=0.1").contains("`b` (θmax/α ≥ 0.1) follows `a` (θmax/α ≥ 0.5)"));
        assert!(e("a=overturned,b=0.3").contains("follows `a` (overturned)"));
        assert!(e("a=0.1,a=0.2").contains("`a` is given twice"));
        assert!(e("big rock=0.1").contains("`big rock`"));
        assert!(e("a=1.2").contains("strictly between 0 and 1"));
        assert!(e("a=lots").contains("NAME=X"));
        assert!(e("").contains("no limit states"));
        // OpenQuake's own first state (its job failed on the duplicate
        // column `contents-no_damage`).
        assert!(e("no_damage=0.1,overturned=overturned").contains("OpenQuake names the state"));
        assert!(e("No_Damage=0.1").contains("OpenQuake names the state"));
    }

    /// An IDA curve worked by hand: θmax/α 0, 0.05, 0.3, 0.7 at η 1, 0.5,
    /// 0.25, 0.2, then overturning at 0.15 (η_c 0.16 after refinement).
    #[test]
    fn capacities_by_hand() {
        let points = [
            run(1.0, 0.0, false),
            run(0.5, 0.05, false),
            run(0.25, 0.3, false),
            run(0.2, 0.7, false),
            run(0.15, 1.0, true),
            run(0.16, 1.0, true),
            run(0.17, 0.9, false),
        ];
        let d = DamageStates::parse("a=0.1,b=0.5,c=0.95,ot=overturned").unwrap();
        let caps = capacities(&d, points, Some(0.16));
        // a: between η 0.5 (0.05) and 0.25 (0.3): 1/η = 2 + (0.05/0.25)·2 = 2.4.
        assert!((caps[0].reached().unwrap() - 1.0 / 2.4).abs() < 1e-15);
        // b: between 0.25 (0.3) and 0.2 (0.7): 1/η = 4 + 0.5·1 = 4.5.
        assert!((caps[1].reached().unwrap() - 1.0 / 4.5).abs() < 1e-15);
        // c: after 0.17 (0.9) the next run overturns, at η 0.16.
        assert_eq!(caps[2], StateCapacity::Reached(0.16));
        assert_eq!(caps[3], StateCapacity::Reached(0.16));
        // A record that never overturns and never reaches 0.5.
        let calm = [run(1.0, 0.0, false), run(0.01, 0.2, false)];
        let caps = capacities(&d, calm, None);
        assert!((caps[0].reached().unwrap() - 1.0 / 50.5).abs() < 1e-12);
        assert_eq!(caps[1], StateCapacity::NotReached(0.01));
        assert_eq!(caps[3], StateCapacity::NotReached(0.01));
    }

    /// The states are reached in order under any IDA curve, even one that
    /// falls back (the resurrection rule keeps the first crossing).
    #[test]
    fn capacities_are_ordered() {
        let points = [
            run(1.0, 0.0, false),
            run(0.6, 0.6, false),
            run(0.5, 0.05, false),
            run(0.3, 0.2, true),
        ];
        let d = DamageStates::default();
        let caps: Vec<f64> = capacities(&d, points, Some(0.3))
            .iter()
            .map(|c| c.reached().unwrap())
            .collect();
        assert!(caps.windows(2).all(|w| w[0] >= w[1]), "{caps:?}");
        // The 0.1 crossing is the first, on the way to η 0.6.
        assert!((caps[0] - 1.0 / (1.0 + (0.1 / 0.6) * (1.0 / 0.6 - 1.0))).abs() < 1e-15);
    }
}
