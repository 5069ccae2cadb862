//! The study file (`kecsim study STUDY.toml`): a base scenario, the axes to vary — any scenario
//! value by its key path — as a full grid or as random samples, and what to extract from each run.
//!
//! ```toml
//! schema_version = 1
//! name = "speed sweep over four track realisations"
//! scenario = "../scenes/ms_vehicle_tab6.toml"   # relative to this file
//! sampling = "grid"                              # or "random" (then `samples = N`)
//! seed = 7                                       # the study seed (random draws, derived seeds)
//! extract = ["max_y_over_q", "max_delta_q_over_q0", "rms(w1.y_mm)", "amplitude(*.y_mm)"]
//!
//! [[axis]]
//! key = "simulation.speed_m_s"
//! range = { from = 15.0, to = 25.0, step = 5.0 }
//!
//! [[axis]]
//! key = "track.irregularities.seed"
//! seeds = 4                                      # four seeds derived from the study seed
//! ```
//!
//! An axis gives its values as `values = [...]` (any TOML values), `range = { from, to, step }` or
//! `{ from, to, count }` (inclusive; integers stay integers), `seeds = N` (N integer seeds derived
//! from the study seed, SplitMix64) or, with random sampling only, `uniform = [lo, hi]`. A grid
//! runs every combination (the last axis varies fastest); random sampling draws each case's value
//! of every axis from a generator seeded by the study seed and the case's index, so that a case
//! is the same whatever the number of jobs or shards.

use std::path::{Path, PathBuf};

use serde::Deserialize;
use toml::{Spanned, Table, Value};

use super::extract::Extract;
use super::StudyError;
use crate::scenario::Scenario;
use crate::track::file::line_of;

/// The study schema this kecsim reads.
pub const STUDY_SCHEMA_VERSION: u32 = 1;

/// The most cases one study may hold (each is a simulation; `--no-limits` lifts it).
pub const MAX_CASES: usize = 100_000;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct StudyToml {
    schema_version: u32,
    name: String,
    scenario: Spanned<String>,
    #[serde(default)]
    sampling: Option<Spanned<String>>,
    #[serde(default)]
    samples: Option<Spanned<i64>>,
    #[serde(default)]
    seed: u64,
    #[serde(default)]
    extract: Vec<Spanned<String>>,
    #[serde(default)]
    axis: Vec<Spanned<AxisToml>>,
    #[serde(default)]
    kind: Option<Spanned<String>>,
    #[serde(default)]
    critical_speed: Option<Spanned<CriticalToml>>,
}

/// `[critical_speed]` of `kind = "critical_speed"`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct CriticalToml {
    speeds: RangeToml,
    #[serde(default = "default_release")]
    release_lateral_m: f64,
    #[serde(default = "default_critical_duration")]
    duration_s: f64,
    #[serde(default = "default_threshold")]
    threshold_mm: f64,
}

fn default_release() -> f64 {
    0.004
}
fn default_critical_duration() -> f64 {
    10.0
}
fn default_threshold() -> f64 {
    0.1
}

/// A critical-speed study (`kind = "critical_speed"`): a speed sweep at constant speed, each
/// case released from `release_lateral_m` (on the hunting limit cycle where one exists), with the
/// limit cycle's amplitude (`amplitude(*.y_mm)`) and the linear stability at that speed
/// (`linear_max_real_1_s`, `linear_hunting_hz`) extracted.
///
/// Why a sweep, not a ramp or a bisection: the cases are independent (all cores, a cluster's
/// shards), the amplitudes against speed are the bifurcation diagram itself, and each case runs at
/// constant speed, so its amplitude is the cycle's at that speed (a ramp's lags behind it). The
/// nonlinear critical speed — the lowest speed at which a limit cycle lives, the cycle's fold —
/// is bracketed by the sweep's step (refine with a finer `speeds` over the bracket); the linear
/// one is interpolated where Re λ crosses zero.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CriticalSpeedSettings {
    pub release_lateral_m: f64,
    pub duration_s: f64,
    /// A case hunts where its amplitude over the last quarter exceeds this, mm.
    pub threshold_mm: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct AxisToml {
    key: Spanned<String>,
    #[serde(default)]
    values: Option<Vec<Value>>,
    #[serde(default)]
    range: Option<RangeToml>,
    #[serde(default)]
    seeds: Option<i64>,
    #[serde(default)]
    uniform: Option<[f64; 2]>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RangeToml {
    from: Value,
    to: Value,
    #[serde(default)]
    step: Option<Value>,
    #[serde(default)]
    count: Option<i64>,
}

/// How the cases are chosen.
#[derive(Debug, Clone, PartialEq)]
pub enum Sampling {
    /// Every combination of the axes' values.
    Grid,
    /// `samples` cases, each axis drawn at random.
    Random { samples: usize },
}

/// The values an axis takes.
#[derive(Debug, Clone, PartialEq)]
pub enum AxisValues {
    /// A list (a grid runs each; random sampling picks one uniformly).
    List(Vec<Value>),
    /// Uniform in [lo, hi] (random sampling only).
    Uniform(f64, f64),
}

/// One varied scenario value.
#[derive(Debug, Clone, PartialEq)]
pub struct Axis {
    /// Its key path in the scenario (`simulation.speed_m_s`; array entries by index:
    /// `vehicle.bodies.0.mass_kg`).
    pub key: String,
    pub values: AxisValues,
    /// The line of the study file that names it.
    pub line: usize,
    /// Its values are derived seeds (`seeds = N`): realisations of one random input, over which
    /// the results are summarised statistically.
    pub seeds: bool,
}

/// One case: its index, the axes' values (in axis order) and the scenario text they give.
#[derive(Debug, Clone, PartialEq)]
pub struct Case {
    pub index: usize,
    pub values: Vec<Value>,
    pub scenario: String,
}

/// A study as read and checked: every case's scenario parses.
#[derive(Debug, Clone)]
pub struct Study {
    pub name: String,
    /// The study file.
    pub path: PathBuf,
    /// The base scenario file; relative paths in the cases' scenarios start from its directory.
    pub scenario_path: PathBuf,
    pub sampling: Sampling,
    pub seed: u64,
    pub axes: Vec<Axis>,
    pub extracts: Vec<Extract>,
    /// The line of the study file that names each extract.
    pub extract_lines: Vec<usize>,
    pub cases: Vec<Case>,
    /// `Some`: a critical-speed study (its first axis is the speed).
    pub critical_speed: Option<CriticalSpeedSettings>,
    /// Identifies the study's content (the kecsim version, its cases' scenarios, axes and
    /// extracts): shards and finished cases are matched on it (FNV-1a, 64 bit).
    pub id: String,
}

impl Study {
    /// The files the study reads: itself, its base scenario and the files the base names (profile
    /// files, a measured irregularity file) — inputs no output of the study may overwrite.
    pub fn input_files(&self) -> Vec<PathBuf> {
        let mut files = vec![self.path.clone(), self.scenario_path.clone()];
        let base = self.scenario_path.parent().unwrap_or(Path::new("."));
        let origin = self.scenario_path.display().to_string();
        if let Ok(scene) = Scenario::read(&self.scenario_path).and_then(|s| s.compile(&origin, base)) {
            files.extend(scene.inputs);
        }
        // Files named only by an axis (`profiles.wheel = ["w1.csv", "w2.csv"]`, an irregularity
        // file per case): every text value that names a file, as the scenario resolves it
        // (relative to its directory) and as given.
        for axis in &self.axes {
            if let AxisValues::List(values) = &axis.values {
                for v in values {
                    if let Value::String(text) = v {
                        for p in [base.join(text), PathBuf::from(text)] {
                            if p.is_file() && !files.contains(&p) {
                                files.push(p);
                            }
                        }
                    }
                }
            }
        }
        files
    }

    /// Reads, checks and expands a study file.
    pub fn read(path: &Path) -> Result<Study, StudyError> {
        let origin = path.display().to_string();
        let text = crate::limits::read_text(path).map_err(|e| StudyError::Io {
            path: origin.clone(),
            message: e.to_string(),
        })?;
        Self::parse(&text, path)
    }

    /// Parses study text; `path` names it in errors and locates the base scenario.
    pub fn parse(text: &str, path: &Path) -> Result<Study, StudyError> {
        let origin = path.display().to_string();
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let at = |offset: usize, message: String| StudyError::Input {
            path: origin.clone(),
            line: line_of(text, offset),
            message,
        };
        let raw: StudyToml = toml::from_str(text).map_err(|e| StudyError::Input {
            path: origin.clone(),
            line: e.span().map_or(0, |s| line_of(text, s.start)),
            message: e.message().trim_end().to_string(),
        })?;
        if let Some(c) = raw.name.chars().find(|c| c.is_control()) {
            let offset = text.find("name").unwrap_or(0);
            return Err(at(
                offset,
                format!(
                    "name = {:?}: contains the control character U+{:04X}; a name is printed and recorded (letters, digits, spaces, punctuation)",
                    raw.name, c as u32
                ),
            ));
        }
        if raw.schema_version != STUDY_SCHEMA_VERSION {
            return Err(at(
                0,
                format!(
                    "schema_version = {}: this kecsim reads schema_version = {STUDY_SCHEMA_VERSION}",
                    raw.schema_version
                ),
            ));
        }
        let base_dir = path.parent().unwrap_or(Path::new("."));
        let scenario_path = base_dir.join(raw.scenario.get_ref());
        let base_text = crate::limits::read_text(&scenario_path).map_err(|e| {
            at(
                raw.scenario.span().start,
                format!(
                    "scenario = \"{}\": cannot read {}: {e}",
                    raw.scenario.get_ref(),
                    scenario_path.display()
                ),
            )
        })?;
        let scenario_origin = scenario_path.display().to_string();
        let base: Table = toml::from_str(&base_text).map_err(|e| {
            at(
                raw.scenario.span().start,
                format!("scenario {scenario_origin}: {}", e.message().trim_end()),
            )
        })?;
        Scenario::parse(&base_text, &scenario_origin)
            .map_err(|e| at(raw.scenario.span().start, format!("the base scenario: {e}")))?;

        let sampling = match (raw.sampling.as_ref().map(|s| s.get_ref().as_str()), &raw.samples) {
            (None | Some("grid"), None) => Sampling::Grid,
            (None | Some("grid"), Some(n)) => {
                return Err(at(
                    n.span().start,
                    "samples: only random sampling (sampling = \"random\") takes a number of samples".into(),
                ))
            }
            (Some("random"), Some(n))
                if (1..=MAX_CASES as i64).contains(n.get_ref())
                    || crate::limits::lifted() && *n.get_ref() >= 1 =>
            {
                Sampling::Random {
                    samples: *n.get_ref() as usize,
                }
            }
            (Some("random"), Some(n)) => {
                return Err(at(
                    n.span().start,
                    format!("samples = {}: expected 1 ..= {MAX_CASES}", n.get_ref()),
                ))
            }
            (Some("random"), None) => {
                return Err(at(
                    raw.sampling.as_ref().map_or(0, |s| s.span().start),
                    "sampling = \"random\" needs `samples = N`".into(),
                ))
            }
            (Some(other), _) => {
                return Err(at(
                    raw.sampling.as_ref().map_or(0, |s| s.span().start),
                    format!("sampling = \"{other}\": expected \"grid\" or \"random\""),
                ))
            }
        };
        let random = matches!(sampling, Sampling::Random { .. });

        let mut axes = Vec::new();
        let mut extracts = Vec::new();
        let mut extract_lines = Vec::new();
        let critical_speed = match (
            raw.kind.as_ref().map(|k| k.get_ref().as_str()),
            &raw.critical_speed,
        ) {
            (None | Some("cases"), None) => None,
            (None | Some("cases"), Some(c)) => {
                return Err(at(
                    c.span().start,
                    "[critical_speed] belongs to kind = \"critical_speed\"".into(),
                ))
            }
            (Some("critical_speed"), None) => {
                return Err(at(
                    raw.kind.as_ref().map_or(0, |k| k.span().start),
                    "kind = \"critical_speed\" needs a [critical_speed] table (speeds = { from, to, step })"
                        .into(),
                ))
            }
            (Some("critical_speed"), Some(c)) => {
                let line = line_of(text, c.span().start);
                if random {
                    return Err(at(
                            c.span().start,
                            "[critical_speed]: a critical-speed study is a sweep: it takes no sampling = \"random\"".into(),
                        ));
                }
                let (own, settings) = critical_speed_axes(c.get_ref(), &base, &scenario_origin)
                    .map_err(|m| at(c.span().start, format!("[critical_speed]: {m}")))?;
                for a in own {
                    axes.push(Axis { line, ..a });
                }
                for x in ["amplitude(*.y_mm)", "linear_max_real_1_s", "linear_hunting_hz"] {
                    extracts.push(Extract::parse(x).map_err(|m| at(c.span().start, m))?);
                    extract_lines.push(line);
                }
                Some(settings)
            }
            (Some(other), _) => {
                return Err(at(
                    raw.kind.as_ref().map_or(0, |k| k.span().start),
                    format!("kind = \"{other}\": expected \"cases\" (the default) or \"critical_speed\""),
                ))
            }
        };
        for a in &raw.axis {
            let line = line_of(text, a.span().start);
            let a = a.get_ref();
            let key = a.key.get_ref().clone();
            let here = |message: String| StudyError::Input {
                path: origin.clone(),
                line: line_of(text, a.key.span().start),
                // (A key may be a hostile megabyte: named by its beginning.)
                message: format!("axis `{}`: {message}", clipped(&key, 80)),
            };
            if axes.iter().any(|b: &Axis| b.key == key) {
                return Err(here("named twice".into()));
            }
            let values = axis_values(a, raw.seed, random).map_err(here)?;
            if let AxisValues::List(v) = &values {
                if v.is_empty() {
                    return Err(here("no values (an empty list or range)".into()));
                }
            }
            check_axis(&base, &key, &values, &scenario_origin).map_err(here)?;
            if a.seeds.is_some() {
                // Realisations of the generated irregularities: a seed nothing reads would give
                // the same run N times, presented as N realisations.
                let track = base.get("track");
                let generated = track
                    .and_then(|t| t.get("irregularities"))
                    .and_then(|i| i.get("psd"))
                    .is_some()
                    && track
                        .and_then(|t| t.get("horizontal"))
                        .and_then(|h| h.as_array())
                        .is_some_and(|h| !h.is_empty());
                if key != "track.irregularities.seed" || !generated {
                    return Err(here(format!(
                        "seeds = N draws realisations of the generated track irregularities: its key is track.irregularities.seed, and the base scenario ({scenario_origin}) must generate them ([track] sections and [track.irregularities] psd = \"…\"){}",
                        if generated { "" } else { "; it does not, so every case would be the same run" }
                    )));
                }
            }
            axes.push(Axis {
                key,
                values,
                line,
                seeds: a.seeds.is_some(),
            });
        }

        for e in &raw.extract {
            extract_lines.push(line_of(text, e.span().start));
            let x = Extract::parse(e.get_ref()).map_err(|m| at(e.span().start, m))?;
            if extracts.contains(&x) {
                return Err(at(
                    e.span().start,
                    format!("extract `{}` named twice", e.get_ref()),
                ));
            }
            extracts.push(x);
        }

        // The cases.
        let count = match &sampling {
            Sampling::Grid => axes.iter().try_fold(1usize, |n, a| match &a.values {
                AxisValues::List(v) => n.checked_mul(v.len()),
                AxisValues::Uniform(..) => Some(n),
            }),
            Sampling::Random { samples } => Some(*samples),
        };
        let count = match count {
            Some(n) if n <= MAX_CASES || crate::limits::lifted() => n,
            _ => {
                return Err(at(
                    0,
                    format!("the axes make more than {MAX_CASES} cases (--no-limits lifts this)"),
                ))
            }
        };
        let mut cases = Vec::with_capacity(count);
        for index in 0..count {
            let values = case_values(&sampling, &axes, raw.seed, index);
            let mut table = base.clone();
            for (a, v) in axes.iter().zip(&values) {
                set_key(&mut table, &a.key, v.clone()).map_err(|m| StudyError::Input {
                    path: origin.clone(),
                    line: a.line,
                    message: format!("axis `{}`: {m}", a.key),
                })?;
            }
            let scenario = toml::to_string(&table).map_err(|e| at(0, e.to_string()))?;
            // (A case's combination, not one line, is at fault: no line.)
            Scenario::parse(&scenario, &scenario_origin).map_err(|e| StudyError::Input {
                path: origin.clone(),
                line: 0,
                message: format!(
                    "case {index} ({}): the scenario does not take it: {}",
                    describe(&axes, &values),
                    scenario_message(&e.to_string(), &scenario_origin)
                ),
            })?;
            cases.push(Case {
                index,
                values,
                scenario,
            });
        }

        // The results of another kecsim version are another study's (the same scenario may give
        // other figures).
        let mut id = Fnv::new();
        id.add(concat!("kecsim ", env!("CARGO_PKG_VERSION")).as_bytes());
        id.add(raw.name.as_bytes());
        for a in &axes {
            id.add(a.key.as_bytes());
        }
        for x in &extracts {
            id.add(x.name().as_bytes());
        }
        if let Some(c) = &critical_speed {
            id.add(format!("critical_speed {}", c.threshold_mm).as_bytes());
        }
        for c in &cases {
            id.add(c.scenario.as_bytes());
        }
        Ok(Study {
            name: raw.name,
            path: path.to_path_buf(),
            scenario_path,
            sampling,
            seed: raw.seed,
            axes,
            extracts,
            extract_lines,
            cases,
            critical_speed,
            id: format!("{:016x}", id.finish()),
        })
    }

    /// The directory relative paths of the cases' scenarios start from.
    pub fn scenario_dir(&self) -> &Path {
        self.scenario_path.parent().unwrap_or(Path::new("."))
    }
}

/// Case `index`'s value of every axis: its place in the grid (the last axis fastest), or drawn
/// from a generator seeded by the study seed and the index.
fn case_values(sampling: &Sampling, axes: &[Axis], seed: u64, index: usize) -> Vec<Value> {
    match sampling {
        Sampling::Grid => {
            let mut rest = index;
            let mut v = vec![Value::Boolean(false); axes.len()];
            for (k, a) in axes.iter().enumerate().rev() {
                if let AxisValues::List(list) = &a.values {
                    v[k] = list[rest % list.len()].clone();
                    rest /= list.len();
                }
            }
            v
        }
        Sampling::Random { .. } => {
            let mut rng = SplitMix64::new(seed ^ (index as u64).wrapping_mul(0xD6E8_FEB8_6659_FD93));
            axes.iter()
                .map(|a| match &a.values {
                    AxisValues::List(list) => {
                        list[(rng.unit() * list.len() as f64) as usize % list.len()].clone()
                    }
                    AxisValues::Uniform(lo, hi) => Value::Float(lo + (hi - lo) * rng.unit()),
                })
                .collect()
        }
    }
}

/// The axes a critical-speed study sets itself (speed sweep, constant speed, release, duration),
/// checked against the base scenario, and its settings.
fn critical_speed_axes(
    c: &CriticalToml,
    base: &Table,
    origin: &str,
) -> Result<(Vec<Axis>, CriticalSpeedSettings), String> {
    if !(c.release_lateral_m.is_finite() && (0.0..=0.02).contains(&c.release_lateral_m)) {
        return Err(format!(
            "release_lateral_m = {}: expected 0 ..= 0.02 m",
            c.release_lateral_m
        ));
    }
    if !(c.duration_s.is_finite() && c.duration_s > 0.0) {
        return Err(format!("duration_s = {}: expected > 0", c.duration_s));
    }
    if !(c.threshold_mm.is_finite() && c.threshold_mm > 0.0) {
        return Err(format!("threshold_mm = {}: expected > 0", c.threshold_mm));
    }
    let speeds = range_values(&c.speeds).map_err(|m| format!("speeds: {m}"))?;
    let mut axes = Vec::new();
    for (key, values) in [
        ("simulation.speed_m_s", speeds),
        ("simulation.speed_ramp_m_s2", vec![Value::Float(0.0)]),
        (
            "simulation.initial.lateral_m",
            vec![Value::Float(c.release_lateral_m)],
        ),
        ("simulation.duration_s", vec![Value::Float(c.duration_s)]),
    ] {
        let values = AxisValues::List(values);
        check_axis(base, key, &values, origin).map_err(|m| format!("`{key}`: {m}"))?;
        axes.push(Axis {
            key: key.to_string(),
            values,
            line: 0,
            seeds: false,
        });
    }
    Ok((
        axes,
        CriticalSpeedSettings {
            release_lateral_m: c.release_lateral_m,
            duration_s: c.duration_s,
            threshold_mm: c.threshold_mm,
        },
    ))
}

/// The values an axis gives: exactly one of `values`, `range`, `seeds`, `uniform` (the latter
/// with random sampling only).
fn axis_values(a: &AxisToml, study_seed: u64, random: bool) -> Result<AxisValues, String> {
    match (&a.values, &a.range, a.seeds, a.uniform) {
        (Some(v), None, None, None) => Ok(AxisValues::List(v.clone())),
        (None, Some(r), None, None) => range_values(r).map(AxisValues::List),
        (None, None, Some(n), None) => {
            if !(1..=MAX_CASES as i64).contains(&n) {
                return Err(format!("seeds = {n}: expected 1 ..= {MAX_CASES}"));
            }
            Ok(AxisValues::List(
                (0..n as u64)
                    .map(|k| Value::Integer(derived_seed(study_seed, k)))
                    .collect(),
            ))
        }
        (None, None, None, Some([lo, hi])) => {
            if !random {
                return Err("`uniform` draws at random: it needs sampling = \"random\" (a grid takes `values`, `range` or `seeds`)".into());
            }
            if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
                return Err(format!("uniform = [{lo}, {hi}]: expected finite lo <= hi"));
            }
            Ok(AxisValues::Uniform(lo, hi))
        }
        _ => Err("give exactly one of `values`, `range`, `seeds`, `uniform`".into()),
    }
}

/// Checks that the scenario reads `key`: the base with the axis's first value must still parse
/// as a scenario (its fields are checked strictly, unknown keys rejected).
fn check_axis(base: &Table, key: &str, values: &AxisValues, origin: &str) -> Result<(), String> {
    let first = match values {
        AxisValues::List(v) => v.first().cloned().ok_or("no values (an empty list or range)")?,
        AxisValues::Uniform(lo, _) => Value::Float(*lo),
    };
    check_key(base, key, first, origin)
}

/// Checks that the scenario `base` with `key` set to `value` still parses as a scenario (its
/// fields are checked strictly, unknown keys rejected): a study's axis, an override of the
/// facade ([`crate::api::SceneInput::set`]).
pub(crate) fn check_key(base: &Table, key: &str, value: Value, origin: &str) -> Result<(), String> {
    let mut probe = base.clone();
    set_key(&mut probe, key, value)?;
    let probe_text = toml::to_string(&probe).map_err(|e| e.to_string())?;
    Scenario::parse(&probe_text, origin).map(|_| ()).map_err(|e| {
        format!(
            "the scenario does not take it: {}",
            scenario_message(&e.to_string(), origin)
        )
    })
}

/// `key = value, …` of a case.
pub fn describe(axes: &[Axis], values: &[Value]) -> String {
    axes.iter()
        .zip(values)
        .map(|(a, v)| format!("{} = {}", a.key, value_text(v)))
        .collect::<Vec<_>>()
        .join(", ")
}

/// A value as a table cell: numbers in their shortest exact form, strings unquoted.
pub fn value_text(v: &Value) -> String {
    match v {
        Value::String(s) => s.clone(),
        Value::Float(f) => format!("{f}"),
        other => other.to_string(),
    }
}

/// The scenario's parse error without its origin (the study names the base scenario).
fn scenario_message(message: &str, origin: &str) -> String {
    message
        .strip_prefix(origin)
        .map(|m| m.trim_start_matches(':').trim().to_string())
        .unwrap_or_else(|| message.to_string())
}

/// The values of a `range`: from, from + step, … up to `to` (inclusive, within 1e-9 of the
/// step), or `count` values evenly from `from` to `to`. Integer bounds and step give integers.
fn range_values(r: &RangeToml) -> Result<Vec<Value>, String> {
    let num = |v: &Value, what: &str| match v {
        Value::Integer(i) => Ok(*i as f64),
        Value::Float(f) if f.is_finite() => Ok(*f),
        other => Err(format!("range.{what} = {other}: expected a number")),
    };
    let (from, to) = (num(&r.from, "from")?, num(&r.to, "to")?);
    let integers = matches!(r.from, Value::Integer(_))
        && matches!(r.to, Value::Integer(_))
        && r.step.as_ref().is_none_or(|s| matches!(s, Value::Integer(_)));
    let limit = if crate::limits::lifted() {
        usize::MAX
    } else {
        MAX_CASES
    };
    match (&r.step, r.count) {
        (Some(step), None) => {
            let step = num(step, "step")?;
            if step.is_nan() || step <= 0.0 || to < from {
                return Err(format!(
                    "range from {from} to {to} by {step}: expected from <= to and a step > 0"
                ));
            }
            let n = ((to - from) / step + 1e-9).floor() as usize + 1;
            if n > limit {
                return Err(format!(
                    "range from {from} to {to} by {step}: more than {MAX_CASES} values"
                ));
            }
            Ok((0..n)
                .map(|k| {
                    if integers {
                        Value::Integer((from + k as f64 * step).round() as i64)
                    } else {
                        Value::Float(from + k as f64 * step)
                    }
                })
                .collect())
        }
        (None, Some(count)) => {
            if count < 1 || count as usize > limit || (count == 1 && from != to) || to < from {
                return Err(format!(
                    "range from {from} to {to} in {count} values: expected from <= to and 1 ..= {MAX_CASES} values (1 only where from = to)"
                ));
            }
            Ok((0..count)
                .map(|k| {
                    let f = if count == 1 {
                        from
                    } else {
                        from + (to - from) * k as f64 / (count - 1) as f64
                    };
                    Value::Float(f)
                })
                .collect())
        }
        _ => Err("range: give `step` or `count` (one of them)".into()),
    }
}

/// Longest key path a study's axis or an override ([`crate::api::SceneInput::set`]) may name,
/// characters (the scenario's keys are under 60).
pub const MAX_KEY_CHARS: usize = 256;
/// Most dot-separated parts of a key path (the scenario's deepest keys have 6).
pub const MAX_KEY_PARTS: usize = 16;
/// Deepest nesting of a value set by key (an array in an array …): deeper, converting and
/// checking it would exhaust the stack (a Python list that contains itself).
pub const MAX_VALUE_DEPTH: usize = 32;
/// Most entries of a value set by key, every level together (each array and table counts, and each
/// of their entries).
pub const MAX_VALUE_ENTRIES: usize = 100_000;
/// Longest string of a value set by key, characters (the longest path Linux takes: a scenario's
/// strings are names, paths and ratios).
pub const MAX_STRING_CHARS: usize = 4096;
/// Most characters of a value's strings together.
pub const MAX_VALUE_CHARS: usize = 1_000_000;

/// `Ok` if `key` is within [`MAX_KEY_CHARS`] and [`MAX_KEY_PARTS`]; else the problem (the key
/// itself not repeated: the caller names it, [`clipped`]). Counted without splitting the key, so a
/// key of a million parts costs nothing.
pub fn check_key_path(key: &str) -> Result<(), String> {
    let parts = key.matches('.').count() + 1;
    if parts > MAX_KEY_PARTS {
        return Err(format!(
            "a key path of {parts} parts: at most {MAX_KEY_PARTS} parts (dot-separated, `simulation.integrator.rtol`) and {MAX_KEY_CHARS} characters"
        ));
    }
    let chars = key.chars().count();
    if chars > MAX_KEY_CHARS {
        return Err(format!(
            "a key path of {chars} characters: at most {MAX_KEY_CHARS} characters and {MAX_KEY_PARTS} parts (`simulation.integrator.rtol`)"
        ));
    }
    Ok(())
}

/// `Ok` if `value` is within [`MAX_VALUE_DEPTH`], [`MAX_VALUE_ENTRIES`], [`MAX_STRING_CHARS`] and
/// [`MAX_VALUE_CHARS`]; else the problem. Walks at most [`MAX_VALUE_DEPTH`] levels deep, whatever
/// the value.
pub fn check_value(value: &Value) -> Result<(), String> {
    fn text(chars: &mut usize, n: usize) -> Result<(), String> {
        if n > MAX_STRING_CHARS {
            return Err(format!("a string of {n} characters: at most {MAX_STRING_CHARS}"));
        }
        *chars += n;
        if *chars > MAX_VALUE_CHARS {
            return Err(format!(
                "strings of more than {MAX_VALUE_CHARS} characters in all: at most {MAX_VALUE_CHARS}"
            ));
        }
        Ok(())
    }
    fn walk(v: &Value, depth: usize, entries: &mut usize, chars: &mut usize) -> Result<(), String> {
        if depth > MAX_VALUE_DEPTH {
            return Err(format!(
                "a value nested deeper than {MAX_VALUE_DEPTH} levels (arrays in arrays): at most {MAX_VALUE_DEPTH}"
            ));
        }
        *entries += 1;
        let n = match v {
            Value::String(s) => return text(chars, s.chars().count()),
            Value::Array(a) => a.len(),
            Value::Table(t) => t.len(),
            _ => 0,
        };
        if *entries + n > MAX_VALUE_ENTRIES {
            return Err(format!(
                "a value of more than {MAX_VALUE_ENTRIES} entries in all (arrays and their entries): at most {MAX_VALUE_ENTRIES}"
            ));
        }
        match v {
            Value::Array(a) => a.iter().try_for_each(|x| walk(x, depth + 1, entries, chars)),
            Value::Table(t) => t.iter().try_for_each(|(k, x)| {
                text(chars, k.chars().count())?;
                walk(x, depth + 1, entries, chars)
            }),
            _ => Ok(()),
        }
    }
    walk(value, 1, &mut 0, &mut 0)
}

/// Drops `value` level by level, without recursion: a value nested deeper than the stack allows
/// (one [`check_value`] refused) is taken apart here instead of overflowing the stack.
pub fn drop_flat(value: Value) {
    let mut pending = vec![value];
    while let Some(v) = pending.pop() {
        match v {
            Value::Array(a) => pending.extend(a),
            Value::Table(t) => pending.extend(t.into_iter().map(|(_, v)| v)),
            _ => {}
        }
    }
}

/// `text` for a message: whole up to `max` characters, else its first `max` and how long it is
/// (a key or a value as the user gave it, which may be megabytes).
pub fn clipped(text: &str, max: usize) -> std::borrow::Cow<'_, str> {
    match text.char_indices().nth(max) {
        None => text.into(),
        Some((end, _)) => format!("{}… ({} characters)", &text[..end], text.chars().count()).into(),
    }
}

/// Sets `key` (dot-separated; array entries by index) in `table`, making the tables on the way.
/// The key and the value are bounded first ([`check_key_path`], [`check_value`]).
pub fn set_key(table: &mut Table, key: &str, value: Value) -> Result<(), String> {
    check_key_path(key)?;
    check_value(&value)?;
    let parts: Vec<&str> = key.split('.').collect();
    if parts.iter().any(|p| p.is_empty()) {
        return Err("an empty part in the key path".into());
    }
    let (last, path) = parts.split_last().ok_or("an empty key path")?;
    let mut here = table;
    for (k, part) in path.iter().enumerate() {
        let entry = here
            .entry(part.to_string())
            .or_insert_with(|| Value::Table(Table::new()));
        let entry = match entry {
            // An array of tables: the next part is the entry's index.
            Value::Array(a) => {
                let Some(index) = parts.get(k + 1).and_then(|p| p.parse::<usize>().ok()) else {
                    return Err(format!(
                        "`{part}` is an array: the next part must be an entry's index"
                    ));
                };
                return set_in_array(a, index, &parts[k + 2..], value, part);
            }
            other => other,
        };
        here = match entry {
            Value::Table(t) => t,
            other => return Err(format!("`{part}` is a value ({}), not a table", other.type_str())),
        };
    }
    if matches!(here.get(*last), Some(Value::Table(_) | Value::Array(_))) {
        return Err(format!("`{last}` is a table or an array, not a value"));
    }
    here.insert(last.to_string(), value);
    Ok(())
}

/// [`set_key`] below an array entry.
fn set_in_array(
    a: &mut [Value],
    index: usize,
    rest: &[&str],
    value: Value,
    name: &str,
) -> Result<(), String> {
    let n = a.len();
    let Some(entry) = a.get_mut(index) else {
        return Err(format!("`{name}` has {n} entries: index {index} is past its end"));
    };
    match (entry, rest.is_empty()) {
        (slot, true) => {
            *slot = value;
            Ok(())
        }
        (Value::Table(t), false) => set_key(t, &rest.join("."), value),
        (other, false) => Err(format!(
            "`{name}.{index}` is a value ({}), not a table",
            other.type_str()
        )),
    }
}

/// SplitMix64 (Steele, Lea & Flood 2014): the study's random draws and derived seeds.
struct SplitMix64(u64);

impl SplitMix64 {
    fn new(seed: u64) -> Self {
        SplitMix64(seed)
    }
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1) (53 bits).
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The k-th seed derived from the study seed: 53 bits (a TOML integer, exact as a double).
pub fn derived_seed(study_seed: u64, k: u64) -> i64 {
    let mut g = SplitMix64::new(study_seed ^ k.wrapping_mul(0xA24B_AED4_963E_E407));
    (g.next() >> 11) as i64
}

/// FNV-1a, 64 bit: the study's identity.
pub(crate) struct Fnv(u64);

impl Fnv {
    pub(crate) fn new() -> Self {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
    pub(crate) fn add(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.0 ^= u64::from(*b);
            self.0 = self.0.wrapping_mul(0x0100_0000_01b3);
        }
        // A separator, so that ("ab", "c") and ("a", "bc") differ.
        self.0 ^= 0xff;
        self.0 = self.0.wrapping_mul(0x0100_0000_01b3);
    }
    pub(crate) fn finish(&self) -> u64 {
        self.0
    }
}

#[cfg(test)]
mod key_limit_tests {
    use super::*;

    fn study_with_axis(key: &str, values: &str) -> Result<Study, StudyError> {
        let text = format!(
            "schema_version = 1\nname = \"limits\"\nscenario = \"../scenes/wheelset_critical_speed.toml\"\nextract = [\"max_abs_y_mm\"]\n\n[[axis]]\nkey = \"{key}\"\nvalues = {values}\n"
        );
        Study::parse(
            &text,
            &Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/studies/limits.toml"),
        )
    }

    /// A key path of 50 000 parts (which built 50 000 nested tables and aborted the process on
    /// the stack) is refused before anything is built, its message short.
    #[test]
    fn a_key_of_many_parts_or_characters_is_refused_with_the_limit() {
        let mut table = Table::new();
        let many = vec!["a"; 50_000].join(".");
        let e = set_key(&mut table, &many, Value::Float(1.0)).unwrap_err();
        assert!(e.contains("50000 parts") && e.contains("at most 16"), "{e}");
        assert!(table.is_empty());
        let long = "x".repeat(300);
        let e = set_key(&mut table, &long, Value::Float(1.0)).unwrap_err();
        assert!(e.contains("300 characters") && e.contains("at most 256"), "{e}");
        // At the limits: set.
        let sixteen = vec!["b"; 16].join(".");
        set_key(&mut table, &sixteen, Value::Float(1.0)).unwrap();

        let e = study_with_axis(&many, "[1.0]").unwrap_err().to_string();
        assert!(e.contains("at most 16 parts") && e.contains("line 7"), "{e}");
        assert!(e.len() < 600, "{} characters", e.len());
    }

    /// A value nested 1e5 deep or of 1e6 entries is refused before it is walked in full.
    #[test]
    fn a_deep_or_huge_value_is_refused_with_the_limit() {
        let mut deep = Value::Float(1.0);
        for _ in 0..100_000 {
            deep = Value::Array(vec![deep]);
        }
        let e = check_value(&deep).unwrap_err();
        assert!(e.contains("deeper than 32 levels"), "{e}");
        // (Dropping it would recurse 1e5 levels.)
        drop_flat(deep);
        let mut ok = Value::Float(1.0);
        for _ in 0..31 {
            ok = Value::Array(vec![ok]);
        }
        check_value(&ok).unwrap();
        check_value(&Value::Array(vec![ok])).unwrap_err();
        let huge = Value::Array(vec![Value::Float(0.5); 1_000_000]);
        let e = check_value(&huge).unwrap_err();
        assert!(e.contains("more than 100000 entries"), "{e}");
        let long = Value::Array(vec![Value::String("x".repeat(1000)); 1001]);
        let e = check_value(&long).unwrap_err();
        assert!(e.contains("1000000 characters"), "{e}");
        check_value(&Value::String("x".repeat(4096))).unwrap();
        let e = check_value(&Value::String("x".repeat(4097))).unwrap_err();
        assert!(e.contains("a string of 4097 characters: at most 4096"), "{e}");
        let mut table = Table::new();
        assert!(set_key(&mut table, "a.b", huge).is_err() && table.is_empty());
        let e = study_with_axis(
            "simulation.speed_m_s",
            &format!("[{}]", "[".repeat(40) + &"]".repeat(40)),
        )
        .unwrap_err()
        .to_string();
        assert!(e.len() < 600, "{e}");
    }

    #[test]
    fn clipped_keeps_short_text_and_says_how_long_long_text_is() {
        assert_eq!(clipped("abc", 3), "abc");
        assert_eq!(clipped("abcd", 3), "abc… (4 characters)");
        assert_eq!(clipped("ééé", 2), "éé… (3 characters)");
    }
}
