//! `kecsim bench dynamics`: the real-time factor of every scene with every contact model, measured
//! in one run, with each model's difference from KEC on the same scene (lateral displacement and
//! yaw of every wheelset over the run) — the speed figure next to its error — the KEC run's
//! integration error against a reference run of the same scene with DOPRI5 at rtol 1e-9, and what
//! streaming the run to a recording costs (the KEC run again, with an `.rrd` file sink).
//!
//! The scenes are the repository's scene files, embedded; each runs over a window that shows what
//! it is for (durations below), so that the whole measurement takes a few minutes.

use std::fmt::Write as _;
use std::hint::black_box;
use std::time::Instant;

use crate::contact::{ContactModel, ContactModelSpec, WarmStart};
use crate::dynamics::integrator::Method;
use crate::dynamics::RunOutput;
use crate::inspect::{self, Sink};
use crate::scenario::{RunOptions, Scenario, Scene};
use crate::track::RailMotion;

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
    differences_until(a, b, f64::INFINITY)
}

/// [`differences`] over the samples up to time `t_end`, s.
pub fn differences_until(a: &RunOutput, b: &RunOutput, t_end: f64) -> (f64, f64) {
    let (mut dy, mut dpsi) = (0.0_f64, 0.0_f64);
    for ((_, sa), (_, sb)) in a.wheelsets.iter().zip(&b.wheelsets) {
        for (p, q) in sa.iter().zip(sb).take_while(|(p, _)| p.t <= t_end + 1e-9) {
            dy = dy.max((p.y - q.y).abs());
            dpsi = dpsi.max((p.yaw - q.yaw).abs());
        }
    }
    (dy, dpsi)
}

/// A scene of [`SCENES`], compiled, with its simulation cut to `window` seconds.
pub fn scene(name: &str, text: &str, window: f64) -> Result<Scene, String> {
    let scenario = Scenario::parse(text, name).map_err(|e| e.to_string())?;
    let mut scene = scenario
        .compile(name, std::path::Path::new("."))
        .map_err(|e| e.to_string())?;
    let (sim, _) = scene
        .simulation
        .as_mut()
        .ok_or_else(|| format!("{name}: no simulation"))?;
    sim.duration_s = window;
    Ok(scene)
}

/// Runs `scene` with the contact model `contact` (and the integrator settings edited by `edit`).
fn run_with(
    scene: &Scene,
    contact: &str,
    edit: impl Fn(&mut crate::dynamics::RunSettings),
    sink: Option<&Sink>,
) -> Result<RunOutput, String> {
    let mut built = scene
        .build_run(&RunOptions {
            contact: Some(contact.to_string()),
            speed_m_s: None,
            ..Default::default()
        })
        .map_err(|e| e.to_string())?;
    edit(&mut built.settings);
    Ok(match sink {
        None => built.run(&mut []),
        Some(sink) => {
            let mut rec = inspect::run::LiveRecorder::open(sink, scene, &built.vehicle.wheelset_names())
                .map_err(|e| e.to_string())?;
            built.run(&mut [&mut rec])
        }
    })
}

/// Runs every scene with every contact model and returns the table (Markdown).
pub fn dynamics() -> Result<String, String> {
    let mut out = String::from(
        "| scene | contact model | integrator (rtol) | simulated s | wall s | real-time factor | steps (rejected) | max Δy vs KEC [mm] | max Δψ vs KEC [mrad] |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    let mut streaming = String::from(
        "\n| scene | output samples | real-time factor without a sink | with an .rrd file sink | streaming cost |\n|---|---|---|---|---|\n",
    );
    let rrd = std::env::temp_dir().join(format!("kecsim-bench-{}.rrd", std::process::id()));
    for (name, text, window) in SCENES {
        let scene = scene(name, text, window)?;
        let (sim, _) = scene.simulation.as_ref().expect("checked by scene()");
        let mut kec: Option<RunOutput> = None;
        for &model in ContactModelSpec::NAMES {
            let o = run_with(&scene, model, |_| {}, None)?;
            let s = &o.summary;
            let diff = match &kec {
                Some(k) if model != "kec" => {
                    let (dy, dpsi) = differences(k, &o);
                    (format!("{:.4}", dy * 1e3), format!("{:.4}", dpsi * 1e3))
                }
                _ if model == "kec" => {
                    // The integration error: against DOPRI5 at rtol 1e-9 on the same scene.
                    let r = run_with(
                        &scene,
                        model,
                        |s| {
                            s.integrator.method = Method::Dopri5;
                            s.integrator.rtol = 1e-9;
                            s.integrator.atol = 1e-11;
                        },
                        None,
                    )?;
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
                "| {name} | {model} | {:?} ({:.0e}) | {:.2} | {:.3} | {:.2}{note} | {} ({}) | {} | {} |",
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
            if model == "kec" {
                // The same run streamed to a recording file (what `kecsim run --save` does).
                let streamed = run_with(&scene, model, |_| {}, Some(&Sink::Save(rrd.clone())))?;
                let (a, b) = (s.realtime_factor, streamed.summary.realtime_factor);
                let extra = streamed.summary.wall_s - s.wall_s;
                let (dy, _) = differences(&o, &streamed);
                let _ = writeln!(
                    streaming,
                    "| {name} | {} | {a:.2} | {b:.2} | {:+.1} % wall time ({:+.0} ms, {:+.1} µs per sample){} |",
                    s.samples,
                    (a / b - 1.0) * 100.0,
                    extra * 1e3,
                    extra * 1e6 / s.samples.max(1) as f64,
                    if dy == 0.0 { "" } else { " (results differ!)" }
                );
                kec = Some(o);
            }
        }
    }
    let _ = std::fs::remove_file(&rrd);
    out.push_str(
        "\nreal-time factor = simulated / wall time of the integration (the contact-table and KEC preprocessing excluded, reported by `kecsim run`); differences against the KEC run of the same scene, all wheelsets, all samples; the KEC row's integration error is its difference from the same scene integrated by DOPRI5 at rtol 1e-9, atol 1e-11\n",
    );
    out.push_str(&streaming);
    out.push_str("\nstreaming: the KEC run again with the live recorder writing an .rrd file as the samples come (batches every 1 s of wall time to a file); the samples are identical\n");
    out.push_str(&dispatch()?);
    Ok(out)
}

/// The cost of calling the contact model through the `dyn ContactModel` interface against calling
/// the concrete KEC model directly (static dispatch, inlinable), per `kinematics` call on random
/// lateral displacements — the measured justification of a trait object for the models.
pub fn dispatch() -> Result<String, String> {
    use crate::contact::models::kec::KecSettings;
    use crate::contact::models::ContactModelSettings;
    use crate::profile::placement::WheelRailPair;
    use crate::profile::StandardProfile;

    let pair = WheelRailPair::standard(StandardProfile::S1002, StandardProfile::Rail60E1, "1:40")
        .map_err(|e| e.to_string())?;
    let settings = KecSettings::default();
    let model = settings.build(&pair, None).map_err(|e| e.to_string())?;
    let concrete = settings.kec_contact(&pair).map_err(|e| e.to_string())?;
    let n = 20_000;
    let ys: Vec<f64> = (0..n)
        .map(|k| 6e-3 * ((k as f64 * 0.618_033_988_75).fract() * 2.0 - 1.0))
        .collect();
    let rails = RailMotion::default();
    // One pass over the points, s per call.
    let pass = |f: &dyn Fn(f64, &mut WarmStart) -> f64| {
        let mut warm = WarmStart::default();
        let t = Instant::now();
        let mut acc = 0.0;
        for &y in &ys {
            acc += f(black_box(y), &mut warm);
        }
        black_box(acc);
        t.elapsed().as_secs_f64() / n as f64
    };
    let dynamic: &dyn ContactModel = model.as_ref();
    // The whole result is kept (black_box), so that the inlined direct call cannot skip the work
    // whose result is unused.
    let via_dyn =
        |y: f64, w: &mut WarmStart| black_box(dynamic.kinematics(y, 0.01, &rails, w)).map_or(0.0, |k| k.z);
    let direct =
        |y: f64, w: &mut WarmStart| black_box(concrete.kinematics(y, 0.01, &rails, w)).map_or(0.0, |k| k.z);
    // Short passes in pairs, alternating which goes first (the machine's speed drifts); the
    // median of the pairs' ratios.
    let pairs = 41;
    let (mut t_dyn, mut t_static, mut ratio) = (Vec::new(), Vec::new(), Vec::new());
    for k in 0..pairs {
        let (d, s) = if k % 2 == 0 {
            let d = pass(&via_dyn);
            (d, pass(&direct))
        } else {
            let s = pass(&direct);
            (pass(&via_dyn), s)
        };
        t_dyn.push(d);
        t_static.push(s);
        ratio.push(d / s);
    }
    let median = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let (lo, hi) = {
        let mut r = ratio.clone();
        r.sort_by(f64::total_cmp);
        (r[pairs / 4], r[3 * pairs / 4])
    };
    Ok(format!(
        "\ncontact-model dispatch (KEC kinematics at {n} y per pass, {pairs} pairs of passes): through `dyn ContactModel` {:.0} ns/call, the concrete type {:.0} ns/call (medians); ratio dyn/concrete {:.3} (median; quartiles {:.3} .. {:.3}); a right-hand side of the Manchester vehicle costs ~30 µs\n",
        median(t_dyn) * 1e9,
        median(t_static) * 1e9,
        median(ratio),
        lo,
        hi
    ))
}
