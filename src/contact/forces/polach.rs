//! Polach's method (Polach 1999, *A fast wheel–rail forces calculation computer code*, VSD 33
//! suppl.; with the 2005 extension for large creep, Wear 258). Formulas as restated in
//! `../shared/design/facts/creep-contact.txt` D.
//!
//! Without spin (s = √(ξx² + ξy²)):
//!
//! ```text
//! C_jj = √((C₁₁ ξx/s)² + (C₂₂ ξy/s)²),   ε = π G a b C_jj s / (4 Q μ)
//! F = (2Qμ/π) (k_A ε / (1 + (k_A ε)²) + arctan(k_S ε)),   Fx = −F ξx/s_C,  Fy = −F ξy/s_C
//! ```
//!
//! (k_A = k_S = 1 is the 1999 method.) Spin enters through s_yC = ξy + φ a when that increases
//! |ξy| (else ξy), s_C = √(ξx² + s_yC²) replaces s in ε, and the lateral force gains
//!
//! ```text
//! K_M = 1 + 6.3 (1 − e^{−a/b}),   ε_φ = 8 b √(ab) G C₂₃ |s_yC| / (3 K_M Q μ),   δ = (ε_φ² − 1)/(ε_φ² + 1)
//! F_yS = (9/16) a Q μ K_M [ε_φ (−δ³/3 + δ²/2 − 1/6) + (1 − δ²)^{3/2}/3] φ / s_C,   Fy −= F_yS
//! ```
//!
//! At small creepage F → G a b C_jj s (Kalker's linear theory in each pure direction) and
//! F_yS → G (ab)^{3/2} C₂₃ φ (pure spin); at large creepage F → μQ. Falling friction (2005):
//! μ = μ₀ ((1 − A) e^{−B w} + A), w = s_C · V the slip velocity. Polach defines no spin moment:
//! Mz = 0.

use serde::Deserialize;
use std::f64::consts::PI;

use super::creepage::Creepage;
use super::patch::{ContactPatch, CreepForce};

/// Parameters of Polach's method. The defaults (k_A = k_S = 1, A = 1) are the 1999 method with
/// constant friction μ = the patch's μ.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PolachParams {
    /// Reduction factor of the initial slope in the area of adhesion, k_A.
    pub k_a: f64,
    /// Reduction factor in the area of slip, k_S (k_S ≤ k_A ≤ 1).
    pub k_s: f64,
    /// Ratio of limit friction at infinite slip velocity to the maximum friction, A = μ∞/μ₀.
    pub friction_ratio: f64,
    /// Exponential friction decrease rate B, s/m.
    pub friction_decay_s_per_m: f64,
}

impl Default for PolachParams {
    fn default() -> Self {
        PolachParams {
            k_a: 1.0,
            k_s: 1.0,
            friction_ratio: 1.0,
            friction_decay_s_per_m: 0.0,
        }
    }
}

/// Polach's creep forces.
pub fn forces(patch: &ContactPatch, creep: &Creepage, p: &PolachParams, speed: f64) -> CreepForce {
    let (sx, sy, phi) = (creep.longitudinal, creep.lateral, creep.spin);
    let (a, b, q, g) = (patch.a, patch.b, patch.normal_force, patch.shear_modulus);
    let k = &patch.kalker;
    let s = sx.hypot(sy);
    let syc = if (sy + phi * a).abs() > sy.abs() {
        sy + phi * a
    } else {
        sy
    };
    let sc = sx.hypot(syc);
    if sc == 0.0 {
        return CreepForce::with_saturation(0.0, 0.0, 0.0, patch);
    }
    // Constant friction (A = 1, the default) needs no exponential: (1 − A) e^{…} + A = 1 exactly.
    let mu = if p.friction_ratio == 1.0 {
        patch.friction
    } else {
        patch.friction
            * ((1.0 - p.friction_ratio) * (-p.friction_decay_s_per_m * sc * speed.abs()).exp()
                + p.friction_ratio)
    };
    if mu <= 0.0 {
        return CreepForce::with_saturation(0.0, 0.0, 0.0, patch);
    }
    let cjj = if s > 0.0 {
        ((k.c11 * sx / s).powi(2) + (k.c22 * sy / s).powi(2)).sqrt()
    } else {
        k.c22
    };
    let eps = PI * g * a * b * cjj * sc / (4.0 * q * mu);
    let ka_eps = p.k_a * eps;
    let f = 2.0 * q * mu / PI * (ka_eps / (1.0 + ka_eps * ka_eps) + (p.k_s * eps).atan());
    let fx = -f * sx / sc;
    let mut fy = -f * sy / sc;
    if phi != 0.0 {
        let km = 1.0 + 6.3 * (1.0 - (-a / b).exp());
        let eps_phi = 8.0 * b * (a * b).sqrt() * g * k.c23 * syc.abs() / (3.0 * km * q * mu);
        let e2 = eps_phi * eps_phi;
        let delta = (e2 - 1.0) / (e2 + 1.0);
        let d2 = delta * delta;
        let bracket =
            eps_phi * (-d2 * delta / 3.0 + d2 / 2.0 - 1.0 / 6.0) + (1.0 - d2).max(0.0).powf(1.5) / 3.0;
        fy -= 9.0 / 16.0 * a * q * mu * km * bracket * phi / sc;
    }
    CreepForce::with_saturation(fx, fy, 0.0, patch)
}
