//! `kecsim run [SCENARIO.toml]`: compile the scenario, build the run, and run it with the
//! observers the options ask for — the recording (streamed as the run goes), the CSV files, the
//! progress bar, the pacing — then print the summary and write the JSON. Without a
//! `[simulation]`, the scenario's contact preprocessing is recorded (as `kecsim kec`).

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result};
use clap::Args;

use kecsim::contact::geometry::ContactGeometry;
use kecsim::contact::kec::KecModel;
use kecsim::contact::lookup::{LookupTable1, TableSettings};
use kecsim::contact::report::kec_summary;
use kecsim::dynamics::output::CsvWriter;
use kecsim::dynamics::{CancelToken, RunEnd, RunObserver, Stop};
use kecsim::inspect::{self, run::LiveRecorder};
use kecsim::scenario::{RunOptions, Scene};

use super::progress::{Pace, Progress};
use super::{check_output_dir, contact_model_names, print_pair, SinkArgs};
use kecsim::dynamics::output::BRIEF_WIDTH;

#[derive(Args)]
pub(super) struct RunArgs {
    /// Scenario file (TOML); omit to run the embedded default.
    scenario: Option<PathBuf>,
    /// Contact model, overriding the scenario's: kec, lookup (1-entry), lookup2 (y, gv), online or elastic (the wheelset free on Hertz contacts).
    #[arg(long, value_parser = contact_model_names())]
    contact: Option<String>,
    /// Initial forward speed, m/s, overriding the scenario's.
    #[arg(long, value_name = "M_S")]
    speed: Option<f64>,
    /// Simulated time, s, overriding the scenario's (checked as the scenario's: the track's end).
    #[arg(long, value_name = "S")]
    duration: Option<f64>,
    /// Write one CSV per wheelset into this directory, and one per carbody with its floor
    /// accelerations (as the run goes, into .NAME.csv.part-PID, renamed to NAME.csv when the run
    /// ends).
    #[arg(long, value_name = "DIR")]
    csv: Option<PathBuf>,
    /// Write the run summary as JSON.
    #[arg(long, value_name = "FILE")]
    json: Option<PathBuf>,
    /// Play the run at this many times real time (for demonstrations with --spawn/--connect);
    /// default: as fast as it computes.
    #[arg(long, value_name = "X")]
    pace: Option<f64>,
    /// The 3D view's factor on the wheelsets' lateral and yaw motion relative to the track (and on
    /// the rails' lateral irregularities), so that their millimetres show; the bodies and the
    /// cross-sections stay true scale; 1 (the default) = true scale.
    #[arg(long, value_name = "FACTOR", default_value_t = kecsim::inspect::world3d::DEFAULT_EXAGGERATION)]
    exaggerate: f64,
    /// The tab of the recording's layout the viewer opens on (a run's; default: overview).
    #[arg(long, value_enum)]
    tab: Option<kecsim::inspect::run::RunTab>,
    /// Print the whole summary (the profiles placed, the settling, what limited the step, every
    /// wheelset's running safety, wear, stress and comfort in full) instead of the short one.
    #[arg(long, short)]
    verbose: bool,
    #[command(flatten)]
    sink: SinkArgs,
}

pub(super) fn run(a: RunArgs) -> Result<()> {
    let (parsed, origin, base) = super::read_scenario(a.scenario.as_deref())?;
    let t = Instant::now();
    let mut scene = parsed.compile(&origin, &base)?;
    scene.table_cache = super::table_cache();
    let brief = |line: String| print!("{}", kecsim::dynamics::output::wrap(&line, BRIEF_WIDTH));
    brief(format!("scenario: {} ({origin})", scene.name));
    for w in &scene.warnings {
        eprintln!("kecsim: warning: {w}");
    }
    let cf = &scene.contact_forces;
    if a.verbose || scene.simulation.is_none() {
        print_pair(&scene.pair);
        println!(
            "contact forces: {} creep model, μ = {}, E = {:.0} GPa, ν = {}",
            cf.model.name(),
            cf.friction,
            cf.material.young_pa * 1e-9,
            cf.material.poisson
        );
    } else {
        brief(format!(
            "wheel {} on rail {} at {}; {} creep forces, μ {}",
            scene.pair.wheel.name,
            scene.pair.rail.name,
            scene.pair.inclination,
            cf.model.name(),
            cf.friction
        ));
    }
    super::check_duration(a.duration)?;
    if let (Some(d), Some((sim, _))) = (a.duration, scene.simulation.as_mut()) {
        sim.duration_s = d;
    }
    if scene.simulation.is_some() {
        return simulate(&scene, a);
    }
    anyhow::ensure!(
        a.contact.is_none()
            && a.speed.is_none()
            && a.duration.is_none()
            && a.csv.is_none()
            && a.json.is_none()
            && a.pace.is_none()
            && a.tab.is_none(),
        "this scenario has no [simulation]: --contact, --speed, --duration, --csv, --json, --pace and --tab need one"
    );
    // The wheelset's contact preprocessing: 1-entry table of the real profiles, then the
    // KEC-equivalent profiles, recorded as `kecsim kec` does.
    let l_w = scene.pair.wheelset.l_w();
    let geom = ContactGeometry::with_defaults(scene.pair.clone());
    let table = LookupTable1::build(&geom, &TableSettings::default())?;
    let model = KecModel::from_table(&table, l_w)?;
    let summary = kec_summary(&format!("kecsim run: {}", scene.name), &geom, &table, &model)
        .map_err(anyhow::Error::msg)?;
    let sink = a.sink.sink();
    let _outputs = super::guard_scene(&scene, a.scenario.as_deref(), &[], &sink)?;
    let delivered = {
        let rec = inspect::open_recording("kecsim", &sink, inspect::kec::blueprint)?;
        inspect::kec::record(&rec, &geom.pair, &table, &model, &summary)?;
        inspect::finish_recording(rec, &sink)
    };
    print!("{summary}");
    println!(
        "scene preprocessed (profiles placed, contact table, KEC profiles) in {:.2} s wall; {}",
        t.elapsed().as_secs_f64(),
        delivered.map_err(anyhow::Error::msg)?
    );
    Ok(())
}

/// A scenario with a simulation: everything that can fail before the run is checked first (the
/// options, the preprocessing, the CSV directory, the sink); the samples then go to the observers
/// as they are computed, so that an early end keeps everything up to it.
fn simulate(scene: &Scene, a: RunArgs) -> Result<()> {
    if let Some(x) = a.pace {
        anyhow::ensure!(
            x.is_finite() && (1e-3..=1e6).contains(&x),
            "--pace {x}: expected a factor of real time in 0.001..1e6 (0.001: 1 s simulated in 17 min)"
        );
    }
    anyhow::ensure!(
        a.exaggerate.is_finite() && (1.0..=1e4).contains(&a.exaggerate),
        "--exaggerate {}: expected a factor in 1..10000 (1: true scale)",
        a.exaggerate
    );
    if let Some(v) = a.speed {
        anyhow::ensure!(
            v.is_finite() && (0.0..=200.0).contains(&v),
            "--speed {v}: expected a forward speed in 0..200 m/s"
        );
    }
    // Ctrl-C / SIGTERM from here on: the run stops at its next step (or at once, if it comes
    // during the preprocessing) and everything up to it is written, however many come.
    let cancel = CancelToken::new();
    super::stop_on_signals(&cancel, "stopping at the next step and writing what was recorded");
    // Every output before any work: a run must not be lost to an unwritable path at its end, nor
    // write over a file it reads (the scenario, the profile and irregularity files it names).
    // A signal while waiting for a spawned viewer ends the wait.
    let sink = a.sink.sink_until(&|| cancel.requested());
    if let Some(dir) = &a.csv {
        check_output_dir("--csv", dir)?;
    }
    let Some((_, vehicle_spec)) = &scene.simulation else {
        anyhow::bail!("{}: no [simulation] to run", scene.origin);
    };
    // Every file `--csv DIR` writes, the carbodies' included.
    let csv_files: Vec<PathBuf> = match &a.csv {
        Some(dir) => vehicle_spec.csv_files(dir),
        None => Vec::new(),
    };
    let mut outputs = vec![("--json", a.json.as_deref())];
    outputs.extend(csv_files.iter().map(|p| ("--csv", Some(p.as_path()))));
    let _outputs = super::guard_scene(scene, a.scenario.as_deref(), &outputs, &sink)?;
    let built = scene.build_run(&RunOptions {
        contact: a.contact.clone(),
        speed_m_s: a.speed,
        threads: super::threads()?,
        cancel: cancel.clone(),
    })?;
    for n in &built.notes {
        eprintln!("kecsim: warning: {n}");
    }
    let s = &built.settings;
    let speed = built.vehicle.reference().speed;
    let brief = |line: String| print!("{}", kecsim::dynamics::output::wrap(&line, BRIEF_WIDTH));
    let ramp = if speed.ramp_m_s2 != 0.0 {
        format!(" (ramp {} m/s²)", speed.ramp_m_s2)
    } else {
        String::new()
    };
    brief(format!(
        "simulating {:.3} s at {} m/s{ramp}: contact model {}, {} rtol {:.0e}",
        s.duration_s,
        speed.initial_m_s,
        built.labels.contact_model,
        format!("{:?}", s.integrator.method).to_uppercase(),
        s.integrator.rtol
    ));
    let drive = built.vehicle.drive_info();
    brief(format!(
        "traction: {}",
        kecsim::dynamics::traction::describe(drive.mode, drive.controller_hz, &drive.driven_wheelsets)
    ));
    if let (true, Some(st)) = (a.verbose, built.vehicle.settling()) {
        println!(
            "static settling: axle loads {} kN (elements preloaded; residual {:.1e} N)",
            st.axle_loads
                .iter()
                .map(|q| format!("{:.1}", q * 1e-3))
                .collect::<Vec<_>>()
                .join(", "),
            st.residual
        );
    }
    let names = built.vehicle.wheelset_names();
    let mut csv = match &a.csv {
        Some(dir) => Some(
            CsvWriter::create(dir, &names, &vehicle_spec.carbody_names())
                .with_context(|| format!("cannot write CSV into {}", dir.display()))?,
        ),
        None => None,
    };
    let world = kecsim::inspect::world3d::World3dSettings {
        exaggerate: a.exaggerate,
    };
    let mut recorder = LiveRecorder::open_on(
        &sink,
        scene,
        &names,
        &world,
        a.tab.unwrap_or(kecsim::inspect::run::RunTab::Overview),
    )?;
    let mut progress = Progress::new();
    let mut pace = a.pace.map(|x| Pace::new(x, cancel.clone()));
    let out = {
        let mut observers: Vec<&mut (dyn RunObserver + Send)> = vec![&mut recorder, &mut progress];
        if let Some(c) = csv.as_mut() {
            observers.push(c);
        }
        if let Some(p) = pace.as_mut() {
            observers.push(p);
        }
        built.run(&mut observers)
    };
    // The recorder is the stream's last handle: a file's footer is written here.
    let delivered = recorder.finish_stream(&sink);
    let summary = &out.summary;
    if a.verbose {
        println!("{}", summary.verdict());
        print!("{summary}");
    } else {
        print!("{}", summary.brief());
    }
    if let Some(c) = &csv {
        for path in c.written() {
            println!("wrote {}", path.display());
        }
    }
    // Every output that could not be written, whatever ended the run (a failure, Ctrl-C, a full
    // disk): each is said, none hidden behind the run's own end.
    let mut not_written: Vec<String> = Vec::new();
    let mut missed = |e: String| {
        if !not_written.contains(&e) {
            not_written.push(e);
        }
    };
    for e in &out.output_failures {
        missed(e.clone());
    }
    if let Some(path) = &a.json {
        let mut summary = summary.clone();
        summary.warnings = scene.warnings.iter().chain(&built.notes).cloned().collect();
        let written = serde_json::to_string_pretty(&summary)
            .map_err(|e| e.to_string())
            .and_then(|text| kecsim::files::write_atomic(path, text.as_bytes()).map_err(|e| e.to_string()));
        match written {
            Ok(()) => println!("wrote {}", path.display()),
            Err(e) => missed(format!("cannot write {}: {e}", path.display())),
        }
    }
    match &delivered {
        Ok(line) => println!("{line}"),
        Err(e) => missed(e.clone()),
    }
    if !a.verbose {
        println!("(the whole summary: --verbose; every figure: --json FILE)");
    }
    let lost = if not_written.is_empty() {
        String::new()
    } else {
        format!(
            "\nNOT written (the files there before, if any, are kept):\n  {}",
            not_written.join("\n  ")
        )
    };
    if let RunEnd::Failed(e) = &out.end {
        let profiles = if e.in_contact_model() {
            format!(
                " (the profiles: wheel {}, rail {}, placed as {} says)",
                scene.pair.wheel.source, scene.pair.rail.source, scene.origin
            )
        } else {
            String::new()
        };
        anyhow::bail!(
            "{}: the run stopped at t = {:.4} s: {e}{profiles}{lost}",
            scene.origin,
            summary.simulated_s
        );
    }
    if let RunEnd::Stopped(Stop::Interrupted { t }) = &out.end {
        if not_written.is_empty() {
            anyhow::bail!("interrupted at t = {t:.4} s; everything recorded up to it is written");
        }
        anyhow::bail!("interrupted at t = {t:.4} s; what was recorded up to it is written, except:{lost}");
    }
    anyhow::ensure!(not_written.is_empty(), "the run ended; {}", lost.trim_start());
    Ok(())
}
