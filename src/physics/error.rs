//! The physics' one error: an input it cannot run.

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PhysicsError {
    #[error("{0}")]
    BadInput(String),
}
