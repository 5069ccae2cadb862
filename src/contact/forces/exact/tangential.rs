//! Kalker's steady-state rolling problem on a grid, solved by Gauss–Seidel over the elements
//! from the leading edge (Kalker 1990 §5.3; Vollebregt's ConvexGS/SteadyGS, CONTACT user guide
//! §4.3, re-derived here from the equations).
//!
//! **Continuum.** The wheel rolls forward (+x): material flows through the patch from the leading
//! edge x = +a to the trailing edge. With u = u_wheel − u_rail the tangential displacement
//! difference and w the rigid slip per unit rolling distance,
//!
//! ```text
//! w = (ξ − φ y,  η + φ x),      s = w − ∂u/∂x          (Kalker 1990 eq. 1.27, steady state)
//! ```
//!
//! is the local slip (per unit rolling distance), and with g = μ p_n the traction bound,
//!
//! ```text
//! |p| ≤ g;   |p| < g ⇒ s = 0 (adhesion);   s ≠ 0 ⇒ p = −g s/|s| (slip, opposing it).
//! ```
//!
//! **Discretisation.** u = A p with the influence coefficients of `influence`; the derivative
//! along the flow is the first-order upwind difference over one element (dq = dx, CONTACT's
//! choice: the particle now at x_I was at x_I + dx one step before). Shifting the sum's index,
//!
//! ```text
//! s_I = w_I + (u(x_I) − u(x_I + dx))/dx = w_I + Σ_K A_IK Δp_K / dx,   Δp_K = p_K − p_{K+}
//! ```
//!
//! with K+ the element upstream of K in its row (p = 0 outside the contact area). In the
//! differences Δp the steady-rolling system has the symmetric positive definite matrix A of the
//! static problem, where its matrix in p, (A − A_shifted)/dx, is not symmetric (an element-wise
//! Gauss–Seidel in p diverges). Δp is non-zero on the contact elements and on the exterior element
//! just behind each row's trailing edge, which the grid must hold (one column of margin there).
//!
//! **Solver** (the idea of Vollebregt's SteadyGS, CONTACT user guide §4.3, re-derived). Rows are
//! swept element by element from the trailing edge to the leading edge. An element I is solved
//! with every Δp held except its own and that of the first element behind it that is not in
//! adhesion (J): raising p_I by δ raises every adhesion element between them with it (their Δp
//! held) and lowers Δp_J by δ. Its slip is then s_I = r + D p_I with
//! D = (A(0) − A(I − J))/dx, diagonal by symmetry. Adhesion: p_I = −D⁻¹ r when |D⁻¹ r| ≤ g;
//! otherwise slip, p_I = −(D + k)⁻¹ r with k ≥ 0 the root of |(D + k)⁻¹ r| = g (so s_I = −k p_I:
//! the slip opposite the traction, its direction solved, not assumed). The adhesion elements
//! carried along are clipped to their bounds. Sweeps repeat until no traction changes by more than
//! `tolerance` × the largest traction (≤ μ p_max; relative, so tiny creepages converge too); the slip at an element is recomputed from all Δp (O(N_c) per element,
//! O(N_c²) per sweep for N_c elements in contact).

use super::error::ExactError;
use super::grid::PressureGrid;
use super::influence::Kernel;
use crate::contact::forces::creepage::Creepage;

/// The spin's rigid slip η + φ(x + c·dx) is taken at c = 1/6 of an element ahead of the centre,
/// as CONTACT does ("offset 1/6 dq used in rolling problems"): a discretisation choice, measured
/// here on pure spin φ = 4 1/m (a = b = 6 mm, 80 kN, μ 0.3): Fy/μN at 10/20/40/80 elements across
/// is −0.2556/−0.2574/−0.2563/−0.2551 with it (CONTACT at 160: −0.2545), −0.218/−0.239/−0.247/
/// −0.251 without it (first order); the creepages ξ, η are unaffected.
pub const SPIN_OFFSET: f64 = 1.0 / 6.0;

/// The state of one element in the solution.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ElementState {
    /// No pressure: outside the contact area.
    Exterior,
    /// Stick: no local slip.
    Adhesion,
    /// The traction is at its bound, opposing the local slip.
    Slip,
}

/// The tangential solution on the grid.
#[derive(Debug, Clone, PartialEq)]
pub struct TractionSolution {
    /// Tractions on the wheel, per element (row by row), Pa.
    pub px: Vec<f64>,
    pub py: Vec<f64>,
    /// Local slip per unit rolling distance (zero in adhesion).
    pub sx: Vec<f64>,
    pub sy: Vec<f64>,
    pub state: Vec<ElementState>,
    /// Forces on the wheel, N, and the spin moment about the patch's origin, N·m.
    pub fx: f64,
    pub fy: f64,
    pub mz: f64,
    /// Gauss–Seidel sweeps used.
    pub sweeps: usize,
}

impl TractionSolution {
    /// Elements in adhesion and in slip.
    pub fn counts(&self) -> (usize, usize) {
        let a = self
            .state
            .iter()
            .filter(|s| **s == ElementState::Adhesion)
            .count();
        let s = self.state.iter().filter(|s| **s == ElementState::Slip).count();
        (a, s)
    }
}

/// Settings of the iteration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IterationSettings {
    /// Stop when no traction changes by more than this × μ p_max in a sweep.
    pub tolerance: f64,
    /// At most this many sweeps; more is non-convergence, reported.
    pub max_sweeps: usize,
}

impl Default for IterationSettings {
    fn default() -> Self {
        IterationSettings {
            tolerance: 1e-7,
            max_sweeps: 2000,
        }
    }
}

/// The influence matrix A of one grid for the steady rolling problem (its kernel, reusable for
/// every creepage and pressure on the same grid: a table's curves).
#[derive(Debug, Clone)]
pub struct RollingOperator {
    mx: usize,
    my: usize,
    kernel: Kernel,
    dx: f64,
    dy: f64,
}

impl RollingOperator {
    /// A for a grid of mx × my elements of dx × dy, shear modulus G, Poisson's ratio ν.
    pub fn new(mx: usize, my: usize, dx: f64, dy: f64, shear_modulus: f64, poisson: f64) -> RollingOperator {
        let m = mx as isize;
        RollingOperator {
            mx,
            my,
            kernel: Kernel::new(dx, dy, -(m - 1), m - 1, my, shear_modulus, poisson),
            dx,
            dy,
        }
    }

    /// The operator for a pressure grid's grid.
    pub fn for_grid(p: &PressureGrid, shear_modulus: f64, poisson: f64) -> RollingOperator {
        let g = &p.grid;
        RollingOperator::new(g.mx, g.my, g.dx, g.dy, shear_modulus, poisson)
    }

    /// Solve the steady rolling problem for the creepages (ξ, η, φ in 1/m) with friction μ.
    /// `start`: tractions to start from (a previous solution on the same grid), or zero.
    pub fn solve(
        &self,
        patch: &PressureGrid,
        friction: f64,
        creep: &Creepage,
        settings: &IterationSettings,
        start: Option<(&[f64], &[f64])>,
    ) -> Result<TractionSolution, ExactError> {
        let g = &patch.grid;
        if g.mx != self.mx || g.my != self.my || g.dx != self.dx || g.dy != self.dy {
            return Err(ExactError::Grid(
                "the rolling operator was built for another grid".into(),
            ));
        }
        for (v, what) in [
            (creep.longitudinal, "ξ"),
            (creep.lateral, "η"),
            (creep.spin, "φ"),
            (friction, "μ"),
        ] {
            if !v.is_finite() {
                return Err(ExactError::NonFinite(what));
            }
        }
        let (mx, my) = (self.mx, self.my);
        let n = mx * my;
        let bound: Vec<f64> = patch.pressure.iter().map(|p| friction * p).collect();
        let g_max = bound.iter().cloned().fold(0.0, f64::max);
        // Each row's span: from the exterior element behind the trailing edge to the leading
        // edge (zero-pressure elements inside a span have a zero bound and zero traction).
        let mut spans: Vec<Option<(usize, usize)>> = Vec::with_capacity(my);
        for j in 0..my {
            let row = &bound[j * mx..(j + 1) * mx];
            let span = match (
                row.iter().position(|&b| b > 0.0),
                row.iter().rposition(|&b| b > 0.0),
            ) {
                (Some(first), Some(last)) => {
                    if first == 0 {
                        return Err(ExactError::Grid(format!(
                            "row {j} has contact in the grid's last column behind the patch: the grid needs an exterior column at the trailing edge"
                        )));
                    }
                    Some((first - 1, last + 1))
                }
                _ => None,
            };
            spans.push(span);
        }
        let (mut px, mut py) = (vec![0.0; n], vec![0.0; n]);
        if let Some((x0, y0)) = start {
            if x0.len() == n && y0.len() == n {
                for k in 0..n {
                    if bound[k] > 0.0 {
                        let (a, b) = clip(x0[k], y0[k], bound[k]);
                        px[k] = a;
                        py[k] = b;
                    }
                }
            }
        }
        // Δp_K = p_K − p_{K+} (upstream neighbour; zero beyond the grid).
        let upstream = |p: &[f64], k: usize| if (k + 1).is_multiple_of(mx) { 0.0 } else { p[k + 1] };
        let (mut dpx, mut dpy) = (vec![0.0; n], vec![0.0; n]);
        for k in 0..n {
            dpx[k] = px[k] - upstream(&px, k);
            dpy[k] = py[k] - upstream(&py, k);
        }
        let mut adhesion = vec![false; n];
        let ker = &self.kernel;
        let k00 = ker.index(0, 0);
        let inv_dq = 1.0 / self.dx;
        let (wx0, wy0) = (creep.longitudinal, creep.lateral);
        let phi = creep.spin;
        let x_ofs = SPIN_OFFSET * self.dx;
        let mut sweeps = 0;
        let mut converged = g_max == 0.0;
        // Under-relaxation where the iteration stagnates (an element cycling between adhesion and
        // slip): ω shrinks by a quarter whenever ten sweeps have not halved the largest change.
        let mut omega: f64 = 1.0;
        let mut history: Vec<f64> = Vec::new();
        while !converged {
            if sweeps >= settings.max_sweeps {
                if start.is_some() {
                    // A warm start that led astray: once more from zero tractions.
                    return self.solve(patch, friction, creep, settings, None);
                }
                return Err(ExactError::NotConverged {
                    sweeps,
                    what: "steady rolling (Gauss–Seidel)",
                });
            }
            sweeps += 1;
            if history.len() >= 10 && history[history.len() - 1] > 0.5 * history[history.len() - 10] {
                omega = (omega * 0.75).max(0.1);
                history.clear();
            }
            let mut change: f64 = 0.0;
            for j in 0..my {
                let Some((lo, hi)) = spans[j] else { continue };
                let row0 = j * mx;
                for i in lo + 1..hi {
                    let k = row0 + i;
                    let gk = bound[k];
                    if gk <= 0.0 {
                        adhesion[k] = false;
                        continue;
                    }
                    // The first element behind I not in adhesion: where the change lands.
                    let mut jx = i - 1;
                    while jx > lo && adhesion[row0 + jx] {
                        jx -= 1;
                    }
                    let kb = ker.index((i - jx) as isize, 0);
                    let dxx = (ker.xx[k00] - ker.xx[kb]) * inv_dq;
                    let dyy = (ker.yy[k00] - ker.yy[kb]) * inv_dq;
                    // Slip at I under the current Δp.
                    let (ux, uy) = self.displacement(&spans, &dpx, &dpy, i, j);
                    let sx = wx0 - phi * g.y(j) + ux * inv_dq;
                    let sy = wy0 + phi * (g.x(i) + x_ofs) + uy * inv_dq;
                    let rx = sx - dxx * px[k];
                    let ry = sy - dyy * py[k];
                    let (mut qx, mut qy) = (-rx / dxx, -ry / dyy);
                    let stick = qx * qx + qy * qy <= gk * gk;
                    if !stick {
                        let kk = slip_root(rx, ry, dxx, dyy, gk);
                        qx = -rx / (dxx + kk);
                        qy = -ry / (dyy + kk);
                    }
                    adhesion[k] = stick;
                    let (ddx, ddy) = (omega * (qx - px[k]), omega * (qy - py[k]));
                    // (ω < 1: p + ω(q − p) lies inside the bound, q and p do.)
                    let (qx, qy) = (px[k] + ddx, py[k] + ddy);
                    if ddx == 0.0 && ddy == 0.0 {
                        continue;
                    }
                    change = change.max(ddx.abs().max(ddy.abs()));
                    px[k] = qx;
                    py[k] = qy;
                    dpx[k] += ddx;
                    dpy[k] += ddy;
                    // Behind I: adhesion elements keep Δp (their p moves with I's, clipped at their
                    // bound), the others keep p; the element behind the trailing edge is exterior.
                    for t in (lo..i).rev() {
                        let kt = row0 + t;
                        let (ux, uy) = (px[kt + 1], py[kt + 1]);
                        if t == lo || bound[kt] <= 0.0 {
                            px[kt] = 0.0;
                            py[kt] = 0.0;
                        } else if adhesion[kt] {
                            let (ax, ay) = clip(ux + dpx[kt], uy + dpy[kt], bound[kt]);
                            px[kt] = ax;
                            py[kt] = ay;
                        }
                        dpx[kt] = px[kt] - ux;
                        dpy[kt] = py[kt] - uy;
                    }
                }
            }
            if !change.is_finite() {
                return Err(ExactError::NonFinite("traction (diverged)"));
            }
            // The undamped change: a damped sweep's steps are ω times the Gauss–Seidel ones.
            let change = change / omega;
            history.push(change);
            // Relative to the largest traction (in the linear range the tractions scale with the
            // creepage: an absolute criterion would leave tiny creepages unconverged), never below
            // 10⁻⁹ of the bound.
            let p_scale = px
                .iter()
                .zip(&py)
                .fold(0.0f64, |m, (x, y)| m.max(x.abs()).max(y.abs()))
                .min(g_max)
                .max(1e-9 * g_max);
            converged = change <= settings.tolerance * p_scale;
        }
        // Slips, states and forces.
        let (mut sx, mut sy) = (vec![0.0; n], vec![0.0; n]);
        let mut state = vec![ElementState::Exterior; n];
        let (mut fx, mut fy, mut mz) = (0.0, 0.0, 0.0);
        for j in 0..my {
            for i in 0..mx {
                let k = j * mx + i;
                if bound[k] <= 0.0 {
                    continue;
                }
                // On its bound: slipping (an adhesion element exactly at its bound has no slip).
                if px[k].hypot(py[k]) >= bound[k] * (1.0 - 1e-9) {
                    let (ux, uy) = self.displacement(&spans, &dpx, &dpy, i, j);
                    sx[k] = wx0 - phi * g.y(j) + ux * inv_dq;
                    sy[k] = wy0 + phi * (g.x(i) + x_ofs) + uy * inv_dq;
                    state[k] = ElementState::Slip;
                } else {
                    state[k] = ElementState::Adhesion;
                }
                fx += px[k];
                fy += py[k];
                mz += g.x(i) * py[k] - g.y(j) * px[k];
            }
        }
        let da = g.area();
        Ok(TractionSolution {
            px,
            py,
            sx,
            sy,
            state,
            fx: fx * da,
            fy: fy * da,
            mz: mz * da,
            sweeps,
        })
    }

    /// Σ_K A(I − K) Δp_K at element I = (i, j) (the displacement difference u(x_I) − u(x_I + dx)).
    #[inline]
    fn displacement(
        &self,
        spans: &[Option<(usize, usize)>],
        dpx: &[f64],
        dpy: &[f64],
        i: usize,
        j: usize,
    ) -> (f64, f64) {
        let ker = &self.kernel;
        let mx = self.mx;
        let (mut ux, mut uy) = (0.0, 0.0);
        for (jj, span) in spans.iter().enumerate() {
            let Some((a, b)) = *span else { continue };
            // The kernel is even under (di, dj) → (−di, −dj): index it by K − I.
            let k0 = ker.index(a as isize - i as isize, jj as isize - j as isize);
            let len = b - a;
            let (kxx, kyy, kxy) = (
                &ker.xx[k0..k0 + len],
                &ker.yy[k0..k0 + len],
                &ker.xy[k0..k0 + len],
            );
            let r0 = jj * mx + a;
            let (qx, qy) = (&dpx[r0..r0 + len], &dpy[r0..r0 + len]);
            // Four independent partial sums per component: the additions' latency overlaps.
            let (mut sx, mut sy) = ([0.0; 4], [0.0; 4]);
            let chunks = len / 4;
            for c in 0..chunks {
                for l in 0..4 {
                    let t = 4 * c + l;
                    sx[l] += kxx[t] * qx[t] + kxy[t] * qy[t];
                    sy[l] += kxy[t] * qx[t] + kyy[t] * qy[t];
                }
            }
            for t in 4 * chunks..len {
                sx[0] += kxx[t] * qx[t] + kxy[t] * qy[t];
                sy[0] += kxy[t] * qx[t] + kyy[t] * qy[t];
            }
            ux += (sx[0] + sx[1]) + (sx[2] + sx[3]);
            uy += (sy[0] + sy[1]) + (sy[2] + sy[3]);
        }
        (ux, uy)
    }
}

/// A traction clipped to the bound g.
fn clip(px: f64, py: f64, g: f64) -> (f64, f64) {
    let m = px.hypot(py);
    if m > g {
        (px * g / m, py * g / m)
    } else {
        (px, py)
    }
}

/// The k ≥ 0 with (rx/(dx + k))² + (ry/(dy + k))² = g², given that k = 0 gives more than g²:
/// Newton from below on a convex decreasing function (monotone convergence), on
/// 1/|q(k)| − 1/g which is nearly linear in k.
pub(crate) fn slip_root(rx: f64, ry: f64, dx: f64, dy: f64, g: f64) -> f64 {
    let r = rx.hypot(ry);
    // Start where every term is at least its share: f(k₀) ≥ 0.
    let mut k = (r / g - dx.max(dy)).max(0.0);
    for _ in 0..50 {
        let (ex, ey) = (dx + k, dy + k);
        let (qx, qy) = (rx / ex, ry / ey);
        let q2 = qx * qx + qy * qy;
        let q = q2.sqrt();
        // h(k) = 1/q − 1/g, h' = −(1/q³) dq²/dk / 2 = (1/q³)(qx²/ex + qy²/ey).
        let h = 1.0 / q - 1.0 / g;
        let dh = (qx * qx / ex + qy * qy / ey) / (q2 * q);
        let step = -h / dh;
        k += step;
        if k < 0.0 {
            k = 0.0;
        }
        if step.abs() <= 1e-14 * (k + dx.min(dy)) {
            break;
        }
    }
    k
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slip_root_meets_the_bound() {
        for &(rx, ry, dx, dy, g) in &[
            (3.0, 4.0, 1.0, 1.0, 2.0),
            (-3.0, 0.5, 1.0, 1.3, 0.7),
            (1e-3, -2.0, 0.8, 1.1, 0.01),
            (5.0, 0.0, 1.0, 2.0, 1.0),
        ] {
            let k = slip_root(rx, ry, dx, dy, g);
            let (qx, qy): (f64, f64) = (rx / (dx + k), ry / (dy + k));
            assert!(k >= 0.0);
            assert!(
                (qx.hypot(qy) - g).abs() < 1e-10 * g,
                "{rx} {ry}: |q| = {}",
                qx.hypot(qy)
            );
        }
    }
}
