//! One interface for every vehicle system the runs integrate — a single wheelset on a moving frame,
//! a bogie, a whole multibody vehicle — with the model kept apart from the run state (MuJoCo's
//! model/data split): a [`VehicleModel`] is built once (bodies, wheelsets, elements with their
//! static preloads, the contact model, the track reference) and never changes during a run; each
//! evaluator of it (the integrator, the output) owns a [`VehicleData`] (the contact models' warm
//! starts, the normal forces the creep forces start from). Two evaluators of one model give the
//! same results from the same state.

use nalgebra::Vector3;
use thiserror::Error;

use super::kinematics::KinematicsMemo;
use super::reference::Reference;
use super::wheelset::{Landing, NormalForceStart, WheelsetDynamics, WheelsetError, WheelsetState};
use crate::contact::{ContactModel, ContactModelError, WarmStart, WheelsetKinematics};
use crate::track::TrackError;

/// A failure while evaluating a vehicle system. Each names where it happened.
#[derive(Debug, Error)]
pub enum DynamicsError {
    #[error("track at s = {s:.3} m: {source}")]
    Track {
        s: f64,
        #[source]
        source: TrackError,
    },
    #[error("{wheelset} derails at s = {s:.2} m: the {side} wheel climbs its flange (y = {y_mm:.4} mm, past the flange's largest contact angle, where the contact model ends: {source})")]
    Derailment {
        wheelset: String,
        side: &'static str,
        y_mm: f64,
        /// Arc length of the wheelset, m.
        s: f64,
        #[source]
        source: Box<ContactModelError>,
    },
    #[error("{wheelset}: contact model at y = {y_mm:.4} mm: {source}")]
    Contact {
        wheelset: String,
        y_mm: f64,
        #[source]
        source: ContactModelError,
    },
    #[error("{wheelset} at y = {y_mm:.4} mm: {source}")]
    Wheelset {
        wheelset: String,
        y_mm: f64,
        #[source]
        source: WheelsetError,
    },
    #[error("the spherical joints' equations are singular (redundant joints?)")]
    JointsSingular,
    #[error("the static equations are singular: some body among [{bodies}] is not held in some direction by the elements")]
    StaticsSingular { bodies: String },
    #[error("centred contact: {0}")]
    CentredContact(#[source] ContactModelError),
    /// A held speed needs more than the drive's limit.
    #[error("simulation.traction.max_force_n = {limit_n} N cannot hold {speed_m_s} m/s: the speed loop asks for {demand_n:.0} N (the vehicle's running and curving resistance, and the ramp's inertia); raise max_force_n, or let the vehicle coast (simulation.traction.mode = \"coast\")")]
    TractionLimit {
        demand_n: f64,
        limit_n: f64,
        speed_m_s: f64,
    },
    /// The speed loop lost the speed (an unstable loop).
    #[error("the speed loop lost the speed: {speed_m_s:.3} m/s against the reference's {reference_m_s:.3} m/s (more than 1 % apart) with simulation.traction.controller_hz = {bandwidth_hz}: lower it (0.1–1 Hz holds the speed)")]
    SpeedLost {
        speed_m_s: f64,
        reference_m_s: f64,
        bandwidth_hz: f64,
    },
}

impl DynamicsError {
    /// The map of a wheelset's contact-model failure to the vehicle's: a flange climb
    /// ([`ContactModelError::flange_climb`]) is a derailment, anything else a contact failure.
    pub fn contact(name: &str, y: f64, s: f64) -> impl FnOnce(ContactModelError) -> DynamicsError + '_ {
        move |source| match source.flange_climb() {
            Some(side) => DynamicsError::Derailment {
                wheelset: name.to_string(),
                side,
                y_mm: y * 1e3,
                s,
                source: Box::new(source),
            },
            None => DynamicsError::Contact {
                wheelset: name.to_string(),
                y_mm: y * 1e3,
                source,
            },
        }
    }

    /// The map of a wheelset's failure to the vehicle's, naming the wheelset and its y.
    pub fn wheelset(name: &str, y: f64) -> impl FnOnce(WheelsetError) -> DynamicsError + '_ {
        move |source| DynamicsError::Wheelset {
            wheelset: name.to_string(),
            y_mm: y * 1e3,
            source,
        }
    }
}

/// The disturbance every wheelset starts from.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct InitialDisturbance {
    /// Lateral displacement, m.
    pub lateral_m: f64,
    /// Yaw, rad.
    pub yaw_rad: f64,
    /// Lateral velocity ẏ, m/s (a wheelset thrown at its flange).
    pub lateral_velocity_m_s: f64,
}

/// The static settling of a multibody vehicle: what the elements' preloads came from.
#[derive(Debug, Clone, PartialEq)]
pub struct Settling {
    /// Static displacement (x, y, z, φ, θ, ψ) of each body had the elements not been preloaded.
    pub sag: Vec<[f64; 6]>,
    /// Largest static residual after settling, N or N m.
    pub residual: f64,
    /// Static axle loads (both wheels, wheelset weight included), N.
    pub axle_loads: Vec<f64>,
}

/// One evaluator's run state.
#[derive(Debug, Clone, Default)]
pub struct VehicleData {
    /// Per wheelset: the contact model's warm start.
    pub warm: Vec<WarmStart>,
    /// Per wheelset: the normal forces and the iteration's secant matrix of the last evaluation,
    /// which the next one starts from ([`NormalForceStart`]).
    pub normal_start: Vec<NormalForceStart>,
    /// Contact-model evaluations (for the statistics).
    pub contact_evaluations: usize,
    /// Where the right-hand sides' time goes, when asked for (`kecsim bench rhs`); None in runs.
    pub part_times: Option<PartTimes>,
    /// Per wheelset: its kinematics from the last full evaluation (`KinematicsMemo`).
    pub kinematics_memo: Vec<Option<KinematicsMemo>>,
    /// The landings of lifted wheels so far (integrator events; trial steps never land).
    pub landings: Vec<LandingEvent>,
}

impl VehicleData {
    /// Fresh warm starts and the given first normal forces.
    pub fn new(lambda: Vec<[f64; 2]>) -> VehicleData {
        let n = lambda.len();
        VehicleData {
            warm: vec![WarmStart::default(); n],
            normal_start: lambda.into_iter().map(NormalForceStart::from).collect(),
            part_times: None,
            kinematics_memo: vec![None; n],
            contact_evaluations: 0,
            landings: Vec::new(),
        }
    }
}

/// The wall time of each part of a vehicle's evaluations (a multibody vehicle's; see
/// [`super::multibody::Multibody::evaluate`]), summed over `evaluations`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PartTimes {
    /// The bodies' track frames.
    pub body_frames_s: f64,
    /// The wheelsets' contact kinematics (the contact model's solve: KEC, tables, online) and
    /// their track frames with the rail irregularities.
    pub contact_kinematics_s: f64,
    /// The force elements' loads and their sums on each body.
    pub elements_s: f64,
    /// The bodies' accelerations and the joints' reactions.
    pub bodies_s: f64,
    /// The wheelsets' dynamics: creep forces, the normal-force iteration, Eq. 53's system.
    pub wheelset_dynamics_s: f64,
    /// Everything, from the first part's start to the last one's end.
    pub total_s: f64,
    pub evaluations: usize,
}

/// Everything one evaluation knows of a wheelset, for output.
#[derive(Debug, Clone, PartialEq)]
pub struct WheelsetSample {
    pub state: WheelsetState,
    pub kin: WheelsetKinematics,
    pub dynamics: WheelsetDynamics,
    /// Its forward speed along the track, ṡ = V + ẋ, m/s.
    pub speed: f64,
    /// The reference's speed V, m/s.
    pub reference_speed: f64,
    /// The drive's torque on each wheel (left, right), N m.
    pub drive_torque: [f64; 2],
    /// Arc length of the wheelset, m.
    pub s: f64,
    /// Rail irregularities at the wheelset [y_lir, z_lir, y_rir, z_rir], m.
    pub rails: [f64; 4],
}

/// A rigid body's state and where it is, for output.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodySample {
    pub s: f64,
    /// (x, y, z, φ, θ, ψ).
    pub q: [f64; 6],
    pub q_dot: [f64; 6],
}

/// A carbody's floor point where ride comfort is read (EN 12299: above each bogie and at the
/// middle of each module).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct FloorPoint {
    /// The carbody's name.
    pub carbody: String,
    /// `middle`, or `over_BOGIE` above a bogie away from the middle.
    pub point: String,
    /// The bogie under it, if any (the middle of a module on a bogie is over that bogie).
    pub over_bogie: Option<String>,
    /// Along the vehicle (the scene's x), m, and above the rail top, m.
    pub x_m: f64,
    pub height_m: f64,
    /// The carbody's index among the bodies.
    #[serde(skip)]
    pub body: usize,
    /// Its arm from the carbody's centre, body axes, m.
    #[serde(skip)]
    pub arm: [f64; 3],
}

/// Everything one evaluation of a vehicle knows, for output.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct VehicleSample {
    pub bodies: Vec<BodySample>,
    pub wheelsets: Vec<WheelsetSample>,
    /// Per element: deflection and force in its first body's axes.
    pub elements: Vec<(Vector3<f64>, Vector3<f64>)>,
    /// Per spherical joint: the position violation |G_b − G_a|, m.
    pub joint_error: Vec<f64>,
    /// Per floor point ([`VehicleModel::floor_points`]): what an accelerometer on the floor reads,
    /// in the carbody's axes, less the static 1 g on z: (x, y, z), m/s².
    pub floor: Vec<[f64; 3]>,
    /// The vehicle's drive ([`super::traction`]).
    pub traction: super::traction::TractionState,
}

/// A vehicle system: the constant model. Its state vector is laid out by the system (see each
/// implementation); its run state is a [`VehicleData`] from [`VehicleModel::new_data`].
pub trait VehicleModel: Send + Sync {
    /// Number of states.
    fn dim(&self) -> usize;
    /// The wheelsets' names, in output order.
    fn wheelset_names(&self) -> Vec<String>;
    /// The rigid bodies' names, in output order (none on a single wheelset).
    fn body_names(&self) -> Vec<String>;
    /// The state at t = 0 with every wheelset disturbed by `initial`, rolling at the reference speed.
    fn initial_state(&self, initial: &InitialDisturbance) -> Vec<f64>;
    /// A fresh run state for one evaluator.
    fn new_data(&self) -> VehicleData;
    /// f(t, x) into `dxdt`.
    fn rhs(&self, data: &mut VehicleData, t: f64, x: &[f64], dxdt: &mut [f64]) -> Result<(), DynamicsError>;
    /// f(t, x) on at least the rows of `rows` (blocks (offset, size)); the other rows of `dxdt`
    /// are left as they are or filled. A finite-difference Jacobian pass reads only its blocks'
    /// rows ([`super::integrator::OdeSystem::rhs_rows`]). Default: the whole right-hand side.
    fn rhs_rows(
        &self,
        data: &mut VehicleData,
        t: f64,
        x: &[f64],
        dxdt: &mut [f64],
        rows: &[(usize, usize)],
    ) -> Result<(), DynamicsError> {
        let _ = rows;
        self.rhs(data, t, x, dxdt)
    }
    /// f(t, x) but for the wheelsets marked in `quiet` (one flag per wheelset), whose dynamics
    /// — the creep forces and the normal-force iteration — are not evaluated: their slots' rows of
    /// `dxdt` are unspecified (the BDF's Newton iteration carries them forward by their Jacobian,
    /// [`crate::dynamics::integrator::Settings::newton_reuse`]). Their kinematics are still
    /// solved: their poses load the elements. Default: the whole right-hand side, and
    /// [`Self::reuses_wheelsets`] false.
    fn rhs_reusing(
        &self,
        data: &mut VehicleData,
        t: f64,
        x: &[f64],
        dxdt: &mut [f64],
        quiet: &[bool],
    ) -> Result<(), DynamicsError> {
        let _ = quiet;
        self.rhs(data, t, x, dxdt)
    }
    /// Whether [`Self::rhs_reusing`] skips the quiet wheelsets' dynamics.
    fn reuses_wheelsets(&self) -> bool {
        false
    }
    /// Everything an evaluation at (t, x) knows, for output.
    fn sample(&self, data: &mut VehicleData, t: f64, x: &[f64]) -> Result<VehicleSample, DynamicsError>;
    /// The wheelsets' contact model.
    fn contact(&self) -> &dyn ContactModel;
    /// The wheels' nominal rolling radius r0, m (the output's z is the centre height minus r0).
    fn nominal_radius(&self) -> f64;
    /// The reference motion along the track.
    fn reference(&self) -> &Reference;
    /// The static settling behind the elements' preloads (multibody vehicles).
    fn settling(&self) -> Option<&Settling> {
        None
    }
    /// What drives the vehicle along the track, for the run's summary ([`super::traction`]).
    fn drive_info(&self) -> super::traction::DriveInfo;
    /// The carbodies' floor points where ride comfort is read (none without carbodies); each
    /// sample's [`VehicleSample::floor`] holds their accelerations in this order.
    fn floor_points(&self) -> Vec<FloorPoint> {
        Vec::new()
    }
    /// Per wheelset: its states (offset, count; see [`WheelsetState::read`]).
    fn wheelset_slots(&self) -> Vec<(usize, usize)>;
    /// Every state's name, "wheelset.state" or "body.state" (e.g. `w1.y_dot`, `c1.psi`): the
    /// wheelsets' slots by [`WheelsetState::slot_names`], the bodies' [`Self::kinematic_blocks`]
    /// as [x, y, z, φ, θ, ψ] in the track frame and their rates; any other state `x[i]`.
    fn state_names(&self) -> Vec<String> {
        let mut names: Vec<String> = (0..self.dim()).map(|i| format!("x[{i}]")).collect();
        for ((o, len), w) in self.wheelset_slots().into_iter().zip(self.wheelset_names()) {
            let slot = WheelsetState::slot_names(len == WheelsetState::slot_size(true));
            for (k, n) in slot.iter().enumerate().take(len) {
                if let Some(v) = names.get_mut(o + k) {
                    *v = format!("{w}.{n}");
                }
            }
        }
        const BODY: [&str; 12] = [
            "x",
            "y",
            "z",
            "phi",
            "theta",
            "psi",
            "x_dot",
            "y_dot",
            "z_dot",
            "phi_dot",
            "theta_dot",
            "psi_dot",
        ];
        for ((o, len), b) in self.kinematic_blocks().into_iter().zip(self.body_names()) {
            if len == BODY.len() {
                for (k, n) in BODY.iter().enumerate() {
                    if let Some(v) = names.get_mut(o + k) {
                        *v = format!("{b}.{n}");
                    }
                }
            }
        }
        names
    }
    /// Per rigid body: its states [q, q̇] (offset, 2 m), q̇ the derivative of q (none by default).
    fn kinematic_blocks(&self) -> Vec<(usize, usize)> {
        Vec::new()
    }
    /// The BDF's Newton matrix blocks by finite-difference pass ([`crate::dynamics::integrator::OdeSystem::newton_groups`]):
    /// by default the wheelsets' slots in one pass.
    fn newton_groups(&self) -> Vec<Vec<(usize, usize)>> {
        vec![self.wheelset_slots()]
    }
    /// Per wheelset: the index of its θ_l in the state (θ_r, θ̇_l, θ̇_r follow; see
    /// [`WheelsetState::read`]).
    fn lift_offsets(&self) -> Vec<usize>;
    /// Lands wheelset `wheelset`'s lifted wheel `side` (0 left, 1 right) at (t, x): the plastic
    /// impact of [`super::wheelset::land`], its velocities changed in `x`.
    fn land(
        &self,
        data: &mut VehicleData,
        t: f64,
        x: &mut [f64],
        wheelset: usize,
        side: usize,
    ) -> Result<Option<Landing>, DynamicsError>;
}

/// A landing that happened during a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LandingEvent {
    pub t: f64,
    pub wheelset: usize,
    pub landing: Landing,
}

/// A model with one evaluator's state: the [`crate::dynamics::integrator::OdeSystem`] an
/// integrator steps.
pub struct Evaluator<'a> {
    pub model: &'a dyn VehicleModel,
    pub data: VehicleData,
    /// The model's [`VehicleModel::lift_offsets`] (constant; read at every accepted step and
    /// every Jacobian column).
    lift_offsets: Vec<usize>,
}

impl<'a> Evaluator<'a> {
    /// An evaluator with a fresh run state.
    pub fn new(model: &'a dyn VehicleModel) -> Evaluator<'a> {
        Evaluator {
            data: model.new_data(),
            lift_offsets: model.lift_offsets(),
            model,
        }
    }

    /// The sample at (t, x).
    pub fn sample(&mut self, t: f64, x: &[f64]) -> Result<VehicleSample, DynamicsError> {
        self.model.sample(&mut self.data, t, x)
    }
}

impl super::integrator::OdeSystem for Evaluator<'_> {
    type Error = DynamicsError;

    fn dim(&self) -> usize {
        self.model.dim()
    }

    fn rhs(&mut self, t: f64, x: &[f64], dxdt: &mut [f64]) -> Result<(), DynamicsError> {
        self.model.rhs(&mut self.data, t, x, dxdt)
    }

    fn rhs_rows(
        &mut self,
        t: f64,
        x: &[f64],
        dxdt: &mut [f64],
        rows: &[(usize, usize)],
    ) -> Result<(), DynamicsError> {
        self.model.rhs_rows(&mut self.data, t, x, dxdt, rows)
    }

    fn rhs_reusing(
        &mut self,
        t: f64,
        x: &[f64],
        dxdt: &mut [f64],
        quiet: &[bool],
    ) -> Result<(), DynamicsError> {
        self.model.rhs_reusing(&mut self.data, t, x, dxdt, quiet)
    }

    /// The wheelsets' slots, where the model skips a quiet wheelset's dynamics
    /// ([`VehicleModel::reuses_wheelsets`]).
    fn reusable_blocks(&self) -> Vec<(usize, usize)> {
        if self.model.reuses_wheelsets() {
            self.model.wheelset_slots()
        } else {
            Vec::new()
        }
    }

    /// The W-method's blocks: each wheelset's states (the creep forces' stiff modes are the
    /// wheelsets' own; a wheelset's accelerations depend on its own states and the bodies', never
    /// on another wheelset's).
    fn jacobian_blocks(&self) -> Option<Vec<(usize, usize)>> {
        Some(self.model.wheelset_slots())
    }

    /// The bodies' [q, q̇] (the BDF's Newton matrix keeps their exact q̇ coupling).
    fn kinematic_blocks(&self) -> Vec<(usize, usize)> {
        self.model.kinematic_blocks()
    }

    /// The wheelsets' blocks, then the bogie frames' (differenced in passes of their own).
    fn newton_groups(&self) -> Option<Vec<Vec<(usize, usize)>>> {
        Some(self.model.newton_groups())
    }

    /// Two per wheelset: each wheel's lift θ (a lifted wheel lands where it passes zero).
    fn event_count(&self) -> usize {
        2 * self.lift_offsets.len()
    }

    fn events(&self, x: &[f64], g: &mut [f64]) {
        for (j, &o) in self.lift_offsets.iter().enumerate() {
            g[2 * j] = x[o];
            g[2 * j + 1] = x[o + 1];
        }
    }

    /// The lift states of a wheel on its rail (θ = θ̇ = 0) are left out of finite-difference
    /// Jacobians: a perturbation there would release the wheel (a switch, not a derivative).
    fn inactive(&self, x: &[f64], j: usize) -> bool {
        self.lift_offsets.iter().any(|&o| {
            (o..o + 4).contains(&j) && {
                let side = (j - o) % 2;
                x[o + side] == 0.0 && x[o + 2 + side] == 0.0
            }
        })
    }

    fn jump(&mut self, t: f64, event: usize, x: &mut [f64]) -> Result<(), DynamicsError> {
        let (wheelset, side) = (event / 2, event % 2);
        if let Some(landing) = self.model.land(&mut self.data, t, x, wheelset, side)? {
            self.data.landings.push(LandingEvent { t, wheelset, landing });
        }
        Ok(())
    }
}
