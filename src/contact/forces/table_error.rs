//! Why the exact-theory table cannot answer (its own module: the table raises it and
//! [`super::patch::CreepForceError`] wraps it).

use thiserror::Error;

/// A table that cannot be read or used.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum TableError {
    #[error("exact-theory table: {0}")]
    Format(String),
    #[error("exact-theory table: a/b = {0:.4} outside its range {1:.2}–{2:.2}")]
    OutOfRange(f64, f64, f64),
    #[error("exact-theory table: built for Poisson's ratio {table}, the patch has {patch}")]
    Poisson { table: f64, patch: f64 },
}
