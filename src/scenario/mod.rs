//! Scenario files (TOML): plain serde types, validated into a scene before anything runs.
//!
//! Rules (README, "Scenario files"): SI units with the unit in each field name, unknown keys are
//! errors that name the file, line and column, paths are relative to the scenario file, and
//! `schema_version` says which format the file follows. Validation collects every problem it finds
//! rather than stopping at the first.
//!
//! This module is the **one compile step** of a run: [`Scenario::compile`] validates the file (every
//! problem at once) and assembles a [`Scene`] — the placed wheel/rail pair, the contact forces, the
//! track, the validated `[simulation]` and `[vehicle]` — and [`Scene::build_run`] builds the
//! run's objects from it ([`simulation`]: contact model, vehicle system, reference, settings). The
//! command line only parses arguments and calls these.

mod finite;
pub mod simulation;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use serde::Deserialize;

use crate::contact::forces::{ContactForceSettings, CreepModel, Material};
use crate::profile::placement::{Inclination, WheelRailPair, WheelsetGeometry};
use crate::profile::{Profile, ProfileKind};
use crate::track::TrackGauge;
use crate::vehicle::VehicleSpec;

pub use crate::SCHEMA_VERSION;
pub use simulation::{BuildError, BuiltRun, PreprocessingCache, RunOptions, Scene, SimulationSpec};

/// The default scenario, embedded in the binary: the paper's case (§8), the MS vehicle on the
/// Tab. 6 track with irregularities at 19 m/s (`assets/scenes/ms_vehicle_tab6.toml`).
pub const DEFAULT_SCENARIO: &str = include_str!("../../assets/scenes/ms_vehicle_tab6.toml");

/// A scenario file as written.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    pub schema_version: u32,
    pub name: String,
    pub profiles: ProfilesSpec,
    #[serde(default)]
    pub track: TrackSpec,
    #[serde(default)]
    pub wheelset: WheelsetSpec,
    #[serde(default)]
    pub contact_forces: ContactForcesSpec,
    /// What to simulate (absent: `kecsim run` does the contact preprocessing only).
    #[serde(default)]
    pub simulation: Option<SimulationSpec>,
    /// The vehicle model of the simulation.
    #[serde(default)]
    pub vehicle: Option<VehicleSpec>,
    /// The text it was parsed from (validation reports lines of the track sections).
    #[serde(skip)]
    pub(crate) source: String,
}

/// Wheel–rail contact forces: friction, material, creep-force model (`[contact_forces.creep]`,
/// e.g. `model = "fastsim"`, `strips = 25`).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactForcesSpec {
    #[serde(default = "default_friction")]
    pub friction: f64,
    #[serde(default = "default_young")]
    pub young_modulus_pa: f64,
    #[serde(default = "default_poisson")]
    pub poisson_ratio: f64,
    #[serde(default)]
    pub creep: CreepModel,
    /// `patches = "post" | "dynamics" | "hertz"`: where the strip model replaces Hertz outside
    /// its validity ([`crate::contact::nonhertz::PatchesMode`]).
    #[serde(default)]
    pub patches: crate::contact::nonhertz::PatchesMode,
}

impl Default for ContactForcesSpec {
    fn default() -> Self {
        ContactForcesSpec {
            friction: default_friction(),
            young_modulus_pa: default_young(),
            poisson_ratio: default_poisson(),
            creep: CreepModel::default(),
            patches: Default::default(),
        }
    }
}

fn default_friction() -> f64 {
    0.3
}
fn default_young() -> f64 {
    Material::STEEL.young_pa
}
fn default_poisson() -> f64 {
    Material::STEEL.poisson
}

/// Wheel and rail profiles.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProfilesSpec {
    /// Standard name or path.
    pub wheel: String,
    /// Standard name or path.
    pub rail: String,
    /// `1:N` or `upright`.
    pub inclination: String,
}

/// The `[track]` table: cross-section gauge and, optionally, the centreline sections and
/// irregularities (see [`crate::track::file`]).
pub use crate::track::file::TrackSpec;

/// Wheelset dimensions.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WheelsetSpec {
    #[serde(default = "default_b2b")]
    pub back_to_back_m: f64,
    #[serde(default = "default_tape")]
    pub rolling_circle_from_back_m: f64,
    #[serde(default = "default_r0")]
    pub nominal_radius_m: f64,
}

impl Default for WheelsetSpec {
    fn default() -> Self {
        WheelsetSpec {
            back_to_back_m: default_b2b(),
            rolling_circle_from_back_m: default_tape(),
            nominal_radius_m: default_r0(),
        }
    }
}

fn default_b2b() -> f64 {
    WheelsetGeometry::default().back_to_back_m
}
fn default_tape() -> f64 {
    WheelsetGeometry::default().rolling_circle_from_back_m
}
fn default_r0() -> f64 {
    WheelsetGeometry::default().nominal_radius_m
}

/// A scenario problem, naming the file.
#[derive(Debug, thiserror::Error)]
pub enum ScenarioError {
    #[error("{path}: cannot read scenario: {source}")]
    Io {
        path: String,
        #[source]
        source: std::io::Error,
    },
    /// Syntax, unknown key, wrong type: the TOML message carries line and column.
    #[error("{path}: {message}")]
    Parse { path: String, message: String },
    /// Every validation problem found, one per line.
    #[error("{path}: invalid scenario:\n  - {}", problems.join("\n  - "))]
    Invalid { path: String, problems: Vec<String> },
}

impl Scenario {
    /// Parses scenario text; `origin` names it in errors (a path or `<embedded default>`).
    pub fn parse(text: &str, origin: &str) -> Result<Self, ScenarioError> {
        // A byte-order mark (editors on Windows write one) is not TOML.
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let mut s: Self = toml::from_str(text).map_err(|e| ScenarioError::Parse {
            path: origin.to_string(),
            message: match e.span().and_then(|span| relocate(text, span.start, e.message())) {
                Some(better) => better,
                None => e.to_string().trim_end().to_string(),
            },
        })?;
        let bad = finite::non_finite_values(text);
        if !bad.is_empty() {
            return Err(ScenarioError::Invalid {
                path: origin.to_string(),
                problems: bad
                    .iter()
                    .map(|(line, key, token)| {
                        format!("{origin}:{line}: {key} = {token}: not a number; expected a finite value")
                    })
                    .collect(),
            });
        }
        s.source = text.to_string();
        Ok(s)
    }

    /// Reads and parses a scenario file.
    pub fn read(path: &Path) -> Result<Self, ScenarioError> {
        let p = path.display().to_string();
        let text = crate::limits::read_text(path).map_err(|source| ScenarioError::Io {
            path: p.clone(),
            source,
        })?;
        Self::parse(&text, &p)
    }

    /// Validates and assembles the scene. `base` is the directory relative paths start from.
    /// Collects all problems before failing.
    pub fn compile(&self, origin: &str, base: &Path) -> Result<Scene, ScenarioError> {
        let mut problems = Vec::new();
        let mut warnings = Vec::new();
        if self.schema_version != SCHEMA_VERSION {
            problems.push(format!(
                "schema_version = {}: this kecsim reads schema_version = {SCHEMA_VERSION}",
                self.schema_version
            ));
        }
        if let Some(c) = self.name.chars().find(|c| c.is_control()) {
            problems.push(locate_key(
                origin,
                &self.source,
                &format!(
                    "name = {:?}: contains the control character U+{:04X}; a name is printed and recorded (letters, digits, spaces, punctuation)",
                    self.name,
                    c as u32
                ),
            ));
        }
        if self.track.horizontal.is_empty() {
            // Without sections the wheelset runs on ideal straight rails: a table of the track
            // that needs a line would be ignored.
            for (table, given, written) in [
                (
                    "[track.irregularities]",
                    self.track.irregularities.is_some(),
                    "irregularities",
                ),
                (
                    "[track.lateral_flexibility]",
                    self.track.lateral_flexibility.is_some(),
                    "lateral_flexibility",
                ),
            ] {
                if given {
                    let at = self.source.find(written).map_or(String::new(), |o| {
                        format!("{origin}:{}: ", crate::track::file::line_of(&self.source, o))
                    });
                    problems.push(format!("{at}{table} needs a track line: give [track] its horizontal sections (without them the wheelset runs on ideal straight rails, and the table would be ignored)"));
                }
            }
        }
        let mut positive = |name: &str, v: f64, lo: f64, hi: f64| {
            if !(v.is_finite() && v >= lo && v <= hi) {
                problems.push(locate_key(
                    origin,
                    &self.source,
                    &format!("{name} = {v}: expected a value in [{lo}, {hi}]"),
                ));
            }
        };
        if self.track.horizontal.is_empty() {
            // (With sections, the track's own validation checks these.)
            positive("track.gauge_m", self.track.gauge_m, 0.5, 2.0);
            positive(
                "track.gauge_measuring_depth_m",
                self.track.gauge_measuring_depth_m,
                0.001,
                0.03,
            );
        }
        positive("wheelset.back_to_back_m", self.wheelset.back_to_back_m, 0.4, 2.0);
        positive(
            "wheelset.rolling_circle_from_back_m",
            self.wheelset.rolling_circle_from_back_m,
            0.0,
            0.2,
        );
        positive(
            "wheelset.nominal_radius_m",
            self.wheelset.nominal_radius_m,
            0.1,
            1.0,
        );
        let inclination = match self.profiles.inclination.parse::<Inclination>() {
            Ok(i) => Some(i),
            Err(e) => {
                problems.push(format!("profiles.inclination: {e}"));
                None
            }
        };
        let cf = &self.contact_forces;
        let material = Material {
            young_pa: cf.young_modulus_pa,
            poisson: cf.poisson_ratio,
        };
        let contact_forces = match ContactForceSettings::new(cf.creep, cf.friction, material) {
            Ok(s) => {
                warnings.extend(
                    s.doubtful()
                        .iter()
                        .map(|w| locate_key(origin, &self.source, &format!("contact_forces: {w}"))),
                );
                Some(s)
            }
            Err(p) => {
                problems.extend(
                    p.into_iter()
                        .map(|p| locate_key(origin, &self.source, &format!("contact_forces: {p}"))),
                );
                None
            }
        };
        let simulation = match (&self.simulation, &self.vehicle) {
            (Some(sim), Some(veh)) => {
                problems.extend(sim.problems().iter().map(|p| locate_key(origin, &self.source, p)));
                if let Some(p) = undriven(sim, veh) {
                    problems.push(locate(origin, &self.source, &p));
                }
                warnings.extend(sim.doubtful().iter().map(|p| locate_key(origin, &self.source, p)));
                // Counts read from the file, held to the limits before anything is built.
                let counts = veh.table_counts();
                let parts: f64 = counts
                    .iter()
                    .filter(|(t, _)| *t == "bodies" || *t == "wheelsets")
                    .map(|(_, n)| *n as f64)
                    .sum();
                if let Err(e) = crate::limits::check(
                    &format!("vehicle: {parts} bodies and wheelsets"),
                    parts,
                    crate::limits::MAX_VEHICLE_PARTS,
                    "a ten-car train has 30 bodies and 40 wheelsets; the run's Jacobian is dense, its factorisation grows with the cube of the count",
                ) {
                    problems.push(e);
                }
                for (table, n) in counts {
                    let limit = if table == "elements" {
                        crate::limits::MAX_VEHICLE_ELEMENTS
                    } else {
                        crate::limits::MAX_VEHICLE_BODIES
                    };
                    if let Err(e) = crate::limits::check(
                        &format!("vehicle.{table}: {n} entries"),
                        n as f64,
                        limit,
                        "a whole train has tens of bodies and hundreds of elements",
                    ) {
                        problems.push(e);
                    }
                }
                problems.extend(
                    veh.problems()
                        .into_iter()
                        .chain(veh.spacing_problems(self.wheelset.nominal_radius_m))
                        .chain(veh.far_attachments(self.wheelset.nominal_radius_m))
                        .map(|p| locate(origin, &self.source, &p)),
                );
                warnings.extend(
                    veh.doubtful()
                        .into_iter()
                        .map(|p| locate(origin, &self.source, &p)),
                );
                Some((sim.clone(), veh.clone()))
            }
            (None, None) => None,
            (Some(_), None) => {
                problems.push("[simulation] needs a [vehicle] table".to_string());
                None
            }
            (None, Some(_)) => {
                problems.push("[vehicle] needs a [simulation] table".to_string());
                None
            }
        };
        let mut inputs = Vec::new();
        let mut load = |spec: &str, kind: ProfileKind| {
            let resolved = resolve_path(spec, base);
            if Path::new(&resolved).is_file() {
                inputs.push(PathBuf::from(&resolved));
            }
            match Profile::resolve(&resolved, kind) {
                Ok(p) => Some(p),
                Err(e) => {
                    problems.push(format!("profiles.{kind}: {e}"));
                    None
                }
            }
        };
        let wheel = load(&self.profiles.wheel, ProfileKind::Wheel);
        let rail = load(&self.profiles.rail, ProfileKind::Rail);
        let track = if self.track.horizontal.is_empty() {
            None
        } else {
            warnings.extend(self.track.doubtful(origin, &self.source));
            match self.track.build(&self.name, origin, &self.source, base) {
                Ok(t) => Some(Arc::new(t)),
                Err(crate::track::TrackError::Invalid { problems: p, .. }) => {
                    problems.extend(p);
                    None
                }
                Err(e) => {
                    problems.push(e.to_string());
                    None
                }
            }
        };
        let invalid = |problems: Vec<String>| ScenarioError::Invalid {
            path: origin.to_string(),
            problems,
        };
        let (Some(wheel), Some(rail), Some(inclination), Some(contact_forces), true) =
            (wheel, rail, inclination, contact_forces, problems.is_empty())
        else {
            return Err(invalid(problems));
        };
        let gauge = TrackGauge {
            gauge_m: self.track.gauge_m,
            measuring_depth_m: self.track.gauge_measuring_depth_m,
        };
        let wheelset = WheelsetGeometry {
            back_to_back_m: self.wheelset.back_to_back_m,
            rolling_circle_from_back_m: self.wheelset.rolling_circle_from_back_m,
            nominal_radius_m: self.wheelset.nominal_radius_m,
        };
        let pair = WheelRailPair::new(wheel, rail, inclination, gauge, wheelset)
            .map_err(|e| invalid(vec![e.to_string()]))?;
        let mut contact_forces = contact_forces;
        if self.contact_forces.patches == crate::contact::nonhertz::PatchesMode::Dynamics {
            contact_forces.patches = Some(std::sync::Arc::new(
                crate::contact::nonhertz::DynamicPatches::new(pair.clone()),
            ));
        }
        if let Some(t) = &track {
            inputs.extend(t.source_files.iter().cloned());
        }
        Ok(Scene {
            inputs,
            name: self.name.clone(),
            origin: origin.to_string(),
            pair,
            contact_forces,
            patches: self.contact_forces.patches,
            track,
            simulation,
            warnings,
            table_cache: None,
        })
    }
}

/// A TOML error inside a tagged table (`[vehicle]` with its `kind`, `[[vehicle.elements]]` with
/// its `type`) is reported by the parser at the table's header, since serde reads such a table as
/// a whole. This finds the line the message is about — the value or key it quotes in backticks
/// or double quotes (`unknown variant \`w\``, `unknown field \`foo\``), searched from the header
/// to the end of the file — and reports it: `line N: MESSAGE (LINE TEXT)`. None when the error is
/// not at a header or nothing quoted is found.
fn relocate(text: &str, at: usize, message: &str) -> Option<String> {
    let header = text.get(at..)?.trim_start();
    if !header.starts_with('[') {
        return None;
    }
    if let Some(found) = wrong_length(text, at, message) {
        return Some(found);
    }
    let token = message
        .split('`')
        .nth(1)
        .or_else(|| message.split('"').nth(1))
        .filter(|t| !t.is_empty())?;
    let rest = &text[at..];
    // Only the table's own lines: the next header ends it (a key of a later table is another
    // key, and was reported as this table's error).
    // (Its sub-tables, `[vehicle.x]` and `[[vehicle.elements]]` of `[vehicle]`, are its own.)
    let table_of = |line: &str| -> Option<String> {
        let t = line.split('#').next().unwrap_or("").trim();
        (t.starts_with('[') && !t.contains('=')).then(|| {
            t.trim_matches(|c| c == '[' || c == ']')
                .split('.')
                .map(str::trim)
                .collect::<Vec<_>>()
                .join(".")
        })
    };
    let own = table_of(header.lines().next().unwrap_or("")).unwrap_or_default();
    let mut lines = Vec::new();
    let mut offset = at;
    for (k, line) in rest.split_inclusive('\n').enumerate() {
        if k > 0 {
            if let Some(t) = table_of(line) {
                if t != own && !t.starts_with(&format!("{own}.")) {
                    break;
                }
            }
        }
        lines.push((offset, line));
        offset += line.len();
    }
    let shown = |offset: usize, message: &str, line: &str| {
        format!(
            "line {}: {} (`{}`)",
            crate::track::file::line_of(text, offset),
            message.trim_end(),
            line.trim()
        )
    };
    for &(offset, line) in &lines {
        let body = line.split('#').next().unwrap_or("");
        let as_value = body.contains(&format!("\"{token}\""))
            || body.split_once('=').is_some_and(|(_, v)| v.trim() == token);
        let as_key = body.trim_start().starts_with(token)
            && body.trim_start()[token.len()..].trim_start().starts_with('=');
        let in_inline = body.contains(&format!("{token} =")) || body.contains(&format!("{token}="));
        if as_value || as_key || in_inline {
            return Some(shown(offset, message, line));
        }
    }
    // "missing field `model`" where the table has a key one or two letters from it: the typo.
    if message.starts_with("missing field") {
        for &(offset, line) in &lines {
            let body = line.split('#').next().unwrap_or("");
            if let Some((key, _)) = body.split_once('=') {
                let key = key.trim();
                if !key.is_empty() && key != token && edit_distance(key, token) <= 2 {
                    return Some(shown(
                        offset,
                        &format!("unknown key `{key}`: did you mean `{token}`? ({message})"),
                        line,
                    ));
                }
            }
        }
    }
    None
}

/// Levenshtein distance of two short keys.
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let here = row[j + 1];
            row[j + 1] = (row[j + 1] + 1).min(row[j] + 1).min(prev + usize::from(ca != cb));
            prev = here;
        }
    }
    row[b.len()]
}

/// "invalid length N, expected an array of length M" inside a tagged table (whose error spans the
/// whole table): the first one-line array of N entries from `at` on, with its line and key.
fn wrong_length(text: &str, at: usize, message: &str) -> Option<String> {
    let n: usize = message
        .strip_prefix("invalid length ")?
        .split(',')
        .next()?
        .trim()
        .parse()
        .ok()?;
    let mut offset = at;
    for line in text[at..].split_inclusive('\n') {
        let body = line.split('#').next().unwrap_or("");
        if let Some((key, value)) = body.split_once('=') {
            let v = value.trim();
            if let Some(inner) = v.strip_prefix('[').and_then(|v| v.strip_suffix(']')) {
                let entries = inner.split(',').filter(|e| !e.trim().is_empty()).count();
                if entries == n && !inner.contains('[') && !inner.contains('{') {
                    return Some(format!(
                        "line {}: {} = [{}]: {} entries, expected {}",
                        crate::track::file::line_of(text, offset),
                        key.trim(),
                        inner.trim(),
                        n,
                        message.rsplit("length ").next().unwrap_or(message).trim()
                    ));
                }
            }
        }
        offset += line.len();
    }
    None
}

/// A vehicle problem with the file and line of the entry it names (`vehicle.wheelsets[w1]…`: the
/// line of `name = "w1"` in the `[vehicle]` part of the file; a problem of the whole table: the
/// `[vehicle]` line).
fn locate(origin: &str, source: &str, problem: &str) -> String {
    let Some(start) = source.find("[vehicle]") else {
        return problem.to_string();
    };
    let entry = problem
        .split_once('[')
        .filter(|(head, _)| head.starts_with("vehicle.") && !head.contains(' '))
        .and_then(|(_, rest)| rest.split_once(']'))
        .map(|(name, _)| name);
    let at = entry
        .and_then(|name| {
            ["name = \"", "name=\""]
                .iter()
                .find_map(|key| source[start..].find(&format!("{key}{name}\"")))
        })
        .map_or(start, |i| start + i);
    format!("{origin}:{}: {problem}", crate::track::file::line_of(source, at))
}

/// A range problem with the file and line of the key it names: `a.b.key = value: …` (the key
/// `key` of the table `[a.b]`), `contact_forces: key = …` and `contact_forces: MODEL: key = …`
/// (`[contact_forces]`, `[contact_forces.creep]`). The line of `key =` inside its table where the
/// file has it, else of the table's header; the problem as it is where neither is found.
fn locate_key(origin: &str, source: &str, problem: &str) -> String {
    let (path, rest) = match problem.strip_prefix("contact_forces: ") {
        Some(r) => match r.split_once(": ") {
            Some((model, r)) if !model.contains(' ') && !model.contains('=') => {
                ("contact_forces.creep.".to_string(), r)
            }
            _ => ("contact_forces.".to_string(), r),
        },
        None => (String::new(), problem),
    };
    let Some((key, _)) = rest.split_once(" = ") else {
        return problem.to_string();
    };
    if key.contains(' ') {
        return problem.to_string();
    }
    let full = format!("{path}{key}");
    let (table, key) = full.rsplit_once('.').unwrap_or(("", full.as_str()));
    let header = |line: &str| {
        let t = line.split('#').next().unwrap_or("").trim();
        t.strip_prefix('[')
            .and_then(|t| t.strip_suffix(']'))
            .map(|name| name.split('.').map(str::trim).collect::<Vec<_>>().join("."))
    };
    let mut offset = 0;
    let mut in_table = table.is_empty();
    let mut header_at = None;
    for line in source.split_inclusive('\n') {
        if let Some(name) = header(line) {
            in_table = name == table;
            if in_table && header_at.is_none() {
                header_at = Some(offset);
            }
        } else if in_table {
            let t = line.trim_start();
            if t.strip_prefix(key)
                .is_some_and(|r| r.trim_start().starts_with('='))
            {
                return format!(
                    "{origin}:{}: {problem}",
                    crate::track::file::line_of(source, offset)
                );
            }
        }
        offset += line.len();
    }
    match header_at {
        Some(at) => format!("{origin}:{}: {problem}", crate::track::file::line_of(source, at)),
        None => problem.to_string(),
    }
}

/// A standard profile name stays as it is; anything else is a path relative to `base`.
fn resolve_path(spec: &str, base: &Path) -> String {
    let name = spec.split_once(":blend=").map_or(spec, |(n, _)| n);
    if crate::profile::StandardProfile::from_name(name).is_some()
        || crate::profile::embedded::EmbeddedProfile::from_name(spec).is_some()
        || Path::new(spec).is_absolute()
    {
        return spec.to_string();
    }
    let p: PathBuf = base.join(spec);
    p.display().to_string()
}

/// A drive asked for (`simulation.traction.mode` "hold_speed" or "force") on a vehicle whose
/// every wheelset is `motored = false`: nothing could transmit it (it drove every wheelset).
fn undriven(sim: &SimulationSpec, veh: &VehicleSpec) -> Option<String> {
    let VehicleSpec::Multibody(m) = veh else {
        return None;
    };
    let mode = sim.traction.mode;
    if mode == simulation::TractionMode::Coast
        || m.wheelsets.is_empty()
        || !m.wheelsets.iter().all(|w| w.motored == Some(false))
    {
        return None;
    }
    Some(format!(
        "vehicle.wheelsets: motored = false on every wheelset ({}), yet simulation.traction.mode = \"{}\" needs a driven wheel: mark the motored ones motored = true, or set mode = \"coast\"",
        m.wheelsets.iter().map(|w| w.name.as_str()).collect::<Vec<_>>().join(", "),
        mode.name()
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bogie scene (S1002 on 60E1 at 1:40, r0 = 0.46 m), whose lines the tests below edit.
    const BOGIE: &str = include_str!("../../assets/scenes/bogie_tab6_curve.toml");

    #[test]
    fn default_scenario_compiles() {
        let s = Scenario::parse(DEFAULT_SCENARIO, "<default>").unwrap();
        let scene = s.compile("<default>", Path::new(".")).unwrap();
        assert_eq!(scene.pair.wheel.name, "ms-tram");
        assert_eq!(scene.pair.rail.name, "54e1:blend=1");
        assert!(scene.simulation.is_some() && scene.track.is_some());
        assert_eq!(scene.contact_forces.model.name(), "exact-table");
        assert_eq!(scene.contact_forces.friction, 0.3);
    }

    #[test]
    fn contact_forces_table_is_read_and_validated() {
        // The default scenario without its own [contact_forces] tables.
        let base = &BOGIE[..BOGIE.find("[contact_forces]").unwrap()];
        let text = format!(
            "{base}\n[contact_forces]\nfriction = 0.35\n[contact_forces.creep]\nmodel = \"fastsim\"\nstrips = 30\n"
        );
        let scene = Scenario::parse(&text, "s.toml")
            .unwrap()
            .compile("s.toml", Path::new("."))
            .unwrap();
        assert_eq!(scene.contact_forces.friction, 0.35);
        assert!(
            matches!(scene.contact_forces.model, CreepModel::Fastsim(f) if f.strips == 30 && f.elements == 25)
        );
        let bad = format!(
            "{base}\n[contact_forces]\nfriction = -1\npoisson_ratio = 0.7\n[contact_forces.creep]\nmodel = \"fastsim\"\nstrips = 0\n"
        );
        let e = Scenario::parse(&bad, "s.toml")
            .unwrap()
            .compile("s.toml", Path::new("."))
            .unwrap_err()
            .to_string();
        for want in ["friction = -1", "poisson_ratio = 0.7", "strips = 0"] {
            assert!(e.contains(want), "{e}");
        }
        let unknown = format!("{base}\n[contact_forces.creep]\nmodel = \"polach\"\nka = 1\n");
        let e = Scenario::parse(&unknown, "s.toml").unwrap_err().to_string();
        assert!(e.contains("line") && e.contains("ka"), "{e}");
    }

    #[test]
    fn unknown_key_is_reported_with_line_and_column() {
        let text = BOGIE.replace("gauge_m = 1.435", "gauge_m = 1.435\ngauge_mm = 1435");
        let line = 1 + text[..text.find("gauge_mm").unwrap()].matches('\n').count();
        let e = Scenario::parse(&text, "s.toml").unwrap_err().to_string();
        assert!(e.starts_with("s.toml: "), "{e}");
        assert!(
            e.contains(&format!("line {line}")) && e.contains("unknown field `gauge_mm`"),
            "{e}"
        );
    }

    #[test]
    fn validation_collects_every_problem() {
        let text = BOGIE
            .replace("schema_version = 1", "schema_version = 7")
            .replace("\"1:40\"", "\"1/40\"")
            .replace("rail = \"60e1\"", "rail = \"no_such_rail.csv\"")
            .replace(
                "[contact_forces]",
                "[wheelset]\nnominal_radius_m = -1.0\n\n[contact_forces]",
            );
        let s = Scenario::parse(&text, "s.toml").unwrap();
        let e = s.compile("s.toml", Path::new("/tmp")).unwrap_err().to_string();
        for needle in [
            "schema_version = 7",
            "inclination",
            "no_such_rail.csv",
            "nominal_radius_m = -1",
        ] {
            assert!(e.contains(needle), "missing '{needle}' in:\n{e}");
        }
    }
}
