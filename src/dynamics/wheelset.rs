//! Newton–Euler equations of one wheelset with its contact constraints solved for the normal
//! forces (paper §2.5, §5, §7, Eq. 53; DYNAMICS.md §2–4).
//!
//! Coordinates relative to the wheelset-track frame (the track frame at the wheelset's arc length,
//! moving along the centreline at speed V): independent x, y, ψ and the spin rate Ω about the
//! axle; dependent z = Z(y, q_r), φ = Φ(y, q_r) from the contact model. Rotations are linearised
//! (axle direction a ≈ (−ψ, 1, φ)), except the rolling, which enters through Ω only.
//!
//! Unknowns: ẍ, ÿ, z̈, φ̈, ψ̈, Ω̇ and the normal-force multipliers λ_l, λ_r. Rows:
//!
//! ```text
//! m (r̈ + a_t + 2 ω_t × ṙ)                      = F + m g_t + Σ λ_i n_i                 (3 rows)
//! I_x (φ̈ + α_tx) − ψ I_y Ω̇ − I_y Ω (ψ̇ + ω_tz) = M_x + Σ λ_i (u_i × n_i)_x
//! I_y Ω̇                                         = a · (M + Σ λ_i u_i × n_i)   (about the axle)
//! I_z (ψ̈ + α_tz) + φ I_y Ω̇ + I_y Ω (φ̇ + ω_tx) = M_z + Σ λ_i (u_i × n_i)_z
//! z̈ − Z_y ÿ = c_z,   φ̈ − Φ_y ÿ = c_φ                                         (constraints)
//! ```
//!
//! with the normal forces at the **real** contact points u_i (relative to the wheelset centre)
//! along the real rail normals n_i (Eq. 53), F and M the applied forces (suspension, creep)
//! about the centre, a_t, ω_t, α_t the track frame's motion (whole, or Eq. 3–4) and g_t gravity in track
//! components. Dropped, by choice: α_t × r and ω_t × (ω_t × r) (r is millimetres; on R ≥ 100 m at
//! 30 m/s they are < 1e-3 m/s²) and products of small rates other than the gyroscopic ones; kept:
//! the gyroscopic moments I_y Ω (ψ̇ + ω_tz), I_y Ω (φ̇ + ω_tx), and Coriolis.
//!
//! The creep forces depend on λ (Hertz ellipse, μN): G(λ) = Φ(λ) − λ = 0, with Φ the normal forces
//! the equations give for the creep forces at λ (DYNAMICS.md §4), solved by Broyden's method from
//! the previous evaluation's λ, to 1e-12 relative — so that the right-hand side is a function of
//! the state alone (the plain fixed point, which stopped after 8 passes, left up to 1.3e-7 relative
//! on the Manchester run, measured; each pass reuses the factored matrix). Its residual is returned;
//! not converging is an error with the diagnosis, as is a λ ≤ 0 (a lifting wheel).

use nalgebra::{Matrix2, SMatrix, SVector, Vector2, Vector3};
use thiserror::Error;

use super::reactions::Reactions;
use crate::contact::forces::{
    ContactForceSettings, ContactFrame, ContactPatch, CreepForce, Creepage, HertzContact, RelativeCurvature,
};
use crate::contact::WheelsetKinematics;
use crate::profile::Side;
use crate::track::{LateralFlexibility, RailMotion};

/// Mass and inertia of a wheelset.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WheelsetInertia {
    pub mass_kg: f64,
    /// Principal moments about x (roll), y (axle), z (yaw), kg m² (an IRW-wheelset: of the whole,
    /// bridge and wheels; the y entry is then unused).
    pub inertia_kg_m2: [f64; 3],
    /// `Some`: an IRW-wheelset (two independently rotating wheels on a non-rotating bridge).
    pub irw: Option<IrwInertia>,
}

/// What an IRW-wheelset adds: each wheel's inertia about its axle (the bridge does not pitch:
/// its suspension holds it, as a solid axle's axle boxes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IrwInertia {
    pub wheel_spin_kg_m2: f64,
}

/// The motion of the wheelset-track frame (whole, or Eq. 3–4) and gravity, in its own components.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FrameMotion {
    /// Forward speed V, m/s.
    pub speed: f64,
    /// a_t = [V̇, ρ_h V², −ρ_v V²].
    pub accel: [f64; 3],
    /// ω_t = [ρ_tw V, ρ_v V, ρ_h V].
    pub omega: [f64; 3],
    /// α_t (Eq. 4).
    pub alpha: [f64; 3],
    /// Gravity in track components [θ_t g, −φ_t g, −g].
    pub gravity: [f64; 3],
}

impl FrameMotion {
    /// Tangent, level track at constant speed.
    pub fn tangent(speed: f64) -> FrameMotion {
        FrameMotion {
            speed,
            gravity: [0.0, 0.0, -9.81],
            ..FrameMotion::default()
        }
    }
}

/// The wheelset's independent state.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct WheelsetState {
    pub x: f64,
    pub y: f64,
    pub psi: f64,
    pub x_dot: f64,
    pub y_dot: f64,
    pub psi_dot: f64,
    /// Spin rate about the axle, rad/s (an IRW-wheelset: of the left wheel).
    pub omega: f64,
    /// IRW-wheelsets: the right wheel's spin rate, rad/s (solid axle: unused).
    pub omega_right: f64,
    /// Lift of each wheel (left, right): the roll θ about the other wheel's contact point that
    /// takes this wheel off its rail (see [`Lift`]), rad; exactly 0 while both wheels touch.
    pub lift: [f64; 2],
    /// θ̇ of each wheel's lift, rad/s; exactly 0 while both wheels touch.
    pub lift_rate: [f64; 2],
    /// Lateral shift d of the track under the wheelset ([`LateralFlexibility`]; 0 on a rigid
    /// track), m, and its rate ḋ, m/s.
    pub track_shift: f64,
    pub track_shift_rate: f64,
}

impl WheelsetState {
    /// States one wheelset takes in a state vector: [x, y, ψ, ẋ, ẏ, ψ̇, Ω_l, (Ω_r: IRW-wheelsets),
    /// θ_l, θ_r, θ̇_l, θ̇_r, d, ḋ] — 13 (solid axle) or 14 (IRW-wheelset).
    pub fn slot_size(irw: bool) -> usize {
        Self::lift_index(irw) + 6
    }

    /// The slot's states by name, in slot order (see [`Self::slot_size`]).
    pub fn slot_names(irw: bool) -> Vec<&'static str> {
        let spins: &[&str] = if irw {
            &["omega_left", "omega_right"]
        } else {
            &["omega"]
        };
        ["x", "y", "psi", "x_dot", "y_dot", "psi_dot"]
            .into_iter()
            .chain(spins.iter().copied())
            .chain([
                "lift_left",
                "lift_right",
                "lift_rate_left",
                "lift_rate_right",
                "track_shift",
                "track_shift_rate",
            ])
            .collect()
    }

    /// Index of θ_l in the slot (θ_r, θ̇_l, θ̇_r follow).
    pub fn lift_index(irw: bool) -> usize {
        if irw {
            8
        } else {
            7
        }
    }

    /// The state from its slot.
    pub fn read(x: &[f64], irw: bool) -> WheelsetState {
        let l = Self::lift_index(irw);
        WheelsetState {
            x: x[0],
            y: x[1],
            psi: x[2],
            x_dot: x[3],
            y_dot: x[4],
            psi_dot: x[5],
            omega: x[6],
            omega_right: if irw { x[7] } else { x[6] },
            lift: [x[l], x[l + 1]],
            lift_rate: [x[l + 2], x[l + 3]],
            track_shift: x[l + 4],
            track_shift_rate: x[l + 5],
        }
    }

    /// Writes the state into its slot.
    pub fn write(&self, x: &mut [f64], irw: bool) {
        let l = Self::lift_index(irw);
        x[..7].copy_from_slice(&[
            self.x,
            self.y,
            self.psi,
            self.x_dot,
            self.y_dot,
            self.psi_dot,
            self.omega,
        ]);
        if irw {
            x[7] = self.omega_right;
        }
        x[l..l + 6].copy_from_slice(&[
            self.lift[0],
            self.lift[1],
            self.lift_rate[0],
            self.lift_rate[1],
            self.track_shift,
            self.track_shift_rate,
        ]);
    }

    /// The rails under the wheelset as its contact sees them: the track's irregularities `rails`
    /// with the lateral shift d (both rails) and its rate added. The shift's acceleration is an
    /// unknown of [`evaluate`], not part of these.
    pub fn shifted_rails(&self, rails: &RailMotion) -> RailMotion {
        let mut r = *rails;
        for k in [0, 2] {
            r.q[k] += self.track_shift;
            r.q_dot[k] += self.track_shift_rate;
        }
        r
    }

    /// The slot's time derivative from the state's slot `x` and the evaluation's accelerations.
    pub fn write_rates(x: &[f64], d: &mut [f64], dynamics: &WheelsetDynamics, irw: bool) {
        let l = Self::lift_index(irw);
        let a = dynamics.accel;
        d[..7].copy_from_slice(&[x[3], x[4], x[5], a[0], a[1], a[4], a[5]]);
        if irw {
            d[7] = dynamics.spin_accel_right;
        }
        d[l..l + 6].copy_from_slice(&[
            x[l + 2],
            x[l + 3],
            dynamics.lift_accel[0],
            dynamics.lift_accel[1],
            x[l + 5],
            dynamics.track_accel,
        ]);
    }
}

/// Applied force and moment about the wheelset centre (suspension, loads), track components, and
/// the drive's torques.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Load {
    pub force: [f64; 3],
    pub moment: [f64; 3],
    /// The motor torque on each wheel (left, right) about the axle, N m, > 0 driving forward
    /// ([`super::traction`]): the vector T a on the wheelset, in each wheel's spin row (a solid
    /// axle's one row takes both); its reaction is on the body carrying the motor.
    pub drive_torque: [f64; 2],
}

/// What one evaluation gives.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct WheelsetDynamics {
    /// ẍ, ÿ, z̈, φ̈, ψ̈, Ω̇ (an IRW-wheelset: Ω̇ of the left wheel).
    pub accel: [f64; 6],
    /// IRW-wheelsets: the right wheel's Ω̇ (solid axle: Ω̇ again).
    pub spin_accel_right: f64,
    /// Normal forces λ_l, λ_r, N.
    pub normal: [f64; 2],
    /// Creep forces (contact frame) left, right.
    pub creep: [CreepForce; 2],
    /// Creepages left, right.
    pub creepage: [Creepage; 2],
    /// |Φ(λ) − λ| of the normal forces returned: the residual of the creep/normal-force
    /// iteration (≤ 1e-12 relative), N.
    pub lambda_change: f64,
    /// The accelerations of the slot's lift entries: θ̈ of each wheel's lift (0 for a wheel on its
    /// rail), rad/s² — the free pose of the elastic model: z̈, φ̈ (its slot's lift entries hold z, φ;
    /// `super::elastic`).
    pub lift_accel: [f64; 2],
    /// Each wheel's gap to its rail along the rail normal (0 on the rail), m.
    pub lift_gap: [f64; 2],
    /// d̈ of the track's lateral shift (0 on a rigid track), m/s².
    pub track_accel: f64,
    /// Lateral (Y) and vertical (Q) force of each rail on its wheel, track frame, N (normal and
    /// creep forces of all the wheel's contacts).
    pub wheel_force: [(f64, f64); 2],
    /// Semi-axes (a, b) of each wheel's Hertz contact ellipse at its normal force, m (a along
    /// the rolling direction; 0 for a lifted wheel).
    pub semi_axes: [(f64, f64); 2],
}

/// Dynamics failures.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum WheelsetError {
    #[error("{side} wheel lifts: normal force {normal:.1} N ≤ 0, but released it would not rise (θ̈ = {lift_accel:.3e} rad/s²: the creep forces hold it down)")]
    Lift {
        side: &'static str,
        normal: f64,
        lift_accel: f64,
    },
    #[error("the {side} wheel lifts {gap_mm:.2} mm off its rail, beyond {limit_mm:.0} mm (EN 14363's wheel-lift limit, where the linearised lift also ends): derailment")]
    LiftLimit {
        side: &'static str,
        gap_mm: f64,
        limit_mm: f64,
    },
    #[error("{side} wheel lifts at a contact where rolling about the other wheel does not open a gap (∂gap/∂θ = {gain:.3} m/rad)")]
    LiftGeometry { side: &'static str, gain: f64 },
    #[error("{side} contact: {message}")]
    Contact { side: &'static str, message: String },
    #[error("singular wheelset equations")]
    Singular,
    #[error("the normal forces and the creep forces did not agree after {passes} passes (last change {change:.3e} N)")]
    NormalForces { change: f64, passes: usize },
}

/// Where the normal-force iteration of [`evaluate`] starts: the normal forces λ and the Broyden
/// matrix B ≈ ∂(Φ(λ) − λ)/∂λ, both carried from one evaluation of a wheelset to the next (the
/// result does not depend on them beyond the iteration's tolerance).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NormalForceStart {
    /// Normal forces (left, right), N.
    pub lambda: [f64; 2],
    /// B; −I starts the iteration as the plain fixed point λ₁ = Φ(λ₀).
    pub secant: Matrix2<f64>,
}

impl From<[f64; 2]> for NormalForceStart {
    fn from(lambda: [f64; 2]) -> Self {
        NormalForceStart {
            lambda,
            secant: -Matrix2::identity(),
        }
    }
}

/// Passes between creep forces and normal forces: at most 1 + this many, until Φ(λ) − λ is below
/// `LAMBDA_TOLERANCE` relative (so that the right-hand side is a function of the state, not of the
/// previous evaluation — implicit integrators difference it); else a diagnosed failure.
const MAX_PASSES: usize = 30;
const LAMBDA_TOLERANCE: f64 = 1e-12;

/// The largest wheel lift, m: 5 mm, the limit of EN 14363's flange-climbing (twist) test; a
/// larger lift ends the run as a derailment ([`WheelsetError::LiftLimit`]). The lift's
/// linearisation ([`Lift`]) is checked to 1.2 % at 0.2 mrad (~0.3 mm) and holds to a few mm.
pub const MAX_LIFT_M: f64 = 5e-3;

/// The smallest ∂gap/∂θ accepted for a lift, m/rad: rolling 1 mrad about the other wheel must open
/// at least 0.02 mm (a wheel flange at ~80° against the rail opens less: no lift there).
const MIN_LIFT_GAIN: f64 = 0.02;

/// A wheel off its rail (departure from the paper, which keeps both KEC constraints always:
/// issue 14). While one wheel is lifted the wheelset keeps one contact constraint, at the other
/// wheel (the pivot p), and gains one coordinate, the roll θ about that contact point. Linearised
/// about the two-point configuration at the same y (z₀ = Z(y), φ₀ = Φ(y), both contacts touching):
///
/// ```text
/// φ = φ₀ + σ θ,   z = z₀ + k σ θ,   σ = +1 (left wheel lifted), −1 (right)
/// k = −(u_pY − (n_pY / n_pZ) u_pZ)          (the pivot's normal velocity stays zero)
/// gap_i = G θ,   G = σ (n_iZ (k + u_iY) − n_iY u_iZ)
/// ```
///
/// with u the contact points relative to the centre and n the rail normals (Y, Z): a rotation
/// δφ moves a wheel point by δφ x × u, and the centre by δz; the pivot's point then moves along
/// its rail's tangent (its lateral sliding is the creep forces' business, y stays independent),
/// the lifted wheel's point leaves its rail at G θ̇. θ ≥ 0 while lifted; a lifted wheel lands
/// where θ returns to 0 (an event of the integrator: [`land`]). Valid for lifts small against
/// the wheel's radius (millimetres), the physical ones short of a derailment ([`MAX_LIFT_M`]).
///
/// **Both wheels off** (a wheelset thrown up by a flange impact): each wheel's lift is its own
/// roll θ_i about the other wheel's contact point, and the two small rotations add,
/// φ = φ₀ + Σ σ_i θ_i, z = z₀ + Σ k_i σ_i θ_i — any (z, φ) near the two-point configuration
/// (k_l ≠ k_r: the pivots lie on either side). Rolling about one wheel's contact point leaves
/// that wheel's gap unchanged to first order, so each gap stays G_i θ_i; each wheel lands on
/// its own event, the other flying on — or both in one impact where they come down together.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lift {
    /// The lifted wheel: 0 left, 1 right.
    pub side: usize,
    /// +1 left, −1 right.
    pub sigma: f64,
    /// ∂z/∂(σθ), m/rad.
    pub k: f64,
    /// ∂gap/∂θ of the lifted wheel, m/rad (> 0).
    pub gain: f64,
    pub theta: f64,
    pub theta_dot: f64,
}

impl Lift {
    /// The lift of wheel `side` at θ = θ̇ = 0 from the two-point configuration `kin` at lateral
    /// displacement `y`.
    pub fn at_rest(side: usize, y: f64, kin: &WheelsetKinematics) -> Result<Lift, WheelsetError> {
        let sigma = if side == 0 { 1.0 } else { -1.0 };
        let u = |c: &crate::contact::ContactPoint| (c.position.0 - y, c.position.1 - kin.z);
        let pivot = &kin.contacts[1 - side];
        let lifted = &kin.contacts[side];
        let (u_py, u_pz) = u(pivot);
        let (n_py, n_pz) = pivot.normal;
        let k = -(u_py - n_py / n_pz * u_pz);
        let (u_iy, u_iz) = u(lifted);
        let (n_iy, n_iz) = lifted.normal;
        let gain = sigma * (n_iz * (k + u_iy) - n_iy * u_iz);
        if gain.is_nan() || gain < MIN_LIFT_GAIN {
            return Err(WheelsetError::LiftGeometry {
                side: Side::BOTH[side].name(),
                gain,
            });
        }
        Ok(Lift {
            side,
            sigma,
            k,
            gain,
            theta: 0.0,
            theta_dot: 0.0,
        })
    }

    /// The lifts the state carries: each wheel off its rail (θ or θ̇ not zero).
    pub fn of(state: &WheelsetState, kin: &WheelsetKinematics) -> Result<Lifts, WheelsetError> {
        let mut lifts = [None; 2];
        for (side, lift) in lifts.iter_mut().enumerate() {
            if state.lift[side] != 0.0 || state.lift_rate[side] != 0.0 {
                let mut l = Lift::at_rest(side, state.y, kin)?;
                l.theta = state.lift[side];
                l.theta_dot = state.lift_rate[side];
                *lift = Some(l);
            }
        }
        Ok(lifts)
    }

    /// The lifted wheel's gap, m.
    pub fn gap(&self) -> f64 {
        self.gain * self.theta
    }

    /// The pose kinematics with the lift: z, φ and their rates moved by θ, θ̇ (the products
    /// k̇ θ̇, k̈ θ of the small lift neglected, as the linearisation does).
    pub fn apply(&self, kin: &WheelsetKinematics) -> WheelsetKinematics {
        let mut k = kin.clone();
        k.z += self.k * self.sigma * self.theta;
        k.phi += self.sigma * self.theta;
        k.z_dot += self.k * self.sigma * self.theta_dot;
        k.phi_dot += self.sigma * self.theta_dot;
        k
    }
}

/// Each wheel's lift, `None` for a wheel on its rail.
pub type Lifts = [Option<Lift>; 2];

/// No wheel lifted.
const ON_RAILS: Lifts = [None, None];

/// The pose kinematics with every lift of `lifts` applied (the small rotations add).
fn apply_lifts(lifts: &Lifts, kin: &WheelsetKinematics) -> WheelsetKinematics {
    lifts.iter().flatten().fold(kin.clone(), |k, l| l.apply(&k))
}

/// The kinematics of the wheelset's pose: the contact model's two-point configuration `kin`, moved
/// by the state's lift if a wheel is off its rail.
pub fn pose_kinematics(
    state: &WheelsetState,
    kin: &WheelsetKinematics,
) -> Result<WheelsetKinematics, WheelsetError> {
    Ok(apply_lifts(&Lift::of(state, kin)?, kin))
}

/// What a landing did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Landing {
    /// The wheel that landed: 0 left, 1 right.
    pub side: usize,
    /// Closing speed along the rail normal just before the impact, m/s.
    pub speed: f64,
    /// Normal impulse on the landing wheel, N s.
    pub impulse: f64,
    /// Normal impulse on the other wheel, N s.
    pub pivot_impulse: f64,
    /// The other wheel, off its rail too, landed in the same impact (its impulse
    /// `pivot_impulse`).
    pub other_landed: bool,
}

/// Points, normals and frames of one pose.
struct Geometry {
    axle: Vector3<f64>,
    arm: [Vector3<f64>; 2],
    normal: [Vector3<f64>; 2],
    frames: [ContactFrame; 2],
}

impl Geometry {
    /// `kin`: the pose kinematics (lift applied).
    fn new(state: &WheelsetState, kin: &WheelsetKinematics) -> Result<Geometry, WheelsetError> {
        let axle = axle_direction(state.psi, kin.phi);
        let [(a0, n0, f0), (a1, n1, f1)] =
            [0, 1].map(|i| contact_geometry(state, kin.z, kin.phi, axle, &kin.contacts[i], i));
        Ok(Geometry {
            axle,
            arm: [a0, a1],
            normal: [n0, n1],
            frames: [f0?, f1?],
        })
    }
}

/// The axle direction a of the linearised rotation, (−ψ, 1, φ) normalised.
pub(crate) fn axle_direction(psi: f64, phi: f64) -> Vector3<f64> {
    Vector3::new(-psi, 1.0, phi).normalize()
}

/// A contact point's arm from the wheelset centre, its rail normal (3-D) and its contact frame,
/// wheel `i` (0 left, 1 right) at centre height `z` and roll `phi`.
///
/// Longitudinal position on the yawed wheel: the wheel is a surface of revolution about the axle
/// a, and the point where its normal equals the rail's normal n (n_x = 0) lies where
/// n · (a × u) = 0 (n in the wheel's meridian plane): with u = (u_x, u_Y, u_Z),
/// u_x = ψ (n_Z u_Y − n_Y u_Z) / (n_Y φ − n_Z) ≈ −ψ (u_Y + r n_Y / n_Z) — the yaw-induced contact
/// shift. Without it the rolling wheel's normal force would do work of order λ Ω r ψ n_Y (see the
/// energy test).
pub(crate) fn contact_geometry(
    state: &WheelsetState,
    z: f64,
    phi: f64,
    axle: Vector3<f64>,
    c: &crate::contact::ContactPoint,
    i: usize,
) -> (Vector3<f64>, Vector3<f64>, Result<ContactFrame, WheelsetError>) {
    let centre = Vector3::new(state.x, state.y, z);
    let (u_y, u_z) = (c.position.0 - state.y, c.position.1 - z);
    let (n_y, n_z) = c.normal;
    let u_x = state.psi * (n_z * u_y - n_y * u_z) / (n_y * phi - n_z);
    let p = Vector3::new(state.x + u_x, c.position.0, c.position.1);
    let normal = Vector3::new(0.0, n_y, n_z);
    let frame = ContactFrame::new(normal, axle, Vector3::x()).map_err(|e| WheelsetError::Contact {
        side: Side::BOTH[i].name(),
        message: e.to_string(),
    });
    (p - centre, normal, frame)
}

/// The 10×10 matrix of [ẍ ÿ z̈ φ̈ ψ̈ Ω̇_l λl λr d̈ Ω̇_r] (a lifted wheel: its λ column is its θ̈;
/// d̈ the track's lateral shift, 0 on a rigid track). It does not depend on the creep forces: factored once, the passes of the creep/normal-force
/// iteration only change the right-hand side.
///
/// Rotational rows: 3 → x (φ̈), 4 → z (ψ̈), 5 → about the axle a (Ω̇). With
/// H = I_x φ̇ x + I_y Ω a + I_z ψ̇ z and ȧ = (−ψ̇, 0, φ̇): the x and z rows carry I_y Ω̇ a_x,
/// I_y Ω̇ a_z; the spin row is the moment about the axle, a · M (not M_y: a normal force
/// at a yawed wheel's contact has a large M_x whose axle component −ψ M_x cancels M_y).
/// An IRW-wheelset has one spin row per wheel (its own contact's moment about the axle,
/// rows 5 and 9); a solid axle ties Ω̇_r = Ω̇_l. Row 8: the track's lateral shift
/// ([`LateralFlexibility`]; on a rigid track d̈ = 0).
/// Rows 6–7: the constraints z̈ − Z_y ÿ (− k σ θ̈) = c_z, φ̈ − Φ_y ÿ (− σ θ̈) = c_φ.
fn matrix(
    inertia: &WheelsetInertia,
    geo: &Geometry,
    kin: &WheelsetKinematics,
    lifts: &Lifts,
    track: Option<&LateralFlexibility>,
) -> SMatrix<f64, 10, 10> {
    let m = inertia.mass_kg;
    let [ix, _, iz] = inertia.inertia_kg_m2;
    let i_spin = spin_inertia(inertia);
    let (arm, normal, axle) = (&geo.arm, &geo.normal, &geo.axle);
    let mut a = SMatrix::<f64, 10, 10>::zeros();
    for k in 0..3 {
        a[(k, k)] = m;
    }
    a[(3, 3)] = ix;
    a[(4, 4)] = iz;
    a[(3, 5)] = i_spin * axle.x;
    a[(4, 5)] = i_spin * axle.z;
    a[(5, 5)] = i_spin;
    for i in 0..2 {
        let t = arm[i].cross(&normal[i]);
        for k in 0..3 {
            a[(k, 6 + i)] = -normal[i][k];
        }
        a[(3, 6 + i)] = -t.x;
        a[(4, 6 + i)] = -t.z;
    }
    match inertia.irw {
        None => {
            for i in 0..2 {
                a[(5, 6 + i)] = -axle.dot(&arm[i].cross(&normal[i]));
            }
            a[(8, 8)] = 1.0;
            a[(9, 9)] = 1.0;
            a[(9, 5)] = -1.0;
        }
        Some(_) => {
            a[(3, 9)] = i_spin * axle.x;
            a[(4, 9)] = i_spin * axle.z;
            a[(9, 9)] = i_spin;
            a[(5, 6)] = -axle.dot(&arm[0].cross(&normal[0]));
            a[(9, 7)] = -axle.dot(&arm[1].cross(&normal[1]));
            a[(8, 8)] = 1.0;
        }
    }
    a[(6, 2)] = 1.0;
    a[(6, 1)] = -kin.z_y;
    a[(7, 3)] = 1.0;
    a[(7, 1)] = -kin.phi_y;
    if let Some(t) = track {
        // Row and column 8: the track's lateral shift, m_t d̈ + Σ λ_i n_iY = −c_t ḋ − k_t d − Σ F_cY
        // (the wheels push the rails with −λ n − F_c); the contact depends on y − d, so the
        // constraints gain + Z_y d̈, + Φ_y d̈.
        a[(8, 8)] = t.mass_kg;
        for i in 0..2 {
            a[(8, 6 + i)] = normal[i].y;
        }
        a[(6, 8)] = kin.z_y;
        a[(7, 8)] = kin.phi_y;
    }
    for l in lifts.iter().flatten() {
        // A lifted wheel carries no force; its column becomes θ̈'s.
        let c = 6 + l.side;
        for r in 0..10 {
            a[(r, c)] = 0.0;
        }
        a[(6, c)] = -l.k * l.sigma;
        a[(7, c)] = -l.sigma;
    }
    a
}

/// The ground velocity of the wheelset's centre in its track frame and the rolling speed the
/// creepages are normalised by (its forward component). The frame sits at the wheelset's own
/// arc length s_ref + d + x and moves along the track at V + ẋ, so the centre is at (0, y, z) in
/// it: v_c = (V + ẋ, ẏ, ż) + ω_t × (0, y, z). (Before issue 46 the centre was taken at (x, y, z):
/// on a curve a wheelset x metres behind its reference gained a lateral velocity ρ_h V x.)
pub(crate) fn centre_velocity(
    frame: &FrameMotion,
    r_dot: &Vector3<f64>,
    y: f64,
    z: f64,
) -> (Vector3<f64>, f64) {
    let w_t = Vector3::from(frame.omega);
    let v_c = Vector3::new(frame.speed, 0.0, 0.0) + r_dot + w_t.cross(&Vector3::new(0.0, y, z));
    (v_c, v_c.x)
}

fn spin_inertia(inertia: &WheelsetInertia) -> f64 {
    match inertia.irw {
        Some(irw) => irw.wheel_spin_kg_m2,
        None => inertia.inertia_kg_m2[1],
    }
}

/// Evaluates the wheelset's accelerations and normal forces. `kin` is the contact model's
/// two-point configuration at the state's y; `start` seeds the normal-force iteration (the
/// previous evaluation's normal forces and secant matrix) and is updated to this one's.
///
/// A wheel whose normal force would be ≤ 0 is released ([`Lift`]): with θ = θ̇ = 0 the equations
/// are solved again with that wheel free, and its θ̈ (≥ 0: the two solutions meet where λ = 0)
/// returned; a lifted wheel (θ or θ̇ ≠ 0 in the state) stays free until it lands. Where the other
/// wheel's normal force then falls ≤ 0 too, it is released as well: the wheelset flies, both
/// wheels free, until one lands. A lift beyond [`MAX_LIFT_M`] is a [`WheelsetError::LiftLimit`].
#[allow(clippy::too_many_arguments)]
pub fn evaluate(
    inertia: &WheelsetInertia,
    state: &WheelsetState,
    kin: &WheelsetKinematics,
    frame: &FrameMotion,
    load: &Load,
    forces: &ContactForceSettings,
    start: &mut NormalForceStart,
    track: Option<&LateralFlexibility>,
) -> Result<WheelsetDynamics, WheelsetError> {
    let lambda_guess = start.lambda;
    let solve_at = |guess: [f64; 2], secant: &mut Matrix2<f64>, lifts: &Lifts| {
        solve(
            inertia, state, kin, frame, load, forces, guess, secant, lifts, track,
        )
    };
    // With `lifts` free (at least one): a wheel still on its rail whose normal force falls ≤ 0
    // is released too (from rest: its θ̈ must be ≥ 0, else the creep forces hold it down).
    let lifted = |lifts: Lifts, guess: [f64; 2]| -> Result<WheelsetDynamics, WheelsetError> {
        // (`solve` pins the lifted wheels' λ at 0.)
        let r = solve_at(guess, &mut -Matrix2::identity(), &lifts)?;
        let Some(p) = (0..2).find(|&i| lifts[i].is_none() && r.normal[i] <= 0.0) else {
            return Ok(r);
        };
        let mut both = lifts;
        both[p] = Some(Lift::at_rest(p, state.y, kin)?);
        let flight = solve_at([0.0; 2], &mut -Matrix2::identity(), &both)?;
        if flight.lift_accel[p] < 0.0 {
            return Err(WheelsetError::Lift {
                side: Side::BOTH[p].name(),
                normal: r.normal[p],
                lift_accel: flight.lift_accel[p],
            });
        }
        Ok(flight)
    };
    // The result; the next evaluation starts from its normal forces (the secant matrix is
    // updated by the both-wheels solve).
    let r = 'result: {
        let lifts = Lift::of(state, kin)?;
        for l in lifts.iter().flatten() {
            if l.gap() > MAX_LIFT_M {
                return Err(WheelsetError::LiftLimit {
                    side: Side::BOTH[l.side].name(),
                    gap_mm: l.gap() * 1e3,
                    limit_mm: MAX_LIFT_M * 1e3,
                });
            }
        }
        if lifts.iter().any(Option::is_some) {
            break 'result lifted(lifts, lambda_guess)?;
        }
        let r = solve_at(lambda_guess, &mut start.secant, &ON_RAILS)?;
        let side = if r.normal[0] <= r.normal[1] { 0 } else { 1 };
        if r.normal[side] > 0.0 {
            break 'result r;
        }
        // Lift-off: release the more unloaded wheel (and the other, should it unload too).
        let mut lifts = ON_RAILS;
        lifts[side] = Some(Lift::at_rest(side, state.y, kin)?);
        let free = lifted(lifts, r.normal)?;
        if free.lift_accel[side] < 0.0 {
            return Err(WheelsetError::Lift {
                side: Side::BOTH[side].name(),
                normal: r.normal[side],
                lift_accel: free.lift_accel[side],
            });
        }
        free
    };
    start.lambda = r.normal;
    Ok(r)
}

/// The equations at one contact state (both wheels on their rails, or `lifts`' wheels free).
#[allow(clippy::too_many_arguments)]
fn solve(
    inertia: &WheelsetInertia,
    state: &WheelsetState,
    kin2: &WheelsetKinematics,
    frame: &FrameMotion,
    load: &Load,
    forces: &ContactForceSettings,
    lambda_guess: [f64; 2],
    secant: &mut Matrix2<f64>,
    lifts: &Lifts,
    track: Option<&LateralFlexibility>,
) -> Result<WheelsetDynamics, WheelsetError> {
    let kin = apply_lifts(lifts, kin2);
    let m = inertia.mass_kg;
    let geo = Geometry::new(state, &kin)?;
    let (axle, arm) = (geo.axle, geo.arm);
    let r_dot = Vector3::new(state.x_dot, state.y_dot, kin.z_dot);
    let w_t = Vector3::from(frame.omega);
    // Angular velocity of each wheel (ground, track components): the axle's or, on an
    // IRW-wheelset, each wheel's own spin about the common axle.
    let omega_wheel = [
        state.omega,
        if inertia.irw.is_some() {
            state.omega_right
        } else {
            state.omega
        },
    ];
    let w_axle = w_t + Vector3::new(kin.phi_dot, 0.0, state.psi_dot);
    let w_wheel = [w_axle + axle * omega_wheel[0], w_axle + axle * omega_wheel[1]];
    let (v_c, rolling_speed) = centre_velocity(frame, &r_dot, state.y, kin.z);
    let on_rail = |i: usize| lifts[i].is_none();
    let mut creepage = [Creepage::default(); 2];
    for i in 0..2 {
        let v_w = v_c + w_wheel[i].cross(&arm[i]);
        creepage[i] = Creepage::from_velocities(
            &geo.frames[i],
            v_w,
            Vector3::zeros(),
            w_wheel[i],
            Vector3::zeros(),
            rolling_speed,
            crate::contact::forces::creepage::REGULARISATION_SPEED,
        );
    }
    // Constant part of the right-hand side (no contact forces).
    let g = Vector3::from(frame.gravity);
    let a_t = Vector3::from(frame.accel);
    let f_known = Vector3::from(load.force) + m * g - m * (a_t + 2.0 * w_t.cross(&r_dot));
    let (gyro_x, gyro_z) = gyroscopic(inertia, state, kin.phi_dot, frame);
    // Applied loads reach the wheels through bearings, which transmit no moment about the axle:
    // remove that component (else e.g. a yaw spring's moment would spin the wheels through the
    // roll angle, φ M_z). On an IRW-wheelset it pitches the bridge instead.
    let m_load = Vector3::from(load.moment);
    let [drive_l, drive_r] = load.drive_torque;
    let m_known = m_load - axle * axle.dot(&m_load) + axle * (drive_l + drive_r);
    // The ellipse shape depends on the curvatures only: solve Hertz once per wheel at the guessed
    // load, look up its Kalker coefficients (a/b fixed), and scale the patch (a, b ∝ N^⅓) in
    // every pass.
    let mut patch0 = [None; 2];
    for i in (0..2).filter(|&i| on_rail(i)) {
        let side = Side::BOTH[i].name();
        let c = &kin.contacts[i];
        let hertz = HertzContact::solve(
            contact_curvature(c, i, kin.phi),
            lambda_guess[i].max(1.0),
            &forces.material,
            &forces.material,
        )
        .map_err(|e| WheelsetError::Contact {
            side,
            message: e.to_string(),
        })?;
        let strip = forces.patches.as_ref().and_then(|dp| {
            let e_star = forces.material.contact_modulus(&forces.material);
            dp.ellipse(Side::BOTH[i], c, hertz.b, hertz.normal_force, e_star)
        });
        let patch = match strip {
            Some((a, b)) => ContactPatch::new(
                a,
                b,
                hertz.normal_force,
                forces.material.shear_modulus(),
                forces.friction,
                &forces.kalker,
            ),
            None => ContactPatch::from_hertz(&hertz, &forces.material, forces.friction, &forces.kalker),
        };
        patch0[i] = Some(patch.map_err(|e| WheelsetError::Contact {
            side,
            message: e.to_string(),
        })?);
    }
    let lu = Reactions::new(matrix(inertia, &geo, &kin, lifts, track));
    let lift_gap = lifts.map(|l| l.map_or(0.0, |l| l.gap()));
    // One pass: the creep forces at the normal forces `lambda`, then the accelerations and the
    // normal forces they give, Φ(λ).
    let pass = |lambda: [f64; 2]| -> Result<WheelsetDynamics, WheelsetError> {
        let mut f = f_known;
        let mut mo = m_known;
        let mut creep_y = 0.0;
        // Moments of each wheel's creep forces about the centre.
        let mut mo_wheel = [Vector3::zeros(); 2];
        let mut creep = [CreepForce::default(); 2];
        let mut semi_axes = [(0.0, 0.0); 2];
        for i in (0..2).filter(|&i| on_rail(i)) {
            let side = Side::BOTH[i].name();
            let n_force = lambda[i].max(1.0);
            let patch = patch0[i].as_ref().ok_or(WheelsetError::Singular)?.scaled(n_force);
            semi_axes[i] = (patch.a, patch.b);
            creep[i] = forces
                .model
                .forces(&patch, &creepage[i], rolling_speed)
                .map_err(|e| WheelsetError::Contact {
                    side,
                    message: e.to_string(),
                })?;
            let fr = &geo.frames[i];
            let fc = fr.force_to_global(creep[i].fx, creep[i].fy, 0.0);
            f += fc;
            creep_y += fc.y;
            mo_wheel[i] = arm[i].cross(&fc) + fr.moment_to_global(creep[i].mz);
            mo += mo_wheel[i];
        }
        // Right-hand side of the (pass-independent) system factored above.
        let mut b = SVector::<f64, 10>::zeros();
        for k in 0..3 {
            b[k] = f[k];
        }
        b[3] = mo.x + gyro_x;
        b[4] = mo.z + gyro_z;
        match inertia.irw {
            None => b[5] = axle.dot(&mo),
            Some(_) => {
                b[5] = axle.dot(&mo_wheel[0]) + drive_l;
                b[9] = axle.dot(&mo_wheel[1]) + drive_r;
            }
        }
        b[6] = kin.c_z;
        b[7] = kin.c_phi;
        if let Some(t) = track {
            b[8] = -t.damping_n_s_per_m * state.track_shift_rate
                - t.stiffness_n_per_m * state.track_shift
                - creep_y;
        }
        let sol = lu.solve(&b).ok_or(WheelsetError::Singular)?;
        if !sol.iter().all(|v| v.is_finite()) {
            return Err(WheelsetError::Singular);
        }
        let mut normal = [sol[6], sol[7]];
        let mut lift_accel = [0.0; 2];
        for l in lifts.iter().flatten() {
            lift_accel[l.side] = sol[6 + l.side];
            normal[l.side] = 0.0;
        }
        Ok(WheelsetDynamics {
            accel: [sol[0], sol[1], sol[2], sol[3], sol[4], sol[5]],
            spin_accel_right: sol[9],
            normal,
            creep,
            creepage,
            lambda_change: 0.0,
            lift_accel,
            lift_gap,
            track_accel: if track.is_some() { sol[8] } else { 0.0 },
            wheel_force: [(0.0, 0.0); 2],
            semi_axes,
        })
    };
    // Solve G(λ) = Φ(λ) − λ = 0 by Broyden's method. Its matrix B ≈ ∂G/∂λ starts from `secant`,
    // the one the wheelset's previous evaluation ended with (G changes little between nearby
    // states: Polach's ε does not depend on N since a²b ∝ N, so G is nearly linear and a carried
    // B converges in 2–3 passes), and is handed back for the next. Should that fail, the
    // iteration starts again as the plain fixed point (B₀ = −I: the first step is λ₁ = Φ(λ₀)),
    // the secant updates making it superlinear where the plain iteration converges linearly (its
    // factor reaches ~0.3 in flange contact). A lifted wheel's λ stays 0.
    let pin = |mut l: [f64; 2]| {
        for lf in lifts.iter().flatten() {
            l[lf.side] = 0.0;
        }
        l
    };
    // Relative, with an absolute floor of 1 nN (a wheelset about to leave both rails has λ → 0).
    let tolerance = |r: &WheelsetDynamics| LAMBDA_TOLERANCE * (r.normal[0].abs() + r.normal[1].abs()) + 1e-9;
    let broyden = |mut jac: Matrix2<f64>| -> Result<(WheelsetDynamics, Matrix2<f64>, bool), WheelsetError> {
        let mut lambda = pin(lambda_guess);
        let mut result = pass(lambda)?;
        let mut g = Vector2::new(result.normal[0] - lambda[0], result.normal[1] - lambda[1]);
        let mut converged = g.amax() <= tolerance(&result);
        for _ in 0..MAX_PASSES {
            if converged {
                break;
            }
            let step = match jac.lu().solve(&(-g)) {
                Some(s) if s.iter().all(|v| v.is_finite()) => s,
                _ => g,
            };
            let next = pin([lambda[0] + step[0], lambda[1] + step[1]]);
            let step = Vector2::new(next[0] - lambda[0], next[1] - lambda[1]);
            let r = pass(next)?;
            let g_next = Vector2::new(r.normal[0] - next[0], r.normal[1] - next[1]);
            let dg = g_next - g;
            let dl = step.norm_squared();
            if dl > 0.0 {
                jac += (dg - jac * step) * step.transpose() / dl;
            }
            lambda = next;
            g = g_next;
            result = r;
            converged = g.amax() <= tolerance(&result);
        }
        result.lambda_change = g.amax();
        Ok((result, jac, converged))
    };
    let fresh = -Matrix2::<f64>::identity();
    let carried = *secant;
    let (result, jac, converged) = match broyden(carried) {
        Ok(r) if r.2 || carried == fresh => r,
        Err(e) if carried == fresh => return Err(e),
        _ => broyden(fresh)?,
    };
    if !converged {
        return Err(WheelsetError::NormalForces {
            change: result.lambda_change,
            passes: MAX_PASSES + 1,
        });
    }
    *secant = if jac.iter().all(|v| v.is_finite()) {
        jac
    } else {
        fresh
    };
    let mut result = result;
    for i in 0..2 {
        // Normal force along the rail normal plus the creep force's lateral/vertical components
        // (the contact frame's t₂ lies in the cross-section: (0, n_z, −n_y) up to the yaw).
        let (ny, nz) = (geo.normal[i].y, geo.normal[i].z);
        let (n, fy) = (result.normal[i], result.creep[i].fy);
        result.wheel_force[i] = (n * ny + fy * nz, n * nz - fy * ny);
    }
    Ok(result)
}

/// A closing lifted wheel's gap below which it lands in the other wheel's landing impact (1 nm:
/// far below anything the motion resolves, far above the events' location error).
const SIMULTANEOUS_GAP_M: f64 = 1e-9;

/// The landing of a lifted wheel (an event of the integrator where its θ returns to 0): a
/// perfectly plastic impact. The impulses P_l, P_r at both contacts (along the rail normals, at
/// the real points) change the velocities so that both constraints hold again:
///
/// ```text
/// M Δv = Σ P_i n_i (the rows of [`evaluate`]'s system with the impulses for the forces)
/// Δż − Z_y Δẏ = −k σ θ̇,   Δφ̇ − Φ_y Δẏ = −σ θ̇     (θ̇ → 0)
/// ```
///
/// `kin` is the two-point configuration at the state's y, `side` the wheel that lands (0 left,
/// 1 right). Should the other wheel be off its rail too (a flight), it lands in the same impact
/// where it is closing within `SIMULTANEOUS_GAP_M` (1 nm) of its rail, else it stays free: no impulse on
/// it, its θ̇ changed by the impact. On return the state has the landed wheel's θ = θ̇ = 0 and
/// the velocities after the impact.
pub fn land(
    inertia: &WheelsetInertia,
    state: &mut WheelsetState,
    kin: &WheelsetKinematics,
    track: Option<&LateralFlexibility>,
    side: usize,
) -> Result<Option<Landing>, WheelsetError> {
    let lifts = Lift::of(state, kin)?;
    let Some(l) = lifts[side] else {
        return Ok(None);
    };
    if l.theta_dot >= 0.0 {
        // Not closing (θ a little below zero from the event's location, or the other wheel's
        // impact sent this one up): back to the rail's surface, no impact.
        state.lift[side] = 0.0;
        return Ok(None);
    }
    // The other wheel lands in the same impact where it is within SIMULTANEOUS_GAP_M of its rail
    // and closing (both wheels of a wheelset thrown up come down in one instant; the event
    // located for one leaves the other a round-off above its rail, whose own event would come
    // only after this impact has changed its speed). Else it flies on, free.
    let other = 1 - side;
    let co_landing = lifts[other].filter(|o| o.gap() <= SIMULTANEOUS_GAP_M && o.theta_dot < 0.0);
    let mut flying = ON_RAILS;
    if co_landing.is_none() {
        flying[other] = lifts[other];
    }
    let geo = Geometry::new(state, &apply_lifts(&lifts, kin))?;
    let a = matrix(inertia, &geo, kin, &flying, track);
    let mut b = SVector::<f64, 10>::zeros();
    for w in std::iter::once(&l).chain(co_landing.as_ref()) {
        b[6] -= w.k * w.sigma * w.theta_dot;
        b[7] -= w.sigma * w.theta_dot;
    }
    let sol = a.lu().solve(&b).ok_or(WheelsetError::Singular)?;
    state.x_dot += sol[0];
    state.y_dot += sol[1];
    state.psi_dot += sol[4];
    state.omega += sol[5];
    state.omega_right += if inertia.irw.is_some() { sol[9] } else { sol[5] };
    if track.is_some() {
        state.track_shift_rate += sol[8];
    }
    state.lift[l.side] = 0.0;
    state.lift_rate[l.side] = 0.0;
    if co_landing.is_some() {
        state.lift[other] = 0.0;
        state.lift_rate[other] = 0.0;
    }
    let pivot_impulse = if flying[other].is_some() {
        state.lift_rate[other] += sol[6 + other];
        0.0
    } else {
        sol[6 + other]
    };
    Ok(Some(Landing {
        side: l.side,
        speed: -l.gain * l.theta_dot,
        impulse: sol[6 + l.side],
        pivot_impulse,
        other_landed: co_landing.is_some(),
    }))
}

/// The frame and gyroscopic terms of the roll and yaw rows (x, z), with the spin angular
/// momentum about the axle H_s (an IRW-wheelset: both wheels'):
/// −I_x α_tx + H_s (ψ̇ + ω_tz) and −I_z α_tz − H_s (φ̇ + ω_tx).
pub(crate) fn gyroscopic(
    inertia: &WheelsetInertia,
    state: &WheelsetState,
    phi_dot: f64,
    frame: &FrameMotion,
) -> (f64, f64) {
    let [ix, _, iz] = inertia.inertia_kg_m2;
    let h_spin = match inertia.irw {
        Some(irw) => irw.wheel_spin_kg_m2 * (state.omega + state.omega_right),
        None => inertia.inertia_kg_m2[1] * state.omega,
    };
    (
        -ix * frame.alpha[0] + h_spin * (state.psi_dot + frame.omega[2]),
        -iz * frame.alpha[2] - h_spin * (phi_dot + frame.omega[0]),
    )
}

/// Relative curvatures at a contact of wheel `i` (0 left, 1 right) of a wheelset rolled by `phi`,
/// its contact angle taken from the wheel's radial direction.
pub(crate) fn contact_curvature(p: &crate::contact::ContactPoint, i: usize, phi: f64) -> RelativeCurvature {
    RelativeCurvature::wheel_rail(
        p.rolling_radius,
        p.contact_angle - side_roll(i, phi),
        p.wheel_curvature,
        p.rail_curvature,
    )
}

/// The contact angle relative to the wheel's radial direction: the track-frame angle minus the
/// wheelset roll (left), plus it (right).
fn side_roll(i: usize, phi: f64) -> f64 {
    if i == 0 {
        phi
    } else {
        -phi
    }
}
