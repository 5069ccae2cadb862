//! The command line: the arguments of every command and the dispatch to one module per command,
//! each of which only parses its options and calls the library.

mod bench;
mod compare;
mod contact;
mod creep;
mod design;
mod generate;
mod kec;
mod paper;
mod patch;
mod profiles;
mod progress;
mod run;
mod study;
mod track;

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::{Args, Parser, Subcommand};

use kecsim::contact::lookup::TableSettings;
use kecsim::contact::ContactModelSpec;
use kecsim::dynamics::{RunPool, Threads};
use kecsim::files::OutputGuard;
use kecsim::inspect::{self, Sink};
use kecsim::profile::placement::{Inclination, WheelRailPair, WheelsetGeometry};
use kecsim::profile::{Profile, ProfileKind};
use kecsim::track::TrackGauge;

#[derive(Parser)]
#[command(
    name = "kecsim",
    version,
    about = "Railway vehicle dynamics with the KEC contact method, inspected in Rerun"
)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Lift the resource limits (grid points, samples, irregularity nodes, track length) that
    /// guard against an input that would exhaust the machine (see the README).
    #[arg(long, global = true)]
    no_limits: bool,
    /// Build the contact tables anew instead of reading them from the cache
    /// ($KECSIM_CACHE_DIR, else $XDG_CACHE_HOME/kecsim, else ~/.cache/kecsim).
    #[arg(long, global = true)]
    no_cache: bool,
}

/// `--no-cache`, set once by [`run`] (the binary's own state; the library takes the cache as a
/// parameter).
static NO_CACHE: std::sync::OnceLock<bool> = std::sync::OnceLock::new();

/// The table cache the commands use: `$KECSIM_CACHE_DIR`, else `$XDG_CACHE_HOME/kecsim`, else
/// `$HOME/.cache/kecsim` (None with `--no-cache` or with none of them set).
fn table_cache() -> Option<kecsim::contact::cache::TableCache> {
    if NO_CACHE.get().copied().unwrap_or(false) {
        return None;
    }
    let var = |k: &str| std::env::var_os(k).filter(|v| !v.is_empty()).map(PathBuf::from);
    let dir = var("KECSIM_CACHE_DIR")
        .or_else(|| var("XDG_CACHE_HOME").map(|d| d.join("kecsim")))
        .or_else(|| var("HOME").map(|d| d.join(".cache").join("kecsim")))?;
    Some(kecsim::contact::cache::TableCache::new(dir.join("tables")))
}

/// Every command takes negative numbers as values (`--step -1` is then reported as a bad step,
/// not as an unknown argument).
#[derive(Subcommand)]
enum Command {
    /// Run a scenario (the embedded default when none is given), streaming it to the recording.
    #[command(allow_negative_numbers = true)]
    Run(run::RunArgs),
    /// The same scene with several contact models: differences of every wheelset (the paper's
    /// Fig. 18-19) and the cost of each, printed and recorded.
    #[command(allow_negative_numbers = true)]
    Compare(compare::CompareArgs),
    /// The paper's case (the embedded default: the MS vehicle on the Tab. 6 track) with KEC and
    /// the tables: its Fig. 14-19 in one recording laid out as the paper's, its Tab. 7 and Fig. 18's
    /// maxima printed beside the paper's numbers.
    #[command(allow_negative_numbers = true)]
    Paper(paper::PaperArgs),
    /// Record the wheel and rail profiles of both sides placed on the track cross-section.
    #[command(allow_negative_numbers = true)]
    Profiles(profiles::ProfilesArgs),
    /// Contact geometry sweep over y: lookup table, contact jumps, equivalent conicity (EN 15302).
    #[command(allow_negative_numbers = true)]
    Contact(contact::ContactArgs),
    /// The KEC-method: knife-edge-equivalent profiles, their kinks, and their accuracy.
    #[command(allow_negative_numbers = true)]
    Kec(kec::KecArgs),
    /// Creep-force curves (force vs creepage) of the creep-force models for one contact ellipse.
    #[command(allow_negative_numbers = true)]
    Creep(creep::CreepArgs),
    /// Contact patches of one wheelset at lateral shifts, yaw and a vertical wheel load: Hertz
    /// and the non-Hertzian strip model (one or more patches each), pressure, area, creep forces.
    #[command(allow_negative_numbers = true)]
    Patch(patch::PatchArgs),
    /// The track: centreline from its sections, curvature, cant, twist, irregularities.
    #[command(allow_negative_numbers = true)]
    Track(track::TrackArgs),
    /// Design a wheel profile on a rail from a target contact-angle function (jump-free by
    /// construction), write it as CSV (mm) and record it beside a reference wheel.
    #[command(allow_negative_numbers = true)]
    DesignWheel(design::DesignArgs),
    /// Write the standard profiles (S1002, 60E1, 54E1) as CSV files, mm.
    #[command(allow_negative_numbers = true)]
    GenerateProfiles(generate::GenerateArgs),
    /// Print measured speed and error of the building blocks (release builds).
    #[command(allow_negative_numbers = true)]
    Bench(bench::BenchArgs),
    /// Run a study: one scenario over many variations (speeds, track realisations, any scenario
    /// value), on all cores or as shards of a cluster job array; one table and one recording
    /// (DIR/study.rrd, where no --save, --spawn or --connect says otherwise).
    #[command(allow_negative_numbers = true)]
    Study(study::StudyArgs),
}

/// Runs the command.
pub fn run(cli: Cli) -> Result<()> {
    if cli.no_limits {
        kecsim::limits::lift();
    }
    NO_CACHE.set(cli.no_cache).ok();
    // The commands whose runs are built inside the library (compare, paper, bench) take
    // `KECSIM_THREADS` from the pool they execute in (their runs' default); `kecsim run` hands it
    // to its run's options; a study runs one case per `--jobs` thread.
    let threads = threads()?;
    let in_threads = |command: Box<dyn FnOnce() -> Result<()> + Send>| match threads {
        Threads::Count(n) => RunPool::new(Threads::Count(n)).install(command),
        _ => command(),
    };
    match cli.command {
        Command::Run(a) => run::run(a),
        Command::Compare(a) => in_threads(Box::new(|| compare::run(a))),
        Command::Paper(a) => in_threads(Box::new(|| paper::run(a))),
        Command::Profiles(a) => profiles::run(a),
        Command::Contact(a) => contact::run(a),
        Command::Kec(a) => kec::run(a),
        Command::Creep(a) => creep::run(a),
        Command::Patch(a) => patch::run(a),
        Command::Track(a) => track::run(a),
        Command::GenerateProfiles(a) => generate::run(a),
        Command::DesignWheel(a) => design::run(a),
        Command::Bench(a) => in_threads(Box::new(|| bench::run(a))),
        Command::Study(a) => study::run(a),
    }
}

/// The threads of every run, from the environment variable `KECSIM_THREADS` (a user contract):
/// N ≥ 1 — N threads (1: every run on one thread alone); unset, 0 or not a number — the
/// library's default, [`Threads::Default`] (two where the machine has two cores: the run's
/// thread and one more, which the wheelsets of each right-hand side and the contact tables'
/// searches are split between). Only the binary reads it.
/// Above [`kecsim::limits::max_threads`] (a stated multiple of the cores) it is refused.
fn threads() -> Result<Threads> {
    let n = std::env::var("KECSIM_THREADS")
        .ok()
        .and_then(|v| v.trim().parse::<usize>().ok())
        .filter(|&n| n >= 1);
    if let Some(n) = n {
        kecsim::limits::check_threads("KECSIM_THREADS", n).map_err(anyhow::Error::msg)?;
    }
    Ok(n.map_or(Threads::Default, Threads::Count))
}

/// The contact models' names, for `--contact`.
fn contact_model_names() -> clap::builder::PossibleValuesParser {
    clap::builder::PossibleValuesParser::new(ContactModelSpec::NAMES)
}

/// A wheel/rail pair and its placement.
#[derive(Args)]
struct PairArgs {
    /// Wheel profile: standard name (s1002) or file (.csv, .dat, .prw).
    #[arg(long, default_value = "s1002")]
    wheel: String,
    /// Rail profile: standard name (60e1, 54e1) or file (.csv, .dat, .prr).
    #[arg(long, default_value = "60e1")]
    rail: String,
    /// Rail inclination: 1:N or "upright" (use "upright" for files that are already inclined).
    #[arg(long, default_value = "1:40")]
    inclination: Inclination,
    /// Track gauge, mm (measured 14 mm below the top of rail).
    #[arg(long, default_value_t = 1435.0)]
    gauge: f64,
    /// Wheelset back-to-back distance, mm.
    #[arg(long, default_value_t = 1360.0)]
    back_to_back: f64,
    /// Nominal wheel radius at the taping line, mm.
    #[arg(long, default_value_t = 460.0)]
    wheel_radius: f64,
}

impl PairArgs {
    fn pair(&self) -> Result<WheelRailPair> {
        let wheel = Profile::resolve(&self.wheel, ProfileKind::Wheel)?;
        let rail = Profile::resolve(&self.rail, ProfileKind::Rail)?;
        let gauge = TrackGauge {
            gauge_m: self.gauge * 1e-3,
            ..TrackGauge::default()
        };
        let wheelset = WheelsetGeometry {
            back_to_back_m: self.back_to_back * 1e-3,
            nominal_radius_m: self.wheel_radius * 1e-3,
            ..WheelsetGeometry::default()
        };
        Ok(WheelRailPair::new(
            wheel,
            rail,
            self.inclination,
            gauge,
            wheelset,
        )?)
    }
}

/// Range and grid of the 1-entry lookup table.
#[derive(Args)]
struct TableArgs {
    /// Largest |y| tabulated, mm [default: flange contact on each side].
    #[arg(long, value_name = "MM")]
    y_max: Option<f64>,
    /// Grid step in y, mm (intervals are refined where the geometry needs it).
    #[arg(long, value_name = "MM", default_value_t = 0.1)]
    step: f64,
}

impl TableArgs {
    /// The settings, checked as the library checks them for every caller
    /// ([`TableSettings::from_mm`]).
    fn settings(&self) -> Result<TableSettings> {
        TableSettings::from_mm(("--step", self.step), self.y_max.map(|v| ("--y-max", v)))
            .map_err(anyhow::Error::msg)
    }
}

/// The scenario file `path` (its name for errors, and the directory its relative paths start
/// from), or the embedded default scenario.
fn read_scenario(path: Option<&Path>) -> Result<(kecsim::scenario::Scenario, String, PathBuf)> {
    use kecsim::scenario::{Scenario, DEFAULT_SCENARIO};
    Ok(match path {
        Some(path) => (
            Scenario::read(path)?,
            path.display().to_string(),
            path.parent().unwrap_or(Path::new(".")).to_path_buf(),
        ),
        None => (
            Scenario::parse(DEFAULT_SCENARIO, "<embedded default scenario>")?,
            "<embedded default scenario>".to_string(),
            PathBuf::from("."),
        ),
    })
}

/// `--y-max` checked against the pair's flange climb ([`TableSettings::check_y_max`]).
fn check_table_range(
    geom: &kecsim::contact::geometry::ContactGeometry,
    settings: &TableSettings,
) -> Result<()> {
    Ok(settings.check_y_max(geom, "--y-max")?)
}

/// Where the recording goes (default: `--save kecsim.rrd`).
#[derive(Args)]
struct SinkArgs {
    /// Save the recording to this .rrd file [default: kecsim.rrd]; with --connect or --spawn,
    /// a copy of what is streamed (written whole whatever the viewer does).
    #[arg(long, value_name = "FILE")]
    save: Option<PathBuf>,
    /// Start a Rerun viewer (`rerun` on PATH) and stream to it.
    #[arg(long, group = "sink")]
    spawn: bool,
    /// Stream to a running viewer [default URL: rerun+http://127.0.0.1:9876/proxy].
    #[arg(long, value_name = "URL", group = "sink", num_args = 0..=1, default_missing_value = inspect::DEFAULT_CONNECT_URL)]
    connect: Option<String>,
}

impl SinkArgs {
    /// Whether any sink option was given on the command line.
    fn given(&self) -> bool {
        self.save.is_some() || self.spawn || self.connect.is_some()
    }

    /// The sink to use: a viewer that cannot be reached (`--connect` with nothing listening within
    /// [`inspect::VIEWER_TIMEOUT`], `--spawn` without `rerun` on PATH or without a display) falls
    /// back to saving the file (`--save`'s, else `kecsim.rrd`), and says so — before any work, so
    /// that nothing waits on an absent viewer. A viewer with `--save`: both.
    fn sink(&self) -> Sink {
        self.sink_until(&|| false)
    }

    /// [`Self::sink`], its wait for a spawned viewer ended by `stop()` (the command's caught
    /// Ctrl-C or SIGTERM: the recording then goes to the file, and the command stops at its next
    /// check).
    fn sink_until(&self, stop: &dyn Fn() -> bool) -> Sink {
        let file = self
            .save
            .clone()
            .unwrap_or_else(|| PathBuf::from(inspect::DEFAULT_RRD));
        let fallback = |why: String| {
            eprintln!(
                "kecsim: {why}; saving the recording to {} instead",
                file.display()
            );
            Sink::Save(file.clone())
        };
        let viewer = |url: String| match &self.save {
            Some(p) => Sink::ConnectAndSave(url, p.clone(), inspect::FileCopy::default()),
            None => Sink::Connect(url),
        };
        if self.spawn {
            // The viewer is started here, before the outputs are guarded: a `rerun` that cannot
            // run or never listens falls back to the file, which the guard then checks.
            match inspect::spawn_obstacle().map_or_else(|| inspect::spawn_viewer_until(stop), Err) {
                Ok(url) => viewer(url),
                Err(why) => fallback(why),
            }
        } else if let Some(url) = &self.connect {
            match inspect::probe_viewer(url, inspect::VIEWER_TIMEOUT) {
                Ok(()) => viewer(url.clone()),
                Err(why) => fallback(why),
            }
        } else {
            Sink::Save(file.clone())
        }
    }
}

/// Parses the command line as [`Cli::parse`] does, with one more help: a misspelt command clap
/// finds nothing like (`kecsim rn`: its similarity measure wants a longer word) gets the
/// commands within two edits of it, or that it is a prefix or an abbreviation of, as a tip.
pub fn parse() -> Cli {
    use clap::error::{ContextKind, ContextValue, ErrorKind};
    use clap::CommandFactory;
    let e = match Cli::try_parse() {
        Ok(cli) => return cli,
        Err(e) => e,
    };
    let suggested = e.get(ContextKind::SuggestedSubcommand).is_some();
    if e.kind() == ErrorKind::InvalidSubcommand && !suggested {
        if let Some(ContextValue::String(typed)) = e.get(ContextKind::InvalidSubcommand) {
            let names: Vec<String> = Cli::command()
                .get_subcommands()
                .map(|c| c.get_name().to_string())
                .collect();
            let near = similar_commands(typed, &names);
            if !near.is_empty() {
                let text = e.render().to_string();
                let (head, tail) = text.split_once("\n\n").unwrap_or((&text, ""));
                eprintln!(
                    "{head}\n\n  tip: a similar command exists: {}\n\n{tail}",
                    near.iter()
                        .map(|n| format!("'{n}'"))
                        .collect::<Vec<_>>()
                        .join(", ")
                );
                std::process::exit(2);
            }
        }
    }
    e.exit()
}

/// The commands within two edits of `typed` (Levenshtein), or that start with it, or that hold
/// its letters in order (an abbreviation: `rn` of `run`), nearest first.
fn similar_commands(typed: &str, names: &[String]) -> Vec<String> {
    fn edits(a: &str, b: &str) -> usize {
        let b: Vec<char> = b.chars().collect();
        let mut row: Vec<usize> = (0..=b.len()).collect();
        for (i, ca) in a.chars().enumerate() {
            let mut prev = row[0];
            row[0] = i + 1;
            for (j, cb) in b.iter().enumerate() {
                let cur = row[j + 1];
                row[j + 1] = (prev + usize::from(ca != *cb)).min(row[j] + 1).min(cur + 1);
                prev = cur;
            }
        }
        row[b.len()]
    }
    let typed = typed.to_lowercase();
    let in_order = |name: &str| {
        let mut letters = name.chars();
        typed.len() >= 2 && typed.chars().all(|c| letters.any(|n| n == c))
    };
    let mut near: Vec<(usize, &String)> = names
        .iter()
        .filter_map(|n| {
            let d = edits(&typed, n);
            (d <= 2 || (typed.len() >= 2 && n.starts_with(&typed)) || in_order(n)).then_some((d, n))
        })
        .collect();
    near.sort();
    near.into_iter().take(3).map(|(_, n)| n.clone()).collect()
}

/// The title of a command's summary on a pair: `kecsim CMD: WHEEL on RAIL at INCLINATION`.
fn title(command: &str, pair: &WheelRailPair) -> String {
    format!(
        "kecsim {command}: {} on {} at {}",
        pair.wheel.name, pair.rail.name, pair.inclination
    )
}

/// The placed pair's summary, as plain text.
fn print_pair(pair: &WheelRailPair) {
    println!(
        "{}",
        inspect::profiles::summary_markdown(pair)
            .replace("**", "")
            .replace('`', "")
    );
}

/// Every file the command writes, checked before any work by [`OutputGuard`]: none is a file the
/// command reads (`inputs`: by any name — a hard link, a symlink, another spelling), none is
/// another output (the sink's file included), each can be written and is not being written by
/// another run. The guard holds the outputs' locks: keep it until the command ends.
fn guard<P: AsRef<Path>>(
    inputs: &[P],
    outputs: &[(&str, Option<&Path>)],
    sink: Option<&Sink>,
) -> Result<OutputGuard> {
    guard_trees(inputs, &[], outputs, sink)
}

/// [`guard`], with directories whose every file the command reads (a study's `cases/`): no
/// output may lie inside them.
fn guard_trees<P: AsRef<Path>>(
    inputs: &[P],
    trees: &[&Path],
    outputs: &[(&str, Option<&Path>)],
    sink: Option<&Sink>,
) -> Result<OutputGuard> {
    let mut g = OutputGuard::new();
    g.inputs(inputs);
    for t in trees {
        g.input_tree(t);
    }
    for (what, p) in outputs {
        if let Some(p) = p {
            g.output(what, p)?;
        }
    }
    if let Some(p) = sink.and_then(Sink::saved) {
        g.output("--save", p)?;
    }
    if g.writes_stdout() {
        crate::say::to_stderr();
    }
    Ok(g)
}

/// Checks, before any work, that files can be written into the directory `dir` (created if
/// missing, in an existing directory; `flag` names the option).
fn check_output_dir(flag: &str, dir: &Path) -> Result<()> {
    if !dir.is_dir() {
        std::fs::create_dir(dir).with_context(|| {
            format!(
                "{flag} {}: cannot create the directory (its parent must exist)",
                dir.display()
            )
        })?;
    }
    kecsim::files::check_dir_writable(dir)
        .with_context(|| format!("{flag} {}: cannot write into this directory", dir.display()))
}

/// The outputs of a command on a scene, guarded as [`guard`] does against the scenario `file` (None:
/// the embedded one) and the files it names ([`kecsim::scenario::Scene::inputs`]).
fn guard_scene(
    scene: &kecsim::scenario::Scene,
    file: Option<&Path>,
    outputs: &[(&str, Option<&Path>)],
    sink: &Sink,
) -> Result<OutputGuard> {
    let inputs: Vec<&Path> = scene.inputs.iter().map(PathBuf::as_path).chain(file).collect();
    guard(&inputs, outputs, Some(sink))
}

/// The outputs of a command on a pair (`--csv`-like options and the sink's file), guarded as
/// [`guard`] does against the profile files read.
fn guard_pair(pair: &PairArgs, outputs: &[(&str, Option<&Path>)], sink: &Sink) -> Result<OutputGuard> {
    guard(
        &[Path::new(&pair.wheel), Path::new(&pair.rail)],
        outputs,
        Some(sink),
    )
}

/// `--duration S` (compare, bench precision): a positive simulated time, at most 1e5 s.
fn check_duration(d: Option<f64>) -> Result<()> {
    if let Some(d) = d {
        anyhow::ensure!(
            d.is_finite() && d > 0.0 && d <= 1e5,
            "--duration {d}: expected a positive time in s, at most 1e5"
        );
    }
    Ok(())
}

/// Ctrl-C and SIGTERM request `cancel` and say `what` happens now. However many come, none ends
/// the process: the command stops where it checks the request and writes what it recorded (the
/// JSON included). Only SIGKILL ends it at once, losing what was not yet written.
fn stop_on_signals(cancel: &kecsim::dynamics::CancelToken, what: &'static str) {
    let request = cancel.clone();
    ctrlc::set_handler(move || {
        if request.request() {
            eprintln!(
                "\nkecsim: already stopping; writing what was recorded (`kill -KILL {}` ends at once and loses it)",
                std::process::id()
            );
        } else {
            eprintln!("\nkecsim: interrupt: {what}");
        }
    })
    .ok();
}

/// A positive length option in mm, converted to m.
fn positive_mm(name: &str, v: f64) -> Result<f64> {
    anyhow::ensure!(
        v.is_finite() && v > 0.0,
        "{name} {v}: expected a positive length in mm"
    );
    Ok(v * 1e-3)
}

#[cfg(test)]
mod suggestion_tests {
    use super::similar_commands;

    #[test]
    fn a_misspelt_command_finds_its_neighbours() {
        let names: Vec<String> = [
            "run", "profiles", "patch", "paper", "compare", "contact", "kec", "study",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        assert_eq!(similar_commands("rn", &names)[0], "run");
        assert_eq!(similar_commands("pofiles", &names), vec!["profiles"]);
        assert_eq!(similar_commands("cmp", &names), vec!["compare"]);
        assert!(similar_commands("zzzzzz", &names).is_empty());
    }
}
