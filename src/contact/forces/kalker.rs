//! Kalker's coefficients C₁₁, C₂₂, C₂₃ of the linear theory of rolling contact (Kalker 1967; Table E.3
//! of Kalker, *Three-dimensional elastic bodies in rolling contact*, 1990, as given in CONTACT's
//! `m_hertz.f90`, see `../shared/design/facts/creep-contact.txt` A):
//!
//! ```text
//! Fx = −G a b C₁₁ ξx
//! Fy = −G a b C₂₂ ξy − G (ab)^{3/2} C₂₃ φ
//! Mz =  G (ab)^{3/2} C₂₃ ξy − G (ab)² C₃₃ φ
//! ```
//!
//! **C₃₃ is not provided**: no verified source of its table was available, so the linear spin
//! moment's φ term is left out (the models that need a spin moment, FASTSIM, compute their own).
//!
//! Interpolation (differs from CONTACT, which interpolates linearly in g):
//! - in ν: Lagrange quadratic through ν = 0, 0.25, 0.5 applied to 1/C (CONTACT's rule), done once
//!   per material;
//! - in a/b: monotone cubic (PCHIP) in ln(a/b) over the 19 table nodes a/b = 0.1 … 1 … 10 (the two
//!   halves of the table joined at a/b = 1); C¹ in a/b, reproduces the table exactly, no overshoot;
//! - beyond a/b < 0.1 or > 10: CONTACT's asymptotic expressions, scaled by a constant so that they
//!   meet the table at the end node (the raw asymptotes are 1–6 % off there).

use std::f64::consts::PI;

use crate::interpolation::{hermite, pchip_slopes};

/// g values of the table rows.
const G: [f64; 10] = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0];

/// Rows for a/b ≤ 1 (g = a/b). (3.14 is Kalker's C22, not π.): [C11(ν=0,.25,.5), C22(...), C23(...)].
#[allow(clippy::approx_constant)]
const TABLE_A_LE_B: [[f64; 9]; 10] = [
    [2.51, 3.31, 4.85, 2.51, 2.52, 2.53, 0.334, 0.473, 0.731],
    [2.59, 3.37, 4.81, 2.59, 2.63, 2.66, 0.483, 0.603, 0.809],
    [2.68, 3.44, 4.80, 2.68, 2.75, 2.81, 0.607, 0.715, 0.889],
    [2.78, 3.53, 4.82, 2.78, 2.88, 2.98, 0.720, 0.823, 0.977],
    [2.88, 3.62, 4.83, 2.88, 3.01, 3.14, 0.827, 0.929, 1.07],
    [2.98, 3.72, 4.91, 2.98, 3.14, 3.31, 0.930, 1.03, 1.18],
    [3.09, 3.81, 4.97, 3.09, 3.28, 3.48, 1.03, 1.14, 1.29],
    [3.19, 3.91, 5.05, 3.19, 3.41, 3.65, 1.13, 1.25, 1.40],
    [3.29, 4.01, 5.12, 3.29, 3.54, 3.82, 1.23, 1.36, 1.51],
    [3.40, 4.12, 5.20, 3.40, 3.67, 3.98, 1.33, 1.47, 1.63],
];

/// Rows for a/b > 1 (g = b/a).
const TABLE_A_GT_B: [[f64; 9]; 10] = [
    [10.7, 11.7, 12.9, 10.7, 12.8, 16.0, 12.2, 14.6, 18.0],
    [6.96, 7.78, 8.82, 6.96, 8.14, 9.79, 5.72, 6.63, 7.89],
    [5.57, 6.34, 7.34, 5.57, 6.40, 7.51, 3.79, 4.32, 5.01],
    [4.84, 5.57, 6.57, 4.84, 5.48, 6.31, 2.88, 3.24, 3.70],
    [4.37, 5.10, 6.11, 4.37, 4.90, 5.56, 2.35, 2.62, 2.96],
    [4.06, 4.78, 5.80, 4.06, 4.50, 5.04, 2.01, 2.23, 2.50],
    [3.82, 4.54, 5.58, 3.82, 4.21, 4.67, 1.76, 1.95, 2.18],
    [3.65, 4.36, 5.42, 3.65, 3.99, 4.39, 1.58, 1.75, 1.94],
    [3.51, 4.22, 5.30, 3.51, 3.81, 4.16, 1.44, 1.59, 1.77],
    [3.40, 4.12, 5.20, 3.40, 3.67, 3.98, 1.33, 1.47, 1.63],
];

/// Kalker's C₁₁, C₂₂, C₂₃ at one a/b.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KalkerCoefficients {
    pub c11: f64,
    pub c22: f64,
    pub c23: f64,
}

/// Lagrange quadratic in ν through ν = 0, 0.25, 0.5 applied to 1/C (CONTACT's rule).
fn in_nu(c0: f64, c25: f64, c50: f64, nu: f64) -> f64 {
    let inv =
        8.0 * (nu - 0.25) * (nu - 0.5) / c0 - 16.0 * nu * (nu - 0.5) / c25 + 8.0 * nu * (nu - 0.25) / c50;
    1.0 / inv
}

/// CONTACT's asymptotes: a ≪ b (g = a/b → 0).
fn asym_narrow(g: f64, nu: f64) -> [f64; 3] {
    [
        PI * PI / (4.0 * (1.0 - nu)),
        PI * PI / 4.0,
        PI * g.sqrt() / (3.0 * (1.0 - nu)) * (1.0 + nu * ((16.0 / g).ln() - 5.0)),
    ]
}

/// CONTACT's asymptotes: a ≫ b (g = b/a → 0).
fn asym_long(g: f64, nu: f64) -> [f64; 3] {
    let l = (16.0 / (g * g)).ln();
    let ln4 = 4.0f64.ln();
    let c11 = 2.0 * PI / ((l - 2.0 * nu) * g) * (1.0 + (3.0 - ln4) / (l - 2.0 * nu));
    let c22 = 2.0 * PI / g * (1.0 + (1.0 - nu) * (3.0 - ln4) / ((1.0 - nu) * l + 2.0 * nu))
        / ((1.0 - nu) * l + 2.0 * nu);
    let c23 = 2.0 * PI / (3.0 * g.powf(1.5) * ((1.0 - nu) * l - 2.0 + 4.0 * nu));
    [c11, c22, c23]
}

/// The table for one Poisson's ratio, ready for interpolation in a/b.
#[derive(Debug, Clone, PartialEq)]
pub struct KalkerTable {
    nu: f64,
    /// Nodes ln(a/b), increasing (19).
    x: Vec<f64>,
    /// C values at the nodes, per coefficient.
    c: [Vec<f64>; 3],
    /// PCHIP slopes dC/d ln(a/b).
    d: [Vec<f64>; 3],
    /// Scale factors of the asymptotes at the two ends [narrow, long], per coefficient.
    scale: [[f64; 3]; 2],
}

impl KalkerTable {
    /// Build for Poisson's ratio ν ∈ [0, 0.5].
    pub fn new(nu: f64) -> KalkerTable {
        let nu = nu.clamp(0.0, 0.5);
        let mut x = Vec::with_capacity(19);
        let mut c: [Vec<f64>; 3] = Default::default();
        let mut push = |ab: f64, row: &[f64; 9]| {
            x.push(ab.ln());
            for (k, ck) in c.iter_mut().enumerate() {
                ck.push(in_nu(row[3 * k], row[3 * k + 1], row[3 * k + 2], nu));
            }
        };
        for (g, row) in G.iter().zip(&TABLE_A_LE_B) {
            push(*g, row);
        }
        for (g, row) in G.iter().zip(&TABLE_A_GT_B).rev().skip(1) {
            push(1.0 / g, row);
        }
        let d = [
            pchip_slopes(&x, &c[0]),
            pchip_slopes(&x, &c[1]),
            pchip_slopes(&x, &c[2]),
        ];
        let n = x.len();
        let (an, al) = (asym_narrow(0.1, nu), asym_long(0.1, nu));
        let scale = [
            [c[0][0] / an[0], c[1][0] / an[1], c[2][0] / an[2]],
            [c[0][n - 1] / al[0], c[1][n - 1] / al[1], c[2][n - 1] / al[2]],
        ];
        KalkerTable { nu, x, c, d, scale }
    }

    /// Poisson's ratio of the table.
    pub fn poisson(&self) -> f64 {
        self.nu
    }

    /// C₁₁, C₂₂, C₂₃ at a/b (> 0).
    pub fn at(&self, a_over_b: f64) -> KalkerCoefficients {
        let t = a_over_b.ln();
        let n = self.x.len();
        let pick = |v: [f64; 3]| KalkerCoefficients {
            c11: v[0],
            c22: v[1],
            c23: v[2],
        };
        if t <= self.x[0] {
            let a = asym_narrow(a_over_b, self.nu);
            let s = self.scale[0];
            return pick([a[0] * s[0], a[1] * s[1], a[2] * s[2]]);
        }
        if t >= self.x[n - 1] {
            let a = asym_long(1.0 / a_over_b, self.nu);
            let s = self.scale[1];
            return pick([a[0] * s[0], a[1] * s[1], a[2] * s[2]]);
        }
        let i = self.x.partition_point(|&xi| xi <= t).clamp(1, n - 1) - 1;
        let mut v = [0.0; 3];
        for (k, vk) in v.iter_mut().enumerate() {
            *vk = hermite(
                self.x[i],
                self.x[i + 1],
                self.c[k][i],
                self.c[k][i + 1],
                self.d[k][i],
                self.d[k][i + 1],
                t,
            )
            .0;
        }
        pick(v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reproduces_the_published_table_at_its_nodes() {
        for (k, nu) in [0.0, 0.25, 0.5].into_iter().enumerate() {
            let t = KalkerTable::new(nu);
            for (g, row) in G.iter().zip(&TABLE_A_LE_B) {
                let c = t.at(*g);
                assert!((c.c11 - row[k]).abs() < 1e-12 && (c.c22 - row[3 + k]).abs() < 1e-12);
                assert!((c.c23 - row[6 + k]).abs() < 1e-12);
            }
            for (g, row) in G.iter().zip(&TABLE_A_GT_B) {
                let c = t.at(1.0 / g);
                assert!((c.c11 - row[k]).abs() < 1e-9 && (c.c22 - row[3 + k]).abs() < 1e-9);
                assert!((c.c23 - row[6 + k]).abs() < 1e-9);
            }
        }
    }

    /// The facts file lists CONTACT's rule evaluated independently at ν = 0.28 and 0.30 (3 decimals).
    #[test]
    fn poisson_interpolation_matches_contact_rule() {
        let rows_028 = [
            (0.1, 3.441, 2.521, 0.496),
            (0.5, 3.734, 3.026, 0.943),
            (1.0, 4.226, 3.705, 1.488),
            (2.0, 5.204, 4.971, 2.657),
            (10.0, 11.832, 13.112, 14.945),
        ];
        let rows_030 = [
            (0.3, 3.647, 2.763, 0.743),
            (1.25, 4.537, 4.065, 1.786),
            (5.0, 7.968, 8.425, 6.848),
        ];
        for (nu, rows) in [(0.28, &rows_028[..]), (0.30, &rows_030[..])] {
            let t = KalkerTable::new(nu);
            for &(ab, c11, c22, c23) in rows {
                let c = t.at(ab);
                assert!(
                    (c.c11 - c11).abs() < 6e-4,
                    "ν={nu} a/b={ab}: C11 {} vs {c11}",
                    c.c11
                );
                assert!(
                    (c.c22 - c22).abs() < 6e-4,
                    "ν={nu} a/b={ab}: C22 {} vs {c22}",
                    c.c22
                );
                assert!(
                    (c.c23 - c23).abs() < 6e-4,
                    "ν={nu} a/b={ab}: C23 {} vs {c23}",
                    c.c23
                );
            }
        }
    }

    #[test]
    fn continuous_monotone_and_asymptotic() {
        let t = KalkerTable::new(0.28);
        // Continuity at the table ends (asymptotes scaled to meet the table).
        for ab in [0.1, 10.0] {
            let lo = t.at(ab * (1.0 - 1e-9));
            let hi = t.at(ab * (1.0 + 1e-9));
            assert!((lo.c11 - hi.c11).abs() < 1e-6 && (lo.c22 - hi.c22).abs() < 1e-6);
            assert!((lo.c23 - hi.c23).abs() < 1e-6);
        }
        // Every coefficient increases with a/b over the whole range (the table does).
        // (Below a/b = 0.1 the asymptotes of C11 and C22 are constant: checked from 0.1 on.)
        let mut prev = t.at(0.1);
        for i in 1..=400 {
            let ab = 0.1 * 10f64.powf(3.0 * i as f64 / 400.0);
            let c = t.at(ab);
            assert!(
                c.c11 > prev.c11 && c.c22 > prev.c22 && c.c23 > prev.c23,
                "a/b = {ab}"
            );
            prev = c;
        }
        // Very narrow contacts: C11 → π²/(4(1−ν)) up to the end-node scale (within 3 %).
        let c = t.at(1e-4);
        assert!((c.c11 / (PI * PI / (4.0 * 0.72)) - 1.0).abs() < 0.03);
    }
}
