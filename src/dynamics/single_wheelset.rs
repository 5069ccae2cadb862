//! Scene: one solid-axle wheelset elastically tied to a frame that moves along the track at the
//! reference speed (the Klingel and critical-speed scenes). The frame applies the axle load and
//! holds the wheelset through longitudinal and lateral spring–dampers at the two axle boxes
//! (lateral semi-spacing b): yaw stiffness 2 k_x b². The frame is the wheelset-track frame itself:
//! on a track with curves and irregularities the wheelset follows the centreline through the frame's whole motion (Eq. 3–4 completed, `crate::track::centreline`)
//! (frame motion, gravity with cant) and its contact sees the rail irregularities at its arc
//! length; without a track it runs on tangent, level, ideal track.
//!
//! State: [x, y, ψ, ẋ, ẏ, ψ̇, Ω, θ_l, θ_r, θ̇_l, θ̇_r] (see [`WheelsetState::read`]); z, φ from the
//! contact model (and a lifted wheel's θ).

use std::sync::Arc;

use super::kinematics::{initial_pose, Kind, Kinematics};
use super::reference::FrameAt;
use super::reference::{Reference, G};
use super::system::{
    DynamicsError, InitialDisturbance, VehicleData, VehicleModel, VehicleSample, WheelsetSample,
};
use super::traction::{DriveInfo, TractionState};
use super::wheelset::{Landing, Load, WheelsetInertia, WheelsetState};
use crate::contact::forces::ContactForceSettings;
use crate::contact::ContactModel;
use crate::track::RailOffsets;

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

/// The single-wheelset system (the model; its run state is a [`VehicleData`]).
pub struct SingleWheelset {
    pub name: String,
    pub inertia: WheelsetInertia,
    pub tie: Tie,
    /// Vertical load the frame puts on the wheelset (both boxes together), N.
    pub axle_load_n: f64,
    pub contact: Arc<dyn ContactModel>,
    pub forces: ContactForceSettings,
    pub r0: f64,
    pub reference: Reference,
}

impl SingleWheelset {
    fn unpack(x: &[f64]) -> WheelsetState {
        WheelsetState::read(x, false)
    }

    /// The contact kinematics of the state at (t, x), its frame and arc length.
    fn kinematics(
        &self,
        data: &mut VehicleData,
        t: f64,
        st: &WheelsetState,
    ) -> Result<(Kinematics, FrameAt, f64), DynamicsError> {
        let (v, v_dot) = self.reference.speed_at(t);
        let s = self.reference.s_ref(t) + st.x;
        let frame = self
            .reference
            .frame(s, v, v_dot)
            .map_err(|source| DynamicsError::Track { s, source })?;
        let kin = Kinematics::of(
            self.contact.as_ref(),
            st,
            &st.shifted_rails(&frame.rails),
            &mut data.warm[0],
        )
        .map_err(DynamicsError::contact(&self.name, st.y, s))?;
        data.contact_evaluations += 1;
        Ok((kin, frame, s))
    }

    /// Evaluates the model at (t, x).
    pub fn evaluate(
        &self,
        data: &mut VehicleData,
        t: f64,
        x: &[f64],
    ) -> Result<WheelsetSample, DynamicsError> {
        self.evaluate_with_tie(data, t, x).map(|(s, _)| s)
    }

    /// [`Self::evaluate`] and the tie's longitudinal force on the wheelset (the traction that
    /// holds its speed), N.
    fn evaluate_with_tie(
        &self,
        data: &mut VehicleData,
        t: f64,
        x: &[f64],
    ) -> Result<(WheelsetSample, f64), DynamicsError> {
        let st = Self::unpack(x);
        let (kin, frame, s) = self.kinematics(data, t, &st)?;
        let v = frame.motion.speed;
        let rails = frame.rails;
        let tie = &self.tie;
        let mut load = Load {
            force: [0.0, 0.0, -self.axle_load_n],
            ..Load::default()
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
        let dynamics = kin
            .evaluate(
                &self.inertia,
                &st,
                &frame.motion,
                &load,
                &self.forces,
                &mut data.normal_start[0],
                self.reference.lateral_flexibility().as_ref(),
            )
            .map_err(DynamicsError::wheelset(&self.name, st.y))?;
        let kin = kin.pose(&st).map_err(DynamicsError::wheelset(&self.name, st.y))?;
        let sample = WheelsetSample {
            state: st,
            kin,
            dynamics,
            speed: v + st.x_dot,
            reference_speed: v,
            drive_torque: [0.0; 2],
            s,
            rails: rails.q,
        };
        Ok((sample, load.force[0]))
    }
}

impl VehicleModel for SingleWheelset {
    fn dim(&self) -> usize {
        WheelsetState::slot_size(false)
    }

    fn wheelset_names(&self) -> Vec<String> {
        vec![self.name.clone()]
    }

    fn body_names(&self) -> Vec<String> {
        Vec::new()
    }

    /// Lateral offset y₀, yaw ψ₀, rolling at V₀/r0 (the elastic model: z, φ sunk by the static
    /// approach; where the rigid solve fails at y₀, the run's first evaluation reports it).
    fn initial_state(&self, initial: &InitialDisturbance) -> Vec<f64> {
        let mut x = vec![0.0; self.dim()];
        let q = 0.5 * (self.axle_load_n + self.inertia.mass_kg * G);
        let rails = self
            .reference
            .frame(self.reference.s_ref(0.0), self.reference.speed.at(0.0), 0.0)
            .map(|f| RailOffsets::from_array(f.rails.q))
            .unwrap_or_default();
        let free = initial_pose(
            self.contact.as_ref(),
            initial.lateral_m,
            &rails,
            [q, q],
            &self.forces,
        )
        .ok()
        .flatten();
        WheelsetState {
            y: initial.lateral_m,
            psi: initial.yaw_rad,
            y_dot: initial.lateral_velocity_m_s,
            omega: self.reference.speed.at(0.0) / self.r0,
            lift: free.map_or([0.0; 2], |(z, phi)| [z, phi]),
            ..WheelsetState::default()
        }
        .write(&mut x, false);
        x
    }

    /// The static wheel loads: half the axle load and the wheelset's weight each.
    fn new_data(&self) -> VehicleData {
        let static_n = 0.5 * (self.axle_load_n + self.inertia.mass_kg * G);
        VehicleData::new(vec![[static_n, static_n]])
    }

    fn rhs(&self, data: &mut VehicleData, t: f64, x: &[f64], dxdt: &mut [f64]) -> Result<(), DynamicsError> {
        let s = self.evaluate(data, t, x)?;
        WheelsetState::write_rates(x, dxdt, &s.dynamics, false);
        Ok(())
    }

    /// The frame at the reference speed holds the wheelset through its tie: the tie's longitudinal
    /// force is the traction ([`super::traction::TractionLaw::Tied`]).
    fn sample(&self, data: &mut VehicleData, t: f64, x: &[f64]) -> Result<VehicleSample, DynamicsError> {
        let (w, tie) = self.evaluate_with_tie(data, t, x)?;
        let traction = TractionState {
            tie_n: tie,
            power_w: tie * w.reference_speed,
            offset_m: w.state.x,
            speed_m_s: w.speed,
            ..TractionState::default()
        };
        Ok(VehicleSample {
            wheelsets: vec![w],
            traction,
            ..VehicleSample::default()
        })
    }

    fn wheelset_slots(&self) -> Vec<(usize, usize)> {
        vec![(0, self.dim())]
    }

    /// Tied to its frame; the weight on the rails is the axle load and the wheelset's own.
    fn drive_info(&self) -> DriveInfo {
        DriveInfo {
            mode: "tied",
            controller_hz: None,
            driven_wheelsets: Vec::new(),
            weight_n: self.axle_load_n + self.inertia.mass_kg * G,
            effective_mass_kg: self.inertia.mass_kg + self.inertia.inertia_kg_m2[1] / (self.r0 * self.r0),
        }
    }

    /// None with the elastic model (its slots hold the free pose; no landing events).
    fn lift_offsets(&self) -> Vec<usize> {
        if !Kind::of(self.contact.as_ref()).lands() {
            return Vec::new();
        }
        vec![WheelsetState::lift_index(false)]
    }

    fn land(
        &self,
        data: &mut VehicleData,
        t: f64,
        x: &mut [f64],
        wheelset: usize,
        side: usize,
    ) -> Result<Option<Landing>, DynamicsError> {
        debug_assert_eq!(wheelset, 0);
        let mut st = Self::unpack(x);
        let (kin, ..) = self.kinematics(data, t, &st)?;
        let landing = kin
            .land(
                &self.inertia,
                &mut st,
                self.reference.lateral_flexibility().as_ref(),
                side,
            )
            .map_err(DynamicsError::wheelset(&self.name, st.y))?;
        st.write(x, false);
        Ok(landing)
    }

    fn contact(&self) -> &dyn ContactModel {
        self.contact.as_ref()
    }

    fn reference(&self) -> &Reference {
        &self.reference
    }

    fn nominal_radius(&self) -> f64 {
        self.r0
    }
}
