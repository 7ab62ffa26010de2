//! A block as a user asks for it ([`BlockAsk`]): by p (and α), or by its
//! half sizes `b`, `h` or full `width`, `height`; its restitution; the
//! model and how to run it; where it stands (a floor) and how firmly (μ).
//! [`BlockAsk::resolve`] checks it all and gives each block's run
//! specification at η = 1 ([`AskedBlock`]).

use serde::Deserialize;

use super::spelling::{AskError, Spelling};
use crate::block::{check_mu, slides_first, Block, Restitution};
use crate::building::ShapedMode;
use crate::floor::{Building, Mode};
use crate::ops::capacity::{Asked, NamedSpec};
use crate::physics::friction::Friction;
use crate::physics::{ModelChoice, NonlinearIntegrator, Overturn, Solver};

/// `--auto-tol` when none is given: the linearised model is accepted where
/// it errs by at most 1 % in η_c.
pub const AUTO_TOL: f64 = 0.01;

/// The block (or blocks: each list a value or several, p × ε or each size
/// × ε) and how to run it. Python's keyword arguments deserialise into it
/// (a list or one number where a list is taken); unknown keys are refused.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct BlockAsk {
    /// Frequency parameter p = √(3g/(4R)) (1/s).
    #[serde(deserialize_with = "many_p")]
    pub p: Vec<f64>,
    /// Half-width and half-height (m).
    #[serde(deserialize_with = "many_b")]
    pub b: Vec<f64>,
    #[serde(deserialize_with = "many_h")]
    pub h: Vec<f64>,
    /// Full width and height (m): b = width/2, h = height/2.
    #[serde(deserialize_with = "many_width")]
    pub width: Vec<f64>,
    #[serde(deserialize_with = "many_height")]
    pub height: Vec<f64>,
    /// Coefficient of restitution, or Housner's bound (needs the sizes).
    #[serde(deserialize_with = "many_eps")]
    pub eps: Vec<Restitution>,
    /// Slenderness α (rad) of a block given by p: for the nonlinear model,
    /// a PGA, μ.
    pub alpha: Option<f64>,
    pub model: ModelChoice,
    pub integrator: NonlinearIntegrator,
    /// The integrator's tolerance; its default when `None`.
    pub rtol: Option<f64>,
    /// The linearised model's accepted error in η_c (`model = auto`, and
    /// the warnings of a regression).
    pub auto_tol: f64,
    pub overturn: Overturn,
    /// The base's static friction coefficient: μ ≤ b/h slides first.
    pub mu: Option<f64>,
    /// The base's kinetic friction coefficient (≤ μ; μ when not given), for
    /// the slide-rock model.
    pub mu_k: Option<f64>,
    /// The building whose floor the block stands on, mode by mode.
    #[serde(deserialize_with = "some_modes")]
    pub floor: Vec<Mode>,
    /// A building with its modes' shapes at every floor, and the floor
    /// the block stands on (instead of `floor`).
    #[serde(deserialize_with = "some_shaped")]
    pub building: Vec<ShapedMode>,
    pub level: Option<usize>,
}

impl Default for BlockAsk {
    fn default() -> Self {
        BlockAsk {
            p: Vec::new(),
            b: Vec::new(),
            h: Vec::new(),
            width: Vec::new(),
            height: Vec::new(),
            eps: Vec::new(),
            alpha: None,
            model: ModelChoice::Linearized,
            integrator: NonlinearIntegrator::Taylor,
            rtol: None,
            auto_tol: AUTO_TOL,
            overturn: Overturn::Static,
            mu: None,
            mu_k: None,
            floor: Vec::new(),
            building: Vec::new(),
            level: None,
        }
    }
}

/// One block as asked, checked: its name (empty for p and ε, `b{b}xh{h}`
/// for sizes), its run specification at η = 1, its friction and whether
/// it slides first (with μ); and why that model.
#[derive(Debug, Clone)]
pub struct AskedBlock {
    pub named: NamedSpec,
    pub why: String,
    /// A block given by sizes too large for an object's
    /// ([`crate::block::size_warning`]).
    pub size_warning: Option<String>,
    /// A block of known α run with the linearised model where its error is
    /// more than `auto_tol` accepts: what `auto`, the other answers'
    /// default, would not run.
    pub linearised: Option<String>,
}

impl AskedBlock {
    /// What every front end says of the block: sizes that look like
    /// another unit's, the linearised model beyond its accepted error, and
    /// a block that slides before it rocks (under a model that does not
    /// slide).
    pub fn warnings(&self) -> Vec<String> {
        let n = &self.named;
        let rocks_only = n.spec.model.equation.friction().is_none();
        let sliding = match (n.slides_first, n.mu, n.alpha_rad) {
            (Some(true), Some(mu), Some(alpha)) if rocks_only => {
                Some(crate::block::sliding_warning(mu, alpha))
            }
            _ => None,
        };
        let linearised = self.linearised.iter().cloned();
        self.size_warning
            .iter()
            .cloned()
            .chain(linearised)
            .chain(sliding)
            .collect()
    }

    /// Every block's [`AskedBlock::warnings`], each said once (the ε of
    /// one size share its warnings).
    pub fn warnings_of(blocks: &[AskedBlock]) -> Vec<String> {
        let mut said: Vec<String> = Vec::new();
        for w in blocks.iter().flat_map(AskedBlock::warnings) {
            if !said.contains(&w) {
                said.push(w);
            }
        }
        said
    }
}

impl BlockAsk {
    /// Every block asked, in order (p outer and ε inner; or each size, then
    /// ε), each checked, at η = 1.
    pub fn resolve(&self, sp: Spelling) -> Result<Vec<AskedBlock>, AskError> {
        let sizes = self.sizes(sp)?;
        if self.eps.is_empty() {
            return Err(AskError(format!("give {}", sp.key("eps"))));
        }
        if !sizes.is_empty() && !self.p.is_empty() {
            return Err(AskError(format!(
                "give the block by {} or by its sizes, not both",
                sp.key("p")
            )));
        }
        if !sizes.is_empty() && self.alpha.is_some() {
            return Err(AskError(format!(
                "{} comes from the block's sizes; give one or the other",
                sp.key("alpha")
            )));
        }
        if let Some(a) = self
            .alpha
            .filter(|a| !(*a > 0.0 && *a < std::f64::consts::FRAC_PI_2))
        {
            // Any model reads PGA = α/η (linearised, g·tan α ≈ gα) from it.
            return Err(AskError(format!(
                "{}: the slenderness α is an angle in (0, π/2) rad",
                sp.set_number("alpha", a)
            )));
        }
        if sizes.is_empty() && self.p.is_empty() {
            return Err(AskError(format!(
                "give the block by {}, or by its half sizes {} or full {}",
                sp.key("p"),
                sp.keys(&["b", "h"]),
                sp.keys(&["width", "height"])
            )));
        }
        self.unused_model_options(sp)?;
        let asked = Asked {
            model: self.model,
            solver: Solver::new(self.integrator, self.rtol)
                .map_err(|e| AskError::of(sp, "rtol", e))?,
            auto_tol: self.auto_tol,
            overturn: self.overturn,
        };
        let mu = self
            .mu
            .map(check_mu)
            .transpose()
            .map_err(|e| AskError::of(sp, "mu", e))?;
        let mut out = Vec::new();
        for &p in &self.p {
            for &eps in &self.eps {
                let Restitution::Value(eps) = eps else {
                    return Err(AskError(format!(
                        "{} needs the block's dimensions ({} or {})",
                        sp.set("eps", "housner"),
                        sp.keys(&["b", "h"]),
                        sp.keys(&["width", "height"])
                    )));
                };
                out.push(self.one(sp, String::new(), p, eps, self.alpha, &asked, mu)?);
            }
        }
        for &(b_m, h_m) in &sizes {
            for &eps in &self.eps {
                let block = Block::new(b_m, h_m, eps).map_err(|e| AskError(e.to_string()))?;
                let name = format!("b{b_m}xh{h_m}");
                let mut asked_block = self.one(
                    sp,
                    name,
                    block.p(),
                    block.eps,
                    Some(block.alpha()),
                    &asked,
                    mu,
                )?;
                asked_block.size_warning = crate::block::size_warning(&block);
                out.push(asked_block);
            }
        }
        Ok(out)
    }

    /// Options the model asked would take and not use, refused.
    fn unused_model_options(&self, sp: Spelling) -> Result<(), AskError> {
        // The linearised equation is stepped exactly: an integrator or its
        // tolerance would be taken and do nothing.
        let integrator = self.integrator != NonlinearIntegrator::Taylor;
        if let Some(key) = self
            .model
            .unused_solver_key(integrator, self.rtol.is_some())
        {
            return Err(AskError(format!(
                "{} is the nonlinear model's; {} is stepped exactly (give {} or {})",
                sp.key(key),
                sp.set("model", "linearized"),
                sp.set("model", "nonlinear"),
                sp.set("model", "auto")
            )));
        }
        // The kinetic friction is the slide-rock model's: the rocking models
        // take μ only to say whether the block slides first.
        if self.mu_k.is_some()
            && self.mu.is_some()
            && matches!(self.model, ModelChoice::Linearized | ModelChoice::Nonlinear)
        {
            return Err(AskError(format!(
                "{} is the slide-rock model's kinetic friction; {} does not slide (give {} or {})",
                sp.key("mu_k"),
                sp.set("model", crate::label::Label::label(self.model)),
                sp.set("model", "slide-rock"),
                sp.set("model", "auto")
            )));
        }
        Ok(())
    }

    /// The one block of a command that runs one.
    pub fn resolve_one(&self, sp: Spelling) -> Result<AskedBlock, AskError> {
        let mut blocks = self.resolve(sp)?;
        if blocks.len() != 1 {
            return Err(AskError(format!(
                "{} blocks given; this runs one (give one value to each block option)",
                blocks.len()
            )));
        }
        Ok(blocks.remove(0))
    }

    /// The building whose floor the blocks stand on, checked; `None` on the
    /// ground.
    pub fn building(&self, sp: Spelling) -> Result<Option<Building>, AskError> {
        building(&self.floor, &self.building, self.level, sp)
    }

    /// The half sizes asked, paired: `b` with `h`, or `width`/2 with
    /// `height`/2.
    fn sizes(&self, sp: Spelling) -> Result<Vec<(f64, f64)>, AskError> {
        let half = !self.b.is_empty() || !self.h.is_empty();
        let full = !self.width.is_empty() || !self.height.is_empty();
        match (half, full) {
            (false, false) => Ok(Vec::new()),
            (true, true) => Err(AskError(format!(
                "give the block's half sizes {} or its full {}, not both",
                sp.keys(&["b", "h"]),
                sp.keys(&["width", "height"])
            ))),
            (true, false) => pairs(sp, ("b", &self.b), ("h", &self.h)),
            (false, true) => Ok(pairs(sp, ("width", &self.width), ("height", &self.height))?
                .into_iter()
                .map(|(w, h)| (w / 2.0, h / 2.0))
                .collect()),
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn one(
        &self,
        sp: Spelling,
        name: String,
        p: f64,
        eps: f64,
        alpha: Option<f64>,
        asked: &Asked,
        mu: Option<f64>,
    ) -> Result<AskedBlock, AskError> {
        let friction = match (mu, self.mu_k) {
            (None, None) => None,
            (None, Some(_)) => {
                return Err(AskError(format!(
                    "{} is the kinetic friction beside {}: give both",
                    sp.key("mu_k"),
                    sp.key("mu")
                )))
            }
            (Some(mu), mu_k) => Some(Friction {
                mu_s: mu,
                mu_k: mu_k.unwrap_or(mu),
            }),
        };
        let (mut named, why) = NamedSpec::ask(name, p, eps, alpha, friction, asked)
            .map_err(|e| AskError(e.to_string()))?;
        let slides_first = match (mu, alpha) {
            (None, _) => None,
            (Some(mu), Some(alpha)) => Some(slides_first(mu, alpha)),
            (Some(_), None) => {
                return Err(AskError(format!(
                    "{} is compared with the block's b/h: give {}, {} or {}",
                    sp.key("mu"),
                    sp.keys(&["b", "h"]),
                    sp.keys(&["width", "height"]),
                    sp.key("alpha")
                )))
            }
        };
        named.mu = mu;
        named.slides_first = slides_first;
        let linearised = match (named.spec.model.equation, alpha) {
            (crate::physics::Equation::Linearized, Some(a)) => {
                let err = crate::physics::linearization_error(a);
                (err > self.auto_tol).then(|| {
                    format!(
                        "the linearised model errs by about {err:.1e} in η_c at α = {a:.4} rad, \
                         more than {} accepts ({:e}); {} runs {} here, as the fragility, risk \
                         and export answers do by default",
                        sp.key("auto_tol"),
                        self.auto_tol,
                        sp.set("model", "auto"),
                        if mu.is_some() {
                            "the slide-rock model (the base's friction given)"
                        } else {
                            "the nonlinear equation"
                        }
                    )
                })
            }
            _ => None,
        };
        Ok(AskedBlock {
            named,
            why,
            size_warning: None,
            linearised,
        })
    }
}

/// A building from its modes, checked; `None` for none.
pub fn building(
    floor: &[Mode],
    shaped: &[ShapedMode],
    level: Option<usize>,
    sp: Spelling,
) -> Result<Option<Building>, AskError> {
    use crate::building::BuildingError as E;
    let modes = crate::building::floor_modes(floor, shaped, level).map_err(|e| match e {
        E::Both => AskError(format!(
            "{} and {} both place the block: give one",
            sp.key("floor"),
            sp.key("building")
        )),
        E::Alone => AskError(format!(
            "{} picks a floor of {}: give both",
            sp.key("level"),
            sp.key("building")
        )),
        E::NoLevel(n) => AskError(format!(
            "{} has floors 1–{n}: give the block's with {}",
            sp.key("building"),
            sp.key("level")
        )),
        E::Level { level, floors } => AskError(format!(
            "{} {level}: the building has floors 1–{floors}",
            sp.key("level")
        )),
        other => AskError::of(sp, "building", other),
    })?;
    if modes.is_empty() {
        return Ok(None);
    }
    let key = if shaped.is_empty() {
        "floor"
    } else {
        "building"
    };
    Building::new(modes)
        .map(Some)
        .map_err(|e| AskError::of(sp, key, e))
}

/// `a` and `b` as pairs, when they are as long as each other.
fn pairs(
    sp: Spelling,
    (a_name, a): (&str, &[f64]),
    (b_name, b): (&str, &[f64]),
) -> Result<Vec<(f64, f64)>, AskError> {
    if a.len() != b.len() {
        return Err(AskError(format!(
            "{} has {} values and {} {}: give one {} for each {}",
            sp.key(a_name),
            a.len(),
            sp.key(b_name),
            b.len(),
            sp.key(b_name),
            sp.key(a_name)
        )));
    }
    Ok(a.iter().copied().zip(b.iter().copied()).collect())
}

/// A floor's modes, where given: a list of modes, or one mode (its text
/// `"T,ZETA,GAMMA_PHI"` as the command line takes it, or its numbers); a
/// list of none is refused (it ran the block on the ground without a
/// word); not given, the ground.
pub(super) fn some_modes<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Vec<Mode>, D::Error> {
    some(
        d,
        "floor: no mode given ([]): give one mode or more, [T, ζ, Γφ] each, or leave floor \
         out for a block on the ground",
    )
}

/// A building's shaped modes, as [`some_modes`] a floor's (the text
/// `"T,ZETA,GAMMA,PHI…"`).
pub(super) fn some_shaped<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> Result<Vec<ShapedMode>, D::Error> {
    some(
        d,
        "building: no mode given ([]): give one mode or more, [T, ζ, Γ, φ…] each, or leave \
         building out",
    )
}

/// [`modes`], none where not given, and a list of none refused with `empty`.
fn some<'de, D, M>(d: D, empty: &'static str) -> Result<Vec<M>, D::Error>
where
    D: serde::Deserializer<'de>,
    M: serde::de::DeserializeOwned,
{
    match modes(d)? {
        Some(modes) if modes.is_empty() => Err(serde::de::Error::custom(empty)),
        modes => Ok(modes.unwrap_or_default()),
    }
}

/// Modes given as a list of modes or as one mode, each read by its own
/// reader (a text such as "0.5,0.05,1.3" was read as a list of its
/// characters, and refused for its first, `0`).
fn modes<'de, D, M>(d: D) -> Result<Option<Vec<M>>, D::Error>
where
    D: serde::Deserializer<'de>,
    M: serde::de::DeserializeOwned,
{
    use serde::de::Error;
    use serde_json::Value;
    let Some(given) = Option::<Value>::deserialize(d)? else {
        return Ok(None);
    };
    let one = |v: Value| M::deserialize(v).map_err(D::Error::custom);
    Ok(Some(match given {
        Value::Array(items) if !items.is_empty() && items.iter().all(Value::is_number) => {
            vec![one(Value::Array(items))?]
        }
        Value::Array(items) => items.into_iter().map(one).collect::<Result<_, _>>()?,
        single => vec![one(single)?],
    }))
}

/// A list, or one value standing for a list of one; refused naming `key`
/// and what it takes (an untagged reading's own message names neither).
fn one_or_many<'de, D, T>(d: D, key: &str, what: &str) -> Result<Vec<T>, D::Error>
where
    D: serde::Deserializer<'de>,
    T: Deserialize<'de>,
{
    #[derive(Deserialize)]
    #[serde(untagged)]
    enum Given<T> {
        Many(Vec<T>),
        One(T),
    }
    let given = Option::<Given<T>>::deserialize(d)
        .map_err(|_| serde::de::Error::custom(format!("{key}: give {what}, or a list of them")))?;
    Ok(match given {
        None => Vec::new(),
        Some(Given::Many(v)) => v,
        Some(Given::One(v)) => vec![v],
    })
}

/// [`one_or_many`] for each keyword that takes one value or a list (serde's
/// `deserialize_with` takes a function of the deserialiser alone).
macro_rules! one_or_many_of {
    ($($name:ident: $key:literal, $what:literal;)*) => {$(
        pub(super) fn $name<'de, D, T>(d: D) -> Result<Vec<T>, D::Error>
        where
            D: serde::Deserializer<'de>,
            T: Deserialize<'de>,
        {
            one_or_many(d, $key, $what)
        }
    )*};
}

one_or_many_of! {
    many_p: "p", "a number (1/s)";
    many_b: "b", "a number (m)";
    many_h: "h", "a number (m)";
    many_width: "width", "a number (m)";
    many_height: "height", "a number (m)";
    many_eps: "eps", "a number in (0, 1] or \"housner\"";
    many_pga: "pga", "a number (g)";
    many_at: "at", "a number (the IM's unit)";
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ask(json: &str) -> Result<BlockAsk, serde_json::Error> {
        serde_json::from_str(json)
    }

    /// A floor is a list of modes or one mode, each as numbers or as the
    /// command line's text; a building likewise; a text mode that does not
    /// read is refused by its own reader.
    #[test]
    fn a_floor_is_one_mode_or_a_list_of_them_as_numbers_or_text() {
        let mode = |t: f64, z: f64, g: f64| Mode {
            period_s: t,
            zeta: z,
            gamma_phi: g,
        };
        for (floor, want) in [
            (r#""0.5,0.05,1.3""#, vec![mode(0.5, 0.05, 1.3)]),
            ("[0.5, 0.05, 1.3]", vec![mode(0.5, 0.05, 1.3)]),
            (r#"["0.5,0.05,1.3"]"#, vec![mode(0.5, 0.05, 1.3)]),
            (
                r#"[[0.5, 0.05, 1.3], "0.2,0.05,0.3"]"#,
                vec![mode(0.5, 0.05, 1.3), mode(0.2, 0.05, 0.3)],
            ),
        ] {
            let a = ask(&format!(r#"{{"b": 0.2, "h": 1, "floor": {floor}}}"#)).unwrap();
            assert_eq!(a.floor, want, "{floor}");
        }
        let e = ask(r#"{"b": 0.2, "h": 1, "floor": "0.5,0.05"}"#)
            .unwrap_err()
            .to_string();
        assert!(e.contains("0.5,0.05"), "{e}");
        let e = ask(r#"{"b": 0.2, "h": 1, "floor": []}"#)
            .unwrap_err()
            .to_string();
        assert!(e.contains("no mode given"), "{e}");
        let one = ask(r#"{"b": 0.2, "h": 1, "building": "0.8,0.05,1.3,0.4,1"}"#).unwrap();
        let list = ask(r#"{"b": 0.2, "h": 1, "building": [[0.8, 0.05, 1.3, 0.4, 1]]}"#).unwrap();
        assert_eq!(one.building, list.building);
        assert_eq!(one.building.len(), 1);
        let e = ask(r#"{"b": 0.2, "h": 1, "building": []}"#)
            .unwrap_err()
            .to_string();
        assert!(e.contains("building: no mode given"), "{e}");
    }

    /// A value of the wrong type is refused naming its keyword and what it
    /// takes, as a list of the wrong type is (serde's untagged reading says
    /// only that no variant matched).
    #[test]
    fn a_wrong_type_is_refused_naming_its_keyword() {
        for (json, says) in [
            (
                r#"{"b": "x", "h": 1}"#,
                "b: give a number (m), or a list of them",
            ),
            (
                r#"{"b": 0.2, "h": [1, "y"]}"#,
                "h: give a number (m), or a list of them",
            ),
            (
                r#"{"p": 2, "eps": "abc"}"#,
                "eps: give a number in (0, 1] or \"housner\"",
            ),
        ] {
            let e = ask(json).unwrap_err().to_string();
            assert!(e.contains(says), "{json}: {e}");
        }
        assert_eq!(ask(r#"{"b": [0.2, 0.3], "h": 1}"#).unwrap().b, [0.2, 0.3]);
    }

    /// One block by its sizes, as Python gives it: α, p and Housner's ε by
    /// hand (b/h = 0.25: ε = 1 − 1.5/17); `auto` with μ chooses the model
    /// that slides where the nonlinear one would run, and says why.
    #[test]
    fn a_block_by_its_sizes() {
        let a =
            ask(r#"{"b": 0.25, "h": 1.0, "eps": "housner", "model": "auto", "mu": 0.5}"#).unwrap();
        let one = a.resolve_one(Spelling::Python).unwrap();
        assert_eq!(one.named.name, "b0.25xh1");
        assert!((one.named.spec.eps - (1.0 - 1.5 / 17.0)).abs() < 1e-15);
        assert_eq!(one.named.alpha_rad, Some(0.25f64.atan()));
        assert_eq!(one.named.slides_first, Some(false));
        assert!(
            one.why
                .starts_with("slide-rock model: μ = 0.5 > b/h = 0.2500"),
            "{}",
            one.why
        );
        let kind = one.named.spec.model.equation.kind();
        assert_eq!(kind, crate::physics::EquationKind::SlideRock);
        let a = ask(r#"{"b": 0.25, "h": 1.0, "eps": 0.8, "model": "auto"}"#).unwrap();
        let one = a.resolve_one(Spelling::Python).unwrap();
        assert!(one.why.contains("nonlinear"), "{}", one.why);
        // The kinetic coefficient alone, or above the static one, is refused.
        let e = |json: &str| ask(json).unwrap().resolve(Spelling::Cli).unwrap_err().0;
        assert!(e(r#"{"b": 0.25, "h": 1, "eps": 0.8, "mu_k": 0.3}"#).contains("give both"));
        // Options a model takes and does nothing with: an integrator or its
        // tolerance for the linearised model, kinetic friction for a model
        // that does not slide. Each is refused, naming the models that take it.
        for (json, says) in [
            (
                r#"{"p": 2, "eps": 0.8, "integrator": "dp5"}"#,
                "integrator is the nonlinear model's",
            ),
            (
                r#"{"p": 2, "eps": 0.8, "rtol": 1e-6}"#,
                "rtol is the nonlinear model's",
            ),
            (
                r#"{"b": 0.25, "h": 1, "eps": 0.8, "mu": 0.5, "mu_k": 0.3, "model": "nonlinear"}"#,
                "--mu-k is the slide-rock model's kinetic friction",
            ),
        ] {
            assert!(e(json).contains(says), "{json}: {}", e(json));
        }
        let nonlinear = r#"{"p": 2, "eps": 0.8, "alpha": 0.2, "model": "nonlinear", "rtol": 1e-9}"#;
        assert!(ask(nonlinear).unwrap().resolve(Spelling::Python).is_ok());
        let high =
            r#"{"b": 0.25, "h": 1, "eps": 0.8, "mu": 0.3, "mu_k": 0.4, "model": "slide-rock"}"#;
        assert!(e(high).contains("must be in (0, μₛ = 0.3]"), "{}", e(high));
    }

    /// A grid p × ε, p outer.
    #[test]
    fn a_grid_of_blocks_in_order() {
        let a = ask(r#"{"p": [1.0, 2.0], "eps": [0.7, 0.8, 0.9]}"#).unwrap();
        let all = a.resolve(Spelling::Cli).unwrap();
        let got: Vec<(f64, f64)> = all
            .iter()
            .map(|b| (b.named.spec.p, b.named.spec.eps))
            .collect();
        assert_eq!(got[..4], [(1.0, 0.7), (1.0, 0.8), (1.0, 0.9), (2.0, 0.7)]);
        assert_eq!(all.len(), 6);
    }

    /// Each refusal names the option as the front end spells it.
    #[test]
    fn refusals_name_the_option_in_each_spelling() {
        let e = |json: &str, sp| ask(json).unwrap().resolve(sp).unwrap_err().0;
        assert!(e(r#"{"p": 2, "eps": "housner"}"#, Spelling::Cli)
            .contains("--eps housner needs the block's dimensions (--b --h or --width --height)"));
        assert!(
            e(r#"{"p": 2, "eps": "housner"}"#, Spelling::Python).contains(
                "eps=\"housner\" needs the block's dimensions (b and h or width and height)"
            )
        );
        assert!(e(r#"{"b": [0.1, 0.2], "h": 1, "eps": 0.8}"#, Spelling::Cli)
            .contains("--b has 2 values and --h 1"));
        assert!(e(r#"{"p": 2, "eps": 0.8, "mu": 0.3}"#, Spelling::Python)
            .starts_with("mu is compared with the block's b/h"));
        assert!(e(
            r#"{"b": 0.2, "h": 1, "eps": 0.8, "mu": -0.3}"#,
            Spelling::Cli
        )
        .starts_with("--mu: friction coefficient μ = -0.3"));
        assert!(e(
            r#"{"p": 2, "eps": 0.8, "rtol": 1e-17, "model": "nonlinear", "alpha": 0.2}"#,
            Spelling::Cli
        )
        .starts_with("--rtol: "));
        assert!(e(
            r#"{"b": 0.2, "h": 1, "width": 1, "height": 2, "eps": 0.8}"#,
            Spelling::Python
        )
        .contains("not both"));
        // Closed sets and unknown keys are refused as they are read.
        let bad = ask(r#"{"p": 2, "eps": 0.8, "model": "exact"}"#)
            .unwrap_err()
            .to_string();
        assert!(
            bad.contains("unknown model `exact`; valid: linearized, nonlinear, auto"),
            "{bad}"
        );
        assert!(ask(r#"{"p": 2, "eps": 0.8, "colour": 1}"#).is_err());
        // The alias of the British spelling.
        assert_eq!(
            ask(r#"{"model": "linearised"}"#).unwrap().model,
            ModelChoice::Linearized
        );
    }
}
