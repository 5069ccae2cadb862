//! The `kecsim` command line: parses arguments and calls the library, nothing else.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, Result};
use clap::{Args, Parser, Subcommand};

use kecsim::contact::forces::sweep::{self, SweepSettings};
use kecsim::contact::forces::{ContactPatch, CreepModel, KalkerTable};
use kecsim::contact::geometry::ContactGeometry;
use kecsim::contact::kec::KecModel;
use kecsim::contact::lookup::{LookupTable1, LookupTable2, TableSettings};
use kecsim::contact::report::{kec_error_markdown, kec_irregularity_errors, ContactReport};
use kecsim::inspect::{self, Sink};
use kecsim::profile::placement::{Inclination, TrackGauge, WheelRailPair, WheelsetGeometry};
use kecsim::profile::{io, Profile, ProfileKind, Side, StandardProfile};
use kecsim::scenario::{Scenario, DEFAULT_SCENARIO};

#[derive(Parser)]
#[command(
    name = "kecsim",
    version,
    about = "Railway vehicle dynamics with the KEC contact method, inspected in Rerun"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scenario (the embedded default when none is given) and record it.
    Run {
        /// Scenario file (TOML); omit to run the embedded default.
        scenario: Option<PathBuf>,
        /// Contact model, overriding the scenario's: kec, lookup (1-entry), lookup2 (y, gv) or online.
        #[arg(long, value_parser = ["kec", "lookup", "lookup2", "online"])]
        contact: Option<String>,
        /// Initial forward speed, m/s, overriding the scenario's.
        #[arg(long, value_name = "M_S")]
        speed: Option<f64>,
        /// Write one CSV per wheelset into this directory.
        #[arg(long, value_name = "DIR")]
        csv: Option<PathBuf>,
        /// Write the run summary as JSON.
        #[arg(long, value_name = "FILE")]
        json: Option<PathBuf>,
        #[command(flatten)]
        sink: SinkArgs,
    },
    /// Record the wheel and rail profiles of both sides placed on the track cross-section.
    Profiles {
        #[command(flatten)]
        pair: PairArgs,
        #[command(flatten)]
        sink: SinkArgs,
    },
    /// Contact geometry sweep over y: lookup table, contact jumps, equivalent conicity (EN 15302).
    Contact {
        #[command(flatten)]
        pair: PairArgs,
        /// Write the 1-entry lookup table as CSV (one row per tabulated y).
        #[arg(long, value_name = "FILE")]
        csv: Option<PathBuf>,
        #[command(flatten)]
        table: TableArgs,
        /// Also build the 2-entry table (y, gauge variation) and write it as CSV.
        #[arg(long, value_name = "FILE")]
        table2_csv: Option<PathBuf>,
        /// Gauge variations of the 2-entry table: −MAX..MAX, mm.
        #[arg(long, value_name = "MM", default_value_t = 10.0)]
        gv_max: f64,
        /// Gauge-variation step of the 2-entry table, mm.
        #[arg(long, value_name = "MM", default_value_t = 1.0)]
        gv_step: f64,
        #[command(flatten)]
        sink: SinkArgs,
    },
    /// The KEC-method: knife-edge-equivalent profiles, their kinks, and their accuracy.
    Kec {
        #[command(flatten)]
        pair: PairArgs,
        /// Write the equivalent profiles as CSV (one row per tabulated y).
        #[arg(long, value_name = "FILE")]
        csv: Option<PathBuf>,
        #[command(flatten)]
        table: TableArgs,
        /// Also measure KEC against the online constraints and the tables under gauge variation and
        /// cross level (±10 mm; builds a 2-entry table, some seconds).
        #[arg(long)]
        accuracy: bool,
        #[command(flatten)]
        sink: SinkArgs,
    },
    /// Creep-force curves (force vs creepage) of the creep-force models for one contact ellipse.
    Creep {
        /// Creep-force model: kalker (linear, saturated), polach, fastsim, or all.
        #[arg(long, default_value = "all", value_parser = ["kalker", "polach", "fastsim", "all"])]
        model: String,
        /// Normal force N, newtons.
        #[arg(long, value_name = "N")]
        normal_force_n: f64,
        /// Semi-axis of the contact ellipse in the rolling direction, mm.
        #[arg(long, value_name = "A")]
        a_mm: f64,
        /// Semi-axis of the contact ellipse in the lateral direction, mm.
        #[arg(long, value_name = "B")]
        b_mm: f64,
        /// Coefficient of friction.
        #[arg(long, default_value_t = 0.3)]
        mu: f64,
        /// Spin creepage φ, 1/m.
        #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
        spin: f64,
        /// The creepage is swept over −MAX..MAX.
        #[arg(long, value_name = "MAX", default_value_t = 0.01)]
        max_creepage: f64,
        /// Points per curve.
        #[arg(long, default_value_t = 201)]
        points: usize,
        /// Shear modulus G, GPa.
        #[arg(long, default_value_t = 82.0)]
        shear_modulus_gpa: f64,
        /// Poisson's ratio ν (for Kalker's coefficients).
        #[arg(long, default_value_t = 0.28)]
        poisson: f64,
        /// Write the curves at the given N and spin as CSV.
        #[arg(long, value_name = "FILE")]
        csv: Option<PathBuf>,
        #[command(flatten)]
        sink: SinkArgs,
    },
    /// The track: centreline from its sections, curvature, cant, twist, irregularities.
    Track {
        /// Track file or scenario file (TOML) with a [track] table; omit for the paper's Tab. 6 track.
        file: Option<PathBuf>,
        /// Sampling step along s for the CSV and the recording, m.
        #[arg(long, value_name = "M", default_value_t = 1.0)]
        step: f64,
        /// Write the sampled track as CSV (s_m, x_m, y_m, z_m, heading_rad, cant_rad, curvature_1pm,
        /// al_mm, vp_mm, gv_mm, cl_mm, …).
        #[arg(long, value_name = "FILE")]
        csv: Option<PathBuf>,
        #[command(flatten)]
        sink: SinkArgs,
    },
    /// Write the standard profiles (S1002, 60E1, 54E1) as CSV files, mm.
    GenerateProfiles {
        /// Output directory.
        #[arg(long, default_value = "profiles")]
        dir: PathBuf,
    },
    /// Print measured speed and error of the building blocks (release builds).
    Bench {
        /// What to measure.
        #[arg(value_enum, default_value = "profiles")]
        target: BenchTarget,
        /// Calls per measurement.
        #[arg(long, default_value_t = 5_000_000)]
        calls: usize,
    },
}

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
    /// Track-frame and irregularity evaluation on the Tab. 6 track.
    Track,
    /// Real-time factor of every scene with every contact model (kec, lookup, lookup2, online), and each
    /// model's difference from KEC on the same scene.
    Dynamics,
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
    fn settings(&self) -> Result<TableSettings> {
        Ok(TableSettings {
            step_m: positive_mm("--step", self.step)?,
            y_max_m: self.y_max.map(|v| positive_mm("--y-max", v)).transpose()?,
            ..TableSettings::default()
        })
    }
}

/// Where the recording goes (default: `--save kecsim.rrd`).
#[derive(Args)]
struct SinkArgs {
    /// Save the recording to this .rrd file [default: kecsim.rrd].
    #[arg(long, value_name = "FILE", group = "sink")]
    save: Option<PathBuf>,
    /// Start a Rerun viewer (`rerun` on PATH) and stream to it.
    #[arg(long, group = "sink")]
    spawn: bool,
    /// Stream to a running viewer [default URL: rerun+http://127.0.0.1:9876/proxy].
    #[arg(long, value_name = "URL", group = "sink", num_args = 0..=1, default_missing_value = inspect::DEFAULT_CONNECT_URL)]
    connect: Option<String>,
}

impl SinkArgs {
    fn sink(&self) -> Sink {
        if self.spawn {
            Sink::Spawn
        } else if let Some(url) = &self.connect {
            Sink::Connect(url.clone())
        } else {
            Sink::Save(
                self.save
                    .clone()
                    .unwrap_or_else(|| PathBuf::from(inspect::DEFAULT_RRD)),
            )
        }
    }
}

fn describe(sink: &Sink) -> String {
    match sink {
        Sink::Save(p) => format!("saved {}", p.display()),
        Sink::Spawn => "streamed to the spawned viewer".into(),
        Sink::Connect(u) => format!("streamed to {u}"),
    }
}

fn record_pair(pair: &WheelRailPair, sink: &Sink) -> Result<()> {
    // The stream lives in this scope: returning (even with an error) drops it and writes the footer.
    let rec = inspect::open_recording("kecsim", sink, inspect::profiles::blueprint)?;
    inspect::profiles::record(&rec, pair)?;
    Ok(())
}

fn print_pair(pair: &WheelRailPair) {
    println!(
        "{}",
        inspect::profiles::summary_markdown(pair)
            .replace("**", "")
            .replace('`', "")
    );
}

fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Run {
            scenario,
            contact,
            speed,
            csv,
            json,
            sink,
        } => {
            let (parsed, origin, base) = match &scenario {
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
            };
            let t = std::time::Instant::now();
            let scene = parsed.compile(&origin, &base)?;
            println!("scenario: {} ({origin})", scene.name);
            print_pair(&scene.pair);
            let cf = &scene.contact_forces;
            println!(
                "contact forces: {} creep model, μ = {}, E = {:.0} GPa, ν = {}",
                cf.model.name(),
                cf.friction,
                cf.material.young_pa * 1e-9,
                cf.material.poisson
            );
            if let Some((sim, vehicle)) = &scene.simulation {
                return run_simulation(&scene, sim, vehicle, contact, speed, csv, json, sink.sink());
            }
            anyhow::ensure!(
                contact.is_none() && speed.is_none() && csv.is_none() && json.is_none(),
                "this scenario has no [simulation]: --contact, --speed, --csv and --json need one"
            );
            // The wheelset's contact preprocessing: 1-entry table of the real profiles, then the
            // KEC-equivalent profiles, recorded as `kecsim kec` does.
            let l_w = scene.pair.wheelset.l_w();
            let geom = ContactGeometry::with_defaults(scene.pair.clone());
            let table = LookupTable1::build(&geom, &TableSettings::default())?;
            let model = KecModel::from_table(&table, l_w)?;
            let summary = kec_summary(&format!("kecsim run: {}", scene.name), &geom, &table, &model)?;
            let sink = sink.sink();
            {
                let rec = inspect::open_recording("kecsim", &sink, inspect::kec::blueprint)?;
                inspect::kec::record(&rec, &geom.pair, &table, &model, &summary)?;
            }
            print!("{summary}");
            println!(
                "scene preprocessed (profiles placed, contact table, KEC profiles) in {:.2} s wall; {}",
                t.elapsed().as_secs_f64(),
                describe(&sink)
            );
        }
        Command::Profiles { pair, sink } => {
            let pair = pair.pair()?;
            let sink = sink.sink();
            record_pair(&pair, &sink)?;
            print_pair(&pair);
            println!("{}", describe(&sink));
        }
        Command::Contact {
            pair,
            csv,
            table,
            table2_csv,
            gv_max,
            gv_step,
            sink,
        } => {
            let pair = pair.pair()?;
            let title = format!(
                "kecsim contact: {} on {} at {}",
                pair.wheel.name, pair.rail.name, pair.inclination
            );
            let geom = ContactGeometry::with_defaults(pair);
            let settings = table.settings()?;
            let report = ContactReport::new(&geom, &settings)?;
            let summary = report.summary(&title);
            let sink = sink.sink();
            {
                let rec = inspect::open_recording("kecsim", &sink, inspect::contact::blueprint)?;
                inspect::contact::record(&rec, &geom, &report.table, &summary)?;
            }
            print!("{summary}");
            if let Some(path) = csv {
                report
                    .table
                    .write_csv(&path)
                    .with_context(|| format!("cannot write {}", path.display()))?;
                println!("wrote {}", path.display());
            }
            if let Some(path) = table2_csv {
                let (gv_max, gv_step) = (
                    positive_mm("--gv-max", gv_max)?,
                    positive_mm("--gv-step", gv_step)?,
                );
                let n = (gv_max / gv_step).round() as i64;
                let gvs: Vec<f64> = (-n..=n).map(|k| k as f64 * gv_step).collect();
                let (lo, hi) = report.table.range();
                let t = std::time::Instant::now();
                let table2 = LookupTable2::build(&geom, lo.abs().min(hi), &gvs, &settings)?;
                table2
                    .write_csv(&path)
                    .with_context(|| format!("cannot write {}", path.display()))?;
                println!(
                    "wrote {} ({} gauge variations, built in {:.1} s)",
                    path.display(),
                    gvs.len(),
                    t.elapsed().as_secs_f64()
                );
            }
            println!("{}", describe(&sink));
        }
        Command::Kec {
            pair,
            csv,
            table,
            accuracy,
            sink,
        } => {
            let pair = pair.pair()?;
            let title = format!(
                "kecsim kec: {} on {} at {}",
                pair.wheel.name, pair.rail.name, pair.inclination
            );
            let l_w = pair.wheelset.l_w();
            let geom = ContactGeometry::with_defaults(pair);
            let settings = table.settings()?;
            let table = LookupTable1::build(&geom, &settings)?;
            let model = KecModel::from_table(&table, l_w)?;
            let mut summary = kec_summary(&title, &geom, &table, &model)?;
            if accuracy {
                let (lo, hi) = table.range();
                let gvs: Vec<f64> = (-10..=10).map(|k| k as f64 * 1e-3).collect();
                let table2 = LookupTable2::build(&geom, lo.abs().min(hi), &gvs, &settings)?;
                // Gauge variations between the 2-entry table's 1 mm columns, so that its
                // interpolation is measured, not its nodes.
                let mut cases: Vec<(f64, f64)> = [-9.5, -4.5, -1.5, 1.5, 4.5, 9.5]
                    .iter()
                    .map(|g| (g * 1e-3, 0.0))
                    .collect();
                cases.extend([-10.0, -5.0, 5.0, 10.0].iter().map(|c| (0.0, c * 1e-3)));
                let rows = kec_irregularity_errors(&geom, &model, &table, &table2, &cases, 41)
                    .map_err(anyhow::Error::msg)?;
                summary += "\nWith irregularities (max error against the online approximate constraints, 41 y per case; 2-entry table gv step 1 mm; the 1-entry table sees only al, vp, cl through Eq. 44–46):\n\n";
                summary += &kec_error_markdown(&rows);
            }
            let sink = sink.sink();
            {
                let rec = inspect::open_recording("kecsim", &sink, inspect::kec::blueprint)?;
                inspect::kec::record(&rec, &geom.pair, &table, &model, &summary)?;
            }
            print!("{summary}");
            if let Some(path) = csv {
                write_kec_csv(&path, &model).with_context(|| format!("cannot write {}", path.display()))?;
                println!("wrote {}", path.display());
            }
            println!("{}", describe(&sink));
        }
        Command::Creep {
            model,
            normal_force_n,
            a_mm,
            b_mm,
            mu,
            spin,
            max_creepage,
            points,
            shear_modulus_gpa,
            poisson,
            csv,
            sink,
        } => {
            anyhow::ensure!(
                normal_force_n.is_finite() && normal_force_n > 0.0,
                "--normal-force-n {normal_force_n}: expected a positive force in N (a lifted wheel has no creep forces)"
            );
            anyhow::ensure!(
                mu.is_finite() && mu > 0.0,
                "--mu {mu}: expected a positive coefficient of friction"
            );
            anyhow::ensure!(
                spin.is_finite(),
                "--spin {spin}: expected a finite spin creepage in 1/m"
            );
            anyhow::ensure!(
                max_creepage.is_finite() && max_creepage > 0.0 && max_creepage <= 1.0,
                "--max-creepage {max_creepage}: expected a creepage in (0, 1]"
            );
            anyhow::ensure!(
                (3..=100_001).contains(&points),
                "--points {points}: expected 3 ..= 100001"
            );
            anyhow::ensure!(
                shear_modulus_gpa.is_finite() && shear_modulus_gpa > 0.0,
                "--shear-modulus-gpa {shear_modulus_gpa}: expected a positive modulus"
            );
            anyhow::ensure!(
                (0.0..=0.5).contains(&poisson),
                "--poisson {poisson}: expected 0 ..= 0.5"
            );
            let table = KalkerTable::new(poisson);
            let patch = ContactPatch::new(
                positive_mm("--a-mm", a_mm)?,
                positive_mm("--b-mm", b_mm)?,
                normal_force_n,
                shear_modulus_gpa * 1e9,
                mu,
                &table,
            )?;
            let models: Vec<CreepModel> = if model == "all" {
                CreepModel::NAMES
                    .iter()
                    .filter_map(|n| CreepModel::by_name(n))
                    .collect()
            } else {
                vec![CreepModel::by_name(&model).with_context(|| format!("unknown creep model {model}"))?]
            };
            let settings = SweepSettings {
                max_creepage,
                points,
                ..SweepSettings::default()
            };
            let summary = sweep::summary_markdown(&models, &patch, spin, &settings);
            let sink = sink.sink();
            {
                let rec = inspect::open_recording("kecsim", &sink, inspect::creep::blueprint)?;
                inspect::creep::record(&rec, &models, &patch, spin, &settings, &summary)?;
            }
            print!("{summary}");
            if let Some(path) = csv {
                let mut rows = Vec::new();
                for m in &models {
                    for c in sweep::Curve::BOTH {
                        rows.extend(sweep::curve(m, &patch, c, spin, &settings)?);
                    }
                }
                sweep::write_csv(&path, &rows).with_context(|| format!("cannot write {}", path.display()))?;
                println!("wrote {} ({} rows)", path.display(), rows.len());
            }
            println!("{}", describe(&sink));
        }
        Command::Track {
            file,
            step,
            csv,
            sink,
        } => {
            let t = std::time::Instant::now();
            let track = match &file {
                Some(path) => kecsim::track::file::read_track(path)?,
                None => kecsim::track::file::tab6()?,
            };
            let build_s = t.elapsed().as_secs_f64();
            let samples = kecsim::track::report::sample(&track, step)?;
            let summary = kecsim::track::report::summary_markdown(&track, &samples);
            let sink = sink.sink();
            {
                let rec = inspect::open_recording("kecsim", &sink, inspect::track::blueprint)?;
                inspect::track::record(&rec, &track, &samples, &summary)?;
            }
            print!("{summary}");
            println!(
                "track built in {:.3} s; {} samples every {step} m",
                build_s,
                samples.len()
            );
            if let Some(path) = csv {
                kecsim::track::report::write_csv(&samples, &path)?;
                println!("wrote {}", path.display());
            }
            println!("{}", describe(&sink));
        }
        Command::GenerateProfiles { dir } => {
            std::fs::create_dir_all(&dir).with_context(|| format!("cannot create {}", dir.display()))?;
            for std in StandardProfile::ALL {
                let path = dir.join(format!("{}.csv", std.name()));
                io::write_csv(&std.profile(), &path)
                    .with_context(|| format!("cannot write {}", path.display()))?;
                println!("wrote {}", path.display());
            }
        }
        Command::Bench { target, calls } => match target {
            BenchTarget::Profiles => {
                if cfg!(debug_assertions) {
                    eprintln!("kecsim: warning: debug build, timings are not representative (use --release)");
                }
                print!("{}", kecsim::bench::table(&kecsim::bench::profiles(calls)));
            }
            BenchTarget::Contact => {
                if cfg!(debug_assertions) {
                    eprintln!("kecsim: warning: debug build, timings are not representative (use --release)");
                }
                let (rows, builds) = kecsim::bench::contact(calls.min(200_000))?;
                print!("{}{builds}", kecsim::bench::contact_table(&rows));
            }
            BenchTarget::Track => {
                if cfg!(debug_assertions) {
                    eprintln!("kecsim: warning: debug build, timings are not representative (use --release)");
                }
                let (rows, notes) = kecsim::bench::track(calls)?;
                print!("{}{notes}", kecsim::bench::table(&rows));
            }
            BenchTarget::Creep => {
                if cfg!(debug_assertions) {
                    eprintln!("kecsim: warning: debug build, timings are not representative (use --release)");
                }
                print!("{}", kecsim::bench::creep(calls.min(1_000_000))?);
            }
            BenchTarget::Kec => {
                if cfg!(debug_assertions) {
                    eprintln!("kecsim: warning: debug build, timings are not representative (use --release)");
                }
                let (rows, builds) = kecsim::bench::kec(calls.min(200_000)).map_err(anyhow::Error::msg)?;
                print!("{}{builds}", kecsim::bench::contact_table(&rows));
            }
            BenchTarget::Dynamics => {
                if cfg!(debug_assertions) {
                    eprintln!("kecsim: warning: debug build, timings are not representative (use --release)");
                }
                use kecsim::dynamics::contact_model::ContactKind;
                let table = kecsim::dynamics::bench::dynamics(&[
                    ContactKind::Kec,
                    ContactKind::Lookup,
                    ContactKind::Lookup2,
                    ContactKind::Online,
                ])
                .map_err(anyhow::Error::msg)?;
                print!("{table}");
            }
        },
    }
    Ok(())
}

/// `kecsim run` of a scenario with a simulation: progress on stderr, summary on stdout, CSV and
/// JSON on request, the recording always (also when the run stops early: everything recorded up
/// to the diagnosis is kept, then the error is returned).
#[allow(clippy::too_many_arguments)]
fn run_simulation(
    scene: &kecsim::scenario::Scene,
    sim: &kecsim::dynamics::spec::SimulationSpec,
    vehicle: &kecsim::dynamics::spec::VehicleSpec,
    contact: Option<String>,
    speed: Option<f64>,
    csv: Option<PathBuf>,
    json: Option<PathBuf>,
    sink: Sink,
) -> Result<()> {
    use kecsim::dynamics::contact_model::ContactKind;
    use std::io::Write;
    let kind = match contact {
        Some(c) => ContactKind::parse(&c).with_context(|| format!("unknown contact model {c}"))?,
        None => sim.contact_model,
    };
    let v = speed.unwrap_or(sim.speed_m_s);
    anyhow::ensure!(
        v.is_finite() && (0.0..=200.0).contains(&v),
        "--speed {v}: expected 0 ..= 200 m/s"
    );
    println!(
        "simulating {:.3} s at {v} m/s (ramp {} m/s²), contact model {}, {} creep, {:?} rtol {:.0e}",
        sim.duration_s,
        sim.speed_ramp_m_s2,
        kind.name(),
        scene.contact_forces.model.name(),
        sim.integrator.method,
        sim.integrator.rtol
    );
    let tty = std::io::IsTerminal::is_terminal(&std::io::stderr());
    let mut bar = |f: f64| {
        if !tty {
            return;
        }
        let n = (f * 40.0).round() as usize;
        eprint!(
            "\r[{}{}] {:5.1} %",
            "#".repeat(n.min(40)),
            " ".repeat(40 - n.min(40)),
            f * 100.0
        );
        let _ = std::io::stderr().flush();
    };
    let out =
        kecsim::dynamics::run::run(scene, sim, vehicle, kind, v, &mut bar).map_err(anyhow::Error::msg)?;
    if tty {
        eprintln!();
    }
    let s = &out.summary;
    if let Some(st) = &out.settling {
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
    {
        let n = out.wheelsets.len();
        let rec = inspect::open_recording("kecsim", &sink, || inspect::run::blueprint_for(n))?;
        inspect::run::record(&rec, scene, &out.wheelsets, s)?;
    }
    println!(
        "simulated {:.3} s in {:.3} s wall: real-time factor {:.1} (preprocessing {:.2} s); {} steps ({} rejected), {} right-hand sides",
        s.simulated_s, s.wall_s, s.realtime_factor, s.preprocessing_s, s.steps, s.rejected_steps, s.rhs_evaluations
    );
    println!(
        "max |y| {:.3} mm, max |yaw| {:.3} mrad, normal forces {:.1} .. {:.1} kN, max |Y/Q| {:.3}",
        s.max_abs_y_mm,
        s.max_abs_yaw_mrad,
        s.min_normal_n * 1e-3,
        s.max_normal_n * 1e-3,
        s.max_abs_y_over_q
    );
    if let Some(v) = s.critical_speed_m_s {
        println!(
            "hunting onset on the speed ramp (critical speed): {v:.2} m/s ({:.0} km/h)",
            v * 3.6
        );
    }
    if let Some(note) = &s.stopped {
        println!("stopped: {note}");
    }
    if let Some(dir) = csv {
        let paths = kecsim::dynamics::run::write_csvs(&dir, &out.wheelsets)
            .with_context(|| format!("cannot write CSV into {}", dir.display()))?;
        for path in paths {
            println!("wrote {}", path.display());
        }
    }
    if let Some(path) = json {
        let text = serde_json::to_string_pretty(s)?;
        std::fs::write(&path, text).with_context(|| format!("cannot write {}", path.display()))?;
        println!("wrote {}", path.display());
    }
    println!("{}", describe(&sink));
    if let Some(e) = &s.error {
        anyhow::bail!("the run stopped at t = {:.4} s: {e}", s.simulated_s);
    }
    Ok(())
}

/// Summary of a KEC model: kinks and reproduction accuracy.
fn kec_summary(
    title: &str,
    geom: &ContactGeometry,
    table: &LookupTable1,
    model: &KecModel,
) -> Result<String> {
    let (lo, hi) = table.range();
    let mut s = format!("# {title}\n\n");
    s += &format!(
        "Equivalent profiles from the 1-entry table over y = {:.3} .. {:.3} mm ({} rows): left s^k = {:.3} .. {:.3} mm, right s^k = {:.3} .. {:.3} mm\n\n",
        lo * 1e3,
        hi * 1e3,
        table.rows.len(),
        model.left.domain().0 * 1e3,
        model.left.domain().1 * 1e3,
        model.right.domain().0 * 1e3,
        model.right.domain().1 * 1e3
    );
    s += "Kinks (the real contact jumps; the equivalent profile stays continuous). At a kink the knife edge touches a corner: the KEC normal, and so the split of the normal force between the two real contact points, is undetermined there (paper §9) — the constraint reaction is one force, applied at the real point of whichever side of the kink the solution lies on.\n\n";
    s += "| side | y [mm] | s^k [mm] | slope before → after | real s^w [mm] before → after | contact angle [°] before → after |\n|---|---|---|---|---|---|\n";
    for k in model.kinks.iter().filter(|k| k.real_jump) {
        s += &format!(
            "| {} | {:+.4} | {:+.4} | {:+.4} → {:+.4} | {:+.3} → {:+.3} | {:.1} → {:.1} |\n",
            k.side.name(),
            k.y * 1e3,
            k.s_k * 1e3,
            k.slope_before,
            k.slope_after,
            k.s_wheel_before * 1e3,
            k.s_wheel_after * 1e3,
            k.angle_before.to_degrees(),
            k.angle_after.to_degrees()
        );
    }
    let others = model.kinks.iter().filter(|k| !k.real_jump).count();
    s += &format!("\n({others} more kinks where the other side's contact jumps: the roll has a kink, this side's real contact moves on continuously.)\n");
    let (ez, ep) = kecsim::contact::kec::reproduction_error(model, &table.rows)?;
    let interp =
        kecsim::contact::report::interpolation_error_kec(geom, table, model, &[1.0 / 3.0, 2.0 / 3.0])
            .map_err(anyhow::Error::msg)?;
    s += &format!(
        "\nIdeal track: KEC reproduces the table at its {} y values to z {:.1e} mm, roll {:.1e} mrad; between them (at 1/3 and 2/3 of every interval) it differs from the online solution by z {:.2e} mm, roll {:.2e} mrad.\n",
        table.rows.len(),
        ez * 1e3,
        ep * 1e3,
        interp.0 * 1e3,
        interp.1 * 1e3
    );
    Ok(s)
}

/// The equivalent profiles as CSV, one row per table row (a jump is two rows with the same y).
fn write_kec_csv(path: &Path, model: &KecModel) -> std::io::Result<()> {
    let mut w = csv::Writer::from_path(path)?;
    w.write_record([
        "y_mm",
        "s_lk_mm",
        "f_lk_mm",
        "s_rk_mm",
        "f_rk_mm",
        "s_wheel_left_mm",
        "s_rail_left_mm",
        "s_wheel_right_mm",
        "s_rail_right_mm",
    ])?;
    // Per node: [y, s^k, f^k, s^w, s^r]; both profiles hold the table's rows in reverse order
    // (s^k decreases with y).
    let collect = |side| -> Vec<[f64; 5]> {
        let p = model.profile(side);
        p.node_y()
            .iter()
            .zip(p.nodes())
            .zip(p.node_real())
            .map(|((&y, (s, f)), (sw, sr))| [y, s, f, sw, sr])
            .collect()
    };
    let (l, r) = (collect(Side::Left), collect(Side::Right));
    for (a, b) in l.iter().rev().zip(r.iter().rev()) {
        let cells = [a[0], a[1], a[2], b[1], b[2], a[3], a[4], b[3], b[4]].map(|v| format!("{:.9}", v * 1e3));
        w.write_record(&cells)?;
    }
    w.flush()
}

/// A positive length option in mm, converted to m.
fn positive_mm(name: &str, v: f64) -> Result<f64> {
    anyhow::ensure!(
        v.is_finite() && v > 0.0,
        "{name} {v}: expected a positive length in mm"
    );
    Ok(v * 1e-3)
}

fn main() -> ExitCode {
    match run(Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("kecsim: error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
