//! `kecsim bench precision [SCENE]`: the work–precision diagram of a scene — for each contact model
//! and integrator, a sweep of tolerances giving the wall time against the error, the error measured
//! against one reference run of the same scene (by default the online contact model, which solves
//! the real profiles on the displaced rails directly, integrated by DOPRI5 at rtol 1e-8). Each row
//! is one run; the error is the largest |Δy| and |Δψ| over every wheelset and output sample, so it
//! holds the contact model's own difference from the reference (its floor) and the integration
//! error together.
//!
//! From the rows: the cost of each contact model at equal error — the cheapest run whose error is
//! within a level — and the ratios the paper's claims rest on (KEC against the lookup tables:
//! 0.80 in the paper; KEC against online contact: ≥ 5× cheaper).

use crate::dynamics::integrator::Method;
use crate::dynamics::RunOutput;
use crate::scenario::{RunOptions, Scene};

use super::dynamics::{differences, differences_until};
pub use crate::compare::precision::{Precision, PrecisionRow};

/// What the sweep runs and what it is measured against.
#[derive(Debug, Clone, PartialEq)]
pub struct PrecisionSettings {
    /// Contact models swept.
    pub contacts: Vec<String>,
    /// Integrators swept.
    pub methods: Vec<Method>,
    /// Relative tolerances swept (each run's atol keeps the scene's atol/rtol ratio).
    pub rtols: Vec<f64>,
    /// The reference run: contact model, integrator and rtol (atol as the sweep's).
    pub reference: (String, Method, f64),
    /// Simulated time, s (None: the scene's).
    pub duration_s: Option<f64>,
    /// The draws: the initial lateral velocity of every wheelset (`[simulation.initial]
    /// lateral_velocity_m_s`), m/s, one sweep and its own reference per draw (empty: one draw,
    /// the scene's own initial state). A run's error is one draw of a trajectory that a
    /// micrometre per second moves by tens of µm: a claim rests on several ([`protocol_draws`]).
    pub draws: Vec<f64>,
}

/// The precision protocol's draws: `n` initial lateral velocities 0, 1, …, n − 1 µm/s.
pub fn protocol_draws(n: usize) -> Vec<f64> {
    (0..n).map(|k| k as f64 * 1e-6).collect()
}

/// The median of `v` (the mean of the middle two for an even count; NaN for none).
fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    match n {
        0 => f64::NAN,
        _ if n % 2 == 1 => v[n / 2],
        _ => 0.5 * (v[n / 2 - 1] + v[n / 2]),
    }
}

impl Default for PrecisionSettings {
    fn default() -> Self {
        PrecisionSettings {
            contacts: ["kec", "lookup", "lookup2", "online"].map(String::from).to_vec(),
            methods: vec![Method::Bdf, Method::Radau5, Method::Dopri5],
            rtols: vec![1e-3, 1e-4, 1e-5],
            reference: ("online".to_string(), Method::Dopri5, 1e-8),
            duration_s: None,
            draws: Vec::new(),
        }
    }
}

/// The outcome of a run in words.
pub(super) fn outcome(o: &RunOutput) -> String {
    let s = &o.summary;
    match (&s.error, &s.stopped) {
        (Some(e), _) => format!("failed: {e}"),
        (None, Some(st)) => format!("stopped: {st}"),
        _ => s.outcome.to_string(),
    }
}

/// Runs the sweep on `scene`, once per draw ([`PrecisionSettings::draws`]), each draw against
/// its own reference; a row's error is the largest over the draws (and the median beside it).
pub fn precision(scene: &Scene, settings: &PrecisionSettings) -> Result<Precision, String> {
    let draws: Vec<Option<f64>> = match settings.draws.is_empty() {
        true => vec![None],
        false => settings.draws.iter().map(|&v| Some(v)).collect(),
    };
    for v in draws.iter().flatten() {
        if !(v.is_finite() && v.abs() <= 1.0) {
            return Err(format!(
                "draw {v} m/s: expected an initial lateral velocity within ±1 m/s"
            ));
        }
    }
    let mut each = Vec::with_capacity(draws.len());
    for &v in &draws {
        let mut drawn = scene.clone();
        if let (Some(v), Some((sim, _))) = (v, drawn.simulation.as_mut()) {
            sim.initial.lateral_velocity_m_s = v;
        }
        each.push(precision_of_one_draw(&drawn, settings)?);
    }
    let first = &each[0];
    let rows = (0..first.rows.len())
        .map(|k| {
            let of = |f: fn(&PrecisionRow) -> f64| each.iter().map(|p| f(&p.rows[k])).collect::<Vec<f64>>();
            let max = |f: fn(&PrecisionRow) -> f64| of(f).into_iter().fold(0.0f64, f64::max);
            let r = &first.rows[k];
            PrecisionRow {
                wall_s: median(of(|r| r.wall_s)),
                preprocessing_s: median(of(|r| r.preprocessing_s)),
                realtime_factor: median(of(|r| r.realtime_factor)),
                steps: median(of(|r| r.steps as f64)).round() as usize,
                rhs_evaluations: median(of(|r| r.rhs_evaluations as f64)).round() as usize,
                outcome: match each.iter().position(|p| p.rows[k].outcome != "completed") {
                    Some(d) if each.len() > 1 => format!("draw {}: {}", d + 1, each[d].rows[k].outcome),
                    Some(d) => each[d].rows[k].outcome.clone(),
                    None => "completed".to_string(),
                },
                max_dy: max(|r| r.max_dy),
                max_dpsi: max(|r| r.max_dpsi),
                single_point_s: of(|r| r.single_point_s).into_iter().fold(f64::INFINITY, f64::min),
                single_point_max_dy: max(|r| r.single_point_max_dy),
                single_point_max_dpsi: max(|r| r.single_point_max_dpsi),
                median_max_dy: median(of(|r| r.max_dy)),
                median_max_dpsi: median(of(|r| r.max_dpsi)),
                ..r.clone()
            }
        })
        .collect();
    Ok(Precision {
        scene: first.scene.clone(),
        simulated_s: first.simulated_s,
        reference: first.reference.clone(),
        reference_wall_s: median(each.iter().map(|p| p.reference_wall_s).collect()),
        rows,
        draws,
    })
}

/// One draw's sweep: the reference run, then every row against it.
fn precision_of_one_draw(scene: &Scene, settings: &PrecisionSettings) -> Result<Precision, String> {
    let mut scene = scene.clone();
    let (sim, _) = scene
        .simulation
        .as_mut()
        .ok_or_else(|| format!("{}: this scenario has no [simulation]", scene.name))?;
    if let Some(d) = settings.duration_s {
        sim.duration_s = d;
    }
    let (simulated_s, atol_per_rtol) = (sim.duration_s, sim.integrator.atol / sim.integrator.rtol);
    if settings.rtols.is_empty() || settings.contacts.is_empty() || settings.methods.is_empty() {
        return Err("the sweep needs at least one contact model, integrator and rtol".to_string());
    }
    for &r in settings.rtols.iter().chain([&settings.reference.2]) {
        if !(r.is_finite() && (1e-14..=1e-1).contains(&r)) {
            return Err(format!("rtol {r}: expected 1e-14 ..= 0.1"));
        }
    }
    let run = |contact: &str, method: Method, rtol: f64| -> Result<RunOutput, String> {
        let mut built = scene
            .build_run(&RunOptions {
                contact: Some(contact.to_string()),
                speed_m_s: None,
                ..Default::default()
            })
            .map_err(|e| e.to_string())?;
        built.settings.integrator.method = method;
        built.settings.integrator.rtol = rtol;
        built.settings.integrator.atol = atol_per_rtol * rtol;
        Ok(built.run(&mut []))
    };
    let (rc, rm, rr) = &settings.reference;
    let reference = run(rc, *rm, *rr)?;
    let reference_outcome = outcome(&reference);
    if reference_outcome != "completed" {
        return Err(format!(
            "the reference run ({rc}, {rm:?} rtol {rr:.0e}) did not complete: {reference_outcome}"
        ));
    }
    // A jump-free pair keeps every run in single-point contact (see `Comparison::pair_jumps`).
    let pair_jumps = crate::compare::pair_has_jumps(&scene.pair);
    let jump = |o: &RunOutput| {
        if pair_jumps {
            crate::compare::first_contact_jump(o).map_or(f64::INFINITY, |j| j.0)
        } else {
            f64::INFINITY
        }
    };
    let reference_jump = jump(&reference);
    let mut rows = Vec::new();
    for contact in &settings.contacts {
        for &method in &settings.methods {
            for &rtol in &settings.rtols {
                let o = run(contact, method, rtol)?;
                let (max_dy, max_dpsi) = differences(&reference, &o);
                let single_point_s = jump(&o).min(reference_jump).min(o.summary.simulated_s);
                let (single_point_max_dy, single_point_max_dpsi) =
                    differences_until(&reference, &o, single_point_s);
                let s = &o.summary;
                rows.push(PrecisionRow {
                    contact: contact.clone(),
                    method,
                    rtol,
                    wall_s: s.wall_s,
                    preprocessing_s: s.preprocessing_s,
                    realtime_factor: s.realtime_factor,
                    simulated_s: s.simulated_s,
                    steps: s.steps,
                    rhs_evaluations: s.rhs_evaluations,
                    outcome: outcome(&o),
                    max_dy,
                    max_dpsi,
                    single_point_s,
                    single_point_max_dy,
                    single_point_max_dpsi,
                    median_max_dy: max_dy,
                    median_max_dpsi: max_dpsi,
                });
            }
        }
    }
    Ok(Precision {
        scene: scene.name.clone(),
        simulated_s,
        reference: format!("{rc}, {rm:?} rtol {rr:.0e}, atol {:.0e}", atol_per_rtol * rr),
        reference_wall_s: reference.summary.wall_s,
        rows,
        draws: vec![scene
            .simulation
            .as_ref()
            .map(|(sim, _)| sim.initial.lateral_velocity_m_s)],
    })
}
