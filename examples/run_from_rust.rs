//! kecsim from another Rust program, through the facade (`kecsim::api`): the embedded default
//! scene (the MS vehicle on the paper's kilometre) at three speeds over its first 200 m, each
//! run's front wheelset read from the result's columns (those of `kecsim run --csv`), with a
//! progress callback and a stop request that would end a run early (Ctrl-C in a program of one's
//! own). Needs no viewer: it builds with `--no-default-features`.
//!
//! `cargo run --release --example run_from_rust`

use kecsim::api::{run, Progress, RunConfig, SceneInput};
use kecsim::dynamics::CancelToken;

fn main() -> Result<(), kecsim::api::Error> {
    println!("speed m/s   samples   max |y| mm   max |yaw| mrad   max Y/Q   wall s");
    for speed in [10.0, 15.0, 19.0] {
        let mut input = SceneInput::embedded_default();
        input.set("simulation.speed_m_s", speed)?;
        input.set("simulation.duration_s", 200.0 / speed)?;
        let scene = input.compile()?;
        let mut last = 0.0;
        let config = RunConfig {
            threads: Some(2),
            cancel: CancelToken::new(),
            progress: Some(Box::new(|p: &Progress| last = p.t_s)),
            ..RunConfig::default()
        };
        let result = run(&scene, config)?;
        let front = &result.wheelsets[0];
        let max_abs = |name: &str| {
            front
                .column(name)
                .expect("a CSV column")
                .iter()
                .fold(0.0f64, |m, v| m.max(v.abs()))
        };
        println!(
            "{speed:9.1} {:9} {:12.3} {:16.3} {:9.3} {:8.2}",
            front.series.len(),
            max_abs("y_mm"),
            max_abs("yaw_mrad"),
            result.summary.max_abs_y_over_q,
            result.summary.wall_s
        );
        if let Some(why) = &result.failure {
            println!("  the run failed at t = {last:.3} s: {why}");
        }
    }
    Ok(())
}
