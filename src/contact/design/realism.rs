//! Realism checks of a wheel on its rail over the running band (issue 48): is the designed
//! contact one a real tread and flange could have, or a mathematical conjugate that only the
//! rigid kinematics like?
//!
//! The band is the centred gauge's flange-to-flange range of the 1-entry table (the left wheel
//! from its field side, y = lo, to its flange contact, y = hi); the pair is symmetric, so the
//! left wheel's contact over the whole band covers every point of the rail it touches. Each
//! figure comes from the table's rows (Hermite-interpolated every [`SAMPLE_STEP_M`]):
//!
//! * **(a) Curvature margin** m = (R_w − R_r)/R_r of the concave wheel over the convex rail at the
//!   contact; with the lateral curvatures κ (positive where convex) m = (κ_r + κ_w)/(−κ_w) where
//!   the wheel is concave and +∞ where it is straight or convex (no conformity). For a conjugate
//!   wheel at zero roll m = Δ/R_r with Δ = (dy/dγ)/cos γ ([`super`]). m → 0 is a conformal
//!   contact: the rigid gap stays at microns over a wide band, Hertz's half-space assumption
//!   (contact size ≪ relative radius R_r R_w/(R_w − R_r) = R_r (1 + m)/m; Johnson, *Contact
//!   Mechanics*, 1985, §4.1) fails, and any wear or tolerance moves the contact by millimetres.
//!   Threshold [`MARGIN_MIN`] = 10 % on every rail arc, away from its joints (±[`JOINT_WINDOW_M`]) — the low end of the 10–15 % the review of
//!   issue 48 asks for; a design choice, not a standard (no standard sets one). Worn wheels
//!   drift towards conformity, which raises the conicity (Polach & Nicklisch, Wear 360–361,
//!   2016, 111–127: "an increase of the contact conformity with wear").
//! * **(b) Contact speed** |ds_w/dy| and |ds_r/dy|: how fast the contact runs along the wheel and
//!   the rail as the wheelset moves. At zero roll ds_r/dy = R_r dγ/dy = 1/m and
//!   ds_w/dy = R_w dγ/dy = 1 + 1/m, so the margin bounds them: [`RAIL_SPEED_MAX`] = 10 and
//!   [`WHEEL_SPEED_MAX`] = 11 are the 10 % margin's (checked off the joint regions, like (a)). A contact that runs 60× faster than the
//!   wheelset puts the kinematics' error in y sixty-fold into the contact position (the forces act
//!   there) and concentrates the wear of a whole band on a few tenths of a millimetre of y.
//! * **(c) Dwell on the rail's arc joints**: the y span over which the rail contact point stays
//!   within ±[`JOINT_TOLERANCE_M`] of a joint between two rail arcs (where the rail's curvature
//!   jumps; found by [`rail_joints`]). Crossing the joint region at ds_r/dy ≥ 1 — the contact
//!   moving along the rail at least as fast as the wheelset moves — takes at most
//!   2 × [`JOINT_TOLERANCE_M`] = [`DWELL_MAX_M`]. A longer dwell parks the contact, its
//!   curvatures (the Hertz ellipse) and its wear on a line where the rail's shape is not smooth;
//!   it is what a conjugate wheel does when its own curvature is ramped slowly across the rail's
//!   jump ([`super::CURVATURE_RAMP_PER_RAD`]).
//! * **(d) Equivalent conicity** (EN 15302 Annex B, [`crate::contact::conicity`]) at 2, 3, 4 mm.
//!   EN 15302 sets no limit (its scope says so). Threshold [`CONICITY_MAX`] = 0.4 at amplitudes
//!   at least [`CONICITY_WALL_CLEARANCE_M`] inside the wall (y below the contact angle's 35°):
//!   the upper end of worn wheels in
//!   service (Polach & Nicklisch 2016 report the conicity of worn profiles rising to ~0.4–0.5
//!   with mileage); a new tread (1:20 cone on a 1:20 rail) gives ~0.05, S1002 on 54E1 at 1:20
//!   0.015. Amplitudes that come within 1 mm of the wall measure the flange root, not the
//!   tread, and are reported without a limit.
//! * **(e) The wall**: where the contact angle passes [`WALL_ANGLE_RAD`] = 35° — there the
//!   gravitational restoring force N (tan γ − tan γ_0) reaches the saturated lateral creep force
//!   of an IRW wheel (μ ≈ 0.3–0.4 of the load), so a wheelset pushed by its creep force stops
//!   there (the MS stand-in's reasoning, docs/method.md).

use crate::contact::lookup::{LookupTable1, TableError};
use crate::profile::Profile;

/// Smallest curvature margin (R_w − R_r)/R_r accepted on a rail arc.
pub const MARGIN_MIN: f64 = 0.10;
/// Largest |ds_r/dy| accepted: 1/[`MARGIN_MIN`].
pub const RAIL_SPEED_MAX: f64 = 10.0;
/// Largest |ds_w/dy| accepted: 1 + 1/[`MARGIN_MIN`].
pub const WHEEL_SPEED_MAX: f64 = 11.0;
/// Half-width of the joint region on the rail, m (the profiles' point spacing).
pub const JOINT_TOLERANCE_M: f64 = 1e-4;
/// Longest dwell accepted in a joint region, m of y.
pub const DWELL_MAX_M: f64 = 2e-4;
/// Largest equivalent conicity accepted below the wall.
pub const CONICITY_MAX: f64 = 0.4;
/// Amplitudes of the conicity check, m.
pub const CONICITY_AMPLITUDES_M: [f64; 3] = [2e-3, 3e-3, 4e-3];
/// The wall's contact angle, rad (35°).
pub const WALL_ANGLE_RAD: f64 = 0.610_865_238_198_015_3;
/// Step of the sweep over the band, m.
pub const SAMPLE_STEP_M: f64 = 1e-6;
/// A change of the rail's curvature radius by this factor within ±[`JOINT_WINDOW_M`] marks a
/// joint between two arcs.
pub const JOINT_RATIO: f64 = 1.5;
/// Half-width of the window across which [`rail_joints`] compares the rail's radii, m; also the
/// half-width of the joint regions left out of the per-arc margin and the speed checks: a rail
/// drawn as a C² spline through points of its arcs (kecsim's 54E1, 60E1: every 0.1 mm and at
/// each joint) rings next to each curvature jump — its radius 0.3–0.5 mm from 54E1's joints
/// is still 2–5 % off (R307 for R300, R84 for R80), closer in it swings far more — so there
/// the figures measure the spline, not the arcs; the joint region has its own check (c), and
/// its speeds are reported apart.
pub const JOINT_WINDOW_M: f64 = 5e-4;
/// How far inside the wall the conicity limit applies, m: amplitudes closer to the wall than
/// this ride the flange root and measure the flange (EN 15302's 3 mm on standard track stand
/// 2–4 mm inside a mainline wheel's flange contact).
pub const CONICITY_WALL_CLEARANCE_M: f64 = 1e-3;
/// Radius standing for a straight stretch of the rail, m.
pub const STRAIGHT_RADIUS_M: f64 = 10.0;

/// A joint between two arcs of a rail head (left orientation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RailJoint {
    /// Surface parameter of the joint, m.
    pub s: f64,
    /// Radii of curvature below and above s, m ([`STRAIGHT_RADIUS_M`] for a straight stretch).
    pub radii: (f64, f64),
}

/// The rail's radius of curvature at s, m, capped at [`STRAIGHT_RADIUS_M`].
fn rail_radius(rail: &Profile, s: f64) -> f64 {
    let k = -rail.eval(s).curvature();
    if k > 1.0 / STRAIGHT_RADIUS_M {
        1.0 / k
    } else {
        STRAIGHT_RADIUS_M
    }
}

/// The joints of a rail head made of arcs: the points where the radius of curvature changes by
/// more than [`JOINT_RATIO`] between 0.3–0.5 mm either side (the median of three samples on each
/// side, so that the profile spline's own ringing next to a joint does not count), each at the
/// largest change of its region.
pub fn rail_joints(rail: &Profile) -> Vec<RailJoint> {
    let (a, b) = rail.domain();
    let step = 1e-5;
    let side = |s: f64, sign: f64| {
        let mut r = [0.6, 0.8, 1.0].map(|f| rail_radius(rail, s + sign * f * JOINT_WINDOW_M));
        r.sort_by(f64::total_cmp);
        r[1]
    };
    let n = ((b - a - 2.0 * JOINT_WINDOW_M) / step).floor() as usize;
    let mut joints: Vec<(RailJoint, f64)> = Vec::new();
    for k in 0..=n {
        let s = a + JOINT_WINDOW_M + k as f64 * step;
        let (lo, hi) = (side(s, -1.0), side(s, 1.0));
        let jump = (hi / lo).ln().abs();
        if jump < JOINT_RATIO.ln() {
            continue;
        }
        let j = RailJoint { s, radii: (lo, hi) };
        match joints.last_mut() {
            Some((last, best)) if s - last.s < 2.0 * JOINT_WINDOW_M => {
                if jump > *best {
                    *last = j;
                    *best = jump;
                }
            }
            _ => joints.push((j, jump)),
        }
    }
    // The largest change is spread over the window; its middle is the joint.
    joints.into_iter().map(|(j, _)| refine_joint(rail, j)).collect()
}

/// The joint's s within its window: where the radius crosses the geometric mean of its two sides.
fn refine_joint(rail: &Profile, j: RailJoint) -> RailJoint {
    let mid = (j.radii.0 * j.radii.1).sqrt().ln();
    let f = |s: f64| rail_radius(rail, s).ln() - mid;
    let (mut lo, mut hi) = (j.s - JOINT_WINDOW_M, j.s + JOINT_WINDOW_M);
    if f(lo) * f(hi) > 0.0 {
        return j;
    }
    for _ in 0..50 {
        let m = 0.5 * (lo + hi);
        if f(m) * f(lo) > 0.0 {
            lo = m
        } else {
            hi = m
        }
    }
    RailJoint {
        s: 0.5 * (lo + hi),
        ..j
    }
}

/// An extreme value over the band and where it occurs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Extreme {
    pub value: f64,
    /// Lateral displacement, m.
    pub y: f64,
    /// The left wheel's contact angle there, rad.
    pub gamma: f64,
    /// The rail contact point there, m, and the rail's radius of curvature, m.
    pub s_rail: f64,
    pub rail_radius: f64,
}

/// The dwell of the contact at one rail joint.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointDwell {
    pub joint: RailJoint,
    /// y span with the rail contact within ±[`JOINT_TOLERANCE_M`] of the joint, m (0: never).
    pub span_m: f64,
    /// First and last y of it, m.
    pub y_range: Option<(f64, f64)>,
    /// The contact angle there, rad (the mean over the span).
    pub gamma: f64,
}

/// The realism figures of a pair (a design or any wheel) on the centred gauge.
#[derive(Debug, Clone)]
pub struct Realism {
    /// The running band, m (flange contact to flange contact).
    pub band: (f64, f64),
    /// Smallest curvature margin over the band (+∞ where the wheel is nowhere concave).
    pub margin: Extreme,
    /// Smallest margin on each rail arc touched: (s range of the arc, m; the smallest margin).
    pub margin_per_arc: Vec<((f64, f64), Extreme)>,
    /// Largest |ds_w/dy| and |ds_r/dy| outside the joint regions (±`JOINT_WINDOW_M`).
    pub wheel_speed: Extreme,
    pub rail_speed: Extreme,
    /// Largest |ds_w/dy| and |ds_r/dy| inside them (reported, not checked; None: none reached).
    pub joint_speed: Option<(Extreme, Extreme)>,
    /// The dwell at each rail joint the band reaches.
    pub dwell: Vec<JointDwell>,
    /// Equivalent conicity (EN 15302 Annex B) at `CONICITY_AMPLITUDES_M`; None where the band
    /// does not reach.
    pub conicity: Vec<(f64, Option<f64>)>,
    /// y where the left wheel's contact angle passes 35° towards its flange, and where the right
    /// wheel's does (negative y), m.
    pub wall: (Option<f64>, Option<f64>),
}

impl Realism {
    /// The figures of the centred gauge's table `table` of a pair on `rail`.
    pub fn new(table: &LookupTable1, rail: &Profile) -> Result<Self, TableError> {
        let (lo, hi) = table.range();
        let n = ((hi - lo) / SAMPLE_STEP_M).floor() as usize;
        let joints = rail_joints(rail);
        let rows: Vec<_> = (0..=n)
            .map(|k| table.lookup(lo + k as f64 * SAMPLE_STEP_M))
            .collect::<Result<_, _>>()?;
        let at = |r: &crate::contact::lookup::TableRow, value: f64| Extreme {
            value,
            y: r.y,
            gamma: r.contact_angle[0],
            s_rail: r.x[3],
            rail_radius: rail_radius(rail, r.x[3]),
        };
        let margin_of = |r: &crate::contact::lookup::TableRow| {
            let (kw, kr) = (r.curvature[0], r.curvature[1]);
            if kw < 0.0 {
                (kr + kw) / -kw
            } else {
                f64::INFINITY
            }
        };
        let smallest = |it: &mut dyn Iterator<Item = &crate::contact::lookup::TableRow>| {
            it.map(|r| at(r, margin_of(r)))
                .min_by(|a, b| a.value.total_cmp(&b.value))
        };
        let margin = smallest(&mut rows.iter()).expect("a band has rows");
        // The arcs between the joints (and the ends of the rail).
        let (ra, rb) = rail.domain();
        let mut cuts: Vec<f64> = vec![ra];
        cuts.extend(joints.iter().map(|j| j.s));
        cuts.push(rb);
        let margin_per_arc = cuts
            .windows(2)
            .filter_map(|w| {
                // Keep clear of the joint regions: the arcs' own margins.
                let (a, b) = (w[0] + JOINT_WINDOW_M, w[1] - JOINT_WINDOW_M);
                smallest(&mut rows.iter().filter(|r| r.x[3] > a && r.x[3] < b)).map(|m| ((w[0], w[1]), m))
            })
            .collect();
        let near_joint = |r: &&crate::contact::lookup::TableRow| {
            joints.iter().any(|j| (r.x[3] - j.s).abs() < JOINT_WINDOW_M)
        };
        let largest = |k: usize, joint: bool| {
            rows.iter()
                .filter(|r| near_joint(r) == joint)
                .map(|r| at(r, r.dx_dy[k].abs()))
                .max_by(|a, b| a.value.total_cmp(&b.value))
        };
        let dwell = joints
            .iter()
            .filter(|j| {
                let (a, b) = (rows[0].x[3].min(rows[n].x[3]), rows[0].x[3].max(rows[n].x[3]));
                j.s > a && j.s < b
            })
            .map(|&joint| {
                let inside: Vec<_> = rows
                    .iter()
                    .filter(|r| (r.x[3] - joint.s).abs() <= JOINT_TOLERANCE_M)
                    .collect();
                JointDwell {
                    joint,
                    span_m: inside.len().saturating_sub(1) as f64 * SAMPLE_STEP_M,
                    y_range: inside.first().map(|f| (f.y, inside[inside.len() - 1].y)),
                    gamma: inside.iter().map(|r| r.contact_angle[0]).sum::<f64>()
                        / inside.len().max(1) as f64,
                }
            })
            .collect();
        let conicity = crate::contact::report::conicity(table, &CONICITY_AMPLITUDES_M)
            .into_iter()
            .map(|c| (c.amplitude, c.annex_b.ok()))
            .collect();
        let wall = (
            rows.iter()
                .find(|r| r.contact_angle[0] >= WALL_ANGLE_RAD)
                .map(|r| r.y),
            rows.iter()
                .rev()
                .find(|r| r.contact_angle[1] >= WALL_ANGLE_RAD)
                .map(|r| r.y),
        );
        Ok(Realism {
            band: (lo, hi),
            margin,
            margin_per_arc,
            wheel_speed: largest(2, false).expect("the band reaches beyond the joints"),
            rail_speed: largest(3, false).expect("the band reaches beyond the joints"),
            joint_speed: largest(2, true).zip(largest(3, true)),
            dwell,
            conicity,
            wall,
        })
    }

    /// The wall's half-play: the smaller |y| of the two walls, m.
    pub fn wall_m(&self) -> Option<f64> {
        match self.wall {
            (Some(a), Some(b)) => Some(a.abs().min(b.abs())),
            (a, b) => a.or(b).map(f64::abs),
        }
    }

    /// Every check that fails, in words (empty: realistic by these checks).
    pub fn problems(&self) -> Vec<String> {
        let mut p = Vec::new();
        for ((a, b), m) in &self.margin_per_arc {
            if m.value < MARGIN_MIN {
                p.push(format!(
                    "curvature margin {:.1} % < {:.0} % on the rail arc R{:.1} (s {:.2} … {:.2} mm), at y = {:+.3} mm",
                    m.value * 100.0,
                    MARGIN_MIN * 100.0,
                    m.rail_radius * 1e3,
                    a * 1e3,
                    b * 1e3,
                    m.y * 1e3
                ));
            }
        }
        for (name, e, max) in [
            ("wheel", &self.wheel_speed, WHEEL_SPEED_MAX),
            ("rail", &self.rail_speed, RAIL_SPEED_MAX),
        ] {
            if e.value > max {
                p.push(format!(
                    "the contact runs along the {name} at |ds/dy| = {:.1} > {max:.0} (y = {:+.3} mm)",
                    e.value,
                    e.y * 1e3
                ));
            }
        }
        for d in &self.dwell {
            if d.span_m > DWELL_MAX_M {
                p.push(format!(
                    "the rail contact dwells within ±{:.2} mm of the joint R{:.0}/R{:.0} (s = {:.2} mm) over {:.3} mm of y > {:.1} mm",
                    JOINT_TOLERANCE_M * 1e3,
                    d.joint.radii.0 * 1e3,
                    d.joint.radii.1 * 1e3,
                    d.joint.s * 1e3,
                    d.span_m * 1e3,
                    DWELL_MAX_M * 1e3
                ));
            }
        }
        let wall = self.wall_m();
        for &(a, c) in &self.conicity {
            if let Some(c) = c {
                if wall.is_none_or(|w| a <= w - CONICITY_WALL_CLEARANCE_M) && c > CONICITY_MAX {
                    p.push(format!(
                        "equivalent conicity {c:.3} > {CONICITY_MAX} at {:.0} mm (at least {:.0} mm inside the wall)",
                        a * 1e3,
                        CONICITY_WALL_CLEARANCE_M * 1e3
                    ));
                }
            }
        }
        if wall.is_none() {
            p.push("the contact angle never reaches 35° on the band: no flange wall".into());
        }
        p
    }

    /// The figures as a markdown table, one column per pair (`names`, `figures`).
    pub fn markdown(names: &[&str], figures: &[&Realism]) -> String {
        let mm = |v: f64| format!("{:+.3}", v * 1e3);
        let ext = |e: &Extreme, pct: bool| {
            if e.value.is_infinite() {
                "∞ (wheel not concave)".to_string()
            } else if pct {
                format!(
                    "{:.1} % at y {} mm (γ {:.1}°, R{:.1})",
                    e.value * 100.0,
                    mm(e.y),
                    e.gamma.to_degrees(),
                    e.rail_radius * 1e3
                )
            } else {
                format!(
                    "{:.2} at y {} mm (γ {:.1}°)",
                    e.value,
                    mm(e.y),
                    e.gamma.to_degrees()
                )
            }
        };
        let mut s = format!(
            "| check (threshold) | {} |\n|---|{}\n",
            names.join(" | "),
            "---|".repeat(names.len())
        );
        let row = |s: &mut String, label: String, f: &dyn Fn(&Realism) -> String| {
            *s += &format!(
                "| {label} | {} |\n",
                figures.iter().map(|r| f(r)).collect::<Vec<_>>().join(" | ")
            );
        };
        row(&mut s, "running band, y [mm]".into(), &|r| {
            format!("{} … {}", mm(r.band.0), mm(r.band.1))
        });
        row(
            &mut s,
            "(a) curvature margin (R_w − R_r)/R_r, smallest anywhere (joints included)".into(),
            &|r| ext(&r.margin, true),
        );
        row(
            &mut s,
            format!(
                "(a) … on each rail arc touched, ±{:.1} mm from its joints (≥ {:.0} %)",
                JOINT_WINDOW_M * 1e3,
                MARGIN_MIN * 100.0
            ),
            &|r| {
                r.margin_per_arc
                    .iter()
                    .map(|(_, m)| {
                        if m.value.is_infinite() {
                            format!("R{:.0}: ∞", m.rail_radius * 1e3)
                        } else {
                            format!("R{:.0}: {:.1} %", m.rail_radius * 1e3, m.value * 100.0)
                        }
                    })
                    .collect::<Vec<_>>()
                    .join(", ")
            },
        );
        row(
            &mut s,
            format!("(b) \\|ds_w/dy\\|, largest off the joints (≤ {WHEEL_SPEED_MAX:.0})"),
            &|r| ext(&r.wheel_speed, false),
        );
        row(
            &mut s,
            format!("(b) \\|ds_r/dy\\|, largest off the joints (≤ {RAIL_SPEED_MAX:.0})"),
            &|r| ext(&r.rail_speed, false),
        );
        row(
            &mut s,
            format!(
                "(b) … within ±{:.1} mm of a joint, wheel / rail (reported)",
                JOINT_WINDOW_M * 1e3
            ),
            &|r| {
                r.joint_speed.map_or("—".into(), |(w, q)| {
                    format!("{} / {}", ext(&w, false), ext(&q, false))
                })
            },
        );
        row(
            &mut s,
            format!(
                "(c) dwell within ±{:.1} mm of a rail joint, y span [mm] (≤ {:.1})",
                JOINT_TOLERANCE_M * 1e3,
                DWELL_MAX_M * 1e3
            ),
            &|r| {
                r.dwell
                    .iter()
                    .map(|d| {
                        format!(
                            "R{:.0}/R{:.0} at {:.1}°: {:.3}",
                            d.joint.radii.0 * 1e3,
                            d.joint.radii.1 * 1e3,
                            d.gamma.to_degrees(),
                            d.span_m * 1e3
                        )
                    })
                    .collect::<Vec<_>>()
                    .join("; ")
            },
        );
        for (k, a) in CONICITY_AMPLITUDES_M.iter().enumerate() {
            row(
                &mut s,
                format!(
                    "(d) equivalent conicity at {:.0} mm (≤ {CONICITY_MAX} if ≥ {:.0} mm inside the wall)",
                    a * 1e3,
                    CONICITY_WALL_CLEARANCE_M * 1e3
                ),
                &|r| {
                    r.conicity
                        .get(k)
                        .and_then(|c| c.1)
                        .map_or("—".into(), |c| format!("{c:.3}"))
                },
            );
        }
        row(
            &mut s,
            "(e) the wall (γ = 35°), y [mm] left / right".into(),
            &|r| {
                let f = |v: Option<f64>| v.map_or("—".into(), mm);
                format!("{} / {}", f(r.wall.0), f(r.wall.1))
            },
        );
        row(&mut s, "checks failed".into(), &|r| {
            let p = r.problems();
            if p.is_empty() {
                "none".into()
            } else {
                p.join("; ")
            }
        });
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::profile::StandardProfile;

    /// 54E1's joints (R300/R80 at |x| = 10.012 mm, R80/R13 at 24.864 mm, R13/1:20 flank) are found
    /// where its sections put them, with their radii.
    #[test]
    fn the_joints_of_54e1_are_its_sections() {
        let rail = StandardProfile::Rail54E1.profile();
        let j = rail_joints(&rail);
        let want = [10.012, 24.8635];
        for w in want {
            for sign in [-1.0, 1.0] {
                let s = sign * w * 1e-3;
                let f = j
                    .iter()
                    .find(|j| (j.s - s).abs() < 5e-5)
                    .unwrap_or_else(|| panic!("no joint at {} mm: {j:?}", s * 1e3));
                let (small, large) = if w < 20.0 { (0.080, 0.300) } else { (0.013, 0.080) };
                let r = (f.radii.0.min(f.radii.1), f.radii.0.max(f.radii.1));
                // Within 6 %: the spline through the arcs still rings 0.3–0.5 mm from the joint.
                assert!(
                    (r.0 / small - 1.0).abs() < 0.06 && (r.1 / large - 1.0).abs() < 0.06,
                    "{f:?}"
                );
            }
        }
        // Plus the two R13 → flank joints, and nothing else.
        assert_eq!(j.len(), 6, "{j:?}");
    }
}
