//! The `[simulation]` table, as written, and what it compiles into: the contact model, the
//! vehicle system (settled), the reference motion along the track and the run settings — the one
//! place where a scenario becomes the objects of a run ([`Scene::build_run`], the compiled
//! scenario's [`Scene`] defined here beside it).

use std::sync::Arc;
use std::time::Instant;

use serde::Deserialize;
use thiserror::Error;

use crate::contact::cache::TableCache;
use crate::contact::forces::ContactForceSettings;
use crate::contact::geometry::ContactGeometry;
use crate::contact::lookup::flange_angle;
use crate::contact::{ContactBuildError, ContactModel, ContactModelSpec};
use crate::dynamics::integrator::{Method, Settings};
use crate::dynamics::multibody::Multibody;
use crate::dynamics::output::RunObserver;
use crate::dynamics::reference::{Reference, SpeedProfile};
use crate::dynamics::safety::SafetyBasis;
use crate::dynamics::single_wheelset::{SingleWheelset, Tie};
use crate::dynamics::traction::{TractionLaw, DEFAULT_BANDWIDTH_HZ, MAX_BANDWIDTH_HZ};
use crate::dynamics::wheelset::WheelsetInertia;
use crate::dynamics::{
    run, CancelToken, DynamicsError, InitialDisturbance, RunLabels, RunOutput, RunPool, RunSettings,
    StopConditions, Threads, VehicleModel,
};
use crate::profile::placement::WheelRailPair;
use crate::track::{FrameModel, Track};
use crate::vehicle::VehicleSpec;

/// `[simulation]`: what to run and how.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SimulationSpec {
    /// `[simulation.contact]`: the contact model and its own settings (`model = "kec"`, …).
    #[serde(default)]
    pub contact: Option<ContactModelSpec>,
    /// The contact model by name alone (the form before `[simulation.contact]`; still read).
    #[serde(default)]
    pub contact_model: Option<String>,
    /// KEC's two-point approach beside `contact_model` (the earlier form of
    /// `[simulation.contact] two_point_approach_m`; still read), m.
    #[serde(default)]
    pub kec_two_point_approach_m: Option<f64>,
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
    /// The track frame's rotation and motion: `"whole"` (default: the exact rotation and the
    /// motion derived from it) or `"paper"` (Eq. 2 linearised, Eq. 3–4 as printed); see
    /// `crate::track::centreline`.
    #[serde(default)]
    pub track_frame: FrameModel,
    /// `[simulation.traction]`: what holds the vehicle's speed.
    #[serde(default)]
    pub traction: TractionSpec,
}

/// `[simulation.traction]`: what drives the vehicle along the track ([`crate::dynamics::traction`]).
///
/// ```toml
/// [simulation.traction]
/// mode = "hold_speed"   # default: a speed loop on the motored wheels holds V(t); or "coast", "force"
/// controller_hz = 0.2   # hold_speed: the loop's bandwidth (0.01 ≤ f ≤ 2 Hz; default 0.2)
/// max_force_n = 20e3    # hold_speed: the drive's limit (a demand beyond it ends the run)
/// # force_n = -5e3      # force: the given traction (> 0) or braking (< 0) force, N
/// ```
#[derive(Debug, Clone, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TractionSpec {
    #[serde(default)]
    pub mode: TractionMode,
    /// `mode = "force"`: the force through the driven wheels, N.
    #[serde(default)]
    pub force_n: Option<f64>,
    /// `mode = "hold_speed"`: the drive's largest force, N (none: unlimited).
    #[serde(default)]
    pub max_force_n: Option<f64>,
    /// `mode = "hold_speed"`: the speed loop's bandwidth, Hz (default 0.2).
    #[serde(default)]
    pub controller_hz: Option<f64>,
}

/// `[simulation.traction] mode`.
#[derive(Debug, Clone, Copy, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum TractionMode {
    /// The speed held at the reference's V(t) by a speed loop on the motored wheels (a vehicle
    /// tied to the track frame: by its tie).
    #[default]
    HoldSpeed,
    /// No drive: the vehicle rolls on, slowed by its resistance (the behaviour before issue 46).
    Coast,
    /// A given force through the motored wheels (`force_n`).
    Force,
}

impl TractionMode {
    /// Its name in a scenario.
    pub fn name(self) -> &'static str {
        match self {
            TractionMode::HoldSpeed => "hold_speed",
            TractionMode::Coast => "coast",
            TractionMode::Force => "force",
        }
    }
}

impl TractionSpec {
    /// Problems with the values (each naming its key).
    pub fn problems(&self) -> Vec<String> {
        let mut p = Vec::new();
        let mode = self.mode.name();
        let not_with = |key: &str, given: bool, modes: &str, p: &mut Vec<String>| {
            if given {
                p.push(format!(
                    "simulation.traction.{key}: only with mode = {modes} (the scene's mode is \"{mode}\")"
                ));
            }
        };
        match self.mode {
            TractionMode::Force => match self.force_n {
                None => p.push(
                    "simulation.traction.mode = \"force\" needs force_n (N: traction > 0, braking < 0)"
                        .to_string(),
                ),
                Some(f) if !(f.is_finite() && f.abs() <= 1e7) => p.push(format!(
                    "simulation.traction.force_n = {f}: expected a force in [-1e7, 1e7] N"
                )),
                Some(_) => {}
            },
            _ => not_with("force_n", self.force_n.is_some(), "\"force\"", &mut p),
        }
        if self.mode == TractionMode::HoldSpeed {
            if let Some(f) = self.max_force_n {
                if !(f.is_finite() && f > 0.0) {
                    p.push(format!(
                        "simulation.traction.max_force_n = {f}: expected a force > 0 N (the drive's limit, traction and braking)"
                    ));
                }
            }
            if let Some(h) = self.controller_hz {
                if !(h.is_finite() && (MIN_BANDWIDTH_HZ..=MAX_BANDWIDTH_HZ).contains(&h)) {
                    p.push(format!(
                        "simulation.traction.controller_hz = {h:?}: expected a bandwidth in [{MIN_BANDWIDTH_HZ}, {MAX_BANDWIDTH_HZ}] Hz — below {MIN_BANDWIDTH_HZ} Hz the loop takes minutes to correct the speed, which is then not held at all; above {MAX_BANDWIDTH_HZ} Hz the traction chases the bogies' vibration, then costs steps, and at hundreds of Hz it meets the wheels' spin–creep dynamics and goes unstable; 0.1–1 Hz holds the speed within 0.02 %"
                    ));
                }
            }
        } else {
            not_with(
                "max_force_n",
                self.max_force_n.is_some(),
                "\"hold_speed\"",
                &mut p,
            );
            not_with(
                "controller_hz",
                self.controller_hz.is_some(),
                "\"hold_speed\"",
                &mut p,
            );
        }
        p
    }
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
    /// ros34pw2, bdf, radau5: accepted steps one Jacobian serves at most before it is evaluated
    /// again (earlier where the method asks for it).
    #[serde(default = "default_jacobian_max_age")]
    pub jacobian_max_age: usize,
    /// bdf: the highest order (1–5; default 5). Given with another method, which has no order to
    /// limit, it is refused.
    #[serde(default)]
    pub max_order: Option<usize>,
    /// bdf: the Newton iteration's stopping tolerance, as a fraction of the local error
    /// tolerance (0.01–1; default 0.1, CVODE's). Given with another method, it is refused.
    #[serde(default)]
    pub newton_tolerance: Option<f64>,
    /// bdf: Newton iterations after the first skip the dynamics (creep forces, normal forces) of
    /// the wheelsets whose last correction is below this fraction of the Newton tolerance,
    /// carrying their rows forward by their Jacobian (0–10; default 0: never). Measured on the
    /// kilometre (docs/performance.md, *Measured and not built*): no gain in wall time, so off by
    /// default. Given with another method, it is refused.
    #[serde(default)]
    pub newton_reuse: Option<f64>,
}

impl IntegratorSpec {
    /// The integrator settings this table describes.
    pub fn settings(&self) -> Settings {
        let mut s = Settings::new(self.method, self.rtol, self.atol);
        s.jacobian_max_age = self.jacobian_max_age;
        s.bdf_max_order = self.max_order.unwrap_or(DEFAULT_BDF_MAX_ORDER);
        s.newton_tolerance = self
            .newton_tolerance
            .unwrap_or(crate::dynamics::integrator::NEWTON_TOLERANCE);
        s.newton_reuse = self.newton_reuse.unwrap_or(0.0);
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
/// Output samples farther apart along the track than this are doubtful, m: the safety figures'
/// 2 m sliding means need at least two samples per mean.
pub const MAX_SAMPLE_SPACING_M: f64 = 1.0;

/// BDF's highest order where `max_order` is not given.
const DEFAULT_BDF_MAX_ORDER: usize = 5;

impl Default for IntegratorSpec {
    fn default() -> Self {
        IntegratorSpec {
            method: default_method(),
            rtol: default_rtol(),
            atol: default_atol(),
            jacobian_max_age: default_jacobian_max_age(),
            max_order: None,
            newton_tolerance: None,
            newton_reuse: None,
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
    /// Lateral velocity ẏ of every wheelset (and body), m/s.
    #[serde(default)]
    pub lateral_velocity_m_s: f64,
}

impl SimulationSpec {
    /// The contact model: `[simulation.contact]`, else `contact_model` (with
    /// `kec_two_point_approach_m`), else KEC with its defaults.
    pub fn contact_spec(&self) -> Result<ContactModelSpec, ContactChoiceError> {
        match (&self.contact, &self.contact_model, self.kec_two_point_approach_m) {
            (Some(c), None, None) => Ok(c.clone()),
            (Some(_), _, _) => Err(ContactChoiceError::Both),
            (None, name, approach) => {
                let name = name.as_deref().unwrap_or("kec");
                let mut spec = ContactModelSpec::default_for(name).ok_or_else(|| {
                    ContactChoiceError::UnknownInScenario {
                        name: name.to_string(),
                    }
                })?;
                if let (ContactModelSpec::Kec(k), Some(a)) = (&mut spec, approach) {
                    k.two_point_approach_m = a;
                }
                Ok(spec)
            }
        }
    }

    /// The contact model `name` (the command line's `--contact`): the scenario's own settings when
    /// it names the same model, else that model's defaults with the scenario's treatment of the
    /// contact jumps carried over — its two-point transitions ([`ContactModelSpec::with_two_point`];
    /// KEC's legacy `kec_two_point_approach_m` counts as the scenario's), so that the models are
    /// compared on the same physics. The notes say what was carried and what a model cannot honour.
    pub fn contact_spec_for(
        &self,
        name: &str,
    ) -> Result<(ContactModelSpec, Vec<String>), ContactChoiceError> {
        let own = self.contact_spec()?;
        if own.name() == name {
            return Ok((own, Vec::new()));
        }
        let spec = ContactModelSpec::default_for(name).ok_or_else(|| ContactChoiceError::Unknown {
            name: name.to_string(),
        })?;
        let mut notes = Vec::new();
        // KEC's legacy key names KEC's approach whatever the scenario's model.
        let legacy = self.kec_two_point_approach_m.filter(|_| name == "kec");
        let Some(tp) = own
            .two_point()
            .or(legacy.zip(spec.two_point()).map(|(a, (_, w))| (a, w)))
        else {
            return Ok((spec, notes));
        };
        let tp = (legacy.unwrap_or(tp.0), tp.1);
        let default_tp = spec.two_point();
        match spec.clone().with_two_point(tp) {
            Ok(carried) => {
                if default_tp != Some(tp) {
                    notes.push(format!(
                        "--contact {name}: the scenario's two-point transitions ({}: approach {} m, width {} m) carried over, so that {name} runs the same physics",
                        own.name(),
                        tp.0,
                        tp.1
                    ));
                }
                Ok((carried, notes))
            }
            Err(why) => {
                notes.push(format!(
                    "--contact {name}: the scenario's two-point transitions ({}: approach {} m) do not apply: {why}",
                    own.name(),
                    tp.0
                ));
                Ok((spec, notes))
            }
        }
    }

    /// Physically doubtful but possible values (warnings, each naming its key): output samples
    /// too far apart along the track for the safety figures, whose 2 m sliding means (EN 14363)
    /// need several samples per 2 m.
    pub fn doubtful(&self) -> Vec<String> {
        let mut w = Vec::new();
        let v_max = self
            .speed_m_s
            .max(self.speed_m_s + self.speed_ramp_m_s2 * self.duration_s)
            .max(0.0);
        let spacing = v_max / self.record_rate_hz;
        if spacing.is_finite() && spacing > MAX_SAMPLE_SPACING_M {
            w.push(format!(
                "simulation.record_rate_hz = {}: samples {spacing:.2} m apart at {v_max} m/s, so the maxima and the 2 m sliding means of the safety figures come from a few samples; {:.0} Hz or more gives them ≤ {MAX_SAMPLE_SPACING_M} m apart",
                self.record_rate_hz,
                (v_max / MAX_SAMPLE_SPACING_M).ceil()
            ));
        }
        w
    }

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
        check("speed_m_s", self.speed_m_s, 0.0, MAX_SPEED_M_S);
        check("speed_ramp_m_s2", self.speed_ramp_m_s2, -20.0, 20.0);
        check("duration_s", self.duration_s, 1e-6, 1e5);
        // 10 kHz: samples 2 mm apart at 20 m/s; 1e5 Hz made the recording the run's cost (0.05× real time).
        check("record_rate_hz", self.record_rate_hz, 0.1, 1e4);
        check("integrator.rtol", self.integrator.rtol, 1e-14, 1e-1);
        check("integrator.atol", self.integrator.atol, 1e-16, 1e-1);
        check(
            "integrator.jacobian_max_age",
            self.integrator.jacobian_max_age as f64,
            1.0,
            1e6,
        );
        let mut late = Vec::new();
        if let Some(o) = self.integrator.max_order {
            check("integrator.max_order", o as f64, 1.0, 5.0);
            if self.integrator.method != Method::Bdf {
                late.push(format!(
                    "simulation.integrator.max_order = {o}: only method = \"bdf\" has an order to limit; method = \"{}\" would ignore it",
                    self.integrator.method.name()
                ));
            }
        }
        // The BDF's Newton settings: each in its range, and refused with another method.
        for (key, value, lo, hi) in [
            ("newton_tolerance", self.integrator.newton_tolerance, 0.01, 1.0),
            ("newton_reuse", self.integrator.newton_reuse, 0.0, 10.0),
        ] {
            let Some(k) = value else { continue };
            check(&format!("integrator.{key}"), k, lo, hi);
            if self.integrator.method != Method::Bdf {
                late.push(format!(
                    "simulation.integrator.{key} = {k}: only method = \"bdf\" takes it; method = \"{}\" would ignore it",
                    self.integrator.method.name()
                ));
            }
        }
        if let Some(a) = self.kec_two_point_approach_m {
            check("kec_two_point_approach_m", a, 0.0, 1e-3);
        }
        check("initial.lateral_m", self.initial.lateral_m, -0.02, 0.02);
        check("initial.yaw_rad", self.initial.yaw_rad, -0.05, 0.05);
        check(
            "initial.lateral_velocity_m_s",
            self.initial.lateral_velocity_m_s,
            -2.0,
            2.0,
        );
        if let Some(v) = self.start_m {
            check("start_m", v, -1e7, 1e7);
        }
        if let Some(v) = self.stop_lateral_m {
            check("stop_lateral_m", v, 1e-5, 0.05);
        }
        match self.contact_spec() {
            Ok(c) => p.extend(c.problems()),
            Err(e) => p.push(e.to_string()),
        }
        p.extend(self.traction.problems());
        // The ramp's end: the same limit as the speed's.
        let end = self.speed_m_s + self.speed_ramp_m_s2 * self.duration_s;
        if self.speed_ramp_m_s2 > 0.0 && end.is_finite() && end > MAX_SPEED_M_S {
            p.push(format!(
                "simulation.speed_ramp_m_s2 = {}: from speed_m_s = {} over duration_s = {} the speed reaches {end} m/s, beyond the {MAX_SPEED_M_S} m/s limit of speed_m_s: at most {} m/s² over this duration",
                self.speed_ramp_m_s2,
                self.speed_m_s,
                self.duration_s,
                (MAX_SPEED_M_S - self.speed_m_s) / self.duration_s
            ));
        }
        if self.speed_ramp_m_s2 != 0.0 && self.traction.mode != TractionMode::HoldSpeed {
            p.push(format!(
                "simulation.speed_ramp_m_s2 = {} with simulation.traction.mode = \"{}\": only a held speed follows a ramp (mode = \"hold_speed\"); a vehicle that coasts or is driven by a given force goes at its own speed",
                self.speed_ramp_m_s2,
                self.traction.mode.name()
            ));
        }
        p.extend(late);
        p
    }

    /// The run settings of this table for scene `scene`.
    pub fn run_settings(&self, scene: &str) -> RunSettings {
        RunSettings {
            scene: scene.to_string(),
            duration_s: self.duration_s,
            record_rate_hz: self.record_rate_hz,
            integrator: self.integrator.settings(),
            initial: InitialDisturbance {
                lateral_m: self.initial.lateral_m,
                yaw_rad: self.initial.yaw_rad,
                lateral_velocity_m_s: self.initial.lateral_velocity_m_s,
            },
            stop: StopConditions {
                lateral_m: self.stop_lateral_m,
            },
            pool: RunPool::default(),
            patches: None,
        }
    }
}

/// A scenario ready to run: profiles loaded and placed, the track built if it has sections.
#[derive(Debug, Clone)]
pub struct Scene {
    pub name: String,
    /// Where it came from (its file, or `<embedded default>`), for errors.
    pub origin: String,
    pub pair: WheelRailPair,
    pub contact_forces: ContactForceSettings,
    /// `[contact_forces] patches`: where the strip model replaces Hertz.
    pub patches: crate::contact::nonhertz::PatchesMode,
    pub track: Option<Arc<Track>>,
    /// The simulation and its vehicle, when the scenario has both.
    pub simulation: Option<(SimulationSpec, VehicleSpec)>,
    /// Physically doubtful but possible values, each naming its key (the run goes on; the command
    /// prints them and the JSON summary carries them).
    pub warnings: Vec<String>,
    /// Where the contact models' tables are cached between runs (None: built every time; the
    /// command line sets it, see [`crate::contact::cache`]).
    pub table_cache: Option<TableCache>,
    /// The files the scenario named and its compile read (profile files, a measured irregularity
    /// file; not the scenario file itself): inputs no output may overwrite
    /// ([`crate::files::OutputGuard`]).
    pub inputs: Vec<std::path::PathBuf>,
}

/// Options of a run beyond its scenario (the command line's `--contact`, `--speed`), and what the
/// program around it decides: its threads and the request that stops it.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RunOptions {
    /// A contact model by name, overriding the scenario's.
    pub contact: Option<String>,
    /// The initial speed, m/s, overriding the scenario's.
    pub speed_m_s: Option<f64>,
    /// The threads of the preprocessing and the run (the pool is made by the build and kept in
    /// the run's settings, [`RunSettings::pool`]).
    pub threads: Threads,
    /// Stops the run at its next step when asked (the binary's Ctrl-C; kept in the integrator
    /// settings, [`Settings::cancel`]).
    pub cancel: CancelToken,
}

/// Why the scenario's contact model, or the one asked for instead, cannot be taken.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ContactChoiceError {
    /// `[simulation.contact]` and the older `contact_model` keys together.
    #[error("simulation: give the contact model either in [simulation.contact] or as contact_model (and kec_two_point_approach_m), not both")]
    Both,
    /// `contact_model = "…"` names no model.
    #[error("simulation.contact_model = \"{name}\": expected one of {}", ContactModelSpec::NAMES.join(", "))]
    UnknownInScenario { name: String },
    /// The model asked for (`--contact`) names no model.
    #[error("unknown contact model \"{name}\": expected one of {}", ContactModelSpec::NAMES.join(", "))]
    Unknown { name: String },
}

/// Why the objects of a run could not be built.
#[derive(Debug, Error)]
pub enum BuildError {
    #[error("this scenario has no [simulation] (and [vehicle]) to run")]
    NoSimulation,
    #[error(transparent)]
    ContactChoice(#[from] ContactChoiceError),
    /// The initial speed asked for (`--speed`) is out of range.
    #[error("--speed {speed}: expected 0 ..= 200 m/s")]
    Speed { speed: f64 },
    /// The run does not fit its track or the resource limits (each problem names its key).
    #[error("{}", problems.join("; "))]
    Extent { problems: Vec<String> },
    /// A comparison of fewer than two contact models.
    #[error("a comparison needs at least two contact models, got {got}")]
    TooFewModels { got: usize },
    /// The contact model could not be built for the scene from the file named first, on the
    /// profiles named last (what to check: the files and their placement).
    #[error("{scene}: {source} (the profiles: {profiles})")]
    Contact {
        scene: String,
        source: ContactBuildError,
        /// `wheel FILE, rail FILE`.
        profiles: String,
    },
    #[error("vehicle: {0}")]
    Vehicle(#[from] DynamicsError),
    /// The traction law does not fit the vehicle (names the key).
    #[error("{problem}")]
    Traction { problem: String },
}

/// The objects of one run: the vehicle system (with its contact model and reference motion), the
/// run settings and the labels of its summary.
pub struct BuiltRun {
    pub vehicle: Box<dyn VehicleModel>,
    pub settings: RunSettings,
    pub labels: RunLabels,
    /// The contact model's settings.
    pub contact: ContactModelSpec,
    /// What the build says about the settings it took (a scenario's two-point transitions carried
    /// to another model, or not honoured by it): to print as warnings.
    pub notes: Vec<String>,
}

impl BuiltRun {
    /// Runs it (see [`crate::dynamics::run::run`]), in its settings' pool.
    pub fn run(&self, observers: &mut [&mut (dyn RunObserver + Send)]) -> RunOutput {
        run(self.vehicle.as_ref(), &self.settings, &self.labels, observers)
    }
}

/// Contact preprocessing shared between runs ([`Scene::build_run_cached`]): each entry a built
/// contact model and its pair's flange angle, keyed by the contact settings and the placed pair.
#[derive(Debug, Default)]
pub struct PreprocessingCache {
    entries: std::sync::Mutex<Vec<CachedContact>>,
}

/// A cache entry: key, model, flange angle.
type CachedContact = (String, Arc<dyn ContactModel>, Option<f64>);

impl PreprocessingCache {
    fn get(&self, key: &str) -> Option<(Arc<dyn ContactModel>, Option<f64>)> {
        let e = self.entries.lock().ok()?;
        e.iter().find(|x| x.0 == key).map(|x| (x.1.clone(), x.2))
    }
    fn put(&self, key: String, model: Arc<dyn ContactModel>, angle: Option<f64>) {
        if let Ok(mut e) = self.entries.lock() {
            if !e.iter().any(|x| x.0 == key) {
                e.push((key, model, angle));
            }
        }
    }
}

/// The vehicle system of a `[vehicle]` table with `contact`, `forces` and the reference motion
/// (a multibody vehicle is settled here: its elements' static preloads).
pub fn build_vehicle(
    spec: &VehicleSpec,
    contact: Arc<dyn ContactModel>,
    forces: &ContactForceSettings,
    r0: f64,
    reference: Reference,
    traction: &TractionSpec,
) -> Result<Box<dyn VehicleModel>, BuildError> {
    if matches!(spec, VehicleSpec::WheelsetOnFrame(_)) && traction.mode != TractionMode::HoldSpeed {
        return Err(BuildError::Traction {
            problem: format!(
                "simulation.traction.mode = \"{}\": a wheelset-on-frame vehicle runs tied to its frame, which moves at the reference speed (the tie's longitudinal force is the traction): only \"hold_speed\" applies",
                traction.mode.name()
            ),
        });
    }
    Ok(match spec {
        VehicleSpec::WheelsetOnFrame(w) => Box::new(SingleWheelset {
            name: crate::vehicle::spec::SINGLE_WHEELSET_NAME.to_string(),
            inertia: WheelsetInertia {
                mass_kg: w.wheelset.mass_kg,
                inertia_kg_m2: w.wheelset.inertia_kg_m2,
                irw: None,
            },
            tie: Tie {
                longitudinal_stiffness_n_per_m: w.tie.longitudinal_stiffness_n_per_m,
                lateral_stiffness_n_per_m: w.tie.lateral_stiffness_n_per_m,
                longitudinal_damping_n_s_per_m: w.tie.longitudinal_damping_n_s_per_m,
                lateral_damping_n_s_per_m: w.tie.lateral_damping_n_s_per_m,
                half_spacing_m: w.tie.half_spacing_m,
            },
            axle_load_n: w.axle_load_n,
            contact,
            forces: forces.clone(),
            r0,
            reference,
        }),
        VehicleSpec::Multibody(m) => {
            let mut sys = Multibody::new(m, contact, forces.clone(), r0, reference)?;
            let law = match traction.mode {
                TractionMode::HoldSpeed => TractionLaw::HoldSpeed(sys.speed_loop(
                    traction.controller_hz.unwrap_or(DEFAULT_BANDWIDTH_HZ),
                    traction.max_force_n,
                )),
                TractionMode::Coast => TractionLaw::Coast,
                TractionMode::Force => TractionLaw::Force {
                    force_n: traction.force_n.unwrap_or(0.0),
                },
            };
            sys.set_traction(law).map_err(|e| BuildError::Traction {
                problem: format!("simulation.traction.mode = \"{}\": {e}", traction.mode.name()),
            })?;
            // A given force beyond adhesion cannot reach the rails: the wheels spin or slide (1e7 N
            // ran into a 5 mm wheel lift reported as a derailment).
            if let (TractionMode::Force, Some(f)) = (traction.mode, traction.force_n) {
                let (load, names) = sys.driven_load();
                let limit = forces.friction * load;
                if load > 0.0 && f.abs() > limit {
                    return Err(BuildError::Traction {
                        problem: format!(
                            "simulation.traction.force_n = {f} N: beyond what adhesion can transmit, μ × the settled load on the driven wheelsets ({}) = {} × {:.1} kN = {:.1} kN; the wheels would spin or slide: expected |force_n| ≤ {:.0} N",
                            names.join(", "),
                            forces.friction,
                            load * 1e-3,
                            limit * 1e-3,
                            limit.floor()
                        ),
                    });
                }
            }
            Box::new(sys)
        }
    })
}

/// The reference motion of a scene: its track, the speed profile, and the start: `start_m`, else
/// the rearmost body at the track's start, else 0.
pub fn reference(
    sim: &SimulationSpec,
    vehicle: &VehicleSpec,
    track: Option<Arc<crate::track::Track>>,
    speed_m_s: f64,
) -> Reference {
    let mut s0 = 0.0;
    if let Some(t) = &track {
        s0 = t.centreline.range().0 - vehicle.rear_offset_m();
    }
    if let Some(s) = sim.start_m {
        s0 = s;
    }
    Reference {
        track,
        s0,
        speed: SpeedProfile {
            initial_m_s: speed_m_s,
            ramp_m_s2: sim.speed_ramp_m_s2,
        },
        frame_model: sim.track_frame,
    }
}

/// The highest speed of a run, m/s (`speed_m_s`, and the end of a speed ramp).
pub const MAX_SPEED_M_S: f64 = 200.0;

/// The lowest bandwidth of the speed loop, Hz (`controller_hz`): a time constant of 16 s.
pub const MIN_BANDWIDTH_HZ: f64 = 0.01;

/// The lowest held speed of a run, m/s (1 cm/s; a start from standstill is speed 0 with a
/// positive ramp): below it the vehicle does not roll over the run (1e-9 m/s was accepted while
/// 0 was refused).
pub const MIN_ROLLING_SPEED_M_S: f64 = 0.01;

/// What a run of `sim` on `reference` would do that it cannot: brake to a standstill (the
/// creepages need a rolling speed), leave the track, or record more samples than
/// [`crate::limits::MAX_RUN_SAMPLES`] — found before any work, with the value to change.
pub fn run_extent_problems(
    sim: &SimulationSpec,
    vehicle: &VehicleSpec,
    reference: &Reference,
) -> Vec<String> {
    let mut p = Vec::new();
    let d = sim.duration_s;
    let speed = reference.speed;
    if speed.initial_m_s <= 0.0 && speed.ramp_m_s2 <= 0.0 {
        p.push(format!(
            "simulation: speed {} m/s with ramp {} m/s² never moves the vehicle (the creepages need a rolling speed)",
            speed.initial_m_s, speed.ramp_m_s2
        ));
    } else if speed.initial_m_s < MIN_ROLLING_SPEED_M_S && speed.ramp_m_s2 <= 0.0 {
        p.push(format!(
            "simulation.speed_m_s = {}: below {MIN_ROLLING_SPEED_M_S} m/s with ramp {} m/s² the vehicle does not roll ({:.3e} m over the run; as 0 m/s is refused, so is this): a speed in m/s, or a start from standstill with speed_m_s = 0 and a positive speed_ramp_m_s2",
            speed.initial_m_s,
            speed.ramp_m_s2,
            speed.initial_m_s * d
        ));
    } else if let Some(ts) = speed.stop_time().filter(|&ts| ts < d) {
        p.push(format!(
            "simulation: the speed ramp {} m/s² brings the vehicle from {} m/s to a standstill at t = {ts:.3} s, within duration_s = {d} s (the creepages need a rolling speed): end the run before it (duration_s < {ts:.3}) or brake less",
            speed.ramp_m_s2, speed.initial_m_s
        ));
    }
    if let Some(track) = &reference.track {
        let (start, end) = track.centreline.range();
        let rear = reference.s0 + vehicle.rear_offset_m();
        if rear < start {
            p.push(format!(
                "simulation.start_m = {}: the vehicle's rearmost body or wheelset starts at s = {rear:.3} m, before the track's start (s = {start} m); start_m ≥ {:.3}",
                reference.s0,
                start - vehicle.rear_offset_m()
            ));
        }
        let front = reference.s0 + vehicle.front_offset_m();
        let travel = speed.distance(d);
        if front > end {
            p.push(format!(
                "simulation.start_m = {}: the vehicle's front starts at s = {front:.3} m, beyond the track's end (s = {end} m)",
                reference.s0
            ));
        } else if front + travel > end {
            // Time at which the front reaches the end: v t + a t²/2 = end − front.
            let room = (end - front).max(0.0);
            let (v, a) = (speed.initial_m_s, speed.ramp_m_s2);
            let t_end = if a.abs() < 1e-12 {
                room / v.max(1e-12)
            } else {
                (-v + (v * v + 2.0 * a * room).max(0.0).sqrt()) / a
            };
            p.push(format!(
                "simulation: the vehicle's front reaches the end of the track (s = {end:.1} m) at t = {t_end:.3} s, within duration_s = {d} s: shorten duration_s to at most {:.3} s, or lengthen the track",
                t_end
            ));
        }
    }
    let rows = d * sim.record_rate_hz * vehicle.wheelset_count() as f64;
    if let Err(e) = crate::limits::check(
        "output samples (duration_s × record_rate_hz × wheelsets)",
        rows,
        crate::limits::MAX_RUN_SAMPLES,
        "lower record_rate_hz or duration_s",
    ) {
        p.push(format!("simulation: {e}"));
    }
    p
}

/// Static wheel load per wheel diameter above which a wheel is doubtful, N/m (0.2 kN/mm; the
/// railways' permissible static wheel loads stay near 0.12 kN/mm, e.g. 112.5 kN on a 920 mm
/// wheel).
pub const DOUBTFUL_WHEEL_LOAD_PER_DIAMETER: f64 = 2e5;

/// Warnings for wheels loaded beyond what their diameter carries (Q₀ = half the static axle load,
/// D = 2 r0): a radius typed in the wrong unit, or a load of another vehicle.
fn wheel_load_notes(axle_loads: &[f64], wheelsets: &[String], r0: f64) -> Vec<String> {
    axle_loads
        .iter()
        .zip(wheelsets)
        .filter_map(|(&q, name)| {
            let per_d = 0.5 * q / (2.0 * r0);
            (per_d > DOUBTFUL_WHEEL_LOAD_PER_DIAMETER).then(|| {
                format!(
                    "{name}: a static wheel load of {:.1} kN on wheels of {:.0} mm diameter ({:.2} kN/mm; permissible wheel loads stay near 0.12 kN/mm): is wheelset.nominal_radius_m = {r0} right?",
                    0.5 * q * 1e-3,
                    2e3 * r0,
                    per_d * 1e-6
                )
            })
        })
        .collect()
}

impl Scene {
    /// Builds the objects of the scene's run with `options` (contact model, vehicle system with
    /// its static settling, reference, settings) — the preprocessing, timed.
    pub fn build_run(&self, options: &RunOptions) -> Result<BuiltRun, BuildError> {
        self.build_run_cached(options, None)
    }

    /// [`Self::build_run`], taking the contact preprocessing (the model's tables and profiles,
    /// the flange angle) from `cache` where an earlier run built it for the same profiles, placement
    /// and contact settings — a study's cases that vary only the speed or the track share it.
    /// A history-dependent model (its warm starts are the evaluators', but to be safe) is not
    /// shared.
    pub fn build_run_cached(
        &self,
        options: &RunOptions,
        cache: Option<&PreprocessingCache>,
    ) -> Result<BuiltRun, BuildError> {
        let (sim, vehicle) = self.simulation.as_ref().ok_or(BuildError::NoSimulation)?;
        let (contact, notes) = match &options.contact {
            Some(name) => sim.contact_spec_for(name),
            None => sim.contact_spec().map(|c| (c, Vec::new())),
        }?;
        let speed = options.speed_m_s.unwrap_or(sim.speed_m_s);
        if !(speed.is_finite() && (0.0..=200.0).contains(&speed)) {
            return Err(BuildError::Speed { speed });
        }
        let reference = reference(sim, vehicle, self.track.clone(), speed);
        let problems = run_extent_problems(sim, vehicle, &reference);
        if !problems.is_empty() {
            return Err(BuildError::Extent { problems });
        }
        // The preprocessing and the run share one pool (the tables' searches and the right-hand
        // sides' wheelsets split between its threads).
        let pool = RunPool::new(options.threads);
        pool.install(|| self.build_in_pool(sim, vehicle, options, cache, contact, notes, reference))
            .map(|mut built| {
                built.settings.pool = pool.clone();
                built
            })
    }

    /// [`Self::build_run_cached`] from the contact model on, inside the run's pool.
    #[allow(clippy::too_many_arguments)]
    fn build_in_pool(
        &self,
        sim: &SimulationSpec,
        vehicle: &VehicleSpec,
        options: &RunOptions,
        cache: Option<&PreprocessingCache>,
        contact: ContactModelSpec,
        notes: Vec<String>,
        reference: Reference,
    ) -> Result<BuiltRun, BuildError> {
        let t = Instant::now();
        let key = format!("{contact:?}|{:?}", self.pair);
        let (model, flange_angle_rad) = match cache.and_then(|c| c.get(&key)) {
            Some(hit) => hit,
            None => {
                let model = contact
                    .build(&self.pair, self.table_cache.as_ref())
                    .map_err(|source| BuildError::Contact {
                        scene: self.origin.clone(),
                        source,
                        profiles: format!("wheel {}, rail {}", self.pair.wheel.source, self.pair.rail.source),
                    })?;
                // The safety figures' flange angle; a pair whose contact cannot be followed up
                // the flange on the ideal track runs without them.
                let geom = ContactGeometry::with_defaults(self.pair.clone());
                let angle = match &self.table_cache {
                    Some(c) => c.flange_angle(&geom).map(|(a, _)| a),
                    None => flange_angle(&geom),
                }
                .ok();
                if let Some(c) = cache.filter(|_| !model.history_dependent()) {
                    c.put(key, model.clone(), angle);
                }
                (model, angle)
            }
        };
        let spec = vehicle;
        let vehicle = build_vehicle(
            spec,
            model,
            &self.contact_forces,
            self.pair.wheelset.nominal_radius_m,
            reference,
            &sim.traction,
        )?;
        let mut notes = notes;
        // The cache files found implausible and rebuilt (which file, why).
        notes.extend(self.table_cache.iter().flat_map(|c| c.take_notes()));
        let axle_loads: Vec<f64> = match (vehicle.settling(), spec) {
            (Some(st), _) => st.axle_loads.clone(),
            // The carried load and the wheelset's own weight.
            (None, VehicleSpec::WheelsetOnFrame(f)) => {
                vec![f.axle_load_n + f.wheelset.mass_kg * crate::dynamics::reference::G]
            }
            _ => Vec::new(),
        };
        notes.extend(wheel_load_notes(
            &axle_loads,
            &vehicle.wheelset_names(),
            self.pair.wheelset.nominal_radius_m,
        ));
        let mut settings = sim.run_settings(&self.name);
        settings.integrator.cancel = options.cancel.clone();
        settings.patches = Some(std::sync::Arc::new(crate::dynamics::patches::PatchPostProcess {
            recompute: self.patches != crate::contact::nonhertz::PatchesMode::Hertz,
            ..crate::dynamics::patches::PatchPostProcess::new(self.pair.clone(), self.contact_forces.material)
        }));
        Ok(BuiltRun {
            vehicle,
            settings,
            labels: RunLabels {
                contact_model: contact.name().to_string(),
                creep_model: self.contact_forces.model.name().to_string(),
                preprocessing_s: t.elapsed().as_secs_f64(),
                safety: flange_angle_rad.map(|flange_angle_rad| SafetyBasis {
                    friction: self.contact_forces.friction,
                    flange_angle_rad,
                }),
                spin_basis: Some(crate::dynamics::run::SpinBasis {
                    shear_modulus: self.contact_forces.material.shear_modulus(),
                    friction: self.contact_forces.friction,
                    kalker: self.contact_forces.kalker.clone(),
                }),
            },
            contact,
            notes,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::models::kec::KecSettings;

    fn spec(extra: &str) -> Result<SimulationSpec, toml::de::Error> {
        toml::from_str(&format!("speed_m_s = 19.0\nduration_s = 1.0\n{extra}"))
    }

    /// `[simulation.contact]` and the earlier keys (`contact_model`, `kec_two_point_approach_m`)
    /// give the same model; both at once, an unknown name or a bad value are reported.
    #[test]
    fn contact_model_from_the_table_or_the_earlier_keys() {
        let table = spec("[contact]\nmodel = \"kec\"\ntwo_point_approach_m = 2e-5").unwrap();
        let legacy = spec("contact_model = \"kec\"\nkec_two_point_approach_m = 2e-5").unwrap();
        let expect = ContactModelSpec::Kec(KecSettings {
            two_point_approach_m: 2e-5,
            ..KecSettings::default()
        });
        assert_eq!(table.contact_spec().unwrap(), expect);
        assert_eq!(legacy.contact_spec().unwrap(), expect);
        assert!(table.problems().is_empty() && legacy.problems().is_empty());
        // Neither: KEC with its defaults.
        assert_eq!(
            spec("").unwrap().contact_spec().unwrap(),
            ContactModelSpec::default()
        );
        // Another model by name: its defaults; the legacy KEC key is then unused.
        let l = spec("contact_model = \"lookup2\"").unwrap();
        assert_eq!(l.contact_spec().unwrap().name(), "lookup2");
        // `--contact`: the scenario's own settings for the same model; for another, its defaults
        // with the scenario's two-point transitions carried over (the same physics), said in a
        // note — or a note that the model cannot honour them (KEC keeping the scenario's legacy
        // approach).
        assert_eq!(table.contact_spec_for("kec").unwrap(), (expect.clone(), vec![]));
        let (online, notes) = table.contact_spec_for("online").unwrap();
        assert_eq!(online.name(), "online");
        assert!(
            notes[0].contains("do not apply") && notes[0].contains("rigidly"),
            "{notes:?}"
        );
        let (t2, notes) = table.contact_spec_for("lookup2").unwrap();
        assert_eq!(
            t2.two_point(),
            expect.two_point(),
            "the scene's treatment, not lookup2's rigid jumps"
        );
        assert!(notes[0].contains("carried over"), "{notes:?}");
        let (k, _) = l.contact_spec_for("kec").unwrap();
        assert_eq!(k.two_point(), l.contact_spec().unwrap().two_point());
        assert_eq!(
            spec("contact_model = \"online\"\nkec_two_point_approach_m = 0.0")
                .unwrap()
                .contact_spec_for("kec")
                .unwrap()
                .0,
            ContactModelSpec::Kec(KecSettings {
                two_point_approach_m: 0.0,
                ..KecSettings::default()
            })
        );
        assert!(table
            .contact_spec_for("magic")
            .unwrap_err()
            .to_string()
            .contains("magic"));
        let both = spec("contact_model = \"kec\"\n[contact]\nmodel = \"kec\"").unwrap();
        assert!(
            both.problems().iter().any(|p| p.contains("not both")),
            "{:?}",
            both.problems()
        );
        let unknown = spec("contact_model = \"magic\"").unwrap();
        assert!(unknown
            .problems()
            .iter()
            .any(|p| p.contains("\"magic\"") && p.contains("lookup2")));
        let bad = spec("[contact]\nmodel = \"lookup2\"\ngv_step_m = 0.0").unwrap();
        assert!(
            bad.problems()
                .iter()
                .any(|p| p.contains("simulation.contact.gv_step_m = 0")),
            "{:?}",
            bad.problems()
        );
        let e = spec("[contact]\nmodel = \"online\"\ntwo_point_approach_m = 1e-5")
            .unwrap_err()
            .to_string();
        assert!(e.contains("two_point_approach_m") && e.contains("line"), "{e}");
    }
}
