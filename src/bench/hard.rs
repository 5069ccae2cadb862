//! `kecsim bench hard`: the hard-case suite (issue 14) — flange impacts (one that lifts the far
//! wheel and lands it), a cross-level dip a wheel flies over, hunting with flange
//! contact, tight curves at low and line speed, a start from standstill, a gauge widening past the tables'
//! range, an alignment kink that makes a flange climb, the Manchester vehicle's kilometre under the
//! German high-disturbance spectrum and under FRA class 4 at 30 m/s — each
//! scene run with the elastic contact model (the reference: two-point contact, lift and landing
//! come from the real profiles) and with the constraint models named beside it. One table: how
//! each run ended (completed, stopped, derailed with the reason, or the model's own limit), its
//! steps and smallest step, the largest |y|, Y/Q and lift, its cost, and its difference from the
//! elastic run of the same scene.
//!
//! The scenes are `assets/scenes/hard/*.toml` (embedded, with the irregularity files they name,
//! written beside them into a temporary directory to be compiled).

use std::fmt::Write as _;

use super::dynamics::differences;
use crate::dynamics::RunOutput;
use crate::scenario::{RunOptions, Scenario, Scene};

/// One scene of the suite: its file name, text, the files it reads, and the contact models run
/// beside its own (elastic).
pub struct HardScene {
    pub name: &'static str,
    pub text: &'static str,
    pub files: &'static [(&'static str, &'static str)],
    pub also: &'static [&'static str],
}

/// The suite.
pub const HARD_SCENES: [HardScene; 11] = [
    HardScene {
        name: "flange_impact",
        text: include_str!("../../assets/scenes/hard/flange_impact.toml"),
        files: &[],
        also: &["kec"],
    },
    HardScene {
        name: "flange_lift",
        text: include_str!("../../assets/scenes/hard/flange_lift.toml"),
        files: &[],
        also: &["kec"],
    },
    HardScene {
        name: "cross_level_dip",
        text: include_str!("../../assets/scenes/hard/cross_level_dip.toml"),
        files: &[(
            "cross_level_dip.csv",
            include_str!("../../assets/scenes/hard/cross_level_dip.csv"),
        )],
        also: &["kec"],
    },
    HardScene {
        name: "hunting",
        text: include_str!("../../assets/scenes/hard/hunting.toml"),
        files: &[],
        also: &["kec"],
    },
    HardScene {
        name: "tight_curve_low",
        text: include_str!("../../assets/scenes/hard/tight_curve_low.toml"),
        files: &[],
        also: &["kec"],
    },
    HardScene {
        name: "tight_curve_line",
        text: include_str!("../../assets/scenes/hard/tight_curve_line.toml"),
        files: &[],
        also: &["kec"],
    },
    HardScene {
        name: "standstill",
        text: include_str!("../../assets/scenes/hard/standstill.toml"),
        files: &[],
        also: &["kec"],
    },
    HardScene {
        name: "gauge_widening",
        text: include_str!("../../assets/scenes/hard/gauge_widening.toml"),
        files: &[(
            "gauge_widening.csv",
            include_str!("../../assets/scenes/hard/gauge_widening.csv"),
        )],
        also: &["kec", "lookup2", "lookup2-paper"],
    },
    HardScene {
        name: "alignment_kink",
        text: include_str!("../../assets/scenes/hard/alignment_kink.toml"),
        files: &[(
            "alignment_kink.csv",
            include_str!("../../assets/scenes/hard/alignment_kink.csv"),
        )],
        also: &["kec"],
    },
    HardScene {
        name: "manchester_high",
        text: include_str!("../../assets/scenes/hard/manchester_high.toml"),
        files: &[],
        also: &["kec"],
    },
    HardScene {
        name: "manchester_fra4",
        text: include_str!("../../assets/scenes/hard/manchester_fra4.toml"),
        files: &[],
        also: &["kec"],
    },
];

/// One run of the suite.
pub struct HardRun {
    pub scene: &'static str,
    pub output: RunOutput,
    /// Largest |Δy| against the scene's elastic run over their common samples, m (None for the
    /// elastic run itself).
    pub dy_to_elastic: Option<f64>,
}

/// Compiles a suite scene (its files written beside it in a temporary directory), its simulated
/// time cut to `window` s where that is shorter.
pub fn compile(scene: &HardScene, window: Option<f64>) -> Result<Scene, String> {
    let dir = std::env::temp_dir().join(format!("kecsim-hard-{}-{}", std::process::id(), scene.name));
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    for (file, text) in scene.files {
        std::fs::write(dir.join(file), text).map_err(|e| format!("{file}: {e}"))?;
    }
    let path = dir.join(format!("{}.toml", scene.name));
    std::fs::write(&path, scene.text).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut compiled = Scenario::read(&path)
        .map_err(|e| e.to_string())?
        .compile(scene.name, &dir)
        .map_err(|e| e.to_string())?;
    let _ = std::fs::remove_dir_all(&dir);
    if let (Some(w), Some((sim, _))) = (window, compiled.simulation.as_mut()) {
        sim.duration_s = sim.duration_s.min(w);
    }
    Ok(compiled)
}

/// Runs every scene (`window`: at most that many simulated seconds each) with elastic contact
/// and the models beside it.
pub fn run_suite(window: Option<f64>) -> Result<Vec<HardRun>, String> {
    let mut runs = Vec::new();
    for hs in &HARD_SCENES {
        let scene = compile(hs, window)?;
        let elastic = run(&scene, "elastic")?;
        let others: Vec<RunOutput> = hs.also.iter().map(|m| run(&scene, m)).collect::<Result<_, _>>()?;
        let dys: Vec<f64> = others.iter().map(|o| differences(&elastic, o).0).collect();
        runs.push(HardRun {
            scene: hs.name,
            output: elastic,
            dy_to_elastic: None,
        });
        for (o, dy) in others.into_iter().zip(dys) {
            runs.push(HardRun {
                scene: hs.name,
                output: o,
                dy_to_elastic: Some(dy),
            });
        }
    }
    Ok(runs)
}

fn run(scene: &Scene, contact: &str) -> Result<RunOutput, String> {
    Ok(scene
        .build_run(&RunOptions {
            contact: Some(contact.to_string()),
            speed_m_s: None,
            ..Default::default()
        })
        .map_err(|e| e.to_string())?
        .run(&mut []))
}

/// How a run ended, in a few words: `completed`, `stopped: …`, `derailed at t s: …`, `failed at
/// t s: …`.
pub fn outcome(o: &RunOutput) -> String {
    let s = &o.summary;
    match (s.outcome, &s.error, &s.stopped) {
        ("completed", _, _) => "completed".to_string(),
        (_, _, Some(stop)) => format!("stopped: {stop}"),
        (kind, Some(e), _) => format!("{kind} at {:.4} s: {e}", s.simulated_s),
        (kind, None, None) => kind.to_string(),
    }
}

/// The suite's table (Markdown).
pub fn hard(window: Option<f64>) -> Result<String, String> {
    let runs = run_suite(window)?;
    let mut out = String::from(
        "| scene | contact model | outcome | simulated s | steps (rejected) | smallest step [µs] | max \\|y\\| [mm] | max Y/Q (2 m) | max \\|Y/Q\\| | min / max normal force [kN] | longest lift [s] (height [mm]) | wall s | real-time factor | max \\|Δy\\| vs elastic [mm] |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in &runs {
        let s = &r.output.summary;
        let y_over_q_2m = s
            .safety
            .as_ref()
            .map(|sf| sf.wheelsets.iter().map(|w| w.y_over_q_2m).fold(0.0, f64::max))
            .map_or("—".to_string(), |v| format!("{v:.3}"));
        let _ = writeln!(
            out,
            "| {} | {} | {} | {:.3} | {} ({}) | {:.2} | {:.2} | {y_over_q_2m} | {:.2} | {:.1} / {:.1} | {:.3} ({:.2}) | {:.2} | {:.2} | {} |",
            r.scene,
            s.contact_model,
            outcome(&r.output).replace('|', "/"),
            s.simulated_s,
            s.steps,
            s.rejected_steps,
            s.smallest_step_s * 1e6,
            s.max_abs_y_mm,
            s.max_abs_y_over_q,
            s.min_normal_n * 1e-3,
            s.max_normal_n * 1e-3,
            s.longest_lift_s,
            s.max_lift_mm,
            s.wall_s,
            s.realtime_factor,
            r.dy_to_elastic.map_or("reference".to_string(), |d| format!("{:.3}", d * 1e3)),
        );
    }
    out.push_str(
        "\nelastic: the reference (the wheelset free, Hertz contacts wherever the real profiles interpenetrate); max |Y/Q| is instantaneous (impacts), Y/Q (2 m) the EN 14363 style sliding mean; the difference to elastic over the common samples, every wheelset\n",
    );
    Ok(out)
}
