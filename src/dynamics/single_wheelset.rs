//! Scene: one solid-axle wheelset elastically tied to a frame that moves along the track at the
//! reference speed (the Klingel and critical-speed scenes, issue 7). The frame applies the axle
//! load and holds the wheelset through longitudinal and lateral spring–dampers at the two axle
//! boxes (lateral semi-spacing b): yaw stiffness 2 k_x b². The frame is the wheelset-track frame
//! itself: on a track with curves and irregularities the wheelset follows the centreline through
//! Eq. 3–4 (frame motion, gravity with cant) and its contact sees the rail irregularities at its
//! arc length; without a track it runs on tangent, level, ideal track.
//!
//! State: [x, y, ψ, ẋ, ẏ, ψ̇, Ω] (see [`super::wheelset`]); z, φ from the contact model.

use super::contact_model::{ContactWarmStart, RailMotion, WheelsetContact, WheelsetKinematics};
use super::integrator::OdeSystem;
use super::wheelset::{evaluate, FrameMotion, Load, WheelsetDynamics, WheelsetInertia, WheelsetState};
use crate::contact::forces::ContactForceSettings;
use crate::track::Track;

/// The tie between the wheelset and the moving frame, per axle box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tie {
    pub longitudinal_stiffness_n_per_m: f64,
    pub lateral_stiffness_n_per_m: f64,
    pub longitudinal_damping_n_s_per_m: f64,
    pub lateral_damping_n_s_per_m: f64,
    /// Lateral semi-spacing of the axle boxes b, m.
    pub half_spacing_m: f64,
}

/// Forward speed of the reference: V(t) = V₀ + a t (a = 0: constant).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpeedProfile {
    pub initial_m_s: f64,
    pub ramp_m_s2: f64,
}

impl SpeedProfile {
    pub fn at(&self, t: f64) -> f64 {
        (self.initial_m_s + self.ramp_m_s2 * t).max(0.0)
    }
    /// Distance travelled by the reference, m.
    pub fn distance(&self, t: f64) -> f64 {
        self.initial_m_s * t + 0.5 * self.ramp_m_s2 * t * t
    }
}

/// The single-wheelset system on tangent, level track.
pub struct SingleWheelset {
    pub inertia: WheelsetInertia,
    pub tie: Tie,
    /// Vertical load the frame puts on the wheelset (both boxes together), N.
    pub axle_load_n: f64,
    pub speed: SpeedProfile,
    pub contact: WheelsetContact,
    pub forces: ContactForceSettings,
    pub r0: f64,
    /// The track (None: tangent, level, ideal).
    pub track: Option<Track>,
    /// Arc length of the reference at t = 0, m.
    pub s0: f64,
    warm: ContactWarmStart,
    lambda: [f64; 2],
    /// Contact-model evaluations (for the statistics).
    pub contact_evaluations: usize,
}

/// Everything one evaluation knows, for output.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WheelsetSample {
    pub state: WheelsetState,
    pub kin: WheelsetKinematics,
    pub dynamics: WheelsetDynamics,
    pub speed: f64,
    /// Arc length of the wheelset, m.
    pub s: f64,
    /// Rail irregularities at the wheelset [y_lir, z_lir, y_rir, z_rir], m.
    pub rails: [f64; 4],
}

impl SingleWheelset {
    pub fn new(
        inertia: WheelsetInertia,
        tie: Tie,
        axle_load_n: f64,
        speed: SpeedProfile,
        contact: WheelsetContact,
        forces: ContactForceSettings,
        r0: f64,
    ) -> SingleWheelset {
        let static_n = 0.5 * (axle_load_n + inertia.mass_kg * 9.81);
        SingleWheelset {
            inertia,
            tie,
            axle_load_n,
            speed,
            contact,
            forces,
            r0,
            track: None,
            s0: 0.0,
            warm: ContactWarmStart::default(),
            lambda: [static_n, static_n],
            contact_evaluations: 0,
        }
    }

    /// A fresh copy of the model (its own warm starts) for evaluating outputs.
    pub fn clone_for_output(&self) -> SingleWheelset {
        SingleWheelset {
            inertia: self.inertia,
            tie: self.tie,
            axle_load_n: self.axle_load_n,
            speed: self.speed,
            contact: self.contact.clone(),
            forces: self.forces.clone(),
            r0: self.r0,
            track: self.track.clone(),
            s0: self.s0,
            warm: ContactWarmStart::default(),
            lambda: self.lambda,
            contact_evaluations: 0,
        }
    }

    /// Initial state: lateral offset y₀ (m), yaw ψ₀ (rad), rolling at V₀/r0.
    pub fn initial_state(&self, y0: f64, psi0: f64) -> Vec<f64> {
        vec![0.0, y0, psi0, 0.0, 0.0, 0.0, self.speed.at(0.0) / self.r0]
    }

    fn unpack(x: &[f64]) -> WheelsetState {
        WheelsetState {
            x: x[0],
            y: x[1],
            psi: x[2],
            x_dot: x[3],
            y_dot: x[4],
            psi_dot: x[5],
            omega: x[6],
            ..WheelsetState::default()
        }
    }

    /// Evaluates the model at (t, x).
    pub fn sample(&mut self, t: f64, x: &[f64]) -> Result<WheelsetSample, String> {
        let st = Self::unpack(x);
        let v = self.speed.at(t);
        let v_dot = if v > 0.0 { self.speed.ramp_m_s2 } else { 0.0 };
        let s = self.s0 + self.speed.distance(t) + st.x;
        let (frame, rails) = match &self.track {
            None => {
                let mut f = FrameMotion::tangent(v);
                f.accel[0] = v_dot;
                (f, RailMotion::default())
            }
            Some(track) => {
                let (tf, irr) = track.eval(s).map_err(|e| format!("track at s = {s:.3} m: {e}"))?;
                let m = tf.motion(v, v_dot);
                let g = tf.gravity(9.81);
                let frame = FrameMotion {
                    speed: v,
                    accel: m.acceleration.into(),
                    omega: m.angular_velocity.into(),
                    alpha: m.angular_acceleration.into(),
                    gravity: g.into(),
                };
                let o = irr.rail_offsets();
                let (dt, dtt) = irr.time_derivatives(v, v_dot);
                let to_rails = |c: [f64; 4]| {
                    let r = crate::contact::RailOffsets::from_irregularities(c[0], c[1], c[2], c[3]);
                    [r.y_left, r.z_left, r.y_right, r.z_right]
                };
                let rails = RailMotion {
                    q: [o.y_left, o.z_left, o.y_right, o.z_right],
                    q_dot: to_rails(dt),
                    q_ddot: to_rails(dtt),
                };
                (frame, rails)
            }
        };
        let kin = self
            .contact
            .kinematics(st.y, st.y_dot, &rails, &mut self.warm)
            .map_err(|e| format!("contact model at y = {:.4} mm: {e}", st.y * 1e3))?;
        self.contact_evaluations += 1;
        let tie = &self.tie;
        let mut load = Load {
            force: [0.0, 0.0, -self.axle_load_n],
            moment: [0.0; 3],
        };
        for b in [tie.half_spacing_m, -tie.half_spacing_m] {
            // Axle-box displacement relative to the frame (linearised rotation about z).
            let dx = st.x - st.psi * b;
            let dx_dot = st.x_dot - st.psi_dot * b;
            let fx = -tie.longitudinal_stiffness_n_per_m * dx - tie.longitudinal_damping_n_s_per_m * dx_dot;
            let fy = -tie.lateral_stiffness_n_per_m * st.y - tie.lateral_damping_n_s_per_m * st.y_dot;
            load.force[0] += fx;
            load.force[1] += fy;
            // Arm (0, b, 0): M = (b F_z, 0, −b F_x).
            load.moment[2] += -b * fx;
        }
        let dynamics = evaluate(&self.inertia, &st, &kin, &frame, &load, &self.forces, self.lambda)
            .map_err(|e| format!("y = {:.4} mm: {e}", st.y * 1e3))?;
        self.lambda = dynamics.normal;
        Ok(WheelsetSample {
            state: st,
            kin,
            dynamics,
            speed: v,
            s,
            rails: rails.q,
        })
    }
}

impl OdeSystem for SingleWheelset {
    fn dim(&self) -> usize {
        7
    }

    fn rhs(&mut self, t: f64, x: &[f64], dxdt: &mut [f64]) -> Result<(), String> {
        let s = self.sample(t, x)?;
        let a = s.dynamics.accel;
        dxdt[0] = x[3];
        dxdt[1] = x[4];
        dxdt[2] = x[5];
        dxdt[3] = a[0];
        dxdt[4] = a[1];
        dxdt[5] = a[4];
        dxdt[6] = a[5];
        Ok(())
    }
}
