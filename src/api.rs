//! The library's facade: what a binding (the Python package in `python/`) or another Rust
//! program uses — a scene loaded from a file or a TOML string, keys overridden by path as a
//! study's axes do, a run with its options (threads, a stop request, a progress callback), and
//! the results as arrays: every wheelset's time series (the columns of `kecsim run --csv`) and
//! the summary (the keys of `kecsim run --json`); the contact sweep (`kecsim contact --csv`) and
//! the profiles (their files' points) likewise.
//!
//! Everything here is built on the modules below it and changes nothing in them: a run through
//! the facade is the run of `kecsim run`, sample for sample (the same build, the same integrator,
//! the same conversion of a sample into CSV units, [`crate::dynamics::output::csv_row`]); the
//! Python tests check the arrays against the CLI's CSV to the last digit written.
//!
//! ```
//! use kecsim::api::{run, RunConfig, SceneInput};
//!
//! # fn main() -> Result<(), kecsim::api::Error> {
//! // A file: `SceneInput::file("assets/scenes/ms_vehicle_tab6.toml")?`; TOML text:
//! // `SceneInput::toml(text, base_dir)?`; here the scene `kecsim run` runs by default.
//! let mut input = SceneInput::embedded_default();
//! input.set("simulation.speed_m_s", 15.0)?;
//! input.set("simulation.duration_s", 0.5)?;
//! let result = run(&input.compile()?, RunConfig::default())?;
//! let w = &result.wheelsets[0];
//! let t = w.column("t_s").expect("a CSV column");
//! let v = w.column("speed_m_s").expect("a CSV column");
//! assert_eq!(t.len(), result.summary.samples);
//! assert!((t[t.len() - 1] - 0.5).abs() < 1e-12 && (v[0] - 15.0).abs() < 1e-9);
//! assert_eq!(result.summary_json()["outcome"], "completed");
//! // A key the scenario does not take is refused, naming it.
//! let e = input.set("simulation.sped_m_s", 1.0).unwrap_err();
//! assert!(e.to_string().contains("simulation.sped_m_s"));
//! # Ok(())
//! # }
//! ```

use std::path::{Path, PathBuf};

use crate::contact::geometry::ContactGeometry;
use crate::contact::lookup::{self, TableError, TableSettings};
use crate::contact::report::ContactReport;
use crate::dynamics::output::{csv_row, ObserverError, OutputSample, RunStart, CSV_COLUMNS};
use crate::dynamics::{CancelToken, RunEnd, RunObserver, RunSummary, Stop, Threads};
use crate::profile::Profile;
use crate::scenario::{BuildError, RunOptions, Scenario, Scene, DEFAULT_SCENARIO};
use crate::study::spec::{check_key, check_key_path, check_value, clipped, drop_flat, set_key};

/// Most overrides of one scene ([`SceneInput::set`]; each is checked against the scenario with all
/// before it).
pub const MAX_OVERRIDES: usize = 1000;
/// Characters of an override's key, value and problem kept in an error (each may be megabytes).
const SHOWN_CHARS: usize = 120;

/// A value given to a key ([`SceneInput::set`]): a TOML value (`15.0`, `3`, `"kec"`, `true`).
pub use toml::Value;

/// What the facade refuses, each naming where: the file (or `<string>`), the line, the key.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The scenario cannot be read or is not a valid scenario (names the file and line).
    #[error(transparent)]
    Scenario(#[from] crate::scenario::ScenarioError),
    /// A path that is neither a readable scenario file nor TOML text.
    #[error("{given}: {problem}")]
    Source { given: String, problem: String },
    /// An override the scenario does not take (names the key).
    #[error("{origin}: override `{key}` = {value}: {problem}")]
    Override {
        origin: String,
        key: String,
        value: String,
        problem: String,
    },
    /// The run's objects cannot be built (the contact model, the vehicle, the run's extent).
    #[error("{origin}: {source}")]
    Build {
        origin: String,
        #[source]
        source: Box<BuildError>,
    },
    /// The contact sweep cannot be tabulated for the scene's profiles.
    #[error("{origin}: contact sweep: {source}")]
    Sweep {
        origin: String,
        #[source]
        source: Box<TableError>,
    },
    /// A run or sweep option out of range (the threads; the sweep's step and half-range).
    #[error("{0}")]
    Option(String),
}

/// A scene before it is compiled: the scenario's text, where it came from, the directory its
/// relative paths start from, and the keys overridden.
#[derive(Debug, Clone)]
pub struct SceneInput {
    text: String,
    origin: String,
    base: PathBuf,
    /// The scenario file, where it came from one.
    file: Option<PathBuf>,
    overrides: Vec<(String, Value)>,
}

impl SceneInput {
    /// A scenario file (relative paths in it start from its directory). Its errors name the
    /// file and line.
    pub fn file(path: impl AsRef<Path>) -> Result<SceneInput, Error> {
        let path = path.as_ref();
        Ok(SceneInput {
            text: Scenario::read(path)?.source,
            origin: path.display().to_string(),
            base: path.parent().unwrap_or(Path::new(".")).to_path_buf(),
            file: Some(path.to_path_buf()),
            overrides: Vec::new(),
        })
    }

    /// A scenario given as TOML text, named `<string>` in errors; relative paths in it start
    /// from `base`.
    pub fn toml(text: &str, base: impl AsRef<Path>) -> Result<SceneInput, Error> {
        let origin = "<string>".to_string();
        Scenario::parse(text, &origin)?;
        Ok(SceneInput {
            text: text.to_string(),
            origin,
            base: base.as_ref().to_path_buf(),
            file: None,
            overrides: Vec::new(),
        })
    }

    /// The scenario `kecsim run` runs without arguments (the paper's Metro de Sevilla vehicle on
    /// its kilometre, `assets/scenes/ms_vehicle_tab6.toml`).
    pub fn embedded_default() -> SceneInput {
        SceneInput {
            text: DEFAULT_SCENARIO.to_string(),
            origin: "<embedded default scenario>".to_string(),
            base: PathBuf::from("."),
            file: None,
            overrides: Vec::new(),
        }
    }

    /// A path or TOML text, as a binding receives it: a string naming an existing file is read as
    /// one; a string with a `=` or a line break is TOML text (relative paths from the current
    /// directory); anything else is a file that does not exist.
    pub fn path_or_toml(scene: &str) -> Result<SceneInput, Error> {
        let path = Path::new(scene);
        if !scene.contains('\n') && path.is_file() {
            return SceneInput::file(path);
        }
        if scene.contains('=') || scene.contains('\n') {
            return SceneInput::toml(scene, ".");
        }
        Err(Error::Source {
            given: scene.to_string(),
            problem: "no such scenario file (and not TOML text: no `key = value`)".into(),
        })
    }

    /// Where the scenario came from (its path, `<string>` or the embedded default's name).
    pub fn origin(&self) -> &str {
        &self.origin
    }

    /// Every file the scene reads — the scenario file (where it came from one) and the files its
    /// compiled `scene` names (profiles, track, irregularities: [`Scene::inputs`]) — which a
    /// writer must never overwrite ([`crate::files::OutputGuard::inputs`]), as `kecsim run` guards
    /// them.
    pub fn files_read(&self, scene: &Scene) -> Vec<PathBuf> {
        scene.inputs.iter().cloned().chain(self.file.clone()).collect()
    }

    /// The scenario's TOML text with the overrides applied (what [`Self::compile`] compiles;
    /// the text itself where there are none).
    pub fn text(&self) -> Result<String, Error> {
        if self.overrides.is_empty() {
            return Ok(self.text.clone());
        }
        toml::to_string(&self.with_overrides()?).map_err(|e| Error::Source {
            given: self.origin.clone(),
            problem: e.to_string(),
        })
    }

    /// Sets `key` (a dot-separated path, array entries by index: `simulation.speed_m_s`,
    /// `vehicle.wheelsets.0.name`) to `value`, as a study's axis does. The key is checked at
    /// once: an error names it and what the scenario expects there. The key, the value and the
    /// number of overrides are bounded ([`crate::study::spec::check_key_path`],
    /// [`crate::study::spec::check_value`], [`MAX_OVERRIDES`]).
    pub fn set(&mut self, key: &str, value: impl Into<Value>) -> Result<&mut SceneInput, Error> {
        let value = value.into();
        // Bounded before the value is cloned or shown (both recurse through it).
        if let Err(problem) = check_key_path(key).and_then(|()| check_value(&value)) {
            let e = self.refused(key, &value, problem);
            drop_flat(value);
            return Err(e);
        }
        if self.overrides.len() >= MAX_OVERRIDES {
            return Err(self.refused(
                key,
                &value,
                format!("more than {MAX_OVERRIDES} overrides: at most {MAX_OVERRIDES}"),
            ));
        }
        check_key(&self.with_overrides()?, key, value.clone(), &self.origin).map_err(|problem| {
            // The TOML parser's excerpt is of the text made with the override, not of the file:
            // its last line (what is wrong) is kept.
            let problem = match problem.split_once("TOML parse error") {
                Some((head, _)) => format!("{head}{}", problem.lines().last().unwrap_or_default().trim()),
                None => problem,
            };
            self.refused(key, &value, problem)
        })?;
        self.overrides.push((key.to_string(), value));
        Ok(self)
    }

    /// The overrides given so far, in order.
    pub fn overrides(&self) -> &[(String, Value)] {
        &self.overrides
    }

    /// Compiles the scene: profiles read and placed, the track built, every value checked (all
    /// problems at once, each naming its key and, without overrides, its line).
    pub fn compile(&self) -> Result<Scene, Error> {
        let (text, origin) = match self.overrides.is_empty() {
            true => (self.text.clone(), self.origin.clone()),
            false => {
                let keys: Vec<&str> = self.overrides.iter().map(|(k, _)| k.as_str()).collect();
                (self.text()?, format!("{} with {}", self.origin, keys.join(", ")))
            }
        };
        Ok(Scenario::parse(&text, &origin)?.compile(&origin, &self.base)?)
    }

    /// The scenario as a TOML table with the overrides so far applied.
    fn with_overrides(&self) -> Result<toml::Table, Error> {
        let text = self.text.strip_prefix('\u{feff}').unwrap_or(&self.text);
        let mut table: toml::Table = toml::from_str(text).map_err(|e| Error::Source {
            given: self.origin.clone(),
            problem: e.to_string(),
        })?;
        for (key, value) in &self.overrides {
            set_key(&mut table, key, value.clone()).map_err(|problem| self.refused(key, value, problem))?;
        }
        Ok(table)
    }

    /// An override refused: its key, value and problem clipped (each may be megabytes); a value
    /// that cannot be shown bounded (nested too deep, too many entries) is described.
    fn refused(&self, key: &str, value: &Value, problem: String) -> Error {
        let value = match (check_value(value), value) {
            (Ok(()), _) => clipped(&value.to_string(), SHOWN_CHARS).into_owned(),
            (Err(_), Value::String(s)) => format!("\"{}\"", clipped(s, SHOWN_CHARS)),
            (Err(_), _) => {
                let kind = value.type_str();
                let article = if kind.starts_with(['a', 'e', 'i', 'o', 'u']) {
                    "an"
                } else {
                    "a"
                };
                format!("({article} {kind} too large to show)")
            }
        };
        Error::Override {
            origin: self.origin.clone(),
            key: clipped(key, SHOWN_CHARS).into_owned(),
            value,
            problem: clipped(&problem, 4 * SHOWN_CHARS).into_owned(),
        }
    }
}

/// Where a run is: what a progress callback receives, at every output sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Progress {
    /// Simulated time reached, s.
    pub t_s: f64,
    /// Simulated time the run is to cover, s.
    pub duration_s: f64,
    /// Output samples so far (per wheelset).
    pub samples: usize,
}

/// A progress callback ([`RunConfig::progress`]).
pub type ProgressCallback<'a> = Box<dyn FnMut(&Progress) + Send + 'a>;

/// The options of a run besides its scene (the command line's `--contact`, `KECSIM_THREADS`,
/// Ctrl-C and the progress bar).
#[derive(Default)]
pub struct RunConfig<'a> {
    /// A contact model by name instead of the scenario's (`kec`, `lookup`, `lookup2`, `online`,
    /// `elastic`).
    pub contact: Option<String>,
    /// Threads of the preprocessing and the right-hand sides (None: two on a machine with two
    /// cores or more; the results are the same to the last bit on any number).
    pub threads: Option<usize>,
    /// Stops the run at its next step when asked; the run then returns what it computed
    /// ([`RunResult::interrupted`]).
    pub cancel: CancelToken,
    /// Called at every output sample, from the run's thread.
    pub progress: Option<ProgressCallback<'a>>,
    /// More observers of the samples as they are computed (a recording, files of one's own).
    pub observers: Vec<&'a mut (dyn RunObserver + Send)>,
}

/// One named column of values.
#[derive(Debug, Clone, PartialEq)]
pub struct Column {
    pub name: String,
    pub values: Vec<f64>,
}

/// A table of columns of equal length (a wheelset's time series, the contact sweep).
#[derive(Debug, Clone, PartialEq)]
pub struct Columns {
    pub columns: Vec<Column>,
}

impl Columns {
    /// The column named `name`.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.columns
            .iter()
            .find(|c| c.name == name)
            .map(|c| c.values.as_slice())
    }

    /// Rows (the length of every column).
    pub fn len(&self) -> usize {
        self.columns.first().map_or(0, |c| c.values.len())
    }

    /// No rows.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Column-major table of `rows`, each of `names.len()` values.
    fn from_rows(names: &[&str], rows: impl Iterator<Item = Vec<f64>>) -> Columns {
        let mut columns: Vec<Column> = names
            .iter()
            .map(|n| Column {
                name: n.to_string(),
                values: Vec::new(),
            })
            .collect();
        for row in rows {
            for (c, v) in columns.iter_mut().zip(row) {
                c.values.push(v);
            }
        }
        Columns { columns }
    }
}

/// One wheelset's time series: the columns of its CSV (`kecsim run --csv DIR` writes
/// `DIR/NAME.csv`), in their order and units, one value per output sample.
#[derive(Debug, Clone, PartialEq)]
pub struct WheelsetSeries {
    pub name: String,
    pub series: Columns,
}

impl WheelsetSeries {
    /// The column named `name` ([`CSV_COLUMNS`]).
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.series.column(name)
    }
}

/// What a run gives back: every wheelset's time series and the summary — also when it stopped
/// early (a stop condition, a stop request, a derailment or another failure of the run: what it
/// computed up to there, and `summary.outcome`/`summary.error` saying why).
#[derive(Debug, Clone)]
pub struct RunResult {
    /// In the vehicle's order.
    pub wheelsets: Vec<WheelsetSeries>,
    /// The summary, its warnings those of the scene and the build (as `kecsim run --json`).
    pub summary: RunSummary,
    /// The run was stopped by its stop request ([`RunConfig::cancel`]).
    pub interrupted: bool,
    /// The run failed (the diagnosis; also in `summary.error`).
    pub failure: Option<String>,
}

impl RunResult {
    /// The summary as `kecsim run --json` writes it (the same keys).
    pub fn summary_json(&self) -> serde_json::Value {
        serde_json::to_value(&self.summary).expect("a run summary serialises (plain fields)")
    }

    /// The wheelset named `name`.
    pub fn wheelset(&self, name: &str) -> Option<&WheelsetSeries> {
        self.wheelsets.iter().find(|w| w.name == name)
    }
}

/// The progress callback as a run observer.
struct ProgressObserver<'a, 'b> {
    callback: &'b mut (dyn FnMut(&Progress) + Send + 'a),
    duration_s: f64,
    samples: usize,
}

impl RunObserver for ProgressObserver<'_, '_> {
    fn start(&mut self, run: &RunStart<'_>) -> Result<(), ObserverError> {
        self.duration_s = run.duration_s;
        Ok(())
    }
    fn sample(&mut self, sample: &OutputSample<'_>) -> Result<(), ObserverError> {
        self.samples += 1;
        (self.callback)(&Progress {
            t_s: sample.t,
            duration_s: self.duration_s,
            samples: self.samples,
        });
        Ok(())
    }
}

/// Runs a compiled scene (it must have a `[simulation]` and a `[vehicle]`) as `kecsim run` does,
/// and returns every wheelset's time series and the summary. A run that stops early returns what
/// it computed (see [`RunResult`]); what cannot be built is an [`Error`].
pub fn run(scene: &Scene, mut config: RunConfig<'_>) -> Result<RunResult, Error> {
    let threads = match config.threads {
        None => Threads::Default,
        Some(0) => return Err(Error::Option("threads = 0: expected at least one".into())),
        Some(n) => {
            crate::limits::check_threads("threads", n).map_err(Error::Option)?;
            Threads::Count(n)
        }
    };
    let built = scene
        .build_run(&RunOptions {
            contact: config.contact.clone(),
            speed_m_s: None,
            threads,
            cancel: config.cancel.clone(),
        })
        .map_err(|source| Error::Build {
            origin: scene.origin.clone(),
            source: Box::new(source),
        })?;
    let mut callback = config.progress.take();
    let mut progress = callback.as_mut().map(|callback| ProgressObserver {
        callback: callback.as_mut(),
        duration_s: built.settings.duration_s,
        samples: 0,
    });
    let mut observers: Vec<&mut (dyn RunObserver + Send)> = config
        .observers
        .iter_mut()
        .map(|o| &mut **o as &mut (dyn RunObserver + Send))
        .collect();
    if let Some(p) = progress.as_mut() {
        observers.push(p);
    }
    let out = built.run(&mut observers);
    let mut summary = out.summary;
    summary.warnings = scene.warnings.iter().chain(&built.notes).cloned().collect();
    let wheelsets = out
        .wheelsets
        .iter()
        .map(|(name, samples)| WheelsetSeries {
            name: name.clone(),
            series: Columns::from_rows(&CSV_COLUMNS, samples.iter().map(csv_row)),
        })
        .collect();
    Ok(RunResult {
        wheelsets,
        summary,
        interrupted: matches!(out.end, RunEnd::Stopped(Stop::Interrupted { .. })),
        failure: match &out.end {
            RunEnd::Failed(e) => Some(e.to_string()),
            _ => None,
        },
    })
}

/// The names of the scene's wheelsets, in the vehicle's order (the keys of
/// [`RunResult::wheelsets`], the CSV files' names).
pub fn wheelset_names(scene: &Scene) -> Result<Vec<String>, Error> {
    match &scene.simulation {
        Some((_, vehicle)) => Ok(vehicle.wheelset_names()),
        None => Err(Error::Build {
            origin: scene.origin.clone(),
            source: Box::new(BuildError::NoSimulation),
        }),
    }
}

/// The contact geometry sweep over the lateral displacement y of the scene's wheel–rail pair: the
/// 1-entry lookup table (Eq. 43–46) as `kecsim contact --csv` writes it (its columns and units,
/// one row per tabulated y; a value the table has not — the second contact where there is none —
/// is NaN, an empty cell in the CSV), and the equivalent conicity (EN 15302) at ŷ = 1..6 mm.
#[derive(Debug, Clone)]
pub struct ContactSweep {
    pub table: Columns,
    /// (ŷ mm, Annex B conicity, linear-regression conicity); None where it cannot be computed.
    pub conicity: Vec<(f64, Option<f64>, Option<f64>)>,
    /// The text `kecsim contact` prints (table range, jumps, interpolation error, conicity).
    pub report: String,
}

/// A contact sweep's settings from a grid step and a largest |y|, both mm (None: the defaults, as
/// `kecsim contact` without `--step`, `--y-max`), checked as `kecsim contact` checks them
/// ([`TableSettings::from_mm`]: the step positive and at most
/// [`lookup::MAX_STEP_MM`], the half-range positive); the errors name them `step_mm`, `y_max_mm`.
pub fn sweep_settings(step_mm: Option<f64>, y_max_mm: Option<f64>) -> Result<TableSettings, Error> {
    let step = step_mm.unwrap_or(TableSettings::default().step_m * 1e3);
    TableSettings::from_mm(("step_mm", step), y_max_mm.map(|v| ("y_max_mm", v))).map_err(Error::Option)
}

/// The scene's contact sweep ([`ContactSweep`]) with the table settings given (the defaults:
/// `TableSettings::default()`, as `kecsim contact` without options). A half-range
/// ([`TableSettings::y_max_m`]) beyond the pair's flange climb is refused as `kecsim contact
/// --y-max` refuses it ([`TableSettings::check_y_max`]; an [`Error::Option`] naming it `y_max_mm`).
///
/// ```
/// use kecsim::api::{contact_sweep, SceneInput};
/// use kecsim::contact::lookup::TableSettings;
///
/// let scene = SceneInput::embedded_default().compile()?;
/// let sweep = contact_sweep(&scene, &TableSettings::default())?;
/// let (y, dr) = (sweep.table.column("y_mm").unwrap(), sweep.table.column("dr_mm").unwrap());
/// // Centred, a symmetric wheelset rolls on equal radii.
/// let k = y.iter().position(|v| v.abs() < 1e-9).expect("y = 0 is tabulated");
/// assert!(dr[k].abs() < 1e-6);
/// // The stand-in wheel's equivalent conicity at ŷ = 2 mm (EN 15302 Annex B): 0.29.
/// let (amplitude_mm, annex_b, _) = sweep.conicity[1];
/// assert!(amplitude_mm == 2.0 && (annex_b.unwrap() - 0.29).abs() < 0.01);
/// # Ok::<(), kecsim::api::Error>(())
/// ```
pub fn contact_sweep(scene: &Scene, settings: &TableSettings) -> Result<ContactSweep, Error> {
    let geom = ContactGeometry::with_defaults(scene.pair.clone());
    let failed = |source| Error::Sweep {
        origin: scene.origin.clone(),
        source: Box::new(source),
    };
    settings.check_y_max(&geom, "y_max_mm").map_err(|e| match e {
        TableError::Invalid(m) => Error::Option(format!("{}: {m}", scene.origin)),
        other => failed(other),
    })?;
    let report = ContactReport::new(&geom, settings).map_err(failed)?;
    let t = &report.table;
    let table = Columns::from_rows(
        &lookup::CSV_COLUMNS,
        t.rows.iter().map(|r| lookup::row_values(r, t).to_vec()),
    );
    let conicity = report
        .conicity
        .iter()
        .map(|c| {
            (
                c.amplitude * 1e3,
                c.annex_b.clone().ok(),
                c.regression.clone().ok(),
            )
        })
        .collect();
    let text = report.summary(&format!("contact: {}", scene.name)).to_string();
    Ok(ContactSweep {
        table,
        conicity,
        report: text,
    })
}

/// A profile's points as its file holds them: lateral y and vertical z of a left-side profile,
/// mm (the columns `y_mm`, `z_mm` of `profiles/*.csv`), with its name, kind and source.
#[derive(Debug, Clone, PartialEq)]
pub struct ProfilePoints {
    pub name: String,
    /// `wheel` or `rail`.
    pub kind: String,
    pub source: String,
    pub y_mm: Vec<f64>,
    pub z_mm: Vec<f64>,
}

impl ProfilePoints {
    fn of(p: &Profile) -> ProfilePoints {
        let (s, z) = p.knots();
        ProfilePoints {
            name: p.name.clone(),
            kind: p.kind.to_string(),
            source: p.source.clone(),
            y_mm: s.iter().map(|v| v * 1e3).collect(),
            z_mm: z.iter().map(|v| v * 1e3).collect(),
        }
    }
}

/// The scene's wheel and rail profiles (in that order), as their files hold them.
///
/// ```
/// use kecsim::api::{profiles, SceneInput};
///
/// let [wheel, rail] = profiles(&SceneInput::embedded_default().compile()?);
/// assert_eq!((wheel.kind.as_str(), rail.name.as_str()), ("wheel", "54e1:blend=1"));
/// assert_eq!(rail.y_mm.len(), rail.z_mm.len());
/// # Ok::<(), kecsim::api::Error>(())
/// ```
pub fn profiles(scene: &Scene) -> [ProfilePoints; 2] {
    [
        ProfilePoints::of(&scene.pair.wheel),
        ProfilePoints::of(&scene.pair.rail),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    const SHORT: &str = "simulation.duration_s";

    /// An override is checked at once, its error naming the key; a misspelt key is refused.
    #[test]
    fn a_misspelt_override_is_refused_naming_its_key() {
        let mut input = SceneInput::embedded_default();
        let e = input.set("simulation.sped_m_s", 10.0).unwrap_err().to_string();
        assert!(e.contains("simulation.sped_m_s") && e.contains("sped_m_s"), "{e}");
        assert!(e.contains("unknown field"), "{e}");
        let e = input.set("simulation.speed_m_s", "fast").unwrap_err().to_string();
        assert!(e.contains("simulation.speed_m_s"), "{e}");
        assert!(input.overrides().is_empty());
        input.set(SHORT, 0.05).unwrap();
        assert_eq!(input.overrides().len(), 1);
    }

    /// Hostile overrides (issue 66): a key of 50 000 parts, a value nested 1e5 deep or of 1e6
    /// entries, a string of 1e7 characters — each refused at once with its limit, the message a
    /// few hundred characters, never the value in full; and no more than [`MAX_OVERRIDES`].
    #[test]
    fn hostile_overrides_are_refused_with_short_messages() {
        let mut input = SceneInput::embedded_default();
        let many = vec!["simulation"; 50_000].join(".");
        let e = input.set(&many, 1.0).unwrap_err().to_string();
        assert!(e.contains("50000 parts: at most 16") && e.len() < 800, "{e}");
        let mut deep = Value::Float(1.0);
        for _ in 0..100_000 {
            deep = Value::Array(vec![deep]);
        }
        // (Refused before it is cloned or shown, and dropped without recursion.)
        let e = input.set(SHORT, deep).unwrap_err().to_string();
        assert!(
            e.contains("deeper than 32 levels")
                && e.contains("= (an array too large to show)")
                && e.len() < 800,
            "{e}"
        );
        let huge = Value::Array(vec![Value::Float(0.5); 1_000_000]);
        let e = input.set(SHORT, huge).unwrap_err().to_string();
        assert!(e.contains("more than 100000 entries") && e.len() < 800, "{e}");
        let e = input.set(SHORT, "x".repeat(10_000_000)).unwrap_err().to_string();
        assert!(
            e.contains(SHORT) && e.contains("characters)") && e.len() < 1200,
            "{e}"
        );
        let e = input
            .set(SHORT, Value::Array(vec![Value::Float(0.5); 50_000]))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("the scenario does not take it") && e.len() < 1200,
            "{e}"
        );
        assert!(input.overrides().is_empty());
        for _ in 0..MAX_OVERRIDES {
            input.set("name", "n").unwrap();
        }
        let e = input.set("name", "n").unwrap_err().to_string();
        assert!(e.contains("more than 1000 overrides"), "{e}");
    }

    /// The files a scene reads: the scenario file and the profile it names; TOML text, the
    /// profiles it names only.
    #[test]
    fn the_files_read_are_the_scenario_and_the_files_it_names() {
        let dir = std::env::temp_dir().join(format!("kecsim-api-files-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        std::fs::copy(root.join("profiles/s1002.csv"), dir.join("wheel.csv")).unwrap();
        let text = "schema_version = 1\nname = \"x\"\n[profiles]\nwheel = \"wheel.csv\"\nrail = \"60e1\"\ninclination = \"1:40\"\n";
        std::fs::write(dir.join("scene.toml"), text).unwrap();
        let input = SceneInput::file(dir.join("scene.toml")).unwrap();
        let files = input.files_read(&input.compile().unwrap());
        assert_eq!(files, vec![dir.join("wheel.csv"), dir.join("scene.toml")]);
        let input = SceneInput::toml(text, &dir).unwrap();
        assert_eq!(
            input.files_read(&input.compile().unwrap()),
            vec![dir.join("wheel.csv")]
        );
        std::fs::remove_dir_all(&dir).ok();
    }

    /// The sweep's options checked as `kecsim contact` checks them, named as the facade names them.
    #[test]
    fn sweep_settings_are_checked_and_the_half_range_against_the_flange_climb() {
        assert_eq!(sweep_settings(None, None).unwrap(), TableSettings::default());
        let e = sweep_settings(Some(5.0), None).unwrap_err().to_string();
        assert!(e.contains("step_mm 5 mm: a grid coarser than 0.25 mm"), "{e}");
        let e = sweep_settings(None, Some(-1.0)).unwrap_err().to_string();
        assert!(e.contains("y_max_mm -1: expected a positive length"), "{e}");
        let scene = SceneInput::embedded_default().compile().unwrap();
        let e = contact_sweep(&scene, &sweep_settings(None, Some(40.0)).unwrap())
            .unwrap_err()
            .to_string();
        assert!(e.contains("y_max_mm 40.000 mm: beyond the flange climb"), "{e}");
        let sweep = contact_sweep(&scene, &sweep_settings(Some(0.25), Some(3.0)).unwrap()).unwrap();
        let y = sweep.table.column("y_mm").unwrap();
        assert!(
            y[0] >= -3.25 && y[y.len() - 1] <= 3.25,
            "{} .. {}",
            y[0],
            y[y.len() - 1]
        );
    }

    /// A scenario error in TOML text names `<string>` and the line.
    #[test]
    fn an_error_in_toml_text_names_its_line() {
        let text = "schema_version = 1\nname = \"x\"\n\n[simulation]\nspeed_m_s = 1.0\nduration_s = 1.0\nbogus = 3\n";
        let e = SceneInput::toml(text, ".").unwrap_err().to_string();
        assert!(e.starts_with("<string>"), "{e}");
        assert!(e.contains("bogus"), "{e}");
        assert!(e.contains("line 7") || e.contains(":7"), "{e}");
    }

    /// Neither a file nor TOML: named as a missing file.
    #[test]
    fn a_missing_file_is_named() {
        let e = SceneInput::path_or_toml("no/such/scene.toml")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("no/such/scene.toml") && e.contains("no such scenario file"),
            "{e}"
        );
    }

    /// The profiles are their files' points (mm): the embedded default's rail is the 54E1,
    /// 72 mm wide at most, its crown at z = 0.
    #[test]
    fn profiles_are_the_files_points_in_mm() {
        let scene = SceneInput::embedded_default().compile().unwrap();
        let [wheel, rail] = profiles(&scene);
        assert_eq!(wheel.kind, "wheel");
        assert_eq!(rail.kind, "rail");
        let zmax = rail.z_mm.iter().cloned().fold(f64::MIN, f64::max);
        assert!(zmax.abs() < 1e-6, "rail crown at {zmax} mm");
        let width = rail.y_mm.last().unwrap() - rail.y_mm[0];
        assert!((50.0..80.0).contains(&width), "rail head {width} mm wide");
    }

    /// A short run through the facade: the columns are the CSV's, every one as long as the
    /// samples the summary counts; a run stopped by its request returns what it computed.
    #[test]
    fn a_run_gives_the_csv_columns_and_a_stopped_run_what_it_computed() {
        let mut input = SceneInput::embedded_default();
        input.set(SHORT, 3.0).unwrap();
        let scene = input.compile().unwrap();
        let result = run(&scene, RunConfig::default()).unwrap();
        assert_eq!(result.summary.outcome, "completed");
        let w = &result.wheelsets[0];
        let names: Vec<&str> = w.series.columns.iter().map(|c| c.name.as_str()).collect();
        assert_eq!(names, *CSV_COLUMNS);
        assert_eq!(w.series.len(), result.summary.samples);
        assert!(w.series.columns.iter().all(|c| c.values.len() == w.series.len()));
        let t = w.column("t_s").unwrap();
        assert!((t[t.len() - 1] - 3.0).abs() < 1e-9, "{}", t[t.len() - 1]);

        let cancel = CancelToken::new();
        let stop = cancel.clone();
        let config = RunConfig {
            cancel,
            progress: Some(Box::new(move |p: &Progress| {
                // (The observers run a sample behind the integrator, on the output worker: a
                // stop asked from one comes a few samples later.)
                if p.t_s >= 0.1 {
                    stop.request();
                }
            })),
            ..RunConfig::default()
        };
        let part = run(&scene, config).unwrap();
        assert!(part.interrupted);
        let n = part.wheelsets[0].series.len();
        assert!(n > 0 && n < result.wheelsets[0].series.len(), "{n}");
        // What it computed is the full run's beginning, bit for bit, on the output grid; the
        // integrator ends at the step where the stop found it, with one more sample there
        // (between two output times) unless the grid just gave one.
        let (t_full, t_part) = (
            result.wheelsets[0].column("t_s").unwrap(),
            part.wheelsets[0].column("t_s").unwrap(),
        );
        let on_grid = match (t_part[n - 1] - t_full[n - 1]).abs() < 1e-12 {
            true => n,
            false => {
                assert!(t_full[n - 2] < t_part[n - 1] && t_part[n - 1] < t_full[n - 1]);
                n - 1
            }
        };
        for column in ["t_s", "y_mm", "yaw_mrad"] {
            let full = result.wheelsets[0].column(column).unwrap();
            let part = part.wheelsets[0].column(column).unwrap();
            assert_eq!(&part[..on_grid], &full[..on_grid], "{column}");
        }
    }
}
