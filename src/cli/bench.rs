//! `kecsim bench [TARGET]`: measured speed with its error, printed (release builds).

use std::path::{Path, PathBuf};

use anyhow::Result;
use clap::builder::TypedValueParser;
use clap::Args;

use kecsim::bench::precision::PrecisionSettings;
use kecsim::dynamics::integrator::Method;
use kecsim::inspect;
use kecsim::scenario::{Scenario, DEFAULT_SCENARIO};

use super::SinkArgs;

#[derive(Args)]
pub(super) struct BenchArgs {
    /// What to measure.
    #[arg(value_enum, default_value = "profiles")]
    target: BenchTarget,
    /// `precision`: the scenario file (TOML) with a [simulation] [default: the embedded MS scene,
    /// the default of `kecsim run`]. `study`: the study file.
    scenario: Option<PathBuf>,
    /// Calls per measurement.
    #[arg(long, default_value_t = DEFAULT_CALLS)]
    calls: usize,
    /// `precision`: simulated time, s [default: 6 s on the embedded MS scene (straight track and
    /// the first wheelsets' swing to the flange at the curve's start), else the scenario's].
    /// `scaling`: the vehicle-size series' window, s [default: 7].
    /// `hard`: at most this much simulated time per scene [default: each scene's].
    #[arg(long, value_name = "S")]
    duration: Option<f64>,
    /// `scaling`: the track lengths, in kilometres of the Tab. 6 track laid end to end [default:
    /// 1, 2, 4].
    #[arg(long, value_delimiter = ',', value_name = "K")]
    km: Vec<usize>,
    /// `precision`: contact models swept [default: kec, lookup, lookup2, online].
    #[arg(long, value_delimiter = ',', value_parser = super::contact_model_names())]
    contact: Vec<String>,
    /// `precision`: integrators swept [default: bdf, dopri5].
    #[arg(long, value_delimiter = ',', value_parser = clap::builder::PossibleValuesParser::new(Method::NAMES).try_map(|m| m.parse::<Method>()))]
    method: Vec<Method>,
    /// `precision`: relative tolerances swept (atol keeps the scene's atol/rtol) [default: 1e-3,
    /// 1e-4, 1e-5].
    #[arg(long, value_delimiter = ',')]
    rtol: Vec<f64>,
    /// `precision`: the reference run's contact model [default: online].
    #[arg(long, value_parser = super::contact_model_names())]
    reference_contact: Option<String>,
    /// `precision`: the reference run's rtol, integrated by DOPRI5 [default: 1e-8].
    #[arg(long)]
    reference_rtol: Option<f64>,
    /// `precision`: the protocol's draws — N sweeps, the initial lateral velocity of every
    /// wheelset 0, 1, …, N − 1 µm/s, each against its own reference run; the errors are the
    /// largest over the draws, with their median [default: 1, the scene's own initial state].
    #[arg(long, value_name = "N")]
    draws: Option<usize>,
    /// `creep-accuracy`: every point and model as CSV.
    #[arg(long, value_name = "FILE")]
    csv: Option<PathBuf>,
    /// `creep-accuracy`: the summary as JSON.
    #[arg(long, value_name = "FILE")]
    json: Option<PathBuf>,
    /// `creep-accuracy`: write the grid's points (n_n,a_mm,b_mm,xi,eta,phi_per_m,mu: the input of
    /// `kecsim creep --at` and of scripts/contact_reference.py) and stop.
    #[arg(long, value_name = "FILE")]
    points_csv: Option<PathBuf>,
    #[command(flatten)]
    sink: SinkArgs,
}

/// `precision` on the embedded MS scene: its default window, s.
const MS_PRECISION_WINDOW_S: f64 = 6.0;

/// Calls per measurement by default.
const DEFAULT_CALLS: usize = 5_000_000;
/// Most calls per measurement (the profile target keeps one result per call: 8 bytes each).
const MAX_CALLS: usize = 100_000_000;

#[derive(Clone, Copy, clap::ValueEnum)]
enum BenchTarget {
    /// Profile evaluation: spline vs analytic definition.
    Profiles,
    /// Contact geometry: online solve (cold, warm) vs 1- and 2-entry look-ups, and table builds.
    Contact,
    /// KEC solve (cold, warm) vs 2-entry look-up vs online, with gauge variation.
    Kec,
    /// Hertz, Kalker coefficients, creepages and the creep-force models, with their errors.
    Creep,
    /// Every creep-force model against Kalker's exact theory over a/b 0.2–5, spin 0–4 1/m and
    /// creepages to full sliding (770 points): max and RMS of |ΔF|/μN, ns per contact; printed,
    /// --json and --csv recorded.
    CreepAccuracy,
    /// Track-frame and irregularity evaluation on the Tab. 6 track.
    Track,
    /// One contact's patch: Hertz, its gap deviation and the strip model (gap section, strips),
    /// µs per contact, and the strip model's pmax against Hertz's.
    Patch,
    /// The samples' patches beyond Hertz on a run (the output worker's post-processing of the
    /// default scene's first --duration s, default 51): µs per contact recomputed, the share of
    /// the contacts recomputed, and what they come to (pmax, area).
    PatchRun,
    /// Real-time factor of every scene with every contact model, each model's difference from KEC
    /// on the same scene, the cost of streaming to a recording, and the contact-model dispatch.
    Dynamics,
    /// The cost of calling a contact model through the `dyn ContactModel` interface.
    Dispatch,
    /// Work–precision of a scene: wall time against error for each contact model and integrator
    /// over a tolerance sweep, against one reference run; printed and recorded (log–log).
    Precision,
    /// Cost against track length (the MS vehicle over 1, 2, 4 km) and against vehicle size (a
    /// bogie, the Manchester vehicle, the MS vehicle, two coupled MS vehicles), with the fitted
    /// exponents.
    Scaling,
    /// The hard-case suite: flange impact, hunting with flange contact, tight curves, a gauge
    /// widening — each with the elastic contact model (the reference) and the constraint models
    /// beside it: outcome, steps, smallest step, max |y|, Y/Q, lift, cost, difference to elastic.
    Hard,
    /// The cost of one right-hand side of each vehicle (a bogie, the Manchester vehicle, the MS
    /// vehicle, two coupled MS vehicles): µs on one thread and on the run's threads, and the share
    /// of each part (body frames, contact kinematics, force elements, bodies and joints, wheelset
    /// dynamics). --duration: the window whose states are evaluated [default: 10 s].
    Rhs,
    /// A study's throughput (the study file in place of the scenario): one job, then one per
    /// core; cases per minute, the speed-up, the overhead per case.
    Study,
}

pub(super) fn run(a: BenchArgs) -> Result<()> {
    if cfg!(debug_assertions) {
        eprintln!("kecsim: warning: debug build, timings are not representative (use --release)");
    }
    anyhow::ensure!(
        (1..=MAX_CALLS).contains(&a.calls),
        "--calls {}: expected 1..={MAX_CALLS} calls per measurement",
        a.calls
    );
    anyhow::ensure!(
        matches!(a.target, BenchTarget::Scaling) || a.km.is_empty(),
        "--km applies to `kecsim bench scaling` only"
    );
    // The sweep's options (`precision` only); --duration is precision's and scaling's.
    let sweep_options = a.scenario.is_some()
        || !a.contact.is_empty()
        || !a.method.is_empty()
        || !a.rtol.is_empty()
        || a.reference_contact.is_some()
        || a.reference_rtol.is_some()
        || a.draws.is_some();
    anyhow::ensure!(
        matches!(a.target, BenchTarget::CreepAccuracy)
            || (a.csv.is_none() && a.json.is_none() && a.points_csv.is_none()),
        "--csv, --json and --points-csv apply to `kecsim bench creep-accuracy` only"
    );
    if matches!(a.target, BenchTarget::CreepAccuracy) {
        anyhow::ensure!(
            !sweep_options && a.duration.is_none() && a.km.is_empty(),
            "`kecsim bench creep-accuracy` takes --csv, --json and --points-csv only"
        );
        return creep_accuracy(a);
    }
    if matches!(a.target, BenchTarget::Study) {
        let path = a
            .scenario
            .as_ref()
            .ok_or_else(|| anyhow::anyhow!("`kecsim bench study STUDY.toml`: give the study file"))?;
        anyhow::ensure!(
            a.contact.is_empty() && a.method.is_empty() && a.rtol.is_empty() && a.duration.is_none(),
            "`kecsim bench study` takes the study file only"
        );
        let study = kecsim::study::Study::read(path)?;
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        print!("{}", kecsim::bench::study::throughput(&study, cores)?);
        return Ok(());
    }
    if matches!(a.target, BenchTarget::Hard) {
        anyhow::ensure!(!sweep_options, "`kecsim bench hard` takes --duration only");
        super::check_duration(a.duration)?;
        print!(
            "{}",
            kecsim::bench::hard::hard(a.duration).map_err(anyhow::Error::msg)?
        );
        return Ok(());
    }
    if matches!(a.target, BenchTarget::Rhs) {
        anyhow::ensure!(!sweep_options, "`kecsim bench rhs` takes --duration only");
        if a.calls != DEFAULT_CALLS {
            eprintln!("kecsim: bench: --calls does not apply to this target (it evaluates a run's states)");
        }
        let mut settings = kecsim::bench::rhs::RhsSettings::default();
        if let Some(d) = a.duration {
            settings.window_s = d;
        }
        print!("{}", kecsim::bench::rhs::rhs(&settings)?.markdown());
        return Ok(());
    }
    if matches!(a.target, BenchTarget::PatchRun) {
        anyhow::ensure!(!sweep_options, "`kecsim bench patch-run` takes --duration only");
        let mut settings = kecsim::bench::patch_run::PatchRunSettings::default();
        if let Some(d) = a.duration {
            settings.duration_s = d;
        }
        print!(
            "{}",
            kecsim::bench::patch_run::patch_run(&settings)
                .map_err(anyhow::Error::msg)?
                .text()
        );
        return Ok(());
    }
    if matches!(a.target, BenchTarget::Scaling) {
        anyhow::ensure!(
            !sweep_options,
            "`kecsim bench scaling` takes --duration and --km only"
        );
        return scaling(a);
    }
    anyhow::ensure!(
        matches!(a.target, BenchTarget::Precision) || !(sweep_options || a.duration.is_some()),
        "a scenario, --duration, --contact, --method, --rtol, --reference-* and --draws apply to `kecsim bench precision` only"
    );
    if matches!(a.target, BenchTarget::Precision) {
        return precision(a);
    }
    let calls = a.calls;
    // Targets whose calls are slow take at most this many (said, not silently).
    let cap = |n: usize| {
        if calls > n {
            eprintln!("kecsim: bench: --calls {calls} capped at {n} for this target");
        }
        calls.min(n)
    };
    if matches!(a.target, BenchTarget::Dynamics | BenchTarget::Dispatch) && calls != DEFAULT_CALLS {
        eprintln!("kecsim: bench: --calls does not apply to this target (it times whole runs)");
    }
    // A spinner with the time elapsed (creep-accuracy has a bar of its own).
    let _stage = (!matches!(a.target, BenchTarget::CreepAccuracy)).then(|| {
        let name = clap::ValueEnum::to_possible_value(&a.target)
            .map_or_else(String::new, |v| v.get_name().to_string());
        super::progress::Stage::new(&format!("bench {name}: measuring"))
    });
    match a.target {
        BenchTarget::Profiles => print!("{}", kecsim::bench::table(&kecsim::bench::profiles(calls))),
        BenchTarget::Contact => {
            let (rows, builds) = kecsim::bench::contact(cap(200_000))?;
            print!("{}{builds}", kecsim::bench::contact_table(&rows));
        }
        BenchTarget::Track => {
            let (rows, notes) = kecsim::bench::track(calls)?;
            print!("{}{notes}", kecsim::bench::table(&rows));
        }
        BenchTarget::Creep => print!("{}", kecsim::bench::creep(cap(1_000_000))?),
        BenchTarget::Patch => print!("{}", kecsim::bench::patch(cap(20)).map_err(anyhow::Error::msg)?),
        BenchTarget::Kec => {
            let (rows, builds) = kecsim::bench::kec(cap(200_000)).map_err(anyhow::Error::msg)?;
            print!("{}{builds}", kecsim::bench::contact_table(&rows));
        }
        BenchTarget::Dynamics => print!(
            "{}",
            kecsim::bench::dynamics::dynamics().map_err(anyhow::Error::msg)?
        ),
        BenchTarget::Dispatch => print!(
            "{}",
            kecsim::bench::dynamics::dispatch().map_err(anyhow::Error::msg)?
        ),
        BenchTarget::Precision
        | BenchTarget::CreepAccuracy
        | BenchTarget::Scaling
        | BenchTarget::Hard
        | BenchTarget::Study
        | BenchTarget::Rhs
        | BenchTarget::PatchRun => {
            unreachable!("handled above")
        }
    }
    Ok(())
}

/// `kecsim bench creep-accuracy`.
fn creep_accuracy(a: BenchArgs) -> Result<()> {
    use kecsim::bench::creep_accuracy::{grid, measure};
    use kecsim::contact::forces::exact::ExactSettings;
    use kecsim::contact::forces::{
        points, CreepModel, FastripSettings, FastsimSettings, SlipDirection, TractionBound,
    };
    let _outputs = super::guard::<&Path>(
        &[],
        &[
            ("--csv", a.csv.as_deref()),
            ("--json", a.json.as_deref()),
            ("--points-csv", a.points_csv.as_deref()),
        ],
        None,
    )?;
    let pts = grid();
    if let Some(path) = &a.points_csv {
        let mut w = kecsim::files::csv_writer(path)?;
        w.write_record(points::POINT_COLUMNS)?;
        for p in &pts {
            w.write_record(p.csv_fields())?;
        }
        kecsim::files::commit_csv(w)?;
        eprintln!("wrote {} ({} points)", path.display(), pts.len());
        return Ok(());
    }
    let models: Vec<(String, CreepModel)> = vec![
        ("kalker".into(), CreepModel::by_name("kalker").unwrap_or_default()),
        ("polach".into(), CreepModel::by_name("polach").unwrap_or_default()),
        ("fastsim".into(), CreepModel::Fastsim(FastsimSettings::default())),
        (
            "fastsim, elliptic bound, opposing slip".into(),
            CreepModel::Fastsim(FastsimSettings {
                bound: TractionBound::Elliptic,
                direction: SlipDirection::Opposing,
                ..FastsimSettings::default()
            }),
        ),
        ("fastrip".into(), CreepModel::Fastrip(FastripSettings::default())),
        ("exact-table".into(), CreepModel::ExactTable),
        (
            "exact 32 × 32 (no extrapolation)".into(),
            CreepModel::Exact(ExactSettings {
                richardson: false,
                ..ExactSettings::default()
            }),
        ),
    ];
    let reference = CreepModel::Exact(ExactSettings::default());
    let counter = super::progress::Counter::new(pts.len() as u64, "exact solutions");
    let acc = measure(
        &pts,
        ("the exact theory (Richardson 32/16)", &reference),
        &models,
        &|| counter.tick(),
    );
    counter.finish();
    let acc = acc?;
    print!("{}", acc.markdown());
    if let Some(path) = &a.json {
        kecsim::files::write_atomic(path, serde_json::to_string_pretty(&acc.json())?.as_bytes())?;
        println!("wrote {}", path.display());
    }
    if let Some(path) = &a.csv {
        let mut w = kecsim::files::csv_writer(path)?;
        acc.write_csv(&mut w)?;
        kecsim::files::commit_csv(w)?;
        println!("wrote {}", path.display());
    }
    Ok(())
}

/// `kecsim bench scaling`.
fn scaling(a: BenchArgs) -> Result<()> {
    if a.calls != DEFAULT_CALLS {
        eprintln!("kecsim: bench: --calls does not apply to this target (it times whole runs)");
    }
    let mut settings = kecsim::bench::scaling::ScalingSettings::default();
    if let Some(d) = a.duration {
        settings.window_s = d;
    }
    if !a.km.is_empty() {
        settings.kilometres = a.km.clone();
    }
    let s = kecsim::bench::scaling::scaling(&settings)?;
    print!("{}", s.markdown());
    Ok(())
}

/// `kecsim bench precision [SCENARIO]`.
fn precision(a: BenchArgs) -> Result<()> {
    super::check_duration(a.duration)?;
    let sink = a.sink.sink();
    let (scene, default_window) = match &a.scenario {
        Some(path) => {
            let origin = path.display().to_string();
            let scene = Scenario::read(path)?.compile(&origin, path.parent().unwrap_or(Path::new(".")))?;
            (scene, None)
        }
        None => {
            let scene = Scenario::parse(DEFAULT_SCENARIO, "ms_vehicle_tab6")?
                .compile("ms_vehicle_tab6", Path::new("."))?;
            (scene, Some(MS_PRECISION_WINDOW_S))
        }
    };
    let _outputs = super::guard_scene(&scene, a.scenario.as_deref(), &[], &sink)?;
    let mut settings = PrecisionSettings {
        duration_s: a.duration.or(default_window),
        ..PrecisionSettings::default()
    };
    if !a.contact.is_empty() {
        settings.contacts = a.contact.clone();
    }
    if !a.method.is_empty() {
        settings.methods = a.method.clone();
    }
    if !a.rtol.is_empty() {
        settings.rtols = a.rtol.clone();
    }
    if let Some(c) = &a.reference_contact {
        settings.reference.0 = c.clone();
    }
    if let Some(r) = a.reference_rtol {
        settings.reference.2 = r;
    }
    if let Some(n) = a.draws {
        anyhow::ensure!(
            (1..=64).contains(&n),
            "--draws {n}: expected 1 ..= 64 draws (each a whole sweep and its reference run)"
        );
        settings.draws = kecsim::bench::precision::protocol_draws(n);
    }
    let p = kecsim::bench::precision::precision(&scene, &settings).map_err(anyhow::Error::msg)?;
    let delivered = {
        let rec = inspect::open_recording("kecsim", &sink, inspect::precision::blueprint)?;
        inspect::precision::record(&rec, &p)?;
        inspect::finish_recording(rec, &sink)
    };
    print!("{}", p.markdown());
    println!("{}", delivered.map_err(anyhow::Error::msg)?);
    Ok(())
}
