//! Failures of the exact solver (its own module: the grid, the normal and the tangential problem
//! report them, and the creep-force layer wraps them).

use thiserror::Error;

/// Failures of the exact solver.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ExactError {
    #[error("exact solver: {0}")]
    Grid(String),
    #[error("exact solver: non-finite {0}")]
    NonFinite(&'static str),
    #[error("exact solver: {what} did not converge in {sweeps} sweeps")]
    NotConverged { sweeps: usize, what: &'static str },
}
