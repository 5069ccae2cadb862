//! The clothoid (and circle, and straight) as one integral: position along a plane curve whose
//! curvature is linear in arc length.
//!
//! With heading ψ(u) = ψ_k + κ_k u + κ' u²/2 from a node k (paper Tab. 1: ρ_h linear in s in a
//! transition, constant in a curve, zero on a straight), the position is
//!
//! ```text
//! x + i y = x_k + i y_k + e^{iψ_k} I(h),   I(h) = ∫₀^h exp(i(κ_k t + κ' t²/2)) dt,
//! ```
//!
//! a Fresnel integral. We evaluate I(h) — and, at no extra cost, the unit tangent
//! f(h) = exp(i(κ_k h + κ' h²/2)) — from the power series of f, f' = i(κ_k + κ' t) f, whose
//! coefficients follow the exact recurrence
//!
//! ```text
//! d₀ = 1,  d₁ = i a d₀,  d_{m+1} = i (a d_m + 2 b d_{m−1}) / (m + 1),   a = κ_k h, b = κ' h²/2,
//! f(h) = Σ d_m,   I(h) = h Σ d_m / (m + 1).
//! ```
//!
//! This is the Fresnel integral by its convergent series, not a chord approximation: the
//! centreline keeps nodes close enough (|a|, |b| ≤ 0.05, see [`super::centreline`]) that the terms
//! fall below 1e-17 after about nine of them, and the series is summed until they do. Unlike the
//! textbook C(ξ) + i S(ξ) form it needs no special case for a transition that starts on a curve
//! (κ_k ≠ 0) or for κ' → 0 (a circle, a straight), where the completed-square form is
//! ill-conditioned.

/// A complex number as (re, im); the series needs nothing more.
pub type C64 = (f64, f64);

/// Largest |κ h| and |κ' h²/2| the node spacing allows (the series then needs ~9 terms).
pub const MAX_PHASE_STEP: f64 = 0.05;

/// Terms are summed until two consecutive ones are below this (relative to 1).
const TERM_TOL: f64 = 1e-18;

/// Unit tangent `f(h)` and integral `I(h)` of exp(i(κ t + κ' t²/2)) over t ∈ [0, h], relative
/// to the heading at t = 0 (see the module doc).
#[inline]
pub fn local_step(kappa: f64, kappa_prime: f64, h: f64) -> (C64, C64) {
    let a = kappa * h;
    let b = 0.5 * kappa_prime * h * h;
    // d_{m-1}, d_m
    let mut prev: C64 = (0.0, 0.0);
    let mut cur: C64 = (1.0, 0.0);
    let mut f: C64 = (1.0, 0.0);
    let mut integral: C64 = (1.0, 0.0);
    for m in 0..60 {
        // next = i (a cur + 2 b prev) / (m + 1)
        let re = a * cur.0 + 2.0 * b * prev.0;
        let im = a * cur.1 + 2.0 * b * prev.1;
        let inv = 1.0 / (m as f64 + 1.0);
        let next = (-im * inv, re * inv);
        f.0 += next.0;
        f.1 += next.1;
        let w = 1.0 / (m as f64 + 2.0);
        integral.0 += next.0 * w;
        integral.1 += next.1 * w;
        let small = |z: C64| z.0.abs() + z.1.abs() < TERM_TOL;
        prev = cur;
        cur = next;
        if small(prev) && small(cur) {
            break;
        }
    }
    (f, (integral.0 * h, integral.1 * h))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn straight_and_circle_closed_forms() {
        let (f, i) = local_step(0.0, 0.0, 3.0);
        assert_eq!(f, (1.0, 0.0));
        assert!((i.0 - 3.0).abs() < 1e-15 && i.1.abs() < 1e-15);
        // Circle of radius R: I(h) = (sin(h/R), 1 − cos(h/R)) R.
        let (r, h) = (200.0, 9.0);
        let (f, i) = local_step(1.0 / r, 0.0, h);
        let ph = h / r;
        assert!((f.0 - ph.cos()).abs() < 1e-16 && (f.1 - ph.sin()).abs() < 1e-16);
        assert!((i.0 - r * ph.sin()).abs() < 1e-13, "{:e}", i.0 - r * ph.sin());
        assert!((i.1 - r * (1.0 - ph.cos())).abs() < 1e-13);
    }

    #[test]
    fn tangent_is_unit_and_matches_heading() {
        let (k, kp, h) = (0.004, 8.5e-5, 10.0);
        let (f, _) = local_step(k, kp, h);
        let psi = k * h + 0.5 * kp * h * h;
        assert!(
            (f.0 - psi.cos()).abs() < 1e-15 && (f.1 - psi.sin()).abs() < 1e-15,
            "{f:?}"
        );
    }

    #[test]
    fn integral_matches_gauss_legendre() {
        // 20-panel 5-point Gauss–Legendre of exp(i(κ t + κ' t²/2)).
        let (k, kp, h) = (-0.003, 4.0e-4, 12.0);
        let (x, w) = (
            [
                0.0,
                -0.538_469_310_105_683_1,
                0.538_469_310_105_683_1,
                -0.906_179_845_938_664,
                0.906_179_845_938_664,
            ],
            [
                0.568_888_888_888_888_9,
                0.478_628_670_499_366_5,
                0.478_628_670_499_366_5,
                0.236_926_885_056_189_1,
                0.236_926_885_056_189_1,
            ],
        );
        let n = 20;
        let (mut re, mut im) = (0.0, 0.0);
        for p in 0..n {
            let (a, b) = (p as f64 * h / n as f64, (p + 1) as f64 * h / n as f64);
            for j in 0..5 {
                let t = 0.5 * (a + b) + 0.5 * (b - a) * x[j];
                let ph = k * t + 0.5 * kp * t * t;
                re += 0.5 * (b - a) * w[j] * ph.cos();
                im += 0.5 * (b - a) * w[j] * ph.sin();
            }
        }
        let (_, i) = local_step(k, kp, h);
        assert!(
            (i.0 - re).abs() < 1e-13 && (i.1 - im).abs() < 1e-13,
            "{i:?} vs {re} {im}"
        );
    }
}
