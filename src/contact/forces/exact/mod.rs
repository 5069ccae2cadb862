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
//! first order in the element size, and [`ExactSettings::default`] extrapolates it away
//! (Richardson, 32 and 16 elements across: within 0.3 % of μN of the converged force in the
//! partly-sliding range).
//!
//! Cost: O(n²) per Gauss–Seidel sweep for n elements in contact (10–70 ms for the default on one
//! core): a reference and a table builder, not a model for the integration's every step.

pub mod error;
pub(crate) mod grid;
pub(crate) mod influence;
pub mod normal;
pub(crate) mod tangential;

use serde::Deserialize;

pub use error::ExactError;
pub use grid::{Grid, PressureGrid};
pub use tangential::{ElementState, IterationSettings, RollingOperator, TractionSolution};

use super::creepage::Creepage;
use super::patch::{ContactPatch, CreepForce};

/// Discretisation of the exact solver on a Hertzian patch.
///
/// The grid error is first order in the element size: on a 6 × 6 mm circle at ξ = 10⁻³ (Fx/μN
/// ≈ −0.44) it is 2.1 % of μN at 24 elements across, 1.3 % at 32, 0.7 % at 64. With `richardson`
/// the patch is solved twice, at n and n/2 elements, and F = 2 F_n − F_{n/2} removes the first-order
/// term: 0.1–0.3 % of μN in the partly-sliding range and ≈ 1 % of the force in the linear range
/// at n = 32 (measured: `docs/method.md`, "Creep forces: the exact theory").
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ExactSettings {
    /// Elements along the ellipse's length 2a and across its width 2b (each).
    pub elements: usize,
    /// Richardson extrapolation from n and n/2 elements.
    pub richardson: bool,
    /// Gauss–Seidel stops when no traction changes by more than this × the largest traction in a
    /// sweep (10⁻⁴: the forces within 10⁻⁶ μN of the converged iteration's, measured on six cases).
    pub tolerance: f64,
}

impl Default for ExactSettings {
    fn default() -> Self {
        ExactSettings {
            elements: 32,
            richardson: true,
            tolerance: 1e-4,
        }
    }
}

impl ExactSettings {
    /// Problems with the settings (empty when valid).
    pub fn problems(&self) -> Vec<String> {
        let mut p = Vec::new();
        if !(8..=400).contains(&self.elements) || (self.richardson && self.elements % 2 == 1) {
            p.push(format!(
                "exact: elements = {}: expected 8 ..= 400 (even with richardson)",
                self.elements
            ));
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

/// Solve the steady rolling problem on the patch's Hertz ellipse with n × n elements over it,
/// starting from `start` (a solution on another grid over the same patch, e.g. a coarser one).
pub fn solve_hertz(
    patch: &ContactPatch,
    creep: &Creepage,
    elements: usize,
    tolerance: f64,
) -> Result<HertzSolution, ExactError> {
    solve_hertz_from(patch, creep, elements, tolerance, None)
}

fn solve_hertz_from(
    patch: &ContactPatch,
    creep: &Creepage,
    elements: usize,
    tolerance: f64,
    start: Option<&HertzSolution>,
) -> Result<HertzSolution, ExactError> {
    let pressure = PressureGrid::hertz(patch.a, patch.b, patch.normal_force, elements, elements)?;
    let op = RollingOperator::for_grid(&pressure, patch.shear_modulus, patch.poisson);
    let it = IterationSettings {
        tolerance,
        ..IterationSettings::default()
    };
    let guess = start.map(|s| prolong(s, &pressure.grid));
    let traction = op.solve(
        &pressure,
        patch.friction,
        creep,
        &it,
        guess.as_ref().map(|(x, y)| (x.as_slice(), y.as_slice())),
    )?;
    Ok(HertzSolution { pressure, traction })
}

/// A solution's tractions carried to another grid over the same area (piecewise constant: each
/// element takes the value of the element its centre lies in).
fn prolong(from: &HertzSolution, to: &Grid) -> (Vec<f64>, Vec<f64>) {
    let g = &from.pressure.grid;
    let (mut px, mut py) = (Vec::with_capacity(to.len()), Vec::with_capacity(to.len()));
    for j in 0..to.my {
        let jc = (((to.y(j) - g.y_lo) / g.dy).floor().max(0.0) as usize).min(g.my - 1);
        for i in 0..to.mx {
            let ic = (((to.x(i) - g.x_lo) / g.dx).floor().max(0.0) as usize).min(g.mx - 1);
            px.push(from.traction.px[jc * g.mx + ic]);
            py.push(from.traction.py[jc * g.mx + ic]);
        }
    }
    (px, py)
}

/// Creep forces of the exact theory on the patch's Hertz ellipse (Richardson-extrapolated when
/// the settings say so; the fine grid then starts from the coarse grid's tractions).
pub fn forces(patch: &ContactPatch, creep: &Creepage, s: &ExactSettings) -> Result<CreepForce, ExactError> {
    if let Some(p) = s.problems().first() {
        return Err(ExactError::Grid(p.clone()));
    }
    let (fx, fy, mz) = if s.richardson {
        let coarse = solve_hertz(patch, creep, s.elements / 2, s.tolerance)?;
        let fine = solve_hertz_from(patch, creep, s.elements, s.tolerance, Some(&coarse))?;
        let (c, f) = (&coarse.traction, &fine.traction);
        (2.0 * f.fx - c.fx, 2.0 * f.fy - c.fy, 2.0 * f.mz - c.mz)
    } else {
        let f = solve_hertz(patch, creep, s.elements, s.tolerance)?.traction;
        (f.fx, f.fy, f.mz)
    };
    Ok(CreepForce::with_saturation(fx, fy, mz, patch))
}

#[cfg(test)]
mod tests;
