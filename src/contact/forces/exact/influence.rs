//! Half-space influence coefficients for piecewise-constant tractions on a rectangular grid
//! (Boussinesq–Cerruti, integrated over each element in closed form; Kalker 1990 §5.2, Johnson
//! 1985 eqs. 3.86 and 3.22).
//!
//! A point force Q in x on the surface of an elastic half-space (shear modulus G, Poisson's
//! ratio ν) displaces the surface at (X, Y) from it, r = √(X² + Y²), by
//!
//! ```text
//! u_x = Q/(2πG) [(1 − ν)/r + ν X²/r³],   u_y = Q/(2πG) ν X Y/r³
//! ```
//!
//! and a normal force P by u_z = P (1 − ν)/(2πG r). Wheel and rail are *quasi-identical* (the same
//! steel): the traction p on the wheel and −p on the rail displace the two surfaces apart by twice
//! one body's displacement, so the relative displacement u = u_wheel − u_rail is the above with
//! 1/(πG) in place of 1/(2πG), and the tangential and normal problems decouple (the coupling terms
//! (1 − 2ν)/G of the two bodies cancel).
//!
//! Integrated over an element (half-sizes hx, hy) centred at offset (X, Y) from the field point,
//! with the corner rule ∫∫ f = F(X₂,Y₂) − F(X₁,Y₂) − F(X₂,Y₁) + F(X₁,Y₁) and the antiderivatives
//!
//! ```text
//! ∫∫ 1/r    → X asinh(Y/|X|) + Y asinh(X/|Y|)
//! ∫∫ X²/r³  → Y asinh(X/|Y|)
//! ∫∫ Y²/r³  → X asinh(Y/|X|)
//! ∫∫ XY/r³  → −r
//! ```
//!
//! the coefficients are
//!
//! ```text
//! A_xx = [(1 − ν) I₁ + ν I_xx]/(πG),  A_yy = [(1 − ν) I₁ + ν I_yy]/(πG),  A_xy = ν I_xy/(πG),
//! A_zz = (1 − ν) I₁/(πG).
//! ```
//!
//! They depend on the offset between elements only, so one kernel per component serves the whole
//! grid: the value for source element J and field element I is stored at (i_I − i_J, j_I − j_J).

/// X asinh(Y/|X|), 0 at X = 0 (its limit).
fn x_asinh(x: f64, y: f64) -> f64 {
    if x == 0.0 {
        0.0
    } else {
        x * (y / x.abs()).asinh()
    }
}

/// The four surface integrals over one element, at a field point (X, Y) from its centre:
/// [I₁, I_xx, I_yy, I_xy].
fn element_integrals(x: f64, y: f64, hx: f64, hy: f64) -> [f64; 4] {
    let mut out = [0.0; 4];
    for (sx, cx) in [(1.0, x + hx), (-1.0, x - hx)] {
        for (sy, cy) in [(1.0, y + hy), (-1.0, y - hy)] {
            let s = sx * sy;
            let fy = x_asinh(cx, cy); // X asinh(Y/|X|): ∫∫ Y²/r³
            let fx = x_asinh(cy, cx); // Y asinh(X/|Y|): ∫∫ X²/r³
            out[0] += s * (fx + fy);
            out[1] += s * fx;
            out[2] += s * fy;
            out[3] -= s * cx.hypot(cy);
        }
    }
    out
}

/// The influence kernels of one grid: element sizes dx × dy, offsets di ∈ [di_min, di_max],
/// dj ∈ [−(my − 1), my − 1].
#[derive(Debug, Clone)]
pub(crate) struct Kernel {
    pub di_min: isize,
    pub di_max: isize,
    pub dj_max: isize,
    /// Row length (number of di values).
    pub width: usize,
    pub xx: Vec<f64>,
    pub yy: Vec<f64>,
    pub xy: Vec<f64>,
    pub zz: Vec<f64>,
}

impl Kernel {
    /// Relative displacements of the two surfaces per unit traction (m/Pa), for offsets
    /// di ∈ [di_min, di_max] (in elements of dx) and |dj| < my.
    pub fn new(
        dx: f64,
        dy: f64,
        di_min: isize,
        di_max: isize,
        my: usize,
        shear_modulus: f64,
        poisson: f64,
    ) -> Kernel {
        let width = (di_max - di_min + 1) as usize;
        let dj_max = my as isize - 1;
        let rows = (2 * dj_max + 1) as usize;
        let n = width * rows;
        let (mut xx, mut yy, mut xy, mut zz) = (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        let c = 1.0 / (std::f64::consts::PI * shear_modulus);
        let nu = poisson;
        for dj in -dj_max..=dj_max {
            for di in di_min..=di_max {
                let k = (dj + dj_max) as usize * width + (di - di_min) as usize;
                let [i1, ixx, iyy, ixy] =
                    element_integrals(di as f64 * dx, dj as f64 * dy, 0.5 * dx, 0.5 * dy);
                xx[k] = c * ((1.0 - nu) * i1 + nu * ixx);
                yy[k] = c * ((1.0 - nu) * i1 + nu * iyy);
                xy[k] = c * nu * ixy;
                zz[k] = c * (1.0 - nu) * i1;
            }
        }
        Kernel {
            di_min,
            di_max,
            dj_max,
            width,
            xx,
            yy,
            xy,
            zz,
        }
    }

    /// Index of offset (di, dj).
    #[inline]
    pub fn index(&self, di: isize, dj: isize) -> usize {
        debug_assert!(di >= self.di_min && di <= self.di_max && dj.abs() <= self.dj_max);
        (dj + self.dj_max) as usize * self.width + (di - self.di_min) as usize
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// Brute-force midpoint quadrature of a point-force kernel over an element away from the
    /// field point.
    fn quadrature(x: f64, y: f64, hx: f64, hy: f64, f: impl Fn(f64, f64) -> f64) -> f64 {
        let n = 400;
        let (sx, sy) = (2.0 * hx / n as f64, 2.0 * hy / n as f64);
        let mut s = 0.0;
        for i in 0..n {
            for j in 0..n {
                let px = x - hx + (i as f64 + 0.5) * sx;
                let py = y - hy + (j as f64 + 0.5) * sy;
                s += f(px, py);
            }
        }
        s * sx * sy
    }

    #[test]
    fn closed_forms_match_quadrature_off_the_element() {
        for &(x, y) in &[(3.0, 0.5), (-2.0, 4.0), (0.0, 3.0), (5.0, -5.0)] {
            let (hx, hy) = (0.5, 0.8);
            let [i1, ixx, iyy, ixy] = element_integrals(x, y, hx, hy);
            let r = |a: f64, b: f64| a.hypot(b);
            let q1 = quadrature(x, y, hx, hy, |a, b| 1.0 / r(a, b));
            let qxx = quadrature(x, y, hx, hy, |a, b| a * a / r(a, b).powi(3));
            let qyy = quadrature(x, y, hx, hy, |a, b| b * b / r(a, b).powi(3));
            let qxy = quadrature(x, y, hx, hy, |a, b| a * b / r(a, b).powi(3));
            for (v, q) in [(i1, q1), (ixx, qxx), (iyy, qyy), (ixy, qxy)] {
                assert!((v - q).abs() < 1e-5 * q1, "({x},{y}): {v} vs {q}");
            }
        }
    }

    /// The self-influence of a square of side 2h under uniform load: ∫∫ 1/r = 8 h asinh(1)
    /// (the displacement at the centre of a uniformly loaded square, Love 1929).
    #[test]
    fn self_influence_of_a_square() {
        let h = 0.7;
        let [i1, ixx, iyy, ixy] = element_integrals(0.0, 0.0, h, h);
        assert!((i1 - 8.0 * h * 1f64.asinh()).abs() < 1e-12);
        assert!((ixx - iyy).abs() < 1e-12 && (ixx + iyy - i1).abs() < 1e-12);
        assert!(ixy.abs() < 1e-12);
        // A uniform circle of radius R gives 2πR at its centre; a square sits between the
        // inscribed and the circumscribed circle.
        assert!(i1 > 2.0 * PI * h && i1 < 2.0 * PI * h * 2f64.sqrt());
    }
}
