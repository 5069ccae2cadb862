//! `kecsim compare SCENARIO [--contact kec,lookup,...] [--duration S]`: the same scene with several
//! contact models, each wheelset's differences from the first model (max and RMS of Δy, Δψ against
//! the paper's 1 mm / 0.5 mrad) and each run's cost, printed and recorded (the paper's Fig. 18–19).

use std::path::{Path, PathBuf};

use anyhow::Result;
use clap::Args;

use kecsim::contact::ContactModelSpec;
use kecsim::inspect;
use kecsim::scenario::Scenario;

use super::SinkArgs;

#[derive(Args)]
pub(super) struct CompareArgs {
    /// Scenario file (TOML) with a [simulation].
    scenario: PathBuf,
    /// Contact models to compare, the first the reference [default: kec, lookup, lookup2].
    #[arg(long, value_delimiter = ',', value_parser = super::contact_model_names())]
    contact: Vec<String>,
    /// Simulated time, s [default: the scenario's].
    #[arg(long, value_name = "S")]
    duration: Option<f64>,
    #[command(flatten)]
    sink: SinkArgs,
}

pub(super) fn run(a: CompareArgs) -> Result<()> {
    let models = if a.contact.is_empty() {
        ["kec", "lookup", "lookup2"]
            .iter()
            .filter(|m| ContactModelSpec::NAMES.contains(m))
            .map(|m| m.to_string())
            .collect()
    } else {
        a.contact.clone()
    };
    super::check_duration(a.duration)?;
    let sink = a.sink.sink();
    let origin = a.scenario.display().to_string();
    let mut scene =
        Scenario::read(&a.scenario)?.compile(&origin, a.scenario.parent().unwrap_or(Path::new(".")))?;
    let _outputs = super::guard_scene(&scene, Some(&a.scenario), &[], &sink)?;
    scene.table_cache = super::table_cache();
    anyhow::ensure!(
        scene.simulation.is_some(),
        "{origin}: this scenario has no [simulation] to compare"
    );
    let progress = super::progress::Runs::new(&models);
    let c = {
        let mut observer = progress;
        let c = kecsim::compare::compare_observed(&scene, &models, a.duration, Some(&mut observer));
        observer.finish();
        c?
    };
    let delivered = {
        let rec = inspect::open_recording("kecsim", &sink, || inspect::compare::blueprint(&c))?;
        inspect::compare::record(&rec, &c, &scene)?;
        inspect::finish_recording(rec, &sink)
    };
    print!("{}", c.markdown());
    println!("{}", delivered.map_err(anyhow::Error::msg)?);
    let failed = kecsim::compare::incomplete_runs(&c.runs);
    anyhow::ensure!(
        failed.is_empty(),
        "{} of {} runs did not complete: {} — the differences cover only the {:.2} s every run covers",
        failed.len(),
        c.runs.len(),
        failed.join(", "),
        c.common_s
    );
    Ok(())
}
