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

use std::fmt::Write as _;

use crate::dynamics::integrator::Method;
use crate::dynamics::RunOutput;
use crate::scenario::{RunOptions, Scene};

use super::dynamics::{differences, differences_until};

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
            methods: vec![Method::Bdf, Method::Dopri5],
            rtols: vec![1e-3, 1e-4, 1e-5],
            reference: ("online".to_string(), Method::Dopri5, 1e-8),
            duration_s: None,
        }
    }
}

/// One run of the sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct PrecisionRow {
    pub contact: String,
    pub method: Method,
    pub rtol: f64,
    /// Integration wall time, s (preprocessing excluded, as in the real-time factor).
    pub wall_s: f64,
    pub preprocessing_s: f64,
    pub realtime_factor: f64,
    pub simulated_s: f64,
    pub steps: usize,
    pub rhs_evaluations: usize,
    /// `completed`, or how the run ended (`failed: …` and the like): its error then covers only
    /// the samples it has and is not used for the cost at equal error.
    pub outcome: String,
    /// Largest |Δy| (m) and |Δψ| (rad) from the reference over every wheelset and sample.
    pub max_dy: f64,
    pub max_dpsi: f64,
    /// The same up to the first real contact jump of this run or the reference
    /// ([`crate::compare::first_contact_jump`]), and that time, s: the error in single-point
    /// contact, apart from how the models treat the jumps.
    pub single_point_s: f64,
    pub single_point_max_dy: f64,
    pub single_point_max_dpsi: f64,
}

impl PrecisionRow {
    fn completed(&self) -> bool {
        self.outcome == "completed"
    }
}

/// The sweep's result.
#[derive(Debug, Clone, PartialEq)]
pub struct Precision {
    pub scene: String,
    pub simulated_s: f64,
    /// The reference run's description and its own cost.
    pub reference: String,
    pub reference_wall_s: f64,
    pub rows: Vec<PrecisionRow>,
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

impl Precision {
    /// The cheapest completed run of `contact` whose error is within (dy, dψ) (m, rad).
    pub fn cheapest_within(&self, contact: &str, dy: f64, dpsi: f64) -> Option<&PrecisionRow> {
        self.rows
            .iter()
            .filter(|r| r.contact == contact && r.completed() && r.max_dy <= dy && r.max_dpsi <= dpsi)
            .min_by(|a, b| a.wall_s.total_cmp(&b.wall_s))
    }

    /// Error levels (Δy m, Δψ rad) for the cost at equal error: the 0.05 mm / 0.05 mrad,
    /// the paper's 1 mm / 0.5 mrad, and between them 0.2 mm / 0.2 mrad.
    pub const LEVELS: [(f64, f64); 3] = [(0.05e-3, 0.05e-3), (0.2e-3, 0.2e-3), (1e-3, 0.5e-3)];

    /// The contact models swept, in order.
    pub fn contacts(&self) -> Vec<String> {
        let mut c: Vec<String> = Vec::new();
        for r in &self.rows {
            if !c.contains(&r.contact) {
                c.push(r.contact.clone());
            }
        }
        c
    }

    /// The report (Markdown): the rows, then the cost of each model at equal error and the
    /// ratios of the paper's claims.
    pub fn markdown(&self) -> String {
        let mut s = format!(
            "# kecsim bench precision: {}\n\n{:.2} s simulated; error = largest |Δy|, |Δψ| over every wheelset and output sample against the reference run ({}, {:.2} s wall); wall = integration time (preprocessing apart)\n\n",
            self.scene, self.simulated_s, self.reference, self.reference_wall_s
        );
        s += "| contact model | integrator | rtol | wall s | real-time factor | preprocessing s | steps | right-hand sides | max \\|Δy\\| [mm] | max \\|Δψ\\| [mrad] | outcome | to the first contact jump [s] | max \\|Δy\\| to it [mm] | max \\|Δψ\\| to it [mrad] |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
        for r in &self.rows {
            let _ = writeln!(
                s,
                "| {} | {:?} | {:.0e} | {:.3} | {:.2} | {:.2} | {} | {} | {:.4} | {:.4} | {} | {:.2} | {:.4} | {:.4} |",
                r.contact,
                r.method,
                r.rtol,
                r.wall_s,
                r.realtime_factor,
                r.preprocessing_s,
                r.steps,
                r.rhs_evaluations,
                r.max_dy * 1e3,
                r.max_dpsi * 1e3,
                r.outcome,
                r.single_point_s,
                r.single_point_max_dy * 1e3,
                r.single_point_max_dpsi * 1e3
            );
        }
        let contacts = self.contacts();
        s += "\nCost at equal error: the wall time of each contact model's cheapest completed run within the error level (— : no run of the sweep reaches it).\n\n| error level |";
        for c in &contacts {
            let _ = write!(s, " {c} |");
        }
        s += " kec / lookup | kec / lookup2 | online / kec |\n|---|";
        s += &"---|".repeat(contacts.len() + 3);
        s += "\n";
        for (dy, dpsi) in Self::LEVELS {
            let _ = write!(s, "| {} mm, {} mrad |", dy * 1e3, dpsi * 1e3);
            for c in &contacts {
                match self.cheapest_within(c, dy, dpsi) {
                    Some(r) => {
                        let _ = write!(s, " {:.3} s ({:?} {:.0e}) |", r.wall_s, r.method, r.rtol);
                    }
                    None => s += " — |",
                }
            }
            let ratio = |a: &str, b: &str| match (
                self.cheapest_within(a, dy, dpsi),
                self.cheapest_within(b, dy, dpsi),
            ) {
                (Some(x), Some(y)) if y.wall_s > 0.0 => format!("{:.2}", x.wall_s / y.wall_s),
                _ => "—".to_string(),
            };
            let _ = writeln!(
                s,
                " {} | {} | {} |",
                ratio("kec", "lookup"),
                ratio("kec", "lookup2"),
                ratio("online", "kec")
            );
        }
        s += "\nThe paper's claims: KEC costs 0.80 of the lookup tables (kec / lookup < 1), and online contact at least 5× KEC (online / kec ≥ 5).\n";
        s
    }
}
