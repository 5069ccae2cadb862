//! FASTSIM (Kalker 1982, *A fast algorithm for the simplified theory of rolling contact*, VSD 11),
//! as restated in `../shared/design/facts/creep-contact.txt` C.
//!
//! Simplified theory: the surface displacement is u = L p, one flexibility per creepage so that
//! the small-creepage limit is Kalker's linear theory exactly:
//!
//! ```text
//! L₁ = 8a / (3 C₁₁ G),   L₂ = 8a / (3 C₂₂ G),   L₃ = π a √(a/b) / (4 C₂₃ G)
//! ```
//!
//! The ellipse is cut into `strips` strips of equal width across y (strip centres y_j); each strip,
//! from its leading edge x = a_j = a √(1 − y_j²/b²) to its trailing edge −a_j, into `elements`
//! elements of length dx = 2 a_j / n, the traction held at the element centres. Marching from the
//! leading edge (p = 0; half a step to the first centre) the rigid slip per unit rolling distance,
//! evaluated midway between successive centres,
//!
//! ```text
//! Sx = ξx/L₁ − φ y/L₃,   Sy = ξy/L₂ + φ x/L₃
//! ```
//!
//! gives the adhesion traction p_H = p(x + dx) − S dx; where |p_H| exceeds the traction bound
//! μ p_z (at the centre), the element slides and p = μ p_z p_H/|p_H|. Forces (on the wheel) are
//! Σ p dx dy (midpoint rule: exact in the adhesion area for ξ alone); the spin moment is
//! Mz = Σ (x p_y − y p_x) dx dy. Holding the tractions at the centres, not at the element ends,
//! matters: a bound evaluated at the trailing edge is zero and would cut the small-creepage slope by
//! about 1/n (4 % at n = 25).
//!
//! Traction bound: Kalker's original FASTSIM uses the parabolic pressure
//! p_z = 2N/(π a b) (1 − x²/a² − y²/b²); the Hertz (elliptic) pressure 3N/(2π a b) √(…) is
//! available as an option. Discretisation error of the default 25 × 25: the small-creepage slope is
//! within 0.1 % of the linear theory (midpoint rule across the strips, error 1/(2 n_y²)).

use serde::Deserialize;
use std::f64::consts::PI;

use super::creepage::Creepage;
use super::exact::tangential::slip_root;
use super::patch::{ContactPatch, CreepForce};

/// The pressure distribution that bounds the traction.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TractionBound {
    /// p_z = 2N/(π a b) (1 − x²/a² − y²/b²) (original FASTSIM).
    #[default]
    Parabolic,
    /// Hertz: p_z = 3N/(2π a b) √(1 − x²/a² − y²/b²).
    Elliptic,
}

/// The traction's direction in a sliding element.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SlipDirection {
    /// The adhesion trial traction scaled to the bound (Kalker's original FASTSIM, and CONTACT's
    /// modified FASTSIM): with three flexibilities (L₁ ≠ L₂) it does not oppose the element's slip,
    /// and in full sliding the force is off the creepage's direction by up to ~8°.
    #[default]
    Scaled,
    /// The traction opposes the element's slip (Coulomb's law element by element): with u = L p,
    /// the slip is L(p − p_trial), and p = (L + k)⁻¹ L p_trial with k ≥ 0 such that |p| = μ p_z
    /// (the same 2 × 2 problem as the exact solver's slip elements).
    Opposing,
}

/// Discretisation and bound of FASTSIM.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FastsimSettings {
    /// Number of strips across the ellipse (lateral).
    pub strips: usize,
    /// Number of elements along each strip (longitudinal).
    pub elements: usize,
    pub bound: TractionBound,
    /// The traction's direction where an element slides.
    pub direction: SlipDirection,
}

impl Default for FastsimSettings {
    fn default() -> Self {
        FastsimSettings {
            strips: 25,
            elements: 25,
            bound: TractionBound::Parabolic,
            direction: SlipDirection::Scaled,
        }
    }
}

/// One element of the traction distribution (for inspection).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TractionElement {
    /// Element centre, m.
    pub x: f64,
    pub y: f64,
    /// Traction at the element centre (on the wheel), Pa.
    pub px: f64,
    pub py: f64,
    /// Traction bound μ p_z at the element centre, Pa.
    pub bound: f64,
    /// The element's trailing node slides.
    pub slip: bool,
}

/// FASTSIM creep forces.
pub fn forces(patch: &ContactPatch, creep: &Creepage, s: &FastsimSettings) -> CreepForce {
    march(patch, creep, s, |_| {})
}

/// FASTSIM, also returning every element's traction (for the inspector).
pub fn distribution(
    patch: &ContactPatch,
    creep: &Creepage,
    s: &FastsimSettings,
) -> (CreepForce, Vec<TractionElement>) {
    let mut elems = Vec::with_capacity(s.strips.max(1) * s.elements.max(1));
    let f = march(patch, creep, s, |e| elems.push(e));
    (f, elems)
}

fn march(
    patch: &ContactPatch,
    creep: &Creepage,
    s: &FastsimSettings,
    mut visit: impl FnMut(TractionElement),
) -> CreepForce {
    let (a, b, n) = (patch.a, patch.b, patch.normal_force);
    let g = patch.shear_modulus;
    let k = &patch.kalker;
    let l1 = 8.0 * a / (3.0 * k.c11 * g);
    let l2 = 8.0 * a / (3.0 * k.c22 * g);
    let l3 = PI * a * (a / b).sqrt() / (4.0 * k.c23 * g);
    let (ny, nx) = (s.strips.max(1), s.elements.max(1));
    let dy = 2.0 * b / ny as f64;
    let mu = patch.friction;
    let (p_scale, elliptic) = match s.bound {
        TractionBound::Parabolic => (mu * 2.0 * n / (PI * a * b), false),
        TractionBound::Elliptic => (mu * 3.0 * n / (2.0 * PI * a * b), true),
    };
    let (sx0, sy0, phi) = (creep.longitudinal / l1, creep.lateral / l2, creep.spin / l3);
    let opposing = s.direction == SlipDirection::Opposing;
    let (mut fx, mut fy, mut mz) = (0.0, 0.0, 0.0);
    let inv_a2 = 1.0 / (a * a);
    // The strips are independent: march LANES of them side by side, so that the latency chain
    // of one strip (slip test, square root, division) overlaps with the others'. Lanes past the
    // last strip have zero length and contribute nothing.
    const LANES: usize = 8;
    let mut j0 = 0;
    while j0 < ny {
        let mut y = [0.0; LANES];
        let mut aj2 = [0.0; LANES];
        let mut aj = [0.0; LANES];
        let mut dx = [0.0; LANES];
        let mut sx = [0.0; LANES];
        for l in 0..LANES {
            if j0 + l < ny {
                y[l] = -b + ((j0 + l) as f64 + 0.5) * dy;
                aj2[l] = (a * a * (1.0 - (y[l] / b).powi(2))).max(0.0);
                aj[l] = aj2[l].sqrt();
                dx[l] = 2.0 * aj[l] / nx as f64;
                sx[l] = sx0 - phi * y[l];
            }
        }
        let mut px = [0.0_f64; LANES];
        let mut py = [0.0_f64; LANES];
        let mut sfx = [0.0; LANES];
        let mut sfy = [0.0; LANES];
        let mut smz = [0.0; LANES];
        for i in 0..nx {
            let (centre, half_first) = (i as f64 + 0.5, i == 0);
            for l in 0..LANES {
                // Element centre, and the step from the previous centre (half a step from the edge).
                let x = aj[l] - centre * dx[l];
                let step = if half_first { 0.5 * dx[l] } else { dx[l] };
                let sy = sy0 + phi * (x + 0.5 * step);
                let mut qx = px[l] - sx[l] * step;
                let mut qy = py[l] - sy * step;
                // Traction bound μ p_z at the centre: 1 − x²/a² − y²/b² = (a_j² − x²)/a².
                let q = ((aj2[l] - x * x) * inv_a2).max(0.0);
                let gmax = p_scale * if elliptic { q.sqrt() } else { q };
                let mag2 = qx * qx + qy * qy;
                let slip = mag2 > gmax * gmax;
                if slip {
                    if opposing && gmax > 0.0 {
                        // s ∝ L p − L q: the root k of |(L + k)⁻¹ L q| = g.
                        let k = slip_root(-l1 * qx, -l2 * qy, l1, l2, gmax);
                        qx *= l1 / (l1 + k);
                        qy *= l2 / (l2 + k);
                    } else {
                        let f = gmax / mag2.sqrt();
                        qx *= f;
                        qy *= f;
                    }
                }
                sfx[l] += qx;
                sfy[l] += qy;
                smz[l] += x * qy - y[l] * qx;
                if j0 + l < ny {
                    visit(TractionElement {
                        x,
                        y: y[l],
                        px: qx,
                        py: qy,
                        bound: gmax,
                        slip,
                    });
                }
                px[l] = qx;
                py[l] = qy;
            }
        }
        for l in 0..LANES {
            fx += sfx[l] * dx[l] * dy;
            fy += sfy[l] * dx[l] * dy;
            mz += smz[l] * dx[l] * dy;
        }
        j0 += LANES;
    }
    CreepForce::with_saturation(fx, fy, mz, patch)
}
