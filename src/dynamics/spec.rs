//! Scenario tables of the dynamics (`[simulation]`, `[vehicle]`), as written. Validated into a
//! run (`super::run::run`) by [`SimulationSpec::problems`] and the scene builder.

use serde::Deserialize;

use super::contact_model::ContactKind;
use super::integrator::{Method, Settings};

/// `[simulation]`: what to run and how.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SimulationSpec {
    /// `kec`, `lookup` or `online`.
    pub contact_model: ContactKind,
    /// Initial forward speed, m/s.
    pub speed_m_s: f64,
    /// Speed ramp, m/s² (0: constant speed).
    #[serde(default)]
    pub speed_ramp_m_s2: f64,
    /// Simulated time, s.
    pub duration_s: f64,
    /// Output (recording and CSV) rate, Hz.
    #[serde(default = "default_rate")]
    pub record_rate_hz: f64,
    #[serde(default)]
    pub integrator: IntegratorSpec,
    #[serde(default)]
    pub initial: InitialSpec,
    /// End the run (normally, with a note) when a wheelset's |y| exceeds this, m — e.g. to stop a
    /// speed ramp once hunting has set in, before flange contact.
    #[serde(default)]
    pub stop_lateral_m: Option<f64>,
    /// Arc length of the vehicle reference at t = 0, m (default: the rearmost body at the
    /// track's start).
    #[serde(default)]
    pub start_m: Option<f64>,
    /// KEC only: the elastic approach δ over which a real contact jump becomes a two-point
    /// transition (the equivalent profiles' kinks are rounded over δ / |Δ tan γ|), m;
    /// 0 keeps the paper's rigid kinks. See [`crate::contact::kec::KecModel::with_two_point_transition`].
    #[serde(default = "default_two_point_approach")]
    pub kec_two_point_approach_m: f64,
}

/// Default elastic approach of the two-point transition, m.
pub const DEFAULT_TWO_POINT_APPROACH_M: f64 = 5e-5;

fn default_two_point_approach() -> f64 {
    DEFAULT_TWO_POINT_APPROACH_M
}

fn default_rate() -> f64 {
    200.0
}

/// `[simulation.integrator]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IntegratorSpec {
    #[serde(default = "default_method")]
    pub method: Method,
    #[serde(default = "default_rtol")]
    pub rtol: f64,
    #[serde(default = "default_atol")]
    pub atol: f64,
    /// ros34pw2: accepted steps one Jacobian serves before it is evaluated again.
    #[serde(default = "default_jacobian_max_age")]
    pub jacobian_max_age: usize,
}

impl IntegratorSpec {
    /// The integrator settings this table describes.
    pub fn settings(&self) -> Settings {
        let mut s = Settings::new(self.method, self.rtol, self.atol);
        s.jacobian_max_age = self.jacobian_max_age;
        s
    }
}

fn default_method() -> Method {
    Method::Ros34pw2
}
fn default_rtol() -> f64 {
    1e-6
}
fn default_atol() -> f64 {
    1e-8
}
fn default_jacobian_max_age() -> usize {
    25
}

impl Default for IntegratorSpec {
    fn default() -> Self {
        IntegratorSpec {
            method: default_method(),
            rtol: default_rtol(),
            atol: default_atol(),
            jacobian_max_age: default_jacobian_max_age(),
        }
    }
}

/// `[simulation.initial]`: the disturbance the wheelsets start from.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InitialSpec {
    #[serde(default)]
    pub lateral_m: f64,
    #[serde(default)]
    pub yaw_rad: f64,
}

/// `[vehicle]`: the model of the scene. Each kind models only what the scene needs.
#[derive(Debug, Clone, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum VehicleSpec {
    /// One solid-axle wheelset tied by spring–dampers at its axle boxes to a frame moving at the
    /// reference speed, which also carries the axle load.
    WheelsetOnFrame(WheelsetOnFrameSpec),
    /// Rigid bodies, solid-axle wheelsets and force elements ([`crate::vehicle::spec`]): a bogie,
    /// a whole vehicle.
    Multibody(crate::vehicle::MultibodySpec),
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WheelsetOnFrameSpec {
    /// Vertical load of the frame on the wheelset (both boxes), N.
    pub axle_load_n: f64,
    pub wheelset: WheelsetSpec,
    pub tie: TieSpec,
}

/// Wheelset mass and principal inertias (roll, spin, yaw).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WheelsetSpec {
    pub mass_kg: f64,
    pub inertia_kg_m2: [f64; 3],
}

/// Axle-box tie (per box).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TieSpec {
    pub longitudinal_stiffness_n_per_m: f64,
    pub lateral_stiffness_n_per_m: f64,
    #[serde(default)]
    pub longitudinal_damping_n_s_per_m: f64,
    #[serde(default)]
    pub lateral_damping_n_s_per_m: f64,
    pub half_spacing_m: f64,
}

impl SimulationSpec {
    /// Problems with the values (empty when valid).
    pub fn problems(&self) -> Vec<String> {
        let mut p = Vec::new();
        let mut check = |name: &str, v: f64, lo: f64, hi: f64| {
            if !(v.is_finite() && v >= lo && v <= hi) {
                p.push(format!(
                    "simulation.{name} = {v}: expected a value in [{lo}, {hi}]"
                ));
            }
        };
        check("speed_m_s", self.speed_m_s, 0.0, 200.0);
        check("speed_ramp_m_s2", self.speed_ramp_m_s2, -20.0, 20.0);
        check("duration_s", self.duration_s, 1e-6, 1e5);
        check("record_rate_hz", self.record_rate_hz, 0.1, 1e5);
        check("integrator.rtol", self.integrator.rtol, 1e-14, 1e-1);
        check("integrator.atol", self.integrator.atol, 1e-16, 1e-1);
        check(
            "integrator.jacobian_max_age",
            self.integrator.jacobian_max_age as f64,
            1.0,
            1e6,
        );
        check(
            "kec_two_point_approach_m",
            self.kec_two_point_approach_m,
            0.0,
            1e-3,
        );
        check("initial.lateral_m", self.initial.lateral_m, -0.02, 0.02);
        check("initial.yaw_rad", self.initial.yaw_rad, -0.05, 0.05);
        if let Some(v) = self.start_m {
            check("start_m", v, -1e7, 1e7);
        }
        if let Some(v) = self.stop_lateral_m {
            check("stop_lateral_m", v, 1e-5, 0.05);
        }
        p
    }
}

impl VehicleSpec {
    pub fn problems(&self) -> Vec<String> {
        let mut p = Vec::new();
        match self {
            VehicleSpec::Multibody(m) => p.extend(m.problems()),
            VehicleSpec::WheelsetOnFrame(w) => {
                let mut check = |name: &str, v: f64, lo: f64, hi: f64| {
                    if !(v.is_finite() && v >= lo && v <= hi) {
                        p.push(format!("vehicle.{name} = {v}: expected a value in [{lo}, {hi}]"));
                    }
                };
                check("axle_load_n", w.axle_load_n, 0.0, 1e7);
                check("wheelset.mass_kg", w.wheelset.mass_kg, 1.0, 1e5);
                for (i, v) in w.wheelset.inertia_kg_m2.iter().enumerate() {
                    check(&format!("wheelset.inertia_kg_m2[{i}]"), *v, 1e-3, 1e6);
                }
                check(
                    "tie.longitudinal_stiffness_n_per_m",
                    w.tie.longitudinal_stiffness_n_per_m,
                    0.0,
                    1e10,
                );
                check(
                    "tie.lateral_stiffness_n_per_m",
                    w.tie.lateral_stiffness_n_per_m,
                    0.0,
                    1e10,
                );
                check(
                    "tie.longitudinal_damping_n_s_per_m",
                    w.tie.longitudinal_damping_n_s_per_m,
                    0.0,
                    1e8,
                );
                check(
                    "tie.lateral_damping_n_s_per_m",
                    w.tie.lateral_damping_n_s_per_m,
                    0.0,
                    1e8,
                );
                check("tie.half_spacing_m", w.tie.half_spacing_m, 0.1, 3.0);
            }
        }
        p
    }
}
