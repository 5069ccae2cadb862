//! The KEC-method: knife-edge-equivalent profiles and constraints (paper §5–7, METHOD.md §6–8).
//!
//! **Equivalent profiles (§6).** From the 1-entry lookup table of the real profiles on an ideal
//! track, each row (y, z, φ) is turned into one point of the left and right equivalent profiles by
//! solving the KEC constraints the other way round (z̃ = z − r0, linearised roll):
//!
//! ```text
//! s^lk = (−y − φ(r0 + z̃) − φ² L_w) / (1 + φ²),   f^lk = z̃ + φ( L_w + s^lk)
//! s^rk = (−y − φ(r0 + z̃) + φ² L_w) / (1 + φ²),   f^rk = z̃ + φ(−L_w + s^rk)
//! ```
//!
//! The row's exact slopes dz/dy, dφ/dy give ds^k/dy and df^k/dy, so f^k(s^k) is a cubic Hermite
//! curve with exact slopes df^k/ds^k at the nodes (C¹; twin table rows at a contact jump give a
//! node with two slopes: the **kink** where the real contact jumps while the equivalent profile
//! stays continuous). With each node the real surface parameters are stored, giving the maps
//! s^w(s^k), s^r(s^k) of Eq. (52) (Hermite with exact slopes, steps at the kinks), and the
//! contact angle, rolling radius and curvatures at the real point (PCHIP).
//!
//! **KEC constraints (§5, Eq. 49–50).** With the rail reduced to a knife edge at the nominal
//! position (L_w from the wheelset centre, shifted by the rail irregularities), four equations in
//! x = [z̃, φ, s^lk, s^rk] for the independent coordinates q = [y, y_lir, z_lir, y_rir, z_rir]:
//!
//! ```text
//! F1 = y + s^lk + φ (r0 + f^lk(s^lk)) − y_lir = 0
//! F2 = z̃ + φ ( L_w + s^lk) − f^lk(s^lk) − z_lir = 0
//! F3 = y + s^rk + φ (r0 + f^rk(s^rk)) − y_rir = 0
//! F4 = z̃ + φ (−L_w + s^rk) − f^rk(s^rk) − z_rir = 0
//! ```
//!
//! solved by Newton from the Eq. (51) guess (s^lk = s^rk = −y, φ = 0, z̃ = (f^lk(−y) + f^rk(−y))/2)
//! or warm from a previous solution. Since q enters F linearly, dx/dq = −J⁻¹ ∂F/∂q and the second
//! derivatives follow from J d²x/dq_a dq_b = −F_xx[dx/dq_a, dx/dq_b] — what the equations of motion
//! need for the velocity and acceleration terms of z and φ.

use nalgebra::{Matrix4, Vector4};

use super::lookup::{transition_room, LookupTable1, TableRow, TRANSITION_PIECES};
use crate::interpolation::{cubic_hermite, hermite, pchip_slopes, quintic};
use crate::profile::Side;

/// Largest width of a two-point transition (fillet) in s^k, m — see
/// [`KecModel::with_two_point_transition`].
pub const TWO_POINT_MAX_WIDTH_M: f64 = 2e-3;

/// KEC errors.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum KecError {
    #[error("the lookup table must be a 1-entry table on an ideal track (gv = 0), got gv = {gv_mm} mm")]
    NotIdeal { gv_mm: f64 },
    #[error("the {side} equivalent profile is not a function of s^k near y = {y_mm:.4} mm (ds^k/dy = {slope:.3}): the roll changes faster than 1/r0")]
    NotMonotone {
        side: &'static str,
        y_mm: f64,
        slope: f64,
    },
    #[error("y = {y_mm:.4} mm: KEC Newton did not converge in {iterations} iterations (last correction {last_step:.3e})")]
    NoConvergence {
        y_mm: f64,
        iterations: usize,
        last_step: f64,
    },
    #[error("y = {y_mm:.4} mm: the {side} knife edge left the equivalent profile (s^k = {s_mm:.3} mm, profile spans {lo_mm:.3}..{hi_mm:.3} mm): beyond the table's flange contact")]
    OffProfile {
        y_mm: f64,
        side: &'static str,
        s_mm: f64,
        lo_mm: f64,
        hi_mm: f64,
    },
}

/// Per-node real-contact quantities interpolated along s^k (PCHIP): contact angle, rolling radius,
/// wheel and rail curvature.
const N_REAL: usize = 4;

/// One side's knife-edge-equivalent profile f^k(s^k) with the maps to the real contact.
#[derive(Debug, Clone)]
pub struct EquivalentProfile {
    pub side: Side,
    /// Nodes sorted by s^k (a kink is two nodes with the same s^k).
    s: Vec<f64>,
    f: Vec<f64>,
    df: Vec<f64>,
    /// Real surface parameters s^w, s^r and their slopes d/ds^k.
    s_wheel: Vec<f64>,
    ds_wheel: Vec<f64>,
    s_rail: Vec<f64>,
    ds_rail: Vec<f64>,
    /// The table's y of each node.
    y: Vec<f64>,
    real: Vec<[f64; N_REAL]>,
    real_slopes: Vec<[f64; N_REAL]>,
}

/// A point of an equivalent profile with the real contact it stands for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EquivalentPoint {
    /// f^k, df^k/ds^k, d²f^k/ds^k².
    pub f: f64,
    pub df: f64,
    pub d2f: f64,
    /// Real wheel and rail surface parameters (Eq. 52), m.
    pub s_wheel: f64,
    pub s_rail: f64,
    /// Real contact angle (rad), rolling radius (m), wheel and rail lateral curvature (1/m).
    pub contact_angle: f64,
    pub rolling_radius: f64,
    pub wheel_curvature: f64,
    pub rail_curvature: f64,
}

impl EquivalentPoint {
    /// Unit normal of the real rail at the real contact point in the track cross-section (Y, Z),
    /// pointing into the wheel, for the side `side`: the contact angle γ tilts it towards the track
    /// centre, n = (−σ sin γ, cos γ) — the direction of the normal force of Eq. (53).
    pub fn normal(&self, side: Side) -> (f64, f64) {
        let (s, c) = self.contact_angle.sin_cos();
        (-side.sign() * s, c)
    }
}

/// Where the real contact jumps: the equivalent profile's kink.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Kink {
    pub side: Side,
    /// Table y of the jump, m.
    pub y: f64,
    /// s^k of the kink, m.
    pub s_k: f64,
    /// df^k/ds^k on the side of smaller and of larger s^k.
    pub slope_before: f64,
    pub slope_after: f64,
    /// Real wheel surface parameter on either side, m.
    pub s_wheel_before: f64,
    pub s_wheel_after: f64,
    /// Real contact angle on either side, rad.
    pub angle_before: f64,
    pub angle_after: f64,
    /// Whether this side's real contact jumps here (otherwise the kink comes from the other
    /// side's jump through the roll, and this side's real contact moves on continuously).
    pub real_jump: bool,
}

/// One node of an equivalent profile with everything stored along it.
struct Node {
    s: f64,
    f: f64,
    df: f64,
    sw: f64,
    dsw: f64,
    sr: f64,
    dsr: f64,
    y: f64,
    real: [f64; N_REAL],
    real_slopes: [f64; N_REAL],
}

impl EquivalentProfile {
    fn build(side: Side, table: &LookupTable1, l_w: f64) -> Result<Self, KecError> {
        let r0 = table.r0;
        let sig = side.sign();
        let (ks_w, ks_r, ki) = match side {
            Side::Left => (2, 3, 0),
            Side::Right => (4, 5, 1),
        };
        let mut nodes = Vec::with_capacity(table.rows.len());
        for r in &table.rows {
            let (y, zt, phi) = (r.y, r.z() - r0, r.phi());
            let (dzt, dphi) = (r.dx_dy[0], r.dx_dy[1]);
            // s^k = N/D with N = −y − φ(r0 + z̃) − σφ²L_w, D = 1 + φ².
            let d = 1.0 + phi * phi;
            let n = -y - phi * (r0 + zt) - sig * phi * phi * l_w;
            let dn = -1.0 - dphi * (r0 + zt) - phi * dzt - 2.0 * sig * phi * dphi * l_w;
            let dd = 2.0 * phi * dphi;
            let s = n / d;
            let ds = (dn * d - n * dd) / (d * d);
            let f = zt + phi * (sig * l_w + s);
            let dfdy = dzt + dphi * (sig * l_w + s) + phi * ds;
            if ds >= -1e-9 {
                return Err(KecError::NotMonotone {
                    side: side.name(),
                    y_mm: y * 1e3,
                    slope: ds,
                });
            }
            nodes.push(Node {
                s,
                f,
                df: dfdy / ds,
                sw: r.x[ks_w],
                dsw: r.dx_dy[ks_w] / ds,
                sr: r.x[ks_r],
                dsr: r.dx_dy[ks_r] / ds,
                y,
                real: [
                    r.contact_angle[ki],
                    r.rolling_radius[ki],
                    r.curvature[2 * ki],
                    r.curvature[2 * ki + 1],
                ],
                real_slopes: [0.0; N_REAL],
            });
        }
        // A jump is two table rows at one y, the limits from either side: the same wheelset
        // configuration, so the same s^k and f — but each row's z and φ carry their own solve's
        // error (~1e-7 rad in φ at the flange-root jump: 4e-8 m in s^k), and two nodes 40 nm
        // apart made one cubic over that gap, f'' ~ 1e8 1/m: not a kink, a spike in the
        // constraint's velocity terms (found on the MS vehicle's leading wheelset). Merge them.
        for k in 0..nodes.len().saturating_sub(1) {
            if nodes[k].y == nodes[k + 1].y {
                let (s_mid, f_mid) = (
                    0.5 * (nodes[k].s + nodes[k + 1].s),
                    0.5 * (nodes[k].f + nodes[k + 1].f),
                );
                for n in [k, k + 1] {
                    nodes[n].s = s_mid;
                    nodes[n].f = f_mid;
                }
            }
        }
        // s^k decreases with y: reverse to increasing s^k.
        nodes.reverse();
        let mut start = 0;
        for end in 1..=nodes.len() {
            if end == nodes.len() || nodes[end].s <= nodes[end - 1].s {
                let ss: Vec<f64> = nodes[start..end].iter().map(|n| n.s).collect();
                for c in 0..N_REAL {
                    let vs: Vec<f64> = nodes[start..end].iter().map(|n| n.real[c]).collect();
                    for (node, d) in nodes[start..end].iter_mut().zip(pchip_slopes(&ss, &vs)) {
                        node.real_slopes[c] = d;
                    }
                }
                start = end;
            }
        }
        Ok(Self::from_nodes(side, &nodes))
    }

    fn from_nodes(side: Side, nodes: &[Node]) -> Self {
        EquivalentProfile {
            side,
            s: nodes.iter().map(|n| n.s).collect(),
            f: nodes.iter().map(|n| n.f).collect(),
            df: nodes.iter().map(|n| n.df).collect(),
            s_wheel: nodes.iter().map(|n| n.sw).collect(),
            ds_wheel: nodes.iter().map(|n| n.dsw).collect(),
            s_rail: nodes.iter().map(|n| n.sr).collect(),
            ds_rail: nodes.iter().map(|n| n.dsr).collect(),
            y: nodes.iter().map(|n| n.y).collect(),
            real: nodes.iter().map(|n| n.real).collect(),
            real_slopes: nodes.iter().map(|n| n.real_slopes).collect(),
        }
    }

    /// Node k as stored.
    fn node(&self, k: usize) -> Node {
        Node {
            s: self.s[k],
            f: self.f[k],
            df: self.df[k],
            sw: self.s_wheel[k],
            dsw: self.ds_wheel[k],
            sr: self.s_rail[k],
            dsr: self.ds_rail[k],
            y: self.y[k],
            real: self.real[k],
            real_slopes: self.real_slopes[k],
        }
    }

    /// Range of s^k, m.
    pub fn domain(&self) -> (f64, f64) {
        (self.s[0], self.s[self.s.len() - 1])
    }

    /// The nodes (s^k, f^k), m — one per table row.
    pub fn nodes(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.s.iter().copied().zip(self.f.iter().copied())
    }

    /// The table y of each node (same order as [`EquivalentProfile::nodes`]).
    pub fn node_y(&self) -> &[f64] {
        &self.y
    }

    /// Real surface parameters (s^w, s^r) of each node.
    pub fn node_real(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.s_wheel.iter().copied().zip(self.s_rail.iter().copied())
    }

    #[inline]
    fn segment(&self, s: f64) -> usize {
        let n = self.s.len();
        let k = match self.s.partition_point(|&v| v <= s) {
            0 => 0,
            p if p >= n => n - 2,
            p => p - 1,
        };
        if self.s[k + 1] == self.s[k] {
            k.saturating_sub(1)
        } else {
            k
        }
    }

    /// f^k and its derivatives at `s` (no range check; extrapolates the end cubic).
    #[inline]
    pub fn eval(&self, s: f64) -> (f64, f64, f64) {
        let k = self.segment(s);
        cubic_hermite(
            self.s[k],
            self.s[k + 1],
            self.f[k],
            self.f[k + 1],
            self.df[k],
            self.df[k + 1],
            s,
        )
    }

    /// The equivalent profile at `s` with the real contact it maps to.
    pub fn point(&self, s: f64) -> EquivalentPoint {
        let k = self.segment(s);
        let (a, b) = (self.s[k], self.s[k + 1]);
        let (f, df, d2f) = cubic_hermite(a, b, self.f[k], self.f[k + 1], self.df[k], self.df[k + 1], s);
        let h = |v: &[f64], d: &[f64]| hermite(a, b, v[k], v[k + 1], d[k], d[k + 1], s).0;
        let real = |c: usize| {
            hermite(
                a,
                b,
                self.real[k][c],
                self.real[k + 1][c],
                self.real_slopes[k][c],
                self.real_slopes[k + 1][c],
                s,
            )
            .0
        };
        EquivalentPoint {
            f,
            df,
            d2f,
            s_wheel: h(&self.s_wheel, &self.ds_wheel),
            s_rail: h(&self.s_rail, &self.ds_rail),
            contact_angle: real(0),
            rolling_radius: real(1),
            wheel_curvature: real(2),
            rail_curvature: real(3),
        }
    }

    /// Replaces the kink at each s_k of `fillets` (s_k, half-width a) by a fillet over
    /// [s_k − a, s_k + a]: the profile left of s_k − a and right of s_k + a is unchanged (the
    /// end nodes take the unfilleted curves' values and slopes there), in between the quintic that
    /// also matches both curves' curvatures (a C² join; stored as `TRANSITION_PIECES` cubic pieces) —
    /// its curvature peaks at ≈ 1.9 Δslope / 2a in the middle. (A single cubic, C¹, made f'' step
    /// from the tread's ~200 1/m to ~2·10⁴ 1/m at the flange-root fillet's ends: a step of the
    /// constraint's vertical acceleration f'' ẏ² of several g at each flange contact.) The
    /// real-contact maps (s^w, s^r, contact angle, rolling radius, curvatures) pass from one side's
    /// values to the other's over the same interval (Hermite with the end slopes).
    fn fillet(&mut self, fillets: &[(f64, f64)]) {
        if fillets.is_empty() {
            return;
        }
        let orig = self.clone();
        let at = |s: f64| {
            let k = orig.segment(s);
            let (a, b) = (orig.s[k], orig.s[k + 1]);
            let (f, df, _) = cubic_hermite(a, b, orig.f[k], orig.f[k + 1], orig.df[k], orig.df[k + 1], s);
            let h = |v: &[f64], d: &[f64]| hermite(a, b, v[k], v[k + 1], d[k], d[k + 1], s);
            let (sw, dsw) = h(&orig.s_wheel, &orig.ds_wheel);
            let (sr, dsr) = h(&orig.s_rail, &orig.ds_rail);
            let mut real = [0.0; N_REAL];
            let mut real_slopes = [0.0; N_REAL];
            for c in 0..N_REAL {
                (real[c], real_slopes[c]) = hermite(
                    a,
                    b,
                    orig.real[k][c],
                    orig.real[k + 1][c],
                    orig.real_slopes[k][c],
                    orig.real_slopes[k + 1][c],
                    s,
                );
            }
            let y = orig.y[k] + (orig.y[k + 1] - orig.y[k]) * (s - a) / (b - a);
            Node {
                s,
                f,
                df,
                sw,
                dsw,
                sr,
                dsr,
                y,
                real,
                real_slopes,
            }
        };
        let inside = |s: f64| {
            fillets
                .iter()
                .any(|&(c, a)| s > c - a - 1e-12 && s < c + a + 1e-12)
        };
        let mut nodes: Vec<Node> = (0..orig.s.len())
            .filter(|&k| !inside(orig.s[k]))
            .map(|k| orig.node(k))
            .collect();
        // Curvature of the unfilleted curve on the side of s away from the kink at c.
        let curvature = |s: f64, outward: f64| {
            let k = orig.segment(s + outward * 1e-12);
            let (a, b) = (orig.s[k], orig.s[k + 1]);
            cubic_hermite(a, b, orig.f[k], orig.f[k + 1], orig.df[k], orig.df[k + 1], s).2
        };
        for &(c, a) in fillets {
            let (n0, n1) = (at(c - a), at(c + a));
            let (c0, c1) = (curvature(c - a, -1.0), curvature(c + a, 1.0));
            // Interior nodes on the quintic (values, slopes, curvatures of both ends matched: the
            // fillet joins C², so a wheelset entering it meets no step in the constraint's
            // velocity terms f'' ẏ²); the real-contact maps as before, Hermite between the ends.
            for i in 1..TRANSITION_PIECES {
                let sq = n0.s + (n1.s - n0.s) * i as f64 / TRANSITION_PIECES as f64;
                let (f, df) = quintic(n0.s, n1.s, (n0.f, n0.df, c0), (n1.f, n1.df, c1), sq);
                let h = |v0: f64, v1: f64, d0: f64, d1: f64| hermite(n0.s, n1.s, v0, v1, d0, d1, sq);
                let (sw, dsw) = h(n0.sw, n1.sw, n0.dsw, n1.dsw);
                let (sr, dsr) = h(n0.sr, n1.sr, n0.dsr, n1.dsr);
                let mut real = [0.0; N_REAL];
                let mut real_slopes = [0.0; N_REAL];
                for k in 0..N_REAL {
                    (real[k], real_slopes[k]) =
                        h(n0.real[k], n1.real[k], n0.real_slopes[k], n1.real_slopes[k]);
                }
                nodes.push(Node {
                    s: sq,
                    f,
                    df,
                    sw,
                    dsw,
                    sr,
                    dsr,
                    y: n0.y + (n1.y - n0.y) * i as f64 / TRANSITION_PIECES as f64,
                    real,
                    real_slopes,
                });
            }
            nodes.push(n0);
            nodes.push(n1);
        }
        nodes.sort_by(|p, q| p.s.total_cmp(&q.s));
        *self = Self::from_nodes(self.side, &nodes);
    }

    fn kinks(&self) -> Vec<Kink> {
        (0..self.s.len() - 1)
            .filter(|&k| self.s[k + 1] == self.s[k])
            .map(|k| Kink {
                side: self.side,
                y: self.y[k],
                s_k: self.s[k],
                slope_before: self.df[k],
                slope_after: self.df[k + 1],
                s_wheel_before: self.s_wheel[k],
                s_wheel_after: self.s_wheel[k + 1],
                angle_before: self.real[k][0],
                angle_after: self.real[k + 1][0],
                real_jump: (self.s_wheel[k + 1] - self.s_wheel[k]).abs() > 1e-5
                    || (self.s_rail[k + 1] - self.s_rail[k]).abs() > 1e-5,
            })
            .collect()
    }
}

/// Independent coordinates of the KEC constraints: q = [y, y_lir, z_lir, y_rir, z_rir].
pub const N_Q: usize = 5;

/// A solved KEC configuration with everything the equations of motion need.
#[derive(Debug, Clone, PartialEq)]
pub struct KecSolution {
    /// Lateral displacement y, m.
    pub y: f64,
    /// Height of the wheelset centre z = z̃ + r0, m.
    pub z: f64,
    /// Roll φ, rad.
    pub phi: f64,
    /// Knife-edge contact parameters s^lk, s^rk, m.
    pub s_k: [f64; 2],
    /// x = [z̃, φ, s^lk, s^rk] derivatives with respect to q = [y, y_lir, z_lir, y_rir, z_rir].
    pub dx_dq: [[f64; N_Q]; 4],
    /// Second derivatives of z̃ and φ with respect to q (symmetric).
    pub d2z_dq2: [[f64; N_Q]; N_Q],
    pub d2phi_dq2: [[f64; N_Q]; N_Q],
    /// The real contact each knife-edge point stands for (left, right).
    pub real: [EquivalentPoint; 2],
    pub iterations: usize,
}

impl KecSolution {
    /// x = [z̃, φ, s^lk, s^rk] with z̃ = z − r0 (`r0` given).
    pub fn x(&self, r0: f64) -> [f64; 4] {
        [self.z - r0, self.phi, self.s_k[0], self.s_k[1]]
    }
    /// Rolling radius difference of the real contacts, m.
    pub fn delta_r(&self) -> f64 {
        self.real[0].rolling_radius - self.real[1].rolling_radius
    }
}

/// Newton settings of the KEC solve.
/// How far beyond its equivalent profile's end a knife edge may land by round-off, m.
const OFF_PROFILE_TOL_M: f64 = 1e-7;
const TOLERANCE: f64 = 1e-14;
const MAX_ITERATIONS: usize = 30;

/// The KEC contact model of a wheelset: both equivalent profiles.
#[derive(Debug, Clone)]
pub struct KecModel {
    pub left: EquivalentProfile,
    pub right: EquivalentProfile,
    /// Nominal rolling radius r0 and wheel lateral position L_w, m.
    pub r0: f64,
    pub l_w: f64,
    /// Where the real contact jumps (the equivalent profiles' kinks).
    pub kinks: Vec<Kink>,
}

impl KecModel {
    /// Builds the equivalent profiles from an ideal-track 1-entry table; `l_w` is the wheelset's
    /// L_w (taping line to wheelset centre), m.
    pub fn from_table(table: &LookupTable1, l_w: f64) -> Result<Self, KecError> {
        if table.gv != 0.0 {
            return Err(KecError::NotIdeal {
                gv_mm: table.gv * 1e3,
            });
        }
        let left = EquivalentProfile::build(Side::Left, table, l_w)?;
        let right = EquivalentProfile::build(Side::Right, table, l_w)?;
        let mut kinks = left.kinks();
        kinks.extend(right.kinks());
        kinks.sort_by(|a, b| a.y.total_cmp(&b.y));
        Ok(KecModel {
            left,
            right,
            r0: table.r0,
            l_w,
            kinks,
        })
    }

    /// Rounds every kink of the equivalent profiles over the lateral range in which, elastically,
    /// the wheel load passes from one real contact point to the other (two-point contact), instead
    /// of the rigid, instantaneous jump. **A departure from the paper**, whose equivalent profile
    /// keeps the kink: there the constraint's velocity terms jump as a wheelset crosses it, the
    /// equations of motion are discontinuous, and a wheelset whose equilibrium lies on the kink
    /// (a trailing wheelset in a curve at the flange-root jump) chatters across it in µs steps.
    ///
    /// Width: with elastic approach δ (the Hertz approach of the wheel load, some 0.05 mm), the
    /// second point takes the load over |Δy| ≈ δ / |Δ tan γ|, and the equivalent profile's slope at a
    /// kink is the real tan γ on either side; so each kink of a real jump is replaced by a fillet of
    /// width w = δ / |Δ slope| in s^k (≈ y) — a few hundredths of a mm at the flange (Δ slope ≈ 2),
    /// some tenths on the tread — and the other side's kink at the same y (through the roll) by a
    /// fillet of the same width. The width is limited to [`TWO_POINT_MAX_WIDTH_M`] (and each
    /// half-width to 0.45 of the distance to the next kink or the profile's end): a wider fillet
    /// at the jumps near the centre changes the small-amplitude rolling-radius difference, i.e. the
    /// equivalent conicity and the critical speed (measured on the critical-speed scene: hunting
    /// onset 29.0 m/s rigid and with widths up to 0.055 mm; none up to 68 m/s with 0.28 mm). Outside the fillets the profiles are unchanged, so the
    /// table rows there are still reproduced exactly; inside, the real contact point, angle and
    /// rolling radius pass from one side's values to the other's (a single resultant standing for
    /// the two loaded points). `approach_m` = 0 keeps the paper's kinks.
    pub fn with_two_point_transition(self, approach_m: f64) -> Self {
        self.with_two_point_transition_capped(approach_m, TWO_POINT_MAX_WIDTH_M)
    }

    /// [`KecModel::with_two_point_transition`] with the fillets' widths limited to `max_width_m`
    /// instead of [`TWO_POINT_MAX_WIDTH_M`] — for pairs without contact jumps near the centre
    /// (whose small-amplitude conicity a wide fillet would change), where the flange-root jump
    /// can take the width that the track's lateral elasticity gives the load transfer (rail-head
    /// deflections of tenths of a millimetre under flange forces), which the rigid rails of the
    /// constraint model do not have.
    pub fn with_two_point_transition_capped(mut self, approach_m: f64, max_width_m: f64) -> Self {
        if approach_m <= 0.0 || self.kinks.is_empty() {
            return self;
        }
        // Half-width per jump y, from the jumping side's slope change.
        let mut half: Vec<(f64, f64)> = Vec::new();
        for k in self.kinks.iter().filter(|k| k.real_jump) {
            let dm = (k.slope_after - k.slope_before).abs().max(1e-6);
            let a = (0.5 * approach_m / dm).min(0.5 * max_width_m);
            match half.iter_mut().find(|(y, _)| (y - k.y).abs() < 1e-9) {
                Some(h) => h.1 = h.1.min(a),
                None => half.push((k.y, a)),
            }
        }
        for side in Side::BOTH {
            let profile = match side {
                Side::Left => &mut self.left,
                Side::Right => &mut self.right,
            };
            let (lo, hi) = profile.domain();
            let centres: Vec<(f64, f64)> = self
                .kinks
                .iter()
                .filter(|k| k.side == side)
                .filter_map(|k| {
                    half.iter()
                        .find(|(y, _)| (y - k.y).abs() < 1e-9)
                        .map(|h| (k.s_k, h.1))
                })
                .collect();
            let at: Vec<f64> = centres.iter().map(|c| c.0).collect();
            let fillets: Vec<(f64, f64)> = centres
                .iter()
                .map(|&(c, a)| (c, a.min(transition_room(c, &at, lo, hi))))
                .filter(|&(_, a)| a > 1e-9)
                .collect();
            profile.fillet(&fillets);
        }
        self
    }

    /// Writes the equivalent profiles as CSV, one row per table row (a jump is two rows with the
    /// same y): `y_mm, s_lk_mm, f_lk_mm, s_rk_mm, f_rk_mm, s_wheel_left_mm, s_rail_left_mm,
    /// s_wheel_right_mm, s_rail_right_mm`.
    pub fn write_csv(&self, path: &std::path::Path) -> std::io::Result<()> {
        let model = self;
        let mut w = crate::files::csv_writer(path)?;
        w.write_record([
            "y_mm",
            "s_lk_mm",
            "f_lk_mm",
            "s_rk_mm",
            "f_rk_mm",
            "s_wheel_left_mm",
            "s_rail_left_mm",
            "s_wheel_right_mm",
            "s_rail_right_mm",
        ])?;
        // Per node: [y, s^k, f^k, s^w, s^r]; both profiles hold the table's rows in reverse order
        // (s^k decreases with y).
        let collect = |side| -> Vec<[f64; 5]> {
            let p = model.profile(side);
            p.node_y()
                .iter()
                .zip(p.nodes())
                .zip(p.node_real())
                .map(|((&y, (s, f)), (sw, sr))| [y, s, f, sw, sr])
                .collect()
        };
        let (l, r) = (collect(Side::Left), collect(Side::Right));
        for (a, b) in l.iter().rev().zip(r.iter().rev()) {
            let cells =
                [a[0], a[1], a[2], b[1], b[2], a[3], a[4], b[3], b[4]].map(|v| format!("{:.9}", v * 1e3));
            w.write_record(&cells)?;
        }
        crate::files::commit_csv(w)
    }

    /// The equivalent profile of a side.
    pub fn profile(&self, side: Side) -> &EquivalentProfile {
        match side {
            Side::Left => &self.left,
            Side::Right => &self.right,
        }
    }

    /// Eq. (51): s^lk = s^rk = −y, φ = 0, z̃ = (f^lk(−y) + f^rk(−y))/2.
    pub fn guess(&self, y: f64) -> [f64; 4] {
        [0.5 * (self.left.eval(-y).0 + self.right.eval(-y).0), 0.0, -y, -y]
    }

    /// Residual of Eq. (49)–(50) and its Jacobian with respect to x = [z̃, φ, s^lk, s^rk].
    pub fn residual(&self, q: &[f64; N_Q], x: &[f64; 4]) -> (Vector4<f64>, Matrix4<f64>) {
        let (zt, phi, sl, sr) = (x[0], x[1], x[2], x[3]);
        let (fl, dfl, _) = self.left.eval(sl);
        let (fr, dfr, _) = self.right.eval(sr);
        let (r0, lw) = (self.r0, self.l_w);
        let f = Vector4::new(
            q[0] + sl + phi * (r0 + fl) - q[1],
            zt + phi * (lw + sl) - fl - q[2],
            q[0] + sr + phi * (r0 + fr) - q[3],
            zt + phi * (-lw + sr) - fr - q[4],
        );
        #[rustfmt::skip]
        let j = Matrix4::new(
            0.0, r0 + fl,  1.0 + phi * dfl, 0.0,
            1.0, lw + sl,  phi - dfl,       0.0,
            0.0, r0 + fr,  0.0,             1.0 + phi * dfr,
            1.0, -lw + sr, 0.0,             phi - dfr,
        );
        (f, j)
    }

    /// Solves the KEC constraints at lateral displacement `y` with rail irregularities
    /// (y_lir, z_lir, y_rir, z_rir) from `start` (a previous x, or `None` for Eq. 51).
    ///
    /// Near a kink (a real contact jump, typically at flange contact) Newton from the Eq. (51)
    /// guess can fail, and near the end of the profiles on displaced rails that guess (s^k = −y,
    /// blind to the rails) can lie off them; the solve then restarts from
    /// [`KecModel::table_guess`], which places each knife edge from its own rail's offset.
    pub fn solve(&self, y: f64, rails: [f64; 4], start: Option<[f64; 4]>) -> Result<KecSolution, KecError> {
        let q = [y, rails[0], rails[1], rails[2], rails[3]];
        match self.newton(y, &q, start.unwrap_or_else(|| self.guess(y))) {
            Err(KecError::NoConvergence { .. } | KecError::OffProfile { .. }) => {
                let guess = self.table_guess(y, rails);
                match self.newton(y, &q, guess) {
                    // Beyond the table's flange contact on a side (its lateral distance to its
                    // rail outside the profile's table rows), Newton has nothing to converge
                    // to: say so.
                    Err(e @ KecError::NoConvergence { .. }) => {
                        for (side, rail_y, s) in [
                            (Side::Left, rails[0], guess[2]),
                            (Side::Right, rails[2], guess[3]),
                        ] {
                            let p = self.profile(side);
                            let ys = p.node_y();
                            let (lo_y, hi_y) =
                                ys.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                                    (a.min(v), b.max(v))
                                });
                            if y - rail_y < lo_y || y - rail_y > hi_y {
                                return Err(self.off_profile(y, side, s));
                            }
                        }
                        Err(e)
                    }
                    other => other,
                }
            }
            other => other,
        }
    }

    /// A start close to the solution: each side's s^k from the node where the table had the same
    /// lateral distance to that side's rail (y − y_ir), then z̃ and φ from the two vertical
    /// equations (F2, F4), which are linear in them.
    pub fn table_guess(&self, y: f64, rails: [f64; 4]) -> [f64; 4] {
        let s_at = |p: &EquivalentProfile, y: f64| {
            // node_y decreases along the nodes (s^k increases).
            let ys = p.node_y();
            let k = ys.partition_point(|&v| v > y).clamp(1, ys.len() - 1);
            let (y0, y1) = (ys[k - 1], ys[k]);
            let t = if y1 != y0 {
                ((y - y0) / (y1 - y0)).clamp(0.0, 1.0)
            } else {
                0.0
            };
            p.s[k - 1] + t * (p.s[k] - p.s[k - 1])
        };
        let (sl, sr) = (s_at(&self.left, y - rails[0]), s_at(&self.right, y - rails[2]));
        let (fl, fr) = (self.left.eval(sl).0 + rails[1], self.right.eval(sr).0 + rails[3]);
        // z̃ + φ(L_w + s_l) = f_l + z_lir,  z̃ + φ(−L_w + s_r) = f_r + z_rir.
        let phi = (fl - fr) / ((self.l_w + sl) - (-self.l_w + sr));
        [fl - phi * (self.l_w + sl), phi, sl, sr]
    }

    fn newton(&self, y: f64, q: &[f64; N_Q], x0: [f64; 4]) -> Result<KecSolution, KecError> {
        let q = *q;
        let mut x = x0;
        let mut last = f64::INFINITY;
        let (mut f, mut j) = self.residual(&q, &x);
        for it in 1..=MAX_ITERATIONS {
            let dx = j.lu().solve(&(-f)).ok_or(KecError::NoConvergence {
                y_mm: y * 1e3,
                iterations: it,
                last_step: last,
            })?;
            // Backtracking on |F|: near a kink of an equivalent profile (a real contact jump) the
            // full Newton step can cycle across it.
            let norm = f.norm();
            let mut alpha = 1.0;
            let (mut xn, mut fn_, mut jn);
            loop {
                xn = x;
                for k in 0..4 {
                    xn[k] += alpha * dx[k];
                }
                (fn_, jn) = self.residual(&q, &xn);
                if fn_.norm() < (1.0 - 1e-4 * alpha) * norm || alpha < 1e-6 || norm < 1e-15 {
                    break;
                }
                alpha *= 0.5;
            }
            x = xn;
            f = fn_;
            j = jn;
            last = alpha * dx.amax();
            if !last.is_finite() {
                break;
            }
            if last < TOLERANCE || (last < 1e-11 && f.amax() < 1e-15) {
                return self.finish(y, x, &j, it);
            }
        }
        Err(KecError::NoConvergence {
            y_mm: y * 1e3,
            iterations: MAX_ITERATIONS,
            last_step: last,
        })
    }

    /// The knife edge of `side` at s^k = `s` is off its equivalent profile at `y`.
    fn off_profile(&self, y: f64, side: Side, s: f64) -> KecError {
        let (lo, hi) = self.profile(side).domain();
        KecError::OffProfile {
            y_mm: y * 1e3,
            side: side.name(),
            s_mm: s * 1e3,
            lo_mm: lo * 1e3,
            hi_mm: hi * 1e3,
        }
    }

    /// The solution at x (`j` the Jacobian there) with its first and second derivatives in q.
    fn finish(
        &self,
        y: f64,
        x: [f64; 4],
        j: &Matrix4<f64>,
        iterations: usize,
    ) -> Result<KecSolution, KecError> {
        for (side, s) in [(Side::Left, x[2]), (Side::Right, x[3])] {
            let (lo, hi) = self.profile(side).domain();
            // At the table's last row the knife edge is at the profile's end: Newton's round-off
            // may put it a hair outside (1e-7 m of s^k is ~1e-9 of the profile's slope change).
            if s < lo - OFF_PROFILE_TOL_M || s > hi + OFF_PROFILE_TOL_M {
                return Err(self.off_profile(y, side, s));
            }
        }
        // J⁻¹ once (4×4, by cofactors): the 5 first and 15 second derivatives below are products
        // with it.
        let singular = || KecError::NoConvergence {
            y_mm: y * 1e3,
            iterations,
            last_step: f64::NAN,
        };
        let inv = j.try_inverse().ok_or_else(singular)?;
        if !inv.iter().all(|v| v.is_finite()) {
            return Err(singular());
        }
        // ∂F/∂q: F1 = y … − y_lir, F2 = … − z_lir, F3 = y … − y_rir, F4 = … − z_rir.
        #[rustfmt::skip]
        let dfdq: [[f64; 4]; N_Q] = [
            [1.0, 0.0, 1.0, 0.0],
            [-1.0, 0.0, 0.0, 0.0],
            [0.0, -1.0, 0.0, 0.0],
            [0.0, 0.0, -1.0, 0.0],
            [0.0, 0.0, 0.0, -1.0],
        ];
        let mut dx = [[0.0; N_Q]; 4];
        for (a, col) in dfdq.iter().enumerate() {
            let v = -(inv * Vector4::from(*col));
            for r in 0..4 {
                dx[r][a] = v[r];
            }
        }
        // Second derivatives: J d²x = −F_xx[dx_a, dx_b] (q enters F linearly).
        let (phi, sl, sr) = (x[1], x[2], x[3]);
        let (_, dfl, d2fl) = self.left.eval(sl);
        let (_, dfr, d2fr) = self.right.eval(sr);
        let mut d2z = [[0.0; N_Q]; N_Q];
        let mut d2phi = [[0.0; N_Q]; N_Q];
        for a in 0..N_Q {
            for b in a..N_Q {
                let (pa, pb) = (dx[1][a], dx[1][b]);
                let (la, lb) = (dx[2][a], dx[2][b]);
                let (ra, rb) = (dx[3][a], dx[3][b]);
                let fxx = Vector4::new(
                    dfl * (pa * lb + la * pb) + phi * d2fl * la * lb,
                    (pa * lb + la * pb) - d2fl * la * lb,
                    dfr * (pa * rb + ra * pb) + phi * d2fr * ra * rb,
                    (pa * rb + ra * pb) - d2fr * ra * rb,
                );
                // Rows 0 and 1 of −J⁻¹ F_xx: z̃ and φ.
                let (vz, vphi) = (
                    -inv.row(0).dot(&fxx.transpose()),
                    -inv.row(1).dot(&fxx.transpose()),
                );
                d2z[a][b] = vz;
                d2z[b][a] = vz;
                d2phi[a][b] = vphi;
                d2phi[b][a] = vphi;
            }
        }
        Ok(KecSolution {
            y,
            z: x[0] + self.r0,
            phi: x[1],
            s_k: [x[2], x[3]],
            dx_dq: dx,
            d2z_dq2: d2z,
            d2phi_dq2: d2phi,
            real: [self.left.point(x[2]), self.right.point(x[3])],
            iterations,
        })
    }
}

/// The table rows the model was built from are reproduced: (max |Δz|, max |Δφ|) over `rows`.
pub fn reproduction_error(model: &KecModel, rows: &[TableRow]) -> Result<(f64, f64), KecError> {
    let (mut ez, mut ep) = (0.0f64, 0.0f64);
    for r in rows {
        let s = model.solve(r.y, [0.0; 4], None)?;
        ez = ez.max((s.z - r.z()).abs());
        ep = ep.max((s.phi - r.phi()).abs());
    }
    Ok((ez, ep))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::geometry::ContactGeometry;
    use crate::contact::lookup::TableSettings;
    use crate::profile::placement::WheelRailPair;
    use crate::profile::StandardProfile;
    use crate::track::RailOffsets;

    /// Every jump of the table (two rows at one y) is a kink of both equivalent profiles — on
    /// both pairs, both sides, mirrored — and away from the kinks (20 µm: right before a jump the
    /// real contact races along the wheel, a genuine fold of the rigid geometry) the profiles'
    /// curvature stays that of real profiles. The MS vehicle's left flange-root jump was two
    /// nodes 40 nm apart instead: f'' ~ 10⁸ 1/m there, the constraint's velocity terms 10⁶ m/s²,
    /// a wheel "flying" off at tight tolerances.
    #[test]
    fn every_table_jump_is_a_kink_of_both_profiles() {
        for (rail, incl) in [
            (StandardProfile::Rail60E1, "1:40"),
            (StandardProfile::Rail54E1, "1:20"),
        ] {
            let pair = WheelRailPair::standard(StandardProfile::S1002, rail, incl).unwrap();
            let l_w = pair.wheelset.l_w();
            let geom = ContactGeometry::with_defaults(pair);
            let table = LookupTable1::build(&geom, &TableSettings::default()).unwrap();
            let model = KecModel::from_table(&table, l_w).unwrap();
            let jumps: Vec<f64> = table
                .rows
                .windows(2)
                .filter(|w| w[0].y == w[1].y)
                .map(|w| w[0].y)
                .collect();
            assert_eq!(model.kinks.len(), 2 * jumps.len(), "{incl}: jumps {jumps:?}");
            for j in &jumps {
                for side in Side::BOTH {
                    assert!(
                        model.kinks.iter().any(|k| k.side == side && k.y == *j),
                        "{incl}: no {side:?} kink at the jump y = {j}"
                    );
                }
                assert!(
                    jumps.iter().any(|m| (m + j).abs() < 1e-6),
                    "{incl}: jump {j} not mirrored"
                );
            }
            for p in [&model.left, &model.right] {
                let (lo, hi) = p.domain();
                let n = 200_000;
                let (worst, at) = (0..=n)
                    .map(|i| lo + (hi - lo) * i as f64 / n as f64)
                    .filter(|s| {
                        model
                            .kinks
                            .iter()
                            .all(|k| k.side != p.side || (s - k.s_k).abs() > 2e-5)
                    })
                    .map(|s| (p.eval(s).2.abs(), s))
                    .fold((0.0, 0.0), |a, b| if b.0 > a.0 { b } else { a });
                println!(
                    "  at s = {:.6} mm (domain {:.4}..{:.4})",
                    at * 1e3,
                    lo * 1e3,
                    hi * 1e3
                );
                println!(
                    "{incl} {:?}: {} kinks, max |f''| {worst:.3e} 1/m",
                    p.side,
                    model.kinks.len()
                );
                assert!(worst < 1e5, "{incl} {:?}: |f''| {worst}", p.side);
            }
        }
    }

    fn setup() -> (ContactGeometry, LookupTable1, KecModel) {
        let pair =
            WheelRailPair::standard(StandardProfile::S1002, StandardProfile::Rail60E1, "1:40").unwrap();
        let l_w = pair.wheelset.l_w();
        let geom = ContactGeometry::with_defaults(pair);
        let table = LookupTable1::build(&geom, &TableSettings::default()).unwrap();
        let model = KecModel::from_table(&table, l_w).unwrap();
        (geom, table, model)
    }

    /// The KEC solve at every row of its own table, to the last (the flange's largest contact
    /// angle), on the MS vehicle's pair (S1002, 54E1 at 1:20, r0 = 295 mm): `kecsim kec` on it
    /// failed at the last row, its knife edge a hair beyond the profile's end by round-off.
    #[test]
    fn solves_at_every_row_of_its_table_to_the_last() {
        let pair = WheelRailPair::new(
            StandardProfile::S1002.profile(),
            StandardProfile::Rail54E1.profile(),
            "1:20".parse().unwrap(),
            crate::track::TrackGauge::default(),
            crate::profile::placement::WheelsetGeometry {
                nominal_radius_m: 0.295,
                ..Default::default()
            },
        )
        .unwrap();
        let l_w = pair.wheelset.l_w();
        let geom = ContactGeometry::with_defaults(pair);
        let table = LookupTable1::build(&geom, &TableSettings::default()).unwrap();
        let model = KecModel::from_table(&table, l_w).unwrap();
        for r in &table.rows {
            model
                .solve(r.y, [0.0; 4], None)
                .unwrap_or_else(|e| panic!("y = {:.4} mm: {e}", r.y * 1e3));
        }
        let (lo, hi) = table.range();
        assert!(
            model.solve(hi + 1e-4, [0.0; 4], None).is_err()
                && model.solve(lo - 1e-4, [0.0; 4], None).is_err()
        );
    }

    #[test]
    fn reproduces_the_table_at_its_nodes_and_stays_continuous_at_jumps() {
        let (_, table, model) = setup();
        let (ez, ep) = reproduction_error(&model, &table.rows).unwrap();
        assert!(ez < 1e-9 && ep < 1e-9, "z {ez:e} phi {ep:e}");
        // Every jump of the table is a kink of the jumping side's equivalent profile (and, through
        // the roll, of the other side's), where the profile stays continuous.
        assert_eq!(
            model.kinks.iter().filter(|k| k.real_jump).count(),
            table.jumps.len(),
            "{:?}",
            model.kinks
        );
        assert!(table.jumps.len() >= 4);
        for k in &model.kinks {
            let p = model.profile(k.side);
            let (a, b) = (p.eval(k.s_k - 1e-12).0, p.eval(k.s_k + 1e-12).0);
            // 2e-12 apart on slopes of up to ~3: continuous to round-off.
            assert!(
                (a - b).abs() < 2e-11,
                "continuous at the kink: {:.3e} {k:?}",
                a - b
            );
        }
    }

    #[test]
    fn first_and_second_derivatives_match_finite_differences() {
        let (_, _, model) = setup();
        let base = [0.0021, 0.0004, -0.0003, -0.0002, 0.0005];
        let solve = |q: [f64; 5]| model.solve(q[0], [q[1], q[2], q[3], q[4]], None).unwrap();
        let s0 = solve(base);
        let h = 1e-6;
        for a in 0..N_Q {
            let mut qp = base;
            qp[a] += h;
            let mut qm = base;
            qm[a] -= h;
            let (sp, sm) = (solve(qp), solve(qm));
            let fd_z = (sp.z - sm.z) / (2.0 * h);
            let fd_phi = (sp.phi - sm.phi) / (2.0 * h);
            assert!(
                (fd_z - s0.dx_dq[0][a]).abs() < 1e-6,
                "dz/dq{a}: {} vs {fd_z}",
                s0.dx_dq[0][a]
            );
            assert!((fd_phi - s0.dx_dq[1][a]).abs() < 1e-6, "dphi/dq{a}");
            for b in 0..N_Q {
                let fd2 = (sp.dx_dq[0][b] - sm.dx_dq[0][b]) / (2.0 * h);
                assert!(
                    (fd2 - s0.d2z_dq2[a][b]).abs() < 1e-3 * (1.0 + fd2.abs()),
                    "d2z/dq{a}dq{b}: {} vs {fd2}",
                    s0.d2z_dq2[a][b]
                );
                let fd2 = (sp.dx_dq[1][b] - sm.dx_dq[1][b]) / (2.0 * h);
                assert!(
                    (fd2 - s0.d2phi_dq2[a][b]).abs() < 1e-3 * (1.0 + fd2.abs()),
                    "d2phi/dq{a}dq{b}"
                );
            }
        }
    }

    #[test]
    fn between_nodes_within_the_interpolation_error_of_the_online_solution() {
        let (geom, table, model) = setup();
        let (mut ez, mut ep) = (0.0f64, 0.0f64);
        for w in table.rows.windows(2) {
            if w[1].y <= w[0].y {
                continue;
            }
            let y = w[0].y + 0.37 * (w[1].y - w[0].y);
            let k = model.solve(y, [0.0; 4], None).unwrap();
            let o = geom.solve(y, &RailOffsets::default()).unwrap();
            ez = ez.max((k.z - o.z).abs());
            ep = ep.max((k.phi - o.phi).abs());
        }
        assert!(ez < 1e-7 && ep < 1e-7, "z {ez:e} phi {ep:e}");
    }

    #[test]
    fn real_normals_match_the_online_contact() {
        let (geom, _, model) = setup();
        for y in [-0.006, -0.002, 0.0, 0.0031, 0.0062] {
            let k = model.solve(y, [0.0; 4], None).unwrap();
            let o = geom.solve(y, &RailOffsets::default()).unwrap();
            for (i, side) in Side::BOTH.into_iter().enumerate() {
                let (a, b) = (k.real[i].normal(side), o.point(side).normal);
                assert!(
                    (a.0 - b.0).abs() < 1e-3 && (a.1 - b.1).abs() < 1e-3,
                    "{side:?} at {y}: {a:?} vs {b:?}"
                );
                assert!((k.real[i].rolling_radius - o.point(side).rolling_radius).abs() < 1e-6);
            }
        }
    }

    /// The two-point transition: each kink becomes a fillet of width δ/|Δslope| (the same width
    /// on the other side's kink at that y), C¹ across, tangent to both slopes; the profile is
    /// untouched outside the fillets (table rows there still reproduced); the real contact passes
    /// continuously from one point to the other; δ = 0 keeps the rigid kinks.
    #[test]
    fn two_point_transition_rounds_each_kink_over_its_elastic_width() {
        let (_, table, rigid) = setup();
        let same = rigid.clone().with_two_point_transition(0.0);
        assert_eq!(same.left.s, rigid.left.s);
        // The default cap, and a wider one (the width then set by the approach).
        for (approach, cap) in [(5e-5, TWO_POINT_MAX_WIDTH_M), (4e-4, 4e-4)] {
            check_fillets(&table, &rigid, approach, cap);
        }
    }

    fn check_fillets(table: &LookupTable1, rigid: &KecModel, approach: f64, cap: f64) {
        let smooth = rigid.clone().with_two_point_transition_capped(approach, cap);
        for k in rigid.kinks.iter().filter(|k| k.real_jump) {
            let dm = (k.slope_after - k.slope_before).abs();
            let a = (0.5 * approach / dm).min(0.5 * cap);
            for side in Side::BOTH {
                let Some(kink) = rigid
                    .kinks
                    .iter()
                    .find(|o| o.side == side && (o.y - k.y).abs() < 1e-9)
                else {
                    continue;
                };
                let (p, r) = (smooth.profile(side), rigid.profile(side));
                let c = kink.s_k;
                // The fillet's ends: the rigid profile's values and slopes.
                // Limited to 0.45 of the distance to the side's next kink.
                let room = rigid
                    .kinks
                    .iter()
                    .filter(|o| o.side == side && o.s_k != c)
                    .map(|o| (o.s_k - c).abs())
                    .fold(f64::INFINITY, f64::min);
                let a = a.min(0.45 * room);
                for s in [c - a, c + a] {
                    let (f, df, _) = p.eval(s);
                    let (g, dg, _) = r.eval(s + if s < c { -1e-13 } else { 1e-13 });
                    assert!(
                        (f - g).abs() < 1e-12 && (df - dg).abs() < 1e-6,
                        "{side:?} y {} end {s}: f {f} vs {g}, f' {df} vs {dg}",
                        k.y
                    );
                }
                // Inside: C¹, the slope passing monotonically from one side's to the other's.
                let n = 200;
                let mut prev = p.eval(c - a);
                for i in 1..=n {
                    let s = c - a + 2.0 * a * i as f64 / n as f64;
                    let cur = p.eval(s);
                    let ds = 2.0 * a / n as f64;
                    assert!(
                        (cur.0 - prev.0 - 0.5 * (cur.1 + prev.1) * ds).abs()
                            < 1e-3 * ds * dm.max(1e-3) + 1e-15,
                        "f' is the slope of f: {side:?} y {} s {s} a {a} {prev:?} {cur:?}",
                        k.y
                    );
                    assert!(
                        (cur.1 - prev.1) * (kink.slope_after - kink.slope_before) >= -1e-9,
                        "{side:?} y {}: slope not monotone in the fillet",
                        k.y
                    );
                    prev = cur;
                }
                if kink.real_jump {
                    // f'' ≈ 1.875 Δslope / 2a in the middle (the quintic between two nearly
                    // straight curves: the slope a smootherstep, whose peak rate is 30/16).
                    let (_, _, d2) = p.eval(c);
                    let expect = 1.875 * (kink.slope_after - kink.slope_before) / (2.0 * a);
                    assert!((d2 - expect).abs() < 0.3 * expect.abs(), "f'' {d2} vs {expect}");
                    // C² at the ends: the curvature continues the rigid curve's (a cubic fillet
                    // stepped it by ~Δslope / a there).
                    for (s, out) in [(c - a, -1e-9), (c + a, 1e-9)] {
                        let inside = p.eval(s - out).2;
                        let outside = r.eval(s + out).2;
                        assert!(
                            (inside - outside).abs() < 0.02 * (expect.abs() + outside.abs()),
                            "{side:?} y {} end {s}: f'' {inside} inside vs {outside} outside",
                            k.y
                        );
                    }
                    // The real contact passes continuously.
                    let (w0, w1) = (p.point(c - a).s_wheel, p.point(c + a).s_wheel);
                    let (r0, r1) = (r.point(c - a - 1e-13).s_wheel, r.point(c + a + 1e-13).s_wheel);
                    assert!(
                        (w0 - r0).abs() < 1e-9 && (w1 - r1).abs() < 1e-9,
                        "{w0} {r0} {w1} {r1}"
                    );
                    assert!((w1 - w0).abs() > 0.5 * (kink.s_wheel_after - kink.s_wheel_before).abs());
                    let mid = p.point(c).s_wheel;
                    assert!((mid - w0) * (w1 - mid) > 0.0, "s^w {w0} {mid} {w1}");
                }
            }
        }
        // Outside the fillets nothing changed: the table rows far from any jump are reproduced.
        let far: Vec<TableRow> = table
            .rows
            .iter()
            .filter(|r| rigid.kinks.iter().all(|k| (r.y - k.y).abs() > 1e-3))
            .cloned()
            .collect();
        assert!(far.len() > 20);
        let (ez, ep) = reproduction_error(&smooth, &far).unwrap();
        assert!(ez < 1e-9 && ep < 1e-9, "z {ez:e} phi {ep:e}");
        // And the smoothed model solves across every former kink without a jump in dz/dy: over
        // ±1 nm the rigid model's dz/dy still jumps by the whole kink, the smoothed one's barely moves.
        for k in rigid.kinks.iter().filter(|k| k.real_jump) {
            let jump = |m: &KecModel| {
                let d = |y: f64| m.solve(y, [0.0; 4], None).unwrap().dx_dq[0][0];
                (d(k.y + 1e-9) - d(k.y - 1e-9)).abs()
            };
            let (r, sm) = (jump(rigid), jump(&smooth));
            assert!(
                r > 1e-3 && sm < 0.01 * r,
                "dz/dy at y {}: rigid jump {r}, smoothed {sm}",
                k.y
            );
        }
    }

    #[test]
    fn out_of_the_table_is_an_error() {
        let (_, table, model) = setup();
        let (_, hi) = table.range();
        let e = model.solve(hi + 0.003, [0.0; 4], None).unwrap_err();
        assert!(
            matches!(e, KecError::OffProfile { .. } | KecError::NoConvergence { .. }),
            "{e}"
        );
    }
}
