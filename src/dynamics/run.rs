//! Running a vehicle system: one loop for every [`VehicleModel`] — integrate with fixed-rate
//! output, hand each output time's samples to the observers as they are produced, check the stop
//! conditions, and summarise (what `kecsim run` prints and writes).
//!
//! A run that ends early keeps everything: a stop condition ([`Stop`]) ends it normally; a failure
//! (a wheel lifts, the step size collapses, the contact model fails, an observer cannot write)
//! ends it with the diagnosis ([`RunEnd::Failed`]); either way the samples up to there are in the
//! [`RunOutput`] and every observer has seen them and its `finish`.

use std::fmt;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

use thiserror::Error;

use super::integrator::{integrate_into, Completion, Flow, IntegrationError, Settings, StallLimit, Stats};
use super::output::{ObserverError, OutputSample, RunObserver, RunStart, RunSummary};
use super::sample::Sample;
use super::system::{
    BodySample, DynamicsError, Evaluator, FloorPoint, InitialDisturbance, LandingEvent, Settling,
    VehicleModel,
};
use super::wheelset::WheelsetError;

/// What to run and how (the vehicle and its track reference are the model's).
#[derive(Debug, Clone, PartialEq)]
pub struct RunSettings {
    /// Scene name (for the summary).
    pub scene: String,
    /// Simulated time, s.
    pub duration_s: f64,
    /// Output rate, Hz.
    pub record_rate_hz: f64,
    pub integrator: Settings,
    pub initial: InitialDisturbance,
    pub stop: StopConditions,
    /// The threads of the run ([`RunPool::new`]; default: the caller's).
    pub pool: RunPool,
    /// The profiles the samples' patches are recomputed from where Hertz does not hold
    /// (`super::patches`); None: Hertz's everywhere (a run built without its scene).
    pub patches: Option<std::sync::Arc<super::patches::PatchPostProcess>>,
}

/// Conditions that end a run normally, before its duration.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StopConditions {
    /// A wheelset beyond |y| = this, m (e.g. to end a speed ramp once hunting has set in).
    pub lateral_m: Option<f64>,
}

/// Why a run ended normally before its duration.
#[derive(Debug, Clone, PartialEq)]
pub enum Stop {
    /// A wheelset exceeded the lateral limit.
    Lateral {
        wheelset: String,
        y_m: f64,
        limit_m: f64,
        t: f64,
        speed_m_s: f64,
    },
    /// Interrupted (Ctrl-C, SIGTERM: the settings' [`CancelToken`](super::CancelToken)) at the
    /// output time t.
    Interrupted { t: f64 },
}

impl fmt::Display for Stop {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Stop::Lateral {
                wheelset,
                y_m,
                limit_m,
                t,
                speed_m_s,
            } => write!(
                f,
                "|y| = {:.3} mm exceeded {:.3} mm at t = {t:.3} s, V = {speed_m_s:.2} m/s ({wheelset})",
                y_m.abs() * 1e3,
                limit_m * 1e3
            ),
            Stop::Interrupted { .. } => write!(f, "interrupted"),
        }
    }
}

impl StopConditions {
    /// The first condition met by this output time's samples.
    pub fn check(&self, t: f64, names: &[String], wheelsets: &[Sample]) -> Option<Stop> {
        let limit = self.lateral_m?;
        wheelsets
            .iter()
            .zip(names)
            .find(|(w, _)| w.y.abs() > limit)
            .map(|(w, name)| Stop::Lateral {
                wheelset: name.clone(),
                y_m: w.y,
                limit_m: limit,
                t,
                speed_m_s: w.speed,
            })
    }
}

/// A run's failure.
#[derive(Debug, Error)]
pub enum RunFailure {
    #[error(transparent)]
    Integration(#[from] IntegrationError<DynamicsError>),
    #[error("output: {0}")]
    Observer(ObserverError),
    /// The step size stayed collapsed ([`STALL_STEPS`] steps in a row shorter than
    /// [`STALL_FRACTION`] of the sampling interval): the run is ended with a diagnosis instead of
    /// grinding on; `state` names the state whose error held most of those steps.
    #[error("step size collapsed at t = {t:.6} s, limited by {state}: {steps} steps in a row shorter than {h_below:.1e} s ({fraction:e} of the sampling interval) advanced the run by only {span_s:.2e} s. A motion this fast is not a railway vehicle's: look for a unit mistake at what {state} belongs to (a mass or inertia in g or g mm², a position in mm given as m, a stiffness far from the vehicle's), or a body held by nothing", fraction = STALL_FRACTION)]
    StepCollapse {
        t: f64,
        h_below: f64,
        steps: usize,
        span_s: f64,
        state: String,
    },
}

/// [`RunFailure::StepCollapse`]: accepted steps in a row, each shorter than [`STALL_FRACTION`] of
/// the sampling interval, that end a run. A flange impact or a landing takes a few hundred such
/// steps at most; a grinding run makes these in seconds of wall time (a bogie of 1 kg: ~30 µs
/// per step).
pub const STALL_STEPS: usize = 10_000;
/// [`STALL_STEPS`]' step size, as a fraction of the sampling interval (1/record_rate_hz).
pub const STALL_FRACTION: f64 = 1e-5;

impl RunFailure {
    /// Whether the contact model failed (the wheel and rail never touch, the contact runs off a
    /// profile, its Newton iteration did not converge): the profiles and their placement are then
    /// what to check, and the message should name their files.
    pub fn in_contact_model(&self) -> bool {
        matches!(
            self,
            RunFailure::Integration(
                IntegrationError::Model { error, .. } | IntegrationError::Output { error, .. },
            ) if matches!(
                error,
                DynamicsError::Contact { .. } | DynamicsError::Wheelset { .. } | DynamicsError::CentredContact(_)
            )
        )
    }

    /// The derailment that ended the run, if that is what did (the wheelset's name): a flange
    /// climb or a wheel lifted beyond its limit, found by a step's evaluation or by an output
    /// sample's (on the step's continuous extension, between its stages).
    pub fn derailment(&self) -> Option<&str> {
        let error = match self {
            RunFailure::Integration(
                IntegrationError::Model { error, .. } | IntegrationError::Output { error, .. },
            ) => error,
            _ => return None,
        };
        match error {
            DynamicsError::Derailment { wheelset, .. }
            | DynamicsError::Wheelset {
                wheelset,
                source: WheelsetError::LiftLimit { .. },
                ..
            } => Some(wheelset),
            _ => None,
        }
    }
}

/// How a run ended.
#[derive(Debug)]
pub enum RunEnd {
    /// It covered its duration.
    Completed,
    /// A stop condition ended it.
    Stopped(Stop),
    /// It failed with this diagnosis.
    Failed(RunFailure),
}

/// A finished (or stopped, or failed) run: every sample up to its end and the summary.
pub struct RunOutput {
    /// Every wheelset's samples, by name.
    pub wheelsets: Vec<(String, Vec<Sample>)>,
    /// Every rigid body's samples, by name (none on the single-wheelset scenes).
    pub bodies: Vec<(String, Vec<(f64, BodySample)>)>,
    /// Multibody vehicles: the static settling behind the elements' preloads.
    pub settling: Option<Settling>,
    pub summary: RunSummary,
    pub end: RunEnd,
    /// The landings of lifted wheels, in time order.
    pub landings: Vec<LandingEvent>,
    /// Per carbody floor point: its accelerations at each sample (x, y, z in the carbody's axes,
    /// less 1 g on z), m/s².
    pub floor: Vec<(FloorPoint, Vec<[f64; 3]>)>,
    /// Every observer's failure (a file it could not write), whatever ended the run: the one
    /// that failed it (also in [`Self::end`]) and those at the end, after a failure or a stop
    /// that [`Self::end`] reports for itself. Empty when every output was written.
    pub output_failures: Vec<String>,
}

impl RunOutput {
    /// The first wheelset's samples.
    pub fn samples(&self) -> &[Sample] {
        self.wheelsets.first().map_or(&[], |w| &w.1)
    }
}

/// Names a run's summary carries besides the vehicle's (the creep model, the preprocessing time).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RunLabels {
    pub contact_model: String,
    pub creep_model: String,
    /// Contact-model and vehicle preprocessing (tables, equivalent profiles, settling, the flange
    /// angle of the safety figures), s.
    pub preprocessing_s: f64,
    /// Friction and flange angle for the running-safety limits (None: no safety figures).
    pub safety: Option<super::safety::SafetyBasis>,
    /// What normalises a contact's spin (None: the summary has no spin figure).
    pub spin_basis: Option<SpinBasis>,
}

/// The contact's material and friction, to express its spin as the share of the linear lateral
/// force: φ̂ = G (ab)^{3/2} C₂₃ |φ| / (μN) (Kalker's linear spin force over the friction limit).
#[derive(Debug, Clone, PartialEq)]
pub struct SpinBasis {
    pub shear_modulus: f64,
    pub friction: f64,
    pub kalker: crate::contact::forces::KalkerTable,
}

impl SpinBasis {
    /// φ̂ of one wheel of a sample (0 where it carries no load or has no patch).
    pub fn normalized_spin(&self, s: &Sample, side: usize) -> f64 {
        let [a, b] = s.semi_axes[side];
        let n = s.normal[side];
        if !(a > 0.0 && b > 0.0 && n > 0.0 && self.friction > 0.0) {
            return 0.0;
        }
        let ab = a * b;
        let c23 = self.kalker.at(a / b).c23;
        self.shear_modulus * ab * ab.sqrt() * c23 * s.creepage[side][2].abs() / (self.friction * n)
    }
}

/// The amplitude below which a hunting cycle has died out on a decelerating ramp, m: 0.1 mm (the
/// cycles seen on S1002/60E1 collapse from some 0.4 mm to hundredths within 1 m/s).
pub const HUNTING_EXTINCT_M: f64 = 1e-4;

/// The nonlinear critical speed on a decelerating ramp (the usual method: start above it on the
/// hunting limit cycle and slow down until the cycle dies): the speed at the first peak of |y|
/// between successive zero crossings below `extinct` (m), after a sustained cycle — two
/// successive peaks above 3 × `extinct`, the later at least 0.9 times the earlier — so that a run
/// which merely decays from its release reports none. `None` too if the cycle never died out, or
/// y never crosses zero (an offset equilibrium: a curve). The figure lags the cycle's fold by the time
/// its amplitude takes to fall to `extinct`, times the deceleration (measured: from 42 and from
/// 60 m/s within 0.06 m/s).
pub fn hunting_extinction(samples: &[Sample], extinct: f64) -> Option<f64> {
    let mut hunted = false;
    let mut previous = 0.0_f64;
    for (peak, speed) in half_cycle_peaks(samples) {
        if peak > 3.0 * extinct && previous > 3.0 * extinct && peak >= 0.9 * previous {
            hunted = true;
        } else if hunted && peak < extinct {
            return Some(speed);
        }
        previous = peak;
    }
    None
}

/// The peaks of |y| between successive zero crossings of y, with the speed at each: (|y|, m/s).
fn half_cycle_peaks(samples: &[Sample]) -> Vec<(f64, f64)> {
    let mut peaks = Vec::new();
    let mut cur = (0.0_f64, 0.0_f64);
    for w in samples.windows(2) {
        if w[1].y.abs() > cur.0 {
            cur = (w[1].y.abs(), w[1].speed);
        }
        if w[0].y.signum() != w[1].y.signum() && w[1].y != 0.0 {
            if cur.0 > 0.0 {
                peaks.push(cur);
            }
            cur = (0.0, 0.0);
        }
    }
    peaks
}

/// Hunting onset on a speed ramp: the peaks of |y| between successive zero crossings form the
/// envelope; where it is smallest the oscillation turned from decaying to growing, i.e. the
/// damping of the hunting mode crossed zero. Returns the speed there, if the envelope afterwards
/// grew to at least `growth` times its minimum (else the ramp never reached the critical speed).
pub fn hunting_onset(samples: &[Sample], growth: f64) -> Option<f64> {
    let peaks = half_cycle_peaks(samples);
    if peaks.len() < 4 {
        return None;
    }
    // Skip the first peak (the release transient).
    let (imin, min) = peaks
        .iter()
        .enumerate()
        .skip(1)
        .min_by(|a, b| a.1 .0.total_cmp(&b.1 .0))?;
    let later = peaks[imin..].iter().map(|p| p.0).fold(0.0, f64::max);
    (later >= growth * min.0).then_some(min.1)
}

/// The threads a run splits its work between: the contact preprocessing's searches and, in every
/// right-hand side, a vehicle's wheelsets (each wheelset's kinematics and dynamics depend only on
/// its own state; the results are the same to the last bit on any number of threads).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Threads {
    /// Called from a thread of a rayon pool (a study's cases, a caller's own pool): that pool's;
    /// else a pool of the run's own with two threads where the machine has two cores (one
    /// where it has one).
    #[default]
    Default,
    /// A pool of the run's own with this many threads (1: every evaluation on one thread). The
    /// binary takes it from the environment variable `KECSIM_THREADS`.
    Count(usize),
    /// No pool of its own: the pool of the thread it is called from (rayon's global pool from
    /// a thread outside any).
    Caller,
}

/// The thread pool of one run ([`Threads`]), made when the run is built and kept with its
/// settings: the preprocessing and the run execute inside it (on one of its threads, which
/// then splits a right-hand side's wheelsets with the others without handing each evaluation to
/// a thread outside). Clones share the pool; none: the caller's. A pool that cannot be made
/// (no threads to start) leaves the run to the caller's.
#[derive(Debug, Clone, Default)]
pub struct RunPool(Option<Arc<rayon::ThreadPool>>);

impl RunPool {
    /// The pool `threads` asks for.
    pub fn new(threads: Threads) -> RunPool {
        let n = match threads {
            Threads::Caller => return RunPool(None),
            Threads::Default if rayon::current_thread_index().is_some() => return RunPool(None),
            Threads::Default => std::thread::available_parallelism().map_or(1, |n| n.get()).min(2),
            Threads::Count(n) => n.max(1),
        };
        RunPool(
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .ok()
                .map(Arc::new),
        )
    }

    /// Runs `f` inside the pool (on the calling thread where there is none).
    pub fn install<R: Send>(&self, f: impl FnOnce() -> R + Send) -> R {
        match &self.0 {
            Some(pool) => pool.install(f),
            None => f(),
        }
    }

    /// Whether the run has a pool of its own (not the caller's: a study's cases run in the
    /// study's pool, one per thread, and get no output worker either).
    pub fn owned(&self) -> bool {
        self.0.is_some()
    }

    /// The number of threads the run's work is split between.
    pub fn threads(&self) -> usize {
        match &self.0 {
            Some(pool) => pool.current_num_threads(),
            None => rayon::current_num_threads(),
        }
    }
}

/// Two run pools are equal when they are the same pool (or both the caller's).
impl PartialEq for RunPool {
    fn eq(&self, other: &Self) -> bool {
        match (&self.0, &other.0) {
            (Some(a), Some(b)) => Arc::ptr_eq(a, b),
            (None, None) => true,
            _ => false,
        }
    }
}

/// Runs `vehicle` as `settings` says, handing every output time to `observers` as it is
/// produced. The integrator steps one evaluator of the model; the outputs come from a second one
/// (so that the integrator's warm starts are untouched by them). With a history-dependent contact
/// model the W-method renews its Jacobian every step (the online solve's warm start makes the
/// right-hand side depend on the evaluation history near contact jumps; with a kept Jacobian its
/// error estimate missed 0.06 mm on the Klingel scene, measured).
///
/// The run executes inside its settings' pool ([`RunSettings::pool`]); a stop asked for through
/// the integrator settings' [`CancelToken`](super::CancelToken) ends it as
/// [`Stop::Interrupted`].
pub fn run(
    vehicle: &dyn VehicleModel,
    settings: &RunSettings,
    labels: &RunLabels,
    observers: &mut [&mut (dyn RunObserver + Send)],
) -> RunOutput {
    settings
        .pool
        .install(|| run_here(vehicle, settings, labels, observers))
}

/// Output times queued for the output worker at most (then the integration waits for it).
///
/// It bounds how far the integration runs ahead of the samples the observers have seen: a stop
/// asked for by an observer is honoured at most `OUTPUT_QUEUE + 2` output times after the sample
/// that asked. 64 smooths the worker's jitter as well as 1024 did (MS kilometre: wall-time ratio
/// 0.996–1.021 side by side, within the machine's noise).
pub const OUTPUT_QUEUE: usize = 64;

/// Why an output time could not be recorded.
enum RecordFailure {
    /// The sample's evaluation failed.
    Sample(DynamicsError),
    /// An observer failed.
    Observer(ObserverError),
}

/// The output side of a run: its own evaluator (its warm starts apart from the integrator's),
/// the samples kept, the observers.
struct Recorder<'v, 'o, 'p> {
    out: Evaluator<'v>,
    r0: f64,
    patches: Option<std::sync::Arc<super::patches::PatchPostProcess>>,
    /// Contacts where the strip model found no solution (Hertz's kept).
    patches_unresolved: usize,
    /// Each wheelset's wheels' last approach (the strip model's warm start).
    patch_warm: Vec<super::patches::PatchWarm>,
    wheelsets: Vec<(String, Vec<Sample>)>,
    bodies: Vec<(String, Vec<(f64, BodySample)>)>,
    /// Per floor point: its accelerations at each sample.
    floor: Vec<(FloorPoint, Vec<[f64; 3]>)>,
    observers: &'o mut [&'p mut (dyn RunObserver + Send)],
}

impl Recorder<'_, '_, '_> {
    /// Samples (t, x), keeps the samples and hands them to every observer; the wheelsets' row.
    fn record(&mut self, t: f64, x: &[f64]) -> Result<Vec<Sample>, RecordFailure> {
        let s = self.out.sample(t, x).map_err(RecordFailure::Sample)?;
        let mut row: Vec<Sample> = s
            .wheelsets
            .iter()
            .map(|w| Sample::new(t, w, self.r0).with_traction(&s.traction))
            .collect();
        if let Some(p) = &self.patches {
            self.patch_warm.resize(row.len(), Default::default());
            for (w, warm) in row.iter_mut().zip(self.patch_warm.iter_mut()) {
                self.patches_unresolved += p.apply_warm(w, warm);
            }
        }
        for (k, w) in row.iter_mut().enumerate() {
            w.set_wear_number_2m(&self.wheelsets[k].1);
            self.wheelsets[k].1.push(*w);
        }
        for (k, b) in s.bodies.iter().enumerate() {
            self.bodies[k].1.push((t, *b));
        }
        for (k, a) in s.floor.iter().enumerate() {
            if let Some(f) = self.floor.get_mut(k) {
                f.1.push(*a);
            }
        }
        let sample = OutputSample {
            t,
            wheelsets: &row,
            bodies: &s.bodies,
            elements: &s.elements,
            floor: &s.floor,
        };
        for o in self.observers.iter_mut() {
            o.sample(&sample).map_err(RecordFailure::Observer)?;
        }
        Ok(row)
    }
}

/// [`run`] on this thread.
fn run_here(
    vehicle: &dyn VehicleModel,
    settings: &RunSettings,
    labels: &RunLabels,
    observers: &mut [&mut (dyn RunObserver + Send)],
) -> RunOutput {
    let names = vehicle.wheelset_names();
    let body_names = vehicle.body_names();
    let r0 = vehicle.nominal_radius();
    let mut integrator = settings.integrator.clone();
    if integrator.stall.is_none() {
        integrator.stall = Some(StallLimit {
            h_below: STALL_FRACTION / settings.record_rate_hz,
            steps: STALL_STEPS,
        });
    }
    if vehicle.contact().history_dependent() {
        integrator.jacobian_max_age = 1;
    }
    let floor_points = vehicle.floor_points();
    let start = RunStart {
        wheelsets: &names,
        bodies: &body_names,
        floor_points: &floor_points,
        duration_s: settings.duration_s,
    };
    let mut observer_error: Option<ObserverError> = None;
    for o in observers.iter_mut() {
        if let Err(e) = o.start(&start) {
            observer_error.get_or_insert(e);
        }
    }
    let mut sys = Evaluator::new(vehicle);
    let mut recorder = Recorder {
        out: Evaluator::new(vehicle),
        r0,
        patches: settings.patches.clone(),
        patches_unresolved: 0,
        patch_warm: Vec::new(),
        wheelsets: names.iter().map(|n| (n.clone(), Vec::new())).collect(),
        bodies: body_names.iter().map(|n| (n.clone(), Vec::new())).collect(),
        floor: floor_points.iter().map(|p| (p.clone(), Vec::new())).collect(),
        observers,
    };
    let x0 = vehicle.initial_state(&settings.initial);
    let mut stop: Option<Stop> = None;
    let mut stats = Stats::default();
    let t_run = Instant::now();
    let dt_out = 1.0 / settings.record_rate_hz;
    let result = if observer_error.is_some() {
        Ok(Completion::Stopped { t: 0.0 })
    } else if settings.pool.owned() && settings.stop.lateral_m.is_none() {
        // The samples computed and handed to the observers on a worker of their own, fed
        // (t, x) in order: the integration never waits for them. The worker's evaluator sees
        // the same states in the same order as it would here, so the samples are the same to
        // the bit. (A stop condition reads each sample before the next step: then here.)
        let failed = AtomicBool::new(false);
        let (sent, queue) = std::sync::mpsc::sync_channel::<(f64, Vec<f64>)>(OUTPUT_QUEUE);
        std::thread::scope(|scope| {
            let worker = scope.spawn(|| {
                RunPool::new(Threads::Count(1)).install(|| {
                    let mut failure = None;
                    for (t, x) in queue {
                        if let Err(e) = recorder.record(t, &x) {
                            failure = Some((t, e));
                            failed.store(true, Ordering::Relaxed);
                            break;
                        }
                    }
                    failure
                })
            });
            let result = integrate_into(
                &mut sys,
                0.0,
                &x0,
                settings.duration_s,
                dt_out,
                &integrator,
                &mut |t, x| {
                    if failed.load(Ordering::Relaxed) || sent.send((t, x.to_vec())).is_err() {
                        return Ok(Flow::Stop);
                    }
                    if settings.integrator.cancel.requested() {
                        stop = Some(Stop::Interrupted { t });
                        return Ok(Flow::Stop);
                    }
                    Ok(Flow::Continue)
                },
                &mut stats,
            );
            drop(sent);
            let failure = match worker.join() {
                Ok(f) => f,
                Err(panic) => std::panic::resume_unwind(panic),
            };
            match failure {
                Some((t, RecordFailure::Sample(error))) => Err(IntegrationError::Output { t, error }),
                Some((_, RecordFailure::Observer(e))) => {
                    observer_error = Some(e);
                    result
                }
                None => result,
            }
        })
    } else {
        integrate_into(
            &mut sys,
            0.0,
            &x0,
            settings.duration_s,
            dt_out,
            &integrator,
            &mut |t, x| {
                let row = match recorder.record(t, x) {
                    Ok(row) => row,
                    Err(RecordFailure::Sample(e)) => return Err(e),
                    Err(RecordFailure::Observer(e)) => {
                        observer_error = Some(e);
                        return Ok(Flow::Stop);
                    }
                };
                stop = if settings.integrator.cancel.requested() {
                    Some(Stop::Interrupted { t })
                } else {
                    settings.stop.check(t, &names, &row)
                };
                Ok(if stop.is_some() {
                    Flow::Stop
                } else {
                    Flow::Continue
                })
            },
            &mut stats,
        )
    };
    let Recorder {
        wheelsets,
        bodies,
        floor,
        observers,
        patches_unresolved,
        ..
    } = recorder;
    let wall_s = t_run.elapsed().as_secs_f64();
    let state_names = vehicle.state_names();
    let mut output_failures: Vec<String> = observer_error.iter().map(|e| e.to_string()).collect();
    let end = match (result, observer_error, stop) {
        (_, Some(e), _) => RunEnd::Failed(RunFailure::Observer(e)),
        (
            Err(IntegrationError::Stalled {
                t,
                h_below,
                steps,
                span_s,
                limiting,
            }),
            None,
            _,
        ) => RunEnd::Failed(RunFailure::StepCollapse {
            t,
            h_below,
            steps,
            span_s,
            state: limiting
                .map(|i| state_names.get(i).cloned().unwrap_or_else(|| format!("x[{i}]")))
                .unwrap_or_else(|| "no single state".to_string()),
        }),
        (Err(e), None, _) => RunEnd::Failed(RunFailure::Integration(e)),
        (Ok(_), None, Some(s)) => RunEnd::Stopped(s),
        // Interrupted between two output times (the integrator ends at its step).
        (Ok(Completion::Stopped { t }), None, None) if settings.integrator.cancel.requested() => {
            RunEnd::Stopped(Stop::Interrupted { t })
        }
        (Ok(_), None, None) => RunEnd::Completed,
    };
    let landings = std::mem::take(&mut sys.data.landings);
    let mut summary = summarise(settings, labels, &wheelsets, wall_s, &stats, &end, &landings);
    summary.step_limiting = stats.limiting_states(STEP_LIMITING_SHOWN, |i| {
        state_names.get(i).cloned().unwrap_or_else(|| format!("x[{i}]"))
    });
    let ramp = vehicle.reference().speed.ramp_m_s2;
    if ramp > 0.0 {
        summary.critical_speed_m_s = wheelsets.first().and_then(|w| hunting_onset(&w.1, 2.0));
    } else if ramp < 0.0 {
        summary.critical_speed_m_s = wheelsets
            .first()
            .and_then(|w| hunting_extinction(&w.1, HUNTING_EXTINCT_M));
        summary.critical_speed_decelerating = true;
    }
    if let (Some(basis), true) = (labels.safety, wheelsets.iter().any(|w| !w.1.is_empty())) {
        // Static wheel loads: half the settled axle load; without a settling (a single wheelset
        // on its frame), the first sample's loads (the run starts at rest on its rails).
        let q0: Vec<[f64; 2]> = match vehicle.settling() {
            Some(st) => st.axle_loads.iter().map(|q| [0.5 * q, 0.5 * q]).collect(),
            None => wheelsets
                .iter()
                .map(|w| w.1.first().map_or([0.0; 2], |p| p.q_force))
                .collect(),
        };
        summary.safety = Some(super::safety::assess(&wheelsets, &q0, basis));
    }
    if wheelsets.iter().any(|w| !w.1.is_empty()) {
        summary.wear = Some(super::wear::assess(&wheelsets));
        let mut stress = super::contact_stress::assess(&wheelsets, super::contact_stress::R260);
        stress.patches_unresolved = patches_unresolved;
        stress.non_hertzian_recomputed = settings.patches.as_ref().is_some_and(|p| p.recompute);
        summary.contact_stress = Some(stress);
    }
    summary.comfort = super::ride::assess(&floor, settings.record_rate_hz);
    let curves = super::resistance::curves(vehicle.reference().track.as_deref());
    summary.traction = super::resistance::assess(vehicle.drive_info(), &wheelsets, &curves);
    let mut end = end;
    for o in observers.iter_mut() {
        if let Err(e) = o.finish(&summary) {
            output_failures.push(e.to_string());
            if !matches!(end, RunEnd::Failed(_)) {
                summary.error = Some(format!("output: {e}"));
                summary.outcome = "failed";
                end = RunEnd::Failed(RunFailure::Observer(e));
            }
        }
    }
    RunOutput {
        wheelsets,
        bodies,
        settling: vehicle.settling().cloned(),
        summary,
        end,
        landings,
        floor,
        output_failures,
    }
}

/// How many of the states that limited the step the summary names ([`RunSummary::step_limiting`]).
const STEP_LIMITING_SHOWN: usize = 6;

fn summarise(
    settings: &RunSettings,
    labels: &RunLabels,
    wheelsets: &[(String, Vec<Sample>)],
    wall_s: f64,
    stats: &Stats,
    end: &RunEnd,
    landings: &[LandingEvent],
) -> RunSummary {
    // The longest continuous lift of one wheel in the samples.
    let mut longest_lift_s: f64 = 0.0;
    for (_, w) in wheelsets {
        for side in 0..2 {
            let mut since: Option<f64> = None;
            for s in w {
                match (s.lift[side] > 0.0, since) {
                    (true, None) => since = Some(s.t),
                    (false, Some(t0)) => {
                        longest_lift_s = longest_lift_s.max(s.t - t0);
                        since = None;
                    }
                    _ => {}
                }
            }
            if let (Some(t0), Some(last)) = (since, w.last()) {
                longest_lift_s = longest_lift_s.max(last.t - t0);
            }
        }
    }
    let samples: Vec<&Sample> = wheelsets.iter().flat_map(|w| w.1.iter()).collect();
    let fold = |f: &dyn Fn(&Sample) -> f64| samples.iter().map(|s| f(s)).fold(0.0_f64, f64::max);
    let simulated_s = wheelsets.first().and_then(|w| w.1.last()).map_or(0.0, |s| s.t);
    let (error, stopped, outcome) = match end {
        RunEnd::Completed => (None, None, "completed"),
        RunEnd::Stopped(s) => (None, Some(s.to_string()), "stopped"),
        RunEnd::Failed(e) if e.derailment().is_some() => (Some(e.to_string()), None, "derailed"),
        RunEnd::Failed(e) => (Some(e.to_string()), None, "failed"),
    };
    RunSummary {
        scene: settings.scene.clone(),
        contact_model: labels.contact_model.clone(),
        creep_model: labels.creep_model.clone(),
        integrator: format!("{:?}", settings.integrator.method).to_lowercase(),
        simulated_s,
        wall_s,
        realtime_factor: if wall_s > 0.0 { simulated_s / wall_s } else { 0.0 },
        steps: stats.accepted,
        rejected_steps: stats.rejected,
        smallest_step_s: if stats.smallest_step.is_finite() {
            stats.smallest_step
        } else {
            0.0
        },
        rhs_evaluations: stats.rhs_evaluations,
        jacobians: stats.jacobians,
        wheelset_dynamics_reused: stats.reused_blocks,
        step_limiting: Vec::new(),
        preprocessing_s: labels.preprocessing_s,
        max_abs_y_mm: fold(&|s| s.y.abs() * 1e3),
        max_abs_yaw_mrad: fold(&|s| s.yaw.abs() * 1e3),
        max_normal_n: fold(&|s| s.normal[0].max(s.normal[1])),
        min_normal_n: samples
            .iter()
            .map(|s| s.normal[0].min(s.normal[1]))
            .fold(f64::INFINITY, f64::min),
        max_abs_y_over_q: fold(&|s| s.max_abs_y_over_q()),
        max_normalized_spin: labels.spin_basis.as_ref().map_or(0.0, |b| {
            fold(&|s| b.normalized_spin(s, 0).max(b.normalized_spin(s, 1)))
        }),
        error,
        stopped,
        critical_speed_m_s: None,
        critical_speed_decelerating: false,
        outcome,
        samples: wheelsets.first().map_or(0, |w| w.1.len()),
        max_lift_mm: fold(&|s| s.lift[0].max(s.lift[1]) * 1e3),
        longest_lift_s,
        landings: landings.len(),
        max_landing_speed_m_s: landings.iter().map(|l| l.landing.speed).fold(0.0, f64::max),
        max_landing_impulse_n_s: landings.iter().map(|l| l.landing.impulse).fold(0.0, f64::max),
        safety: None,
        wear: None,
        contact_stress: None,
        comfort: None,
        traction: None,
        derailment_max_y_over_q_2m: match end {
            RunEnd::Failed(e) => e.derailment().and_then(|name| {
                let w = &wheelsets.iter().find(|w| w.0 == name)?.1;
                let s_end = w.last()?.s;
                Some(
                    w.iter()
                        .filter(|p| p.s >= s_end - 2.0)
                        .map(|p| p.max_abs_y_over_q())
                        .fold(0.0, f64::max),
                )
            }),
            _ => None,
        },
        warnings: Vec::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sample of lateral displacement `y` at speed `speed`.
    fn sample(t: f64, speed: f64, y: f64) -> Sample {
        Sample {
            y,
            ..Sample::at(t, 0.0, speed)
        }
    }

    /// A 2 Hz cycle on a decelerating ramp (50 m/s at −0.5 m/s²) whose amplitude is 2 mm until
    /// 35 m/s and collapses there by a factor 10 per second: the extinction is reported at the
    /// first peak below 0.1 mm, i.e. where 2 mm · 10^−(35 − v)/0.5 = 0.1 mm, 34.35 m/s within half a
    /// cycle (0.125 m/s); a cycle that never dies out, or never was one, gives none.
    #[test]
    fn the_hunting_cycle_dies_out_where_its_peaks_fall_below_the_threshold() {
        let cycle = |amplitude: &dyn Fn(f64) -> f64| -> Vec<Sample> {
            (0..8000)
                .map(|k| {
                    let t = k as f64 * 0.005;
                    let v = 50.0 - 0.5 * t;
                    sample(t, v, amplitude(v) * (2.0 * std::f64::consts::PI * 2.0 * t).sin())
                })
                .collect()
        };
        let dying = cycle(&|v: f64| {
            if v > 35.0 {
                2e-3
            } else {
                2e-3 * 10f64.powf(-(35.0 - v) / 0.5)
            }
        });
        let expected = 35.0 - 0.5 * (2e-3 / HUNTING_EXTINCT_M).log10();
        let v = hunting_extinction(&dying, HUNTING_EXTINCT_M).expect("the cycle dies out");
        assert!(v <= expected && v > expected - 0.125, "{v} vs {expected}");
        assert_eq!(hunting_extinction(&cycle(&|_| 2e-3), HUNTING_EXTINCT_M), None);
        assert_eq!(hunting_extinction(&cycle(&|_| 3e-5), HUNTING_EXTINCT_M), None);
        // Released from 4 mm below the critical speed: one large half cycle, then decay — no
        // cycle, no critical speed.
        let transient = cycle(&|v: f64| 4e-3 * 10f64.powf(-(50.0 - v)));
        assert_eq!(hunting_extinction(&transient, HUNTING_EXTINCT_M), None);
    }
}
