//! Contact lookup tables (paper §4.3, Eq. 43–46).
//!
//! **1-entry table**: the contact configuration tabulated against the lateral displacement y on a
//! track without irregularities, from flange contact on one side to flange contact on the other.
//! **2-entry table**: the same against (y, gv), gv the gauge variation. Each gauge column spans
//! its own gauge's flange contact on either side and is entered at the same fraction of the way
//! to it as the y asked is of the way to the flange-climb limit interpolated at its gv; a look-up
//! beyond that limit is refused.
//!
//! **Entry under irregularities.** The paper (Eq. 44–46, as printed) enters with ȳ = y − al and
//! returns z = z_clu + vp, φ = φ_clu + cl/(2 L_r). That ignores that a cross level *turns* the
//! rail pair: in the turned rails' frame the wheelset centre, r0 above rail level, sits r0·δ to
//! the side (1.2 mm of z error at cl = 5 mm on S1002/54E1). By default ([`CrossLevelEntry::Rotated`])
//! the tables are entered in the frame of the rail pair's rigid motion instead
//! ([`RailPairMotion`], [`enter_rotated`]); the printed form remains as [`CrossLevelEntry::Paper`].
//!
//! **Interpolation.** Each row stores, besides z, φ and the four surface parameters, their exact
//! derivatives with respect to y (and gv) from the implicit function theorem, so z, φ and the
//! surface parameters are interpolated by cubic Hermite polynomials with those slopes: C¹ and
//! fourth-order accurate where the geometry is smooth. Where the contact **jumps**, the jump
//! location is found by bisection and the table holds two rows at the same y (the limits from
//! either side), so that no interpolation ever runs across a jump: z and φ keep their kink, the
//! surface parameters their step. The other stored quantities (contact angles, rolling radii,
//! curvatures, contact positions) are interpolated by monotone piecewise-cubic Hermite (PCHIP,
//! Fritsch–Carlson) between jumps. Across gv (2-entry) a cubic Hermite with Catmull–Rom slopes
//! from the columns' own values, each column entered flange-aligned ([`LookupTable2::lookup`]);
//! a jump whose location does not move as the flange does is still smeared over one gv cell — the
//! 2-entry table's inherent error, measured by `kecsim bench contact`.

use rayon::prelude::*;
use serde::Deserialize;
use std::path::Path;

use super::geometry::{ContactError, ContactGeometry, ContactSolution};
use crate::interpolation::{catmull_rom_weights, cubic_hermite, hermite, pchip_slopes, quintic};
use crate::track::RailOffsets;

/// One tabulated contact configuration (SI). Also the result of a look-up.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TableRow {
    /// Lateral displacement y, m.
    pub y: f64,
    /// Gauge variation gv the row belongs to, m.
    pub gv: f64,
    /// x = [z, φ, s^lw, s^lr, s^rw, s^rr] (z: wheelset centre height, m; φ rad; s in m).
    pub x: [f64; 6],
    /// dx/dy.
    pub dx_dy: [f64; 6],
    /// dx/dgv.
    pub dx_dgv: [f64; 6],
    /// Contact angle left, right, rad.
    pub contact_angle: [f64; 2],
    /// Rolling radius left, right, m.
    pub rolling_radius: [f64; 2],
    /// Wheel and rail lateral curvatures: [wheel left, rail left, wheel right, rail right], 1/m.
    pub curvature: [f64; 4],
    /// Contact point positions in the wheelset-track frame: [Y_l, Z_l, Y_r, Z_r], m.
    pub position: [f64; 4],
    /// Smallest gap of a secondary point within the two-point tolerance, left and right, m
    /// (NaN where there is none).
    pub two_point_gap: [f64; 2],
}

/// Number of "other" quantities interpolated by PCHIP.
const N_OTHER: usize = 12;

impl TableRow {
    fn from_solution(s: &ContactSolution, gv: f64) -> Self {
        let gap = |p: &[super::geometry::SecondaryPoint]| p.iter().map(|q| q.gap).fold(f64::NAN, f64::min);
        TableRow {
            y: s.y,
            gv,
            x: s.x(),
            dx_dy: s.dx_dy,
            dx_dgv: s.dx_dgv,
            contact_angle: [s.left.contact_angle, s.right.contact_angle],
            rolling_radius: [s.left.rolling_radius, s.right.rolling_radius],
            curvature: [
                s.left.wheel_curvature,
                s.left.rail_curvature,
                s.right.wheel_curvature,
                s.right.rail_curvature,
            ],
            position: [
                s.left.position.0,
                s.left.position.1,
                s.right.position.0,
                s.right.position.1,
            ],
            two_point_gap: [gap(&s.secondary[0]), gap(&s.secondary[1])],
        }
    }

    /// Height of the wheelset centre z, m.
    pub fn z(&self) -> f64 {
        self.x[0]
    }
    /// Roll angle φ, rad.
    pub fn phi(&self) -> f64 {
        self.x[1]
    }
    /// Rolling radius difference Δr = r_left − r_right, m.
    pub fn delta_r(&self) -> f64 {
        self.rolling_radius[0] - self.rolling_radius[1]
    }

    /// The row of an ideal-track configuration (at ȳ) moved as Eq. (44)–(46) move the wheelset
    /// onto displaced rails: its centre from (ȳ, z) to (y, z + vp) and its roll by δ = cl/(2 L_r).
    /// The real contact points are the wheel's, so they move with it — c′ + R(δ)(p − c) — and the
    /// normals turn by δ with the rails (the contact angle by +δ on the left, −δ on the right).
    /// (Returning the ideal track's points instead put the lever arms off by (al, z_ir) per side:
    /// a false rolling-radius difference equal to the cross level and a roll moment ≈ W al.)
    pub fn displaced(&self, y: f64, vp: f64, delta: f64) -> TableRow {
        let mut r = *self;
        let (c_y, c_z) = (self.y, self.x[0]);
        let (sd, cd) = delta.sin_cos();
        r.y = y;
        r.x[0] = c_z + vp;
        r.x[1] = self.x[1] + delta;
        for i in 0..2 {
            let (dy, dz) = (self.position[2 * i] - c_y, self.position[2 * i + 1] - c_z);
            r.position[2 * i] = y + cd * dy - sd * dz;
            r.position[2 * i + 1] = r.x[0] + sd * dy + cd * dz;
        }
        r.contact_angle[0] = self.contact_angle[0] + delta;
        r.contact_angle[1] = self.contact_angle[1] - delta;
        r
    }

    fn other(&self) -> [f64; N_OTHER] {
        let mut o = [0.0; N_OTHER];
        o[0..2].copy_from_slice(&self.contact_angle);
        o[2..4].copy_from_slice(&self.rolling_radius);
        o[4..8].copy_from_slice(&self.curvature);
        o[8..12].copy_from_slice(&self.position);
        o
    }

    fn set_other(&mut self, o: &[f64; N_OTHER]) {
        self.contact_angle.copy_from_slice(&o[0..2]);
        self.rolling_radius.copy_from_slice(&o[2..4]);
        self.curvature.copy_from_slice(&o[4..8]);
        self.position.copy_from_slice(&o[8..12]);
    }
}

/// How a lookup table is entered under cross level: `cross_level_entry` of the `lookup` and
/// `lookup2` contact models.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum CrossLevelEntry {
    /// The rail pair's rigid motion ([`enter_rotated`]): the wheelset's pose taken into the turned
    /// rails' frame, the table entered there and its configuration turned back (the default).
    #[default]
    Rotated,
    /// Eq. (44)–(46) as printed: ȳ = y − al, z = z_clu + vp, φ = φ_clu + cl/(2 L_r), the contact
    /// points moved with the wheelset ([`TableRow::displaced`]).
    Paper,
}

/// The rigid motion of the rail pair that a set of rail offsets makes: what [`enter_rotated`]
/// enters a table with.
///
/// The online constraints (Eq. 38, [`ContactGeometry`]) place a side's rail profile frame at
/// O_σ = (σ L_r + y_σir, z_r + z_σir), turned by α_σ = σβ + δ with δ = cl/(2 L_r) (σ = +1 left,
/// −1 right; z_r the frames' height on the ideal track, L_r their lateral offset). With the pair's
/// centre m = (al, z_r + vp) and its half-span h = O_L − m = (L_r + gv/2, cl/2) = |h| (cos θ, sin θ):
///
/// ```text
/// O_σ = m + R(θ) [σ (L_r + gv_t/2), 0]      θ = atan2(cl, 2 L_r + gv),  gv_t = 2|h| − 2 L_r
/// α_σ = θ + σβ + ε                          ε = δ − θ
/// ```
///
/// that is, exactly the ideal pair at the gauge variation gv_t, translated by (al, vp) and turned
/// by θ about its centre — but for each profile frame turned a further ε about its own origin. To
/// second order θ = δ (1 − gv/(2 L_r)), gv_t = gv + L_r δ², ε = δ gv/(2 L_r) + δ³/3: the pair
/// turned by δ about the track centre at rail level, with the gauge variation as ±gv/2 in the
/// turned frame (METHOD.md §5) — up to the widening L_r δ², which [`enter_rotated`] leaves out on
/// purpose (the approximate constraints' linearised roll undoes it; see there). ε is neglected: it
/// tilts each rail head by at most 4.4e-5 rad (gv = cl = 10 mm, L_r = 0.75 m), moving the contact
/// by ε s^r ≲ 1.5 µm on the flange; with gv = 0 it is δ³/3 ≈ 1e-7 rad. (θ = δ instead would make
/// ε = 0 but leave the rails' origins ∓gv δ/2 off vertically — a cross level of gv δ in the turned
/// frame that the table does not hold, L_r/s^r ≈ 20–40 times the effect of ε.)
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RailPairMotion {
    /// The offsets' alignment, vertical profile, gauge variation and cross level, m.
    pub al: f64,
    pub vp: f64,
    pub gv: f64,
    pub cl: f64,
    /// The pair's rotation θ about its centre, rad.
    pub theta: f64,
    /// 2|h| = hypot(2 L_r + gv, cl), m (dθ/dgv = −sin θ / 2|h|).
    span: f64,
}

impl RailPairMotion {
    /// The motion of the rail pair with frames `l_r` either side of the track centre that `off`
    /// makes.
    pub fn new(off: &RailOffsets, l_r: f64) -> Self {
        let (al, vp, gv, cl) = off.combinations();
        let w = 2.0 * l_r + gv;
        RailPairMotion {
            al,
            vp,
            gv,
            cl,
            theta: cl.atan2(w),
            span: w.hypot(cl),
        }
    }
}

/// A 2-entry look-up this far beyond its flange-climb limit is still taken as at the limit (the
/// round-off of a y computed from the limit), m.
const LIMIT_ROUND_OFF_M: f64 = 1e-12;

/// Newton steps of [`enter_rotated`] at most (it converges in 2–3).
const ENTRY_MAX_ITERATIONS: usize = 20;
/// [`enter_rotated`] stops when its Newton step in y′ is below this, m.
const ENTRY_TOLERANCE_M: f64 = 1e-15;

/// Eq. (44)–(46) rederived as the rigid motion of the rail pair: the contact of a wheelset at
/// lateral displacement `y` on rails moved by `m` ([`RailPairMotion`]), from a table `table`
/// (y′ ↦ its row on the ideal track at the gauge variation gv of `m`, for a 2-entry table) whose
/// entries span `range`; `out_of_range(y′)` is the error for an entry y′ outside it. `z_r` is the
/// rail profile frames' height on the ideal track (the centre of the turn).
///
/// The contact of rigid profiles is unchanged by a rigid motion of wheelset and rails together.
/// In the turned rails' frame (origin at the pair's centre, axes turned by θ; c = cos θ,
/// s = sin θ) the rails are the ideal pair at gauge variation gv, so the wheelset's pose there is
/// the table's (Eq. 43):
///
/// ```text
/// y′ =  c (y − al) + s (z − z_r − vp)
/// z′ − z_r = −s (y − al) + c (z − z_r − vp),    z′ = z_clu(y′, gv),  φ′ = φ − θ = φ_clu(y′, gv)      (44′)
/// ```
///
/// y is the independent coordinate (coordinate partitioning), so y′ follows from the inverse map
/// with z eliminated,
///
/// ```text
/// G(y′) = c y′ − s (z_clu(y′) − z_r) − (y − al) = 0,        G′ = c − s ∂z_clu/∂y′               (45′)
/// ```
///
/// by Newton from y′ = (y − al + s (z_clu(y − al) − z_r))/c: G′ ∈ [0.95, 1.05] (|∂z_clu/∂y′| ≤ 7
/// on the flanges, |θ| ≤ 7 mrad), so it converges to round-off in 2–3 steps, and G is monotone, so
/// across a kink of z_clu (a contact jump) the steps still contract, by |1 − G′₊/G′₋| ≤ 0.1. Then
///
/// ```text
/// z = z_r + vp + s y′ + c (z_clu − z_r),     φ = φ_clu + θ                                         (46′)
/// ```
///
/// the contact points moved the same way, P = (al, z_r + vp) + R(θ)(P′ − (0, z_r)), the contact
/// angles turned by +θ on the left and −θ on the right (the normals turn with the rails), the
/// surface parameters, rolling radii and curvatures unchanged. The derivatives by the chain rule,
/// dy′/dy = 1/G′:
///
/// ```text
/// dz/dy = (s + c ∂z_clu/∂y′)/G′,   dφ/dy = (∂φ_clu/∂y′)/G′,   ds/dy = (∂s_clu/∂y′)/G′
/// ```
///
/// and in gv at fixed y, al, vp, cl (dθ/dgv = −s/2|h|) through dy′/dgv = −(∂G/∂gv)/G′, with the
/// table's own gv-slopes.
///
/// **Where this departs from the paper.** Eq. (44)–(46) as printed are (44′)–(46′) with θ → δ and
/// the s terms dropped: ȳ = y − al, z = z_clu + vp, φ = φ_clu + δ. But s (z − z_r − vp) ≈ r0 δ is
/// not small on the table's scale — 1 mm at cl = 5 mm on a 295 mm wheel — and near the flange it
/// changes z by a millimetre: the printed form is 1.2 mm / 1.6 mrad from the online constraints on
/// S1002/54E1 at 1:20 (r0 = 295 mm) at cl = ±5 mm, this one 0.017 mm / 0.017 mrad.
///
/// **The turned pair's gauge, and what remains.** Exactly, the turned rails are gv_t = gv + L_r δ²
/// apart ([`RailPairMotion`]); the table is entered at gv all the same (a 1-entry table at no gv
/// at all). The approximate constraints (Eq. 35–42) roll the wheel by the linearised
/// A(φ) = [[1, −φ], [φ, 1]] = (1 + φ²/2) R(φ) + O(φ³) (Eq. 37, 39) — a wheel that grows with its
/// roll — and R(θ) A(φ′) = A(φ′ + θ) − κ I + O(θ³), κ = θ²/2 + θ φ′: the online wheelset on the
/// turned rails is 2κ L_w wider and about κ r lower than the rigidly turned table's. Its θ² L_w
/// part cancels the rails' L_r δ² (L_w ≈ L_r, θ ≈ δ): entering at gv_t would be exact for rigidly
/// rolled wheels but twice as far from the approximate constraints (0.031 mm / 0.036 mrad at cl =
/// 5 mm on S1002/54E1, with the online solution itself as the table). What remains is the θ φ′
/// part, largest in flange contact where φ′ is: 0.017 mm / 0.017 mrad at cl = ±5 mm, 0.036 /
/// 0.034 at ±10 mm. It is the reference's linearisation, not the table's entries: an exact table
/// (the online solution on the ideal rails) corrected for κ — entered at gv − 2κ L_w, z raised by
/// κ r — agrees with the online constraints to 1–2 µm (measured: `tests/lookup_entry.rs`).
pub fn enter_rotated(
    y: f64,
    m: &RailPairMotion,
    z_r: f64,
    range: (f64, f64),
    table: impl Fn(f64) -> Result<TableRow, TableError>,
    out_of_range: impl FnOnce(f64) -> TableError,
) -> Result<TableRow, TableError> {
    let (s, c) = m.theta.sin_cos();
    let u = y - m.al;
    let (lo, hi) = range;
    // Beyond the range the table is held at its end (z_clu constant, G linear): Newton then finds
    // G's root there and the entry is refused below.
    let at = |v: f64| table(v.clamp(lo, hi));
    let mut yp = (u + s * (at(u)?.x[0] - z_r)) / c;
    let mut row = at(yp)?;
    for _ in 0..ENTRY_MAX_ITERATIONS {
        let slope = if (lo..=hi).contains(&yp) {
            row.dx_dy[0]
        } else {
            0.0
        };
        let step = (c * yp - s * (row.x[0] - z_r) - u) / (c - s * slope);
        yp -= step;
        row = at(yp)?;
        if step.abs() <= ENTRY_TOLERANCE_M {
            break;
        }
    }
    if !(lo..=hi).contains(&yp) {
        return Err(out_of_range(yp));
    }
    Ok(turned_back(&row, yp, y, m, z_r))
}

/// The last step of [`enter_rotated`]: the row `r` of the turned frame at y′ = `yp` (the ideal
/// pair at the gauge variation of `m`) moved back onto the displaced rails, for the wheelset at
/// `y`, with its derivatives by the chain rule (Eq. 46′ and below).
pub fn turned_back(r: &TableRow, yp: f64, y: f64, m: &RailPairMotion, z_r: f64) -> TableRow {
    let (s, c) = m.theta.sin_cos();
    let r = *r;
    let inv = 1.0 / (c - s * r.dx_dy[0]);
    let zc = r.x[0] - z_r;
    let mut out = r;
    out.y = y;
    out.gv = m.gv;
    out.x[0] = z_r + m.vp + s * yp + c * zc;
    out.x[1] = r.x[1] + m.theta;
    out.dx_dy[0] = (s + c * r.dx_dy[0]) * inv;
    for k in 1..6 {
        out.dx_dy[k] = r.dx_dy[k] * inv;
    }
    let theta_gv = -s / m.span;
    let yp_gv = -((-s * yp - c * zc) * theta_gv - s * r.dx_dgv[0]) * inv;
    out.dx_dgv[0] = (c * yp - s * zc) * theta_gv + (s + c * r.dx_dy[0]) * yp_gv + c * r.dx_dgv[0];
    out.dx_dgv[1] = r.dx_dy[1] * yp_gv + r.dx_dgv[1] + theta_gv;
    for k in 2..6 {
        out.dx_dgv[k] = r.dx_dy[k] * yp_gv + r.dx_dgv[k];
    }
    for i in 0..2 {
        let (py, pz) = (r.position[2 * i], r.position[2 * i + 1] - z_r);
        out.position[2 * i] = m.al + c * py - s * pz;
        out.position[2 * i + 1] = z_r + m.vp + s * py + c * pz;
    }
    out.contact_angle[0] = r.contact_angle[0] + m.theta;
    out.contact_angle[1] = r.contact_angle[1] - m.theta;
    out
}

/// Lookup-table errors.
#[derive(Debug, thiserror::Error)]
pub enum TableError {
    #[error(transparent)]
    Contact(#[from] ContactError),
    #[error("{what} = {value_mm:.4} mm is outside the table ({min_mm:.4} .. {max_mm:.4} mm)")]
    OutOfRange {
        what: &'static str,
        value_mm: f64,
        min_mm: f64,
        max_mm: f64,
    },
    /// A 2-entry look-up beyond the flange-climb limit at its gauge variation (each gauge column
    /// ends at its own; between columns the limit is interpolated linearly in gv).
    #[error("y = {y_mm:.4} mm is beyond the 2-entry table's flange-climb limit at gv = {gv_mm:.4} mm ({limit_mm:.4} mm)")]
    BeyondFlangeLimit { y_mm: f64, gv_mm: f64, limit_mm: f64 },
    #[error("{path}: cannot read table: {source}")]
    Io {
        path: String,
        #[source]
        source: std::io::Error,
    },
    #[error("{path}:{line}: {problem}")]
    Format {
        path: String,
        line: usize,
        problem: String,
    },
    #[error("{0}")]
    Invalid(String),
}

/// Table construction settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TableSettings {
    /// Grid step in y, m (EN 15302 asks for ≤ 0.1 mm).
    pub step_m: f64,
    /// Largest |y| tabulated; `None`: up to flange contact on each side (see [`flange_contact_limit`]).
    pub y_max_m: Option<f64>,
    /// A surface parameter that departs from its Hermite prediction by more than this between two
    /// grid nodes marks a contact jump, m.
    pub jump_threshold_m: f64,
    /// A grid interval is halved while the Hermite interpolation of z (m) or φ (rad) at its
    /// midpoint misses the online solution by more than this.
    pub refine_tolerance: f64,
    /// ... or a surface parameter misses by more than this, m.
    pub refine_tolerance_s_m: f64,
    /// ... or the chord of a contact angle misses it by more than this, rad.
    pub refine_tolerance_angle_rad: f64,
    /// At most this many halvings of a grid interval.
    pub max_refinements: u32,
}

impl Default for TableSettings {
    fn default() -> Self {
        TableSettings {
            step_m: 1e-4,
            y_max_m: None,
            jump_threshold_m: 2e-4,
            refine_tolerance: 1e-8,
            refine_tolerance_s_m: 1e-5,
            refine_tolerance_angle_rad: 2e-4,
            max_refinements: 8,
        }
    }
}

/// The coarsest grid step of a contact sweep asked for by a user, mm: coarser, the grid can step
/// over contact jumps (they are found between grid nodes): at 0.5 mm the sweep of S1002 on 60E1
/// misses one of its six.
pub const MAX_STEP_MM: f64 = 0.25;

impl TableSettings {
    /// The settings of a sweep asked for with a grid step and, optionally, a largest |y|, both in
    /// mm as `kecsim contact --step --y-max` and the Python package's `contact_sweep(step_mm=,
    /// y_max_mm=)` take them (`step.0` and `y_max.0` name the options in the errors): the step
    /// positive and at most [`MAX_STEP_MM`], the half-range positive. The half-range is checked
    /// against the pair by [`TableSettings::check_y_max`].
    pub fn from_mm(step: (&str, f64), y_max: Option<(&str, f64)>) -> Result<TableSettings, String> {
        let (name, v) = step;
        if v.is_finite() && v > MAX_STEP_MM {
            return Err(format!(
                "{name} {v} mm: a grid coarser than {MAX_STEP_MM} mm can step over contact jumps (they are found between grid nodes); default 0.1"
            ));
        }
        let positive = |(name, v): (&str, f64)| {
            if v.is_finite() && v > 0.0 {
                Ok(v * 1e-3)
            } else {
                Err(format!("{name} {v}: expected a positive length in mm"))
            }
        };
        Ok(TableSettings {
            step_m: positive(step)?,
            y_max_m: y_max.map(positive).transpose()?,
            ..TableSettings::default()
        })
    }

    /// The half-range ([`TableSettings::y_max_m`], named `name` in the error) checked against the
    /// pair's flange climb ([`flange_limits`]): a table asked beyond it would tabulate a wheel
    /// climbing over its flange tip (a derailment), which no contact model uses.
    pub fn check_y_max(&self, geom: &ContactGeometry, name: &str) -> Result<(), TableError> {
        let Some(m) = self.y_max_m else {
            return Ok(());
        };
        let (lo, hi) = flange_limits(geom, 0.0)?;
        let limit = (-lo).max(hi);
        if m <= limit + 1e-9 {
            return Ok(());
        }
        Err(TableError::Invalid(format!(
            "{name} {:.3} mm: beyond the flange climb at {:.3} / {:.3} mm (where the contact leaves the flange's steepest flank towards its tip); a table past it would tabulate a wheel climbing over its flange — give at most {:.3} mm, or leave {name} out for flange contact to flange contact",
            m * 1e3,
            lo * 1e3,
            hi * 1e3,
            limit * 1e3
        )))
    }
}

/// Surface parameters that differ by more than this at a located jump make it a real jump, m.
const JUMP_MIN_STEP_M: f64 = 1e-5;

/// A contact jump found while building a table.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Jump {
    /// Where, m.
    pub y: f64,
    /// Which side's contact jumps (true for left), and the wheel surface parameter before/after, m.
    pub left: bool,
    pub s_wheel_before: f64,
    pub s_wheel_after: f64,
}

/// The 1-entry lookup table (at one gauge variation).
#[derive(Debug, Clone)]
pub struct LookupTable1 {
    /// Gauge variation of this table, m (0 for the plain 1-entry table).
    pub gv: f64,
    /// Rows sorted by y; a jump is two consecutive rows with the same y.
    pub rows: Vec<TableRow>,
    /// PCHIP slopes d(other)/dy per row (one-sided at jumps and ends).
    other_slopes: Vec<[f64; N_OTHER]>,
    /// Jumps found.
    pub jumps: Vec<Jump>,
    /// Nominal rolling radius r0 and the rail profile frames' lateral offset L_r and height z_r on
    /// the ideal track, m (the entry under irregularities: [`RailPairMotion`], [`enter_rotated`]).
    pub r0: f64,
    pub l_r: f64,
    pub z_r: f64,
    /// The y of flange climb on the right (< 0) and on the left (> 0) at this table's gauge
    /// variation, m, which the table spans (its range snapped to its grid; a table built or read
    /// over a fixed range: the range).
    pub flange_limits: (f64, f64),
}

/// The 0.1 mm scan up the flange from y = 0 shared by [`flange_contact_limit`] and
/// [`flange_angle`]: the contact angles of one side, past 45°, until they fall
/// [`FLANGE_FLANK_TOLERANCE_RAD`] below the largest so far (or the wheel leaves the profile).
/// Returns the last y (≥ 0, towards that side) whose angle is within the tolerance of the
/// largest, the largest sampled angle, whether the scan ended on a falling angle (else the
/// profile ended), and the sampled y of the largest angle.
fn flange_scan(angle: &impl Fn(f64) -> Result<f64, TableError>) -> Result<(f64, f64, bool, f64), TableError> {
    let step = FLANGE_SCAN_STEP_M;
    let mut prev = angle(0.0)?;
    let mut largest = prev;
    let mut at = 0.0;
    let mut y = 0.0;
    loop {
        let next_y = y + step;
        let a = match angle(next_y) {
            Ok(a) => a,
            Err(_) if prev > 45f64.to_radians() => return Ok((y, largest, false, at)),
            Err(e) => return Err(e),
        };
        if prev > 45f64.to_radians() && a < largest - FLANGE_FLANK_TOLERANCE_RAD {
            return Ok((y, largest, true, at));
        }
        if a > largest {
            largest = a;
            at = next_y;
        }
        if next_y > 0.05 {
            return Err(TableError::Invalid(
                "no flange contact found within 50 mm of the centred position".into(),
            ));
        }
        prev = a;
        y = next_y;
    }
}

/// Step of the scan up the flange (`flange_scan`), m.
pub const FLANGE_SCAN_STEP_M: f64 = 1e-4;

/// The contact angle of one side at |y| towards that side.
fn side_angle(
    geom: &ContactGeometry,
    off: RailOffsets,
    left: bool,
) -> impl Fn(f64) -> Result<f64, TableError> + '_ {
    move |y: f64| {
        let s = geom.solve(if left { y } else { -y }, &off)?;
        Ok(if left {
            s.left.contact_angle
        } else {
            s.right.contact_angle
        })
    }
}

/// The y up to which the wheelset can go towards the left before that wheel climbs its flange:
/// the contact runs up the flange's steepest flank and leaves it towards the tip, where the
/// contact angle has fallen [`FLANGE_FLANK_TOLERANCE_RAD`] below its largest value (S1002's flank
/// is straight, 70°, for about 1.4 mm of the wheel; on S1002/60E1 and 54E1 the rigid contact
/// jumps onto it close to that end — the same limit as the elastic model's). Found by a 0.1 mm
/// scan from y = 0, refined by bisection. By symmetry of use, the table spans ±this on a
/// symmetric pair; for an asymmetric pair both sides are scanned.
pub fn flange_contact_limit(
    geom: &ContactGeometry,
    off: &RailOffsets,
    left: bool,
) -> Result<f64, TableError> {
    let angle = side_angle(geom, *off, left);
    let (y, largest, falls, _) = flange_scan(&angle)?;
    if !falls {
        return Ok(y);
    }
    // The angle crosses largest − tolerance between y and y + step: bisection.
    let threshold = largest - FLANGE_FLANK_TOLERANCE_RAD;
    let (mut lo, mut hi) = (y, y + FLANGE_SCAN_STEP_M);
    while hi - lo > 1e-7 {
        let mid = 0.5 * (lo + hi);
        if angle(mid)? >= threshold {
            lo = mid
        } else {
            hi = mid
        }
    }
    Ok(lo)
}

/// Both flange-climb limits of `geom` at gauge variation `gv` ([`flange_contact_limit`]): the y
/// of the right flange's (< 0) and of the left flange's (> 0), m.
pub fn flange_limits(geom: &ContactGeometry, gv: f64) -> Result<(f64, f64), TableError> {
    let off = RailOffsets::gauge_variation(gv);
    let (right, left) = rayon::join(
        || flange_contact_limit(geom, &off, false),
        || flange_contact_limit(geom, &off, true),
    );
    Ok((-right?, left?))
}

/// How far below its largest value the contact angle falls where the contact leaves the flange's
/// steepest flank towards the tip (a flange climb beyond), rad: 0.5°.
pub const FLANGE_FLANK_TOLERANCE_RAD: f64 = 0.5 * std::f64::consts::PI / 180.0;

/// The flange angle of a pair for Nadal's limit: the largest contact angle, reached where the
/// contact climbs the flange — on the ideal track, the larger of both sides' sampled maxima of the
/// 0.1 mm scan up the flange that [`flange_contact_limit`] also uses (near its maximum the angle
/// is flat: the sampled one is within hundredths of a degree of the true one), rad.
pub fn flange_angle(geom: &ContactGeometry) -> Result<f64, TableError> {
    flange_angle_found(geom).map(|f| f.angle_rad)
}

/// Where [`flange_angle`] found each side's largest sampled contact angle, and that angle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlangeAngleScan {
    /// The flange angle: the larger of both sides' largest sampled contact angles, rad.
    pub angle_rad: f64,
    /// The sampled |y| of the left wheel's and of the right wheel's largest angle, m.
    pub at_m: [f64; 2],
}

/// [`flange_angle`] with where each side's largest angle was sampled.
pub fn flange_angle_found(geom: &ContactGeometry) -> Result<FlangeAngleScan, TableError> {
    let off = RailOffsets::default();
    let side = |left: bool| flange_scan(&side_angle(geom, off, left)).map(|(_, a, _, at)| (a, at));
    let (l, r) = rayon::join(|| side(true), || side(false));
    let ((al, yl), (ar, yr)) = (l?, r?);
    Ok(FlangeAngleScan {
        angle_rad: al.max(ar),
        at_m: [yl, yr],
    })
}

/// The flange angle from the places `at_m` ([`FlangeAngleScan::at_m`]) where a scan found each
/// side's largest angle (a cached scan), checked: each must be a sampled largest — above 45° and
/// no smaller than the angles one scan step either side of it — else an error saying which side
/// and what was found. The angle is computed from the geometry at those places (six contact
/// solutions instead of the scan's hundreds), bit for bit the scan's.
pub fn flange_angle_at(geom: &ContactGeometry, at_m: [f64; 2]) -> Result<f64, String> {
    let off = RailOffsets::default();
    let mut largest = f64::NEG_INFINITY;
    for (k, (left, name)) in [(true, "left"), (false, "right")].into_iter().enumerate() {
        let y = at_m[k];
        if !(y.is_finite() && (0.0..=0.05).contains(&y)) {
            return Err(format!(
                "the {name} flange's largest contact angle at |y| = {y} m: expected 0 ..= 0.05 m"
            ));
        }
        let angle = side_angle(geom, off, left);
        let a = angle(y).map_err(|e| format!("the {name} wheel at |y| = {:.4} mm: {e}", y * 1e3))?;
        if !(a > 45f64.to_radians() && a < std::f64::consts::FRAC_PI_2) {
            return Err(format!(
                "the {name} wheel's contact angle at |y| = {:.4} mm is {:.3}°: not a flange contact (expected 45° .. 90°)",
                y * 1e3,
                a.to_degrees()
            ));
        }
        for n in [y - FLANGE_SCAN_STEP_M, y + FLANGE_SCAN_STEP_M] {
            if let Ok(b) = angle(n) {
                // (1e-9 rad: the scan's neighbour below is summed in another order.)
                if b > a + 1e-9 {
                    return Err(format!(
                        "the {name} wheel's contact angle at |y| = {:.4} mm, {:.3}°, is not the flange's largest ({:.3}° at {:.4} mm)",
                        y * 1e3,
                        a.to_degrees(),
                        b.to_degrees(),
                        n * 1e3
                    ));
                }
            }
        }
        largest = largest.max(a);
    }
    Ok(largest)
}

/// One grid interval of a table being built: its solutions after the left node (up to and
/// including the right one) and the contact jump inside it, if any.
type Interval = (Vec<ContactSolution>, Option<Jump>);

/// The largest half-width a two-point transition centred at `c` may take: 0.45 of the distance
/// to the nearest other centre of `centres` or to an end of [lo, hi] (shared by the KEC profiles
/// and the tables).
pub(crate) fn transition_room(c: f64, centres: &[f64], lo: f64, hi: f64) -> f64 {
    0.45 * centres
        .iter()
        .filter(|&&o| o != c)
        .map(|o| (o - c).abs())
        .chain([c - lo, hi - c])
        .fold(f64::INFINITY, f64::min)
}

/// Cubic pieces a two-point transition is stored in (the tables' rows, the KEC profiles' nodes).
pub(crate) const TRANSITION_PIECES: usize = 8;

impl LookupTable1 {
    /// Builds the table of `geom` at gauge variation `gv` over `[y_min, y_max]` with step `step`,
    /// locating contact jumps exactly.
    pub fn build_range(
        geom: &ContactGeometry,
        gv: f64,
        y_min: f64,
        y_max: f64,
        settings: &TableSettings,
    ) -> Result<Self, TableError> {
        let off = RailOffsets::gauge_variation(gv);
        let nodes = (y_max - y_min) / settings.step_m;
        if !(settings.step_m > 0.0 && nodes.is_finite() && nodes >= 0.0) {
            return Err(TableError::Invalid(format!(
                "table grid y = {:.4}..{:.4} mm every {} mm: expected a positive step and a finite range",
                y_min * 1e3,
                y_max * 1e3,
                settings.step_m * 1e3
            )));
        }
        crate::limits::check(
            &format!("table grid points every {:.3e} mm", settings.step_m * 1e3),
            nodes,
            crate::limits::MAX_TABLE_NODES,
            "use a coarser step (intervals are refined where the geometry needs it)",
        )
        .map_err(TableError::Invalid)?;
        let n = (nodes.round().max(1.0)) as usize;
        let grid: Vec<f64> = (0..=n)
            .map(|k| y_min + (y_max - y_min) * k as f64 / n as f64)
            .collect();
        // The grid's solutions, then each interval's refinement, in parallel (each is a search of
        // its own; the results and the first error in grid order).
        let coarse = grid
            .par_iter()
            .map(|&y| geom.solve(y, &off))
            .collect::<Vec<_>>()
            .into_iter()
            .collect::<Result<Vec<_>, _>>()?;
        // Between grid nodes: a contact jump is located by bisection and held as two rows at the
        // same y; a sharp change of slope (the contact crossing a profile-curvature change) looks
        // like a jump to the detector but has equal limits, and becomes an ordinary node; then
        // intervals are halved where the Hermite cubic misses the online solution.
        let intervals: Vec<Result<Interval, TableError>> = coarse
            .par_windows(2)
            .map(|w| {
                let (a, b) = (&w[0], &w[1]);
                let mut sols = Vec::new();
                let mut jump = None;
                match Self::jump_between(a, b, settings.jump_threshold_m) {
                    Some(left) => {
                        let (sa, sb, yj) = Self::locate_jump(geom, &off, a, b, left)?;
                        Self::refine(geom, &off, a, &sa, settings, settings.max_refinements, &mut sols)?;
                        let step = (2..6).map(|k| (sa.x()[k] - sb.x()[k]).abs()).fold(0.0, f64::max);
                        if step > JUMP_MIN_STEP_M {
                            let k = if left { 2 } else { 4 };
                            jump = Some(Jump {
                                y: yj,
                                left,
                                s_wheel_before: sa.x()[k],
                                s_wheel_after: sb.x()[k],
                            });
                            sols.push(sb.clone());
                            Self::refine(geom, &off, &sb, b, settings, settings.max_refinements, &mut sols)?;
                        } else {
                            Self::refine(geom, &off, &sa, b, settings, settings.max_refinements, &mut sols)?;
                        }
                    }
                    None => Self::refine(geom, &off, a, b, settings, settings.max_refinements, &mut sols)?,
                }
                Ok((sols, jump))
            })
            .collect();
        let mut sols = vec![coarse[0].clone()];
        let mut jumps = Vec::new();
        for interval in intervals {
            let (part, jump) = interval?;
            sols.extend(part);
            jumps.extend(jump);
        }
        let rows: Vec<TableRow> = sols.iter().map(|s| TableRow::from_solution(s, gv)).collect();
        let pair = &geom.pair;
        Ok(Self::from_rows(
            gv,
            rows,
            jumps,
            pair.wheelset.nominal_radius_m,
            pair.rail_placement.lateral_m,
            pair.rail_placement.vertical_m,
        ))
    }

    /// The 1-entry table of `geom` (no irregularity) from flange contact on the right to flange
    /// contact on the left, unless `settings.y_max_m` fixes the range.
    pub fn build(geom: &ContactGeometry, settings: &TableSettings) -> Result<Self, TableError> {
        let (lo, hi) = match settings.y_max_m {
            Some(m) => (-m, m),
            None => flange_limits(geom, 0.0)?,
        };
        // Snap the range to the grid through y = 0, so that y = 0 is a node.
        let k = |v: f64| (v / settings.step_m).round() * settings.step_m;
        let mut t = Self::build_range(geom, 0.0, k(lo), k(hi), settings)?;
        t.flange_limits = (lo, hi);
        Ok(t)
    }

    /// Appends the solutions strictly after `a` up to and including `b`, halving the interval
    /// while the midpoint misses the Hermite prediction by more than the tolerance.
    fn refine(
        geom: &ContactGeometry,
        off: &RailOffsets,
        a: &ContactSolution,
        b: &ContactSolution,
        settings: &TableSettings,
        depth: u32,
        out: &mut Vec<ContactSolution>,
    ) -> Result<(), TableError> {
        if depth > 0 {
            let ym = 0.5 * (a.y + b.y);
            let mid = geom.solve(ym, off)?;
            let miss = |c: usize| {
                (hermite(a.y, b.y, a.x()[c], b.x()[c], a.dx_dy[c], b.dx_dy[c], ym).0 - mid.x()[c]).abs()
            };
            let miss_zphi = (0..2).map(miss).fold(0.0, f64::max);
            // The surface parameters too: where the contact is near-conformal they move several
            // times faster than y (ds^w/dy = 1 + ρ_r/Δ), and the contact points, angles and
            // curvatures that the forces read are interpolated between these rows.
            let miss_s = (2..6).map(miss).fold(0.0, f64::max);
            // And the contact angles (interpolated by PCHIP, without exact slopes): the chord's
            // miss at the midpoint, h²γ''/8, bounds what PCHIP leaves by far.
            let miss_angle = [(a.left, b.left, mid.left), (a.right, b.right, mid.right)]
                .iter()
                .map(|(p, q, m)| (0.5 * (p.contact_angle + q.contact_angle) - m.contact_angle).abs())
                .fold(0.0, f64::max);
            if miss_zphi > settings.refine_tolerance
                || miss_s > settings.refine_tolerance_s_m
                || miss_angle > settings.refine_tolerance_angle_rad
            {
                Self::refine(geom, off, a, &mid, settings, depth - 1, out)?;
                return Self::refine(geom, off, &mid, b, settings, depth - 1, out);
            }
        }
        out.push(b.clone());
        Ok(())
    }

    /// A jump between two grid solutions: a surface parameter departs from the Hermite-consistent
    /// prediction. Returns which side (true = left).
    fn jump_between(a: &ContactSolution, b: &ContactSolution, threshold: f64) -> Option<bool> {
        let h = b.y - a.y;
        for (k, left) in [(2usize, true), (3, true), (4, false), (5, false)] {
            let predicted = 0.5 * (a.dx_dy[k] + b.dx_dy[k]) * h;
            if ((b.x()[k] - a.x()[k]) - predicted).abs() > threshold {
                return Some(left);
            }
        }
        None
    }

    /// Bisection for the jump between `a` (before) and `b` (after): returns the branch-A and
    /// branch-B solutions at the jump, and its y.
    fn locate_jump(
        geom: &ContactGeometry,
        off: &RailOffsets,
        a: &ContactSolution,
        b: &ContactSolution,
        left: bool,
    ) -> Result<(ContactSolution, ContactSolution, f64), TableError> {
        let k = if left { 2 } else { 4 };
        let (mut lo, mut hi) = (a.y, b.y);
        let (mut last_a, mut last_b) = (a.clone(), b.clone());
        while hi - lo > 1e-10 {
            let m = 0.5 * (lo + hi);
            let s = geom.solve(m, off)?;
            if (s.x()[k] - last_a.x()[k]).abs() < (s.x()[k] - last_b.x()[k]).abs() {
                lo = m;
                last_a = s;
            } else {
                hi = m;
                last_b = s;
            }
        }
        // At the jump both branches touch at once, so z_A(y_j) = z_B(y_j): refine y_j by secant
        // steps on z_A − z_B with each branch continued by Newton from its bisection limit, so
        // that the twin rows share z and φ. Where the continuation misbehaves (near-conformal
        // contact), the two global solutions 1e-10 m either side of the jump are kept.
        if let Some((a_j, b_j)) = Self::refine_jump(geom, off, &last_a, &last_b) {
            let yj = a_j.y;
            return Ok((a_j, b_j, yj));
        }
        let yj = 0.5 * (lo + hi);
        last_a.y = yj;
        last_b.y = yj;
        Ok((last_a, last_b, yj))
    }

    /// Secant refinement of a jump between branch solutions `a` (before) and `b` (after).
    fn refine_jump(
        geom: &ContactGeometry,
        off: &RailOffsets,
        a: &ContactSolution,
        b: &ContactSolution,
    ) -> Option<(ContactSolution, ContactSolution)> {
        let branch_gap = |y: f64| -> Option<(f64, ContactSolution, ContactSolution)> {
            let (sa, _, _) = geom.newton(y, off, a.x()).ok()?;
            let (sb, _, _) = geom.newton(y, off, b.x()).ok()?;
            Some((
                sa[0] - sb[0],
                geom.solve_from(y, off, a).ok()?,
                geom.solve_from(y, off, b).ok()?,
            ))
        };
        let (mut y0, mut y1) = (a.y, b.y);
        let (mut g0, _, _) = branch_gap(y0)?;
        let (mut g1, _, _) = branch_gap(y1)?;
        for _ in 0..8 {
            if g1 == g0 {
                break;
            }
            let y2 = y1 - g1 * (y1 - y0) / (g1 - g0);
            // The bisection located the switch of the global solution only as well as the
            // interpenetration tolerance allows: accept a root within 1 µm of it.
            if (y2 - 0.5 * (a.y + b.y)).abs() > 1e-6 {
                return None;
            }
            let (g2, sa, sb) = branch_gap(y2)?;
            if g2.abs() < 1e-13 {
                // Same configuration on both branches (to round-off, made exact so that the
                // equivalent profiles meet in one point), different contact points.
                let same = (sa.phi - sb.phi).abs() < 1e-11;
                let distinct = (2..6).any(|k| (sa.x()[k] - sb.x()[k]).abs() > 1e-6);
                let mut sb = sb;
                sb.z = sa.z;
                sb.phi = sa.phi;
                return (same && distinct).then_some((sa, sb));
            }
            (y0, g0, y1, g1) = (y1, g1, y2, g2);
        }
        None
    }

    /// Assembles a table from rows (sorted by y, jumps as duplicate y), computing PCHIP slopes;
    /// its flange limits are its range.
    pub fn from_rows(gv: f64, rows: Vec<TableRow>, jumps: Vec<Jump>, r0: f64, l_r: f64, z_r: f64) -> Self {
        let mut other_slopes = vec![[0.0; N_OTHER]; rows.len()];
        let mut start = 0;
        for end in 1..=rows.len() {
            if end == rows.len() || rows[end].y <= rows[end - 1].y {
                let ys: Vec<f64> = rows[start..end].iter().map(|r| r.y).collect();
                let others: Vec<[f64; N_OTHER]> = rows[start..end].iter().map(|r| r.other()).collect();
                for c in 0..N_OTHER {
                    let vs: Vec<f64> = others.iter().map(|o| o[c]).collect();
                    for (slopes, d) in other_slopes[start..end].iter_mut().zip(pchip_slopes(&ys, &vs)) {
                        slopes[c] = d;
                    }
                }
                start = end;
            }
        }
        let flange_limits = (rows[0].y, rows[rows.len() - 1].y);
        LookupTable1 {
            gv,
            rows,
            other_slopes,
            jumps,
            r0,
            l_r,
            z_r,
            flange_limits,
        }
    }

    /// Rounds each contact jump of the table over the lateral range in which, elastically, the
    /// load passes from one contact point to the other — the same departure from the paper as
    /// KEC's two-point transitions ([`crate::contact::kec::KecModel::with_two_point_transition`]),
    /// so that the tables and KEC model the same physics. Half-width a = ½ δ / |Δ tan γ| (δ the
    /// approach, Δ tan γ the jumping side's), at most ½ `max_width_m` and 0.45 of the distance to
    /// the next jump or the table's end. Inside, z and φ follow the quintic matching values,
    /// slopes and curvatures of both sides (C²: the rigid table's corner made the directional
    /// differences' velocity terms an impulse — an impact at every crossing), the surface
    /// parameters pass by Hermite between the sides' values and slopes, the other quantities
    /// linearly (then PCHIP over the new rows). `approach_m` = 0 keeps the rigid jumps.
    pub fn with_two_point_transition(self, approach_m: f64, max_width_m: f64) -> Self {
        if approach_m <= 0.0 || max_width_m <= 0.0 {
            return self;
        }
        let jumps_at: Vec<usize> = (0..self.rows.len().saturating_sub(1))
            .filter(|&k| self.rows[k].y == self.rows[k + 1].y)
            .collect();
        if jumps_at.is_empty() {
            return self;
        }
        let (lo, hi) = self.range();
        let ys: Vec<f64> = jumps_at.iter().map(|&k| self.rows[k].y).collect();
        let mut fillets: Vec<(f64, f64)> = Vec::new();
        for (j, &k) in jumps_at.iter().enumerate() {
            let (a, b) = (&self.rows[k], &self.rows[k + 1]);
            let dtan = (0..2)
                .map(|i| (b.contact_angle[i].tan() - a.contact_angle[i].tan()).abs())
                .fold(1e-6, f64::max);
            let half = (0.5 * approach_m / dtan)
                .min(0.5 * max_width_m)
                .min(transition_room(ys[j], &ys, lo, hi));
            if half > 1e-9 {
                fillets.push((ys[j], half));
            }
        }
        let inside = |y: f64| {
            fillets
                .iter()
                .any(|&(c, a)| y > c - a - 1e-12 && y < c + a + 1e-12)
        };
        let mut rows: Vec<TableRow> = self.rows.iter().filter(|r| !inside(r.y)).copied().collect();
        for &(c, a) in &fillets {
            let (Ok(r0), Ok(r1)) = (self.lookup(c - a), self.lookup(c + a)) else {
                continue;
            };
            let curv = |y: f64, comp: usize| self.curvature(y, comp);
            let ends = |comp: usize, r: &TableRow, y: f64| (r.x[comp], r.dx_dy[comp], curv(y, comp));
            for i in 0..=TRANSITION_PIECES {
                let t = i as f64 / TRANSITION_PIECES as f64;
                let y = c - a + 2.0 * a * t;
                let mut row = if t < 0.5 { r0 } else { r1 };
                row.y = y;
                for comp in 0..6 {
                    let (v, d) = if comp < 2 {
                        quintic(c - a, c + a, ends(comp, &r0, c - a), ends(comp, &r1, c + a), y)
                    } else {
                        hermite(
                            c - a,
                            c + a,
                            r0.x[comp],
                            r1.x[comp],
                            r0.dx_dy[comp],
                            r1.dx_dy[comp],
                            y,
                        )
                    };
                    row.x[comp] = v;
                    row.dx_dy[comp] = d;
                    row.dx_dgv[comp] = r0.dx_dgv[comp] + t * (r1.dx_dgv[comp] - r0.dx_dgv[comp]);
                }
                let (o0, o1) = (r0.other(), r1.other());
                let o: [f64; N_OTHER] = std::array::from_fn(|m| o0[m] + t * (o1[m] - o0[m]));
                row.set_other(&o);
                rows.push(row);
            }
        }
        rows.sort_by(|p, q| p.y.total_cmp(&q.y));
        let jumps = self
            .jumps
            .iter()
            .filter(|j| !fillets.iter().any(|&(c, _)| c == j.y))
            .copied()
            .collect();
        let mut t = Self::from_rows(self.gv, rows, jumps, self.r0, self.l_r, self.z_r);
        t.flange_limits = self.flange_limits;
        t
    }

    /// The second derivative in y of z (`comp` 0) or φ (1) of the table's interpolant at y (the
    /// cubic Hermite of the segment holding y).
    fn curvature(&self, y: f64, comp: usize) -> f64 {
        let k = self.segment(y);
        let (a, b) = (&self.rows[k], &self.rows[k + 1]);
        cubic_hermite(a.y, b.y, a.x[comp], b.x[comp], a.dx_dy[comp], b.dx_dy[comp], y).2
    }

    /// The segment k with rows[k].y <= y < rows[k+1].y (the right-hand limit at a jump).
    fn segment(&self, y: f64) -> usize {
        let k = match self.rows.partition_point(|r| r.y <= y) {
            0 => 0,
            p if p >= self.rows.len() => self.rows.len() - 2,
            p => p - 1,
        };
        if self.rows[k + 1].y == self.rows[k].y {
            k.saturating_sub(1)
        } else {
            k
        }
    }

    /// Tabulated y range, m.
    pub fn range(&self) -> (f64, f64) {
        (self.rows[0].y, self.rows[self.rows.len() - 1].y)
    }

    /// Interpolated contact configuration at `y` (no irregularity). Out of range is an error.
    pub fn lookup(&self, y: f64) -> Result<TableRow, TableError> {
        Ok(self.lookup_with_position_slopes(y)?.0)
    }

    /// [`LookupTable1::lookup`] with the y-slopes of the interpolated contact positions
    /// d[Y_l, Z_l, Y_r, Z_r]/dy (the PCHIP interpolant's own derivative), for the per-wheel entry
    /// ([`super::per_wheel`]).
    pub fn lookup_with_position_slopes(&self, y: f64) -> Result<(TableRow, [f64; 4]), TableError> {
        let (lo, hi) = self.range();
        if !(lo..=hi).contains(&y) {
            return Err(TableError::OutOfRange {
                what: "y",
                value_mm: y * 1e3,
                min_mm: lo * 1e3,
                max_mm: hi * 1e3,
            });
        }
        let k = self.segment(y);
        let (a, b) = (&self.rows[k], &self.rows[k + 1]);
        let mut out = *a;
        out.y = y;
        for c in 0..6 {
            let (v, d) = hermite(a.y, b.y, a.x[c], b.x[c], a.dx_dy[c], b.dx_dy[c], y);
            out.x[c] = v;
            out.dx_dy[c] = d;
            let t = (y - a.y) / (b.y - a.y);
            out.dx_dgv[c] = a.dx_dgv[c] + t * (b.dx_dgv[c] - a.dx_dgv[c]);
        }
        let (oa, ob) = (a.other(), b.other());
        let mut o = [0.0; N_OTHER];
        let mut slopes = [0.0; 4];
        for c in 0..N_OTHER {
            let (v, d) = hermite(
                a.y,
                b.y,
                oa[c],
                ob[c],
                self.other_slopes[k][c],
                self.other_slopes[k + 1][c],
                y,
            );
            o[c] = v;
            if c >= 8 {
                slopes[c - 8] = d;
            }
        }
        out.set_other(&o);
        let t = (y - a.y) / (b.y - a.y);
        out.two_point_gap = if t < 0.5 { a.two_point_gap } else { b.two_point_gap };
        Ok((out, slopes))
    }

    /// The contact of a wheelset at lateral displacement `y` on rails with offsets `off`, entered
    /// by the rail pair's rigid motion ([`CrossLevelEntry::Rotated`], [`enter_rotated`]). A 1-entry
    /// table ignores the gauge variation.
    pub fn contact(&self, y: f64, off: &RailOffsets) -> Result<TableRow, TableError> {
        self.contact_with(y, off, CrossLevelEntry::Rotated)
    }

    /// [`LookupTable1::contact`] with the entry chosen: [`CrossLevelEntry::Paper`] is Eq. (44)–(46)
    /// as printed — enter with ȳ = y − al, then z = z_clu + vp, φ = φ_clu + cl/(2 L_r), the contact
    /// points and normals moved with the wheelset ([`TableRow::displaced`]).
    pub fn contact_with(
        &self,
        y: f64,
        off: &RailOffsets,
        entry: CrossLevelEntry,
    ) -> Result<TableRow, TableError> {
        match entry {
            CrossLevelEntry::Paper => {
                let (al, vp, _gv, cl) = off.combinations();
                Ok(self.lookup(y - al)?.displaced(y, vp, cl / (2.0 * self.l_r)))
            }
            CrossLevelEntry::Rotated => {
                let m = RailPairMotion::new(off, self.l_r);
                let (lo, hi) = self.range();
                enter_rotated(
                    y,
                    &m,
                    self.z_r,
                    (lo, hi),
                    |v| self.lookup(v),
                    |v| TableError::OutOfRange {
                        what: "y",
                        value_mm: v * 1e3,
                        min_mm: lo * 1e3,
                        max_mm: hi * 1e3,
                    },
                )
            }
        }
    }

    /// Writes the table as CSV (the columns of the README, one row per tabulated y).
    pub fn write_csv(&self, path: &Path) -> std::io::Result<()> {
        write_rows_csv(path, &[self])
    }

    /// Reads a table written by [`LookupTable1::write_csv`].
    pub fn read_csv(path: &Path) -> Result<Self, TableError> {
        Ok(table_of(&read_rows_csv(path, false)?))
    }
}

/// The 2-entry lookup table over (y, gv): one 1-entry table per gauge variation, each over its own
/// y range.
#[derive(Debug, Clone)]
pub struct LookupTable2 {
    pub columns: Vec<LookupTable1>,
}

impl LookupTable2 {
    /// Builds the table at the gauge variations `gvs` (sorted, m), grid `settings.step_m` in y.
    ///
    /// With `settings.y_max_m` = `None` (the default) each column spans its own gauge's flange
    /// climb ([`flange_limits`]) on both sides (its range snapped outwards to the grid):
    /// [`LookupTable2::lookup`] enters every column at the y that lies as far towards its own
    /// flange limit as the y asked lies towards the limit interpolated at the gv asked, so no
    /// column is needed beyond its own flange climb. With `Some(m)` every column spans ±m (and its
    /// limits are ±m: the look-up is then at the same y in every column).
    pub fn build(geom: &ContactGeometry, gvs: &[f64], settings: &TableSettings) -> Result<Self, TableError> {
        if gvs.len() < 2 || gvs.windows(2).any(|w| w[1] <= w[0]) {
            return Err(TableError::Invalid(
                "a 2-entry table needs at least two increasing gauge variations".into(),
            ));
        }
        let n = gvs.len();
        // Per column: its flange limits (right, left), m, which it spans.
        let limits: Vec<(f64, f64)> = match settings.y_max_m {
            Some(m) => vec![(-m, m); n],
            None => gvs
                .par_iter()
                .map(|&gv| flange_limits(geom, gv))
                .collect::<Vec<_>>()
                .into_iter()
                .collect::<Result<Vec<_>, _>>()?,
        };
        // Snap each range outwards to the grid through y = 0.
        let step = settings.step_m;
        let ranges: Vec<(f64, f64)> = limits
            .iter()
            .map(|&(lo, hi)| ((lo / step).floor() * step, (hi / step).ceil() * step))
            .collect();
        crate::limits::check(
            &format!(
                "2-entry table nodes ({} gauge variations × grid points every {:.3e} mm)",
                n,
                step * 1e3
            ),
            ranges.iter().map(|(lo, hi)| (hi - lo) / step).sum(),
            crate::limits::MAX_TABLE_NODES,
            "use fewer gauge variations (a coarser gauge-variation step) or a coarser y step",
        )
        .map_err(TableError::Invalid)?;
        let columns = (0..n)
            .into_par_iter()
            .map(|k| -> Result<LookupTable1, TableError> {
                let mut c = LookupTable1::build_range(geom, gvs[k], ranges[k].0, ranges[k].1, settings)?;
                c.flange_limits = limits[k];
                Ok(c)
            })
            .collect::<Vec<_>>()
            .into_iter()
            .collect::<Result<Vec<_>, _>>()?;
        Ok(LookupTable2 { columns })
    }

    /// Every column with its two-point transitions
    /// ([`LookupTable1::with_two_point_transition`]).
    pub fn with_two_point_transition(self, approach_m: f64, max_width_m: f64) -> Self {
        LookupTable2 {
            columns: self
                .columns
                .into_iter()
                .map(|c| c.with_two_point_transition(approach_m, max_width_m))
                .collect(),
        }
    }

    /// Gauge variations tabulated, m.
    pub fn gvs(&self) -> Vec<f64> {
        self.columns.iter().map(|c| c.gv).collect()
    }

    /// The column j with gv_j ≤ gv ≤ gv_{j+1} (j + 1 < the number of columns) and the fraction t
    /// of the way; out of the gv range an error.
    fn bracket(&self, gv: f64) -> Result<(usize, f64), TableError> {
        let n = self.columns.len();
        let (g0, g1) = (self.columns[0].gv, self.columns[n - 1].gv);
        if !(g0..=g1).contains(&gv) {
            return Err(TableError::OutOfRange {
                what: "gv",
                value_mm: gv * 1e3,
                min_mm: g0 * 1e3,
                max_mm: g1 * 1e3,
            });
        }
        let j = self.columns.partition_point(|c| c.gv <= gv).clamp(1, n - 1) - 1;
        let (a, b) = (self.columns[j].gv, self.columns[j + 1].gv);
        Ok((j, (gv - a) / (b - a)))
    }

    /// The flange-climb limits (right < 0, left > 0) at gauge variation `gv`: the columns' own
    /// ([`LookupTable1::flange_limits`]), linear in gv between them, m.
    pub fn flange_limits(&self, gv: f64) -> Result<(f64, f64), TableError> {
        let (j, t) = self.bracket(gv)?;
        let (a, b) = (self.columns[j].flange_limits, self.columns[j + 1].flange_limits);
        Ok((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1)))
    }

    /// Interpolated configuration at (y, gv): 1-entry look-ups in the neighbouring columns, then
    /// cubic Hermite across gv with slopes from the columns' values themselves (centred
    /// differences over the neighbouring columns, one-sided at the range's ends: Catmull–Rom).
    /// z, φ and the surface parameters are then one fixed linear combination of up to four
    /// columns' values, so they are as continuous in y as the columns are (kinks at each column's
    /// jumps, never steps), and the y-slopes are the same combination of the columns' — the
    /// interpolant's own derivative. (The stored dx/dgv slopes are not used for it: they step where
    /// a column's contact jumps, which made z step in y between columns — issue 13.) The other
    /// quantities (contact positions, angles, radii, curvatures) are linear in gv.
    ///
    /// **Flange-aligned entry.** Column k is entered at y_k = y · λ_k/λ(gv), λ_k its own
    /// flange-climb limit on the side of y (right for y < 0) and λ(gv) the limit interpolated
    /// linearly in gv between the two bracketing columns ([`LookupTable2::flange_limits`]): each
    /// column at the same fraction of the way to its flange as the y asked. A flange (and each
    /// contact jump near it) lies at a fixed distance from its rail, so it moves with gv/2; at a
    /// fixed y the interpolation across gv smeared the flange's kink over a gv cell (1.2 mm of z
    /// between the 1 mm columns of S1002/60E1 at 1:40 near the flange, against 0.03 mm aligned;
    /// in the tread 0.009 against 0.002 mm). The slopes follow by the chain rule:
    /// ∂x/∂y = Σ w_k (λ_k/λ) x_k′(y_k), and ∂x/∂gv adds Σ w_k x_k′(y_k) y ∂(λ_k/λ)/∂gv. With equal
    /// limits in every column (a table built over a common ±y_max, or read from a file without the
    /// limits) y_k = y.
    ///
    /// A y beyond the flange-climb limit at gv is refused ([`TableError::BeyondFlangeLimit`]); an
    /// outer column enters the slopes only where it holds its y_k (always, for a table built here;
    /// else the slope on that side is one-sided, as at the gv range's ends).
    pub fn lookup(&self, y: f64, gv: f64) -> Result<TableRow, TableError> {
        let n = self.columns.len();
        let (j, t) = self.bracket(gv)?;
        let (lo, hi) = self.flange_limits(gv)?;
        if y > hi + LIMIT_ROUND_OFF_M || y < lo - LIMIT_ROUND_OFF_M {
            return Err(TableError::BeyondFlangeLimit {
                y_mm: y * 1e3,
                gv_mm: gv * 1e3,
                limit_mm: if y > hi { hi } else { lo } * 1e3,
            });
        }
        // The side's limits: λ(gv), its slope in gv, and each column's λ_k.
        let side = |c: &LookupTable1| {
            if y >= 0.0 {
                c.flange_limits.1
            } else {
                c.flange_limits.0
            }
        };
        let (la, lb) = (side(&self.columns[j]), side(&self.columns[j + 1]));
        let lambda = la + t * (lb - la);
        let lambda_gv = (lb - la) / (self.columns[j + 1].gv - self.columns[j].gv);
        // Column i at its y_i (clamped by round-off only), with dy_i/dy and dy_i/dgv; None where
        // it does not hold y_i.
        let entry = |i: usize| -> Option<Result<(TableRow, f64, f64), TableError>> {
            let c = &self.columns[i];
            let ratio = side(c) / lambda;
            let (a, b) = c.range();
            let yi = y * ratio;
            if yi < a - LIMIT_ROUND_OFF_M || yi > b + LIMIT_ROUND_OFF_M {
                return None;
            }
            Some(
                c.lookup(yi.clamp(a, b))
                    .map(|r| (r, ratio, -y * ratio * lambda_gv / lambda)),
            )
        };
        let bracketing = |i: usize| {
            entry(i).unwrap_or_else(|| {
                let (a, b) = self.columns[i].range();
                Err(TableError::OutOfRange {
                    what: "y (a 2-entry column)",
                    value_mm: y * 1e3,
                    min_mm: a * 1e3,
                    max_mm: b * 1e3,
                })
            })
        };
        let (a, b) = (bracketing(j)?, bracketing(j + 1)?);
        let before = if j > 0 { entry(j - 1).transpose()? } else { None };
        let after = if j + 2 < n {
            entry(j + 2).transpose()?
        } else {
            None
        };
        let g = |i: usize| self.columns[i].gv;
        let (w, dw) = catmull_rom_weights(
            before.is_some().then(|| g(j - 1)),
            g(j),
            g(j + 1),
            after.is_some().then(|| g(j + 2)),
            gv,
        );
        let rows = [before, Some(a), Some(b), after];
        let mut out = a.0;
        out.y = y;
        out.gv = gv;
        for c in 0..6 {
            let (mut x, mut xy, mut xg) = (0.0, 0.0, 0.0);
            for (k, r) in rows.iter().enumerate() {
                if let Some((r, dy, dg)) = r {
                    x += w[k] * r.x[c];
                    xy += w[k] * r.dx_dy[c] * dy;
                    xg += dw[k] * r.x[c] + w[k] * r.dx_dy[c] * dg;
                }
            }
            out.x[c] = x;
            out.dx_dy[c] = xy;
            out.dx_dgv[c] = xg;
        }
        let (oa, ob) = (a.0.other(), b.0.other());
        let o: [f64; N_OTHER] = std::array::from_fn(|c| oa[c] + t * (ob[c] - oa[c]));
        out.set_other(&o);
        Ok(out)
    }

    /// The contact of a wheelset at `y` on rails with offsets `off`, the gauge variation as second
    /// entry, entered by the rail pair's rigid motion ([`CrossLevelEntry::Rotated`],
    /// [`enter_rotated`]).
    pub fn contact(&self, y: f64, off: &RailOffsets) -> Result<TableRow, TableError> {
        self.contact_with(y, off, CrossLevelEntry::Rotated)
    }

    /// [`LookupTable2::contact`] with the entry chosen (see [`LookupTable1::contact_with`]).
    pub fn contact_with(
        &self,
        y: f64,
        off: &RailOffsets,
        entry: CrossLevelEntry,
    ) -> Result<TableRow, TableError> {
        let c0 = &self.columns[0];
        match entry {
            CrossLevelEntry::Paper => {
                let (al, vp, gv, cl) = off.combinations();
                Ok(self.lookup(y - al, gv)?.displaced(y, vp, cl / (2.0 * c0.l_r)))
            }
            CrossLevelEntry::Rotated => {
                let m = RailPairMotion::new(off, c0.l_r);
                let gv = m.gv;
                let (lo, hi) = self.flange_limits(gv)?;
                enter_rotated(
                    y,
                    &m,
                    c0.z_r,
                    (lo, hi),
                    |v| self.lookup(v, gv),
                    |v| TableError::BeyondFlangeLimit {
                        y_mm: v * 1e3,
                        gv_mm: gv * 1e3,
                        limit_mm: if v > hi { hi } else { lo } * 1e3,
                    },
                )
            }
        }
    }

    /// Writes all columns into one CSV (with the `gv_mm` column; one block of rows per column,
    /// each as long as its own range).
    pub fn write_csv(&self, path: &Path) -> std::io::Result<()> {
        write_rows_csv(path, &self.columns.iter().collect::<Vec<_>>())
    }

    /// Reads a table written by [`LookupTable2::write_csv`].
    pub fn read_csv(path: &Path) -> Result<Self, TableError> {
        let rows = read_rows_csv(path, true)?;
        let mut columns: Vec<LookupTable1> = Vec::new();
        let mut start = 0;
        for end in 1..=rows.len() {
            if end == rows.len() || rows[end].row.gv != rows[start].row.gv {
                if end - start < 2 {
                    return Err(TableError::Format {
                        path: path.display().to_string(),
                        line: 0,
                        problem: format!("gauge variation {} mm has a single row", rows[start].row.gv * 1e3),
                    });
                }
                columns.push(table_of(&rows[start..end]));
                start = end;
            }
        }
        if columns.len() < 2 || columns.windows(2).any(|w| w[1].gv <= w[0].gv) {
            return Err(TableError::Format {
                path: path.display().to_string(),
                line: 0,
                problem: "a 2-entry table needs at least two gauge variations in increasing order".into(),
            });
        }
        Ok(LookupTable2 { columns })
    }
}

/// The CSV columns, in order (after `gv_mm` for 2-entry tables). Lengths mm, angles rad unless
/// named (roll in mrad), derivatives in SI (m/m, rad/m).
pub const CSV_COLUMNS: [&str; 40] = [
    "y_mm",
    "z_mm",
    "roll_mrad",
    "dr_mm",
    "contact_angle_left_rad",
    "contact_angle_right_rad",
    "s_wheel_left_mm",
    "s_rail_left_mm",
    "s_wheel_right_mm",
    "s_rail_right_mm",
    "rolling_radius_left_mm",
    "rolling_radius_right_mm",
    "wheel_curvature_left_1pm",
    "rail_curvature_left_1pm",
    "wheel_curvature_right_1pm",
    "rail_curvature_right_1pm",
    "contact_y_left_mm",
    "contact_z_left_mm",
    "contact_y_right_mm",
    "contact_z_right_mm",
    "two_point_gap_left_mm",
    "two_point_gap_right_mm",
    "dz_dy",
    "droll_dy_rad_per_m",
    "ds_wheel_left_dy",
    "ds_rail_left_dy",
    "ds_wheel_right_dy",
    "ds_rail_right_dy",
    "dz_dgv",
    "droll_dgv_rad_per_m",
    "ds_wheel_left_dgv",
    "ds_rail_left_dgv",
    "ds_wheel_right_dgv",
    "ds_rail_right_dgv",
    "gv_mm",
    "r0_mm",
    "rail_lateral_offset_mm",
    "rail_vertical_offset_mm",
    "flange_limit_right_mm",
    "flange_limit_left_mm",
];

/// The columns a table file may lack: `gv_mm` (a 1-entry table's), and those added after the
/// first format — the rail frames' height (the centre of the cross level's turn; 0 when absent,
/// which moves the turn's centre by z_r θ ≈ nm) and the flange limits (the table's range when
/// absent).
const CSV_OPTIONAL: [&str; 4] = [
    "gv_mm",
    "rail_vertical_offset_mm",
    "flange_limit_right_mm",
    "flange_limit_left_mm",
];

pub(crate) fn row_values(r: &TableRow, t: &LookupTable1) -> [f64; 40] {
    let mm = 1e3;
    [
        r.y * mm,
        (r.x[0] - t.r0) * mm,
        r.x[1] * 1e3,
        r.delta_r() * mm,
        r.contact_angle[0],
        r.contact_angle[1],
        r.x[2] * mm,
        r.x[3] * mm,
        r.x[4] * mm,
        r.x[5] * mm,
        r.rolling_radius[0] * mm,
        r.rolling_radius[1] * mm,
        r.curvature[0],
        r.curvature[1],
        r.curvature[2],
        r.curvature[3],
        r.position[0] * mm,
        r.position[1] * mm,
        r.position[2] * mm,
        r.position[3] * mm,
        r.two_point_gap[0] * mm,
        r.two_point_gap[1] * mm,
        r.dx_dy[0],
        r.dx_dy[1],
        r.dx_dy[2],
        r.dx_dy[3],
        r.dx_dy[4],
        r.dx_dy[5],
        r.dx_dgv[0],
        r.dx_dgv[1],
        r.dx_dgv[2],
        r.dx_dgv[3],
        r.dx_dgv[4],
        r.dx_dgv[5],
        r.gv * mm,
        t.r0 * mm,
        t.l_r * mm,
        t.z_r * mm,
        t.flange_limits.0 * mm,
        t.flange_limits.1 * mm,
    ]
}

/// Writes the tables' rows, one per line, with the [`CSV_COLUMNS`] header (a NaN gap is an empty
/// cell).
fn write_rows_csv(path: &Path, tables: &[&LookupTable1]) -> std::io::Result<()> {
    let mut w = crate::files::csv_writer(path)?;
    w.write_record(CSV_COLUMNS)?;
    for (t, r) in tables.iter().flat_map(|t| t.rows.iter().map(move |r| (t, r))) {
        let cells: Vec<String> = row_values(r, t)
            .iter()
            .map(|v| {
                if v.is_nan() {
                    String::new()
                } else {
                    format!("{v:.12e}")
                }
            })
            .collect();
        w.write_record(&cells)?;
    }
    crate::files::commit_csv(w)
}

/// A row read from a table file, with what its table holds besides (repeated on every row).
struct ReadRow {
    row: TableRow,
    /// r0, L_r, z_r, m.
    frame: (f64, f64, f64),
    /// Flange limits (right, left), m; NaN where the file has none.
    flange_limits: (f64, f64),
}

fn read_rows_csv(path: &Path, two_entry: bool) -> Result<Vec<ReadRow>, TableError> {
    let p = path.display().to_string();
    let text = crate::limits::read_text(path).map_err(|source| TableError::Io {
        path: p.clone(),
        source,
    })?;
    let mut rdr = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let fmt = |line: usize, problem: String| TableError::Format {
        path: p.clone(),
        line,
        problem,
    };
    let header = rdr
        .headers()
        .map_err(|e| fmt(1, format!("malformed header: {e}")))?
        .clone();
    // Column index per name; None for an optional column the file lacks (and for gv_mm in a
    // 1-entry table, which ignores it).
    let mut col = [None; CSV_COLUMNS.len()];
    for (i, name) in CSV_COLUMNS.iter().enumerate() {
        if !two_entry && *name == "gv_mm" {
            continue;
        }
        col[i] = header.iter().position(|h| h == *name);
        // (gv_mm is optional only to a 1-entry table, skipped above.)
        if col[i].is_none() && (*name == "gv_mm" || !CSV_OPTIONAL.contains(name)) {
            return Err(fmt(1, format!("missing column '{name}'")));
        }
    }
    let mut rows = Vec::new();
    for rec in rdr.records() {
        let rec = rec.map_err(|e| {
            fmt(
                e.position().map_or(0, |q| q.line() as usize),
                format!("malformed row: {e}"),
            )
        })?;
        let line = rec.position().map_or(0, |q| q.line() as usize);
        let mut v = [0.0f64; CSV_COLUMNS.len()];
        for (i, name) in CSV_COLUMNS.iter().enumerate() {
            let Some(c) = col[i] else {
                v[i] = if name.starts_with("flange_limit") {
                    f64::NAN
                } else {
                    0.0
                };
                continue;
            };
            let cell = rec.get(c).unwrap_or("");
            v[i] = if cell.is_empty() && name.starts_with("two_point") {
                f64::NAN
            } else {
                cell.parse::<f64>()
                    .map_err(|_| fmt(line, format!("column '{name}': '{cell}' is not a number")))?
            };
        }
        let m = 1e-3;
        let r0 = v[35] * m;
        rows.push(ReadRow {
            row: TableRow {
                y: v[0] * m,
                gv: v[34] * m,
                x: [v[1] * m + r0, v[2] * 1e-3, v[6] * m, v[7] * m, v[8] * m, v[9] * m],
                dx_dy: [v[22], v[23], v[24], v[25], v[26], v[27]],
                dx_dgv: [v[28], v[29], v[30], v[31], v[32], v[33]],
                contact_angle: [v[4], v[5]],
                rolling_radius: [v[10] * m, v[11] * m],
                curvature: [v[12], v[13], v[14], v[15]],
                position: [v[16] * m, v[17] * m, v[18] * m, v[19] * m],
                two_point_gap: [v[20] * m, v[21] * m],
            },
            frame: (r0, v[36] * m, v[37] * m),
            flange_limits: (v[38] * m, v[39] * m),
        });
    }
    if rows.len() < 2 {
        return Err(fmt(rows.len() + 1, "a table needs at least two rows".into()));
    }
    Ok(rows)
}

/// A table of rows read from a file (all of one gauge variation).
fn table_of(rows: &[ReadRow]) -> LookupTable1 {
    let (r0, l_r, z_r) = rows[0].frame;
    let mut t = LookupTable1::from_rows(
        rows[0].row.gv,
        rows.iter().map(|r| r.row).collect(),
        Vec::new(),
        r0,
        l_r,
        z_r,
    );
    let (lo, hi) = rows[0].flange_limits;
    if lo.is_finite() && hi.is_finite() {
        t.flange_limits = (lo, hi);
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::profile::placement::WheelRailPair;
    use crate::profile::StandardProfile;

    fn geometry() -> ContactGeometry {
        let pair =
            WheelRailPair::standard(StandardProfile::S1002, StandardProfile::Rail60E1, "1:40").unwrap();
        ContactGeometry::with_defaults(pair)
    }

    /// The sweep's options as the command line and the Python package take them, checked in one
    /// place: the step in (0, 0.25] mm, the half-range positive and within the flange climb.
    #[test]
    fn sweep_options_are_checked_for_every_caller() {
        let s = TableSettings::from_mm(("--step", 0.25), Some(("--y-max", 3.0))).unwrap();
        assert_eq!((s.step_m, s.y_max_m), (0.25e-3, Some(3e-3)));
        let e = TableSettings::from_mm(("step_mm", 5.0), None).unwrap_err();
        assert!(e.starts_with("step_mm 5 mm: a grid coarser than 0.25 mm"), "{e}");
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let e = TableSettings::from_mm(("--step", bad), None).unwrap_err();
            assert!(e.contains("expected a positive length in mm"), "{bad}: {e}");
            let e = TableSettings::from_mm(("--step", 0.1), Some(("y_max_mm", bad))).unwrap_err();
            assert!(e.starts_with("y_max_mm ") && e.contains("positive"), "{bad}: {e}");
        }
        let g = geometry();
        s.check_y_max(&g, "--y-max").unwrap();
        let far = TableSettings::from_mm(("step_mm", 0.1), Some(("y_max_mm", 40.0))).unwrap();
        let e = far.check_y_max(&g, "y_max_mm").unwrap_err().to_string();
        assert!(
            e.starts_with("y_max_mm 40.000 mm: beyond the flange climb") && e.contains("leave y_max_mm out"),
            "{e}"
        );
    }

    #[test]
    fn table_reproduces_online_solution_and_holds_jumps() {
        let g = geometry();
        let settings = TableSettings {
            y_max_m: Some(0.007),
            ..TableSettings::default()
        };
        let t = LookupTable1::build(&g, &settings).unwrap();
        // S1002/60E1 1:40 jumps near the centred position and towards the flange (both sides).
        assert!(t.jumps.len() >= 4, "jumps {:?}", t.jumps);
        assert!(
            t.jumps.iter().any(|j| j.y.abs() < 1e-3),
            "a jump near y = 0: {:?}",
            t.jumps
        );
        // At the nodes the table is the online solution; between them within the interpolation error.
        let off = RailOffsets::default();
        for k in (0..t.rows.len()).step_by(17) {
            let r = &t.rows[k];
            let l = t.lookup(r.y).unwrap();
            assert!((l.z() - r.z()).abs() < 1e-15 || r.y == t.rows.get(k + 1).map_or(f64::NAN, |n| n.y));
        }
        let mut worst_z: f64 = 0.0;
        for k in 0..t.rows.len() - 1 {
            let (a, b) = (&t.rows[k], &t.rows[k + 1]);
            if b.y <= a.y {
                continue;
            }
            let y = 0.5 * (a.y + b.y);
            let online = g.solve(y, &off).unwrap();
            let l = t.lookup(y).unwrap();
            worst_z = worst_z.max((l.z() - online.z).abs());
            assert!(
                (l.phi() - online.phi).abs() < 1e-6,
                "phi at {y}: {} vs {}",
                l.phi(),
                online.phi
            );
        }
        assert!(worst_z < 1e-6, "z interpolation error {worst_z}");
        assert!(t.lookup(0.0071).is_err());
    }

    /// Issue 13, the 2-entry table's defect: between two gv columns the interpolation used each
    /// column's dz/dgv, which steps where that column's contact jumps: z(y) at a fixed gv between
    /// columns then stepped too (tens of µm), and the dynamics' second differences of z turned the
    /// steps into spikes of vertical acceleration that unloaded the wheels (the Manchester and MS
    /// vehicles lifted and stopped within 2–5 s). z and φ must be continuous in y at every gv —
    /// Lipschitz with the steepest flange slopes — and their y-slopes the interpolant's own.
    #[test]
    fn two_entry_table_is_continuous_in_y_between_its_columns() {
        let g = geometry();
        let gvs = [-2e-3, -1e-3, 0.0, 1e-3, 2e-3];
        let common = TableSettings {
            y_max_m: Some(6e-3),
            ..TableSettings::default()
        };
        let t = LookupTable2::build(&g, &gvs, &common).unwrap();
        let dy = 1e-6;
        for gv in [-1.5e-3, -0.3e-3, 0.5e-3, 1.7e-3] {
            let (mut worst_z, mut worst_phi, mut worst_slope): (f64, f64, f64) = (0.0, 0.0, 0.0);
            let n = 11_000;
            let mut prev = t.lookup(-5.5e-3, gv).unwrap();
            for k in 1..=n {
                let y = -5.5e-3 + k as f64 * dy;
                let r = t.lookup(y, gv).unwrap();
                worst_z = worst_z.max((r.z() - prev.z()).abs() / dy);
                worst_phi = worst_phi.max((r.phi() - prev.phi()).abs() / dy);
                // The stored slope is the interpolant's: its mean over the step matches the
                // difference (away from the kinks, where the two one-sided slopes differ).
                let fd = (r.z() - prev.z()) / dy;
                let mean = 0.5 * (r.dx_dy[0] + prev.dx_dy[0]);
                if (r.dx_dy[0] - prev.dx_dy[0]).abs() < 1e-4 {
                    worst_slope = worst_slope.max((fd - mean).abs());
                }
                prev = r;
            }
            println!(
                "gv {:.1} mm: max |dz/dy| {worst_z:.3}, max |dφ/dy| {worst_phi:.3} 1/m, slope mismatch {worst_slope:.2e}",
                gv * 1e3
            );
            // The steepest columns (flange contact, ~80°) reach |dz/dy| ≈ 7; a step of 20 µm
            // or more within 1 µm is a discontinuity (the defect gave 683).
            assert!(worst_z < 20.0, "z steps at gv = {gv}: {worst_z}");
            assert!(worst_phi < 30.0, "φ steps at gv = {gv}: {worst_phi}");
            assert!(
                worst_slope < 1e-4,
                "dz/dy not the interpolant's slope: {worst_slope}"
            );
        }
    }

    /// The tables' two-point transitions: no jump left, the rigid table's rows outside the
    /// transitions kept, z and φ meeting both sides with value, slope and curvature (C²), the
    /// curvature inside bounded by the quintic's 1.875 Δslope / 2a.
    #[test]
    fn table_two_point_transitions_are_c2_and_local() {
        let g = geometry();
        let rigid = LookupTable1::build(&g, &TableSettings::default()).unwrap();
        let (approach, width) = (5e-4, 5e-4);
        let smooth = rigid.clone().with_two_point_transition(approach, width);
        assert!(smooth.rows.windows(2).all(|w| w[1].y > w[0].y), "a jump is left");
        let jumps: Vec<(f64, f64)> = rigid
            .rows
            .windows(2)
            .filter(|w| w[0].y == w[1].y)
            .map(|w| {
                let dtan = (0..2)
                    .map(|i| (w[1].contact_angle[i].tan() - w[0].contact_angle[i].tan()).abs())
                    .fold(1e-6, f64::max);
                (w[0].y, (0.5 * approach / dtan).min(0.5 * width))
            })
            .collect();
        assert!(jumps.len() >= 4);
        for r in &rigid.rows {
            if jumps.iter().all(|&(c, a)| (r.y - c).abs() > a + 1e-9) {
                let l = smooth.lookup(r.y).unwrap();
                assert!((l.z() - r.z()).abs() < 1e-15 && (l.phi() - r.phi()).abs() < 1e-15);
            }
        }
        for &(c, a0) in &jumps {
            // The half-width actually used (limited by the neighbouring jumps too).
            let (lo, hi) = rigid.range();
            let room = jumps
                .iter()
                .filter(|j| j.0 != c)
                .map(|j| (j.0 - c).abs())
                .chain([c - lo, hi - c])
                .fold(f64::INFINITY, f64::min);
            let a = a0.min(0.45 * room);
            let (r0, r1) = (rigid.lookup(c - a).unwrap(), rigid.lookup(c + a).unwrap());
            for comp in 0..2 {
                for (y, r, out) in [(c - a, &r0, -1e-9), (c + a, &r1, 1e-9)] {
                    let l = smooth.lookup(y).unwrap();
                    assert!((l.x[comp] - r.x[comp]).abs() < 1e-12, "value at {y}");
                    assert!((l.dx_dy[comp] - r.dx_dy[comp]).abs() < 1e-6, "slope at {y}");
                    let (inside, outside) = (smooth.curvature(y - out, comp), rigid.curvature(y + out, comp));
                    let dslope = (r1.dx_dy[comp] - r0.dx_dy[comp]).abs();
                    assert!(
                        (inside - outside).abs() < 0.05 * (dslope / (2.0 * a) + outside.abs()) + 1e-6,
                        "jump {c}: comp {comp} curvature {inside} vs {outside}"
                    );
                }
                let dslope = (r1.dx_dy[comp] - r0.dx_dy[comp]).abs();
                let worst = (0..=100)
                    .map(|i| smooth.curvature(c - a + 2.0 * a * i as f64 / 100.0, comp).abs())
                    .fold(0.0, f64::max);
                assert!(
                    worst < 1.3 * 1.875 * dslope / (2.0 * a) + 50.0,
                    "jump {c}: curvature {worst}"
                );
            }
        }
    }

    #[test]
    fn csv_round_trip_and_missing_column() {
        let g = geometry();
        let t = LookupTable1::build(
            &g,
            &TableSettings {
                y_max_m: Some(0.001),
                ..TableSettings::default()
            },
        )
        .unwrap();
        let path = std::env::temp_dir().join(format!("kecsim-table-{}.csv", std::process::id()));
        t.write_csv(&path).unwrap();
        let u = LookupTable1::read_csv(&path).unwrap();
        for y in [-0.00093, -0.0002, 0.0, 0.00041, 0.00099] {
            let (a, b) = (t.lookup(y).unwrap(), u.lookup(y).unwrap());
            for c in 0..6 {
                assert!((a.x[c] - b.x[c]).abs() < 1e-12, "col {c} at {y}");
            }
        }
        let text = std::fs::read_to_string(&path)
            .unwrap()
            .replacen("roll_mrad", "roll_deg", 1);
        std::fs::write(&path, text).unwrap();
        let e = LookupTable1::read_csv(&path).unwrap_err().to_string();
        assert!(e.contains(":1: missing column 'roll_mrad'"), "{e}");
        let e = LookupTable2::read_csv(&path).unwrap_err().to_string();
        assert!(e.contains("missing column 'roll_mrad'"), "{e}");
    }
}
