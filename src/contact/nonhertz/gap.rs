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
    /// Index of the contact's own sample (s = s_w or s_r) in the graph.
    centre: usize,
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
        let keep = |mut v: Vec<f64>| {
            v.truncate(hi + 1);
            v.drain(..lo);
            v
        };
        Graph {
            w: keep(w),
            v: keep(v),
            s: keep(s),
            x: keep(x),
            centre: c - lo,
        }
    }

    /// The w-range of the graph a sampling of `n_half` steps each side of the contact gives: the
    /// same samples (the same s-grid), the part of them this graph holds.
    fn extent(&self, n_half: usize) -> (f64, f64) {
        let lo = self.centre.saturating_sub(n_half);
        let hi = (self.centre + n_half).min(self.w.len() - 1);
        (self.w[lo], self.w[hi])
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

/// Samples each side of the contact for a window's half-width (clamped to 1–100 mm).
fn half_samples(half_window: f64) -> (f64, usize) {
    let half_window = half_window.clamp(GAP_STEP_M * 10.0, 0.1);
    (half_window, (half_window / GAP_STEP_M).round() as usize)
}

/// Both profiles sampled as graphs across the approach direction, with what the gap on a grid
/// needs.
struct Graphs {
    rail: Graph,
    wheel: Graph,
    side: Side,
    nominal_radius: f64,
    rail_angle: f64,
    approach_angle: f64,
    /// Both samplings hold the contact's own sample (it lies in its profile's domain): a narrower
    /// window's samples are then a part of these.
    centred: bool,
}

impl Graphs {
    fn new(wheel: &Profile, rail: &Profile, input: &GapInput) -> Result<Graphs, GapError> {
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
        let (_, n_half) = half_samples(half_window);
        let mut centred = true;
        let mut sample = |centre: f64, domain: (f64, f64), f: &dyn Fn(f64) -> ((f64, f64), f64)| {
            let mut s = Vec::with_capacity(2 * n_half + 1);
            let mut w = Vec::with_capacity(2 * n_half + 1);
            let mut v = Vec::with_capacity(2 * n_half + 1);
            let mut x = Vec::with_capacity(2 * n_half + 1);
            let mut c_idx = None;
            for i in 0..=2 * n_half {
                let si = centre + (i as f64 - n_half as f64) * GAP_STEP_M;
                if si < domain.0 || si > domain.1 {
                    continue;
                }
                if i == n_half {
                    c_idx = Some(s.len());
                }
                let (p, xi) = f(si);
                let (wi, vi) = to_uv(p);
                s.push(si);
                w.push(wi - w0);
                v.push(vi);
                x.push(xi);
            }
            centred &= c_idx.is_some();
            Graph::monotone_around(s, w, v, x, c_idx.unwrap_or(0))
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
        let rail_graph = sample(s_rail, rail.domain_side(side), &rail_xy);
        let wheel_graph = sample(s_wheel, wheel.domain_side(side), &wheel_xy);
        Ok(Graphs {
            rail: rail_graph,
            wheel: wheel_graph,
            side,
            nominal_radius,
            rail_angle,
            approach_angle,
            centred,
        })
    }

    /// The grid's index range (w = i GAP_STEP_M) of the gap sampled over `half_window`.
    fn range(&self, half_window: f64) -> Result<(i64, i64), GapError> {
        let (half_window, n_half) = half_samples(half_window);
        let (r0, r1) = self.rail.extent(n_half);
        let (w0, w1) = self.wheel.extent(n_half);
        let lo = r0.max(w0).max(-half_window);
        let hi = r1.min(w1).min(half_window);
        if !(lo < -GAP_STEP_M && hi > GAP_STEP_M) {
            return Err(GapError::Folded(1e3 * lo.abs().min(hi.abs())));
        }
        Ok(((lo / GAP_STEP_M).ceil() as i64, (hi / GAP_STEP_M).floor() as i64))
    }

    /// The gap on the grid `range`.
    fn section(&self, (i_lo, i_hi): (i64, i64)) -> GapSection {
        let (rg, wg) = (&self.rail, &self.wheel);
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
        let sigma = self.side.sign();
        for i in i_lo..=i_hi {
            let x = i as f64 * GAP_STEP_M;
            let (vr, sr, dzr) = rg.at(x, &mut kr);
            let (vw, sw, zw) = wg.at(x, &mut kw);
            // Rail slope against w: the profile's slope angle less the approach angle.
            let angle = dzr.atan();
            out.w.push(x);
            out.gap.push(vw - vr);
            out.s_rail.push(sr);
            out.s_wheel.push(sw);
            out.cos_slope.push((angle + self.approach_angle).cos().max(1e-3));
            out.contact_angle.push(sigma * angle + self.rail_angle * sigma);
            out.radius.push(self.nominal_radius - zw);
        }
        out
    }
}

impl GapSection {
    /// The gap around the contact (see the module's documentation).
    pub fn new(wheel: &Profile, rail: &Profile, input: &GapInput) -> Result<GapSection, GapError> {
        let g = Graphs::new(wheel, rail, input)?;
        Ok(g.section(g.range(input.half_window)?))
    }

    /// The gap around the contact over `input`'s window and over a narrower one (`narrow_half`,
    /// m), made from one sampling of the profiles: each the same, to the last bit, as
    /// [`GapSection::new`] with that window (the narrower one a part of the wider: the same
    /// s-grid of samples, the same w-grid). (narrow, wide); the narrow one is its error where it
    /// cannot be made. What a solution that tries the narrow window first, and the wide one where
    /// the patch reaches the narrow one's end, needs.
    pub fn nested(
        wheel: &Profile,
        rail: &Profile,
        input: &GapInput,
        narrow_half: f64,
    ) -> Result<(Result<GapSection, GapError>, GapSection), GapError> {
        let g = Graphs::new(wheel, rail, input)?;
        let (lo, hi) = g.range(input.half_window)?;
        let wide = g.section((lo, hi));
        let narrow = if !g.centred || narrow_half.is_nan() || narrow_half > input.half_window {
            GapSection::new(
                wheel,
                rail,
                &GapInput {
                    half_window: narrow_half,
                    ..*input
                },
            )
        } else {
            g.range(narrow_half).map(|(nlo, nhi)| {
                // Inside the wide range: the narrow window's samples are a part of the wide's.
                let (a, b) = ((nlo.max(lo) - lo) as usize, (nhi.min(hi) - lo) as usize);
                let cut = |v: &[f64]| v[a..=b].to_vec();
                GapSection {
                    w: cut(&wide.w),
                    gap: cut(&wide.gap),
                    s_rail: cut(&wide.s_rail),
                    s_wheel: cut(&wide.s_wheel),
                    cos_slope: cut(&wide.cos_slope),
                    contact_angle: cut(&wide.contact_angle),
                    radius: cut(&wide.radius),
                    contact: (-nlo) as usize,
                }
            })
        };
        Ok((narrow, wide))
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

    /// The nested sections are the separate ones, to the last bit, over contacts across the tread
    /// and flange of two pairs (the designed wheel on the blended rail; S1002 on 60E1), along the
    /// normal and along the vertical, both sides — and where the narrow window cannot be made the
    /// error is the separate one's.
    #[test]
    fn nested_sections_are_the_separate_ones() {
        use crate::contact::geometry::ContactGeometry;
        use crate::profile::embedded::EmbeddedProfile;
        use crate::profile::placement::WheelRailPair;
        use crate::profile::placement::WheelsetGeometry;
        use crate::profile::ProfileKind;
        use crate::track::RailOffsets;
        use crate::track::TrackGauge;
        let tram = WheelRailPair::new(
            EmbeddedProfile::from_name("ms-tram").unwrap().profile().unwrap(),
            Profile::resolve("54e1:blend=1", ProfileKind::Rail).unwrap(),
            "1:20".parse().unwrap(),
            TrackGauge::default(),
            WheelsetGeometry {
                back_to_back_m: 1.366,
                nominal_radius_m: 0.295,
                ..WheelsetGeometry::default()
            },
        );
        let pairs = [
            tram,
            WheelRailPair::standard(StandardProfile::S1002, StandardProfile::Rail60E1, "1:40"),
        ];
        let mut compared = 0;
        for pair in pairs {
            let pair = pair.unwrap();
            let geom = ContactGeometry::with_defaults(pair.clone());
            for k in -16..=16 {
                let sol = geom.solve(k as f64 * 5e-4, &RailOffsets::default()).unwrap();
                for side in Side::BOTH {
                    let p = sol.point(side);
                    for along_normal in [true, false] {
                        let input = GapInput {
                            side,
                            s_wheel: p.s_wheel,
                            s_rail: p.s_rail,
                            nominal_radius: pair.wheelset.nominal_radius_m,
                            rail_angle: side.sign() * pair.inclination.angle_rad,
                            approach_angle: if along_normal {
                                GapInput::along_normal(&pair.rail, side, p.s_rail)
                            } else {
                                0.0
                            },
                            half_window: GAP_WINDOW_M,
                        };
                        let (narrow, wide) =
                            GapSection::nested(&pair.wheel, &pair.rail, &input, 0.008).unwrap();
                        let alone_wide = GapSection::new(&pair.wheel, &pair.rail, &input).unwrap();
                        let alone_narrow = GapSection::new(
                            &pair.wheel,
                            &pair.rail,
                            &GapInput {
                                half_window: 0.008,
                                ..input
                            },
                        );
                        let bits = |g: &GapSection| {
                            [
                                &g.w,
                                &g.gap,
                                &g.s_rail,
                                &g.s_wheel,
                                &g.cos_slope,
                                &g.contact_angle,
                                &g.radius,
                            ]
                            .iter()
                            .flat_map(|v| v.iter().map(|x| x.to_bits()))
                            .chain([g.contact as u64])
                            .collect::<Vec<u64>>()
                        };
                        assert_eq!(
                            bits(&wide),
                            bits(&alone_wide),
                            "wide, y = {} mm, {side:?}",
                            k as f64 * 0.5
                        );
                        match (narrow, alone_narrow) {
                            (Ok(a), Ok(b)) => {
                                assert!(a.w.len() < wide.w.len());
                                assert_eq!(bits(&a), bits(&b), "narrow, y = {} mm, {side:?}", k as f64 * 0.5);
                                compared += 1;
                            }
                            (a, b) => assert_eq!(a.err(), b.err()),
                        }
                    }
                }
            }
        }
        assert!(compared > 200, "{compared} narrow sections compared");
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
