//! Running a scene: build the contact model, the system and the integrator from the scenario,
//! integrate with fixed-rate output, and summarise (what `kecsim run` prints and writes).
//!
//! A run that fails part-way (a wheel lifts, the step size collapses, the contact model fails)
//! returns what it recorded up to the failure together with the diagnosis, so that nothing is lost.

use std::time::Instant;

use serde::Serialize;

use super::contact_model::{ContactKind, WheelsetContact};
use super::integrator::{integrate_into, IntegrationError, Stats};
use super::multibody::{BodySample, Multibody, Settling};
use super::single_wheelset::{SingleWheelset, SpeedProfile, Tie};
use super::spec::{SimulationSpec, VehicleSpec};
use super::wheelset::WheelsetInertia;
use crate::contact::geometry::ContactGeometry;
use crate::contact::kec::KecModel;
use crate::contact::lookup::{LookupTable1, LookupTable2, TableSettings};
use crate::scenario::Scene;

/// One output sample of one wheelset.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    pub t: f64,
    /// Arc length of the wheelset, m.
    pub s: f64,
    pub speed: f64,
    pub y: f64,
    pub yaw: f64,
    /// Centre height minus r0, m.
    pub z: f64,
    pub roll: f64,
    /// Normal forces left, right, N.
    pub normal: [f64; 2],
    /// Creep forces (contact frame) left, right: Fx, Fy, N.
    pub creep_x: [f64; 2],
    pub creep_y: [f64; 2],
    /// Lateral (Y) and vertical (Q) wheel–rail force on each wheel, track frame, N.
    pub y_force: [f64; 2],
    pub q_force: [f64; 2],
    /// Contact on the real wheel and rail (paper convention), m.
    pub s_wheel: [f64; 2],
    pub s_rail: [f64; 2],
    /// Contact positions (Y, Z) in the wheelset-track frame, m.
    pub position: [(f64, f64); 2],
    /// KEC: knife-edge contact parameters, m.
    pub s_knife: Option<[f64; 2]>,
    pub rails: [f64; 4],
}

/// The run summary (`--json`).
#[derive(Debug, Clone, Serialize)]
pub struct RunSummary {
    pub scene: String,
    pub contact_model: String,
    pub creep_model: String,
    pub integrator: String,
    pub simulated_s: f64,
    pub wall_s: f64,
    /// Simulated time over wall time.
    pub realtime_factor: f64,
    pub steps: usize,
    pub rejected_steps: usize,
    pub rhs_evaluations: usize,
    pub preprocessing_s: f64,
    pub max_abs_y_mm: f64,
    pub max_abs_yaw_mrad: f64,
    pub max_normal_n: f64,
    pub min_normal_n: f64,
    pub max_abs_y_over_q: f64,
    /// Why the run stopped early, if it did.
    pub error: Option<String>,
    /// A stop condition that ended the run normally (`stop_lateral_m`).
    pub stopped: Option<String>,
    /// With a speed ramp: the speed at which the lateral oscillation stopped decaying and started
    /// to grow (hunting onset), m/s — see [`hunting_onset`].
    pub critical_speed_m_s: Option<f64>,
}

/// Marker of the stop condition in the observer's error.
const STOP: &str = "stop condition: ";

/// Hunting onset on a speed ramp: the peaks of |y| between successive zero crossings form the
/// envelope; where it is smallest the oscillation turned from decaying to growing, i.e. the
/// damping of the hunting mode crossed zero. Returns the speed there, if the envelope afterwards
/// grew to at least `growth` times its minimum (else the ramp never reached the critical speed).
pub fn hunting_onset(samples: &[Sample], growth: f64) -> Option<f64> {
    let mut peaks: Vec<(f64, f64)> = Vec::new(); // (|y| peak, speed there)
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

/// A finished (or stopped) run.
pub struct RunOutput {
    /// The first wheelset's samples.
    pub samples: Vec<Sample>,
    /// Every wheelset's samples, by name (the first is `samples` again).
    pub wheelsets: Vec<(String, Vec<Sample>)>,
    /// Every rigid body's samples, by name (none on the single-wheelset scenes).
    pub bodies: Vec<(String, Vec<(f64, BodySample)>)>,
    /// Multibody vehicles: the static settling behind the elements' preloads.
    pub settling: Option<Settling>,
    pub summary: RunSummary,
}

/// Builds the contact model of `kind` for the scene's wheel/rail pair, KEC with the scene's
/// two-point transition.
pub fn build_contact(scene: &Scene, kind: ContactKind) -> Result<WheelsetContact, String> {
    let approach = scene
        .simulation
        .as_ref()
        .map_or(super::spec::DEFAULT_TWO_POINT_APPROACH_M, |s| {
            s.0.kec_two_point_approach_m
        });
    build_contact_with(scene, kind, approach)
}

/// [`build_contact`] with the KEC two-point transition's elastic approach `approach_m`
/// (0: the paper's rigid kinks).
pub fn build_contact_with(
    scene: &Scene,
    kind: ContactKind,
    approach_m: f64,
) -> Result<WheelsetContact, String> {
    let pair = scene.pair.clone();
    let geometry = ContactGeometry::with_defaults(pair.clone());
    Ok(match kind {
        ContactKind::Online => WheelsetContact::Online {
            geometry: Box::new(geometry),
        },
        ContactKind::Lookup2 => {
            // y up to flange contact of the centred gauge (as `kecsim bench kec`), gv ±10 mm by 1 mm.
            let settings = TableSettings::default();
            let t1 = LookupTable1::build(&geometry, &settings).map_err(|e| e.to_string())?;
            let (lo, hi) = t1.range();
            let gvs: Vec<f64> = (-10..=10).map(|k| k as f64 * 1e-3).collect();
            let table = LookupTable2::build(&geometry, lo.abs().min(hi), &gvs, &settings)
                .map_err(|e| e.to_string())?;
            WheelsetContact::Lookup2 {
                table: Box::new(table),
            }
        }
        ContactKind::Lookup | ContactKind::Kec => {
            let table =
                LookupTable1::build(&geometry, &TableSettings::default()).map_err(|e| e.to_string())?;
            if kind == ContactKind::Lookup {
                WheelsetContact::Lookup {
                    table: Box::new(table),
                }
            } else {
                let model = KecModel::from_table(&table, pair.wheelset.l_w())
                    .map_err(|e| e.to_string())?
                    .with_two_point_transition(approach_m);
                WheelsetContact::Kec {
                    model: Box::new(model),
                    pair: Box::new(pair),
                }
            }
        }
    })
}

/// Runs the scene's simulation with `contact` and initial speed `speed` (m/s); `progress` is
/// called with the simulated fraction done.
pub fn run(
    scene: &Scene,
    sim: &SimulationSpec,
    vehicle: &VehicleSpec,
    contact: ContactKind,
    speed: f64,
    progress: &mut dyn FnMut(f64),
) -> Result<RunOutput, String> {
    match vehicle {
        VehicleSpec::WheelsetOnFrame(w) => run_single(scene, sim, w, contact, speed, progress),
        VehicleSpec::Multibody(m) => run_multibody(scene, sim, m, contact, speed, progress),
    }
}

/// The stop condition: a wheelset beyond |y| = `limit` ends the run normally (with a note).
fn check_stop(
    t: f64,
    limit: Option<f64>,
    wheelsets: &[super::single_wheelset::WheelsetSample],
) -> Result<(), String> {
    let Some(limit) = limit else {
        return Ok(());
    };
    match wheelsets.iter().find(|w| w.state.y.abs() > limit) {
        Some(w) => Err(format!(
            "{STOP}|y| = {:.3} mm exceeded {:.3} mm at t = {t:.3} s, V = {:.2} m/s",
            w.state.y.abs() * 1e3,
            limit * 1e3,
            w.speed
        )),
        None => Ok(()),
    }
}

/// The scene's integrator settings for `contact`. With the online model, the W-method renews its
/// Jacobian every step: the online solve's warm start makes the right-hand side depend on the
/// evaluation history near contact jumps, and with a kept Jacobian its error estimate missed
/// 0.06 mm on the Klingel scene (measured; 0.004 mm with a Jacobian per step, as DOPRI5).
fn integrator_settings(sim: &SimulationSpec, contact: ContactKind) -> super::integrator::Settings {
    let mut s = sim.integrator.settings();
    if contact == ContactKind::Online {
        s.jacobian_max_age = 1;
    }
    s
}

/// Reports progress every 1 % of the duration.
fn tick(t: f64, duration: f64, last: &mut f64, progress: &mut dyn FnMut(f64)) {
    if t - *last >= 0.01 * duration {
        progress(t / duration);
        *last = t;
    }
}

/// Splits an integration result into (error, stop note).
fn outcome(result: Result<(), IntegrationError>) -> (Option<String>, Option<String>) {
    match result {
        Ok(()) => (None, None),
        Err(IntegrationError::Model { message, .. }) if message.contains(STOP) => (
            None,
            Some(message.split(STOP).nth(1).unwrap_or_default().to_string()),
        ),
        Err(e) => (Some(e.to_string()), None),
    }
}

fn run_multibody(
    scene: &Scene,
    sim: &SimulationSpec,
    spec: &crate::vehicle::MultibodySpec,
    contact: ContactKind,
    speed: f64,
    progress: &mut dyn FnMut(f64),
) -> Result<RunOutput, String> {
    let t_pre = Instant::now();
    let model = build_contact_with(scene, contact, sim.kec_two_point_approach_m)?;
    let r0 = scene.pair.wheelset.nominal_radius_m;
    let mut sys = Multibody::from_spec(
        spec,
        model,
        scene.contact_forces.clone(),
        r0,
        SpeedProfile {
            initial_m_s: speed,
            ramp_m_s2: sim.speed_ramp_m_s2,
        },
    );
    let settling = sys.settle()?;
    let preprocessing_s = t_pre.elapsed().as_secs_f64();
    sys.track = scene.track.clone();
    if let Some(track) = &scene.track {
        // The rearmost body starts at the beginning of the track.
        let rear = sys
            .bodies
            .iter()
            .map(|b| b.d)
            .chain(sys.wheelsets.iter().map(|w| w.d))
            .fold(0.0_f64, f64::min);
        sys.s0 = track.centreline.range().0 - rear;
    }
    if let Some(s0) = sim.start_m {
        sys.s0 = s0;
    }
    let x0 = sys.initial_state(sim.initial.lateral_m, sim.initial.yaw_rad);
    let settings = integrator_settings(sim, contact);
    let dt_out = 1.0 / sim.record_rate_hz;
    let names: Vec<String> = sys.wheelsets.iter().map(|w| w.name.clone()).collect();
    let body_names: Vec<String> = sys.bodies.iter().map(|b| b.name.clone()).collect();
    let mut wheelsets: Vec<(String, Vec<Sample>)> = names.iter().map(|n| (n.clone(), Vec::new())).collect();
    let mut bodies: Vec<(String, Vec<(f64, BodySample)>)> =
        body_names.iter().map(|n| (n.clone(), Vec::new())).collect();
    let duration = sim.duration_s;
    let mut observer_sys = sys.clone_for_output();
    let t_run = Instant::now();
    let mut last_progress = 0.0;
    let stop = sim.stop_lateral_m;
    let mut stats = Stats::default();
    let result = integrate_into(
        &mut sys,
        0.0,
        &x0,
        duration,
        dt_out,
        &settings,
        &mut |t, x| {
            let s = observer_sys.evaluate_at(t, x, None)?;
            for (k, w) in s.wheelsets.iter().enumerate() {
                wheelsets[k].1.push(to_sample(t, w, r0));
            }
            for (k, b) in s.bodies.iter().enumerate() {
                bodies[k].1.push((t, *b));
            }
            check_stop(t, stop, &s.wheelsets)?;
            tick(t, duration, &mut last_progress, progress);
            Ok(())
        },
        &mut stats,
    );
    let wall_s = t_run.elapsed().as_secs_f64();
    let (error, stopped) = outcome(result);
    let samples = wheelsets.first().map(|w| w.1.clone()).unwrap_or_default();
    let simulated_s = samples.last().map_or(0.0, |s| s.t);
    let all: Vec<Sample> = wheelsets.iter().flat_map(|w| w.1.iter().copied()).collect();
    let mut summary = summarise(
        scene,
        sim,
        contact,
        &all,
        simulated_s,
        wall_s,
        preprocessing_s,
        &stats,
        error,
    );
    summary.stopped = stopped;
    Ok(RunOutput {
        samples,
        wheelsets,
        bodies,
        settling: Some(settling),
        summary,
    })
}

fn run_single(
    scene: &Scene,
    sim: &SimulationSpec,
    w: &super::spec::WheelsetOnFrameSpec,
    contact: ContactKind,
    speed: f64,
    progress: &mut dyn FnMut(f64),
) -> Result<RunOutput, String> {
    let t_pre = Instant::now();
    let model = build_contact_with(scene, contact, sim.kec_two_point_approach_m)?;
    let preprocessing_s = t_pre.elapsed().as_secs_f64();
    let r0 = scene.pair.wheelset.nominal_radius_m;
    let mut sys = SingleWheelset::new(
        WheelsetInertia {
            mass_kg: w.wheelset.mass_kg,
            inertia_kg_m2: w.wheelset.inertia_kg_m2,
            irw: None,
        },
        Tie {
            longitudinal_stiffness_n_per_m: w.tie.longitudinal_stiffness_n_per_m,
            lateral_stiffness_n_per_m: w.tie.lateral_stiffness_n_per_m,
            longitudinal_damping_n_s_per_m: w.tie.longitudinal_damping_n_s_per_m,
            lateral_damping_n_s_per_m: w.tie.lateral_damping_n_s_per_m,
            half_spacing_m: w.tie.half_spacing_m,
        },
        w.axle_load_n,
        SpeedProfile {
            initial_m_s: speed,
            ramp_m_s2: sim.speed_ramp_m_s2,
        },
        model,
        scene.contact_forces.clone(),
        r0,
    );
    sys.track = scene.track.clone();
    if let Some(track) = &scene.track {
        sys.s0 = track.centreline.range().0;
    }
    if let Some(s0) = sim.start_m {
        sys.s0 = s0;
    }
    let x0 = sys.initial_state(sim.initial.lateral_m, sim.initial.yaw_rad);
    let settings = integrator_settings(sim, contact);
    let dt_out = 1.0 / sim.record_rate_hz;
    let mut samples: Vec<Sample> = Vec::new();
    let duration = sim.duration_s;
    // The observer re-evaluates the model at the output state for the forces (a second instance,
    // so that the integrator's warm starts are untouched).
    let mut observer_sys = sys.clone_for_output();
    let t_run = Instant::now();
    let mut last_progress = 0.0;
    let stop = sim.stop_lateral_m;
    let mut stats = Stats::default();
    let result = integrate_into(
        &mut sys,
        0.0,
        &x0,
        duration,
        dt_out,
        &settings,
        &mut |t, x| {
            let s = observer_sys.sample(t, x)?;
            samples.push(to_sample(t, &s, r0));
            check_stop(t, stop, std::slice::from_ref(&s))?;
            tick(t, duration, &mut last_progress, progress);
            Ok(())
        },
        &mut stats,
    );
    let wall_s = t_run.elapsed().as_secs_f64();
    let (error, stopped) = outcome(result);
    let simulated_s = samples.last().map_or(0.0, |s| s.t);
    let mut summary = summarise(
        scene,
        sim,
        contact,
        &samples,
        simulated_s,
        wall_s,
        preprocessing_s,
        &stats,
        error,
    );
    summary.stopped = stopped;
    if sim.speed_ramp_m_s2 != 0.0 {
        summary.critical_speed_m_s = hunting_onset(&samples, 2.0);
    }
    Ok(RunOutput {
        wheelsets: vec![("wheelset_1".to_string(), samples.clone())],
        samples,
        bodies: Vec::new(),
        settling: None,
        summary,
    })
}

/// The output sample of one wheelset evaluation (Y and Q per wheel in the track frame).
pub fn to_sample(t: f64, s: &super::single_wheelset::WheelsetSample, r0: f64) -> Sample {
    let d = &s.dynamics;
    let mut y_force = [0.0; 2];
    let mut q_force = [0.0; 2];
    for i in 0..2 {
        let n = s.kin.contacts[i].normal;
        // Normal force along the rail normal plus the creep force's lateral/vertical components
        // (the contact frame's t₂ lies in the cross-section: (0, n_z, −n_y) up to the yaw).
        let (ny, nz) = n;
        y_force[i] = d.normal[i] * ny + d.creep[i].fy * nz;
        q_force[i] = d.normal[i] * nz - d.creep[i].fy * ny;
    }
    Sample {
        t,
        s: s.s,
        speed: s.speed,
        y: s.state.y,
        yaw: s.state.psi,
        z: s.kin.z - r0,
        roll: s.kin.phi,
        normal: d.normal,
        creep_x: [d.creep[0].fx, d.creep[1].fx],
        creep_y: [d.creep[0].fy, d.creep[1].fy],
        y_force,
        q_force,
        s_wheel: [s.kin.contacts[0].s_wheel, s.kin.contacts[1].s_wheel],
        s_rail: [s.kin.contacts[0].s_rail, s.kin.contacts[1].s_rail],
        position: [s.kin.contacts[0].position, s.kin.contacts[1].position],
        s_knife: s.kin.s_knife,
        rails: s.rails,
    }
}

#[allow(clippy::too_many_arguments)]
fn summarise(
    scene: &Scene,
    sim: &SimulationSpec,
    contact: ContactKind,
    samples: &[Sample],
    simulated_s: f64,
    wall_s: f64,
    preprocessing_s: f64,
    stats: &Stats,
    error: Option<String>,
) -> RunSummary {
    let fold = |f: &dyn Fn(&Sample) -> f64| samples.iter().map(f).fold(0.0_f64, f64::max);
    RunSummary {
        scene: scene.name.clone(),
        contact_model: contact.name().to_string(),
        creep_model: scene.contact_forces.model.name().to_string(),
        integrator: format!("{:?}", sim.integrator.method).to_lowercase(),
        simulated_s,
        wall_s,
        realtime_factor: if wall_s > 0.0 { simulated_s / wall_s } else { 0.0 },
        steps: stats.accepted,
        rejected_steps: stats.rejected,
        rhs_evaluations: stats.rhs_evaluations,
        preprocessing_s,
        max_abs_y_mm: fold(&|s| s.y.abs() * 1e3),
        max_abs_yaw_mrad: fold(&|s| s.yaw.abs() * 1e3),
        max_normal_n: fold(&|s| s.normal[0].max(s.normal[1])),
        min_normal_n: samples
            .iter()
            .map(|s| s.normal[0].min(s.normal[1]))
            .fold(f64::INFINITY, f64::min),
        max_abs_y_over_q: fold(&|s| {
            (s.y_force[0] / s.q_force[0])
                .abs()
                .max((s.y_force[1] / s.q_force[1]).abs())
        }),
        error,
        stopped: None,
        critical_speed_m_s: None,
    }
}

/// Writes one CSV per wheelset into `dir` (`wheelset_1.csv`): `t_s, s_m, speed_m_s, y_mm,
/// yaw_mrad, z_mm, roll_mrad, n_left_n, n_right_n, fx_left_n, fy_left_n, fx_right_n, fy_right_n,
/// y_left_n, q_left_n, y_right_n, q_right_n, s_wheel_left_mm, s_rail_left_mm, s_wheel_right_mm,
/// s_rail_right_mm`.
/// One CSV per wheelset, `DIR/NAME.csv`.
pub fn write_csvs(
    dir: &std::path::Path,
    wheelsets: &[(String, Vec<Sample>)],
) -> Result<Vec<std::path::PathBuf>, csv::Error> {
    wheelsets
        .iter()
        .map(|(name, samples)| write_csv(dir, name, samples))
        .collect()
}

/// The CSV of one wheelset, `DIR/NAME.csv`.
pub fn write_csv(
    dir: &std::path::Path,
    name: &str,
    samples: &[Sample],
) -> Result<std::path::PathBuf, csv::Error> {
    std::fs::create_dir_all(dir)?;
    let path = dir.join(format!("{name}.csv"));
    let mut w = csv::Writer::from_path(&path)?;
    w.write_record([
        "t_s",
        "s_m",
        "speed_m_s",
        "y_mm",
        "yaw_mrad",
        "z_mm",
        "roll_mrad",
        "n_left_n",
        "n_right_n",
        "fx_left_n",
        "fy_left_n",
        "fx_right_n",
        "fy_right_n",
        "y_left_n",
        "q_left_n",
        "y_right_n",
        "q_right_n",
        "s_wheel_left_mm",
        "s_rail_left_mm",
        "s_wheel_right_mm",
        "s_rail_right_mm",
        "rail_y_left_mm",
        "rail_z_left_mm",
        "rail_y_right_mm",
        "rail_z_right_mm",
    ])?;
    for s in samples {
        let v = [
            s.t,
            s.s,
            s.speed,
            s.y * 1e3,
            s.yaw * 1e3,
            s.z * 1e3,
            s.roll * 1e3,
            s.normal[0],
            s.normal[1],
            s.creep_x[0],
            s.creep_y[0],
            s.creep_x[1],
            s.creep_y[1],
            s.y_force[0],
            s.q_force[0],
            s.y_force[1],
            s.q_force[1],
            s.s_wheel[0] * 1e3,
            s.s_rail[0] * 1e3,
            s.s_wheel[1] * 1e3,
            s.s_rail[1] * 1e3,
            s.rails[0] * 1e3,
            s.rails[1] * 1e3,
            s.rails[2] * 1e3,
            s.rails[3] * 1e3,
        ];
        w.write_record(v.iter().map(|x| format!("{x:.9e}")))?;
    }
    w.flush()?;
    Ok(path)
}
