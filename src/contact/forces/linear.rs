//! Kalker's linear theory with a saturation law.
//!
//! The linear forces (see [`super::ContactPatch::linear`]) grow without bound; a saturation law
//! scales the resultant so that it approaches μN:
//!
//! ```text
//! β = |F_lin| / (μN),   |F| = μN (β − β²/3 + β³/27)  for β < 3,  μN otherwise,
//! (Fx, Fy, Mz) = |F|/|F_lin| · (Fx, Fy, Mz)_lin
//! ```
//!
//! the cubic of Johnson & Vermeulen (1964) as used by Shen, Hedrick & Elkins (1983): slope 1 at
//! β = 0 (the linear theory), C¹ at β = 3 where it reaches μN.

use serde::Deserialize;

use super::creepage::Creepage;
use super::patch::{ContactPatch, CreepForce};

/// Saturation law applied to Kalker's linear forces.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Saturation {
    /// Johnson–Vermeulen cubic (Shen–Hedrick–Elkins).
    #[default]
    ShenHedrickElkins,
    /// No saturation: the linear theory alone (valid only at small creepage).
    None,
}

/// The saturation factor |F| / |F_lin| for β = |F_lin| / (μN).
pub fn saturation_factor(beta: f64) -> f64 {
    if beta <= 0.0 {
        1.0
    } else if beta < 3.0 {
        1.0 - beta / 3.0 + beta * beta / 27.0
    } else {
        1.0 / beta
    }
}

/// Forces of the linear theory, saturated.
pub fn forces(patch: &ContactPatch, creep: &Creepage, saturation: Saturation) -> CreepForce {
    let (fx, fy, mz) = patch.linear(creep);
    let s = match saturation {
        Saturation::None => 1.0,
        Saturation::ShenHedrickElkins => {
            let limit = patch.friction * patch.normal_force;
            if limit > 0.0 {
                saturation_factor(fx.hypot(fy) / limit)
            } else {
                0.0
            }
        }
    };
    CreepForce::with_saturation(s * fx, s * fy, s * mz, patch)
}
