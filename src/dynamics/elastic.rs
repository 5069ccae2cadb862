//! A wheelset on elastic contacts ([`crate::contact::models::elastic`]; issue 14, not in the
//! paper): free in x, y, z, φ, ψ and its spin, pushed by a Hertz normal force at every region where
//! its real profiles interpenetrate the rails' ([`crate::contact::elastic`]). No constraint, so no
//! normal-force unknowns: the Newton–Euler rows of [`super::wheelset`] with the contact forces known,
//!
//! ```text
//! m (r̈ + a_t + 2 ω_t × ṙ)                      = F + m g_t + Σ_k (N_k n_k + F_ck)
//! I_x (φ̈ + α_tx) − ψ I_y Ω̇ − I_y Ω (ψ̇ + ω_tz) = M_x + Σ_k u_k × (N_k n_k + F_ck) + M_ck   (x)
//! I_y Ω̇                                         = a · (M + Σ_k …)        (each wheel's own, IRW)
//! I_z (ψ̈ + α_tz) + φ I_y Ω̇ + I_y Ω (φ̇ + ω_tx) = (same, z)
//! N_k = w_k K_k δ_k^{3/2} (1 + χ δ̇_k)  ≥ 0        (Hertz; Hunt–Crossley damping)
//! ```
//!
//! w_k the share of a contact inside a region with others ([`crate::contact::elastic`]),
//! K_k from the Hertz solution at the point's curvatures (δ ∝ N^{2/3}: K = δ₁^{−3/2} with δ₁ the
//! approach at 1 N), the creep forces F_ck, M_ck from the contact's ellipse at N_k and its
//! creepages, as for the constraint models. In the state the slot's four lift entries hold the free
//! z, φ, ż, φ̇ ([`WheelsetState::free_pose`]): a free wheelset has no lift coordinates, each wheel's
//! gap is its own. The free pose is one kind of a wheelset's kinematics
//! ([`super::kinematics::Kinematics::Free`]); this module uses the constrained wheelset's types
//! and geometry ([`super::wheelset`]), never the other way.

use nalgebra::Vector3;

use super::wheelset::{
    axle_direction, contact_curvature, contact_geometry, gyroscopic, FrameMotion, Load, WheelsetDynamics,
    WheelsetError, WheelsetInertia, WheelsetState,
};
use crate::contact::elastic::{ElasticContact, ElasticContacts, FreePose};
use crate::contact::forces::{ContactForceSettings, ContactPatch, CreepForce, Creepage, HertzContact};
use crate::contact::{ContactModel, ContactModelError, WarmStart, WheelsetKinematics};
use crate::profile::Side;
use crate::track::{LateralFlexibility, RailMotion, RailOffsets};

/// The free wheelset's kinematics: its pose (z, φ and their rates the state's own; Z_y = Φ_y = c
/// = 0; `contacts` each wheel's closest point) and the elastic contacts found at it.
#[derive(Debug, Clone, PartialEq)]
pub struct FreeKinematics {
    pub pose: WheelsetKinematics,
    /// (Boxed: they are four times the rest, and kinematics are moved several times per
    /// evaluation.)
    pub contacts: Box<ElasticContacts>,
}

/// The elastic search `search` at the state's free pose. `rails`: the rails under the wheelset
/// ([`WheelsetState::shifted_rails`]).
pub fn free_kinematics(
    search: &ElasticContact,
    st: &WheelsetState,
    rails: &RailMotion,
) -> Result<FreeKinematics, ContactModelError> {
    let pose = st.free_pose();
    let contacts = search.search(&pose, rails)?;
    Ok(FreeKinematics {
        pose: WheelsetKinematics {
            z: pose.z,
            phi: pose.phi,
            z_dot: pose.z_dot,
            phi_dot: pose.phi_dot,
            contacts: contacts.closest,
            ..WheelsetKinematics::default()
        },
        contacts: Box::new(contacts),
    })
}

/// The elastic model's initial pose at lateral displacement `y` on rails displaced by `rails` under
/// the static wheel loads `loads` (left, right; N, vertical): the rigid touching configuration lowered by each
/// wheel's Hertz approach (a wheel sinks δ / n_Z to approach δ along its normal). `model` is the
/// elastic model (its [`ContactModel::configuration`] the rigid touching one).
pub fn initial_free_pose(
    model: &dyn ContactModel,
    y: f64,
    rails: &RailOffsets,
    loads: [f64; 2],
    forces: &ContactForceSettings,
) -> Result<(f64, f64), ContactModelError> {
    let c = model.configuration(y, rails, &mut WarmStart::default())?;
    let mut sink = [0.0; 2];
    let mut arm = [0.0; 2];
    for i in 0..2 {
        let p = &c.contacts[i];
        let n_z = p.normal.1;
        let hertz = HertzContact::solve(
            contact_curvature(p, i, c.phi),
            loads[i].max(1.0) / n_z,
            &forces.material,
            &forces.material,
        )
        .map_err(|e| ContactModelError::Other(Box::new(e)))?;
        sink[i] = hertz.penetration / n_z;
        arm[i] = p.position.0 - y;
    }
    // dz + dφ u_l = −sink_l, dz + dφ u_r = −sink_r.
    let d_phi = (sink[1] - sink[0]) / (arm[0] - arm[1]);
    let d_z = -sink[0] - d_phi * arm[0];
    Ok((c.z + d_z, c.phi + d_phi))
}

/// The accelerations of a free wheelset on its elastic contacts (`free`: its pose, the state's
/// own z, φ and rates, and the contacts found there). The slot's lift entries hold z, φ: their
/// accelerations z̈, φ̈ are returned as its `lift_accel` too.
pub fn evaluate_free(
    inertia: &WheelsetInertia,
    state: &WheelsetState,
    free: &FreeKinematics,
    frame: &FrameMotion,
    load: &Load,
    forces: &ContactForceSettings,
    track: Option<&LateralFlexibility>,
) -> Result<WheelsetDynamics, WheelsetError> {
    let (kin, contacts) = (&free.pose, free.contacts.as_ref());
    let m = inertia.mass_kg;
    let [ix, _, iz] = inertia.inertia_kg_m2;
    let (z, phi) = (kin.z, kin.phi);
    let axle = axle_direction(state.psi, phi);
    let r_dot = Vector3::new(state.x_dot, state.y_dot, kin.z_dot);
    let w_t = Vector3::from(frame.omega);
    let irw = inertia.irw.is_some();
    let omega_wheel = [state.omega, if irw { state.omega_right } else { state.omega }];
    let w_axle = w_t + Vector3::new(kin.phi_dot, 0.0, state.psi_dot);
    let (v_c, rolling_speed) = super::wheelset::centre_velocity(frame, &r_dot, state.y, z);
    let g = Vector3::from(frame.gravity);
    let a_t = Vector3::from(frame.accel);
    let mut f = Vector3::from(load.force) + m * g - m * (a_t + 2.0 * w_t.cross(&r_dot));
    let m_load = Vector3::from(load.moment);
    let [drive_l, drive_r] = load.drive_torque;
    let mut mo = m_load - axle * axle.dot(&m_load) + axle * (drive_l + drive_r);
    let mut mo_wheel = [Vector3::zeros(); 2];
    let mut out = WheelsetDynamics::default();
    let mut contact_y = 0.0;
    for i in 0..2 {
        let side = Side::BOTH[i].name();
        let err = |e: String| WheelsetError::Contact { side, message: e };
        let w_wheel = w_axle + axle * omega_wheel[i];
        let mut deepest = true;
        let mut creep_sum = CreepForce::lifted();
        for p in contacts.of(i) {
            let (arm, _, frame_c) = contact_geometry(state, z, phi, axle, &p.point, i);
            let frame_c = frame_c?;
            let v_w = v_c + w_wheel.cross(&arm);
            let creepage = Creepage::from_velocities(
                &frame_c,
                v_w,
                Vector3::zeros(),
                w_wheel,
                Vector3::zeros(),
                rolling_speed,
                crate::contact::forces::creepage::REGULARISATION_SPEED,
            );
            if deepest {
                out.creepage[i] = creepage;
                deepest = false;
            }
            // Hertz: δ ∝ N^{2/3}, so N = (δ / δ₁)^{3/2} with δ₁ the approach at 1 N.
            let unit = HertzContact::solve(
                contact_curvature(&p.point, i, phi),
                1.0,
                &forces.material,
                &forces.material,
            )
            .map_err(|e| err(e.to_string()))?;
            let elastic = p.share * (p.depth / unit.penetration).powf(1.5);
            let normal = (elastic * (1.0 + contacts.damping_s_per_m * p.rate)).max(0.0);
            if normal <= 0.0 {
                continue;
            }
            let patch = ContactPatch::from_hertz(
                &unit.scaled(normal),
                &forces.material,
                forces.friction,
                &forces.kalker,
            )
            .map_err(|e| err(e.to_string()))?;
            let creep = forces
                .model
                .forces(&patch, &creepage, rolling_speed)
                .map_err(|e| err(e.to_string()))?;
            let fc = frame_c.force_to_global(creep.fx, creep.fy, normal);
            let mc = arm.cross(&fc) + frame_c.moment_to_global(creep.mz);
            f += fc;
            mo += mc;
            mo_wheel[i] += mc;
            contact_y += fc.y;
            out.normal[i] += normal;
            out.wheel_force[i].0 += fc.y;
            out.wheel_force[i].1 += fc.z;
            creep_sum = CreepForce {
                fx: creep_sum.fx + creep.fx,
                fy: creep_sum.fy + creep.fy,
                mz: creep_sum.mz + creep.mz,
                saturation: creep_sum.saturation.max(creep.saturation),
                lifted: false,
            };
        }
        out.creep[i] = creep_sum;
        out.lift_gap[i] = contacts.gap[i].max(0.0);
    }
    let (gyro_x, gyro_z) = gyroscopic(inertia, state, kin.phi_dot, frame);
    // Spin rows first (each wheel's own on an IRW-wheelset), then roll and yaw with the spin
    // accelerations' gyroscopic coupling I_y Ω̇ a.
    let (spin_l, spin_r, spin_sum) = match inertia.irw {
        Some(w) => {
            let l = (axle.dot(&mo_wheel[0]) + drive_l) / w.wheel_spin_kg_m2;
            let r = (axle.dot(&mo_wheel[1]) + drive_r) / w.wheel_spin_kg_m2;
            (l, r, w.wheel_spin_kg_m2 * (l + r))
        }
        None => {
            let i_y = inertia.inertia_kg_m2[1];
            let s = axle.dot(&mo) / i_y;
            (s, s, i_y * s)
        }
    };
    let phi_ddot = (mo.x + gyro_x - spin_sum * axle.x) / ix;
    let psi_ddot = (mo.z + gyro_z - spin_sum * axle.z) / iz;
    let accel = [f.x / m, f.y / m, f.z / m, phi_ddot, psi_ddot, spin_l];
    if !accel.iter().chain([&spin_r]).all(|v| v.is_finite()) {
        return Err(WheelsetError::Singular);
    }
    out.accel = accel;
    out.lift_accel = [accel[2], accel[3]];
    out.spin_accel_right = spin_r;
    if let Some(t) = track {
        // The wheels push the rails with the opposite of their contact forces.
        out.track_accel = (-t.damping_n_s_per_m * state.track_shift_rate
            - t.stiffness_n_per_m * state.track_shift
            - contact_y)
            / t.mass_kg;
    }
    Ok(out)
}

impl WheelsetState {
    /// The elastic model's free pose: the slot's lift entries θ_l, θ_r, θ̇_l, θ̇_r hold z, φ, ż, φ̇.
    pub fn free_pose(&self) -> FreePose {
        FreePose {
            y: self.y,
            z: self.lift[0],
            phi: self.lift[1],
            y_dot: self.y_dot,
            z_dot: self.lift_rate[0],
            phi_dot: self.lift_rate[1],
        }
    }
}
