//! How far Hertz holds at a contact: the deviation of the real gap from Hertz's quadratic over
//! Hertz's own patch.
//!
//! Hertz takes the relative lateral curvature B₀ = ½(k_w + k_r) at the contact point as constant:
//! its gap across the patch is B₀ t² (t along the surface). The real gap is
//!
//! ```text
//! g(t) = ∫₀ᵗ (t − τ) 2B(τ) dτ,     B(τ) = ½ (k_w(s_w + τ c) + k_r(s_r + τ c))
//! ```
//!
//! (c = cos of the rail's slope: the profile parameter is lateral, t is along the surface). The
//! measure is the larger relative deviation at the patch's two lateral edges t = ±b,
//!
//! ```text
//! D = max± |g(±b) − B₀ b²| / (B₀ b²)
//! ```
//!
//! 0 for constant curvature; 1 where the gap at the edge is double or nothing of Hertz's (a patch
//! crossing an arc joint into a radius 6× larger gives D ≈ 0.4 on its far half). A conformal
//! contact (B₀ ≤ 0) has D = ∞. The gap is integrated by Simpson's rule on 8 intervals a side
//! (exact for curvature piecewise linear within 1e-3 of B₀ b²).
//!
//! [`HERTZ_VALIDITY_LIMIT`] = 0.25: over four profile pairs (S1002/60E1 at 1:40 and 1:20, ms-tram
//! and ms-standin on 54E1 at 1:20) Hertz's p0 is within 5.2 % of the strip model's on every contact
//! with D ≤ 0.25 and up to 96 % off beyond; with 0.30 one contact 65 % off would count as valid
//! (the scene test `contact_patches::hertz_validity_limit` asserts 10 % within; against CONTACT on
//! the Manchester benchmark Hertz is within 5.2 % where D ≤ 0.25).

use crate::profile::Profile;
use crate::track::Side;

/// Hertz is taken as valid at a contact whose gap deviation D is at most this.
pub const HERTZ_VALIDITY_LIMIT: f64 = 0.25;

/// The gap deviation D of a contact (module documentation): wheel and rail parameters at the
/// contact (paper convention, m) and Hertz's lateral semi-axis `b` (m).
pub fn hertz_deviation(
    wheel: &Profile,
    rail: &Profile,
    side: Side,
    s_wheel: f64,
    s_rail: f64,
    b: f64,
) -> f64 {
    let rel = |t: f64| -> f64 {
        let w = wheel.eval_side(side, s_wheel + t);
        let r = rail.eval_side(side, s_rail + t);
        0.5 * (w.curvature() - r.curvature())
    };
    let b0 = rel(0.0);
    if b0.is_nan() || b0 <= 0.0 || b.is_nan() || b <= 0.0 {
        return f64::INFINITY;
    }
    let c = 1.0 / (1.0 + rail.eval_side(side, s_rail).dz.powi(2)).sqrt();
    let quad = b0 * b * b;
    let mut worst: f64 = 0.0;
    for sign in [-1.0, 1.0] {
        // g(b) = ∫₀^b (b − τ) 2B(τ) dτ by Simpson on 8 intervals.
        let n = 8;
        let h = b / n as f64;
        let mut sum = 0.0;
        for k in 0..=n {
            let tau = k as f64 * h;
            let wgt = if k == 0 || k == n {
                1.0
            } else if k % 2 == 1 {
                4.0
            } else {
                2.0
            };
            sum += wgt * (b - tau) * 2.0 * rel(sign * tau * c);
        }
        let g = sum * h / 3.0;
        worst = worst.max((g - quad).abs() / quad);
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::profile::ProfileKind;

    fn arc_profile(kind: ProfileKind, radii: (f64, f64)) -> Profile {
        // Two arcs meeting tangentially at s = 0: radius radii.0 for s < 0, radii.1 for s > 0.
        let n = 801;
        let s: Vec<f64> = (0..n)
            .map(|i| -0.012 + 0.024 * i as f64 / (n - 1) as f64)
            .collect();
        let sign = if kind == ProfileKind::Rail { -1.0 } else { 1.0 };
        let z = s
            .iter()
            .map(|&s| {
                let r = if s < 0.0 { radii.0 } else { radii.1 };
                sign * (r - (r * r - s * s).sqrt())
            })
            .collect();
        Profile::from_points("arcs", kind, "test", s, z).unwrap()
    }

    #[test]
    fn constant_curvature_is_valid_and_a_joint_is_not() {
        let wheel = arc_profile(ProfileKind::Wheel, (1e3, 1e3));
        let circle = arc_profile(ProfileKind::Rail, (0.08, 0.08));
        let d = hertz_deviation(&wheel, &circle, Side::Left, 0.0, -0.002, 0.003);
        assert!(d < 0.02, "{d}");
        // 80 mm meeting 13 mm at the joint, the contact 1 mm on the R80 side, b = 4 mm: the far
        // side of the patch is 6× more curved.
        let joint = arc_profile(ProfileKind::Rail, (0.013, 0.08));
        let d = hertz_deviation(&wheel, &joint, Side::Left, 0.0, 0.001, 0.004);
        assert!(d > 1.0, "{d}");
        // Concave wheel hugging the rail: conformal, never valid.
        let hollow = arc_profile(ProfileKind::Rail, (0.07, 0.07));
        let hollow = Profile::from_points(
            "hollow",
            ProfileKind::Wheel,
            "test",
            hollow.knots().0.to_vec(),
            hollow.knots().1.to_vec(),
        )
        .unwrap();
        assert!(hertz_deviation(&hollow, &circle, Side::Left, 0.0, 0.0, 0.003).is_infinite());
    }
}
