//! The paper's comparison (§8.3, Fig. 18–19) for any scene: the same run with several contact
//! models, each wheelset's lateral displacement and yaw against the first model's (the reference
//! of the comparison, KEC by default) — maximum and RMS of the difference over the time all runs
//! cover, against the paper's bounds (1 mm, 0.5 mrad) — and what each run cost.
//! `kecsim compare` prints it and records it ([`crate::inspect::compare`]).

pub mod precision;

use std::fmt::Write as _;

use crate::contact::geometry::ContactGeometry;
use crate::contact::lookup::{LookupTable1, TableSettings};
use crate::dynamics::RunOutput;
use crate::profile::placement::WheelRailPair;
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

/// The runs that did not complete ("MODEL (outcome)"): a comparison covers only the time every
/// run covers.
pub fn incomplete_runs(runs: &[ModelRun]) -> Vec<String> {
    runs.iter()
        .filter(|r| matches!(r.output.summary.outcome, "failed" | "derailed"))
        .map(|r| format!("{} ({})", r.model, r.output.summary.outcome))
        .collect()
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
    /// The model compared against: the comparison's first (KEC by default) or `online`, the
    /// independent reference.
    pub reference: String,
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
    /// Per wheelset, each model against the first; then, where `online` ran, each other model
    /// against it.
    pub differences: Vec<WheelsetDifference>,
    /// Whether the scene's pair has a contact jump on the ideal track (its 1-entry table's): a
    /// jump-free pair keeps every run in single-point contact, so the single-point window is the
    /// whole run (the heuristic of [`first_contact_jump`] would only find the fast but continuous
    /// sweeps of a near-conformal flange root).
    pub pair_jumps: bool,
    /// What the runs' builds said about their settings (a scenario's two-point transitions
    /// carried to another model, or not honoured by it).
    pub notes: Vec<String>,
}

/// Runs `scene` with each of `models` (the first is the reference) for `duration_s` (None: the
/// scene's), and compares.
pub fn compare(scene: &Scene, models: &[String], duration_s: Option<f64>) -> Result<Comparison, BuildError> {
    compare_observed(scene, models, duration_s, None)
}

/// [`compare`], each run's samples also handed to `observer` (a progress bar: its `start` comes
/// once a run, in the order of `models`).
pub fn compare_observed(
    scene: &Scene,
    models: &[String],
    duration_s: Option<f64>,
    mut observer: Option<&mut (dyn crate::dynamics::RunObserver + Send)>,
) -> Result<Comparison, BuildError> {
    if models.len() < 2 {
        return Err(BuildError::TooFewModels { got: models.len() });
    }
    // The duration asked for goes through the same checks as the scenario's (track end, samples).
    let mut scene = scene.clone();
    if let (Some(d), Some((sim, _))) = (duration_s, scene.simulation.as_mut()) {
        sim.duration_s = d;
    }
    let mut runs = Vec::with_capacity(models.len());
    let mut notes = Vec::new();
    for model in models {
        let built = scene.build_run(&RunOptions {
            contact: Some(model.clone()),
            speed_m_s: None,
            ..Default::default()
        })?;
        notes.extend(built.notes.iter().cloned());
        let output = match observer.as_mut() {
            Some(o) => built.run(&mut [&mut **o]),
            None => built.run(&mut []),
        };
        runs.push(ModelRun {
            model: model.clone(),
            output,
        });
    }
    let pair_jumps = pair_has_jumps(&scene.pair);
    let common_s = runs
        .iter()
        .map(|r| r.output.summary.simulated_s)
        .fold(f64::INFINITY, f64::min);
    let jump_of = |o: &RunOutput| {
        if pair_jumps {
            first_contact_jump(o).map_or(f64::INFINITY, |j| j.0)
        } else {
            f64::INFINITY
        }
    };
    let mut differences = Vec::new();
    let mut references: Vec<&ModelRun> = runs.iter().take(1).collect();
    references.extend(runs.iter().skip(1).filter(|r| r.model == "online"));
    for reference in references {
        let reference_jump = jump_of(&reference.output);
        for other in runs.iter().filter(|r| r.model != reference.model) {
            let single_point_s = jump_of(&other.output).min(reference_jump).min(common_s);
            for ((name, a), (_, b)) in reference.output.wheelsets.iter().zip(&other.output.wheelsets) {
                differences.push(difference(
                    name,
                    &reference.model,
                    &other.model,
                    a,
                    b,
                    common_s,
                    single_point_s,
                ));
            }
        }
    }
    Ok(Comparison {
        scene: scene.name.clone(),
        runs,
        common_s,
        differences,
        pair_jumps,
        notes,
    })
}

/// Whether `pair` has a contact jump on the ideal track, from flange contact to flange contact
/// (its 1-entry table's jumps; a pair whose table cannot be built counts as having them).
pub fn pair_has_jumps(pair: &WheelRailPair) -> bool {
    LookupTable1::build(
        &ContactGeometry::with_defaults(pair.clone()),
        &TableSettings::default(),
    )
    .map_or(true, |t| !t.jumps.is_empty())
}

/// One wheelset's differences between `model`'s samples `b` and `reference`'s `a` over the
/// common time, and up to `single_point_s`.
fn difference(
    wheelset: &str,
    reference: &str,
    model: &str,
    a: &[crate::dynamics::Sample],
    b: &[crate::dynamics::Sample],
    common_s: f64,
    single_point_s: f64,
) -> WheelsetDifference {
    let (mut n, mut max_dy, mut sum_dy, mut max_dpsi, mut sum_dpsi) = (0usize, 0.0_f64, 0.0, 0.0_f64, 0.0);
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
    WheelsetDifference {
        wheelset: wheelset.to_string(),
        model: model.to_string(),
        reference: reference.to_string(),
        samples: n,
        max_dy,
        rms_dy: rms(sum_dy),
        max_dpsi,
        rms_dpsi: rms(sum_dpsi),
        single_point_s,
        single_point_max_dy: single_dy,
        single_point_max_dpsi: single_dpsi,
    }
}

/// The paper's Tab. 7: computational time of KEC and of the lookup tables for its 52.6 s
/// simulated (Matlab, i7-6700HQ, ode15s with at most 0.02 s steps), s.
pub const PAPER_TAB7_S: (f64, f64) = (347.0, 434.0);

impl Comparison {
    /// The run of `model`, if it ran.
    pub fn run(&self, model: &str) -> Option<&ModelRun> {
        self.runs.iter().find(|r| r.model == model)
    }

    /// The cost lines (the paper's Tab. 7): each table model's cost against KEC's, integration
    /// alone (the paper's figure: its tables are built beforehand) and with the preprocessing.
    pub fn cost_lines(&self) -> String {
        let Some(kec) = self.run("kec") else {
            return String::new();
        };
        let k = &kec.output.summary;
        let mut s = format!(
            "\nCost (the paper's Tab. 7: KEC {:.0} s, tables {:.0} s for 52.6 s simulated — {:.2} and {:.2} × real time, KEC/tables {:.2}):\n\n",
            PAPER_TAB7_S.0,
            PAPER_TAB7_S.1,
            PAPER_TAB7_S.0 / 52.6,
            PAPER_TAB7_S.1 / 52.6,
            PAPER_TAB7_S.0 / PAPER_TAB7_S.1
        );
        for r in self.runs.iter().filter(|r| r.model != "kec") {
            let o = &r.output.summary;
            if o.simulated_s <= 0.0 || k.simulated_s <= 0.0 {
                continue;
            }
            // Per simulated second, so that runs that ended early compare fairly.
            let per = |w: f64, t: f64| w / t;
            let integration = per(k.wall_s, k.simulated_s) / per(o.wall_s, o.simulated_s);
            let whole = per(k.wall_s + k.preprocessing_s, k.simulated_s)
                / per(o.wall_s + o.preprocessing_s, o.simulated_s);
            let _ = writeln!(
                s,
                "* kec / {}: {:.2} integration alone ({:.3} / {:.3} s of computation per simulated s), {:.2} with the preprocessing (KEC {:.2} s, {} {:.2} s)",
                r.model,
                integration,
                k.wall_s / k.simulated_s,
                o.wall_s / o.simulated_s,
                whole,
                k.preprocessing_s,
                r.model,
                o.preprocessing_s
            );
        }
        s
    }

    /// The report: each run's outcome and cost, then each wheelset's differences (Markdown).
    /// The result first: each model against each reference, the largest difference over every
    /// wheelset, and whether it is within the paper's bounds on all of them (markdown bullets).
    pub fn result_lines(&self) -> String {
        let mut s =
            String::from("**Result** (the largest over every wheelset; the tables below have each):\n\n");
        let mut pairs: Vec<(&str, &str)> = self
            .differences
            .iter()
            .map(|d| (d.reference.as_str(), d.model.as_str()))
            .collect();
        pairs.dedup();
        let mut said: Vec<(&str, &str)> = Vec::new();
        for (reference, model) in pairs {
            // The same pair the other way round says nothing new.
            if said.contains(&(model, reference)) || said.contains(&(reference, model)) {
                continue;
            }
            said.push((reference, model));
            let of: Vec<&WheelsetDifference> = self
                .differences
                .iter()
                .filter(|d| d.reference == reference && d.model == model && d.samples >= 2)
                .collect();
            if of.is_empty() {
                continue;
            }
            let dy = of.iter().map(|d| d.max_dy).fold(0.0, f64::max);
            let dpsi = of.iter().map(|d| d.max_dpsi).fold(0.0, f64::max);
            let within = of.iter().all(|d| d.within_paper_bounds());
            let _ = writeln!(
                s,
                "- {model} against {reference}: max |Δy| {:.4} mm, max |Δψ| {:.4} mrad — {}",
                dy * 1e3,
                dpsi * 1e3,
                if within {
                    "within the paper's 1 mm / 0.5 mrad on every wheelset"
                } else {
                    "NOT within the paper's 1 mm / 0.5 mrad on every wheelset"
                }
            );
        }
        s
    }

    pub fn markdown(&self) -> String {
        let mut s = format!("# kecsim compare: {}\n\n", self.scene);
        s += &self.result_lines();
        s += "\n| contact model | simulated s | outcome | wall s | real-time factor | preprocessing s | steps (rejected) | right-hand sides |\n|---|---|---|---|---|---|---|---|\n";
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
        s += &self.cost_lines();
        if !self.notes.is_empty() {
            s += "\nSettings: ";
            s += &self.notes.join("; ");
            s += "\n";
        }
        let window = if self.pair_jumps {
            "up to the first real contact jump of either run on any wheel (the contact point moving > 5 mm on a wheel between two samples): there the models agree in single-point contact, beyond it each has its own two-point treatment"
        } else {
            "the pair has no contact jump on the ideal track (its 1-entry table), so every run stays in single-point contact: the window is the whole run"
        };
        let mut references: Vec<&str> = self.differences.iter().map(|d| d.reference.as_str()).collect();
        references.dedup();
        for reference in references {
            let paper = self.runs.first().is_some_and(|r| r.model == reference);
            let _ = write!(
                s,
                "\nDifferences from {reference}{} over the {:.2} s every run covers{}, and in single-point contact ({window}):\n\n| wheelset | contact model | max \\|Δy\\| [mm] | RMS Δy [mm] | max \\|Δψ\\| [mrad] | RMS Δψ [mrad] | within the paper's bounds | single-point window [s] | max \\|Δy\\| in it [mm] | max \\|Δψ\\| in it [mrad] |\n|---|---|---|---|---|---|---|---|---|---|\n",
                if reference == "online" { " (the approximate constraints solved at every evaluation: the independent reference)" } else { "" },
                self.common_s,
                if paper {
                    format!(" (the paper's bounds: {} mm, {} mrad)", PAPER_BOUNDS.0 * 1e3, PAPER_BOUNDS.1 * 1e3)
                } else {
                    String::new()
                }
            );
            for d in self.differences.iter().filter(|d| d.reference == reference) {
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
        }
        s
    }
}
