//! C² interpolating cubic spline z(s) with O(1) interval lookup: the curve of the wheel and rail
//! profiles ([`crate::profile`]) and of measured irregularity files ([`crate::track::measured`]).
//!
//! The profile functions h(s) of the paper (§3, Eq. 20–21) must give value, slope and second
//! derivative at millions of points per second. We interpolate the profile points with a
//! cubic spline in the second-derivative form
//!
//! ```text
//! z(s) = A z_i + B z_{i+1} + ((A³−A) M_i + (B³−B) M_{i+1}) h_i²/6,
//! A = (s_{i+1} − s)/h_i,  B = 1 − A,  h_i = s_{i+1} − s_i,
//! ```
//!
//! with *not-a-knot* end conditions (z''' continuous at the second and last-but-one knot), which
//! keeps fourth-order accuracy up to the ends instead of forcing z'' = 0 there as the natural
//! spline does — profile ends (a flange back, a rail gauge corner) are curved, not straight.
//!
//! Interval lookup uses a uniform cell table over the knot range: `cell → first interval that
//! intersects it`, then a short forward scan, so lookups are O(1) for any knot distribution.
//! Outside the knots the spline is continued by its end tangent (C¹): a caller that needs to know
//! it left the profile checks [`CubicSpline::domain`].

/// Value, first and second derivative of a profile function at one point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurvePoint {
    /// z(s)
    pub z: f64,
    /// dz/ds
    pub dz: f64,
    /// d²z/ds²
    pub d2z: f64,
}

impl CurvePoint {
    /// Signed curvature κ = z'' / (1 + z'²)^{3/2} of the plane curve (s, z(s)).
    pub fn curvature(&self) -> f64 {
        self.d2z / (1.0 + self.dz * self.dz).powf(1.5)
    }
}

/// Interpolating C² cubic spline with not-a-knot ends. Knots strictly increasing.
#[derive(Debug, Clone)]
pub struct CubicSpline {
    s: Vec<f64>,
    z: Vec<f64>,
    /// Second derivatives at the knots.
    m: Vec<f64>,
    cell_origin: f64,
    cell_inv_width: f64,
    cell_start: Vec<u32>,
}

/// Why a spline could not be built (the caller adds file and line).
#[derive(Debug, Clone, PartialEq)]
pub enum SplineError {
    TooFewPoints(usize),
    NotIncreasing(usize),
    NotFinite(usize),
}

impl CubicSpline {
    /// Builds the spline through `(s[i], z[i])`; needs at least 4 points, strictly increasing `s`.
    pub fn new(s: Vec<f64>, z: Vec<f64>) -> Result<Self, SplineError> {
        assert_eq!(s.len(), z.len(), "spline: s and z lengths differ");
        let n = s.len();
        if n < 4 {
            return Err(SplineError::TooFewPoints(n));
        }
        for i in 0..n {
            if !s[i].is_finite() || !z[i].is_finite() {
                return Err(SplineError::NotFinite(i));
            }
            if i > 0 && s[i] <= s[i - 1] {
                return Err(SplineError::NotIncreasing(i));
            }
        }
        let m = not_a_knot_second_derivatives(&s, &z);
        let mut sp = CubicSpline {
            s,
            z,
            m,
            cell_origin: 0.0,
            cell_inv_width: 0.0,
            cell_start: Vec::new(),
        };
        sp.build_cells();
        Ok(sp)
    }

    fn build_cells(&mut self) {
        let n = self.s.len();
        let (a, b) = (self.s[0], self.s[n - 1]);
        let cells = 2 * n;
        let w = (b - a) / cells as f64;
        self.cell_origin = a;
        self.cell_inv_width = 1.0 / w;
        self.cell_start = Vec::with_capacity(cells + 1);
        let mut i = 0usize;
        for k in 0..=cells {
            let x = a + k as f64 * w;
            while i + 2 < n && self.s[i + 1] <= x {
                i += 1;
            }
            self.cell_start.push(i as u32);
        }
    }

    /// Knot range `[s_first, s_last]`.
    pub fn domain(&self) -> (f64, f64) {
        (self.s[0], self.s[self.s.len() - 1])
    }

    /// The knots (lateral coordinates) and values the spline interpolates.
    pub fn knots(&self) -> (&[f64], &[f64]) {
        (&self.s, &self.z)
    }

    #[inline]
    fn interval(&self, x: f64) -> usize {
        let n = self.s.len();
        // One cell back guards against rounding at a cell boundary.
        let k = ((x - self.cell_origin) * self.cell_inv_width) as isize - 1;
        let k = k.clamp(0, self.cell_start.len() as isize - 1) as usize;
        let mut i = self.cell_start[k] as usize;
        while i + 2 < n && self.s[i + 1] < x {
            i += 1;
        }
        i
    }

    /// Value and derivatives at `x`; beyond the ends, the end tangent line (z'' = 0).
    #[inline]
    pub fn eval(&self, x: f64) -> CurvePoint {
        let n = self.s.len();
        if x < self.s[0] {
            let p = self.eval_in(0, self.s[0]);
            return CurvePoint {
                z: p.z + p.dz * (x - self.s[0]),
                dz: p.dz,
                d2z: 0.0,
            };
        }
        if x > self.s[n - 1] {
            let p = self.eval_in(n - 2, self.s[n - 1]);
            return CurvePoint {
                z: p.z + p.dz * (x - self.s[n - 1]),
                dz: p.dz,
                d2z: 0.0,
            };
        }
        self.eval_in(self.interval(x), x)
    }

    #[inline]
    fn eval_in(&self, i: usize, x: f64) -> CurvePoint {
        let h = self.s[i + 1] - self.s[i];
        let a = (self.s[i + 1] - x) / h;
        let b = 1.0 - a;
        let (mi, mj) = (self.m[i], self.m[i + 1]);
        let (zi, zj) = (self.z[i], self.z[i + 1]);
        let z = a * zi + b * zj + ((a * a * a - a) * mi + (b * b * b - b) * mj) * h * h / 6.0;
        let dz = (zj - zi) / h - (3.0 * a * a - 1.0) * h / 6.0 * mi + (3.0 * b * b - 1.0) * h / 6.0 * mj;
        let d2z = a * mi + b * mj;
        CurvePoint { z, dz, d2z }
    }
}

/// Second derivatives M_i of the not-a-knot cubic spline.
///
/// Interior rows: h_{i−1} M_{i−1} + 2(h_{i−1}+h_i) M_i + h_i M_{i+1} = 6(d_i − d_{i−1}).
/// Not-a-knot eliminates M_0 = M_1(1 + h_0/h_1) − M_2 h_0/h_1 and the mirror relation for
/// M_{n−1}, leaving a tridiagonal system in M_1..M_{n−2}, solved by the Thomas algorithm.
fn not_a_knot_second_derivatives(s: &[f64], z: &[f64]) -> Vec<f64> {
    let n = s.len();
    let h: Vec<f64> = (0..n - 1).map(|i| s[i + 1] - s[i]).collect();
    let d: Vec<f64> = (0..n - 1).map(|i| (z[i + 1] - z[i]) / h[i]).collect();
    let k = n - 2; // unknowns M_1..M_{n-2}
    let mut lo = vec![0.0; k];
    let mut di = vec![0.0; k];
    let mut up = vec![0.0; k];
    let mut rhs = vec![0.0; k];
    for r in 0..k {
        let i = r + 1;
        lo[r] = h[i - 1];
        di[r] = 2.0 * (h[i - 1] + h[i]);
        up[r] = h[i];
        rhs[r] = 6.0 * (d[i] - d[i - 1]);
    }
    // Left not-a-knot: fold M_0 into row 0.
    let (h0, h1) = (h[0], h[1]);
    di[0] += h0 * (1.0 + h0 / h1);
    up[0] -= h0 * h0 / h1;
    // Right not-a-knot: fold M_{n-1} into the last row.
    let (ha, hb) = (h[n - 3], h[n - 2]);
    di[k - 1] += hb * (1.0 + hb / ha);
    lo[k - 1] -= hb * hb / ha;
    if k == 1 {
        // n = 3 cannot happen (n ≥ 4 checked), kept for clarity.
        rhs[0] /= di[0];
    } else {
        // Thomas algorithm.
        for r in 1..k {
            let w = lo[r] / di[r - 1];
            di[r] -= w * up[r - 1];
            rhs[r] -= w * rhs[r - 1];
        }
        rhs[k - 1] /= di[k - 1];
        for r in (0..k - 1).rev() {
            rhs[r] = (rhs[r] - up[r] * rhs[r + 1]) / di[r];
        }
    }
    let mut m = vec![0.0; n];
    m[1..n - 1].copy_from_slice(&rhs);
    m[0] = m[1] * (1.0 + h0 / h1) - m[2] * h0 / h1;
    m[n - 1] = m[n - 2] * (1.0 + hb / ha) - m[n - 3] * hb / ha;
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reproduces_a_cubic_exactly() {
        // Not-a-knot reproduces any cubic; use uneven knots.
        let f = |x: f64| 0.3 * x * x * x - 1.2 * x * x + 0.5 * x - 2.0;
        let s: Vec<f64> = [0.0, 0.3, 0.35, 1.0, 1.7, 2.0, 3.1].to_vec();
        let z: Vec<f64> = s.iter().map(|&x| f(x)).collect();
        let sp = CubicSpline::new(s, z).unwrap();
        for k in 0..=100 {
            let x = 3.1 * k as f64 / 100.0;
            let p = sp.eval(x);
            assert!((p.z - f(x)).abs() < 1e-12, "z at {x}");
            assert!((p.dz - (0.9 * x * x - 2.4 * x + 0.5)).abs() < 1e-11);
            assert!((p.d2z - (1.8 * x - 2.4)).abs() < 1e-10);
        }
    }

    #[test]
    fn converges_fourth_order_on_a_circle() {
        // Error on a circular arc falls ~16x when the spacing halves.
        let r = 0.013;
        let f = |x: f64| (r * r - x * x).sqrt();
        let err = |n: usize| {
            let s: Vec<f64> = (0..n).map(|i| -0.01 + 0.02 * i as f64 / (n - 1) as f64).collect();
            let z = s.iter().map(|&x| f(x)).collect();
            let sp = CubicSpline::new(s, z).unwrap();
            (0..1000)
                .map(|k| -0.01 + 0.02 * k as f64 / 999.0)
                .map(|x| (sp.eval(x).z - f(x)).abs())
                .fold(0.0, f64::max)
        };
        let (e1, e2) = (err(41), err(81));
        assert!(e1 / e2 > 12.0, "ratio {}", e1 / e2);
    }

    #[test]
    fn lookup_is_correct_for_clustered_knots() {
        // Knots clustered at one end (as in measured profiles) must still be found.
        let s: Vec<f64> = (0..200).map(|i| (i as f64 / 199.0).powi(6)).collect();
        let z: Vec<f64> = s.iter().map(|x| x.sin()).collect();
        let sp = CubicSpline::new(s.clone(), z).unwrap();
        for k in 0..5000 {
            let x = k as f64 / 4999.0;
            let i = sp.interval(x);
            assert!(s[i] <= x + 1e-15 && x <= s[i + 1] + 1e-15, "x={x} i={i}");
        }
    }

    #[test]
    fn extrapolates_by_the_end_tangent() {
        let s: Vec<f64> = (0..10).map(|i| i as f64).collect();
        let z: Vec<f64> = s.iter().map(|x| x * x).collect();
        let sp = CubicSpline::new(s, z).unwrap();
        let p = sp.eval(10.0);
        assert!((p.z - (81.0 + 18.0)).abs() < 1e-9);
        assert!((p.dz - 18.0).abs() < 1e-9);
        assert_eq!(p.d2z, 0.0);
    }

    #[test]
    fn rejects_bad_knots() {
        assert_eq!(
            CubicSpline::new(vec![0.0, 1.0, 2.0], vec![0.0; 3]).unwrap_err(),
            SplineError::TooFewPoints(3)
        );
        assert_eq!(
            CubicSpline::new(vec![0.0, 1.0, 1.0, 2.0], vec![0.0; 4]).unwrap_err(),
            SplineError::NotIncreasing(2)
        );
        assert_eq!(
            CubicSpline::new(vec![0.0, 1.0, 2.0, 3.0], vec![0.0, f64::NAN, 0.0, 0.0]).unwrap_err(),
            SplineError::NotFinite(1)
        );
    }
}
