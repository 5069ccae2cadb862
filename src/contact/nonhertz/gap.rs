//! The gap between the real wheel and rail profiles around a contact, along the direction the
//! wheel approaches the rail ([`GapSection`]): what a non-Hertzian patch is made from.
//!
//! Both profiles are plane curves (s, z(s)) in their own frames (the side's orientation, paper
//! convention: s increases towards +Y). At a rigid contact the wheel touches the rail at the
//! pair (s_w, s_r) with equal tangents, which fixes the wheel's placement relative to the rail:
//! rotated by θ = atan z_r'(s_r) − atan z_w'(s_w) about the contact point C = (s_r, z_r(s_r)),
//!
//! ```text
//! P_w(s) = C + R(θ) [s − s_w,  z_w(s) − z_w(s_w)]ᵀ          (rail frame)
//! ```
//!
//! (the wheel's material above its curve, the rail's below). In the frame of the approach
//! direction u (unit, rail frame; w across it, towards +s), each curve near the contact is a graph
//! v(w), and the gap along u is
//!
//! ```text
//! g(w) = v_w(w) − v_r(w)  ≥ 0,   g = 0 at the contact;   normal gap ≈ g cos θ_r(w)
//! ```
//!
//! with θ_r(w) the rail surface's slope angle against w. A rigid approach δ of the wheel along u
//! overlaps the profiles by δ − g(w) along u: one patch per connected region of overlap.
//!
//! Only the placement at the contact is used: no wheelset pose, no track. Yaw's effect on the
//! contact (the lead of a flange contact ahead of the axle) is neglected here, as in the contact
//! geometry ([`crate::contact::geometry`]).

use crate::profile::Profile;
use crate::track::Side;

/// Lateral sampling of the profiles and the gap, m.
pub const GAP_STEP_M: f64 = 1e-4;
/// Half-width of the window the gap is sampled over, each side of the contact, m.
pub const GAP_WINDOW_M: f64 = 0.025;

/// The gap of one wheel to its rail around a contact, sampled uniformly across the approach
/// direction.
#[derive(Debug, Clone)]
pub struct GapSection {
    /// Across-coordinate w of each sample (rail frame, perpendicular to u, 0 at the contact), m.
    pub w: Vec<f64>,
    /// Gap along u, m (0 at the contact, up to the sampling).
    pub gap: Vec<f64>,
    /// Rail parameter s_r at each sample (paper convention), m.
    pub s_rail: Vec<f64>,
    /// Wheel parameter s_w at each sample (paper convention), m.
    pub s_wheel: Vec<f64>,
    /// cos of the rail surface's slope against w (normal gap = gap × this; arc = dw / this).
    pub cos_slope: Vec<f64>,
    /// Contact angle of the rail normal at each sample, track frame (from vertical, positive
    /// towards the track centre), rad.
    pub contact_angle: Vec<f64>,
    /// Wheel rolling radius at each sample, m.
    pub radius: Vec<f64>,
    /// Index of the rigid contact (the sample nearest w = 0).
    pub contact: usize,
}

/// Why a gap section could not be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GapError {
    #[error("non-finite contact input ({0})")]
    NonFinite(&'static str),
    #[error("the profiles fold over within {0:.3} mm of the contact (no gap function there)")]
    Folded(f64),
}

/// A plane curve sampled as a graph v(w) across the approach direction.
struct Graph {
    w: Vec<f64>,
    v: Vec<f64>,
    s: Vec<f64>,
    /// A profile value carried along (the rail's slope dz/ds, the wheel's z).
    x: Vec<f64>,
}

impl Graph {
    /// The part of the sampled curve (s_i, w_i, v_i), ordered by s, that is a graph in w
    /// (w increasing) and contains sample `c`.
    fn monotone_around(s: Vec<f64>, w: Vec<f64>, v: Vec<f64>, x: Vec<f64>, c: usize) -> Graph {
        let n = w.len();
        let mut lo = c;
        while lo > 0 && w[lo - 1] < w[lo] {
            lo -= 1;
        }
        let mut hi = c;
        while hi + 1 < n && w[hi + 1] > w[hi] {
            hi += 1;
        }
        Graph {
            w: w[lo..=hi].to_vec(),
            v: v[lo..=hi].to_vec(),
            s: s[lo..=hi].to_vec(),
            x: x[lo..=hi].to_vec(),
        }
    }

    /// Linear interpolation of (v, s) at `x`, walking the cursor `k` forwards (x increasing).
    fn at(&self, x: f64, k: &mut usize) -> (f64, f64, f64) {
        while *k + 2 < self.w.len() && self.w[*k + 1] < x {
            *k += 1;
        }
        let (w0, w1) = (self.w[*k], self.w[*k + 1]);
        let t = ((x - w0) / (w1 - w0)).clamp(0.0, 1.0);
        (
            self.v[*k] + t * (self.v[*k + 1] - self.v[*k]),
            self.s[*k] + t * (self.s[*k + 1] - self.s[*k]),
            self.x[*k] + t * (self.x[*k + 1] - self.x[*k]),
        )
    }
}

/// Where the wheel is and where it approaches from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GapInput {
    pub side: Side,
    /// Rigid contact on the wheel and the rail (paper convention), m.
    pub s_wheel: f64,
    pub s_rail: f64,
    /// Nominal rolling radius r0 (the wheel radius is r0 − z_w(s)), m.
    pub nominal_radius: f64,
    /// Angle of the rail frame in the track frame (σβ, plus a cross-level rotation if any), rad.
    pub rail_angle: f64,
    /// Angle of the approach direction u from the rail frame's vertical, towards +s, rad.
    pub approach_angle: f64,
    /// Half-width of the window sampled each side of the contact, m (`GAP_WINDOW_M`).
    pub half_window: f64,
}

impl GapInput {
    /// The approach along the rail normal at the contact (the direction of the normal force).
    pub fn along_normal(rail: &Profile, side: Side, s_rail: f64) -> f64 {
        (-rail.eval_side(side, s_rail).dz).atan()
    }
}

impl GapSection {
    /// The gap around the contact (see the module's documentation).
    pub fn new(wheel: &Profile, rail: &Profile, input: &GapInput) -> Result<GapSection, GapError> {
        let GapInput {
            side,
            s_wheel,
            s_rail,
            nominal_radius,
            rail_angle,
            approach_angle,
            half_window,
        } = *input;
        for (v, what) in [
            (s_wheel, "s_w"),
            (s_rail, "s_r"),
            (nominal_radius, "r0"),
            (rail_angle, "rail angle"),
            (approach_angle, "approach angle"),
            (half_window, "window"),
        ] {
            if !v.is_finite() {
                return Err(GapError::NonFinite(what));
            }
        }
        let (su, cu) = approach_angle.sin_cos();
        // u = (su, cu); w-axis u⊥ = (cu, −su).
        let to_uv = |p: (f64, f64)| (p.0 * cu - p.1 * su, p.0 * su + p.1 * cu);
        let pr = rail.eval_side(side, s_rail);
        let pw = wheel.eval_side(side, s_wheel);
        let theta = pr.dz.atan() - pw.dz.atan();
        let (st, ct) = theta.sin_cos();
        let c = (s_rail, pr.z);
        let (w0, _) = to_uv(c);
        let half_window = half_window.clamp(GAP_STEP_M * 10.0, 0.1);
        let n_half = (half_window / GAP_STEP_M).round() as usize;
        let sample = |centre: f64, domain: (f64, f64), f: &dyn Fn(f64) -> ((f64, f64), f64)| {
            let mut s = Vec::with_capacity(2 * n_half + 1);
            let mut w = Vec::with_capacity(2 * n_half + 1);
            let mut v = Vec::with_capacity(2 * n_half + 1);
            let mut x = Vec::with_capacity(2 * n_half + 1);
            let mut c_idx = 0;
            for i in 0..=2 * n_half {
                let si = centre + (i as f64 - n_half as f64) * GAP_STEP_M;
                if si < domain.0 || si > domain.1 {
                    continue;
                }
                if i == n_half {
                    c_idx = s.len();
                }
                let (p, xi) = f(si);
                let (wi, vi) = to_uv(p);
                s.push(si);
                w.push(wi - w0);
                v.push(vi);
                x.push(xi);
            }
            (s, w, v, x, c_idx)
        };
        let rail_xy = |s: f64| {
            let p = rail.eval_side(side, s);
            ((s, p.z), p.dz)
        };
        let wheel_xy = |s: f64| {
            let z = wheel.eval_side(side, s).z;
            let dz = z - pw.z;
            let ds = s - s_wheel;
            ((c.0 + ct * ds - st * dz, c.1 + st * ds + ct * dz), z)
        };
        let (s, w, v, x, ci) = sample(s_rail, rail.domain_side(side), &rail_xy);
        let rg = Graph::monotone_around(s, w, v, x, ci);
        let (s, w, v, x, ci) = sample(s_wheel, wheel.domain_side(side), &wheel_xy);
        let wg = Graph::monotone_around(s, w, v, x, ci);
        let lo = rg.w[0].max(wg.w[0]).max(-half_window);
        let hi = rg.w[rg.w.len() - 1].min(wg.w[wg.w.len() - 1]).min(half_window);
        if !(lo < -GAP_STEP_M && hi > GAP_STEP_M) {
            return Err(GapError::Folded(1e3 * lo.abs().min(hi.abs())));
        }
        let i_lo = (lo / GAP_STEP_M).ceil() as i64;
        let i_hi = (hi / GAP_STEP_M).floor() as i64;
        let n = (i_hi - i_lo + 1) as usize;
        let mut out = GapSection {
            w: Vec::with_capacity(n),
            gap: Vec::with_capacity(n),
            s_rail: Vec::with_capacity(n),
            s_wheel: Vec::with_capacity(n),
            cos_slope: Vec::with_capacity(n),
            contact_angle: Vec::with_capacity(n),
            radius: Vec::with_capacity(n),
            contact: (-i_lo) as usize,
        };
        let (mut kr, mut kw) = (0, 0);
        let sigma = side.sign();
        for i in i_lo..=i_hi {
            let x = i as f64 * GAP_STEP_M;
            let (vr, sr, dzr) = rg.at(x, &mut kr);
            let (vw, sw, zw) = wg.at(x, &mut kw);
            // Rail slope against w: the profile's slope angle less the approach angle.
            let slope = dzr.atan() + approach_angle;
            out.w.push(x);
            out.gap.push(vw - vr);
            out.s_rail.push(sr);
            out.s_wheel.push(sw);
            out.cos_slope.push(slope.cos().max(1e-3));
            out.contact_angle.push(sigma * dzr.atan() + rail_angle * sigma);
            out.radius.push(nominal_radius - zw);
        }
        Ok(out)
    }

    /// Local minima of the gap below `limit` (m), deepest first; the rigid contact's is first
    /// where it is the deepest.
    pub fn minima(&self, limit: f64) -> Vec<usize> {
        let g = &self.gap;
        let n = g.len();
        let mut m: Vec<usize> = (0..n)
            .filter(|&i| g[i] < limit && (i == 0 || g[i] <= g[i - 1]) && (i + 1 == n || g[i] < g[i + 1]))
            .collect();
        m.sort_by(|&a, &b| g[a].total_cmp(&g[b]));
        m
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::profile::{ProfileKind, StandardProfile};

    /// A circle of radius r as a profile z(s) = ±(r − √(r² − s²)) over |s| ≤ 0.6 r.
    pub(crate) fn circle(kind: ProfileKind, r: f64) -> Profile {
        let n = 601;
        let s: Vec<f64> = (0..n)
            .map(|i| 0.6 * r * (2.0 * i as f64 / (n - 1) as f64 - 1.0))
            .collect();
        let sign = if kind == ProfileKind::Rail { -1.0 } else { 1.0 };
        let z = s.iter().map(|s| sign * (r - (r * r - s * s).sqrt())).collect();
        Profile::from_points("circle", kind, "test", s, z).unwrap()
    }

    #[test]
    fn two_circles_give_the_quadratic_gap() {
        // Wheel radius of curvature 0.5 m (convex downwards), rail 0.3 m (convex upwards): gap
        // ≈ ½ (1/0.5 + 1/0.3) w² near the contact.
        let wheel = circle(ProfileKind::Wheel, 0.5);
        let rail = circle(ProfileKind::Rail, 0.3);
        let g = GapSection::new(
            &wheel,
            &rail,
            &GapInput {
                side: Side::Left,
                s_wheel: 0.0,
                s_rail: 0.0,
                nominal_radius: 0.46,
                rail_angle: 0.0,
                approach_angle: 0.0,
                half_window: GAP_WINDOW_M,
            },
        )
        .unwrap();
        let b = 0.5 * (1.0 / 0.5 + 1.0 / 0.3);
        for (i, &w) in g.w.iter().enumerate() {
            if w.abs() < 0.01 {
                let exact = b * w * w;
                assert!(
                    (g.gap[i] - exact).abs() < 0.01 * exact + 1e-9,
                    "w = {w}: {} vs {exact}",
                    g.gap[i]
                );
            }
        }
        assert_eq!(g.minima(1e-4)[0], g.contact);
    }

    #[test]
    fn placement_is_tangent_on_real_profiles() {
        // S1002 on 60E1 at a flange-root point: the gap is ≥ 0 and ~0 at the contact for a pair
        // of parameters with equal slopes.
        let wheel = StandardProfile::S1002.profile();
        let rail = StandardProfile::Rail60E1.profile();
        let g = GapSection::new(
            &wheel,
            &rail,
            &GapInput {
                side: Side::Left,
                s_wheel: 0.0,
                s_rail: 0.0,
                nominal_radius: 0.46,
                rail_angle: 0.025,
                approach_angle: 0.0,
                half_window: GAP_WINDOW_M,
            },
        )
        .unwrap();
        assert!(g.gap[g.contact].abs() < 1e-12);
        assert!(g.w.len() > 100);
    }
}
