//! Kalker's exact theory of steady rolling contact on a grid: the reference the creep-force
//! models are measured against (`kecsim creep --model exact`, `kecsim bench creep-accuracy`).
//!
//! The contact patch is cut into rectangular elements of constant traction (`grid`); the
//! half-space gives each element's displacement under every other's traction in closed form
//! (`influence`); the normal pressure is Hertz's on the ellipse ([`PressureGrid::hertz`]), any
//! given shape ([`PressureGrid::from_fn`]: a non-Hertzian patch of the strip model), or the
//! discrete normal problem's solution for a gap (`normal`); the tangential problem — stick where
//! the slip vanishes, slip opposing the traction at the bound μ p — is solved element by element
//! (`tangential`). Forces are Σ p dx dy, the spin moment Σ (x p_y − y p_x) dx dy.
//!
//! This is the theory CONTACT (Vollebregt, after Kalker) implements; the code is kecsim's own,
//! checked against CONTACT's published outputs (`tests/data/contact/`) and against Kalker's
//! linear-theory coefficients (`super::kalker`) at small creepage. Its error is the grid's:
//! first order in the element size (`docs/method.md`, "Creep forces"); [`ExactSettings::default`]
//! holds the force within the figure stated there.
//!
//! Cost: O(n²) per Gauss–Seidel sweep for n elements in contact (~20 ms at the default 40 × 40
//! on one core): a reference and a table builder, not a model for the integration's every step.

pub(crate) mod grid;
pub(crate) mod influence;
pub mod normal;
pub(crate) mod tangential;

use serde::Deserialize;
use thiserror::Error;

pub use grid::{Grid, PressureGrid};
pub use tangential::{ElementState, IterationSettings, RollingOperator, TractionSolution};

use super::creepage::Creepage;
use super::patch::{ContactPatch, CreepForce};

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

/// Discretisation of the exact solver on a Hertzian patch.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ExactSettings {
    /// Elements along the ellipse's length 2a (rolling direction).
    pub elements_x: usize,
    /// Elements across its width 2b.
    pub elements_y: usize,
    /// Gauss–Seidel stops when no traction changes by more than this × μ p₀ in a sweep.
    pub tolerance: f64,
}

impl Default for ExactSettings {
    fn default() -> Self {
        ExactSettings {
            elements_x: 40,
            elements_y: 40,
            tolerance: 1e-7,
        }
    }
}

impl ExactSettings {
    /// Problems with the settings (empty when valid).
    pub fn problems(&self) -> Vec<String> {
        let mut p = Vec::new();
        for (n, what) in [(self.elements_x, "elements_x"), (self.elements_y, "elements_y")] {
            if !(4..=400).contains(&n) {
                p.push(format!("exact: {what} = {n}: expected 4 ..= 400"));
            }
        }
        if !(self.tolerance > 0.0 && self.tolerance <= 1e-2) {
            p.push(format!(
                "exact: tolerance = {}: expected (0, 0.01]",
                self.tolerance
            ));
        }
        p
    }
}

/// The exact solution on a Hertzian patch: the pressure grid and the tangential solution.
#[derive(Debug, Clone)]
pub struct HertzSolution {
    pub pressure: PressureGrid,
    pub traction: TractionSolution,
}

/// Solve the steady rolling problem on the patch's Hertz ellipse.
pub fn solve_hertz(
    patch: &ContactPatch,
    creep: &Creepage,
    s: &ExactSettings,
) -> Result<HertzSolution, ExactError> {
    let pressure = PressureGrid::hertz(patch.a, patch.b, patch.normal_force, s.elements_x, s.elements_y)?;
    let op = RollingOperator::for_grid(&pressure, patch.shear_modulus, patch.poisson);
    let it = IterationSettings {
        tolerance: s.tolerance,
        ..IterationSettings::default()
    };
    let traction = op.solve(&pressure, patch.friction, creep, &it, None)?;
    Ok(HertzSolution { pressure, traction })
}

/// Creep forces of the exact theory on the patch's Hertz ellipse.
pub fn forces(patch: &ContactPatch, creep: &Creepage, s: &ExactSettings) -> Result<CreepForce, ExactError> {
    let sol = solve_hertz(patch, creep, s)?;
    let t = &sol.traction;
    Ok(CreepForce::with_saturation(t.fx, t.fy, t.mz, patch))
}

#[cfg(test)]
mod tests;
