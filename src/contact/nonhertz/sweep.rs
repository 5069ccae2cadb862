//! One wheelset's contact patches at prescribed lateral shifts, yaw and vertical wheel load: what
//! `kecsim patch` computes (the Manchester contact benchmark's set-up: Shackleton & Iwnicki,
//! *Vehicle System Dynamics* 46 (2008) 73–100; the contact-point positions and loads as CONTACT
//! computes them for it).
//!
//! At each shift y the rigid contact geometry ([`ContactGeometry::solve`]) gives the wheelset's
//! height and roll and each wheel's contact point. Each wheel then carries the vertical load Q,
//! the wheel pressed down onto its rail (the lateral position held, as in CONTACT's "vertical
//! problem with prescribed vertical force"):
//!
//! ```text
//! Σ_patches ( N_i n_i,z + F_i · e_z ) = Q
//! ```
//!
//! with F_i the patch's creep force — in flange contact the friction carries a good part of the
//! wheel's load (CONTACT includes it; so does this). The patches are Hertz's single ellipse at the
//! rigid contact point ([`PatchModel::Hertz`]) or the strip model's patches from the gap
//! ([`PatchModel::Strips`]).
//!
//! **Creepages** from the wheelset's rigid motion: forward speed V along the track, yaw ψ, no
//! lateral or yaw velocity, rolling at Ω = V / r0 about its yawed axle (no traction); at a patch's
//! load centre r = (0, Y − y, Z − z) turned by ψ, v_w = V e_x + Ω a × r, v_r = 0 (with
//! [`Creepage::from_velocities`]: the contact frame from the patch's normal and the axle).
//! **Creep forces** on the patch's equivalent ellipse (same area and width;
//! [`StripPatch::equivalent_ellipse`]) by the chosen creep model — Polach by default, spin
//! included; Kalker's coefficients at that ellipse's a/b.

use nalgebra::Vector3;

use super::gap::{GapInput, GapSection};
use super::strips::{self, StripPatch, StripSettings};
use super::validity::hertz_deviation;
use crate::contact::forces::creepage::{ContactFrame, Creepage};
use crate::contact::forces::hertz::{HertzContact, RelativeCurvature};
use crate::contact::forces::{ContactForceSettings, ContactPatch, CreepForce};
use crate::contact::geometry::{ContactGeometry, ContactSolution};
use crate::contact::ContactPoint;
use crate::profile::placement::WheelRailPair;
use crate::track::{RailOffsets, Side};

/// A contact within this of the flange tip's radius is on the tip (the wheel derailed), m.
pub const FLANGE_TIP_M: f64 = 5e-4;

/// The patch model: Hertz at the rigid contact point, or the strip model from the gap.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PatchModel {
    Hertz,
    Strips,
}

impl PatchModel {
    pub const ALL: [PatchModel; 2] = [PatchModel::Hertz, PatchModel::Strips];
    /// Names on the command line and in the CSV's `model` column.
    pub fn name(self) -> &'static str {
        match self {
            PatchModel::Hertz => "hertz",
            PatchModel::Strips => "kp",
        }
    }

    pub fn by_name(name: &str) -> Option<PatchModel> {
        match name {
            "hertz" => Some(PatchModel::Hertz),
            "kp" | "strips" => Some(PatchModel::Strips),
            _ => None,
        }
    }
}

/// The benchmark's set-up.
#[derive(Debug, Clone)]
pub struct PatchSweepSettings {
    /// Yaw per lateral shift, rad per m (the benchmark: 2.4 mrad per mm = 2.4 rad/m).
    pub yaw_per_m: f64,
    /// Vertical load per wheel, N.
    pub load: f64,
    /// Forward speed, m/s.
    pub speed: f64,
    pub forces: ContactForceSettings,
    pub strips: StripSettings,
    /// Half-width of the gap's window around the rigid contact, m.
    pub window_m: f64,
    /// The wheelset's rolling rate Ω, rad/s; None: rolling freely (the longitudinal creep
    /// forces' moment about the axle zero, found by the secant method).
    pub pitch_rate: Option<f64>,
}

/// One patch of one wheel.
#[derive(Debug, Clone, PartialEq)]
pub struct PatchResult {
    pub model: PatchModel,
    pub normal_force: f64,
    pub max_pressure: f64,
    pub area: f64,
    pub contact_angle: f64,
    pub s_rail: f64,
    pub s_wheel: f64,
    /// The ellipse the creep model used (a rolling, b lateral), m.
    pub semi_axes: (f64, f64),
    /// Rolling radius at the patch's load centre, m.
    pub rolling_radius: f64,
    pub creepage: Creepage,
    pub creep: CreepForce,
    /// The strip model's patch (None for Hertz).
    pub strips: Option<StripPatch>,
}

/// One wheel at one shift.
#[derive(Debug, Clone, PartialEq)]
pub struct WheelPatches {
    pub side: Side,
    /// The rigid contact point.
    pub rigid: ContactPoint,
    /// Hertz's gap deviation at the rigid contact ([`hertz_deviation`]; ∞ where conformal).
    pub hertz_deviation: f64,
    pub patches: Vec<PatchResult>,
}

/// All wheels at one shift, one model.
#[derive(Debug, Clone, PartialEq)]
pub struct ShiftPatches {
    /// Lateral shift (kecsim's y, to the left), m.
    pub y: f64,
    pub yaw: f64,
    pub z: f64,
    pub roll: f64,
    pub model: PatchModel,
    pub wheels: [WheelPatches; 2],
    /// The rolling rate Ω, rad/s.
    pub pitch_rate: f64,
}

/// Why a shift has no patches.
#[derive(Debug, thiserror::Error)]
pub enum PatchSweepError {
    #[error("y = {y_mm} mm: {message}")]
    Shift { y_mm: f64, message: String },
}

fn err(y: f64, message: impl ToString) -> PatchSweepError {
    PatchSweepError::Shift {
        y_mm: y * 1e3,
        message: message.to_string(),
    }
}

/// The patches of both wheels at shift `y` for `model`, at the settings' rolling rate or rolling
/// freely: Ω with Σ F_x r = 0 over all patches (no torque on the axle).
pub fn patches_at(
    pair: &WheelRailPair,
    geometry: &ContactGeometry,
    y: f64,
    model: PatchModel,
    settings: &PatchSweepSettings,
) -> Result<ShiftPatches, PatchSweepError> {
    let sol = rigid_contact(pair, geometry, y)?;
    if let Some(omega) = settings.pitch_rate {
        return patches_with(pair, &sol, y, model, settings, omega);
    }
    let torque = |sh: &ShiftPatches| -> f64 {
        sh.wheels
            .iter()
            .flat_map(|w| w.patches.iter())
            .map(|p| p.creep.fx * p.rolling_radius)
            .sum()
    };
    let mut w0 = settings.speed / pair.wheelset.nominal_radius_m;
    let mut s0 = patches_with(pair, &sol, y, model, settings, w0)?;
    let mut t0 = torque(&s0);
    let mut w1 = w0 * (1.0 + 1e-3);
    for _ in 0..40 {
        let s1 = patches_with(pair, &sol, y, model, settings, w1)?;
        let t1 = torque(&s1);
        if t1.abs() < 1e-6 * settings.load * pair.wheelset.nominal_radius_m || t1 == t0 {
            return Ok(s1);
        }
        let w2 = w1 - t1 * (w1 - w0) / (t1 - t0);
        (w0, t0, s0) = (w1, t1, s1);
        w1 = w2;
    }
    Err(err(y, format!("free rolling: no rolling rate balances the creep torque ({} left after 40 steps; last Ω {w0} rad/s)", t0 / s0.wheels.len() as f64)))
}

/// The wheelset's rigid contact at shift `y` (it does not depend on the rolling rate: solved once
/// per shift), refused where a wheel rides on its flange tip.
fn rigid_contact(
    pair: &WheelRailPair,
    geometry: &ContactGeometry,
    y: f64,
) -> Result<ContactSolution, PatchSweepError> {
    let off = RailOffsets::default();
    let sol = geometry.solve(y, &off).map_err(|e| err(y, e))?;
    // On or past the flange tip (within [`FLANGE_TIP_M`] of the wheel's largest radius, on its
    // flange side — left-side orientation s < 0): the wheelset has climbed over its flange.
    let (ks, kz) = pair.wheel.knots();
    let tip = ks
        .iter()
        .zip(kz)
        .filter(|(s, _)| **s < 0.0)
        .min_by(|a, b| a.1.total_cmp(b.1))
        .map(|(s, z)| (*s, *z));
    if let Some((tip_s, tip_z)) = tip {
        for side in Side::BOTH {
            let sw = side.sign() * sol.point(side).s_wheel;
            let z = pair.wheel.eval(sw).z;
            if sw < 0.0 && (sw < tip_s || z < tip_z + FLANGE_TIP_M) {
                return Err(err(
                    y,
                    format!(
                        "the {} wheel rides on its flange tip (contact at s_w = {:.2} mm, {:.2} mm below the tip's radius; the tip at s_w = {:.2} mm): the wheelset has climbed over its flange — give a smaller shift",
                        side.name(),
                        sol.point(side).s_wheel * 1e3,
                        (z - tip_z) * 1e3,
                        side.sign() * tip_s * 1e3
                    ),
                ));
            }
        }
    }
    Ok(sol)
}

/// The patches of both wheels at shift `y` for `model`, rolling at `omega` (rad/s).
fn patches_with(
    pair: &WheelRailPair,
    sol: &ContactSolution,
    y: f64,
    model: PatchModel,
    settings: &PatchSweepSettings,
    omega: f64,
) -> Result<ShiftPatches, PatchSweepError> {
    let yaw = settings.yaw_per_m * y;
    let e_star = settings
        .forces
        .material
        .contact_modulus(&settings.forces.material);
    let wheel = |side: Side| -> Result<WheelPatches, PatchSweepError> {
        let point = *sol.point(side);
        let hz_curv = RelativeCurvature::at_contact(&point);
        let hz_dev = HertzContact::solve(
            hz_curv,
            settings.load,
            &settings.forces.material,
            &settings.forces.material,
        )
        .map(|h| hertz_deviation(&pair.wheel, &pair.rail, side, point.s_wheel, point.s_rail, h.b))
        .unwrap_or(f64::INFINITY);
        let kin = Kinematics {
            y,
            z: sol.z,
            yaw,
            speed: settings.speed,
            omega,
            roll: sol.phi,
        };
        let patches = match model {
            PatchModel::Hertz => {
                vec![hertz_patch(&point, &kin, side, settings).map_err(|e| err(y, e))?]
            }
            PatchModel::Strips => {
                strip_patches(pair, &point, &kin, side, e_star, settings).map_err(|e| err(y, e))?
            }
        };
        Ok(WheelPatches {
            side,
            rigid: point,
            hertz_deviation: hz_dev,
            patches,
        })
    };
    Ok(ShiftPatches {
        y,
        yaw,
        z: sol.z,
        roll: sol.phi,
        model,
        wheels: [wheel(Side::Left)?, wheel(Side::Right)?],
        pitch_rate: omega,
    })
}

/// The wheelset's rigid motion.
struct Kinematics {
    y: f64,
    z: f64,
    yaw: f64,
    roll: f64,
    speed: f64,
    omega: f64,
}

impl Kinematics {
    /// Contact frame, creepages at a contact point (Y, Z) with normal angle `angle` (track frame,
    /// from vertical towards the track centre) on `side`.
    fn creepage(
        &self,
        side: Side,
        position: (f64, f64),
        angle: f64,
    ) -> Result<(ContactFrame, Creepage), String> {
        // Linearised rotation, as the dynamics (`dynamics::wheelset::axle_direction`).
        let axle = Vector3::new(-self.yaw, 1.0, self.roll).normalize();
        // Normal towards the track centre on each side: −Y on the left, +Y on the right.
        let (n_y, n_z) = (-side.sign() * angle.sin(), angle.cos());
        let frame =
            ContactFrame::new(Vector3::new(0.0, n_y, n_z), axle, Vector3::x()).map_err(|e| e.to_string())?;
        // The yawed wheel touches where its normal is the rail's: ahead of or behind the axle by
        // u_x = ψ (n_Z u_Y − n_Y u_Z) / (n_Y φ − n_Z) (as `dynamics::wheelset::contact_geometry`;
        // on a flange at 66° and 15.6 mrad, 17 mm — the lateral creepage there is ψ / cos γ, not
        // ψ cos γ).
        let (u_y, u_z) = (position.0 - self.y, position.1 - self.z);
        let u_x = self.yaw * (n_z * u_y - n_y * u_z) / (n_y * self.roll - n_z);
        let r = Vector3::new(u_x, u_y, u_z);
        let w = axle * self.omega;
        let v = Vector3::new(self.speed, 0.0, 0.0) + w.cross(&r);
        let c = Creepage::from_velocities(&frame, v, Vector3::zeros(), w, Vector3::zeros(), self.speed, 0.0);
        Ok((frame, c))
    }
}

/// Iterates the normal force for the vertical balance N n_z + F·e_z = Q at fixed creepage.
fn balance(
    frame: &ContactFrame,
    creepage: &Creepage,
    settings: &PatchSweepSettings,
    mut evaluate: impl FnMut(f64) -> Result<(ContactPatch, f64), String>,
) -> Result<(f64, ContactPatch, CreepForce), String> {
    let q = settings.load;
    let nz = frame.normal.z;
    if nz <= 0.05 {
        return Err(format!(
            "contact normal {:.1}° from vertical: no vertical load can be carried",
            nz.acos().to_degrees()
        ));
    }
    let mut vertical_creep = 0.0;
    let mut last = None;
    for _ in 0..60 {
        let n = ((q - vertical_creep) / nz).max(1e-3 * q);
        let (patch, _) = evaluate(n)?;
        let f = settings
            .forces
            .model
            .forces(&patch, creepage, settings.speed)
            .map_err(|e| e.to_string())?;
        let fz = frame.force_to_global(f.fx, f.fy, 0.0).z;
        let done = (fz - vertical_creep).abs() < 1e-9 * q;
        vertical_creep = 0.5 * (vertical_creep + fz);
        last = Some((n, patch, f));
        if done {
            break;
        }
    }
    last.ok_or_else(|| "no balance".to_string())
}

fn hertz_patch(
    point: &ContactPoint,
    kin: &Kinematics,
    side: Side,
    settings: &PatchSweepSettings,
) -> Result<PatchResult, String> {
    let (frame, creepage) = kin.creepage(side, point.position, point.contact_angle)?;
    let curv = RelativeCurvature::at_contact(point);
    let m = settings.forces.material;
    let (n, patch, creep) = balance(&frame, &creepage, settings, |n| {
        let h = HertzContact::solve(curv, n, &m, &m).map_err(|e| e.to_string())?;
        let p = ContactPatch::from_hertz(&h, &m, settings.forces.friction, &settings.forces.kalker)
            .map_err(|e| e.to_string())?;
        Ok((p, h.max_pressure))
    })?;
    let h = HertzContact::solve(curv, n, &m, &m).map_err(|e| e.to_string())?;
    Ok(PatchResult {
        model: PatchModel::Hertz,
        normal_force: n,
        max_pressure: h.max_pressure,
        area: std::f64::consts::PI * h.a * h.b,
        contact_angle: point.contact_angle,
        s_rail: point.s_rail,
        s_wheel: point.s_wheel,
        semi_axes: (patch.a, patch.b),
        rolling_radius: point.rolling_radius,
        creepage,
        creep,
        strips: None,
    })
}

/// The strip model's patches with the vertical balance (creep forces included): the load along
/// the vertical the strips carry is Q less the creep forces' vertical components, iterated.
fn strip_patches(
    pair: &WheelRailPair,
    point: &ContactPoint,
    kin: &Kinematics,
    side: Side,
    e_star: f64,
    settings: &PatchSweepSettings,
) -> Result<Vec<PatchResult>, String> {
    let rail_angle = side.sign() * pair.inclination.angle_rad;
    let input = GapInput {
        side,
        s_wheel: point.s_wheel,
        s_rail: point.s_rail,
        nominal_radius: pair.wheelset.nominal_radius_m,
        rail_angle,
        // Vertical in the track frame, in the rail's frame.
        approach_angle: rail_angle,
        half_window: settings.window_m,
    };
    let sec = GapSection::new(&pair.wheel, &pair.rail, &input).map_err(|e| e.to_string())?;
    let m = settings.forces.material;
    let mut vertical_creep = 0.0;
    let q = settings.load;
    let mut out = Vec::new();
    for _ in 0..60 {
        let patches =
            strips::solve(&sec, q - vertical_creep, e_star, &settings.strips).map_err(|e| e.to_string())?;
        out.clear();
        let mut fz_sum = 0.0;
        for p in patches {
            // Position of the patch's load centre in the wheelset-track frame: the rigid contact
            // point moved along the rail profile.
            let (py, pz) = pair.rail_placement.rail_point(&pair.rail, side, p.s_rail);
            let (frame, creepage) = kin.creepage(side, (py, pz), p.contact_angle)?;
            let (a, b) = p.equivalent_ellipse();
            let patch = ContactPatch::new(
                a,
                b,
                p.normal_force,
                m.shear_modulus(),
                settings.forces.friction,
                &settings.forces.kalker,
            )
            .map_err(|e| e.to_string())?;
            let creep = settings
                .forces
                .model
                .forces(&patch, &creepage, settings.speed)
                .map_err(|e| e.to_string())?;
            fz_sum += frame.force_to_global(creep.fx, creep.fy, 0.0).z;
            out.push(PatchResult {
                model: PatchModel::Strips,
                normal_force: p.normal_force,
                max_pressure: p.max_pressure,
                area: p.area,
                contact_angle: p.contact_angle,
                s_rail: p.s_rail,
                s_wheel: p.s_wheel,
                semi_axes: (a, b),
                rolling_radius: p.rolling_radius,
                creepage,
                creep,
                strips: Some(p),
            });
        }
        let done = (fz_sum - vertical_creep).abs() < 1e-9 * q;
        vertical_creep = 0.5 * (vertical_creep + fz_sum);
        if done {
            break;
        }
    }
    Ok(out)
}

/// The CSV columns of `kecsim patch --csv` (a contract: scripts read them by name; add, don't
/// rename). Units in the names; angles in rad; y and s in the paper's convention (to the left).
pub const CSV_COLUMNS: [&str; 24] = [
    "y_mm",
    "yaw_mrad",
    "side",
    "patch",
    "model",
    "fn_n",
    "pmax_mpa",
    "area_mm2",
    "contact_angle_rad",
    "s_rail_mm",
    "s_wheel_mm",
    "a_mm",
    "b_mm",
    "s_rail_from_mm",
    "s_rail_to_mm",
    "creepage_x",
    "creepage_y",
    "spin_1pm",
    "fx_n",
    "fy_n",
    "mz_nm",
    "hertz_deviation",
    "z_mm",
    "roll_mrad",
];

/// Writes one row per patch (shift, side, model) to `path` ([`CSV_COLUMNS`]).
pub fn write_csv(path: &std::path::Path, shifts: &[ShiftPatches]) -> Result<usize, csv::Error> {
    let mut w = crate::files::csv_writer(path)?;
    w.write_record(CSV_COLUMNS)?;
    let mut rows = 0;
    let f = |x: f64, d: usize| format!("{:.*}", d, x + 0.0);
    for sh in shifts {
        for wp in &sh.wheels {
            for (k, p) in wp.patches.iter().enumerate() {
                let range = p
                    .strips
                    .as_ref()
                    .map(|s| s.s_rail_range)
                    .unwrap_or((p.s_rail - p.semi_axes.1, p.s_rail + p.semi_axes.1));
                w.write_record([
                    f(sh.y * 1e3, 4),
                    f(sh.yaw * 1e3, 4),
                    wp.side.name().to_string(),
                    (k + 1).to_string(),
                    p.model.name().to_string(),
                    f(p.normal_force, 2),
                    f(p.max_pressure * 1e-6, 2),
                    f(p.area * 1e6, 3),
                    f(p.contact_angle, 6),
                    f(p.s_rail * 1e3, 4),
                    f(p.s_wheel * 1e3, 4),
                    f(p.semi_axes.0 * 1e3, 4),
                    f(p.semi_axes.1 * 1e3, 4),
                    f(range.0 * 1e3, 4),
                    f(range.1 * 1e3, 4),
                    format!("{:.6e}", p.creepage.longitudinal),
                    format!("{:.6e}", p.creepage.lateral),
                    format!("{:.6e}", p.creepage.spin),
                    f(p.creep.fx, 2),
                    f(p.creep.fy, 2),
                    f(p.creep.mz, 4),
                    if wp.hertz_deviation.is_finite() {
                        f(wp.hertz_deviation, 4)
                    } else {
                        "inf".to_string()
                    },
                    f((sh.z) * 1e3, 5),
                    f(sh.roll * 1e3, 5),
                ])?;
                rows += 1;
            }
        }
    }
    crate::files::commit_csv(w)?;
    Ok(rows)
}

/// A markdown table of the patches (printed and recorded).
pub fn summary_markdown(title: &str, shifts: &[ShiftPatches], settings: &PatchSweepSettings) -> String {
    let mut s = format!("# {title}\n\n");
    s += &format!(
        "Vertical load {:.1} kN per wheel, yaw {:.3} mrad per mm of shift, speed {} m/s, μ = {}, creep model {} on each patch's equivalent ellipse. `kp`: Kik–Piotrowski strips corrected to Hertz on a quadratic gap; `hertz`: the ellipse at the rigid contact point. D: Hertz's gap deviation over its patch (valid ≤ {}).\n\n",
        settings.load * 1e-3,
        settings.yaw_per_m,
        settings.speed,
        settings.forces.friction,
        settings.forces.model.name(),
        super::validity::HERTZ_VALIDITY_LIMIT
    );
    s += "| y mm | side | model | patch | N kN | pmax MPa | area mm² | angle ° | s_r mm | s_w mm | Fx N | Fy N | D |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for sh in shifts {
        for wp in &sh.wheels {
            for (k, p) in wp.patches.iter().enumerate() {
                s += &format!(
                    "| {:.2} | {} | {} | {} | {:.2} | {:.0} | {:.1} | {:.2} | {:.2} | {:.2} | {:.0} | {:.0} | {:.2} |\n",
                    sh.y * 1e3,
                    wp.side.name(),
                    p.model.name(),
                    k + 1,
                    p.normal_force * 1e-3,
                    p.max_pressure * 1e-6,
                    p.area * 1e6,
                    p.contact_angle.to_degrees(),
                    p.s_rail * 1e3,
                    p.s_wheel * 1e3,
                    p.creep.fx,
                    p.creep.fy,
                    wp.hertz_deviation
                );
            }
        }
    }
    s
}
