//! Elastic wheel–rail contact: the interpenetration of the real profiles at a free wheelset pose
//! (issue 14; not in the paper, which constrains the wheelset to the rails — the commercial codes'
//! "elastic" or penalty contact, here the independent reference for two-point contact, wheel lift
//! and flange impacts).
//!
//! The wheelset is free in all its coordinates: given y, z, φ (and their rates) and the displaced
//! rails, each wheel is searched for the regions where it interpenetrates its rail. In each rail's
//! own profile frame (origin O and rotation α = σβ + δ of Eq. 38) the rail head is the graph
//! h^r(s); a wheel point W(s^w) of Eq. (37) lands at (p_s, p_h) = A(α)ᵀ (W − O) and its gap along the
//! rail frame's vertical is
//!
//! ```text
//! g(s^w) = p_h(s^w) − h^r(p_s(s^w))
//! ```
//!
//! Every local minimum of g below zero is a contact: there the wheel and rail are parallel
//! (g' = 0), so the normal approach of the two locally parallel surfaces is
//! δ = −g cos γ_r, with tan γ_r = h^r'(p_s) the rail's slope in its frame.
//!
//! **One region, shared contacts.** On near-conformal treads (S1002 on 60E1) one interpenetration
//! region can hold two minima of g with a shallow hump between them, and which is deeper swaps as
//! the wheelset moves. Counting both in full would double the wheel's load; counting only the
//! deepest would make the load jump at the swap (the two points' curvatures, so their Hertz
//! stiffnesses, differ) and where the hump breaks the surface. So each minimum m of depth D_m
//! carries the share w_m of its own Hertz force: with P_m the depth of its deepest pass (the
//! highest gap on the way) to another minimum of its region, ρ_m = (D_m − P_m)/D_m its prominence
//! ratio and μ = 1 + Σρ − max ρ the region's multiplicity, w_m = μ ρ_m / Σρ. A region of one
//! minimum, or minima parted by a pass above zero, count in full (w = 1); a shoulder (ρ = 0) not
//! at all; two equal minima over a shallow hump half each; and every share is continuous in the
//! pose. A departure from the multi-Hertzian codes, which separate regions only; stated, tested. The contact point is the
//! wheel point there, the normal the rail's (Eq. 40), the curvatures the profiles' (the Hertz
//! ellipse, normal force δ → N and its damping are the dynamics' business:
//! [`crate::dynamics::elastic`]). The approach rate δ̇ is the closing speed of the wheel point on
//! the rail along the normal: the wheel point moves at (ẏ − φ̇ u_z, ż + φ̇ u_y) (u from the centre),
//! the rail at its irregularity rates (its roll rate δ̇ neglected: below 1e-4 m/s at the contact).
//!
//! **Search**: g sampled every [`ElasticContact::scan_step_m`] over the wheel where it lies over the
//! rail (the rail head tabulated on a 25 µm grid, linear between: ≤ 1e-8 m from the spline on a
//! 13 mm gauge corner); each sampled local minimum below [`CANDIDATE_GAP_M`] and the global minimum
//! are polished by golden-section search on the exact g (splines of both profiles) to 1e-9 m in
//! s^w. Two minima that polish to the same point count once; a wheel keeps its
//! [`MAX_POINTS_PER_WHEEL`] deepest contacts (tread and flange: more are reported as dropped).
//! The yaw is neglected in the search, as in the online constraints (§4.2); the dynamics moves the
//! point along the rail by the yaw as for the constraint models.

use super::geometry::ContactGeometry;
use super::point::ContactPoint;
use crate::profile::Side;
use crate::track::{RailMotion, RailOffsets};

/// Contacts a wheel keeps (the deepest).
pub const MAX_POINTS_PER_WHEEL: usize = 4;
/// A sampled local minimum of the gap below this is polished (the sampled gap overstates the
/// exact one by at most ~ step² κ / 8: 0.1 mm covers a 0.5 mm step on a 10 mm radius), m.
pub const CANDIDATE_GAP_M: f64 = 1e-4;
/// The largest approach taken as contact, m: a wheel 2 mm into its rail (the Hertz approach of a
/// 1 MN impact is ~0.4 mm) is an initial state or a pose far off, reported.
pub const MAX_APPROACH_M: f64 = 2e-3;
/// The rail head's tabulation step for the scan, m.
const RAIL_TABLE_STEP_M: f64 = 2.5e-5;

/// The wheelset's free pose and its rates in the wheelset-track frame.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FreePose {
    pub y: f64,
    /// Centre height z (the contact geometry's convention: 0 where the nominal wheel touches the
    /// undisplaced rail), m.
    pub z: f64,
    pub phi: f64,
    pub y_dot: f64,
    pub z_dot: f64,
    pub phi_dot: f64,
}

/// One region where a wheel and its rail interpenetrate.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Penetration {
    /// The wheel point of deepest penetration, with the rail's normal and both curvatures.
    pub point: ContactPoint,
    /// Normal approach δ > 0, m.
    pub depth: f64,
    /// Its rate δ̇ (positive closing), m/s.
    pub rate: f64,
    /// The share w of its Hertz force the contact carries (1 for a region of its own; see the
    /// module doc).
    pub share: f64,
}

/// Everything the elastic search found at one pose.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ElasticContacts {
    /// Per wheel (left, right) its contacts, deepest first.
    pub points: [[Option<Penetration>; MAX_POINTS_PER_WHEEL]; 2],
    /// Each wheel's smallest normal gap to its rail (negative: the deepest approach), m.
    pub gap: [f64; 2],
    /// The point of smallest gap of each wheel (its deepest contact, or where a lifted wheel is
    /// closest to its rail).
    pub closest: [ContactPoint; 2],
    /// Contacts found beyond [`MAX_POINTS_PER_WHEEL`] on a wheel, dropped.
    pub dropped: usize,
    /// The normal damping χ of the Hunt–Crossley law (N = K δ^{3/2} (1 + χ δ̇)), s/m.
    pub damping_s_per_m: f64,
}

impl ElasticContacts {
    /// The contacts of wheel `i` (0 left, 1 right).
    pub fn of(&self, i: usize) -> impl Iterator<Item = &Penetration> {
        self.points[i].iter().flatten()
    }
}

/// The elastic contact search of a placed wheel–rail pair.
#[derive(Debug, Clone)]
pub struct ElasticContact {
    pub geometry: ContactGeometry,
    /// Sampling step of the wheel in the scan, m.
    pub scan_step_m: f64,
    /// Hunt–Crossley damping χ, s/m.
    pub damping_s_per_m: f64,
    /// Per side: wheel samples (s^w, h^w).
    wheel: [Vec<(f64, f64)>; 2],
    /// Per side: s^w where the flange's steepest part (its largest contact angle) ends towards the
    /// tip, and that angle.
    flange: [(f64, f64); 2],
    /// Rail head h^r on a uniform grid in s (left orientation): s₀, 1/Δs, values.
    rail: (f64, f64, Vec<f64>),
}

/// A polished minimum: s^w, s^r, vertical gap g (rail frame).
#[derive(Debug, Clone, Copy)]
struct Minimum {
    sw: f64,
    sr: f64,
    g: f64,
}

impl ElasticContact {
    /// The search for `geometry`'s pair, the wheel sampled every `scan_step_m`.
    pub fn new(geometry: ContactGeometry, scan_step_m: f64, damping_s_per_m: f64) -> ElasticContact {
        let pair = &geometry.pair;
        let mut wheel = [Vec::new(), Vec::new()];
        for side in Side::BOTH {
            let (a, b) = pair.wheel.domain_side(side);
            let n = ((b - a) / scan_step_m).ceil().max(1.0) as usize;
            wheel[side_index(side)] = (0..=n)
                .map(|k| {
                    let s = a + (b - a) * k as f64 / n as f64;
                    (s, geometry.wheel(side, s).0)
                })
                .collect();
        }
        let (a, b) = pair.rail.domain();
        let n = ((b - a) / RAIL_TABLE_STEP_M).ceil().max(1.0) as usize;
        let ds = (b - a) / n as f64;
        let values = (0..=n).map(|k| pair.rail.eval(a + ds * k as f64).z).collect();
        // The flange's largest contact angle: the radius grows fastest towards the track centre
        // (−σ dh/ds largest), sampled every 10 µm; S1002's flank is straight there, so the limit
        // is the flank's end towards the tip, where the angle has fallen 0.5° below its largest.
        let mut flange = [(0.0, 0.0); 2];
        for side in Side::BOTH {
            let (a, b) = pair.wheel.domain_side(side);
            let n = ((b - a) / 1e-5).ceil() as usize;
            let slopes: Vec<(f64, f64)> = (0..=n)
                .map(|k| {
                    let s = a + (b - a) * k as f64 / n as f64;
                    (s, -side.sign() * geometry.wheel(side, s).1)
                })
                .collect();
            let (k_max, &(_, steepest)) =
                slopes
                    .iter()
                    .enumerate()
                    .fold((0, &slopes[0]), |m, v| if v.1 .1 > m.1 .1 { v } else { m });
            let angle = steepest.atan();
            let fallen = (angle - crate::contact::lookup::FLANGE_FLANK_TOLERANCE_RAD).tan();
            // Towards the tip: smaller s on the left wheel, larger on the right.
            let tip: Box<dyn Iterator<Item = &(f64, f64)>> = if side == Side::Left {
                Box::new(slopes[..=k_max].iter().rev())
            } else {
                Box::new(slopes[k_max..].iter())
            };
            let end = tip
                .take_while(|(_, m)| *m >= fallen)
                .last()
                .map_or(slopes[k_max].0, |v| v.0);
            flange[side_index(side)] = (end, angle);
        }
        ElasticContact {
            geometry,
            scan_step_m,
            damping_s_per_m,
            wheel,
            flange,
            rail: (a, 1.0 / ds, values),
        }
    }

    /// The tabulated rail head of side `side` at s (paper convention), `None` off the rail.
    #[inline]
    fn rail_table(&self, side: Side, s: f64) -> Option<f64> {
        let s_left = if side == Side::Left { s } else { -s };
        let (s0, inv, v) = (&self.rail.0, &self.rail.1, &self.rail.2);
        let u = (s_left - s0) * inv;
        if u < 0.0 {
            return None;
        }
        let k = u as usize;
        if k + 1 >= v.len() {
            return None;
        }
        let t = u - k as f64;
        Some(v[k] + t * (v[k + 1] - v[k]))
    }

    /// The exact gap of wheel point s^w: (g, p_s) in side `side`'s rail frame.
    fn exact_gap(&self, side: Side, frame: &RailFrame, pose: &FreePose, sw: f64) -> (f64, f64) {
        let (hw, _, _) = self.geometry.wheel(side, sw);
        let (ps, ph) = frame.to_rail(self.wheel_point(side, pose, sw, hw));
        (ph - self.geometry.rail(side, ps).0, ps)
    }

    /// Wheel point W(s^w) of Eq. (37) in the wheelset-track frame.
    #[inline]
    fn wheel_point(&self, side: Side, pose: &FreePose, sw: f64, hw: f64) -> (f64, f64) {
        let lat = side.sign() * self.geometry.l_w() + sw;
        (pose.y + lat + pose.phi * hw, pose.z + pose.phi * lat - hw)
    }

    /// The s^w where side `side`'s flange leaves its largest contact angle towards the tip (0.5°
    /// below it), and that angle (rad): a contact beyond it is a wheel climbing its flange.
    pub fn flange_limit(&self, side: Side) -> (f64, f64) {
        self.flange[side_index(side)]
    }

    /// The contacts at `pose` on rails moving as `rails`. A contact past its flange's largest
    /// contact angle (towards the tip) is a flange climb ([`ElasticError::FlangeClimb`]): the
    /// constraint models' profiles end there too, and Nadal's limit is taken there.
    pub fn search(&self, pose: &FreePose, rails: &RailMotion) -> Result<ElasticContacts, ElasticError> {
        let off = RailOffsets::from_array(rails.q);
        let mut out = ElasticContacts {
            damping_s_per_m: self.damping_s_per_m,
            ..ElasticContacts::default()
        };
        for side in Side::BOTH {
            let i = side_index(side);
            let frame = RailFrame::new(&self.geometry, side, &off);
            // The sampled gap over the rail.
            let samples = &self.wheel[i];
            let mut gaps = Vec::with_capacity(samples.len());
            for &(sw, hw) in samples {
                let (ps, ph) = frame.to_rail(self.wheel_point(side, pose, sw, hw));
                gaps.push(self.rail_table(side, ps).map(|h| ph - h));
            }
            let mut global: Option<usize> = None;
            let mut candidates = Vec::new();
            for (k, g) in gaps.iter().enumerate() {
                let Some(g) = *g else { continue };
                if global.is_none_or(|m| gaps[m].is_some_and(|gm| g < gm)) {
                    global = Some(k);
                }
                let before = k.checked_sub(1).and_then(|j| gaps[j]);
                let after = gaps.get(k + 1).copied().flatten();
                if g < CANDIDATE_GAP_M && before.is_none_or(|b| g <= b) && after.is_none_or(|a| g < a) {
                    candidates.push(k);
                }
            }
            let Some(global) = global else {
                return Err(ElasticError::OffRail {
                    side: side.name(),
                    y_mm: pose.y * 1e3,
                });
            };
            if !candidates.contains(&global) {
                candidates.push(global);
            }
            // Polish each candidate on the exact gap between its neighbours.
            let mut minima: Vec<(usize, Minimum)> = Vec::with_capacity(candidates.len());
            for k in candidates {
                let lo = samples[k.saturating_sub(1)].0;
                let hi = samples[(k + 1).min(samples.len() - 1)].0;
                let m = self.polish(side, &frame, pose, lo, hi);
                if !minima
                    .iter()
                    .any(|(_, o)| (o.sw - m.sw).abs() < 0.5 * self.scan_step_m)
                {
                    minima.push((k, m));
                }
            }
            minima.sort_by(|a, b| a.1.g.total_cmp(&b.1.g));
            let deepest = minima[0].1;
            out.gap[i] = self.normal_gap(side, &deepest);
            out.closest[i] = self.point(side, &off, pose, &deepest);
            // The minima below zero, their passes and shares (see the module doc).
            let inside: Vec<(usize, Minimum)> = minima.iter().copied().filter(|(_, m)| m.g < 0.0).collect();
            let pass = |a: usize, b: usize| {
                let (a, b) = if a < b { (a, b) } else { (b, a) };
                gaps[a..=b]
                    .iter()
                    .map(|g| g.unwrap_or(f64::INFINITY))
                    .fold(f64::NEG_INFINITY, f64::max)
            };
            let shares = shares(&inside.iter().map(|(k, m)| (*k, -m.g)).collect::<Vec<_>>(), pass);
            let mut found: Vec<(f64, Minimum)> = inside
                .iter()
                .zip(shares)
                .filter(|(_, w)| *w > 0.0)
                .map(|((_, m), w)| (w, *m))
                .collect();
            // Deepest first.
            found.sort_by(|a, b| a.1.g.total_cmp(&b.1.g));
            let mut slot = 0;
            for (share, m) in &found {
                if slot == MAX_POINTS_PER_WHEEL {
                    out.dropped += 1;
                    continue;
                }
                let point = self.point(side, &off, pose, m);
                // Closing speed of the wheel point on the rail along the normal.
                let (uy, uz) = (point.position.0 - pose.y, point.position.1 - pose.z);
                let (vy, vz) = (pose.y_dot - pose.phi_dot * uz, pose.z_dot + pose.phi_dot * uy);
                let (ry, rz) = (rails.q_dot[2 * i], rails.q_dot[2 * i + 1]);
                let (ny, nz) = point.normal;
                out.points[i][slot] = Some(Penetration {
                    point,
                    depth: -self.normal_gap(side, m),
                    share: *share,
                    rate: -((vy - ry) * ny + (vz - rz) * nz),
                });
                slot += 1;
            }
            if let Some(p) = out.of(i).find(|p| p.depth > MAX_APPROACH_M) {
                return Err(ElasticError::Interpenetration {
                    side: side.name(),
                    depth_mm: p.depth * 1e3,
                    y_mm: pose.y * 1e3,
                });
            }
            let (limit, angle) = self.flange[i];
            if let Some(p) = out.of(i).find(|p| side.sign() * (p.point.s_wheel - limit) < 0.0) {
                return Err(ElasticError::FlangeClimb {
                    side: side.name(),
                    y_mm: pose.y * 1e3,
                    s_wheel_mm: p.point.s_wheel * 1e3,
                    limit_mm: limit * 1e3,
                    angle_deg: angle.to_degrees(),
                });
            }
        }
        Ok(out)
    }

    /// The normal gap at a minimum of the vertical gap: g cos γ_r, tan γ_r the rail's slope there.
    fn normal_gap(&self, side: Side, m: &Minimum) -> f64 {
        let slope = self.geometry.rail(side, m.sr).1;
        m.g / (1.0 + slope * slope).sqrt()
    }

    fn point(&self, side: Side, off: &RailOffsets, pose: &FreePose, m: &Minimum) -> ContactPoint {
        self.geometry
            .contact_point(side, off, pose.y, pose.z, pose.phi, m.sw, m.sr)
    }

    /// Golden-section search of the exact gap on [lo, hi] to 1e-9 m in s^w.
    fn polish(&self, side: Side, frame: &RailFrame, pose: &FreePose, mut lo: f64, mut hi: f64) -> Minimum {
        let r = 0.5 * (5f64.sqrt() - 1.0);
        let f = |s: f64| self.exact_gap(side, frame, pose, s);
        let mut c = hi - r * (hi - lo);
        let mut d = lo + r * (hi - lo);
        let (mut fc, mut fd) = (f(c).0, f(d).0);
        while hi - lo > 1e-9 {
            if fc < fd {
                hi = d;
                d = c;
                fd = fc;
                c = hi - r * (hi - lo);
                fc = f(c).0;
            } else {
                lo = c;
                c = d;
                fc = fd;
                d = lo + r * (hi - lo);
                fd = f(d).0;
            }
        }
        let sw = 0.5 * (lo + hi);
        let (g, sr) = f(sw);
        Minimum { sw, sr, g }
    }
}

/// The shares w_m of the minima `(sample index, depth D_m > 0)` of one wheel, `pass(a, b)` the
/// highest sampled gap between samples a and b (the pass; < 0: the minima lie in one region).
/// Within a region (minima joined by passes below zero), with P_m the depth of m's deepest pass
/// to another minimum, ρ_m = (D_m − P_m) / D_m ∈ [0, 1] its prominence ratio and
/// μ = 1 + Σρ − max ρ the region's multiplicity: w_m = μ ρ_m / Σρ.
fn shares(minima: &[(usize, f64)], pass: impl Fn(usize, usize) -> f64) -> Vec<f64> {
    let n = minima.len();
    // Regions by union of the minima joined below zero.
    let mut region: Vec<usize> = (0..n).collect();
    let mut pass_depth = vec![0.0_f64; n];
    for a in 0..n {
        for b in a + 1..n {
            let p = pass(minima[a].0, minima[b].0);
            if p < 0.0 {
                pass_depth[a] = pass_depth[a].max(-p);
                pass_depth[b] = pass_depth[b].max(-p);
                let (ra, rb) = (region[a], region[b]);
                for r in region.iter_mut() {
                    if *r == rb {
                        *r = ra;
                    }
                }
            }
        }
    }
    let rho: Vec<f64> = minima
        .iter()
        .zip(&pass_depth)
        .map(|(&(_, d), &p)| ((d - p) / d).clamp(0.0, 1.0))
        .collect();
    (0..n)
        .map(|m| {
            let members = (0..n).filter(|&k| region[k] == region[m]);
            let (sum, max) = members.fold((0.0, 0.0_f64), |(s, x), k| (s + rho[k], x.max(rho[k])));
            if sum <= 0.0 {
                // A flat region (every minimum at its pass): one contact, shared equally.
                let count = (0..n).filter(|&k| region[k] == region[m]).count();
                return 1.0 / count as f64;
            }
            (1.0 + sum - max) * rho[m] / sum
        })
        .collect()
}

/// A rail's profile frame: origin O and rotation α (Eq. 38).
struct RailFrame {
    origin: (f64, f64),
    sin: f64,
    cos: f64,
}

impl RailFrame {
    fn new(geometry: &ContactGeometry, side: Side, off: &RailOffsets) -> RailFrame {
        let (sin, cos) = geometry.alpha(side, off).sin_cos();
        RailFrame {
            origin: geometry.rail_origin(side, off),
            sin,
            cos,
        }
    }

    /// (p_s, p_h) = A(α)ᵀ (p − O).
    #[inline]
    fn to_rail(&self, p: (f64, f64)) -> (f64, f64) {
        let (dy, dz) = (p.0 - self.origin.0, p.1 - self.origin.1);
        (self.cos * dy + self.sin * dz, -self.sin * dy + self.cos * dz)
    }
}

fn side_index(side: Side) -> usize {
    match side {
        Side::Left => 0,
        Side::Right => 1,
    }
}

/// Elastic-search failures.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ElasticError {
    #[error("the {side} wheel is off its rail laterally (no wheel point over the rail head at y = {y_mm:.2} mm): the wheelset has derailed")]
    OffRail { side: &'static str, y_mm: f64 },
    #[error("the {side} wheel is {depth_mm:.2} mm inside its rail at y = {y_mm:.2} mm: no contact approach (a Hertz approach is tenths of a millimetre) — an initial state or a pose off the profiles")]
    Interpenetration {
        side: &'static str,
        depth_mm: f64,
        y_mm: f64,
    },
    #[error("the {side} wheel climbs its flange: a contact at s^w = {s_wheel_mm:.2} mm, past the flange's largest contact angle ({angle_deg:.1}° at {limit_mm:.2} mm), at y = {y_mm:.2} mm")]
    FlangeClimb {
        side: &'static str,
        y_mm: f64,
        s_wheel_mm: f64,
        limit_mm: f64,
        angle_deg: f64,
    },
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::profile::placement::WheelRailPair;
    use crate::profile::StandardProfile;

    fn search(rail: StandardProfile, incl: &str) -> ElasticContact {
        let pair = WheelRailPair::standard(StandardProfile::S1002, rail, incl).unwrap();
        ElasticContact::new(ContactGeometry::with_defaults(pair), 2.5e-4, 2.0)
    }

    fn rails(off: &RailOffsets) -> RailMotion {
        RailMotion {
            q: [off.y_left, off.z_left, off.y_right, off.z_right],
            ..RailMotion::default()
        }
    }

    /// At the online constraints' solution (Newton on Eq. 35–36, an independent solver seeded by
    /// its own global search) every wheel just touches: the search finds a gap of zero there, at
    /// the same wheel point (away from the contact jumps), on ideal and on displaced rails; sunk
    /// by Δ, each wheel's deepest contact approaches by Δ n_Z along its normal (closed form for
    /// locally parallel surfaces).
    #[test]
    fn the_rigid_solution_touches_and_a_sink_approaches_by_its_normal_component() {
        for (rail, incl) in [
            (StandardProfile::Rail60E1, "1:40"),
            (StandardProfile::Rail54E1, "1:20"),
        ] {
            let e = search(rail, incl);
            // Displaced rails: the alignment moves the flange contact by 1 mm (the relative
            // displacement stays short of the flange's largest angle).
            for (off, ys) in [
                (
                    RailOffsets::default(),
                    [-6e-3, -4e-3, -1.5e-3, 0.0, 2.5e-3, 4.5e-3, 6e-3],
                ),
                (
                    RailOffsets::from_irregularities(0.001, 0.002, 0.0015, -0.001),
                    [-5e-3, -4e-3, -1.5e-3, 0.0, 2.5e-3, 4.5e-3, 6e-3],
                ),
            ] {
                for y in ys {
                    let sol = e.geometry.solve(y, &off).unwrap();
                    let pose = FreePose {
                        y,
                        z: sol.z,
                        phi: sol.phi,
                        ..FreePose::default()
                    };
                    let c = e.search(&pose, &rails(&off)).unwrap();
                    for (i, point) in [sol.left, sol.right].iter().enumerate() {
                        assert!(
                            c.gap[i].abs() < 2e-7,
                            "{incl} y = {y}: wheel {i} gap {:.3e} m",
                            c.gap[i]
                        );
                        if sol.secondary.is_empty() {
                            assert!(
                                (c.closest[i].s_wheel - point.s_wheel).abs() < 1e-4,
                                "{incl} y = {y}: wheel {i} at s^w {:.5} vs online {:.5}",
                                c.closest[i].s_wheel,
                                point.s_wheel
                            );
                        }
                    }
                    let sink = 5e-5;
                    let c = e
                        .search(
                            &FreePose {
                                z: sol.z - sink,
                                ..pose
                            },
                            &rails(&off),
                        )
                        .unwrap();
                    for i in 0..2 {
                        let p = c.points[i][0].unwrap();
                        let expected = sink * p.point.normal.1;
                        assert!(
                            (p.depth - expected).abs() < 0.02 * expected,
                            "{incl} y = {y}: wheel {i} depth {:.4e} vs Δ n_Z {:.4e}",
                            p.depth,
                            expected
                        );
                        // The deepest of a wheel's contacts is in a region of its own or shares it.
                        assert!(p.share > 0.0 && p.share <= 1.0 + 1e-12);
                    }
                }
            }
        }
    }

    /// A wheel lifted by h above the touching pose has no contact and a gap of h n_Z.
    #[test]
    fn a_lifted_wheel_has_no_contact_and_its_gap() {
        let e = search(StandardProfile::Rail60E1, "1:40");
        let sol = e.geometry.solve(0.0, &RailOffsets::default()).unwrap();
        // Roll about the right contact so that the left wheel rises by ~0.3 mm.
        let lift = 3e-4;
        let arm = sol.left.position.0 - sol.right.position.0;
        let pose = FreePose {
            y: 0.0,
            z: sol.z + 0.5 * lift,
            phi: sol.phi + lift / arm,
            ..FreePose::default()
        };
        let c = e.search(&pose, &RailMotion::default()).unwrap();
        assert!(c.of(0).next().is_none(), "{:?}", c.points[0]);
        let expected = lift * sol.left.normal.1;
        assert!(
            (c.gap[0] - expected).abs() < 0.03 * expected,
            "gap {:.4e} vs {expected:.4e}",
            c.gap[0]
        );
    }

    /// The approach rate is the closing speed along the normal: sinking at ż gives δ̇ = −ż n_Z; a
    /// rail rising at ż_r gives +ż_r n_Z.
    #[test]
    fn the_approach_rate_is_the_closing_speed() {
        let e = search(StandardProfile::Rail60E1, "1:40");
        let sol = e.geometry.solve(1e-3, &RailOffsets::default()).unwrap();
        let pose = FreePose {
            y: 1e-3,
            z: sol.z - 5e-5,
            phi: sol.phi,
            z_dot: -0.01,
            ..FreePose::default()
        };
        let mut moving = RailMotion::default();
        moving.q_dot[1] = 0.02;
        let c = e.search(&pose, &moving).unwrap();
        let l = c.points[0][0].unwrap();
        let r = c.points[1][0].unwrap();
        assert!((l.rate - 0.03 * l.point.normal.1).abs() < 1e-9, "{}", l.rate);
        assert!((r.rate - 0.01 * r.point.normal.1).abs() < 1e-9, "{}", r.rate);
    }

    /// The constraint models' range (the tables', the KEC profiles') ends where the elastic model
    /// sees a flange climb: the contact geometry's scan up the flange and the wheel profile's own
    /// slope (independent: one solves the rigid contact, the other reads the wheel's tangent) put
    /// the end of S1002's steepest flank towards the tip at the same wheel point, at the same
    /// angle (in the wheel's frame: the contact angle less the roll). On these pairs the rigid
    /// contact jumps onto the flank close to that end.
    #[test]
    fn the_contact_range_ends_at_the_end_of_the_flanges_steepest_flank() {
        for (rail, inclination) in [
            (StandardProfile::Rail60E1, "1:40"),
            (StandardProfile::Rail54E1, "1:20"),
        ] {
            let e = search(rail, inclination);
            let off = RailOffsets::default();
            let (sw_limit, angle) = e.flange_limit(Side::Left);
            let limit = crate::contact::lookup::flange_contact_limit(&e.geometry, &off, true).unwrap();
            let end = e.geometry.solve(limit, &off).unwrap();
            let wheel_angle = end.left.contact_angle - end.phi;
            println!(
                "{rail:?} {inclination}: range to y = {:.3} mm, contact at s^w = {:.3} mm ({:.2}° on the wheel); elastic limit s^w = {:.3} mm (largest angle {:.2}°)",
                limit * 1e3,
                end.left.s_wheel * 1e3,
                wheel_angle.to_degrees(),
                sw_limit * 1e3,
                angle.to_degrees(),
            );
            assert!(
                (end.left.s_wheel - sw_limit).abs() < 5e-5,
                "{} vs {sw_limit}",
                end.left.s_wheel
            );
            let tolerance = crate::contact::lookup::FLANGE_FLANK_TOLERANCE_RAD;
            assert!(
                (wheel_angle - (angle - tolerance)).abs() < 0.2f64.to_radians(),
                "{}",
                wheel_angle.to_degrees()
            );
        }
    }

    /// The flange's largest contact angle from the wheel profile's steepest point agrees with the
    /// contact geometry's flange scan (the largest contact angle the online solution reaches,
    /// `lookup::flange_angle`); a wheelset pushed past the online flange-contact limit has its
    /// contact past that point — a flange climb, reported as such (the left wheel at +y) — and
    /// short of it none.
    #[test]
    fn a_contact_past_the_flanges_largest_angle_is_a_flange_climb() {
        let e = search(StandardProfile::Rail60E1, "1:40");
        let scan = crate::contact::lookup::flange_angle(&e.geometry).unwrap();
        for side in Side::BOTH {
            let (_, angle) = e.flange_limit(side);
            assert!(
                (angle - scan).abs() < 0.5f64.to_radians(),
                "{side:?}: {} vs {}",
                angle.to_degrees(),
                scan.to_degrees()
            );
        }
        let off = RailOffsets::default();
        let limit = crate::contact::lookup::flange_contact_limit(&e.geometry, &off, true).unwrap();
        let at = |y: f64| {
            let sol = e.geometry.solve(y, &off).unwrap();
            let pose = FreePose {
                y,
                z: sol.z - 2e-5,
                phi: sol.phi,
                ..FreePose::default()
            };
            e.search(&pose, &RailMotion::default())
        };
        assert!(at(limit - 5e-4).is_ok());
        match at(limit + 1e-3) {
            Err(ElasticError::FlangeClimb { side, .. }) => assert_eq!(side, "left"),
            other => panic!("past the limit {limit}: {other:?}"),
        }
    }

    /// A wheel millimetres inside its rail is no contact approach: reported, not turned into a
    /// force of meganewtons.
    #[test]
    fn a_wheel_deep_inside_its_rail_is_an_error() {
        let e = search(StandardProfile::Rail60E1, "1:40");
        let sol = e.geometry.solve(0.0, &RailOffsets::default()).unwrap();
        let pose = |sink: f64| FreePose {
            z: sol.z - sink,
            phi: sol.phi,
            ..FreePose::default()
        };
        assert!(e.search(&pose(1.5e-3), &RailMotion::default()).is_ok());
        match e.search(&pose(3e-3), &RailMotion::default()) {
            Err(ElasticError::Interpenetration { side, depth_mm, .. }) => {
                assert_eq!(side, "left");
                assert!(depth_mm > 2.0, "{depth_mm}");
            }
            other => panic!("{other:?}"),
        }
    }

    /// The shares: separate regions in full, a shoulder not at all, two equal minima over a shallow
    /// hump half each, and continuity where a region splits and where the deeper one swaps.
    #[test]
    fn shares_count_regions_once_and_are_continuous() {
        // Two minima at samples 0 and 10 with depths d0, d1 and the pass gap p between them.
        let w = |d0: f64, d1: f64, p: f64| shares(&[(0, d0), (10, d1)], |_, _| p);
        assert_eq!(w(5e-5, 3e-5, 1e-6), vec![1.0, 1.0]);
        let shoulder = w(5e-5, 3e-5, -3e-5);
        assert!(
            (shoulder[0] - 1.0).abs() < 1e-12 && shoulder[1].abs() < 1e-12,
            "{shoulder:?}"
        );
        let flat = w(5e-5, 5e-5, -4.99e-5);
        assert!(flat.iter().all(|s| (s - 0.501).abs() < 1e-3), "{flat:?}");
        // Splitting: the pass crossing zero.
        let (a, b) = (w(5e-5, 3e-5, -1e-12), w(5e-5, 3e-5, 1e-12));
        assert!(
            (a[0] - b[0]).abs() < 1e-6 && (a[1] - b[1]).abs() < 1e-6,
            "{a:?} {b:?}"
        );
        // Swapping: equal depths from either side.
        let (a, b) = (w(4e-5 + 1e-12, 4e-5, -2e-5), w(4e-5, 4e-5 + 1e-12, -2e-5));
        assert!(
            (a[0] - b[0]).abs() < 1e-6 && (a[1] - b[1]).abs() < 1e-6,
            "{a:?} {b:?}"
        );
        // A region of its own beside a shared one keeps its full share.
        let three = shares(&[(0, 5e-5), (10, 4e-5), (20, 4e-5)], |a, b| {
            if a.max(b) == 20 && a.min(b) == 10 {
                -3.9e-5
            } else {
                1e-6
            }
        });
        assert!((three[0] - 1.0).abs() < 1e-12, "{three:?}");
        assert!(
            three[1] > 0.4 && three[1] < 0.6 && (three[1] - three[2]).abs() < 1e-12,
            "{three:?}"
        );
    }
}
