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
}

impl Default for PrecisionSettings {
    fn default() -> Self {
        PrecisionSettings {
            contacts: ["kec", "lookup", "lookup2", "online"].map(String::from).to_vec(),
            methods: vec![Method::Bdf, Method::Radau5, Method::Dopri5],
            rtols: vec![1e-3, 1e-4, 1e-5],
            reference: ("online".to_string(), Method::Dopri5, 1e-8),
            duration_s: None,
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

/// Runs the sweep on `scene`.
pub fn precision(scene: &Scene, settings: &PrecisionSettings) -> Result<Precision, String> {
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
    })
}
