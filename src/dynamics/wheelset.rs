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
//! about the centre, a_t, ω_t, α_t the track frame's motion (Eq. 3–4) and g_t gravity in track
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

use crate::contact::forces::{
    ContactForceSettings, ContactFrame, ContactPatch, CreepForce, Creepage, HertzContact, RelativeCurvature,
};
use crate::contact::WheelsetKinematics;
use crate::profile::Side;

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

/// The motion of the wheelset-track frame (Eq. 3–4) and gravity, in its own components.
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
}

/// Applied force and moment about the wheelset centre (suspension, loads), track components.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Load {
    pub force: [f64; 3],
    pub moment: [f64; 3],
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
}

/// Dynamics failures.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum WheelsetError {
    #[error("{side} wheel lifts: normal force {normal:.1} N ≤ 0 (the constraint contact model cannot follow a lifting wheel)")]
    Lift { side: &'static str, normal: f64 },
    #[error("{side} contact: {message}")]
    Contact { side: &'static str, message: String },
    #[error("singular wheelset equations")]
    Singular,
    #[error("the normal forces and the creep forces did not agree after {passes} passes (last change {change:.3e} N)")]
    NormalForces { change: f64, passes: usize },
}

/// Passes between creep forces and normal forces: at most 1 + this many, until Φ(λ) − λ is below
/// `LAMBDA_TOLERANCE` relative (so that the right-hand side is a function of the state, not of the
/// previous evaluation — implicit integrators difference it); else a diagnosed failure.
const MAX_PASSES: usize = 30;
const LAMBDA_TOLERANCE: f64 = 1e-12;

/// Evaluates the wheelset's accelerations and normal forces. `lambda_guess` seeds the creep
/// forces' first pass (e.g. the previous evaluation's normal forces).
#[allow(clippy::too_many_arguments)]
pub fn evaluate(
    inertia: &WheelsetInertia,
    state: &WheelsetState,
    kin: &WheelsetKinematics,
    frame: &FrameMotion,
    load: &Load,
    forces: &ContactForceSettings,
    lambda_guess: [f64; 2],
) -> Result<WheelsetDynamics, WheelsetError> {
    let m = inertia.mass_kg;
    let [ix, iy, iz] = inertia.inertia_kg_m2;
    let centre = Vector3::new(state.x, state.y, kin.z);
    let r_dot = Vector3::new(state.x_dot, state.y_dot, kin.z_dot);
    let axle = Vector3::new(-state.psi, 1.0, kin.phi).normalize();
    let w_t = Vector3::from(frame.omega);
    // Angular velocity of the wheelset (ground, track components).
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
    // Ground velocity of the centre: frame speed + relative (Coriolis of r dropped, see doc).
    let v_c = Vector3::new(frame.speed, 0.0, 0.0) + r_dot + w_t.cross(&centre);
    // Contact points (3D, the yawed wheel's lowest line) and normals.
    let mut arm = [Vector3::zeros(); 2];
    let mut normal = [Vector3::zeros(); 2];
    let mut frames = [None; 2];
    for (i, c) in kin.contacts.iter().enumerate() {
        // Longitudinal position on the yawed wheel: the wheel is a surface of revolution about
        // the axle a, and the point where its normal equals the rail's normal n (n_x = 0) lies
        // where n · (a × u) = 0 (n in the wheel's meridian plane): with u = (u_x, u_Y, u_Z),
        // u_x = ψ (n_Z u_Y − n_Y u_Z) / (n_Y φ − n_Z) ≈ −ψ (u_Y + r n_Y / n_Z) — the yaw-induced
        // contact shift. Without it the rolling wheel's normal force would do work of order
        // λ Ω r ψ n_Y (see the energy test).
        let (u_y, u_z) = (c.position.0 - state.y, c.position.1 - kin.z);
        let (n_y, n_z) = c.normal;
        let u_x = state.psi * (n_z * u_y - n_y * u_z) / (n_y * kin.phi - n_z);
        let p = Vector3::new(state.x + u_x, c.position.0, c.position.1);
        arm[i] = p - centre;
        normal[i] = Vector3::new(0.0, c.normal.0, c.normal.1);
        let side = if i == 0 { "left" } else { "right" };
        frames[i] =
            Some(
                ContactFrame::new(normal[i], axle, Vector3::x()).map_err(|e| WheelsetError::Contact {
                    side,
                    message: e.to_string(),
                })?,
            );
    }
    let mut creepage = [Creepage::default(); 2];
    for i in 0..2 {
        let f = frames[i].as_ref().ok_or(WheelsetError::Singular)?;
        let v_w = v_c + w_wheel[i].cross(&arm[i]);
        creepage[i] = Creepage::from_velocities(
            f,
            v_w,
            Vector3::zeros(),
            w_wheel[i],
            Vector3::zeros(),
            frame.speed,
            crate::contact::forces::creepage::REGULARISATION_SPEED,
        );
    }
    // Constant part of the right-hand side (no contact forces).
    let g = Vector3::from(frame.gravity);
    let a_t = Vector3::from(frame.accel);
    let f_known = Vector3::from(load.force) + m * g - m * (a_t + 2.0 * w_t.cross(&r_dot));
    // Spin inertia per wheel and the spin angular momentum about the axle, H_s a.
    let i_spin = match inertia.irw {
        Some(irw) => irw.wheel_spin_kg_m2,
        None => iy,
    };
    let h_spin = match inertia.irw {
        Some(irw) => irw.wheel_spin_kg_m2 * (state.omega + state.omega_right),
        None => iy * state.omega,
    };
    // Frame and gyroscopic terms of the roll and yaw rows.
    let gyro_x = -ix * frame.alpha[0] + h_spin * (state.psi_dot + frame.omega[2]);
    let gyro_z = -iz * frame.alpha[2] - h_spin * (kin.phi_dot + frame.omega[0]);
    // Applied loads reach the wheels through bearings, which transmit no moment about the axle:
    // remove that component (else e.g. a yaw spring's moment would spin the wheels through the
    // roll angle, φ M_z). On an IRW-wheelset it pitches the bridge instead.
    let m_load = Vector3::from(load.moment);
    let m_known = m_load - axle * axle.dot(&m_load);
    // The ellipse shape depends on the curvatures only: solve Hertz once per wheel at the guessed
    // load and scale it (a, b ∝ N^⅓) in every pass.
    let mut hertz0 = [None; 2];
    for i in 0..2 {
        let side = if i == 0 { "left" } else { "right" };
        let c = &kin.contacts[i];
        let curv = RelativeCurvature::wheel_rail(
            c.rolling_radius,
            c.contact_angle - side_roll(i, kin.phi),
            c.wheel_curvature,
            c.rail_curvature,
        );
        hertz0[i] = Some(
            HertzContact::solve(curv, lambda_guess[i].max(1.0), &forces.material, &forces.material).map_err(
                |e| WheelsetError::Contact {
                    side,
                    message: e.to_string(),
                },
            )?,
        );
    }
    // 10×10: [ẍ ÿ z̈ φ̈ ψ̈ Ω̇_l λl λr θ̈_bridge Ω̇_r]. The matrix does not depend on the creep
    // forces: factored once, the passes of the creep/normal-force iteration only change the
    // right-hand side.
    //
    // Rotational rows: 3 → x (φ̈), 4 → z (ψ̈), 5 → about the axle a (Ω̇). With
    // H = I_x φ̇ x + I_y Ω a + I_z ψ̇ z and ȧ = (−ψ̇, 0, φ̇): the x and z rows carry I_y Ω̇ a_x,
    // I_y Ω̇ a_z; the spin row is the moment about the axle, a · M (not M_y: a normal force
    // at a yawed wheel's contact has a large M_x whose axle component −ψ M_x cancels M_y).
    // An IRW-wheelset has one spin row per wheel (its own contact's moment about the axle,
    // rows 5 and 9); a solid axle ties Ω̇_r = Ω̇_l. Row 8 (θ̈ = 0) keeps a place for a bridge
    // pitch degree of freedom, which neither model has: the suspension holds the bridge.
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
    // Constraints.
    a[(6, 2)] = 1.0;
    a[(6, 1)] = -kin.z_y;
    a[(7, 3)] = 1.0;
    a[(7, 1)] = -kin.phi_y;
    let lu = a.lu();
    // One pass: the creep forces at the normal forces `lambda`, then the accelerations and the
    // normal forces they give, Φ(λ).
    let pass = |lambda: [f64; 2]| -> Result<WheelsetDynamics, WheelsetError> {
        let mut f = f_known;
        let mut mo = m_known;
        // Moments of each wheel's creep forces about the centre.
        let mut mo_wheel = [Vector3::zeros(); 2];
        let mut creep = [CreepForce::default(); 2];
        for i in 0..2 {
            let side = if i == 0 { "left" } else { "right" };
            let n_force = lambda[i].max(1.0);
            let hertz = hertz0[i].as_ref().ok_or(WheelsetError::Singular)?.scaled(n_force);
            let patch = ContactPatch::from_hertz(&hertz, &forces.material, forces.friction, &forces.kalker)
                .map_err(|e| WheelsetError::Contact {
                side,
                message: e.to_string(),
            })?;
            creep[i] = forces
                .model
                .forces(&patch, &creepage[i], frame.speed)
                .map_err(|e| WheelsetError::Contact {
                    side,
                    message: e.to_string(),
                })?;
            let fr = frames[i].as_ref().ok_or(WheelsetError::Singular)?;
            let fc = fr.force_to_global(creep[i].fx, creep[i].fy, 0.0);
            f += fc;
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
                b[5] = axle.dot(&mo_wheel[0]);
                b[9] = axle.dot(&mo_wheel[1]);
            }
        }
        b[6] = kin.c_z;
        b[7] = kin.c_phi;
        let sol = lu.solve(&b).ok_or(WheelsetError::Singular)?;
        Ok(WheelsetDynamics {
            accel: [sol[0], sol[1], sol[2], sol[3], sol[4], sol[5]],
            spin_accel_right: sol[9],
            normal: [sol[6], sol[7]],
            creep,
            creepage,
            lambda_change: 0.0,
        })
    };
    // Solve G(λ) = Φ(λ) − λ = 0 by Broyden's method, started as the plain fixed point (B₀ = −I:
    // the first step is λ₁ = Φ(λ₀)); the secant updates make it superlinear where the plain
    // iteration converges linearly (its factor reaches ~0.3 in flange contact).
    let mut lambda = lambda_guess;
    let mut result = pass(lambda)?;
    let mut g = Vector2::new(result.normal[0] - lambda[0], result.normal[1] - lambda[1]);
    let mut jac = -Matrix2::<f64>::identity();
    let tolerance = |r: &WheelsetDynamics| LAMBDA_TOLERANCE * (1.0 + r.normal[0].abs() + r.normal[1].abs());
    let mut converged = g.amax() <= tolerance(&result);
    for _ in 0..MAX_PASSES {
        if converged {
            break;
        }
        let step = match jac.lu().solve(&(-g)) {
            Some(s) if s.iter().all(|v| v.is_finite()) => s,
            _ => g,
        };
        let next = [lambda[0] + step[0], lambda[1] + step[1]];
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
    for (i, side) in Side::BOTH.iter().enumerate() {
        if result.normal[i].is_nan() || result.normal[i] <= 0.0 {
            return Err(WheelsetError::Lift {
                side: side.name(),
                normal: result.normal[i],
            });
        }
    }
    if !converged {
        return Err(WheelsetError::NormalForces {
            change: result.lambda_change,
            passes: MAX_PASSES + 1,
        });
    }
    Ok(result)
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
