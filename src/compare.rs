//! The paper's comparison (§8.3, Fig. 18–19) for any scene: the same run with several contact
//! models, each wheelset's lateral displacement and yaw against the first model's (the reference
//! of the comparison, KEC by default) — maximum and RMS of the difference over the time all runs
//! cover, against the paper's bounds (1 mm, 0.5 mrad) — and what each run cost.
//! `kecsim compare` prints it and records it ([`crate::inspect::compare`]).

use std::fmt::Write as _;

use crate::dynamics::RunOutput;
use crate::scenario::{BuildError, RunOptions, Scene};

/// The paper's bounds on the difference between KEC and the lookup tables (§8.3): lateral
/// displacement, m, and yaw, rad.
pub const PAPER_BOUNDS: (f64, f64) = (1e-3, 0.5e-3);

/// A move of a wheel's contact point on the wheel profile between two output samples above which
/// it counts as a contact jump, m (tread → flange root: 20 mm on S1002; continuous motion moves it
/// by well under 1 mm in one sample at the output rates used).
pub const JUMP_MOVE_M: f64 = 5e-3;

/// The first real contact jump of a run on any of its wheels: the time of the last sample before
/// it and the wheelset — a wheel's contact point moving by more than [`JUMP_MOVE_M`] on the wheel
/// between two samples. None: every wheel stayed in single-point contact.
pub fn first_contact_jump(output: &RunOutput) -> Option<(f64, String)> {
    let mut first: Option<(f64, String)> = None;
    for (name, samples) in &output.wheelsets {
        let moved = samples
            .windows(2)
            .find(|w| (0..2).any(|i| (w[1].s_wheel[i] - w[0].s_wheel[i]).abs() > JUMP_MOVE_M));
        if let Some(w) = moved {
            if first.as_ref().is_none_or(|(t, _)| w[0].t < *t) {
                first = Some((w[0].t, name.clone()));
            }
        }
    }
    first
}

/// One model's run of the comparison.
pub struct ModelRun {
    pub model: String,
    pub output: RunOutput,
}

/// One wheelset's differences between a model and the reference model, over the common time.
#[derive(Debug, Clone, PartialEq)]
pub struct WheelsetDifference {
    pub wheelset: String,
    pub model: String,
    /// Samples compared.
    pub samples: usize,
    pub max_dy: f64,
    pub rms_dy: f64,
    pub max_dpsi: f64,
    pub rms_dpsi: f64,
    /// The time up to which neither run had a contact jump on any wheel ([`first_contact_jump`];
    /// the common time if none), s, and the largest |Δy| (m), |Δψ| (rad) up to it: the models'
    /// agreement in single-point contact, apart from how each treats the jumps.
    pub single_point_s: f64,
    pub single_point_max_dy: f64,
    pub single_point_max_dpsi: f64,
}

impl WheelsetDifference {
    /// Within the paper's bounds (max |Δy| < 1 mm and max |Δψ| < 0.5 mrad).
    pub fn within_paper_bounds(&self) -> bool {
        self.max_dy < PAPER_BOUNDS.0 && self.max_dpsi < PAPER_BOUNDS.1
    }
}

/// The runs and their differences.
pub struct Comparison {
    pub scene: String,
    pub runs: Vec<ModelRun>,
    /// Simulated time every run covers, s.
    pub common_s: f64,
    /// Per model after the first, per wheelset.
    pub differences: Vec<WheelsetDifference>,
}

/// Runs `scene` with each of `models` (the first is the reference) for `duration_s` (None: the
/// scene's), and compares.
pub fn compare(scene: &Scene, models: &[String], duration_s: Option<f64>) -> Result<Comparison, BuildError> {
    if models.len() < 2 {
        return Err(BuildError::Options(format!(
            "a comparison needs at least two contact models, got {}",
            models.len()
        )));
    }
    // The duration asked for goes through the same checks as the scenario's (track end, samples).
    let mut scene = scene.clone();
    if let (Some(d), Some((sim, _))) = (duration_s, scene.simulation.as_mut()) {
        sim.duration_s = d;
    }
    let mut runs = Vec::with_capacity(models.len());
    for model in models {
        let built = scene.build_run(&RunOptions {
            contact: Some(model.clone()),
            speed_m_s: None,
        })?;
        runs.push(ModelRun {
            model: model.clone(),
            output: built.run(&mut []),
        });
    }
    let common_s = runs
        .iter()
        .map(|r| r.output.summary.simulated_s)
        .fold(f64::INFINITY, f64::min);
    let mut differences = Vec::new();
    if let Some((reference, others)) = runs.split_first() {
        let reference_jump = first_contact_jump(&reference.output).map_or(f64::INFINITY, |j| j.0);
        for other in others {
            let single_point_s = first_contact_jump(&other.output)
                .map_or(f64::INFINITY, |j| j.0)
                .min(reference_jump)
                .min(common_s);
            for ((name, a), (_, b)) in reference.output.wheelsets.iter().zip(&other.output.wheelsets) {
                let (mut n, mut max_dy, mut sum_dy, mut max_dpsi, mut sum_dpsi) =
                    (0usize, 0.0_f64, 0.0, 0.0_f64, 0.0);
                let (mut single_dy, mut single_dpsi) = (0.0_f64, 0.0_f64);
                for (p, q) in a.iter().zip(b).take_while(|(p, _)| p.t <= common_s + 1e-9) {
                    let (dy, dpsi) = ((p.y - q.y).abs(), (p.yaw - q.yaw).abs());
                    max_dy = max_dy.max(dy);
                    max_dpsi = max_dpsi.max(dpsi);
                    sum_dy += dy * dy;
                    sum_dpsi += dpsi * dpsi;
                    n += 1;
                    if p.t <= single_point_s + 1e-9 {
                        single_dy = single_dy.max(dy);
                        single_dpsi = single_dpsi.max(dpsi);
                    }
                }
                let rms = |s: f64| if n > 0 { (s / n as f64).sqrt() } else { 0.0 };
                differences.push(WheelsetDifference {
                    wheelset: name.clone(),
                    model: other.model.clone(),
                    samples: n,
                    max_dy,
                    rms_dy: rms(sum_dy),
                    max_dpsi,
                    rms_dpsi: rms(sum_dpsi),
                    single_point_s,
                    single_point_max_dy: single_dy,
                    single_point_max_dpsi: single_dpsi,
                });
            }
        }
    }
    Ok(Comparison {
        scene: scene.name.clone(),
        runs,
        common_s,
        differences,
    })
}

impl Comparison {
    /// The report: each run's outcome and cost, then each wheelset's differences (Markdown).
    pub fn markdown(&self) -> String {
        let mut s = format!("# kecsim compare: {}\n\n", self.scene);
        s += "| contact model | simulated s | outcome | wall s | real-time factor | preprocessing s | steps (rejected) | right-hand sides |\n|---|---|---|---|---|---|---|---|\n";
        for r in &self.runs {
            let m = &r.output.summary;
            let outcome = match (&m.error, &m.stopped) {
                (Some(e), _) => format!("failed: {e}"),
                (None, Some(st)) => format!("stopped: {st}"),
                _ => m.outcome.to_string(),
            };
            let _ = writeln!(
                s,
                "| {} | {:.2} | {outcome} | {:.3} | {:.2} | {:.2} | {} ({}) | {} |",
                r.model,
                m.simulated_s,
                m.wall_s,
                m.realtime_factor,
                m.preprocessing_s,
                m.steps,
                m.rejected_steps,
                m.rhs_evaluations
            );
        }
        if let Some(reference) = self.runs.first() {
            let _ = write!(
                s,
                "\nDifferences from {} over the {:.2} s every run covers (the paper's bounds: {} mm, {} mrad), and up to the first real contact jump of either run on any wheel (the contact point moving > 5 mm on a wheel between two samples): there the models agree in single-point contact, beyond it each has its own two-point treatment:\n\n| wheelset | contact model | max \\|Δy\\| [mm] | RMS Δy [mm] | max \\|Δψ\\| [mrad] | RMS Δψ [mrad] | within the paper's bounds | to the first jump [s] | max \\|Δy\\| to it [mm] | max \\|Δψ\\| to it [mrad] |\n|---|---|---|---|---|---|---|---|---|---|\n",
                reference.model,
                self.common_s,
                PAPER_BOUNDS.0 * 1e3,
                PAPER_BOUNDS.1 * 1e3
            );
        }
        for d in &self.differences {
            let _ = writeln!(
                s,
                "| {} | {} | {:.4} | {:.4} | {:.4} | {:.4} | {} | {:.2} | {:.4} | {:.4} |",
                d.wheelset,
                d.model,
                d.max_dy * 1e3,
                d.rms_dy * 1e3,
                d.max_dpsi * 1e3,
                d.rms_dpsi * 1e3,
                if d.samples < 2 {
                    "— (no common samples)"
                } else if d.within_paper_bounds() {
                    "yes"
                } else {
                    "no"
                },
                d.single_point_s,
                d.single_point_max_dy * 1e3,
                d.single_point_max_dpsi * 1e3
            );
        }
        s
    }
}
