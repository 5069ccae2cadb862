//! What streaming a run to an `.rrd` file costs: the scene run twice in one process, without a
//! sink and with the live recorder of `kecsim run --save`, each run's wall time (the recorded one
//! from opening the sink to the stream's end) and their ratio printed (the samples are the same; the recorder's threads compete with the run
//! where the cores are few).
//!
//! ```text
//! KECSIM_THREADS=1 taskset -c 0 cargo run --release --example recording_cost -- assets/scenes/ms_vehicle_tab6.toml [OUT.rrd] [PAIRS]
//! ```
//!
//! On one core (`taskset -c 0`, `KECSIM_THREADS=1`) the MS kilometre's recording measured
//! (2026-12-01, `farm-bench --pin 0`, 3 pairs) 1.09–1.19× the wall time, median 1.12, after the
//! batches to a file were made 1 s of wall time apart and the cross-sections sent as columns
//! with them; before, 1.17–1.47×, median 1.22 (batches every 50 ms, a log call per snapshot).
//! With the 3D view and the running bands (2026-12-03, a noisy VM, 3 pairs): 0.90–1.19×, median
//! 1.07 on one core; 0.98–1.21×, median 1.03 on two threads; the `.rrd` 26.3 → 34.3 MB.

use anyhow::{bail, Context, Result};
use kecsim::dynamics::Threads;
use kecsim::inspect::run::LiveRecorder;
use kecsim::inspect::Sink;
use kecsim::scenario::{RunOptions, Scenario};

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let [_, scene, rest @ ..] = args.as_slice() else {
        bail!("usage: recording_cost SCENE.toml [OUT.rrd] [PAIRS]");
    };
    let out = rest
        .first()
        .cloned()
        .unwrap_or_else(|| "recording_cost.rrd".to_string());
    let pairs: usize = match rest.get(1) {
        Some(p) => p.parse().with_context(|| format!("PAIRS: not a count: {p}"))?,
        None => 2,
    };
    let path = std::path::Path::new(scene);
    let base = path.parent().unwrap_or(std::path::Path::new("."));
    let scene = Scenario::read(path)?.compile(scene, base)?;
    // `KECSIM_THREADS` as the binary reads it: the runs' threads.
    let options = RunOptions {
        threads: std::env::var("KECSIM_THREADS")
            .ok()
            .and_then(|v| v.parse::<usize>().ok())
            .filter(|&n| n >= 1)
            .map_or(Threads::Default, Threads::Count),
        ..RunOptions::default()
    };
    let mut ratios = Vec::new();
    for pair in 0..pairs {
        let built = scene.build_run(&options)?;
        let t0 = std::time::Instant::now();
        let bare = built.run(&mut []);
        let bare_s = t0.elapsed().as_secs_f64();
        let built = scene.build_run(&options)?;
        let sink = Sink::Save(out.clone().into());
        // From opening the sink to the last byte written (the run and the stream's end).
        let t0 = std::time::Instant::now();
        let mut recorder = LiveRecorder::open(&sink, &scene, &built.vehicle.wheelset_names())?;
        let recorded = built.run(&mut [&mut recorder]);
        recorder.finish_stream(&sink).map_err(anyhow::Error::msg)?;
        let recorded_s = t0.elapsed().as_secs_f64();
        if bare.summary.steps != recorded.summary.steps {
            bail!(
                "the two runs differ: {} against {} steps",
                bare.summary.steps,
                recorded.summary.steps
            );
        }
        let ratio = recorded_s / bare_s;
        println!(
            "pair {}: {:.1} s simulated, {} steps: {:.3} s without a sink, {:.3} s recording to {out}: {ratio:.3}×",
            pair + 1,
            bare.summary.simulated_s,
            bare.summary.steps,
            bare_s,
            recorded_s
        );
        ratios.push(ratio);
    }
    ratios.sort_by(f64::total_cmp);
    println!(
        "recording cost: {:.3}× the wall time (median of {pairs})",
        ratios[ratios.len() / 2]
    );
    Ok(())
}
