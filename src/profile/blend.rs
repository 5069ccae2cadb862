//! A rail head whose curvature is continuous: the published tangent arcs (R300, R80, R13 of
//! EN 13674-1) with the curvature jump at each arc–arc joint blended over ± w of arc length
//! (issue 52). A model change, and stated as one: a measured rail is smooth, the published
//! construction's curvature jumps (1/300 → 1/80 → 1/13 mm⁻¹) are a drawing convention; where the
//! contact crosses one, Hertz's semi-axes jump (b 0.9 ↔ 15.8 mm across ±0.3 mm on the designed
//! wheels), the contact point sweeps millimetres of the wheel within micrometres of wheelset y, and
//! the integrator pays in rejected steps (`../shared/design/SPEED.md`, last section).
//!
//! **Construction.** The head is built from its curvature as a function of the arc length s
//! from the crown's top (the section is symmetric): κ(s) = 1/R_i on each arc, and across the
//! joint at s_j
//!
//! ```text
//! κ(s) = κ_A + (κ_B − κ_A) S(u),   u = (s − s_j + w) / 2w ∈ [0, 1],   S(u) = 10u³ − 15u⁴ + 6u⁵
//! ```
//!
//! (S the quintic smoothstep: κ is C¹, the profile C³, the curvature monotone between the two
//! radii). The tangent angle θ(s) = ∫κ ds is integrated in closed form; since S − H(u − ½) is odd
//! about the joint, θ leaves each blend at the published joint's angle plus the published arc's,
//! so every arc keeps its radius and its angular extent, and the R13 meets the 1:20 flank
//! (tan θ = 20) as published. The position x = ∫cos θ ds, depth d = ∫sin θ ds are integrated by
//! Simpson's rule on 1 µm steps. The price: the arcs beyond a blend are moved by a few µm
//! (normal to the head: ≤ 7 µm at w = 1 mm on 54E1, [`max_shape_change_mm`]); the flank's joint
//! with the R13 (at 87°, where no wheel touches) is kept as published.
//!
//! Why not blend the two arcs' functions, g = (1 − S) g_A + S g_B, keeping both arcs where
//! they are? Two internally tangent circles cannot be joined by a curve of monotone curvature
//! without moving one of them (the *shift* of a transition between the arcs of a compound curve);
//! the function blend over ±1 mm overshoots to R10.6 and to a concave bump (R − 207 mm) at the
//! R80/R13 joint. Here the arcs move by micrometres instead.

/// The published rail head: the radii (mm, crown first) and where each arc ends (|y|, mm).
#[derive(Debug, Clone, Copy)]
pub struct RailHead {
    /// Crown R300, then R80, then R13.
    pub radii_mm: [f64; 3],
    /// |y| where the R300 and the R80 end, mm.
    pub arc_ends_mm: [f64; 2],
    /// Slope of the straight flank (20: 1:20).
    pub flank_slope: f64,
    /// Depth below the top of rail down to which the flank is drawn, mm.
    pub flank_depth_mm: f64,
}

/// Integration step along the arc length, mm.
const STEP_MM: f64 = 1e-3;

/// Largest blend half-width accepted, mm: the blends of the R300/R80 and R80/R13 joints must not
/// overlap, nor reach the flank (on 54E1 the R80 spans 11.1 mm of arc, the R13 12.4 mm).
pub const MAX_BLEND_MM: f64 = 3.0;

impl RailHead {
    /// Arc lengths from the crown's top to the two blended joints and to the flank, mm, and the
    /// tangent angles there (rad).
    pub(crate) fn joints(&self) -> ([f64; 3], [f64; 3]) {
        let [r1, r2, r3] = self.radii_mm;
        let [x1, x2] = self.arc_ends_mm;
        let th1 = (x1 / r1).asin();
        let x20 = (r1 - r2) * th1.sin();
        let th2 = ((x2 - x20) / r2).asin();
        let th3 = self.flank_slope.atan();
        let s1 = r1 * th1;
        let s2 = s1 + r2 * (th2 - th1);
        let s3 = s2 + r3 * (th3 - th2);
        ([s1, s2, s3], [th1, th2, th3])
    }

    /// Curvature κ(s), 1/mm (convex head: positive), with the joints at s1 and s2 blended over
    /// ± `w` mm; `w = 0` gives the published jumps. (The construction uses its integral,
    /// `angle`; this is the tests' view of it.)
    #[cfg(test)]
    pub fn curvature(&self, s: f64, w: f64) -> f64 {
        let ([s1, s2, s3], _) = self.joints();
        let k = self.radii_mm.map(|r| 1.0 / r);
        if s >= s3 {
            return 0.0;
        }
        let step = |sj: f64, ka: f64, kb: f64| {
            if w <= 0.0 {
                return if s < sj { ka } else { kb };
            }
            let u = ((s - sj + w) / (2.0 * w)).clamp(0.0, 1.0);
            ka + (kb - ka) * smoothstep(u)
        };
        if s < 0.5 * (s1 + s2) {
            step(s1, k[0], k[1])
        } else {
            step(s2, k[1], k[2])
        }
    }

    /// Tangent angle θ(s) = ∫₀ˢ κ ds, rad, in closed form (S's integral is u⁴(5/2 − 3u + u²)).
    fn angle(&self, s: f64, w: f64) -> f64 {
        let ([s1, s2, s3], [_, _, th3]) = self.joints();
        let k = self.radii_mm.map(|r| 1.0 / r);
        if s >= s3 {
            return th3;
        }
        // ∫ from −∞ of the step from ka to kb at sj, less ka·s: the jump's share.
        let jump = |sj: f64, dk: f64| {
            if w <= 0.0 {
                return dk * (s - sj).max(0.0);
            }
            let u = (s - sj + w) / (2.0 * w);
            let i = if u <= 0.0 {
                0.0
            } else if u >= 1.0 {
                0.5 + (u - 1.0)
            } else {
                u.powi(4) * (2.5 - 3.0 * u + u * u)
            };
            dk * 2.0 * w * i
        };
        k[0] * s + jump(s1, k[1] - k[0]) + jump(s2, k[2] - k[1])
    }

    /// The half head's points (y from the centreline, depth below the top; mm) every `ds` mm of
    /// arc length from the crown's top to the flank's end, the joints blended over ± `w` mm.
    pub fn half_points(&self, w: f64, ds: f64) -> Vec<(f64, f64)> {
        let ([_, _, s3], [_, _, th3]) = self.joints();
        let n_head = (s3 / STEP_MM).ceil() as usize;
        let h = s3 / n_head as f64;
        // Simpson on pairs of steps; points kept every ~ds.
        let keep = ((ds / (2.0 * h)).round() as usize).max(1);
        let (mut x, mut d) = (0.0, 0.0);
        let mut pts = vec![(0.0, 0.0)];
        let mut pair = 0;
        let mut k = 0;
        while k + 2 <= n_head {
            let (sa, sm, sb) = (k as f64 * h, (k as f64 + 1.0) * h, (k as f64 + 2.0) * h);
            let (ta, tm, tb) = (self.angle(sa, w), self.angle(sm, w), self.angle(sb, w));
            x += h / 3.0 * (ta.cos() + 4.0 * tm.cos() + tb.cos());
            d += h / 3.0 * (ta.sin() + 4.0 * tm.sin() + tb.sin());
            k += 2;
            pair += 1;
            if pair % keep == 0 || k + 2 > n_head {
                pts.push((x, d));
            }
        }
        if k < n_head {
            // An odd step count: the last step by the trapezoid (h ≤ 1 µm, θ smooth).
            let (sa, sb) = (k as f64 * h, s3);
            let (ta, tb) = (self.angle(sa, w), self.angle(sb, w));
            x += 0.5 * (sb - sa) * (ta.cos() + tb.cos());
            d += 0.5 * (sb - sa) * (ta.sin() + tb.sin());
            pts.push((x, d));
        }
        // The flank, straight at th3 down to the flank depth.
        let (x3, d3) = (x, d);
        let run = (self.flank_depth_mm - d3) / th3.sin();
        let n = (run / ds).ceil().max(1.0) as usize;
        for j in 1..=n {
            let l = run * j as f64 / n as f64;
            pts.push((x3 + l * th3.cos(), d3 + l * th3.sin()));
        }
        pts
    }

    /// The whole head (both halves), y increasing, every `ds` mm of arc length.
    pub fn points(&self, w: f64, ds: f64) -> Vec<(f64, f64)> {
        let half = self.half_points(w, ds);
        let mut pts: Vec<(f64, f64)> = half.iter().rev().map(|&(x, d)| (-x, d)).collect();
        pts.extend(half.into_iter().skip(1));
        pts
    }
}

/// The quintic smoothstep 10u³ − 15u⁴ + 6u⁵ (0 → 1 on [0, 1], first and second derivatives 0 at
/// both ends).
#[cfg(test)]
fn smoothstep(u: f64) -> f64 {
    u * u * u * (10.0 + u * (-15.0 + 6.0 * u))
}

/// Largest distance, normal to the head, between the blended head (± `w` mm) and the published
/// one over the head's width, mm (the shape change the blend is).
pub fn max_shape_change_mm(head: &RailHead, published: &dyn Fn(f64) -> f64, w: f64) -> f64 {
    head.half_points(w, 0.01)
        .iter()
        .map(|&(x, d)| {
            let (g, slope) = (published(x), {
                let e = 1e-4;
                (published(x + e) - published(x - e)) / (2.0 * e)
            });
            (d - g).abs() / (1.0 + slope * slope).sqrt()
        })
        .fold(0.0, f64::max)
}
