//! Wheel profile design from a target contact-angle function: a direct, conjugate design on a
//! given rail (issue 32; `kecsim design-wheel`).
//!
//! **The idea.** On the approximate constraints (Eq. 35–42), a wheelset at lateral displacement y
//! touches the left rail at the rail point whose normal makes the contact angle γ with the vertical
//! (positive towards the track centre). Prescribe γ(y), strictly increasing from the wheel's field
//! side to its flange: for each y the rail point P_r(y) is the one with that normal, and the wheel
//! must pass through P_r with its surface parallel to the rail there. With the wheelset's roll φ(y)
//! (Eq. 37, linearised) that fixes, for each y, one point of the wheel and its slope:
//!
//! ```text
//! s^w(y)   = Y_r(y) − y − L_w − φ h^w(s^w)                 (Eq. 37, Y component)
//! h^w′(s^w) = −tan(γ(y) − atan φ(y))                          (Eq. 36: t^w · n^r = 0)
//! ```
//!
//! and h^w(s) follows by integrating the slope along s^w (anchored at the taping line,
//! h^w(0) = r0). The wheel so built is *conjugate* to the rail: at every contact angle its radius
//! of curvature exceeds the rail's by Δ(γ) = (dy/dγ) / cos γ > 0 (zero roll), which is what makes
//! the contact point move continuously and monotonically over both profiles — no contact jump
//! anywhere in the designed range. (A wheel of the rail's own radius at some angle, Δ = 0, is
//! conformal there: the contact would sweep an arc at one y — the jumps of S1002's R13 flange root
//! on the rail's R13 gauge corner.) The roll φ(y) depends on the wheel being designed: the design
//! starts from φ = 0, solves the designed pair's constraints ([`ContactGeometry`]) for φ(y), and
//! repeats until φ changes by less than 1e-9 rad, so that the designed pair realises the target
//! γ(y) on the constraints themselves.
//!
//! What this is: the *conjugate* (envelope) construction of a wheel from a prescribed
//! contact-angle function γ(y) on a given rail — the wheel point for each y placed on the rail
//! point with that normal, parallel to it — which is the "design by the contact angle function" of
//! Shen, Ayasse, Chollet & Pratt ("A unique design method for wheel profiles by considering the
//! contact angle function", Proc. IMechE Part F 217, 2003, 25–30; cited from the literature, its
//! text not checked here), not an optimisation. It is not Shevtsov, Markine & Esveld's method
//! (Wear 258, 2005, 1022–1030), which optimises B-spline parameters of the wheel towards a target
//! rolling-radius-difference function; nor Polach's design for a target conicity (Wear 271,
//! 2011, 195–202), which shapes the tread from the conicity and the contact position. γ(y), the
//! rail contact point s^r(y) (the rail head is convex) and Δr(y) are one function of the other
//! (Δr′(y) = tan γ · ds^w/dy per wheel), so the three approaches aim at the same object by
//! different handles. The design is only as realistic as its target: `realism` measures what
//! it gives (curvature margin, contact speed, dwell on the rail's arc joints, conicity, wall).
//!
//! **Beyond the designed range.** Towards the field side the wheel continues straight with its last
//! slope; beyond the flank's contact end the flank continues straight at its angle, a tip circle
//! gives the flange height, and a back circle meets the flange back (the flange back never
//! touches the rail; it exists so that the flange measures — EN 13715's S_h, S_d, qR — are
//! defined, see `crate::profile::measures`).

pub(crate) mod realism;
pub(crate) mod target;

pub use realism::Realism;
pub use target::parse_target;

use crate::profile::measures::{flange_measures, FlangeMeasures};
use crate::profile::placement::{Inclination, RailPlacement, WheelRailPair, WheelsetGeometry};
use crate::profile::{Profile, ProfileKind, Side};
use crate::track::{RailOffsets, TrackGauge};

use super::geometry::ContactGeometry;
use crate::interpolation::{cubic_hermite, pchip_slopes};

/// What the wheel must do: its contact angle against the wheelset's lateral displacement and its
/// flange (SI).
#[derive(Debug, Clone, PartialEq)]
pub struct DesignTarget {
    /// The designed profile's name.
    pub name: String,
    /// Control points (y, γ) of the left wheel's contact angle against the lateral displacement y
    /// (towards the left, i.e. towards this wheel's flange), m and rad; both strictly increasing.
    /// Interpolated by monotone cubic Hermite (PCHIP). The last angle is the flank's.
    pub contact_angle: Vec<(f64, f64)>,
    /// Flange height S_h below the taping line, m.
    pub flange_height_m: f64,
    /// Radius of the flange tip, m.
    pub flange_tip_radius_m: f64,
    /// Lateral end of the profile on the field side, m from the taping line.
    pub field_end_m: f64,
    /// Largest rate of change of ln ρ_w with the contact angle where the rail's curvature
    /// jumps, 1/rad ([`CURVATURE_RAMP_PER_RAD`] unless the target says otherwise): the slower
    /// the ramp, the longer the contact dwells on the rail's arc joint (issue 48).
    pub curvature_ramp_per_rad: f64,
    /// Arc-length spacing of the designed part's output points, m ([`OUTPUT_STEP_M`] unless the
    /// target says otherwise). The profile is a C² spline through its points: a fast curvature
    /// ramp drawn with few points makes it ring, locally more curved than the rail (refused by
    /// the conformity check); a finer spacing lets it follow.
    pub output_step_m: f64,
}

/// Design errors: a target no wheel can meet, or a placement that does not fit it.
#[derive(Debug, thiserror::Error)]
pub enum DesignError {
    #[error("design target: {0}")]
    Target(String),
    #[error(transparent)]
    Placement(#[from] crate::profile::placement::PlacementError),
    #[error("the designed wheel: {0}")]
    Result(String),
}

/// Fine grid of the design in y.
const DESIGN_NODES: usize = 6000;
/// Nodes at which the roll of the designed pair is solved per iteration.
const ROLL_NODES: usize = 241;
/// The roll iteration stops when φ changes by less than this, rad.
const ROLL_TOLERANCE_RAD: f64 = 1e-9;
/// At most this many roll iterations.
const MAX_ROLL_ITERATIONS: usize = 12;
/// Arc-length spacing of the output points, m (as the standard profiles: 0.1 mm).
pub const OUTPUT_STEP_M: f64 = 1e-4;
/// Steepest slope kept at the flange back (as S1002's generated profile), |dz/ds|.
const BACK_SLOPE: f64 = 10.0;

impl DesignTarget {
    /// Everything wrong with the target, each naming the value (empty: valid).
    pub fn problems(&self) -> Vec<String> {
        let mut p = Vec::new();
        let pts = &self.contact_angle;
        if pts.len() < 2 {
            p.push(format!(
                "contact_angle: {} point(s); a target needs at least 2",
                pts.len()
            ));
            return p;
        }
        for (k, &(y, g)) in pts.iter().enumerate() {
            if !(y.is_finite() && g.is_finite()) {
                p.push(format!("contact_angle point {}: not a finite number", k + 1));
            }
            if !(-0.03..=0.03).contains(&y) {
                p.push(format!(
                    "contact_angle point {}: y = {:.3} mm; expected within ±30 mm (the lateral play of a wheelset)",
                    k + 1,
                    y * 1e3
                ));
            }
            if !(-1.4..=1.55).contains(&g) {
                p.push(format!(
                    "contact_angle point {}: {:.2}°; expected −80° .. 89° (a contact angle of a rail head)",
                    k + 1,
                    g.to_degrees()
                ));
            }
        }
        for (k, w) in pts.windows(2).enumerate() {
            if w[1].0 <= w[0].0 {
                p.push(format!(
                    "contact_angle points {} and {}: y = {:.3} then {:.3} mm; y must increase",
                    k + 1,
                    k + 2,
                    w[0].0 * 1e3,
                    w[1].0 * 1e3
                ));
            } else if w[1].1 <= w[0].1 {
                p.push(format!(
                    "contact_angle points {} and {}: {:.3}° at y = {:.3} mm, then {:.3}° at y = {:.3} mm — non-monotone contact: \
                     the contact angle must rise strictly as the wheelset moves towards the flange (a falling or flat angle is a \
                     contact that jumps back or sweeps an arc at one y: no wheel can do it in single-point contact)",
                    k + 1,
                    k + 2,
                    w[0].1.to_degrees(),
                    w[0].0 * 1e3,
                    w[1].1.to_degrees(),
                    w[1].0 * 1e3
                ));
            }
        }
        let (first, last) = (pts[0], pts[pts.len() - 1]);
        if !(first.0 < 0.0 && last.0 > 0.0) {
            p.push(format!(
                "contact_angle: y spans {:.3} .. {:.3} mm; it must include the centred position y = 0",
                first.0 * 1e3,
                last.0 * 1e3
            ));
        }
        if !(0.002..=0.05).contains(&self.flange_height_m) {
            p.push(format!(
                "flange_height_mm = {:.3}: expected 2 .. 50 mm",
                self.flange_height_m * 1e3
            ));
        }
        if !(0.001..=0.05).contains(&self.flange_tip_radius_m) {
            p.push(format!(
                "flange_tip_radius_mm = {:.3}: expected 1 .. 50 mm",
                self.flange_tip_radius_m * 1e3
            ));
        }
        if !(10.0..=1e5).contains(&self.curvature_ramp_per_rad) {
            p.push(format!(
                "curvature_ramp_per_rad = {}: expected 10 .. 100000",
                self.curvature_ramp_per_rad
            ));
        }
        if !(5e-6..=OUTPUT_STEP_M).contains(&self.output_step_m) {
            p.push(format!(
                "output_step_mm = {}: expected 0.005 .. 0.1",
                self.output_step_m * 1e3
            ));
        }
        if !(0.01..=0.2).contains(&self.field_end_m) {
            p.push(format!(
                "field_end_mm = {:.3}: expected 10 .. 200 mm",
                self.field_end_m * 1e3
            ));
        }
        p
    }

    /// γ(y) and dγ/dy by PCHIP through the control points (monotone: no overshoot between them).
    fn angle_function(&self) -> impl Fn(f64) -> (f64, f64) + '_ {
        let ys: Vec<f64> = self.contact_angle.iter().map(|p| p.0).collect();
        let gs: Vec<f64> = self.contact_angle.iter().map(|p| p.1).collect();
        let d = if ys.len() >= 3 {
            pchip_slopes(&ys, &gs)
        } else {
            let m = (gs[1] - gs[0]) / (ys[1] - ys[0]);
            vec![m, m]
        };
        move |y: f64| {
            let k = ys.partition_point(|&v| v <= y).clamp(1, ys.len() - 1) - 1;
            let (g, dg, _) = cubic_hermite(ys[k], ys[k + 1], gs[k], gs[k + 1], d[k], d[k + 1], y);
            (g, dg)
        }
    }
}

/// The placed rail of the design (left side) and its contact-angle inversion.
struct RailSide<'a> {
    rail: &'a Profile,
    placement: RailPlacement,
}

impl RailSide<'_> {
    /// The track-frame contact angle of the left rail's point s: atan(h^r′) + β (Eq. 40).
    fn angle(&self, s: f64) -> f64 {
        self.rail.eval(s).dz.atan() + self.placement.inclination_rad
    }

    /// The left rail's point whose normal makes angle γ (bisection: the angle falls along the
    /// convex head), or None where the head has no such normal.
    fn point_at(&self, gamma: f64) -> Option<f64> {
        let (a, b) = self.rail.domain();
        if !(self.angle(b) <= gamma && gamma <= self.angle(a)) {
            return None;
        }
        let (mut lo, mut hi) = (a, b);
        for _ in 0..80 {
            let m = 0.5 * (lo + hi);
            if self.angle(m) > gamma {
                lo = m
            } else {
                hi = m
            }
        }
        Some(0.5 * (lo + hi))
    }
}

/// One node of the designed part of the wheel: the contact it is built for and the wheel there.
#[derive(Debug, Clone, Copy)]
pub struct DesignNode {
    /// Lateral displacement, m.
    pub y: f64,
    /// Target contact angle, rad.
    pub gamma: f64,
    /// Rail contact point s^r (left orientation), m.
    pub s_rail: f64,
    /// Wheel contact point s^w, m.
    pub s_wheel: f64,
    /// Wheel radius h^w and slope dh^w/ds^w there.
    pub radius: f64,
    pub slope: f64,
    /// The roll of the designed pair at y, rad.
    pub phi: f64,
}

/// A designed wheel.
#[derive(Debug, Clone)]
pub struct WheelDesign {
    pub target: DesignTarget,
    /// The profile (SI), ready to place.
    pub profile: Profile,
    /// The designed nodes, in y order.
    pub nodes: Vec<DesignNode>,
    /// How far the realised contact angle departs from the target's, as the largest difference
    /// of the y at which both reach the same angle (m) — where the rail's
    /// curvature jumps (its arcs' joints) the wheel's curvature is ramped over
    /// [`CURVATURE_RAMP_PER_RAD`] instead of jumping too, so the realised γ(y) rises a little
    /// more slowly there — and how much later the flank angle is reached because of it, m.
    pub max_departure_m: f64,
    pub flank_shift_m: f64,
    /// Roll iterations used and the last change of φ, rad.
    pub iterations: usize,
    pub last_roll_change_rad: f64,
    /// The flange measures of the result.
    pub measures: FlangeMeasures,
    /// Largest difference between the target contact angle and the one the designed pair's
    /// constraints give, over the designed y range where both wheels stay on their designed
    /// parts, rad.
    pub max_angle_error_rad: f64,
}

/// Designs a wheel for `rail` at `inclination`, `gauge` and the wheelset geometry (back-to-back,
/// taping line, r0) that will carry it.
pub fn design_wheel(
    rail: &Profile,
    inclination: Inclination,
    gauge: TrackGauge,
    wheelset: WheelsetGeometry,
    target: &DesignTarget,
) -> Result<WheelDesign, DesignError> {
    let problems = target.problems();
    if !problems.is_empty() {
        return Err(DesignError::Target(problems.join("; ")));
    }
    if rail.kind != ProfileKind::Rail {
        return Err(DesignError::Target(format!(
            "'{}' is not a rail profile",
            rail.name
        )));
    }
    let side = RailSide {
        rail,
        placement: RailPlacement::new(rail, inclination, gauge)?,
    };
    let realisable = realisable_angle(target, &side)?;
    let (y0, y1) = (realisable[0].0, realisable[realisable.len() - 1].0);
    let ys: Vec<f64> = (0..=DESIGN_NODES)
        .map(|k| y0 + (y1 - y0) * k as f64 / DESIGN_NODES as f64)
        .collect();
    let gammas: Vec<f64> = ys.iter().map(|&y| interpolate(&realisable, y)).collect();
    let gamma_of = target.angle_function();
    let target_y1 = target.contact_angle[target.contact_angle.len() - 1].0;
    // How far (in y) the realised function reaches each angle from where the target does.
    let _ = &gamma_of;
    let departure = target_departure(target, &realisable);
    // The rail points of the target angles.
    let (ra, rb) = rail.domain();
    let mut rails = Vec::with_capacity(ys.len());
    for (&y, &g) in ys.iter().zip(&gammas) {
        let s = side.point_at(g).ok_or_else(|| {
            DesignError::Target(format!(
                "contact angle {:.2}° at y = {:.3} mm: the rail '{}' at {} has no point with that normal (its head spans {:.2}° .. {:.2}°)",
                g.to_degrees(),
                y * 1e3,
                rail.name,
                inclination,
                side.angle(rb).to_degrees(),
                side.angle(ra).to_degrees()
            ))
        })?;
        rails.push((s, side.placement.rail_point(rail, Side::Left, s)));
    }
    let l_w = wheelset.l_w();
    let r0 = wheelset.nominal_radius_m;
    let mut phi = vec![0.0; ys.len()];
    let mut radius = vec![r0; ys.len()];
    let mut iterations = 0;
    loop {
        iterations += 1;
        let nodes = design_nodes(&ys, &gammas, &rails, &phi, &radius, l_w, r0)?;
        let profile = assemble(target, &nodes, &wheelset)?;
        let pair = WheelRailPair::new(profile.clone(), rail.clone(), inclination, gauge, wheelset)?;
        let geom = ContactGeometry::with_defaults(pair);
        let rolls = roll_of(&geom, &ys, &phi);
        let change = rolls
            .iter()
            .zip(&phi)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        phi = rolls;
        radius = nodes.iter().map(|n| n.radius).collect();
        if change < ROLL_TOLERANCE_RAD || iterations >= MAX_ROLL_ITERATIONS {
            let nodes = design_nodes(&ys, &gammas, &rails, &phi, &radius, l_w, r0)?;
            let profile = assemble(target, &nodes, &wheelset)?;
            let measures = flange_measures(&profile, wheelset.rolling_circle_from_back_m)
                .map_err(DesignError::Result)?;
            let pair = WheelRailPair::new(profile.clone(), rail.clone(), inclination, gauge, wheelset)?;
            let geom = ContactGeometry::with_defaults(pair);
            let max_angle_error_rad = angle_error(&geom, &ys, &gammas);
            conformity_check(&profile, rail, &nodes)?;
            return Ok(WheelDesign {
                target: target.clone(),
                flank_shift_m: y1 - target_y1,
                max_departure_m: departure,
                profile,
                nodes,
                iterations,
                last_roll_change_rad: change,
                measures,
                max_angle_error_rad,
            });
        }
    }
}

/// Refuses a designed wheel whose radius of curvature falls below the rail's at one of its
/// designed contacts: there the concave wheel is more curved than the convex rail, the contact
/// is not a single point but two (it jumps). The conjugate construction keeps ρ_w = ρ_r + Δ > ρ_r
/// on paper; the profile's spline through the points can still ring below it next to a steep
/// curvature ramp ([`DesignTarget::curvature_ramp_per_rad`]). (A small positive margin is not
/// refused but flagged by the realism checks, [`realism`].)
fn conformity_check(profile: &Profile, rail: &Profile, nodes: &[DesignNode]) -> Result<(), DesignError> {
    for n in nodes {
        let kw = profile.eval(n.s_wheel).curvature();
        let kr = -rail.eval(n.s_rail).curvature();
        if kw < 0.0 && kr + kw < 0.0 {
            return Err(DesignError::Result(format!(
                "at y = {:.3} mm (contact angle {:.2}°) the wheel's radius of curvature R{:.2} mm falls below the rail's R{:.2} mm: \
                 the wheel would be more curved than the rail there and touch it at two points (a contact jump); \
                 ramp the curvature more slowly (curvature_ramp_per_rad) or let the contact angle rise more slowly there",
                n.y * 1e3,
                n.gamma.to_degrees(),
                -1e3 / kw,
                1e3 / kr
            )));
        }
    }
    Ok(())
}

/// Largest rate of change of ln ρ_w with the contact angle, 1/rad: where the rail's curvature
/// radius jumps (R300 → R80 → R13 on 54E1 and 60E1), the wheel's ramps over ln(ρ1/ρ2)/this
/// (0.34° from R300 to R80), so that the wheel's curvature is continuous — a C² spline through its
/// points then reproduces it without ringing. (A wheel whose curvature jumps with the rail's
/// keeps the conjugacy only on paper: the spline's overshoot next to the jump makes the
/// near-conformal wheel locally more curved than the rail, and the contact jumps there by a
/// tenth of a millimetre — seen on the first designs.)
pub const CURVATURE_RAMP_PER_RAD: f64 = 220.0;

/// Nodes of the contact-angle grid on which the realisable γ(y) is built.
const ANGLE_NODES: usize = 40_000;

/// Linear interpolation in a table (x, v) sorted by x, clamped at the ends.
fn interpolate(table: &[(f64, f64)], x: f64) -> f64 {
    let k = table.partition_point(|p| p.0 <= x).clamp(1, table.len() - 1);
    let (a, b) = (table[k - 1], table[k]);
    if b.0 == a.0 {
        return b.1;
    }
    a.1 + (x - a.0) / (b.0 - a.0) * (b.1 - a.1)
}

/// The realisable contact-angle function (y, γ), dense. At zero roll a wheel conjugate to the
/// rail has the radius of curvature ρ_w = ρ_r + Δ, Δ = (dy/dγ)/cos γ (the module doc), so
/// y(γ) = y(γ0) + ∫ (ρ_w − ρ_r) cos γ dγ. The target's ρ_w = ρ_r + Δ_t jumps wherever the
/// rail's ρ_r does; it is replaced by its smallest upper envelope whose logarithm changes by at
/// most [`CURVATURE_RAMP_PER_RAD`] per radian. The envelope lies above the target's radius, so
/// the contact dwells a little longer at each rail joint; to keep the target's anchors — the
/// centred position y = 0 at γ_t(0) and the flank angle at the last target y — the target's Δ_t
/// is scaled by one factor λ ≤ 1 on each side of y = 0 (found by bisection).
fn realisable_angle(target: &DesignTarget, side: &RailSide) -> Result<Vec<(f64, f64)>, DesignError> {
    let gamma_of = target.angle_function();
    let pts = &target.contact_angle;
    let (g0, g1) = (pts[0].1, pts[pts.len() - 1].1);
    let (y_lo, y_hi) = (pts[0].0, pts[pts.len() - 1].0);
    let g_mid = gamma_of(0.0).0;
    // y_t(γ) by bisection on the monotone target.
    let y_of = |g: f64| {
        let (mut lo, mut hi) = (y_lo, y_hi);
        for _ in 0..70 {
            let m = 0.5 * (lo + hi);
            if gamma_of(m).0 < g {
                lo = m
            } else {
                hi = m
            }
        }
        0.5 * (lo + hi)
    };
    let (ra, rb) = side.rail.domain();
    let n = ANGLE_NODES;
    let gs: Vec<f64> = (0..=n).map(|j| g0 + (g1 - g0) * j as f64 / n as f64).collect();
    let mut rho_r = Vec::with_capacity(n + 1);
    let mut delta_t = Vec::with_capacity(n + 1);
    for &g in &gs {
        let s = side.point_at(g).ok_or_else(|| {
            DesignError::Target(format!(
                "contact angle {:.2}° (at y = {:.3} mm): the rail '{}' has no point with that normal (its head spans {:.2}° .. {:.2}° at its inclination)",
                g.to_degrees(),
                y_of(g) * 1e3,
                side.rail.name,
                side.angle(rb).to_degrees(),
                side.angle(ra).to_degrees()
            ))
        })?;
        let p = side.rail.eval(s);
        // The head is convex (z'' < 0); a straight stretch has an unbounded radius.
        rho_r.push((1.0 + p.dz * p.dz).powf(1.5) / (-p.d2z).max(1e-12));
        delta_t.push(1.0 / (gamma_of(y_of(g)).1.max(1e-12) * g.cos()));
    }
    let j_mid = gs.partition_point(|&g| g < g_mid).clamp(1, n - 1);
    let step = (g1 - g0) / n as f64 * target.curvature_ramp_per_rad;
    // y(γ) for the scale factors (λ below γ_t(0), λ above).
    let build = |lam_lo: f64, lam_hi: f64| -> Vec<(f64, f64)> {
        let mut ln_w: Vec<f64> = (0..=n)
            .map(|j| (rho_r[j] + if j < j_mid { lam_lo } else { lam_hi } * delta_t[j]).ln())
            .collect();
        for j in 1..=n {
            ln_w[j] = ln_w[j].max(ln_w[j - 1] - step);
        }
        for j in (0..n).rev() {
            ln_w[j] = ln_w[j].max(ln_w[j + 1] - step);
        }
        let f = |k: usize| (ln_w[k].exp() - rho_r[k]) * gs[k].cos();
        let mut out = Vec::with_capacity(n + 1);
        let mut y = y_lo;
        out.push((y, g0));
        for j in 1..=n {
            y += 0.5 * (f(j - 1) + f(j)) * (gs[j] - gs[j - 1]);
            out.push((y, gs[j]));
        }
        out
    };
    // Bisection on each factor for its anchor (y = 0 at j_mid, y_hi at the end): the length of
    // each part grows with its λ; the other part's λ barely matters (the ramps are short).
    let solve = |anchor: &Anchor<'_>, lam_other: f64, low: bool| -> Result<f64, DesignError> {
        let eval = |lam: f64| {
            anchor(&if low {
                build(lam, lam_other)
            } else {
                build(lam_other, lam)
            })
        };
        if eval(0.0) > 0.0 {
            return Err(DesignError::Target(format!(
                "the rail's curvature jumps alone (ramped over {} per rad) take more lateral play than the target gives {} the centred position: widen the contact_angle range there",
                target.curvature_ramp_per_rad,
                if low { "on the field side of" } else { "between the flank and" }
            )));
        }
        let (mut lo, mut hi) = (0.0, 1.0);
        if eval(hi) <= 0.0 {
            return Ok(hi);
        }
        for _ in 0..50 {
            let m = 0.5 * (lo + hi);
            if eval(m) > 0.0 {
                hi = m
            } else {
                lo = m
            }
        }
        Ok(0.5 * (lo + hi))
    };
    let mid_anchor = |t: &[(f64, f64)]| interpolate_y(t, g_mid);
    let end_anchor = |t: &[(f64, f64)]| t[n].0 - y_hi;
    let mut lam = (1.0, 1.0);
    for _ in 0..3 {
        lam.0 = solve(&mid_anchor, lam.1, true)?;
        lam.1 = solve(&end_anchor, lam.0, false)?;
    }
    Ok(build(lam.0, lam.1))
}

/// The largest |y_realised(γ) − y_target(γ)| over the target's angles, m.
fn target_departure(target: &DesignTarget, realised: &[(f64, f64)]) -> f64 {
    let gamma_of = target.angle_function();
    let (y0, y1) = (
        target.contact_angle[0].0,
        target.contact_angle[target.contact_angle.len() - 1].0,
    );
    (0..=2000)
        .map(|k| {
            let y = y0 + (y1 - y0) * k as f64 / 2000.0;
            (interpolate_y(realised, gamma_of(y).0) - y).abs()
        })
        .fold(0.0, f64::max)
}

/// Where a realisable table (y, γ) misses one of the target's anchors, m.
type Anchor<'a> = dyn Fn(&[(f64, f64)]) -> f64 + 'a;

/// y at angle `g` in a table (y, γ) rising in both.
fn interpolate_y(table: &[(f64, f64)], g: f64) -> f64 {
    let k = table.partition_point(|p| p.1 <= g).clamp(1, table.len() - 1);
    let (a, b) = (table[k - 1], table[k]);
    if b.1 == a.1 {
        return b.0;
    }
    a.0 + (g - a.1) / (b.1 - a.1) * (b.0 - a.0)
}

/// The wheel's nodes for the roll `phi` and the radii `radius` of the previous pass.
fn design_nodes(
    ys: &[f64],
    gammas: &[f64],
    rails: &[(f64, (f64, f64))],
    phi: &[f64],
    radius: &[f64],
    l_w: f64,
    r0: f64,
) -> Result<Vec<DesignNode>, DesignError> {
    let mut nodes: Vec<DesignNode> = (0..ys.len())
        .map(|k| {
            let (s_rail, (ry, _)) = rails[k];
            DesignNode {
                y: ys[k],
                gamma: gammas[k],
                s_rail,
                s_wheel: ry - ys[k] - l_w - phi[k] * radius[k],
                radius: 0.0,
                slope: -(gammas[k] - phi[k].atan()).tan(),
                phi: phi[k],
            }
        })
        .collect();
    // s^w falls as y rises (the contact runs towards the flange on the wheel faster than on the
    // rail); integrate the slope from the flange end towards the field side.
    for w in nodes.windows(2) {
        if w[1].s_wheel >= w[0].s_wheel {
            return Err(DesignError::Target(format!(
                "at y = {:.4} mm the wheel's contact point does not move towards the flange (s^w {:.4} → {:.4} mm): the roll changes faster than the target angle",
                w[1].y * 1e3,
                w[0].s_wheel * 1e3,
                w[1].s_wheel * 1e3
            )));
        }
    }
    let n = nodes.len();
    let mut h = vec![0.0; n];
    for k in (0..n - 1).rev() {
        let ds = nodes[k].s_wheel - nodes[k + 1].s_wheel;
        h[k] = h[k + 1] + 0.5 * (nodes[k].slope + nodes[k + 1].slope) * ds;
    }
    // Anchor at the taping line: h^w(0) = r0.
    let (lo, hi) = (nodes[n - 1].s_wheel, nodes[0].s_wheel);
    if !(lo < 0.0 && hi > 0.0) {
        return Err(DesignError::Target(format!(
            "the designed contact spans the wheel from s = {:.2} to {:.2} mm: it must cross the taping line (s = 0); widen the contact_angle range",
            lo * 1e3,
            hi * 1e3
        )));
    }
    let k = nodes.partition_point(|nd| nd.s_wheel > 0.0);
    let (a, b) = (&nodes[k - 1], &nodes[k]);
    let t = (0.0 - b.s_wheel) / (a.s_wheel - b.s_wheel);
    let h0 = h[k] + t * (h[k - 1] - h[k]);
    for (nd, hk) in nodes.iter_mut().zip(h) {
        nd.radius = r0 + hk - h0;
    }
    Ok(nodes)
}

/// The roll of the designed pair at every design node: solved at [`ROLL_NODES`] nodes and
/// interpolated linearly; where the constraints cannot be solved (beyond a flange climb), the
/// previous pass's roll is kept.
fn roll_of(geom: &ContactGeometry, ys: &[f64], previous: &[f64]) -> Vec<f64> {
    use rayon::prelude::*;
    let n = ys.len() - 1;
    let idx: Vec<usize> = (0..ROLL_NODES).map(|k| k * n / (ROLL_NODES - 1)).collect();
    let solved: Vec<Option<f64>> = idx
        .par_iter()
        .map(|&k| geom.solve(ys[k], &RailOffsets::default()).ok().map(|s| s.phi))
        .collect();
    let mut out = previous.to_vec();
    for (w, sw) in idx.windows(2).zip(solved.windows(2)) {
        if let (Some(a), Some(b)) = (sw[0], sw[1]) {
            for (k, o) in out.iter_mut().enumerate().take(w[1] + 1).skip(w[0]) {
                let t = (k - w[0]) as f64 / (w[1] - w[0]) as f64;
                *o = a + t * (b - a);
            }
        }
    }
    out
}

/// Largest |γ_target − γ_left| over the nodes where the designed pair can be solved and both
/// wheels touch their designed parts (the right wheel's contact at y is the left's at −y).
fn angle_error(geom: &ContactGeometry, ys: &[f64], gammas: &[f64]) -> f64 {
    use rayon::prelude::*;
    let (y0, y1) = (ys[0], ys[ys.len() - 1]);
    let n = ys.len() - 1;
    (0..ROLL_NODES)
        .into_par_iter()
        .map(|i| {
            let k = i * n / (ROLL_NODES - 1);
            let y = ys[k];
            if -y < y0 || -y > y1 {
                return 0.0;
            }
            match geom.solve(y, &RailOffsets::default()) {
                Ok(s) => (s.left.contact_angle - gammas[k]).abs(),
                Err(_) => f64::INFINITY,
            }
        })
        .reduce(|| 0.0, f64::max)
}

/// The whole wheel as a profile: flange back, tip, flank, the designed part, the field side.
fn assemble(
    target: &DesignTarget,
    nodes: &[DesignNode],
    wheelset: &WheelsetGeometry,
) -> Result<Profile, DesignError> {
    let r0 = wheelset.nominal_radius_m;
    let step = target.output_step_m;
    // (s, z) with z = r0 − h^w; the designed part from the flange end (last node) to the field.
    let z_of = |nd: &DesignNode| r0 - nd.radius;
    let flank = &nodes[nodes.len() - 1];
    let (s_f, z_f) = (flank.s_wheel, z_of(flank));
    let m = -flank.slope; // dz/ds on the flank (positive: the flange hangs down towards −s)
    let h = target.flange_height_m;
    let rt = target.flange_tip_radius_m;
    let q = (1.0 + m * m).sqrt();
    // Tip circle: lowest point at z = −h, tangent to the flank line, centre inside the wheel.
    let zc = -h + rt;
    let sc = s_f + (zc - z_f - rt * q) / m;
    let (s_t, z_t) = (sc + rt * m / q, zc - rt / q);
    if m <= 0.0 || m.is_nan() || s_t > s_f || z_f < -h + rt * (1.0 - 1.0 / q) {
        return Err(DesignError::Target(format!(
            "flange_height_mm = {:.2}: the flank's contact end lies {:.2} mm below the taping line (the rail's gauge corner reaches that deep at the last target angle {:.1}°), \
             and a tip of radius {:.1} mm cannot be fitted below it; a flange lower than the rail's gauge corner carries no flange contact — give a higher flange, a smaller tip radius or a smaller last angle",
            h * 1e3,
            -z_f * 1e3,
            flank.gamma.to_degrees(),
            rt * 1e3
        )));
    }
    let s_back = -wheelset.rolling_circle_from_back_m;
    let rb = sc - s_back;
    if rb <= rt.min(0.002) {
        return Err(DesignError::Target(format!(
            "the flange's tip lies {:.2} mm from the flange back: no room for a flange back (the designed flank is {:.2} mm from the taping line; a flange this thick does not fit the {:.0} mm from the back to the taping line)",
            rb * 1e3,
            -s_f * 1e3,
            -s_back * 1e3
        )));
    }
    let mut pts: Vec<(f64, f64)> = Vec::new();
    let mut push = |p: (f64, f64)| {
        if pts.last().is_none_or(|l: &(f64, f64)| p.0 > l.0 + 1e-9) {
            pts.push(p);
        }
    };
    // Back circle (centre (sc, −h + rb)), from where |dz/ds| = BACK_SLOPE to the bottom.
    let zb = -h + rb;
    let u_start = rb * BACK_SLOPE / (1.0 + BACK_SLOPE * BACK_SLOPE).sqrt();
    arc(sc, zb, rb, -u_start, 0.0, step, &mut push);
    // Tip circle from the bottom to the tangent point on the flank.
    arc(sc, zc, rt, 0.0, s_t - sc, step, &mut push);
    // The flank line to the contact end.
    line((s_t, z_t), (s_f, z_f), step, &mut push);
    // The designed part, resampled every `step` of arc length by cubic Hermite on the
    // nodes' values and slopes (dz/ds = −h^w′).
    let rev: Vec<&DesignNode> = nodes.iter().rev().collect();
    let mut s = s_f;
    let s_end = rev[rev.len() - 1].s_wheel;
    let mut k = 0;
    while s < s_end {
        while k + 2 < rev.len() && rev[k + 1].s_wheel <= s {
            k += 1;
        }
        let (a, b) = (rev[k], rev[k + 1]);
        let (z, dz, _) = cubic_hermite(a.s_wheel, b.s_wheel, z_of(a), z_of(b), -a.slope, -b.slope, s);
        push((s, z));
        s += step / (1.0 + dz * dz).sqrt();
    }
    let last = rev[rev.len() - 1];
    let (s_l, z_l, m_l) = (last.s_wheel, z_of(last), -last.slope);
    push((s_l, z_l));
    // The field side: straight with the last slope.
    if target.field_end_m > s_l {
        line(
            (s_l, z_l),
            (target.field_end_m, z_l + m_l * (target.field_end_m - s_l)),
            step,
            &mut push,
        );
    }
    let (sv, zv): (Vec<f64>, Vec<f64>) = pts.into_iter().unzip();
    Profile::from_points(
        &target.name,
        ProfileKind::Wheel,
        "designed by kecsim design-wheel",
        sv,
        zv,
    )
    .map_err(|e| DesignError::Result(format!("the profile's points do not make a curve: {e:?}")))
}

/// Points of the lower arc of the circle (centre (sc, zc), radius r) for s − sc in [u0, u1],
/// every `step` of arc length, both ends included.
fn arc(sc: f64, zc: f64, r: f64, u0: f64, u1: f64, step: f64, push: &mut impl FnMut((f64, f64))) {
    let (a0, a1) = ((u0 / r).clamp(-1.0, 1.0).asin(), (u1 / r).clamp(-1.0, 1.0).asin());
    let n = (((a1 - a0).abs() * r) / step).ceil().max(1.0) as usize;
    for i in 0..=n {
        let a = a0 + (a1 - a0) * i as f64 / n as f64;
        push((sc + r * a.sin(), zc - r * a.cos()));
    }
}

/// Points of a straight segment every `step`, both ends included.
fn line(p: (f64, f64), q: (f64, f64), step: f64, push: &mut impl FnMut((f64, f64))) {
    let len = ((q.0 - p.0).powi(2) + (q.1 - p.1).powi(2)).sqrt();
    let n = (len / step).ceil().max(1.0) as usize;
    for i in 0..=n {
        let t = i as f64 / n as f64;
        push((p.0 + t * (q.0 - p.0), p.1 + t * (q.1 - p.1)));
    }
}

/// The jump check of one gauge column: the y range swept (up to the flange-climb limit on each
/// side, at most the range asked for) and the contact jumps found in it.
#[derive(Debug, Clone)]
pub struct ColumnCheck {
    /// Gauge variation, m.
    pub gv: f64,
    /// Range swept, m.
    pub range: (f64, f64),
    /// Jumps found: (y, left?, s^w before, after), m.
    pub jumps: Vec<super::lookup::Jump>,
}

/// Sweeps the pair's contact over |y| ≤ `y_max` on the ideal track and on every gauge variation
/// of the 2-entry table's default columns (−10 … 10 mm, 1 mm), each up to its own flange-climb
/// limit on each side, locating contact jumps as the table builder does.
pub fn jump_check(pair: &WheelRailPair, y_max: f64) -> Result<Vec<ColumnCheck>, super::lookup::TableError> {
    use super::lookup::{flange_contact_limit, LookupTable1, TableSettings};
    use rayon::prelude::*;
    let geom = ContactGeometry::with_defaults(pair.clone());
    let settings = TableSettings::default();
    let gvs: Vec<f64> = (-10..=10).map(|k| k as f64 * 1e-3).collect();
    gvs.par_iter()
        .map(|&gv| {
            let off = RailOffsets::gauge_variation(gv);
            let lo = flange_contact_limit(&geom, &off, false)?.min(y_max);
            let hi = flange_contact_limit(&geom, &off, true)?.min(y_max);
            let t = LookupTable1::build_range(&geom, gv, -lo, hi, &settings)?;
            Ok(ColumnCheck {
                gv,
                range: (-lo, hi),
                jumps: t.jumps,
            })
        })
        .collect()
}

/// What `kecsim design-wheel` prints, records and writes into the profile's header.
#[derive(Debug, Clone)]
pub struct DesignReport {
    pub design: WheelDesign,
    /// The designed pair's and the reference pair's 1-entry tables (ideal track, flange to flange).
    pub table: super::lookup::LookupTable1,
    pub reference_table: super::lookup::LookupTable1,
    pub reference_name: String,
    pub reference_measures: Option<FlangeMeasures>,
    pub checks: Vec<ColumnCheck>,
    pub reference_checks: Vec<ColumnCheck>,
    /// Equivalent conicity (EN 15302 Annex B) at 1 … 6 mm of both.
    pub conicity: Vec<(f64, Option<f64>, Option<f64>)>,
    /// Wall time of the design, s.
    pub design_s: f64,
    /// The rail's name.
    pub rail: String,
    /// The realism checks of the designed and the reference pair (`realism`); the reference's
    /// is None where its table cannot be swept.
    pub realism: Realism,
    pub reference_realism: Option<Realism>,
}

impl DesignReport {
    /// Builds the tables and conicities of both pairs.
    pub fn new(
        design: &WheelDesign,
        pair: &WheelRailPair,
        reference: &WheelRailPair,
        checks: &[ColumnCheck],
        reference_checks: &[ColumnCheck],
        design_s: f64,
    ) -> Result<Self, DesignError> {
        use super::lookup::{LookupTable1, TableSettings};
        let table_error =
            |e: super::lookup::TableError| DesignError::Result(format!("its contact table: {e}"));
        let settings = TableSettings::default();
        let table = LookupTable1::build(&ContactGeometry::with_defaults(pair.clone()), &settings)
            .map_err(table_error)?;
        let reference_table =
            LookupTable1::build(&ContactGeometry::with_defaults(reference.clone()), &settings)
                .map_err(table_error)?;
        let realism = Realism::new(&table, &pair.rail).map_err(table_error)?;
        let reference_realism = Realism::new(&reference_table, &reference.rail).ok();
        let amps: Vec<f64> = (1..=6).map(|k| k as f64 * 1e-3).collect();
        let c = super::report::conicity(&table, &amps);
        let cr = super::report::conicity(&reference_table, &amps);
        let conicity = amps
            .iter()
            .zip(c.iter().zip(&cr))
            .map(|(&a, (x, r))| (a, x.annex_b.clone().ok(), r.annex_b.clone().ok()))
            .collect();
        Ok(DesignReport {
            design: design.clone(),
            table,
            reference_table,
            reference_name: reference.wheel.name.clone(),
            reference_measures: flange_measures(
                &reference.wheel,
                reference.wheelset.rolling_circle_from_back_m,
            )
            .ok(),
            checks: checks.to_vec(),
            reference_checks: reference_checks.to_vec(),
            conicity,
            design_s,
            rail: pair.rail.name.clone(),
            realism,
            reference_realism,
        })
    }

    /// The jump checks in one line: columns, their range, jumps found.
    fn checks_line(checks: &[ColumnCheck]) -> String {
        let jumps: usize = checks.iter().map(|c| c.jumps.len()).sum();
        let lo = checks.iter().map(|c| c.range.0).fold(f64::NEG_INFINITY, f64::max);
        let hi = checks.iter().map(|c| c.range.1).fold(f64::INFINITY, f64::min);
        let centred = checks.iter().find(|c| c.gv == 0.0);
        let mut s = format!(
            "{} contact jumps in {} gauge columns (gv −10 … +10 mm), each swept to its flange-climb limit or ±{:.1} mm (every column covers {:.2} … {:.2} mm)",
            jumps,
            checks.len(),
            checks.iter().map(|c| c.range.1.max(-c.range.0)).fold(0.0, f64::max) * 1e3,
            lo * 1e3,
            hi * 1e3
        );
        if let Some(c) = centred {
            s += &format!(
                "; on the centred gauge: {} over {:.2} … {:.2} mm",
                c.jumps.len(),
                c.range.0 * 1e3,
                c.range.1 * 1e3
            );
        }
        for c in checks {
            for j in &c.jumps {
                s += &format!(
                    "\n  * gv {:+.0} mm, y = {:+.3} mm, {} wheel: s^w {:+.3} → {:+.3} mm",
                    c.gv * 1e3,
                    j.y * 1e3,
                    if j.left { "left" } else { "right" },
                    j.s_wheel_before * 1e3,
                    j.s_wheel_after * 1e3
                );
            }
        }
        s
    }

    /// The printed summary (markdown).
    pub fn markdown(&self, inclination: &str) -> String {
        let d = &self.design;
        let t = &d.target;
        let mut s = format!(
            "# kecsim design-wheel: '{}' on {} at {}\n\n",
            t.name, self.rail, inclination
        );
        s += &format!("**Verdict**: {}\n\n", self.verdict());
        s += &format!(
            "Designed in {:.2} s: {} roll iterations (last change of φ {:.1e} rad); the designed pair's constraints give the target angle to {:.3}° (largest difference over the designed range)\n\n",
            self.design_s,
            d.iterations,
            d.last_roll_change_rad,
            d.max_angle_error_rad.to_degrees()
        );
        s += &format!(
            "Realised against the target: the wheel's curvature ramped where the rail's jumps (ln ρ_w by at most {} per rad), the target's Δ scaled to keep y = 0 and the flank where the target puts them: each angle reached within {:.3} mm of the target's y, the last one {:.3} mm later\n\n",
            t.curvature_ramp_per_rad,
            d.max_departure_m * 1e3,
            d.flank_shift_m * 1e3
        );
        let m = &d.measures;
        let row = |name: &str, m: &FlangeMeasures| {
            format!(
                "| {name} | {:.2} | {:.2} | {:.2} | {:.2} |\n",
                m.height_m * 1e3,
                m.thickness_m * 1e3,
                m.qr_m * 1e3,
                m.steepest_angle_rad.to_degrees()
            )
        };
        s += "Flange (EN 13715 measures: S_h from the taping line, S_d 10 mm above it from the flange back, qR to 2 mm inside the tip):\n\n";
        s += "| wheel | S_h [mm] | S_d [mm] | qR [mm] | steepest flank [°] |\n|---|---|---|---|---|\n";
        s += &row(&t.name, m);
        if let Some(r) = &self.reference_measures {
            s += &row(&self.reference_name, r);
        }
        let problems = m.problems();
        s += &if problems.is_empty() {
            "\nWithin EN 13715's flange heights and thicknesses, qR ≥ 6.5 mm, steepest flank ≥ 70°.\n\n"
                .to_string()
        } else {
            format!("\nOutside the EN 13715-type ranges: {}\n\n", problems.join("; "))
        };
        let (lo, hi) = self.table.range();
        let (rlo, rhi) = self.reference_table.range();
        s += &format!(
            "Flange contact (the contact leaving the steepest flank): designed ±{:.2} mm ({:.2} … {:.2}), {} {:.2} … {:.2} mm\n\n",
            0.5 * (hi - lo) * 1e3,
            lo * 1e3,
            hi * 1e3,
            self.reference_name,
            rlo * 1e3,
            rhi * 1e3
        );
        s += &format!(
            "Contact jumps, designed: {}\n\n{}\n\n",
            Self::checks_line(&self.checks),
            jump_free_span(&self.checks)
        );
        s += &format!(
            "Contact jumps, {}: {}\n\n",
            self.reference_name,
            Self::checks_line(&self.reference_checks)
        );
        s += &format!(
            "Equivalent conicity (EN 15302 Annex B):\n\n| ŷ [mm] | {} | {} |\n|---|---|---|\n",
            t.name, self.reference_name
        );
        let f = |v: &Option<f64>| v.map_or("—".to_string(), |v| format!("{v:.4}"));
        for (a, c, r) in &self.conicity {
            s += &format!("| {:.1} | {} | {} |\n", a * 1e3, f(c), f(r));
        }
        s += "\nRealism on the centred gauge (the thresholds and their reasons: `kecsim::contact::design::realism`; a failed check is flagged here, not refused):\n\n";
        let mut names = vec![t.name.as_str()];
        let mut figures = vec![&self.realism];
        if let Some(r) = &self.reference_realism {
            names.push(&self.reference_name);
            figures.push(r);
        }
        s += &Realism::markdown(&names, &figures);
        s += &format!(
            "\nTarget contact angle γ(y) of the left wheel (y towards its flange): {}\n",
            t.contact_angle
                .iter()
                .map(|(y, g)| format!("{:+.2} mm → {:.2}°", y * 1e3, g.to_degrees()))
                .collect::<Vec<_>>()
                .join(", ")
        );
        s
    }

    /// The design's verdict in one line: the contact jumps on the centred gauge and over the
    /// gauge columns, the flange against EN 13715's ranges, the realism checks.
    pub fn verdict(&self) -> String {
        let centred = self.checks.iter().find(|c| c.gv == 0.0).map(|c| c.jumps.len());
        let all: usize = self.checks.iter().map(|c| c.jumps.len()).sum();
        let jumps = match centred {
            Some(0) => format!(
                "jump-free on the centred gauge ({})",
                jump_free_span(&self.checks)
            ),
            Some(n) => format!("{n} CONTACT JUMPS on the centred gauge ({all} over the gauge columns)"),
            None => format!("{all} contact jumps over the gauge columns"),
        };
        let flange = self.design.measures.problems();
        let flange = if flange.is_empty() {
            "the flange within EN 13715's ranges".to_string()
        } else {
            format!("the flange OUTSIDE EN 13715's ranges ({})", flange.join("; "))
        };
        let realism = self.realism.problems();
        let realism = if realism.is_empty() {
            "every realism check passed".to_string()
        } else {
            format!("{} realism checks FAILED ({})", realism.len(), realism.join("; "))
        };
        format!("{jumps}; {flange}; {realism}")
    }

    /// The profile file's header: where it comes from, where it runs and the target, so that it
    /// can be redone (`kecsim design-wheel --target` with these values).
    pub fn header_lines(&self, inclination: &str, pair: &WheelRailPair) -> Vec<String> {
        let d = &self.design;
        let t = &d.target;
        let w = &pair.wheelset;
        vec![
            format!(
                "designed by `kecsim design-wheel` (direct conjugate design: the wheel built point by point from a target contact angle gamma(y), its roll iterated on the constraints Eq. 35-42)"
            ),
            format!(
                "for rail {} at {}, gauge {:.1} mm, back-to-back {:.1} mm, taping line {:.1} mm from the flange back, r0 {:.1} mm",
                self.rail,
                inclination,
                pair.rail_placement.gauge.gauge_m * 1e3,
                w.back_to_back_m * 1e3,
                w.rolling_circle_from_back_m * 1e3,
                w.nominal_radius_m * 1e3
            ),
            format!(
                "target contact angle (y_mm -> deg): {}",
                t.contact_angle
                    .iter()
                    .map(|(y, g)| format!("{:.3} -> {:.3}", y * 1e3, g.to_degrees()))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            format!(
                "flange: height {:.2} mm, tip radius {:.2} mm; field side to {:.1} mm; curvature ramp {} per rad, points every {} mm",
                t.flange_height_m * 1e3,
                t.flange_tip_radius_m * 1e3,
                t.field_end_m * 1e3,
                t.curvature_ramp_per_rad,
                t.output_step_m * 1e3
            ),
            format!(
                "result: S_h {:.2} mm, S_d {:.2} mm, qR {:.2} mm, steepest flank {:.2} deg; flange contact at +-{:.2} mm; {}",
                d.measures.height_m * 1e3,
                d.measures.thickness_m * 1e3,
                d.measures.qr_m * 1e3,
                d.measures.steepest_angle_rad.to_degrees(),
                self.table.range().1 * 1e3,
                jump_free_span(&self.checks)
            ),
            format!(
                "realism: curvature margin >= {:.1} %, |ds_w/dy| <= {:.2}, |ds_r/dy| <= {:.2}, longest dwell on a rail joint {:.3} mm, conicity {}, wall (35 deg) at +-{}; checks failed: {}",
                self.realism.margin.value * 100.0,
                self.realism.wheel_speed.value,
                self.realism.rail_speed.value,
                self.realism.dwell.iter().map(|d| d.span_m).fold(0.0, f64::max) * 1e3,
                self.realism
                    .conicity
                    .iter()
                    .map(|(a, c)| format!("{:.0} mm {}", a * 1e3, c.map_or("-".into(), |c| format!("{c:.3}"))))
                    .collect::<Vec<_>>()
                    .join(", "),
                self.realism.wall_m().map_or("-".into(), |w| format!("{:.2} mm", w * 1e3)),
                self.realism.problems().len()
            ),
        ]
    }
}

/// The contact jumps of the gauge columns in words: the gauge variations (around 0) free of
/// them, and how many the others have.
pub fn jump_free_span(checks: &[ColumnCheck]) -> String {
    let free = |c: &ColumnCheck| c.jumps.is_empty();
    let Some(k0) = checks.iter().position(|c| c.gv == 0.0) else {
        return "no centred column".into();
    };
    if !free(&checks[k0]) {
        return format!("{} contact jumps on the centred gauge", checks[k0].jumps.len());
    }
    let mut lo = k0;
    while lo > 0 && free(&checks[lo - 1]) {
        lo -= 1;
    }
    let mut hi = k0;
    while hi + 1 < checks.len() && free(&checks[hi + 1]) {
        hi += 1;
    }
    let others: usize = checks.iter().map(|c| c.jumps.len()).sum();
    let mut s = format!(
        "no contact jump at gauge variations {:+.0} .. {:+.0} mm (each column up to its flange-climb limit)",
        checks[lo].gv * 1e3,
        checks[hi].gv * 1e3
    );
    if others > 0 {
        s += &format!(
            "; {others} at gv {} mm (both flanges at their walls: the gauge narrowed below the wheelset's play)",
            checks
                .iter()
                .filter(|c| !free(c))
                .map(|c| format!("{:+.0}", c.gv * 1e3))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    s
}

#[cfg(test)]
mod brute_tests;
#[cfg(test)]
mod tests;
