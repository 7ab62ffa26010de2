//! The exact integrator: closed-form stepping of the linearised rocking
//! equation (`closed_form`), events bracketed between the closed-form
//! turning points and located to a few ulps (`locate`), small hops after an
//! impact in closed form (`hop`), and whole intervals crossed on a proof that
//! they hold no event (`proofs`, two runs at once in `lanes`); `stepper`
//! holds the constants of one (p, η, dt) and `rock` the [`super::Stepper`].
//! Derivation: docs/MODEL.md, §3.1–3.3.

mod closed_form;
mod hop;
#[cfg(target_arch = "x86_64")]
mod lanes;
mod locate;
mod proofs;
mod rock;
mod stepper;

pub use closed_form::{cosh_m1, sinhc_m1};
pub use stepper::Exact;
