//! The exact theory tabulated (`model = "exact-table"`): Kalker's exact theory of steady rolling
//! on Hertz's ellipse ([`super::exact`]), solved once over a grid of normalised inputs and
//! interpolated at run time — the idea of Kalker's USETAB, with kecsim's own table and solver.
//!
//! **Similarity.** For a Hertz patch of given a/b (and ν), the exact solution depends on the
//! creepages only through
//!
//! ```text
//! ξ̂ = G ab C₁₁ ξ / (μN),   η̂ = G ab C₂₂ η / (μN),   φ̂ = G (ab)^{3/2} C₂₃ φ / (μN)
//! ```
//!
//! (lengths scale with c = √(ab), tractions with μ p₀ ∝ μN/c², u = A p ∝ c p/G), and gives
//! F/(μN) and Mz/(μN c). In these variables Kalker's linear theory is F̂x = −ξ̂, F̂y = −η̂ − φ̂.
//!
//! **Symmetry.** F(ξ, −η, −φ) = (Fx, −Fy, −Mz) (mirror in y) and F(−ξ, η, φ) = (−Fx, Fy, Mz)
//! (that mirror composed with F(−w) = −F(w)): the table holds ξ̂ ≥ 0, φ̂ ≥ 0.
//!
//! **Coordinates.** ln(a/b); u = φ̂/(φ_s + φ̂) ∈ [0, 1] (φ_s = 1); the creepage in polar form around
//! Kalker's linear force, ρ = |(ξ̂, η̂ + φ̂)| with t = ρ/(ρ_s + ρ) ∈ [0, 1] (ρ_s = 2) and
//! θ = atan2(η̂ + φ̂, ξ̂) ∈ [−π/2, π/2]. u = 1 and t = 1 are the limits
//! φ̂ → ∞ and ρ → ∞ (solved at 10⁶), so no creepage and no spin lies outside the table; a/b does
//! (the table spans 0.05–20): there [`ExactTable::forces`] answers an error and the model falls
//! back to the exact solver (never an extrapolated force).
//!
//! **Interpolation.** Each a/b slice is refined on first use ([`REFINE`]: 2× in u and t, 49
//! directions uniform in w = tan(θ/2)) by a cubic interpolation of the nodes — Catmull–Rom in θ
//! (mirrored beyond ±π/2 by the symmetry), then monotone cubics (Fritsch–Carlson) in t and u —, and
//! a call reads the refined grid multilinearly (linear in ln(a/b) between two slices: 16 values).
//! Monotone because a cubic's overshoot at the knee where the force meets μN is a falling branch —
//! a negative creep stiffness, the defect this model replaces (Catmull–Rom had one of 1.9·10⁻⁴ μN
//! per step there; tested now). The table's error against the exact solver is measured by
//! `kecsim bench creep-accuracy` and tested.
//!
//! **File.** `assets/creep/exact_table.bin` (embedded in the library): a header (magic, version,
//! ν, the solver's settings, the node counts), the nodes, the values as f32 (F̂x, F̂y, M̂z per
//! node, θ fastest, then t, u, a/b), and an FNV-1a checksum of all of it. Loading checks the
//! checksum and every value's plausibility (finite, |F̂| ≤ 1.02); `kecsim creep --build-table`
//! rebuilds it.

use std::f64::consts::FRAC_PI_2;
use std::sync::OnceLock;

use rayon::prelude::*;

use super::creepage::Creepage;
use super::exact::{IterationSettings, PressureGrid, RollingOperator};
use super::kalker::KalkerTable;
use super::patch::{ContactPatch, CreepForce};

/// The shipped table.
const EMBEDDED: &[u8] = include_bytes!("../../../assets/creep/exact_table.bin");
const MAGIC: &[u8; 8] = b"KECXTAB1";

pub use super::table_error::TableError;

/// The nodes of a table and the exact solver's settings that fill it.
#[derive(Debug, Clone, PartialEq)]
pub struct TableSpec {
    pub poisson: f64,
    /// Elements across the ellipse of the fine grid (the coarse one has half; Richardson).
    pub elements: usize,
    pub tolerance: f64,
    /// ρ_s and φ_s of the maps t = ρ/(ρ + ρ_s), u = φ̂/(φ̂ + φ_s).
    pub rho_scale: f64,
    pub phi_scale: f64,
    /// ln(a/b) nodes, increasing.
    pub log_ab: Vec<f64>,
    /// u = φ̂/(φ_s + φ̂) nodes, 0 … 1.
    pub u: Vec<f64>,
    /// t = ρ/(ρ_s + ρ) nodes, 0 … 1.
    pub t: Vec<f64>,
    /// θ nodes, −π/2 … π/2.
    pub theta: Vec<f64>,
}

impl Default for TableSpec {
    fn default() -> Self {
        let lin = |n: usize, a: f64, b: f64| -> Vec<f64> {
            (0..n).map(|i| a + (b - a) * i as f64 / (n - 1) as f64).collect()
        };
        TableSpec {
            poisson: 0.28,
            elements: 32,
            tolerance: 1e-5,
            rho_scale: 2.0,
            phi_scale: 1.0,
            log_ab: lin(19, 0.05f64.ln(), 20f64.ln()),
            u: lin(19, 0.0, 1.0),
            t: lin(25, 0.0, 1.0),
            theta: lin(13, -FRAC_PI_2, FRAC_PI_2),
        }
    }
}

/// The exact theory tabulated.
#[derive(Debug, Clone, PartialEq)]
pub struct ExactTable {
    pub spec: TableSpec,
    /// (F̂x, F̂y, M̂z) per node, θ fastest, then t, u, a/b.
    values: Vec<[f32; 3]>,
    /// Each a/b slice refined by the cubic interpolation, made on first use: [`REFINE`]-fold in u
    /// and t, and in w = tan(θ/2) uniform with [`REFINE`]-fold θ's count; the run-time
    /// interpolation is then multilinear (16 nodes).
    fine: Vec<OnceLock<Vec<[f32; 3]>>>,
}

/// Refinement of the run-time grid in u, t and θ (the nodes' spacing divided by these; in θ the
/// count, the fine nodes uniform in w = tan(θ/2), 2.4–4.8° apart): a chord of the unit circle
/// over 4.8° is 0.09 % short of it (the force at full sliding).
pub const REFINE: [usize; 3] = [2, 2, 4];

/// Stand-in for ∞ in the solver: ρ, φ̂ at t = 1, u = 1.
const INFINITE: f64 = 1e6;

fn from_unit(s: f64, scale: f64) -> f64 {
    if s >= 1.0 {
        INFINITE
    } else {
        scale * s / (1.0 - s)
    }
}

/// Catmull–Rom weights of the four nodes i − 1 … i + 2 at local coordinate w ∈ [0, 1].
#[inline]
fn cr(w: f64) -> [f64; 4] {
    let (w2, w3) = (w * w, w * w * w);
    [
        0.5 * (-w + 2.0 * w2 - w3),
        0.5 * (2.0 - 5.0 * w2 + 3.0 * w3),
        0.5 * (w + 4.0 * w2 - 3.0 * w3),
        0.5 * (-w2 + w3),
    ]
}

/// The cell [x_i, x_{i+1}] of uniform nodes holding x (clamped to the ends) and the local
/// coordinate in it.
#[inline]
fn uniform_cell(nodes: &[f64], x: f64) -> (usize, f64) {
    cell_of(nodes[0], nodes[1] - nodes[0], nodes.len(), x)
}

/// The same for n nodes x₀ + k h.
#[inline]
fn cell_of(x0: f64, h: f64, n: usize, x: f64) -> (usize, f64) {
    let s = ((x - x0) / h).clamp(0.0, (n - 1) as f64);
    let i = (s as usize).min(n - 2);
    (i, s - i as f64)
}

/// Whether the nodes are equally spaced (to 10⁻⁹ of the span).
fn is_uniform(nodes: &[f64]) -> bool {
    let n = nodes.len();
    let h = (nodes[n - 1] - nodes[0]) / (n - 1) as f64;
    h > 0.0
        && nodes
            .iter()
            .enumerate()
            .all(|(i, &x)| (x - (nodes[0] + h * i as f64)).abs() <= 1e-9 * h * n as f64)
}

/// Monotone cubic Hermite interpolation (Fritsch–Carlson) between v₀ and v₁ at local coordinate
/// w, each of the three components on its own, from the node before (v₋) and after (v₊) where
/// they exist (uniform nodes). The tangents are Catmull–Rom's (one-sided at an end), set to zero
/// where the data turn and limited to three times the neighbouring secants, so the interpolant
/// never overshoots its nodes and is monotone wherever they are — no false falling branch at the
/// knee where the exact force meets μN.
#[inline]
fn monotone_cubic(
    vm: Option<[f64; 3]>,
    v0: [f64; 3],
    v1: [f64; 3],
    vp: Option<[f64; 3]>,
    w: f64,
) -> [f64; 3] {
    let (w2, w3) = (w * w, w * w * w);
    let h00 = 2.0 * w3 - 3.0 * w2 + 1.0;
    let h10 = w3 - 2.0 * w2 + w;
    let h01 = -2.0 * w3 + 3.0 * w2;
    let h11 = w3 - w2;
    let tangent = |before: Option<f64>, after: Option<f64>| -> f64 {
        match (before, after) {
            (Some(b), Some(a)) => {
                if a * b <= 0.0 {
                    0.0
                } else {
                    let m = 0.5 * (a + b);
                    let lim = 3.0 * a.abs().min(b.abs());
                    m.signum() * m.abs().min(lim)
                }
            }
            _ => 0.0,
        }
    };
    // At an end: the three-point one-sided slope (3d − d')/2, kept to the secant's sign and
    // three times its size.
    let end = |d: f64, next: Option<f64>| -> f64 {
        let m = next.map_or(d, |e| 0.5 * (3.0 * d - e));
        if m * d <= 0.0 {
            0.0
        } else {
            m.signum() * m.abs().min(3.0 * d.abs())
        }
    };
    let mut out = [0.0; 3];
    for c in 0..3 {
        let d = v1[c] - v0[c];
        let before = vm.map(|v| v0[c] - v[c]);
        let after = vp.map(|v| v[c] - v1[c]);
        let m0 = if before.is_some() {
            tangent(before, Some(d))
        } else {
            end(d, after)
        };
        let m1 = if after.is_some() {
            tangent(Some(d), after)
        } else {
            end(d, before)
        };
        out[c] = h00 * v0[c] + h10 * m0 + h01 * v1[c] + h11 * m1;
    }
    out
}

/// The normalising factors of a patch: ξ̂ = k₁ξ, η̂ = k₂η, φ̂ = k₃φ; F = μN F̂; Mz = μN c M̂.
#[derive(Debug, Clone, Copy)]
struct Scales {
    k1: f64,
    k2: f64,
    k3: f64,
    mun: f64,
    c: f64,
}

impl Scales {
    fn of(p: &ContactPatch) -> Scales {
        let mun = p.friction * p.normal_force;
        let ab = p.a * p.b;
        let c = ab.sqrt();
        let g = p.shear_modulus / mun;
        Scales {
            k1: g * ab * p.kalker.c11,
            k2: g * ab * p.kalker.c22,
            k3: g * ab * c * p.kalker.c23,
            mun,
            c,
        }
    }
}

impl ExactTable {
    /// The shipped table (read and checked once).
    pub fn embedded() -> Result<&'static ExactTable, TableError> {
        static TABLE: OnceLock<Result<ExactTable, TableError>> = OnceLock::new();
        TABLE
            .get_or_init(|| ExactTable::from_bytes(EMBEDDED))
            .as_ref()
            .map_err(Clone::clone)
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.values.len()
    }

    /// Whether it has no node (never for a valid table).
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// The range of a/b the table covers.
    pub fn ab_range(&self) -> (f64, f64) {
        let l = &self.spec.log_ab;
        (l[0].exp(), l[l.len() - 1].exp())
    }

    /// Creep forces on the wheel from the table: an error where a/b lies outside it or the
    /// patch's ν is not the table's.
    pub fn forces(&self, patch: &ContactPatch, creep: &Creepage) -> Result<CreepForce, TableError> {
        if (patch.poisson - self.spec.poisson).abs() > 1e-9 {
            return Err(TableError::Poisson {
                table: self.spec.poisson,
                patch: patch.poisson,
            });
        }
        let ab = patch.a / patch.b;
        let la = ab.ln();
        let s = &self.spec;
        let (lo, hi) = (s.log_ab[0], s.log_ab[s.log_ab.len() - 1]);
        if !(la >= lo - 1e-12 && la <= hi + 1e-12) {
            let (a0, a1) = self.ab_range();
            return Err(TableError::OutOfRange(ab, a0, a1));
        }
        if patch.friction <= 0.0 || patch.normal_force <= 0.0 {
            return Ok(CreepForce::with_saturation(0.0, 0.0, 0.0, patch));
        }
        let k = Scales::of(patch);
        let (mut xi, mut eta, mut phi) = (k.k1 * creep.longitudinal, k.k2 * creep.lateral, k.k3 * creep.spin);
        // Symmetries: φ̂ ≥ 0 (mirror in y), then ξ̂ ≥ 0.
        // (At φ = 0 also η̂ ≥ 0: the mirror then holds exactly, not to the solver's residue.)
        let flip_y = phi < 0.0 || (phi == 0.0 && eta < 0.0);
        if flip_y {
            eta = -eta;
            phi = -phi;
        }
        let flip_x = xi < 0.0;
        if flip_x {
            xi = -xi;
        }
        // The creepage in polar form around Kalker's linear force (ξ̂, η̂ + φ̂).
        let ly = eta + phi;
        let rho = (xi * xi + ly * ly).sqrt();
        let t = rho / (s.rho_scale + rho);
        let u = phi / (s.phi_scale + phi);
        // The angle as w = tan(θ/2) = ly/(ξ̂ + ρ) ∈ [−1, 1] (ξ̂ ≥ 0: no cancellation; no atan2).
        let w = if rho > 0.0 { ly / (xi + rho) } else { 0.0 };
        let [mut fx, mut fy, mut mz] = self.interpolate(la, u, t, w);
        // The symmetries fix these exactly (the nodes carry the solver's residue): ξ = 0 gives
        // Fx = 0 (F(−ξ, η, φ) = (−Fx, Fy, Mz)); η = φ = 0 gives Fy = Mz = 0.
        if xi == 0.0 {
            fx = 0.0;
        }
        if phi == 0.0 && eta == 0.0 {
            fy = 0.0;
            mz = 0.0;
        }
        if flip_x {
            fx = -fx;
        }
        if flip_y {
            fy = -fy;
            mz = -mz;
        }
        Ok(CreepForce::with_saturation(
            k.mun * fx,
            k.mun * fy,
            k.mun * k.c * mz,
            patch,
        ))
    }

    /// One empty refined slice per a/b node.
    fn with_slices(mut self) -> ExactTable {
        self.fine = (0..self.spec.log_ab.len()).map(|_| OnceLock::new()).collect();
        self
    }

    /// Node counts of the refined grid in u, t, θ.
    fn fine_counts(&self) -> (usize, usize, usize) {
        let s = &self.spec;
        let f = |n: usize, r: usize| (n - 1) * r + 1;
        (
            f(s.u.len(), REFINE[0]),
            f(s.t.len(), REFINE[1]),
            f(s.theta.len(), REFINE[2]),
        )
    }

    /// The a/b slice `ia` refined (made once, on first use).
    fn slice(&self, ia: usize) -> &[[f32; 3]] {
        self.fine[ia].get_or_init(|| {
            let s = &self.spec;
            let (nu, nt, nth) = self.fine_counts();
            let at = |v: &[f64], k: usize, r: usize| {
                let h = (v[1] - v[0]) / r as f64;
                (v[0] + h * k as f64).min(v[v.len() - 1])
            };
            let mut out = Vec::with_capacity(nu * nt * nth);
            for ku in 0..nu {
                for kt in 0..nt {
                    for kth in 0..nth {
                        let v = self.interpolate_cubic(
                            ia,
                            at(&s.u, ku, REFINE[0]),
                            at(&s.t, kt, REFINE[1]),
                            2.0 * (-1.0 + 2.0 * kth as f64 / (nth - 1) as f64).atan(),
                        );
                        out.push(v.map(|x| x as f32));
                    }
                }
            }
            out
        })
    }

    /// (F̂x, F̂y, M̂z) at (ln a/b, u, t, w) with w = tan(θ/2) ∈ [−1, 1]: linear in ln(a/b) and, on
    /// the refined grid (uniform in u, t and w), in u, t and w (16 nodes; the refined nodes are the
    /// cubic interpolation's, so the error is the cubic's plus the linear one's over the finer
    /// spacing: measured by `kecsim bench creep-accuracy`, tested below).
    pub fn interpolate(&self, la: f64, u: f64, t: f64, w: f64) -> [f64; 3] {
        let s = &self.spec;
        let (nu, nt, nth) = self.fine_counts();
        let (ia, wa) = uniform_cell(&s.log_ab, la);
        let fine = |v: &[f64], r: usize| (v[1] - v[0]) / r as f64;
        let (iu, wu) = cell_of(s.u[0], fine(&s.u, REFINE[0]), nu, u);
        let (it, wt) = cell_of(s.t[0], fine(&s.t, REFINE[1]), nt, t);
        let (ith, wth) = cell_of(-1.0, 2.0 / (nth - 1) as f64, nth, w);
        let mut out = [0.0; 3];
        for (da, fa) in [(0usize, 1.0 - wa), (1, wa)] {
            if fa == 0.0 {
                continue;
            }
            let v = self.slice(ia + da);
            for (du, fu) in [(0usize, 1.0 - wu), (1, wu)] {
                for (dt, ft) in [(0usize, 1.0 - wt), (1, wt)] {
                    let base = ((iu + du) * nt + it + dt) * nth + ith;
                    let (n0, n1) = (v[base], v[base + 1]);
                    let f = fa * fu * ft;
                    let (f0, f1) = (f * (1.0 - wth), f * wth);
                    for c in 0..3 {
                        out[c] += f0 * n0[c] as f64 + f1 * n1[c] as f64;
                    }
                }
            }
        }
        out
    }

    /// The cubic interpolation on the a/b slice `ia` at (u, t, θ): Catmull–Rom in θ (the nodes
    /// beyond ±π/2 by the mirror θ → ±π − θ of F(−ξ, η, φ) = (−Fx, Fy, Mz)), then a monotone cubic
    /// in t, then in u.
    fn interpolate_cubic(&self, ia: usize, u: f64, t: f64, theta: f64) -> [f64; 3] {
        let s = &self.spec;
        let (nu, nt, nth) = (s.u.len(), s.t.len(), s.theta.len());
        let (iu, wu) = uniform_cell(&s.u, u);
        let (it, wt) = uniform_cell(&s.t, t);
        let (ith, wth) = uniform_cell(&s.theta, theta);
        let cth = cr(wth);
        let mut jth = [0usize; 4];
        let mut sth = [[0.0f64; 3]; 4];
        for q in 0..4 {
            let j = ith as isize - 1 + q as isize;
            let (jj, sx) = if j < 0 {
                (-j, -1.0)
            } else if j >= nth as isize {
                (2 * (nth as isize - 1) - j, -1.0)
            } else {
                (j, 1.0)
            };
            jth[q] = jj as usize;
            sth[q] = [cth[q] * sx, cth[q], cth[q]];
        }
        let t_lo = it.saturating_sub(1);
        let t_hi = (it + 2).min(nt - 1);
        let u_lo = iu.saturating_sub(1);
        let u_hi = (iu + 2).min(nu - 1);
        let mut along_u = [[0.0f64; 3]; 4];
        for ku in u_lo..=u_hi {
            let mut along_t = [[0.0f64; 3]; 4];
            for kt in t_lo..=t_hi {
                let base = ((ia * nu + ku) * nt + kt) * nth;
                let mut v = [0.0f64; 3];
                for q in 0..4 {
                    let n = self.values[base + jth[q]];
                    for c in 0..3 {
                        v[c] += sth[q][c] * n[c] as f64;
                    }
                }
                along_t[kt + 1 - it] = v;
            }
            along_u[ku + 1 - iu] = monotone_cubic(
                (it > 0).then_some(along_t[0]),
                along_t[1],
                along_t[2],
                (it + 2 < nt).then_some(along_t[3]),
                wt,
            );
        }
        monotone_cubic(
            (iu > 0).then_some(along_u[0]),
            along_u[1],
            along_u[2],
            (iu + 2 < nu).then_some(along_u[3]),
            wu,
        )
    }

    /// Solves every node with the exact solver (Richardson over the spec's grids), lines of
    /// t at fixed (a/b, u, θ) warm-started point to point; `done` is called per node line.
    pub fn build(spec: &TableSpec, done: &(dyn Fn() + Sync)) -> Result<ExactTable, super::exact::ExactError> {
        let table = KalkerTable::new(spec.poisson);
        let (g, n, mu) = (82e9, 1e5, 0.3);
        let lines: Vec<(usize, usize, usize)> = (0..spec.log_ab.len())
            .flat_map(|ia| {
                (0..spec.u.len()).flat_map(move |iu| (0..spec.theta.len()).map(move |ith| (ia, iu, ith)))
            })
            .collect();
        let solved: Result<Vec<Vec<[f32; 3]>>, _> = lines
            .par_iter()
            .map(|&(ia, iu, ith)| {
                let ab = spec.log_ab[ia].exp();
                let c = 5e-3;
                let (a, b) = (c * ab.sqrt(), c / ab.sqrt());
                let patch = ContactPatch::new(a, b, n, g, mu, &table)
                    .map_err(|e| super::exact::ExactError::Grid(e.to_string()))?;
                let k = Scales::of(&patch);
                let phi = from_unit(spec.u[iu], spec.phi_scale) / k.k3;
                let th = spec.theta[ith];
                let it_settings = IterationSettings {
                    tolerance: spec.tolerance,
                    ..IterationSettings::default()
                };
                let grids = [spec.elements, spec.elements / 2].map(|m| {
                    let p = PressureGrid::hertz(a, b, n, m, m);
                    p.map(|p| {
                        let op = RollingOperator::for_grid(&p, g, spec.poisson);
                        (p, op)
                    })
                });
                let [fine, coarse] = grids;
                let (fine, coarse) = (fine?, coarse?);
                let mut warm: [Option<(Vec<f64>, Vec<f64>)>; 2] = [None, None];
                let mut out = Vec::with_capacity(spec.t.len());
                for &tv in &spec.t {
                    let rho = from_unit(tv, spec.rho_scale);
                    let phi_hat = from_unit(spec.u[iu], spec.phi_scale);
                    let eta_hat = if rho >= INFINITE {
                        rho * th.sin()
                    } else {
                        rho * th.sin() - phi_hat
                    };
                    let creep = Creepage::new(rho * th.cos() / k.k1, eta_hat / k.k2, phi);
                    let mut f = [[0.0; 3]; 2];
                    for (q, (p, op)) in [&fine, &coarse].into_iter().enumerate() {
                        let start = warm[q].as_ref().map(|(x, y)| (x.as_slice(), y.as_slice()));
                        let sol = op.solve(p, mu, &creep, &it_settings, start).map_err(|e| {
                            super::exact::ExactError::Grid(format!(
                                "the node a/b = {ab:.4}, u = {}, t = {tv}, θ = {th:.4} ({} elements): {e}",
                                spec.u[iu], p.grid.my
                            ))
                        })?;
                        f[q] = [sol.fx, sol.fy, sol.mz];
                        warm[q] = Some((sol.px, sol.py));
                    }
                    let r = |i: usize| 2.0 * f[0][i] - f[1][i];
                    out.push([
                        (r(0) / k.mun) as f32,
                        (r(1) / k.mun) as f32,
                        (r(2) / (k.mun * k.c)) as f32,
                    ]);
                }
                done();
                Ok(out)
            })
            .collect();
        let solved = solved?;
        // Reorder: lines are (a/b, u, θ) with t inside; the table is θ fastest, then t.
        let (nu_, nt, nth) = (spec.u.len(), spec.t.len(), spec.theta.len());
        let mut values = vec![[0.0f32; 3]; spec.log_ab.len() * nu_ * nt * nth];
        for (line, &(ia, iu, ith)) in solved.iter().zip(&lines) {
            for (it, v) in line.iter().enumerate() {
                values[((ia * nu_ + iu) * nt + it) * nth + ith] = *v;
            }
        }
        Ok(ExactTable {
            spec: spec.clone(),
            fine: Vec::new(),
            values,
        }
        .with_slices())
    }

    /// The file's bytes (see the module's documentation).
    pub fn to_bytes(&self) -> Vec<u8> {
        let s = &self.spec;
        let mut b = Vec::new();
        b.extend_from_slice(MAGIC);
        b.extend_from_slice(&s.poisson.to_le_bytes());
        b.extend_from_slice(&(s.elements as u32).to_le_bytes());
        b.extend_from_slice(&s.tolerance.to_le_bytes());
        b.extend_from_slice(&s.rho_scale.to_le_bytes());
        b.extend_from_slice(&s.phi_scale.to_le_bytes());
        for v in [&s.log_ab, &s.u, &s.t, &s.theta] {
            b.extend_from_slice(&(v.len() as u32).to_le_bytes());
        }
        for v in [&s.log_ab, &s.u, &s.t, &s.theta] {
            for x in v.iter() {
                b.extend_from_slice(&x.to_le_bytes());
            }
        }
        for v in &self.values {
            for x in v {
                b.extend_from_slice(&x.to_le_bytes());
            }
        }
        let sum = fnv1a(&b);
        b.extend_from_slice(&sum.to_le_bytes());
        b
    }

    /// Reads and checks a table file's bytes: the checksum, the sizes against the file's length
    /// (before allocating), the nodes' order and range, every value finite and plausible.
    pub fn from_bytes(bytes: &[u8]) -> Result<ExactTable, TableError> {
        let bad = |m: &str| TableError::Format(m.to_string());
        if bytes.len() < 8 + 8 + 4 + 8 + 16 + 16 + 8 || &bytes[..8] != MAGIC {
            return Err(bad("not a kecsim exact-theory table (magic)"));
        }
        let (body, sum) = bytes.split_at(bytes.len() - 8);
        let sum = u64::from_le_bytes(sum.try_into().map_err(|_| bad("checksum"))?);
        if fnv1a(body) != sum {
            return Err(bad("checksum mismatch: the file is damaged"));
        }
        let mut pos = 8;
        let mut take = |n: usize| -> Result<&[u8], TableError> {
            let s = body.get(pos..pos + n).ok_or_else(|| bad("truncated"))?;
            pos += n;
            Ok(s)
        };
        let f64_ = |s: &[u8]| f64::from_le_bytes(s.try_into().unwrap_or([0; 8]));
        let u32_ = |s: &[u8]| u32::from_le_bytes(s.try_into().unwrap_or([0; 4])) as usize;
        let poisson = f64_(take(8)?);
        let elements = u32_(take(4)?);
        let tolerance = f64_(take(8)?);
        let rho_scale = f64_(take(8)?);
        let phi_scale = f64_(take(8)?);
        if !(rho_scale > 0.0 && rho_scale < 1e3 && phi_scale > 0.0 && phi_scale < 1e3) {
            return Err(bad("map scales out of range"));
        }
        let mut counts = [0usize; 4];
        for c in counts.iter_mut() {
            *c = u32_(take(4)?);
            if !(2..=1000).contains(c) {
                return Err(bad("node count out of range"));
            }
        }
        let nodes: usize = counts.iter().sum();
        let cells: usize = counts.iter().product();
        // The header so far: magic, ν, elements, tolerance, the two scales, four counts.
        if body.len() != 8 + 8 + 4 + 8 + 16 + 16 + 8 * nodes + 12 * cells {
            return Err(bad("size does not match its node counts"));
        }
        let mut axes: [Vec<f64>; 4] = Default::default();
        for (axis, &n) in axes.iter_mut().zip(&counts) {
            for _ in 0..n {
                axis.push(f64_(take(8)?));
            }
            if !axis.iter().all(|v| v.is_finite()) || !axis.windows(2).all(|w| w[1] > w[0]) {
                return Err(bad("nodes not finite and increasing"));
            }
        }
        let [log_ab, u, t, theta] = axes;
        let unit = |v: &[f64]| v[0] == 0.0 && v[v.len() - 1] == 1.0;
        if !(unit(&u) && unit(&t))
            || (theta[0] + FRAC_PI_2).abs() > 1e-12
            || (theta[theta.len() - 1] - FRAC_PI_2).abs() > 1e-12
            || !(0.0..=0.5).contains(&poisson)
        {
            return Err(bad("nodes do not span u, t ∈ [0, 1], θ ∈ [−π/2, π/2]"));
        }
        if ![&log_ab, &u, &t, &theta]
            .iter()
            .all(|v| v.len() >= 2 && is_uniform(v))
        {
            return Err(bad("nodes are not equally spaced on every axis"));
        }
        let mut values = Vec::with_capacity(cells);
        for _ in 0..cells {
            let s = take(12)?;
            let v = [0, 4, 8].map(|o| f32::from_le_bytes(s[o..o + 4].try_into().unwrap_or([0; 4])));
            if !v.iter().all(|x| x.is_finite())
                || (v[0] as f64).hypot(v[1] as f64) > 1.02
                || v[2].abs() > 10.0
            {
                return Err(bad("a value is not finite or beyond full sliding"));
            }
            values.push(v);
        }
        Ok(ExactTable {
            spec: TableSpec {
                poisson,
                elements,
                tolerance,
                rho_scale,
                phi_scale,
                log_ab,
                u,
                t,
                theta,
            },
            fine: Vec::new(),
            values,
        }
        .with_slices())
    }
}

/// FNV-1a, 64 bit.
fn fnv1a(b: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &x in b {
        h ^= x as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::forces::exact::{self, ExactSettings};

    fn patch(a_mm: f64, b_mm: f64) -> ContactPatch {
        ContactPatch::new(a_mm * 1e-3, b_mm * 1e-3, 80e3, 82e9, 0.3, &KalkerTable::new(0.28)).unwrap()
    }

    /// The shipped table reads back to itself; a damaged byte, a truncation, a forged header that
    /// asks for 9 GB and a forged NaN (both with the checksum recomputed) are refused, saying why,
    /// without allocating for the forged sizes.
    #[test]
    fn the_shipped_table_is_checked_on_reading() {
        let t = ExactTable::embedded().unwrap();
        assert_eq!(
            t.spec,
            TableSpec::default(),
            "the shipped table is the default spec's"
        );
        let bytes = t.to_bytes();
        assert_eq!(bytes, EMBEDDED);
        let mut damaged = bytes.clone();
        damaged[5000] ^= 1;
        assert!(ExactTable::from_bytes(&damaged)
            .unwrap_err()
            .to_string()
            .contains("checksum"));
        assert!(ExactTable::from_bytes(&bytes[..bytes.len() / 2]).is_err());
        let reseal = |mut b: Vec<u8>| {
            let n = b.len() - 8;
            let sum = fnv1a(&b[..n]);
            b[n..].copy_from_slice(&sum.to_le_bytes());
            b
        };
        // The first node count (at byte 44) forged to 1000: 9 GB of values asked for.
        let mut forged = bytes.clone();
        forged[44..48].copy_from_slice(&1000u32.to_le_bytes());
        let e = ExactTable::from_bytes(&reseal(forged)).unwrap_err().to_string();
        assert!(e.contains("size does not match"), "{e}");
        // A value forged to NaN.
        let mut forged = bytes.clone();
        let k = bytes.len() - 8 - 12;
        forged[k..k + 4].copy_from_slice(&f32::NAN.to_le_bytes());
        let e = ExactTable::from_bytes(&reseal(forged)).unwrap_err().to_string();
        assert!(e.contains("not finite"), "{e}");
    }

    /// Between its nodes (a/b, spin, creepage all off-node, at a/b 0.3–3.3 and beyond the
    /// symmetry's folds), the table is within 1 % of μN of the exact solver; at the nodes it is
    /// the solver's value; a/b outside the table is refused (the model then answers through the
    /// exact solver: `contact::forces::tests`).
    #[test]
    fn the_table_holds_the_exact_theory_between_its_nodes() {
        let t = ExactTable::embedded().unwrap();
        let s = ExactSettings::default();
        let mut worst: f64 = 0.0;
        for (a, b) in [(5.0, 7.2), (9.0, 4.1), (3.3, 10.9), (8.4, 2.55)] {
            let p = patch(a, b);
            for c in [
                Creepage::new(3.1e-4, -1.7e-4, 0.37),
                Creepage::new(-1.9e-3, 6.3e-4, -1.3),
                Creepage::new(7.7e-4, -2.6e-3, 2.9),
                Creepage::new(-6.1e-3, -4.4e-3, 3.7),
                Creepage::new(0.0, 1.3e-3, -0.8),
            ] {
                let e = exact::forces(&p, &c, &s).unwrap();
                let f = t.forces(&p, &c).unwrap();
                let d = (f.fx - e.fx).hypot(f.fy - e.fy) / (0.3 * 80e3);
                assert!(
                    d < 0.01,
                    "{a}×{b} {c:?}: table ({:.0}, {:.0}) exact ({:.0}, {:.0})",
                    f.fx,
                    f.fy,
                    e.fx,
                    e.fy
                );
                worst = worst.max(d);
            }
        }
        assert!(worst > 0.0);
        let narrow = patch(30.0, 1.0);
        assert!(matches!(
            t.forces(&narrow, &Creepage::new(1e-3, 0.0, 0.0)),
            Err(TableError::OutOfRange(..))
        ));
    }

    /// No falling branch: at constant friction the force opposing the creepage grows with it —
    /// −∂Fx/∂ξ ≥ 0 along ξ and −∂Fy/∂η ≥ 0 along η, spin included — over a/b 0.2–5, φ from −4 to
    /// 4 1/m, the other creepage held at 0, ±10⁻³, ±3·10⁻³, each line from −2 to +2 × the
    /// saturation creepage in 400 steps (Polach's Fy falls by 1.7 kN over such a line at the MS
    /// flange root: `contact::forces::tests`).
    #[test]
    fn the_table_has_no_falling_branch() {
        let t = ExactTable::embedded().unwrap();
        let mut lines = 0;
        for (a, b) in [
            (2.7, 13.4),
            (4.2, 8.5),
            (6.0, 6.0),
            (8.5, 4.2),
            (13.4, 2.7),
            (6.333, 2.689),
        ] {
            let p = patch(a, b);
            let sat = 3.0 * 0.3 * 80e3 / (p.shear_modulus * p.a * p.b * p.kalker.c22);
            for phi in [-4.0, -2.5, -1.0, 0.0, 0.7, 1.831, 3.0, 4.0] {
                for other in [0.0, 1e-3, -1e-3, 3e-3, -3e-3] {
                    for lateral in [true, false] {
                        let mut prev: Option<f64> = None;
                        for k in 0..=400 {
                            let s = sat * (-2.0 + 4.0 * k as f64 / 400.0);
                            let c = if lateral {
                                Creepage::new(other, s, phi)
                            } else {
                                Creepage::new(s, other, phi)
                            };
                            let f = t.forces(&p, &c).unwrap();
                            let v = if lateral { f.fy } else { f.fx };
                            if let Some(q) = prev {
                                assert!(
                                    v <= q + 1e-9 * 0.3 * 80e3,
                                    "{a}×{b}, φ {phi}, {} creepage {s:.3e} (other {other}): F {q} → {v}",
                                    if lateral { "lateral" } else { "longitudinal" }
                                );
                            }
                            prev = Some(v);
                        }
                        lines += 1;
                    }
                }
            }
        }
        assert_eq!(lines, 6 * 8 * 5 * 2);
    }
}
