//! The discrete normal contact problem: the pressure on a grid for a given undeformed gap and
//! normal force (Kalker 1990 §5.2; solved by Polonsky & Keer's constrained conjugate gradients,
//! *Wear* 231 (1999) 206–219, the method of CONTACT's NormCG).
//!
//! With h the undeformed distance between the surfaces at each element centre, δ the approach
//! and u = A_zz p the elastic displacement (`influence`), the deformed distance is
//! e = h − δ + u, and
//!
//! ```text
//! p ≥ 0,   e ≥ 0,   p e = 0,   Σ p dx dy = N.
//! ```
//!
//! The iteration works on the elements with p > 0 (the contact set), its search direction is
//! conjugate there, elements with a negative distance enter the set, and the total force is
//! restored after each step; it stops when the relative change of the pressure is below the
//! tolerance. The approach δ is the mean of h + u over the contact set.

use super::error::ExactError;
use super::grid::{Grid, PressureGrid};
use super::influence::Kernel;

/// u = A p by direct convolution over the grid (O(n²)).
fn apply(kernel: &Kernel, grid: &Grid, p: &[f64], out: &mut [f64]) {
    let (mx, my) = (grid.mx, grid.my);
    out.iter_mut().for_each(|v| *v = 0.0);
    for jj in 0..my {
        for ii in 0..mx {
            let q = p[jj * mx + ii];
            if q == 0.0 {
                continue;
            }
            for j in 0..my {
                let base = kernel.index(-(ii as isize), j as isize - jj as isize);
                let krow = &kernel.zz[base..base + mx];
                let orow = &mut out[j * mx..(j + 1) * mx];
                for (o, k) in orow.iter_mut().zip(krow) {
                    *o += k * q;
                }
            }
        }
    }
}

/// The normal problem's solution.
#[derive(Debug, Clone, PartialEq)]
pub struct NormalSolution {
    pub pressure: PressureGrid,
    /// Approach of the bodies, m.
    pub approach: f64,
    pub iterations: usize,
}

/// Solve for the pressure under gap `gap` (m, at the element centres, row by row) and normal force
/// N, for quasi-identical bodies of shear modulus G and Poisson's ratio ν.
pub fn solve(
    grid: Grid,
    gap: &[f64],
    normal_force: f64,
    shear_modulus: f64,
    poisson: f64,
    tolerance: f64,
) -> Result<NormalSolution, ExactError> {
    let n = grid.len();
    if gap.len() != n {
        return Err(ExactError::Grid(format!(
            "gap has {} values for {n} elements",
            gap.len()
        )));
    }
    if let Some(k) = gap.iter().position(|h| !h.is_finite()) {
        return Err(ExactError::Grid(format!("gap value {k} is not finite")));
    }
    if !(normal_force.is_finite() && normal_force > 0.0) {
        return Err(ExactError::Grid(format!(
            "normal force {normal_force} N: expected positive"
        )));
    }
    let m = grid.mx as isize;
    let kernel = Kernel::new(grid.dx, grid.dy, -(m - 1), m - 1, grid.my, shear_modulus, poisson);
    let da = grid.area();
    // Start: uniform pressure where the gap is within reach of the smallest gaps.
    let h_min = gap.iter().cloned().fold(f64::INFINITY, f64::min);
    let h_max = gap.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    let reach = h_min + 0.25 * (h_max - h_min);
    let mut p: Vec<f64> = gap.iter().map(|&h| if h <= reach { 1.0 } else { 0.0 }).collect();
    let s: f64 = p.iter().sum::<f64>() * da;
    p.iter_mut().for_each(|v| *v *= normal_force / s);
    let (mut u, mut r) = (vec![0.0; n], vec![0.0; n]);
    let mut t = vec![0.0; n];
    let mut g_old = 1.0;
    let mut conjugate = false;
    let mut approach = 0.0;
    for it in 1..=2000 {
        apply(&kernel, &grid, &p, &mut u);
        // Gap residual on the contact set, its mean the approach.
        let (mut sum, mut cnt) = (0.0, 0usize);
        for k in 0..n {
            if p[k] > 0.0 {
                sum += gap[k] + u[k];
                cnt += 1;
            }
        }
        approach = sum / cnt.max(1) as f64;
        let e: Vec<f64> = (0..n).map(|k| gap[k] + u[k] - approach).collect();
        let g_norm: f64 = (0..n).filter(|&k| p[k] > 0.0).map(|k| e[k] * e[k]).sum();
        for k in 0..n {
            t[k] = if p[k] > 0.0 {
                e[k] + if conjugate { g_norm / g_old * t[k] } else { 0.0 }
            } else {
                0.0
            };
        }
        g_old = g_norm.max(f64::MIN_POSITIVE);
        apply(&kernel, &grid, &t, &mut r);
        let (mut rs, mut rc) = (0.0, 0usize);
        for k in 0..n {
            if p[k] > 0.0 {
                rs += r[k];
                rc += 1;
            }
        }
        let rmean = rs / rc.max(1) as f64;
        let (mut num, mut den) = (0.0, 0.0);
        for k in 0..n {
            if p[k] > 0.0 {
                num += e[k] * t[k];
                den += (r[k] - rmean) * t[k];
            }
        }
        let tau = if den != 0.0 { num / den } else { 0.0 };
        let p_old = p.clone();
        for k in 0..n {
            if p[k] > 0.0 {
                p[k] = (p[k] - tau * t[k]).max(0.0);
            }
        }
        // Elements that penetrate without pressure enter the contact set.
        let mut entered = false;
        for k in 0..n {
            if p_old[k] == 0.0 && e[k] < 0.0 {
                p[k] = -tau * e[k];
                if p[k] <= 0.0 {
                    p[k] = -e[k] * normal_force / (da * h_max.max(1e-12));
                }
                entered = true;
            }
        }
        conjugate = !entered;
        let s: f64 = p.iter().sum::<f64>() * da;
        if !(s > 0.0 && s.is_finite()) {
            return Err(ExactError::NonFinite("normal pressure (diverged)"));
        }
        p.iter_mut().for_each(|v| *v *= normal_force / s);
        let change: f64 = p.iter().zip(&p_old).map(|(a, b)| (a - b).abs()).sum::<f64>() * da;
        if change <= tolerance * normal_force {
            return Ok(NormalSolution {
                pressure: PressureGrid { grid, pressure: p },
                approach,
                iterations: it,
            });
        }
    }
    let _ = approach;
    Err(ExactError::NotConverged {
        sweeps: 2000,
        what: "normal problem (conjugate gradients)",
    })
}
