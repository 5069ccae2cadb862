//! Complete elliptic integrals of the first and second kind by the arithmetic–geometric mean.
//!
//! With modulus k (k² = e², the eccentricity squared of the Hertz ellipse) and k' = √(1 − k²):
//!
//! ```text
//! K(k) = ∫₀^{π/2} dθ / √(1 − k² sin²θ)  = π / (2 AGM(1, k'))
//! E(k) = ∫₀^{π/2} √(1 − k² sin²θ) dθ    = K(k) · (1 − Σₙ 2ⁿ⁻¹ cₙ²),   c₀ = k, cₙ₊₁ = (aₙ − bₙ)/2
//! ```
//!
//! The AGM converges quadratically: five or six steps reach machine precision for k < 1 − 1e-12.
//! Both are computed, never tabulated (issue 5).

use std::f64::consts::FRAC_PI_2;

/// K(k) and E(k) for 0 ≤ k < 1, given the complementary modulus k' = √(1 − k²) as well, so that
/// callers near k → 1 (very elongated ellipses) pass k' without cancellation.
pub fn complete_ke(k: f64, k_prime: f64) -> (f64, f64) {
    let mut a = 1.0;
    let mut b = k_prime;
    let mut c = k;
    let mut sum = 0.5 * c * c; // 2^(n-1) c_n² for n = 0
    let mut pow = 0.5;
    for _ in 0..40 {
        if (a - b).abs() <= 1e-16 * a {
            break;
        }
        let an = 0.5 * (a + b);
        let bn = (a * b).sqrt();
        c = 0.5 * (a - b);
        pow *= 2.0;
        sum += pow * c * c;
        a = an;
        b = bn;
    }
    let kk = FRAC_PI_2 / a;
    (kk, kk * (1.0 - sum))
}

/// Derivatives dK/dk and dE/dk (k in (0, 1)).
pub fn derivatives(k: f64, k_prime: f64, kk: f64, ee: f64) -> (f64, f64) {
    let dk = ee / (k * k_prime * k_prime) - kk / k;
    let de = (ee - kk) / k;
    (dk, de)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Composite Gauss–Legendre (5 points, 2000 panels) of the defining integrals: independent of AGM.
    fn quad(k: f64) -> (f64, f64) {
        let xg = [
            0.0,
            0.538_469_310_105_683_1,
            -0.538_469_310_105_683_1,
            0.906_179_845_938_664,
            -0.906_179_845_938_664,
        ];
        let wg = [
            0.568_888_888_888_888_9,
            0.478_628_670_499_366_5,
            0.478_628_670_499_366_5,
            0.236_926_885_056_189_1,
            0.236_926_885_056_189_1,
        ];
        let n = 2000;
        let h = FRAC_PI_2 / n as f64;
        let (mut kk, mut ee) = (0.0, 0.0);
        for i in 0..n {
            let mid = (i as f64 + 0.5) * h;
            for (x, w) in xg.iter().zip(wg) {
                let t = mid + 0.5 * h * x;
                let d = (1.0 - k * k * t.sin().powi(2)).sqrt();
                kk += 0.5 * h * w / d;
                ee += 0.5 * h * w * d;
            }
        }
        (kk, ee)
    }

    #[test]
    fn agm_matches_quadrature_and_known_values() {
        let (k0, e0) = complete_ke(0.0, 1.0);
        assert!((k0 - FRAC_PI_2).abs() < 1e-15 && (e0 - FRAC_PI_2).abs() < 1e-15);
        // Abramowitz & Stegun 17: k² = 1/2: K = 1.854074677301372, E = 1.350643881047675.
        let k = 0.5f64.sqrt();
        let (kk, ee) = complete_ke(k, k);
        assert!((kk - 1.854_074_677_301_372).abs() < 1e-14, "{kk}");
        assert!((ee - 1.350_643_881_047_675).abs() < 1e-14, "{ee}");
        for &k in &[0.1, 0.3, 0.6, 0.9, 0.99] {
            let (kk, ee) = complete_ke(k, (1.0 - k * k).sqrt());
            let (kq, eq) = quad(k);
            assert!((kk - kq).abs() < 1e-9 * kq, "K({k}) {kk} vs {kq}");
            assert!((ee - eq).abs() < 1e-11, "E({k}) {ee} vs {eq}");
        }
    }

    #[test]
    fn derivatives_match_finite_differences() {
        for &k in &[0.2, 0.5, 0.8, 0.95] {
            let h = 1e-6;
            let f = |k: f64| complete_ke(k, (1.0 - k * k).sqrt());
            let (kk, ee) = f(k);
            let (dk, de) = derivatives(k, (1.0 - k * k).sqrt(), kk, ee);
            let (kp, ep) = f(k + h);
            let (km, em) = f(k - h);
            assert!(
                (dk - (kp - km) / (2.0 * h)).abs() < 1e-6 * dk.abs().max(1.0),
                "dK {k}"
            );
            assert!(
                (de - (ep - em) / (2.0 * h)).abs() < 1e-6 * de.abs().max(1.0),
                "dE {k}"
            );
        }
    }
}
