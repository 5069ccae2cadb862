//! Track irregularities (paper §2.3, METHOD.md §2): alignment, vertical profile, gauge variation
//! and cross level as C² functions of s with first and second derivatives, generated from a PSD
//! or read from a measured file ([`super::measured`]), and the rail displacements and rail-frame
//! placement they imply.
//!
//! **Representation.** Values and first and second derivatives of the four irregularities at
//! nodes s_k; between nodes a quintic Hermite interpolant matching all three at both ends: C² in
//! s, so the dynamics gets continuous velocities and accelerations V d/ds, V² d²/ds² of the
//! irregularities. Generated irregularities give exact node derivatives (error O(h⁶) in value,
//! O(h⁴) in the second derivative); a measured file gives node values only, and a not-a-knot cubic
//! spline supplies the derivatives (the quintic then reproduces that cubic exactly). Lookup is
//! O(1) on a uniform grid and a binary search otherwise.
//!
//! **Generation: sum of cosines**, one independent random-phase series per irregularity:
//! ```text
//! x(s) = Σ_k √(2 S(Ω_k) ΔΩ) cos(Ω_k s + φ_k),   Ω_k = Ω_min + (k − ½) ΔΩ,  φ_k ~ U[0, 2π)
//! ```
//! Chosen over the inverse FFT because the band [2π/λ_max, 2π/λ_min] is honoured exactly for any
//! limits and track length, the variance of every band is the PSD integral by construction, the
//! derivatives are analytic (the node derivatives are exact), it needs no FFT dependency, and the
//! cost (cosines × nodes, evaluated by phasor rotation) is paid once per run. The cosines are
//! spaced ΔΩ ≤ π/L so the signal's period 2π/ΔΩ is at least twice the track length L (no
//! repetition along the track). Phases come from SplitMix64 seeded by (seed, channel): the same
//! seed gives the same track on every machine.

use super::error::TrackError;
use super::psd::{Channel, Psd};
use super::rails::{RailMotion, RailOffsets};

/// Value, first and second s-derivative of the four irregularities at one s, SI (m, m/m, 1/m),
/// in the order al, vp, gv, cl.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct IrregularityState {
    pub value: [f64; 4],
    pub d1: [f64; 4],
    pub d2: [f64; 4],
}

/// Placement of one rail-profile frame in the track cross-section (METHOD.md §2, Eq. 6–7):
/// origin [0, y, z] in the track frame, rotated about X by `angle_rad`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RailFrame {
    pub y_m: f64,
    pub z_m: f64,
    pub angle_rad: f64,
}

impl IrregularityState {
    pub fn al(&self) -> f64 {
        self.value[0]
    }
    pub fn vp(&self) -> f64 {
        self.value[1]
    }
    pub fn gv(&self) -> f64 {
        self.value[2]
    }
    pub fn cl(&self) -> f64 {
        self.value[3]
    }

    /// Rail displacements [y_lir, z_lir, y_rir, z_rir] (the contact code's [`RailOffsets`], built
    /// by its own conversion so both agree by construction).
    pub fn rail_offsets(&self) -> RailOffsets {
        let v = self.value;
        RailOffsets::from_irregularities(v[0], v[1], v[2], v[3])
    }

    /// Time derivatives seen by a point moving at speed `v` with acceleration `v_dot`:
    /// ẋ = x' V, ẍ = x'' V² + x' V̇ (per irregularity).
    pub fn time_derivatives(&self, v: f64, v_dot: f64) -> ([f64; 4], [f64; 4]) {
        let mut dt = [0.0; 4];
        let mut dtt = [0.0; 4];
        for c in 0..4 {
            dt[c] = self.d1[c] * v;
            dtt[c] = self.d2[c] * v * v + self.d1[c] * v_dot;
        }
        (dt, dtt)
    }

    /// The rail displacements q_r = [y_lir, z_lir, y_rir, z_rir] and their time derivatives seen by
    /// a wheelset moving at speed `v` with acceleration `v_dot` (Eq. 5–11 with
    /// [`Self::time_derivatives`]).
    pub fn rail_motion(&self, v: f64, v_dot: f64) -> RailMotion {
        let (dt, dtt) = self.time_derivatives(v, v_dot);
        let rails = |c: [f64; 4]| RailOffsets::from_irregularities(c[0], c[1], c[2], c[3]).to_array();
        RailMotion {
            q: self.rail_offsets().to_array(),
            q_dot: rails(dt),
            q_ddot: rails(dtt),
        }
    }

    /// The rail-profile frames (METHOD.md §2, Eq. 6–7): origins [0, ±L_r, 0] plus the rail
    /// displacement, rotated about X by +β + δ (left) and −β + δ (right), with β the rail
    /// inclination and δ = (z_lir − z_rir)/(2 L_r) (Eq. 7's linearised roll).
    pub fn rail_frames(&self, l_r: f64, beta: f64) -> (RailFrame, RailFrame) {
        let o = self.rail_offsets();
        let delta = o.delta(l_r);
        (
            RailFrame {
                y_m: l_r + o.y_left,
                z_m: o.z_left,
                angle_rad: beta + delta,
            },
            RailFrame {
                y_m: -l_r + o.y_right,
                z_m: o.z_right,
                angle_rad: -beta + delta,
            },
        )
    }
}

/// How a set of irregularities came about (for summaries).
#[derive(Debug, Clone, PartialEq)]
pub enum Origin {
    Generated(Generation),
    Measured { path: String },
}

/// The settings of a generated set.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Generation {
    pub psd: Psd,
    pub seed: u64,
    pub wavelength_min_m: f64,
    pub wavelength_max_m: f64,
    /// Number of cosines per irregularity; `None`: the smallest with ΔΩ ≤ π/L, at least 500.
    pub cosines: Option<usize>,
    /// Node spacing of the interpolant; `None`: λ_min/10.
    pub step_m: Option<f64>,
}

impl Generation {
    pub fn new(psd: Psd, seed: u64) -> Self {
        let (a, b) = psd.default_band_m();
        Generation {
            psd,
            seed,
            wavelength_min_m: a,
            wavelength_max_m: b,
            cosines: None,
            step_m: None,
        }
    }

    /// Angular frequency band [Ω_min, Ω_max], rad/m.
    pub fn band(&self) -> (f64, f64) {
        let tau = std::f64::consts::TAU;
        (tau / self.wavelength_max_m, tau / self.wavelength_min_m)
    }

    /// Checks the settings; every problem, one per entry.
    pub fn problems(&self) -> Vec<String> {
        let mut p = Vec::new();
        let (a, b) = (self.wavelength_min_m, self.wavelength_max_m);
        if !(a.is_finite() && a > 0.0 && b.is_finite() && b > a) {
            p.push(format!(
                "wavelength_min_m = {a}, wavelength_max_m = {b}: expected 0 < min < max"
            ));
        }
        if let Some(n) = self.cosines {
            if !(10..=1_000_000).contains(&n) {
                p.push(format!("cosines = {n}: expected 10..1000000"));
            }
        }
        if let Some(h) = self.step_m {
            if !(h.is_finite() && h > 0.0 && h <= a / 4.0) {
                p.push(format!(
                    "step_m = {h}: expected 0 < step ≤ wavelength_min_m/4 = {}",
                    a / 4.0
                ));
            }
        }
        p
    }
}

/// One irregularity as a sum of cosines: the exact generated signal (also the reference the
/// interpolant is checked against).
#[derive(Debug, Clone)]
pub struct CosineSum {
    pub omega: Vec<f64>,
    pub amplitude: Vec<f64>,
    pub phase: Vec<f64>,
}

impl CosineSum {
    /// Value, first and second derivative at `s` (direct sum: slow, for checks).
    pub fn eval(&self, s: f64) -> (f64, f64, f64) {
        let (mut v, mut d1, mut d2) = (0.0, 0.0, 0.0);
        for k in 0..self.omega.len() {
            let (sn, cs) = (self.omega[k] * s + self.phase[k]).sin_cos();
            let (a, w) = (self.amplitude[k], self.omega[k]);
            v += a * cs;
            d1 -= a * w * sn;
            d2 -= a * w * w * cs;
        }
        (v, d1, d2)
    }
}

/// SplitMix64: a small, well-mixed generator whose output depends only on the seed.
struct SplitMix64(u64);

impl SplitMix64 {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The automatic number of cosines: the smallest with ΔΩ ≤ π/L, at least 500.
fn cosine_count(g: &Generation, length_m: f64) -> usize {
    let (w0, w1) = g.band();
    ((length_m.max(1.0) * (w1 - w0) / std::f64::consts::PI).ceil() as usize).max(500)
}

/// The cosine series of each irregularity for a track of length `length_m` (see the module doc).
pub fn cosine_sums(g: &Generation, length_m: f64) -> [CosineSum; 4] {
    let (w0, w1) = g.band();
    let n = g.cosines.unwrap_or_else(|| cosine_count(g, length_m));
    let dw = (w1 - w0) / n as f64;
    Channel::ALL.map(|ch| {
        let mut rng = SplitMix64(g.seed ^ (0xA076_1D64_78BD_642F_u64.wrapping_mul(ch as u64 + 1)));
        let omega: Vec<f64> = (0..n).map(|k| w0 + (k as f64 + 0.5) * dw).collect();
        let amplitude = omega
            .iter()
            .map(|&w| (2.0 * g.psd.density(ch, w) * dw).sqrt())
            .collect();
        let phase = (0..n).map(|_| std::f64::consts::TAU * rng.uniform()).collect();
        CosineSum {
            omega,
            amplitude,
            phase,
        }
    })
}

/// The four irregularities, C² in s.
#[derive(Debug, Clone)]
pub struct Irregularities {
    s: Vec<f64>,
    nodes: Vec<[[f64; 4]; 3]>,
    /// Uniform grid: s_0 and 1/h; `None` for a non-uniform one.
    uniform: Option<(f64, f64)>,
    pub origin: Origin,
    /// Run-in: over `[s_a, s_a + L]` the irregularities grow from zero with the C² ramp
    /// w(u) = 10u³ − 15u⁴ + 6u⁵, u = (s − s_a)/L, so that a vehicle can start on ideal track.
    pub run_in: Option<(f64, f64)>,
}

impl Irregularities {
    /// From node values, first and second derivatives, SI. `s` strictly increasing, ≥ 2 nodes.
    pub fn from_nodes(s: Vec<f64>, nodes: Vec<[[f64; 4]; 3]>, origin: Origin) -> Result<Self, TrackError> {
        let bad = |problem: String| TrackError::Irregularity(problem);
        if s.len() < 2 || s.len() != nodes.len() {
            return Err(bad(format!(
                "{} nodes for {} positions: need at least 2, one per position",
                nodes.len(),
                s.len()
            )));
        }
        for k in 0..s.len() {
            if !s[k].is_finite() || nodes[k].iter().flatten().any(|v| !v.is_finite()) {
                return Err(bad(format!("node {k} (s = {}) is not finite", s[k])));
            }
            if k > 0 && s[k] <= s[k - 1] {
                return Err(bad(format!(
                    "s does not increase at node {k}: {} after {}",
                    s[k],
                    s[k - 1]
                )));
            }
        }
        let n = s.len();
        let h = (s[n - 1] - s[0]) / (n - 1) as f64;
        let is_uniform = s
            .iter()
            .enumerate()
            .all(|(k, &x)| (x - (s[0] + k as f64 * h)).abs() <= 1e-9 * h);
        Ok(Irregularities {
            uniform: is_uniform.then_some((s[0], 1.0 / h)),
            s,
            nodes,
            origin,
            run_in: None,
        })
    }

    /// Generates the irregularities of `g` over `[from_m, to_m]` (see the module doc). Also
    /// returns the cosine series (the exact signals).
    pub fn generate(g: &Generation, from_m: f64, to_m: f64) -> Result<(Self, [CosineSum; 4]), TrackError> {
        let problems = g.problems();
        if !problems.is_empty() {
            return Err(TrackError::Irregularity(problems.join("; ")));
        }
        if !(from_m.is_finite() && to_m.is_finite() && to_m > from_m) {
            return Err(TrackError::Irregularity(format!(
                "cannot generate over s = {from_m}..{to_m} m"
            )));
        }
        let length = to_m - from_m;
        let step = g.step_m.unwrap_or(g.wavelength_min_m / 10.0);
        let nodes_needed = length / step + 1.0;
        let cosines_needed = g
            .cosines
            .map_or_else(|| cosine_count(g, length) as f64, |n| n as f64);
        let limits = [
            crate::limits::check(
                &format!("irregularity nodes over {length:.0} m every {step:.3e} m"),
                nodes_needed,
                crate::limits::MAX_IRREGULARITY_NODES,
                "raise step_m or wavelength_min_m (the default step is wavelength_min_m/10), or shorten the track",
            ),
            crate::limits::check(
                &format!(
                    "cosines per irregularity for {length:.0} m over {}..{} m wavelengths",
                    g.wavelength_min_m, g.wavelength_max_m
                ),
                cosines_needed,
                crate::limits::MAX_COSINES,
                "raise wavelength_min_m, or set cosines",
            ),
            crate::limits::check(
                "irregularity generation work (cosines × nodes × 4)",
                4.0 * cosines_needed * nodes_needed,
                crate::limits::MAX_GENERATION_WORK,
                "raise wavelength_min_m or step_m, set fewer cosines, or shorten the track",
            ),
        ];
        if let Some(Err(e)) = limits.into_iter().find(|r| r.is_err()) {
            return Err(TrackError::Limit(e));
        }
        let sums = cosine_sums(g, length);
        let n = ((length / step).ceil() as usize).max(1) + 1;
        let h = length / (n - 1) as f64;
        // The last node exactly at the track's end (j h rounds below it: the track's last metre
        // was then outside the irregularities by 1e-13 m, and `kecsim track` failed at its end).
        let s: Vec<f64> = (0..n)
            .map(|j| if j + 1 == n { to_m } else { from_m + j as f64 * h })
            .collect();
        let mut nodes = vec![[[0.0; 4]; 3]; n];
        for (c, sum) in sums.iter().enumerate() {
            for k in 0..sum.omega.len() {
                let (a, w) = (sum.amplitude[k], sum.omega[k]);
                let (rs, rc) = (w * h).sin_cos();
                let (mut ps, mut pc) = (0.0, 0.0);
                for (j, node) in nodes.iter_mut().enumerate() {
                    // Phasor e^{i(Ω s_j + φ)}, rotated by e^{iΩh} per node and reset every 512.
                    if j % 512 == 0 {
                        (ps, pc) = (w * s[j] + sum.phase[k]).sin_cos();
                    } else {
                        (ps, pc) = (ps * rc + pc * rs, pc * rc - ps * rs);
                    }
                    node[0][c] += a * pc;
                    node[1][c] -= a * w * ps;
                    node[2][c] -= a * w * w * pc;
                }
            }
        }
        let irr = Self::from_nodes(s, nodes, Origin::Generated(*g))?;
        Ok((irr, sums))
    }

    /// Range of s covered, m.
    pub fn range(&self) -> (f64, f64) {
        (self.s[0], self.s[self.s.len() - 1])
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.s.len()
    }

    pub fn is_empty(&self) -> bool {
        self.s.is_empty()
    }

    #[inline]
    fn interval(&self, s: f64) -> usize {
        let last = self.s.len() - 2;
        match self.uniform {
            Some((s0, inv_h)) => (((s - s0) * inv_h) as usize).min(last),
            None => self.s.partition_point(|&x| x <= s).saturating_sub(1).min(last),
        }
    }

    /// The four irregularities and their s-derivatives at `s` (quintic Hermite, see module doc).
    #[inline]
    pub fn eval(&self, s: f64) -> Result<IrregularityState, TrackError> {
        let (a, b) = self.range();
        if !(s >= a && s <= b) {
            return Err(TrackError::OutOfRange { s, from: a, to: b });
        }
        let i = self.interval(s);
        let h = self.s[i + 1] - self.s[i];
        let t = (s - self.s[i]) / h;
        let (t2, t3) = (t * t, t * t * t);
        let (t4, t5) = (t3 * t, t3 * t2);
        // Quintic Hermite basis: values, first and second derivatives in t.
        let hb = [
            1.0 - 10.0 * t3 + 15.0 * t4 - 6.0 * t5,
            t - 6.0 * t3 + 8.0 * t4 - 3.0 * t5,
            0.5 * (t2 - 3.0 * t3 + 3.0 * t4 - t5),
            0.5 * (t3 - 2.0 * t4 + t5),
            -4.0 * t3 + 7.0 * t4 - 3.0 * t5,
            10.0 * t3 - 15.0 * t4 + 6.0 * t5,
        ];
        let d1b = [
            -30.0 * t2 + 60.0 * t3 - 30.0 * t4,
            1.0 - 18.0 * t2 + 32.0 * t3 - 15.0 * t4,
            0.5 * (2.0 * t - 9.0 * t2 + 12.0 * t3 - 5.0 * t4),
            0.5 * (3.0 * t2 - 8.0 * t3 + 5.0 * t4),
            -12.0 * t2 + 28.0 * t3 - 15.0 * t4,
            30.0 * t2 - 60.0 * t3 + 30.0 * t4,
        ];
        let d2b = [
            -60.0 * t + 180.0 * t2 - 120.0 * t3,
            -36.0 * t + 96.0 * t2 - 60.0 * t3,
            0.5 * (2.0 - 18.0 * t + 36.0 * t2 - 20.0 * t3),
            0.5 * (6.0 * t - 24.0 * t2 + 20.0 * t3),
            -24.0 * t + 84.0 * t2 - 60.0 * t3,
            60.0 * t - 180.0 * t2 + 120.0 * t3,
        ];
        let (n0, n1) = (&self.nodes[i], &self.nodes[i + 1]);
        let (inv_h, h2) = (1.0 / h, h * h);
        let mut out = IrregularityState::default();
        for c in 0..4 {
            let coef = [
                n0[0][c],
                h * n0[1][c],
                h2 * n0[2][c],
                h2 * n1[2][c],
                h * n1[1][c],
                n1[0][c],
            ];
            let dot = |b: &[f64; 6]| (0..6).map(|j| coef[j] * b[j]).sum::<f64>();
            out.value[c] = dot(&hb);
            out.d1[c] = dot(&d1b) * inv_h;
            out.d2[c] = dot(&d2b) * inv_h * inv_h;
        }
        if let Some((s_a, l)) = self.run_in {
            let u = ((s - s_a) / l).clamp(0.0, 1.0);
            if u < 1.0 {
                // Product rule with the ramp w(u): v = w g, v' = w' g + w g', v'' = w'' g + 2 w' g' + w g''.
                let w = u * u * u * (10.0 - 15.0 * u + 6.0 * u * u);
                let w1 = 30.0 * u * u * (1.0 - u) * (1.0 - u) / l;
                let w2 = 60.0 * u * (1.0 - u) * (1.0 - 2.0 * u) / (l * l);
                for c in 0..4 {
                    let (g, g1, g2) = (out.value[c], out.d1[c], out.d2[c]);
                    out.value[c] = w * g;
                    out.d1[c] = w1 * g + w * g1;
                    out.d2[c] = w2 * g + 2.0 * w1 * g1 + w * g2;
                }
            }
        }
        Ok(out)
    }

    /// Node positions and values (s, [al, vp, gv, cl]) in SI, for writing and plotting.
    pub fn node_values(&self) -> impl Iterator<Item = (f64, [f64; 4])> + '_ {
        self.s.iter().zip(&self.nodes).map(|(&s, n)| (s, n[0]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn run_in_ramps_from_zero_with_consistent_derivatives() {
        let g = Generation::new(Psd::Fra(4), 3);
        let (mut irr, _) = Irregularities::generate(&g, 0.0, 200.0).unwrap();
        let full = irr.eval(30.0).unwrap();
        irr.run_in = Some((0.0, 20.0));
        assert_eq!(irr.eval(0.0).unwrap().value, [0.0; 4]);
        assert_eq!(irr.eval(30.0).unwrap(), full, "unchanged past the run-in");
        // Derivatives against central differences of the tapered values, inside the ramp.
        let h = 1e-4;
        let (p, m, c) = (
            irr.eval(7.0 + h).unwrap(),
            irr.eval(7.0 - h).unwrap(),
            irr.eval(7.0).unwrap(),
        );
        for k in 0..4 {
            let d1 = (p.value[k] - m.value[k]) / (2.0 * h);
            let d2 = (p.d1[k] - m.d1[k]) / (2.0 * h);
            assert!(
                (d1 - c.d1[k]).abs() < 1e-6 * (1e-3 + c.d1[k].abs()),
                "{k}: {d1} {}",
                c.d1[k]
            );
            assert!(
                (d2 - c.d2[k]).abs() < 1e-5 * (1e-2 + c.d2[k].abs()),
                "{k}: {d2} {}",
                c.d2[k]
            );
        }
    }

    fn small() -> (Irregularities, [CosineSum; 4]) {
        let mut g = Generation::new(Psd::GermanHigh, 7);
        g.wavelength_min_m = 2.0;
        g.wavelength_max_m = 40.0;
        Irregularities::generate(&g, 10.0, 210.0).unwrap()
    }

    #[test]
    fn interpolant_matches_the_exact_cosine_sum_with_derivatives() {
        let (irr, sums) = small();
        let mut worst = [[0.0f64; 3]; 4];
        let mut scale = [[0.0f64; 3]; 4];
        for j in 0..2000 {
            let s = 10.0 + 200.0 * (j as f64 + 0.37) / 2000.0;
            let st = irr.eval(s).unwrap();
            for c in 0..4 {
                let (v, d1, d2) = sums[c].eval(s);
                let got = [st.value[c], st.d1[c], st.d2[c]];
                for (q, e) in [v, d1, d2].into_iter().enumerate() {
                    worst[c][q] = worst[c][q].max((got[q] - e).abs());
                    scale[c][q] = scale[c][q].max(e.abs());
                }
            }
        }
        for c in 0..4 {
            // Relative to the signal's largest magnitude: value 1e-5, d1 1e-4, d2 2e-3.
            for (q, tol) in [1e-5, 1e-4, 2e-3].into_iter().enumerate() {
                let rel = worst[c][q] / scale[c][q];
                assert!(rel < tol, "channel {c} derivative {q}: relative error {rel:e}");
            }
        }
    }

    /// The generated range is exactly the track's: the last node is its end (with j·h it was
    /// 1e-13 m short on the Tab. 6 kilometre, and evaluating the track's end failed).
    #[test]
    fn generated_irregularities_cover_the_whole_track() {
        let g = Generation::new(Psd::GermanLow, 1);
        for (a, b) in [(0.0, 1000.0), (10.0, 210.0), (0.3, 999.7)] {
            let (irr, _) = Irregularities::generate(&g, a, b).unwrap();
            assert_eq!(irr.range(), (a, b));
            assert!(irr.eval(b).is_ok() && irr.eval(a).is_ok());
        }
    }

    /// An oversized request is refused with the limit before anything is allocated.
    #[test]
    fn oversized_generation_is_refused_before_allocating() {
        let mut g = Generation::new(Psd::GermanLow, 1);
        g.step_m = Some(1e-9);
        let e = Irregularities::generate(&g, 0.0, 1000.0)
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains("irregularity nodes") && e.contains("limit"), "{e}");
    }

    #[test]
    fn spline_derivatives_match_finite_differences() {
        let (irr, _) = small();
        let e = 1e-4;
        for s in [11.11, 57.3, 123.456, 209.0] {
            let (m, f, p) = (
                irr.eval(s - e).unwrap(),
                irr.eval(s).unwrap(),
                irr.eval(s + e).unwrap(),
            );
            for c in 0..4 {
                let fd1 = (p.value[c] - m.value[c]) / (2.0 * e);
                let fd2 = (p.d1[c] - m.d1[c]) / (2.0 * e);
                assert!(
                    (fd1 - f.d1[c]).abs() < 1e-7 * f.d1[c].abs().max(1e-3),
                    "s={s} c={c} d1 {fd1} vs {}",
                    f.d1[c]
                );
                assert!(
                    (fd2 - f.d2[c]).abs() < 1e-6 * f.d2[c].abs().max(1e-2),
                    "s={s} c={c} d2 {fd2} vs {}",
                    f.d2[c]
                );
            }
        }
    }

    #[test]
    fn same_seed_same_track_other_seed_other_track() {
        let (a, _) = small();
        let (b, _) = small();
        assert_eq!(a.eval(77.7).unwrap(), b.eval(77.7).unwrap());
        let mut g = Generation::new(Psd::GermanHigh, 8);
        g.wavelength_min_m = 2.0;
        g.wavelength_max_m = 40.0;
        let (c, _) = Irregularities::generate(&g, 10.0, 210.0).unwrap();
        assert_ne!(a.eval(77.7).unwrap().value, c.eval(77.7).unwrap().value);
    }

    #[test]
    fn rail_offsets_use_the_contact_conversion_and_eq7_roll() {
        let st = IrregularityState {
            value: [2e-3, 1e-3, 4e-3, -3e-3],
            ..Default::default()
        };
        let o = st.rail_offsets();
        assert!((o.y_left - 4e-3).abs() < 1e-15 && (o.y_right - 0.0).abs() < 1e-15);
        assert!((o.z_left + 0.5e-3).abs() < 1e-15 && (o.z_right - 2.5e-3).abs() < 1e-15);
        let (l, r) = st.rail_frames(0.75, (1.0f64 / 40.0).atan());
        let delta = -3e-3 / 1.5;
        assert!((l.angle_rad - ((1.0f64 / 40.0).atan() + delta)).abs() < 1e-15);
        assert!((r.angle_rad - (-(1.0f64 / 40.0).atan() + delta)).abs() < 1e-15);
        assert!((l.y_m - 0.754).abs() < 1e-15 && (r.y_m + 0.75).abs() < 1e-15);
    }

    #[test]
    fn quintic_reproduces_a_quintic_polynomial_on_a_nonuniform_grid() {
        let f = |x: f64| {
            [
                x.powi(5) - 2.0 * x * x,
                5.0 * x.powi(4) - 4.0 * x,
                20.0 * x.powi(3) - 4.0,
            ]
        };
        let s = vec![0.0, 0.3, 1.0, 1.2, 2.0];
        let nodes = s
            .iter()
            .map(|&x| {
                let v = f(x);
                [[v[0]; 4], [v[1]; 4], [v[2]; 4]]
            })
            .collect();
        let irr = Irregularities::from_nodes(s, nodes, Origin::Measured { path: "t".into() }).unwrap();
        for x in [0.1, 0.77, 1.1, 1.9] {
            let st = irr.eval(x).unwrap();
            let v = f(x);
            assert!(
                (st.value[2] - v[0]).abs() < 1e-12
                    && (st.d1[2] - v[1]).abs() < 1e-11
                    && (st.d2[2] - v[2]).abs() < 1e-10
            );
        }
    }
}
