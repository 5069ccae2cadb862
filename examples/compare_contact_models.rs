//! Run one scene with every contact model and watch the runs through an observer of your own —
//! the library's interfaces behind `kecsim run`: compile a scenario, build its run with a contact
//! model, attach observers, run.
//!
//! ```sh
//! cargo run --release --example compare_contact_models -- assets/scenes/bogie_tab6_curve.toml 3
//! ```

use std::path::Path;

use kecsim::contact::ContactModelSpec;
use kecsim::dynamics::output::{ObserverError, OutputSample, RunObserver};
use kecsim::scenario::{RunOptions, Scenario};

/// Prints the leading wheelset's lateral displacement and yaw once per simulated second.
struct EverySecond {
    next_t: f64,
}

impl RunObserver for EverySecond {
    fn sample(&mut self, s: &OutputSample<'_>) -> Result<(), ObserverError> {
        if s.t >= self.next_t {
            let w = &s.wheelsets[0];
            println!(
                "  t = {:5.2} s  s = {:7.2} m  y = {:+7.3} mm  yaw = {:+7.3} mrad  Q = {:5.1} / {:5.1} kN",
                s.t,
                w.s,
                w.y * 1e3,
                w.yaw * 1e3,
                w.normal[0] * 1e-3,
                w.normal[1] * 1e-3
            );
            self.next_t += 1.0;
        }
        Ok(())
    }
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let path = Path::new(
        args.first()
            .map_or("assets/scenes/bogie_tab6_curve.toml", |s| s.as_str()),
    );
    let duration: f64 = args.get(1).map_or(Ok(3.0), |s| s.parse())?;
    let origin = path.display().to_string();
    let scene = Scenario::read(path)?.compile(&origin, path.parent().unwrap_or(Path::new(".")))?;
    for &model in ContactModelSpec::NAMES.iter().filter(|&&m| m != "online") {
        let mut run = scene.build_run(&RunOptions {
            contact: Some(model.to_string()),
            speed_m_s: None,
            ..Default::default()
        })?;
        run.settings.duration_s = duration;
        println!(
            "{} with {model} (preprocessing {:.2} s):",
            scene.name, run.labels.preprocessing_s
        );
        let out = run.run(&mut [&mut EverySecond { next_t: 0.0 }]);
        print!("{}", out.summary);
    }
    Ok(())
}
