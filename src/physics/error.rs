//! The physics' errors: an input it cannot run, a stop asked for.

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PhysicsError {
    #[error("{0}")]
    BadInput(String),
    /// The run was not started: a stop was asked for ([`super::interrupt`]).
    #[error("interrupted")]
    Interrupted,
}
