//! FaStrip (Sichani, Enblom & Berg 2016, *An alternative to FASTSIM for tangential solution of the
//! wheel–rail contact*, Vehicle System Dynamics 54(6) 748–764; the "modified FaStrip" variant of
//! CONTACT's user guide §3.x, M = 5): Kalker's strip theory across the patch, FASTSIM's
//! direction in the slip zones.
//!
//! The ellipse is cut into strips along the rolling direction; strip j at y_j has half-length
//! a_j = a √(1 − y_j²/b²). With p₀ = 3N/(2πab) and Kalker's C₁₁, C₂₂, C₂₃ at a/b, the creepages in
//! the strip theory's normalisation are
//!
//! ```text
//! ξ' = −2(1 − ν) G C₁₁ ξ / (π² μ p₀),   η' = −2(1 − ν) G C₂₂ η / (π² μ p₀),
//! φ' = −3 √(ab) G C₂₃ φ / (2π μ p₀)
//! ```
//!
//! (the linear limit is then Kalker's exactly). The strip's slip zone runs from the trailing edge
//! over a length 2d_j,
//!
//! ```text
//! d_j = (√(η'² + (1 − φ'²)(ξ' − φ' y_j/a)²) + η' φ') / (1 − φ'²) · a / (1 − ν)
//! ```
//!
//! (full sliding where d_j ≥ a_j, d_j < 0, or the root is imaginary), and in the adhesion zone
//! x > −a_j + 2d_j Carter's two-ellipse traction holds:
//!
//! ```text
//! p_x = μ p₀ κ (√(a_j² − x²) − √((a_j − d_j)² − (x − d_j)²)) / a
//! p_y = μ p₀ (λ √(a_j² − x²) − (λ − φ') √((a_j − d_j)² − (x − d_j)²)) / a
//! κ, λ = (ξ' − φ' y_j/a, η' + φ' d_j/a) / |(ξ' − φ' y_j/a, η' + φ' d_j/a)|
//! ```
//!
//! In the slip zone the traction is μ p (p the Hertz pressure) in the direction FASTSIM gives there
//! (three flexibilities, elliptic bound, the traction opposing the local slip: [`super::fastsim`]). Where a strip's adhesion traction
//! would exceed the bound (large spin), the strip keeps FASTSIM's tractions (the modified variant's
//! check). Forces and spin moment are the midpoint sums over strips × elements, as FASTSIM's.

use serde::Deserialize;
use std::f64::consts::PI;

use super::creepage::Creepage;
use super::fastsim::{self, FastsimSettings, SlipDirection, TractionBound};
use super::patch::{ContactPatch, CreepForce};

/// Discretisation of FaStrip.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FastripSettings {
    /// Strips across the ellipse.
    pub strips: usize,
    /// Elements along each strip.
    pub elements: usize,
}

impl Default for FastripSettings {
    fn default() -> Self {
        FastripSettings {
            strips: 30,
            elements: 30,
        }
    }
}

/// FaStrip creep forces.
pub fn forces(patch: &ContactPatch, creep: &Creepage, s: &FastripSettings) -> CreepForce {
    let (a, b, n) = (patch.a, patch.b, patch.normal_force);
    let (g, nu, mu) = (patch.shear_modulus, patch.poisson, patch.friction);
    let k = &patch.kalker;
    let p0 = 1.5 * n / (PI * a * b);
    let (ny, nx) = (s.strips.max(1), s.elements.max(1));
    if mu <= 0.0 || p0 <= 0.0 {
        return CreepForce::with_saturation(0.0, 0.0, 0.0, patch);
    }
    let scale = mu * p0;
    let xi = -2.0 * (1.0 - nu) * g * k.c11 * creep.longitudinal / (PI * PI * scale);
    let eta = -2.0 * (1.0 - nu) * g * k.c22 * creep.lateral / (PI * PI * scale);
    let phi = -3.0 * (a * b).sqrt() * g * k.c23 * creep.spin / (2.0 * PI * scale);
    // FASTSIM's tractions (elliptic bound) give the direction in the slip zones.
    let fs = FastsimSettings {
        strips: ny,
        elements: nx,
        bound: TractionBound::Elliptic,
        direction: SlipDirection::Opposing,
    };
    let (_, mut elems) = fastsim::distribution(patch, creep, &fs);
    let dy = 2.0 * b / ny as f64;
    // Strip by strip (FASTSIM marches several strips side by side), leading edge first.
    let strip_of = |y: f64| ((y + b) / dy - 0.5).round() as i64;
    elems.sort_by(|p, q| strip_of(p.y).cmp(&strip_of(q.y)).then(q.x.total_cmp(&p.x)));
    let (mut fx, mut fy, mut mz) = (0.0, 0.0, 0.0);
    for j in 0..ny {
        let row = &elems[j * nx..(j + 1) * nx];
        let y = row[0].y;
        let aj = a * (1.0 - (y / b).powi(2)).max(0.0).sqrt();
        if aj <= 0.0 {
            continue;
        }
        let dx = 2.0 * aj / nx as f64;
        // Half-length of the slip zone (the strip slides wholly where it reaches the leading edge).
        let xs = xi - phi * y / a;
        let d = if (phi.abs() - 1.0).abs() <= 1e-6 {
            f64::INFINITY
        } else {
            let disc = eta * eta + (1.0 - phi * phi) * xs * xs;
            if disc >= 0.0 {
                let d = (disc.sqrt() + eta * phi) / (1.0 - phi * phi) * a / (1.0 - nu);
                if d < 0.0 {
                    f64::INFINITY
                } else {
                    d
                }
            } else {
                f64::INFINITY
            }
        };
        let ys = eta + phi * if d.is_finite() { d } else { 0.0 } / a;
        let norm = xs.hypot(ys).max(1e-300);
        let (kappa, lambda) = (xs / norm, ys / norm);
        let lambda_p = lambda - phi;
        let x_interface = if d.is_finite() { -aj + 2.0 * d } else { aj };
        // Carter's traction integrated over each element exactly (it is singular at the slip
        // zone's end when d → 0: a midpoint rule would lose ~4 % of the linear slope at 100
        // elements); where it would exceed the bound the strip keeps FASTSIM's tractions.
        let rad_adh = aj - d.min(aj);
        let over_bound = row.iter().any(|e| {
            let x = e.x;
            if x <= x_interface {
                return false;
            }
            let sq_cnt = (aj * aj - x * x).max(0.0).sqrt() / a;
            let sq_adh = (rad_adh * rad_adh - (x - d).powi(2)).max(0.0).sqrt() / a;
            let (qx, qy) = (kappa * (sq_cnt - sq_adh), lambda * sq_cnt - lambda_p * sq_adh);
            qx * qx + qy * qy > 1.0 + 1e-12
        });
        for (i, e) in row.iter().enumerate() {
            if over_bound {
                fx += e.px * dx * dy;
                fy += e.py * dx * dy;
                mz += (e.x * e.py - y * e.px) * dx * dy;
                continue;
            }
            // The element [lo, hi] (elements run from the leading edge backwards).
            let hi = aj - i as f64 * dx;
            let lo = hi - dx;
            // Adhesion part: ∫ μ p₀ (κ, λ)·√(a_j² − x²)/a − μ p₀ (κ, λ')·√(r² − (x − d)²)/a.
            let (alo, ahi) = (lo.max(x_interface), hi);
            if ahi > alo {
                let (c0, c1) = disc_moments(aj, 0.0, alo, ahi);
                let (d0, d1) = disc_moments(rad_adh, d, alo, ahi);
                let k = scale / a;
                // Force of the part, and the moment ∫ x p_y of its lateral traction.
                let (px0, py0) = (k * kappa * (c0 - d0), k * (lambda * c0 - lambda_p * d0));
                let xpy = k * (lambda * c1 - lambda_p * d1);
                fx += px0 * dy;
                fy += py0 * dy;
                mz += (xpy - y * px0) * dy;
            }
            // Slip part: the bound μ p = μ p₀ √(a_j² − x²)/a in FASTSIM's direction.
            let (slo, shi) = (lo, hi.min(x_interface));
            if shi > slo {
                let m = e.px.hypot(e.py);
                if m > 0.0 {
                    let (ux, uy) = (e.px / m, e.py / m);
                    let (c0, c1) = disc_moments(aj, 0.0, slo, shi);
                    let k = scale / a;
                    fx += k * ux * c0 * dy;
                    fy += k * uy * c0 * dy;
                    mz += k * (uy * c1 - y * ux * c0) * dy;
                }
            }
        }
    }
    CreepForce::with_saturation(fx, fy, mz, patch)
}

/// ∫ √(r² − (x − c)²) dx and ∫ x √(r² − (x − c)²) dx over [lo, hi] ∩ [c − r, c + r].
fn disc_moments(r: f64, c: f64, lo: f64, hi: f64) -> (f64, f64) {
    let (lo, hi) = (lo.max(c - r), hi.min(c + r));
    if hi <= lo || hi.is_nan() || lo.is_nan() || r <= 0.0 {
        return (0.0, 0.0);
    }
    // With t = x − c: F0(t) = (t √(r² − t²) + r² asin(t/r))/2, F1(t) = −(r² − t²)^{3/2}/3 (the
    // moment about c), and ∫ x = ∫ t + c ∫ 1.
    let f0 = |t: f64| {
        let q = (r * r - t * t).max(0.0);
        0.5 * (t * q.sqrt() + r * r * (t / r).clamp(-1.0, 1.0).asin())
    };
    let f1 = |t: f64| -(r * r - t * t).max(0.0).powf(1.5) / 3.0;
    let (t0, t1) = (lo - c, hi - c);
    let i0 = f0(t1) - f0(t0);
    (i0, f1(t1) - f1(t0) + c * i0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::forces::kalker::KalkerTable;

    fn patch(a_mm: f64, b_mm: f64) -> ContactPatch {
        ContactPatch::new(a_mm * 1e-3, b_mm * 1e-3, 80e3, 82e9, 0.3, &KalkerTable::new(0.28)).unwrap()
    }

    /// Small creepage: Kalker's linear theory (the normalisation makes it so: Carter's strip in the
    /// limit d → 0 integrates to G ab C ξ).
    #[test]
    fn small_creepage_is_kalkers_linear_theory() {
        for (a, b) in [(6.0, 6.0), (4.0, 8.0), (8.0, 4.0)] {
            let p = patch(a, b);
            let s = FastripSettings {
                strips: 100,
                elements: 100,
            };
            let (g, ab) = (p.shear_modulus, p.a * p.b);
            let fx = forces(&p, &Creepage::new(1e-7, 0.0, 0.0), &s);
            let fy = forces(&p, &Creepage::new(0.0, 1e-7, 0.0), &s);
            let c11 = -fx.fx / (g * ab * 1e-7);
            let c22 = -fy.fy / (g * ab * 1e-7);
            assert!(
                (c11 / p.kalker.c11 - 1.0).abs() < 0.02,
                "{a}x{b}: C11 {c11} vs {}",
                p.kalker.c11
            );
            assert!(
                (c22 / p.kalker.c22 - 1.0).abs() < 0.02,
                "{a}x{b}: C22 {c22} vs {}",
                p.kalker.c22
            );
        }
    }

    /// Large creepage: full sliding, |F| = μN along the creepage.
    #[test]
    fn large_creepage_slides_fully() {
        let p = patch(6.0, 4.0);
        let f = forces(&p, &Creepage::new(0.03, -0.04, 0.0), &FastripSettings::default());
        let mun = 0.3 * 80e3;
        assert!((f.fx.hypot(f.fy) / mun - 1.0).abs() < 0.01, "{f:?}");
        assert!((f.fy / f.fx - (-0.04 / 0.03)).abs() < 0.02, "{f:?}");
    }
}
