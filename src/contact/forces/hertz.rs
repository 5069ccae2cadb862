//! Hertz contact between wheel and rail (paper §7: the creep forces need the contact ellipse, from
//! the surface curvatures at the **real** contact point and the normal force).
//!
//! Relative curvatures, convex positive (`../shared/design/facts/creep-contact.txt` B):
//!
//! ```text
//! A = ½ (k_wx + k_rx),   k_wx = cos γ / r   (wheel, rolling direction; rail straight: k_rx = 0)
//! B = ½ (k_wy + k_ry)                        (lateral: wheel and rail profile curvatures)
//! ```
//!
//! `cos γ / r` is the normal curvature of the wheel's parallel circle at a point of radius r whose
//! surface normal makes the angle γ with the radial direction (Meusnier). Many codes take 1/r; the
//! difference matters on the flange (γ ≈ 60–70°) where it halves A. A departure from nothing in the
//! paper, which does not state it.
//!
//! With A ≤ B the longer semi-axis lies along x. The eccentricity e (g = b/a = √(1 − e²)) solves
//!
//! ```text
//! B / A = [E(e)/(1 − e²) − K(e)] / [K(e) − E(e)]
//! ```
//!
//! and, with 1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂ (k₁ + k₂ = 1/(π E*)):
//!
//! ```text
//! a = m c₀,  b = n c₀,  c₀ = [3 N / (4 E* (A + B))]^(1/3),   m = [2 E(e) / (π g²)]^(1/3),  n = m g
//! p₀ = 3 N / (2 π a b),   δ = b² (A + B) K(e) / E(e)   (approach of the two bodies, b the minor axis)
//! ```
//!
//! Solved by a safeguarded Newton iteration on ln g with analytic derivatives of K and E, seeded by
//! Johnson's approximation g ≈ (A/B)^(2/3); for B/A − 1 < 1e-7 the series B/A ≈ 1 + ¾ e² is used
//! (K − E loses all its digits there).
//!
//! **Tabulated** for the dynamics (7 % of the MS case's right-hand side went to the iteration): m, n,
//! K/E and e² against x = ln(B/A) ∈ [0, ln 1000] on [`SHAPE_TABLE_KNOTS`] knots, not-a-knot cubic
//! splines through the Newton solutions (all four are smooth in x, e² ≈ 4x/3 near the circle); beyond
//! 1000 the Newton solution. Within 1e-10 of it (relative; test).

use std::sync::OnceLock;

use thiserror::Error;

use super::elliptic::{complete_ke, derivatives};
use crate::spline::CubicSpline;

/// Largest curvature ratio B/A the shape table covers.
pub const SHAPE_TABLE_MAX_RATIO: f64 = 1000.0;
/// Knots of the shape table, uniform in ln(B/A).
pub const SHAPE_TABLE_KNOTS: usize = 3000;

/// The ellipse shape against x = ln(B/A): m, n, K/E, e².
struct ShapeTable {
    m: CubicSpline,
    n: CubicSpline,
    k_over_e: CubicSpline,
    e2: CubicSpline,
}

static SHAPE_TABLE: OnceLock<Option<ShapeTable>> = OnceLock::new();

/// The shape table, built on first use from the Newton solutions (None if a knot failed: the
/// Newton solution is then used everywhere).
fn shape_table() -> Option<&'static ShapeTable> {
    SHAPE_TABLE
        .get_or_init(|| {
            let x_max = SHAPE_TABLE_MAX_RATIO.ln();
            let xs: Vec<f64> = (0..SHAPE_TABLE_KNOTS)
                .map(|i| x_max * i as f64 / (SHAPE_TABLE_KNOTS - 1) as f64)
                .collect();
            let shapes = xs
                .iter()
                .map(|x| EllipseShape::from_ratio(x.exp()))
                .collect::<Result<Vec<_>, _>>()
                .ok()?;
            let column = |f: fn(&EllipseShape) -> f64| {
                CubicSpline::new(xs.clone(), shapes.iter().map(f).collect()).ok()
            };
            Some(ShapeTable {
                m: column(|s| s.m)?,
                n: column(|s| s.n)?,
                k_over_e: column(|s| s.k_over_e)?,
                e2: column(|s| s.e * s.e)?,
            })
        })
        .as_ref()
}

/// Elastic constants of a body (or of both, wheel and rail being the same steel).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    /// Young's modulus E, Pa.
    pub young_pa: f64,
    /// Poisson's ratio ν.
    pub poisson: f64,
}

impl Material {
    /// Wheel and rail steel: E = 210 GPa, ν = 0.28 (G = 82.0 GPa).
    pub const STEEL: Material = Material {
        young_pa: 2.1e11,
        poisson: 0.28,
    };

    /// Shear modulus G = E / (2 (1 + ν)).
    pub fn shear_modulus(&self) -> f64 {
        self.young_pa / (2.0 * (1.0 + self.poisson))
    }

    /// Contact modulus E* of two bodies: 1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂.
    pub fn contact_modulus(&self, other: &Material) -> f64 {
        1.0 / ((1.0 - self.poisson.powi(2)) / self.young_pa + (1.0 - other.poisson.powi(2)) / other.young_pa)
    }
}

impl Default for Material {
    fn default() -> Self {
        Material::STEEL
    }
}

/// Relative curvatures A (rolling direction x) and B (lateral direction y), 1/m, convex positive.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RelativeCurvature {
    pub a: f64,
    pub b: f64,
}

impl RelativeCurvature {
    /// From the real contact point: the wheel's rolling radius r (m) and contact angle γ (rad, between
    /// the contact normal and the wheel's radial direction), the lateral curvatures of the wheel and
    /// rail profiles (1/m, convex positive, as [`crate::contact::ContactPoint`] gives them).
    /// The rail is straight along x.
    pub fn wheel_rail(
        rolling_radius: f64,
        contact_angle: f64,
        wheel_curvature: f64,
        rail_curvature: f64,
    ) -> Self {
        let a = 0.5 * contact_angle.cos().abs() / rolling_radius;
        let b = 0.5 * (wheel_curvature + rail_curvature);
        // Conformal contact (a wheel throat hugging the rail's gauge corner: B → 0): Hertz's
        // ellipse would grow without bound across a band where the profiles are only nearly
        // conformal. The ratio of the curvatures is held to MAX_CURVATURE_RATIO (semi-axes ratio
        // ≈ 10, where Kalker's tables end) both ways — a stated limit, not Hertz. Concave-on-
        // concave (B < 0 by more than the limit would lift) stays an error.
        //
        // Measured (issue 49, Manchester benchmark against CONTACT): in deep flange contact
        // (B/A ≈ 70) the clamp A ≥ B/31.6 raises p0 by 20–35 % (2.2 % off without it). It stays in
        // the dynamics: without it the hard cases' flange events change (the alignment kink's
        // elastic derailment completes instead; the flange-lift ratio of KEC to elastic goes from
        // 1.78 to 5.0), which is not resolved yet. The runs' reported p0 and area do not take it:
        // a clamped contact's patch is recomputed by the strip model
        // ([`crate::dynamics::patches`]), which reproduces the unclamped Hertz there.
        let b = if b > -a { b.max(a / MAX_CURVATURE_RATIO) } else { b };
        let a = a.max(b / MAX_CURVATURE_RATIO);
        RelativeCurvature { a, b }
    }
}

/// The smallest B/A a conformal wheel–rail contact is given (B ≥ A / this; see
/// [`RelativeCurvature::wheel_rail`]): 31.6 = 10^1.5, where Johnson's g ≈ (A/B)^(2/3) reaches
/// b/a = 0.1, the end of Kalker's tables.
pub const MAX_CURVATURE_RATIO: f64 = 31.6;

impl RelativeCurvature {
    /// At a real contact point of the contact geometry. Its contact angle is measured in the track
    /// frame; the wheel's radial direction is tilted by the wheelset roll φ (a few mrad), which
    /// changes cos γ by at most sin γ · |φ| (< 0.3 % at 70°, 3 mrad): neglected.
    pub fn at_contact(point: &crate::contact::ContactPoint) -> Self {
        RelativeCurvature::wheel_rail(
            point.rolling_radius,
            point.contact_angle,
            point.wheel_curvature,
            point.rail_curvature,
        )
    }
}

/// Why no Hertz ellipse exists.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum HertzError {
    #[error("non-Hertzian contact: relative curvatures A = {a:.4} 1/m, B = {b:.4} 1/m must both be positive (conformal or concave contact)")]
    NotConvex { a: f64, b: f64 },
    #[error("invalid Hertz input: {0}")]
    Input(String),
}

/// The Hertz contact ellipse and its pressure.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzContact {
    /// Semi-axis in the rolling direction x, m.
    pub a: f64,
    /// Semi-axis in the lateral direction y, m.
    pub b: f64,
    /// Approach (penetration) of the two bodies, m.
    pub penetration: f64,
    /// Maximum pressure p₀ = 3N / (2π a b), Pa.
    pub max_pressure: f64,
    /// The normal force the ellipse was computed for, N.
    pub normal_force: f64,
    /// Eccentricity e of the ellipse (0: circle).
    pub eccentricity: f64,
    /// Classical Hertz coefficients m, n (a or b = m or n · c₀, m along the longer axis).
    pub m: f64,
    pub n: f64,
}

impl HertzContact {
    /// a / b.
    pub fn ratio(&self) -> f64 {
        self.a / self.b
    }

    /// Solve the Hertz problem for normal force N > 0 between two bodies of the given materials
    /// (the ellipse's shape from the table within its range).
    pub fn solve(
        curvature: RelativeCurvature,
        normal_force: f64,
        m1: &Material,
        m2: &Material,
    ) -> Result<HertzContact, HertzError> {
        Self::solve_with(curvature, normal_force, m1, m2, EllipseShape::of_ratio)
    }

    /// [`Self::solve`] with the ellipse's shape by the Newton iteration instead of the table: the
    /// reference the table is checked against (tests, `kecsim bench creep`).
    pub fn solve_by_newton(
        curvature: RelativeCurvature,
        normal_force: f64,
        m1: &Material,
        m2: &Material,
    ) -> Result<HertzContact, HertzError> {
        Self::solve_with(curvature, normal_force, m1, m2, EllipseShape::from_ratio)
    }

    fn solve_with(
        curvature: RelativeCurvature,
        normal_force: f64,
        m1: &Material,
        m2: &Material,
        shape_of: fn(f64) -> Result<EllipseShape, HertzError>,
    ) -> Result<HertzContact, HertzError> {
        let RelativeCurvature { a: ca, b: cb } = curvature;
        if !(ca.is_finite() && cb.is_finite()) || ca <= 0.0 || cb <= 0.0 {
            return Err(HertzError::NotConvex { a: ca, b: cb });
        }
        if !(normal_force.is_finite() && normal_force > 0.0) {
            return Err(HertzError::Input(format!(
                "normal force {normal_force} N must be positive"
            )));
        }
        // Longer axis along the smaller curvature.
        let (small, large) = if ca <= cb { (ca, cb) } else { (cb, ca) };
        let shape = shape_of(large / small)?;
        let e_star = m1.contact_modulus(m2);
        let c0 = (3.0 * normal_force / (4.0 * e_star * (ca + cb))).cbrt();
        let major = shape.m * c0;
        let minor = shape.n * c0;
        let (a, b) = if ca <= cb { (major, minor) } else { (minor, major) };
        Ok(HertzContact {
            a,
            b,
            penetration: minor * minor * (ca + cb) * shape.k_over_e,
            max_pressure: 3.0 * normal_force / (2.0 * std::f64::consts::PI * a * b),
            normal_force,
            eccentricity: shape.e,
            m: shape.m,
            n: shape.n,
        })
    }

    /// The ellipse scaled to another normal force (a, b ∝ N^(1/3), δ ∝ N^(2/3), p₀ ∝ N^(1/3)):
    /// the shape depends on the curvatures only, so a dynamics step can reuse it.
    pub fn scaled(&self, normal_force: f64) -> HertzContact {
        let s = (normal_force / self.normal_force).cbrt();
        HertzContact {
            a: self.a * s,
            b: self.b * s,
            penetration: self.penetration * s * s,
            max_pressure: self.max_pressure * s,
            normal_force,
            ..*self
        }
    }
}

/// Shape of the ellipse for a curvature ratio B/A ≥ 1 (larger over smaller).
#[derive(Debug, Clone, Copy)]
struct EllipseShape {
    e: f64,
    m: f64,
    n: f64,
    /// K(e) / E(e).
    k_over_e: f64,
}

impl EllipseShape {
    /// From the table ([`shape_table`]) within its range, else by Newton ([`Self::from_ratio`]).
    fn of_ratio(ratio: f64) -> Result<EllipseShape, HertzError> {
        if (1.0..=SHAPE_TABLE_MAX_RATIO).contains(&ratio) {
            if let Some(t) = shape_table() {
                let x = ratio.ln();
                return Ok(EllipseShape {
                    e: t.e2.eval(x).z.max(0.0).sqrt(),
                    m: t.m.eval(x).z,
                    n: t.n.eval(x).z,
                    k_over_e: t.k_over_e.eval(x).z,
                });
            }
        }
        Self::from_ratio(ratio)
    }

    fn from_ratio(ratio: f64) -> Result<EllipseShape, HertzError> {
        use std::f64::consts::PI;
        if ratio - 1.0 < 1e-7 {
            // Series: B/A ≈ 1 + ¾ e² (+ O(e⁴)).
            let e2 = (ratio - 1.0).max(0.0) / 0.75;
            let g = (1.0 - e2).sqrt();
            let (kk, ee) = complete_ke(e2.sqrt(), g);
            let m = (2.0 * ee / (PI * g * g)).cbrt();
            return Ok(EllipseShape {
                e: e2.sqrt(),
                m,
                n: m * g,
                k_over_e: kk / ee,
            });
        }
        // f(u) = ln(B/A)(g) − ln(ratio), u = ln g ∈ (−∞, 0); f decreasing in u.
        let target = ratio.ln();
        let f = |u: f64| -> (f64, f64, f64, f64) {
            let g = u.exp();
            let k = (1.0 - g * g).sqrt();
            let (kk, ee) = complete_ke(k, g);
            let (dk, de) = derivatives(k, g, kk, ee);
            let num = ee / (g * g) - kk;
            let den = kk - ee;
            // d/dg via dk/dg = −g/k.
            let dkg = -g / k;
            let dnum = de * dkg / (g * g) - 2.0 * ee / (g * g * g) - dk * dkg;
            let dden = (dk - de) * dkg;
            let val = (num / den).ln() - target;
            let dval_dg = dnum / num - dden / den;
            (val, dval_dg * g, kk, ee)
        };
        let mut lo = -60.0_f64; // f(lo) > 0 (g = e^-60: ratio astronomically large)
        let mut hi = 0.0_f64; // f(0⁻) = −target < 0
        let mut u = (-(2.0 / 3.0) * target).clamp(-59.0, -1e-9);
        for _ in 0..100 {
            let (val, dval, kk, ee) = f(u);
            if !val.is_finite() {
                return Err(HertzError::Input(format!("curvature ratio {ratio} out of range")));
            }
            if val.abs() < 1e-14 {
                let g = u.exp();
                let m = (2.0 * ee / (PI * g * g)).cbrt();
                return Ok(EllipseShape {
                    e: (1.0 - g * g).sqrt(),
                    m,
                    n: m * g,
                    k_over_e: kk / ee,
                });
            }
            if val > 0.0 {
                lo = u;
            } else {
                hi = u;
            }
            let mut next = u - val / dval;
            if !(next > lo && next < hi && dval.is_finite()) {
                next = 0.5 * (lo + hi);
            }
            if (next - u).abs() < 1e-15 {
                let g = next.exp();
                let (kk, ee) = complete_ke((1.0 - g * g).sqrt(), g);
                let m = (2.0 * ee / (PI * g * g)).cbrt();
                return Ok(EllipseShape {
                    e: (1.0 - g * g).sqrt(),
                    m,
                    n: m * g,
                    k_over_e: kk / ee,
                });
            }
            u = next;
        }
        Err(HertzError::Input(format!(
            "eccentricity iteration did not converge for B/A = {ratio}"
        )))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// The classical m, n table (facts file B, after Timoshenko; cos θ = (B − A)/(A + B)).
    /// The table against the Newton solution it is built from, between and at its knots, and near
    /// the circle (where the Newton solution switches to the series).
    #[test]
    fn tabulated_shape_matches_the_newton_solution() {
        let mut ratios: Vec<f64> = (0..20_000)
            .map(|i| SHAPE_TABLE_MAX_RATIO.powf(i as f64 / 19_999.0))
            .collect();
        // Not B/A − 1 ≈ 1e-7 itself: there the Newton reference loses 9 digits to K − E (its
        // series takes over just below) — the table, through smoother knots, is the better one.
        ratios.extend([
            1.0,
            1.0 + 1e-12,
            1.0 + 1e-9,
            1.0 + 5e-8,
            1.0 + 1e-6,
            1.0 + 1e-4,
            31.6,
        ]);
        let (mut worst, mut worst_e) = (0.0f64, 0.0f64);
        for r in ratios {
            let t = EllipseShape::of_ratio(r).unwrap();
            let x = EllipseShape::from_ratio(r).unwrap();
            let rel = |a: f64, b: f64| ((a - b) / b).abs();
            worst = worst
                .max(rel(t.m, x.m))
                .max(rel(t.n, x.n))
                .max(rel(t.k_over_e, x.k_over_e));
            worst_e = worst_e.max((t.e - x.e).abs());
        }
        println!("shape table: m, n, K/E within {worst:.2e} (relative), e within {worst_e:.2e}");
        assert!(worst < 1e-10, "m, n, K/E: {worst}");
        assert!(worst_e < 1e-6, "e: {worst_e}");
    }

    #[test]
    fn m_n_match_the_classical_table() {
        let table = [
            (10.0, 6.6115, 0.3110),
            (20.0, 3.8160, 0.4121),
            (30.0, 2.7306, 0.4931),
            (40.0, 2.1357, 0.5673),
            (50.0, 1.7541, 0.6407),
            (60.0, 1.4858, 0.7171),
            (70.0, 1.2851, 0.7999),
            (80.0, 1.1278, 0.8927),
            (85.0, 1.0609, 0.9442),
            (90.0, 1.0, 1.0),
        ];
        for (theta, m, n) in table {
            let c = (theta * PI / 180.0_f64).cos();
            // A + B = 2, B − A = 2c.
            let ratio = (1.0 + c) / (1.0 - c);
            let s = EllipseShape::from_ratio(ratio).unwrap();
            assert!((s.m - m).abs() < 6e-5, "θ={theta}: m {} vs {m}", s.m);
            assert!((s.n - n).abs() < 6e-5, "θ={theta}: n {} vs {n}", s.n);
        }
        // Timoshenko's printed values: θ = 30°: 2.731/0.493, 60°: 1.486/0.717.
        let s = EllipseShape::from_ratio(3.0).unwrap();
        assert!((s.m - 1.486).abs() < 1e-3 && (s.n - 0.717).abs() < 1e-3);
    }

    #[test]
    fn circle_is_hertz_sphere_on_plane() {
        // Sphere of radius R on a flat: A = B = 1/(2R), a³ = 3NR/(4E*), δ = a²/R.
        let r = 0.46;
        let n = 80e3;
        let curv = RelativeCurvature {
            a: 0.5 / r,
            b: 0.5 / r,
        };
        let h = HertzContact::solve(curv, n, &Material::STEEL, &Material::STEEL).unwrap();
        let e_star = Material::STEEL.contact_modulus(&Material::STEEL);
        let a = (3.0 * n * r / (4.0 * e_star)).cbrt();
        assert!((h.a - a).abs() < 1e-12 && (h.b - a).abs() < 1e-12);
        assert!((h.penetration - a * a / r).abs() < 1e-12);
        assert!((h.max_pressure - 3.0 * n / (2.0 * PI * a * a)).abs() < 1e-3);
    }

    /// Hertz's cylinder (line contact; Johnson, *Contact Mechanics*, Eq. 4.45: a² = 4P′R/(πE*),
    /// p₀ = 2P′/(πa), so p₀ = a E*/(2R)) as the limit of a long ellipse: a wheel-like curvature
    /// 1/(2R) across the patch and almost none along it (ratio 1e-3, 1e-4) gives p₀ = b E*/(2R)
    /// with b the minor semi-axis, to the ellipse's end effects (b/a)² ln(a/b): measured 4.5e-4 and 4.6e-5.
    #[test]
    fn a_long_ellipse_is_hertz_cylinder() {
        let m = Material::STEEL;
        let e_star = m.contact_modulus(&m);
        let r = 0.3;
        for (ratio, tol) in [(1e-3, 1e-3), (1e-4, 1e-4)] {
            let curv = RelativeCurvature {
                a: ratio * 0.5 / r,
                b: 0.5 / r,
            };
            let h = HertzContact::solve(curv, 60e3, &m, &m).unwrap();
            let minor = h.a.min(h.b);
            let cylinder = minor * e_star / (2.0 * r);
            let err = (h.max_pressure - cylinder).abs() / cylinder;
            println!(
                "ratio {ratio}: p0 {:.1} MPa vs cylinder {:.1} MPa ({err:.1e})",
                h.max_pressure * 1e-6,
                cylinder * 1e-6
            );
            assert!(err < tol, "ratio {ratio}: {err}");
        }
    }

    #[test]
    fn axes_follow_the_smaller_curvature_and_scale_with_load() {
        let m = Material::STEEL;
        let c1 = RelativeCurvature { a: 1.0, b: 5.0 };
        let c2 = RelativeCurvature { a: 5.0, b: 1.0 };
        let h1 = HertzContact::solve(c1, 50e3, &m, &m).unwrap();
        let h2 = HertzContact::solve(c2, 50e3, &m, &m).unwrap();
        assert!(h1.a > h1.b);
        assert!((h1.a - h2.b).abs() < 1e-15 && (h1.b - h2.a).abs() < 1e-15);
        let h3 = HertzContact::solve(c1, 100e3, &m, &m).unwrap();
        let s = h1.scaled(100e3);
        for (x, y) in [
            (h3.a, s.a),
            (h3.b, s.b),
            (h3.penetration, s.penetration),
            (h3.max_pressure, s.max_pressure),
        ] {
            assert!((x - y).abs() < 1e-12 * x.abs(), "{x} {y}");
        }
    }

    /// Johnson's form of the approach δ = p₀ b K(e) / E* (b the minor semi-axis) equals the form used.
    #[test]
    fn penetration_two_forms_agree() {
        let m = Material::STEEL;
        for ratio in [1.5, 4.0, 20.0, 200.0] {
            let h = HertzContact::solve(RelativeCurvature { a: 1.0, b: ratio }, 70e3, &m, &m).unwrap();
            let s = EllipseShape::from_ratio(ratio).unwrap();
            let (kk, _) = complete_ke(s.e, (1.0 - s.e * s.e).sqrt());
            let johnson = h.max_pressure * h.b * kk / m.contact_modulus(&m);
            // 1e-9: the solve's shape comes from the table (within 1e-10 of the Newton solution).
            assert!(
                (h.penetration - johnson).abs() < 1e-9 * johnson,
                "{ratio}: {} {johnson}",
                h.penetration
            );
        }
    }

    /// Direct numerical check of the whole solution: the Hertz pressure p₀√(1 − x²/a² − y²/b²) on an
    /// elastic half-space pair gives the normal displacement (Boussinesq)
    /// u(x, y) = 1/(π E*) ∬ p / r dA, which inside the ellipse must equal δ − A x² − B y².
    /// Integrated in polar coordinates around the field point (the 1/r singularity cancels).
    #[test]
    fn boussinesq_displacement_closes_the_gap() {
        let m = Material::STEEL;
        let e_star = m.contact_modulus(&m);
        let curv = RelativeCurvature { a: 2.2, b: 9.0 };
        let h = HertzContact::solve(curv, 60e3, &m, &m).unwrap();
        let (a, b) = (h.a, h.b);
        let pressure = |x: f64, y: f64| {
            let q = 1.0 - (x / a).powi(2) - (y / b).powi(2);
            if q > 0.0 {
                h.max_pressure * q.sqrt()
            } else {
                0.0
            }
        };
        for &(fx, fy) in &[(0.0, 0.0), (0.5, 0.2), (-0.3, -0.6), (0.8, 0.0)] {
            let (x0, y0) = (fx * a, fy * b);
            let n_theta = 720;
            let mut u = 0.0;
            for i in 0..n_theta {
                let th = (i as f64 + 0.5) * 2.0 * PI / n_theta as f64;
                let (c, s) = (th.cos(), th.sin());
                // Ray exit: (x0 + ρc)²/a² + (y0 + ρs)²/b² = 1.
                let qa = (c / a).powi(2) + (s / b).powi(2);
                let qb = 2.0 * (x0 * c / (a * a) + y0 * s / (b * b));
                let qc = (x0 / a).powi(2) + (y0 / b).powi(2) - 1.0;
                let rho_max = (-qb + (qb * qb - 4.0 * qa * qc).sqrt()) / (2.0 * qa);
                // ∫₀^ρmax p dρ; p = p₀ √(q(ρ)) vanishes like √ at the end: substitute ρ = ρmax (1 − t²).
                let nr = 200;
                let mut line = 0.0;
                for j in 0..nr {
                    let t = (j as f64 + 0.5) / nr as f64;
                    let rho = rho_max * (1.0 - t * t);
                    line += pressure(x0 + rho * c, y0 + rho * s) * 2.0 * t * rho_max / nr as f64;
                }
                u += line * 2.0 * PI / n_theta as f64;
            }
            u /= PI * e_star;
            let expect = h.penetration - curv.a * x0 * x0 - curv.b * y0 * y0;
            assert!(
                (u - expect).abs() < 2e-4 * h.penetration,
                "({fx},{fy}): {u} vs {expect}"
            );
        }
    }

    #[test]
    fn bad_input_is_an_error() {
        let m = Material::STEEL;
        assert!(matches!(
            HertzContact::solve(RelativeCurvature { a: 1.0, b: -0.5 }, 1e4, &m, &m),
            Err(HertzError::NotConvex { .. })
        ));
        assert!(HertzContact::solve(RelativeCurvature { a: 1.0, b: 2.0 }, 0.0, &m, &m).is_err());
        assert!(HertzContact::solve(RelativeCurvature { a: f64::NAN, b: 2.0 }, 1e3, &m, &m).is_err());
    }
}
