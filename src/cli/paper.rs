//! `kecsim paper [SCENARIO.toml] [--tables lookup2|lookup2-paper|lookup] [--duration S]`: the paper's case (the
//! embedded default scenario: the MS vehicle on the Tab. 6 track) run with KEC and with the
//! tables, its Fig. 14–19 recorded in one recording laid out as the paper's, and its Tab. 7 and
//! Fig. 18's summary printed beside the paper's numbers.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;

use kecsim::inspect;

use super::SinkArgs;

#[derive(Args)]
pub(super) struct PaperArgs {
    /// Scenario file (TOML) with a [simulation] and track sections; omit for the embedded default
    /// (the paper's case).
    scenario: Option<PathBuf>,
    /// The lookup-table model KEC is compared with: lookup2 (gauge variation per wheel), lookup2-paper
    /// (the paper's 2-entry table, 1 mm gauge columns) or lookup (1-entry).
    #[arg(long, default_value = "lookup2", value_parser = ["lookup2", "lookup2-paper", "lookup"])]
    tables: String,
    /// Simulated time, s [default: the scenario's].
    #[arg(long, value_name = "S")]
    duration: Option<f64>,
    #[command(flatten)]
    sink: SinkArgs,
}

pub(super) fn run(a: PaperArgs) -> Result<()> {
    super::check_duration(a.duration)?;
    let sink = a.sink.sink();
    let (parsed, origin, base) = super::read_scenario(a.scenario.as_deref())?;
    let mut scene = parsed.compile(&origin, &base)?;
    let _outputs = super::guard_scene(&scene, a.scenario.as_deref(), &[], &sink)?;
    scene.table_cache = super::table_cache();
    for w in &scene.warnings {
        eprintln!("kecsim: warning: {w}");
    }
    anyhow::ensure!(
        scene.simulation.is_some() && scene.track.is_some(),
        "{origin}: the paper's case needs a [simulation] and track sections (Fig. 17-19 run along a track)"
    );
    eprintln!(
        "kecsim paper: {} — contact tables, then the runs with kec and {} (each takes what `kecsim run` takes)",
        scene.name, a.tables
    );
    let mut progress = super::progress::Runs::new(&["kec".to_string(), a.tables.clone()]);
    let f = kecsim::paper::assemble_observed(&scene, &a.tables, a.duration, Some(&mut progress));
    progress.finish();
    let f = f?;
    let summary = f.markdown();
    let delivered = {
        let rec = inspect::open_recording("kecsim", &sink, || inspect::paper::blueprint(&f))?;
        inspect::paper::record(&rec, &f, &summary)?;
        inspect::finish_recording(rec, &sink)
    };
    print!("{summary}");
    println!("{}", delivered.map_err(anyhow::Error::msg)?);
    let failed = kecsim::compare::incomplete_runs(&f.runs);
    anyhow::ensure!(
        failed.is_empty(),
        "{} of {} runs did not complete: {} — the figures cover only the {:.2} s both runs cover",
        failed.len(),
        f.runs.len(),
        failed.join(", "),
        f.figures.t.last().copied().unwrap_or(0.0)
    );
    Ok(())
}
