//! `kecsim bench dynamics`: the real-time factor of every scene with every contact model, measured
//! in one run, with each model's difference from KEC on the same scene (lateral displacement and
//! yaw of every wheelset over the run) — the speed figure next to its error — and the KEC run's
//! integration error against a reference run of the same scene with DOPRI5 at rtol 1e-9.
//!
//! The scenes are the repository's scene files, embedded; each runs over a window that shows what
//! it is for (durations below), so that the whole measurement takes a few minutes.

use std::fmt::Write as _;

use super::contact_model::ContactKind;
use super::integrator::Method;
use super::run::{run, RunOutput};
use crate::scenario::Scenario;

/// The embedded scenes and the simulated window the benchmark runs, s.
pub const SCENES: [(&str, &str, f64); 3] = [
    (
        "wheelset_klingel",
        include_str!("../../assets/scenes/wheelset_klingel.toml"),
        4.0,
    ),
    (
        "bogie_tab6_curve",
        include_str!("../../assets/scenes/bogie_tab6_curve.toml"),
        4.0,
    ),
    (
        "manchester_vehicle1_tab6",
        include_str!("../../assets/scenes/manchester_vehicle1_tab6.toml"),
        3.0,
    ),
];

/// Largest |Δy| and |Δψ| over all wheelsets and samples between two runs of one scene.
pub fn differences(a: &RunOutput, b: &RunOutput) -> (f64, f64) {
    let (mut dy, mut dpsi) = (0.0_f64, 0.0_f64);
    for ((_, sa), (_, sb)) in a.wheelsets.iter().zip(&b.wheelsets) {
        for (p, q) in sa.iter().zip(sb) {
            dy = dy.max((p.y - q.y).abs());
            dpsi = dpsi.max((p.yaw - q.yaw).abs());
        }
    }
    (dy, dpsi)
}

/// Runs every scene with every contact model and returns the table (Markdown).
pub fn dynamics(models: &[ContactKind]) -> Result<String, String> {
    let mut out = String::from(
        "| scene | contact model | integrator (rtol) | simulated s | wall s | real-time factor | steps (rejected) | max Δy vs KEC [mm] | max Δψ vs KEC [mrad] |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    for (name, text, window) in SCENES {
        let scenario = Scenario::parse(text, name).map_err(|e| e.to_string())?;
        let scene = scenario
            .compile(name, std::path::Path::new("."))
            .map_err(|e| e.to_string())?;
        let (mut sim, vehicle) = scene
            .simulation
            .clone()
            .ok_or_else(|| format!("{name}: no simulation"))?;
        sim.duration_s = window;
        let mut kec: Option<RunOutput> = None;
        for &kind in models {
            let o = run(&scene, &sim, &vehicle, kind, sim.speed_m_s, &mut |_| {})?;
            let s = &o.summary;
            let diff = match (&kec, kind) {
                (Some(k), ContactKind::Lookup | ContactKind::Lookup2 | ContactKind::Online) => {
                    let (dy, dpsi) = differences(k, &o);
                    (format!("{:.4}", dy * 1e3), format!("{:.4}", dpsi * 1e3))
                }
                (_, ContactKind::Kec) => {
                    // The integration error: against DOPRI5 at rtol 1e-9 on the same scene.
                    let mut tight = sim.clone();
                    tight.integrator.method = Method::Dopri5;
                    tight.integrator.rtol = 1e-9;
                    tight.integrator.atol = 1e-11;
                    let r = run(&scene, &tight, &vehicle, kind, sim.speed_m_s, &mut |_| {})?;
                    let (dy, dpsi) = differences(&r, &o);
                    (
                        format!("integration error {:.1e}", dy * 1e3),
                        format!("integration error {:.1e}", dpsi * 1e3),
                    )
                }
                _ => ("—".to_string(), "—".to_string()),
            };
            let note = match (&s.error, &s.stopped) {
                (Some(e), _) => format!(" (stopped: {e})"),
                _ => String::new(),
            };
            let _ = writeln!(
                out,
                "| {name} | {} | {:?} ({:.0e}) | {:.2} | {:.3} | {:.2}{note} | {} ({}) | {} | {} |",
                kind.name(),
                sim.integrator.method,
                sim.integrator.rtol,
                s.simulated_s,
                s.wall_s,
                s.realtime_factor,
                s.steps,
                s.rejected_steps,
                diff.0,
                diff.1
            );
            if kind == ContactKind::Kec {
                kec = Some(o);
            }
        }
    }
    out.push_str(
        "\nreal-time factor = simulated / wall time of the integration (the contact-table and KEC preprocessing excluded, reported by `kecsim run`); differences against the KEC run of the same scene, all wheelsets, all samples; the KEC row's integration error is its difference from the same scene integrated by DOPRI5 at rtol 1e-9, atol 1e-11\n",
    );
    Ok(out)
}
