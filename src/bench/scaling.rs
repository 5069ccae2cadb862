//! `kecsim bench scaling`: the cost of a run against the length of the track and against the size
//! of the vehicle, each series with its fitted exponent (cost ∝ size^p; p = 1 is linear).
//!
//! - **Track length**: the MS scene (KEC, its BDF) over its Tab. 6 track laid `k` times end to end
//!   (k = 1, 2, 4: 1, 2, 4 km, the irregularities generated over the whole length), each run from
//!   the track's start until the leading wheelset nears the end. The cost should grow with the
//!   simulated time only: p ≈ 1 for the wall time.
//! - **Vehicle size**: a bogie, the Manchester vehicle 1, the MS vehicle and two MS vehicles coupled
//!   ([`coupled_ms`]), each on its own scene's track over the same simulated window with the same
//!   integrator (BDF, rtol 1e-4, atol 1e-6: one setting for all four), KEC. The cost of one right-hand side
//!   should grow linearly with the number of states (each body and wheelset is evaluated once, the
//!   joints' Schur complement is block-sparse); the wall time per simulated second also carries the
//!   step count, which depends on each vehicle's dynamics.
//!
//! Runs without a recording (the computation alone); wall time of the integration, preprocessing
//! apart, as in the real-time factor.

use std::fmt::Write as _;

use toml::{Table, Value};

use thiserror::Error;

use crate::dynamics::integrator::Method;
use crate::scenario::{BuildError, RunOptions, Scenario, ScenarioError, Scene, DEFAULT_SCENARIO};

/// Why the scaling series cannot be measured.
#[derive(Debug, Error)]
pub enum ScalingError {
    /// The track lengths asked for are not 1 ..= 16 km.
    #[error("track lengths: expected 1 ..= 16 kilometres")]
    TrackLengths,
    /// The vehicle-size series' window (`--duration`) is not in (0, 40] s.
    #[error("--duration {window_s}: expected a window of (0, 40] s for the vehicle-size series")]
    Window { window_s: f64 },
    /// A scene the series derives from is not embedded.
    #[error("no embedded scene {name}")]
    NoScene { name: String },
    /// The embedded scene's TOML cannot be read.
    #[error("{scene}: {source}")]
    Read {
        scene: &'static str,
        source: toml::de::Error,
    },
    /// The embedded scene lacks a part a derived scene edits (named in `problem`).
    #[error("{scene}: {problem}")]
    Shape { scene: &'static str, problem: String },
    /// A derived scene cannot be written back as TOML.
    #[error("{scene}: {source}")]
    Write {
        scene: &'static str,
        source: toml::ser::Error,
    },
    /// A series' scene does not compile.
    #[error("{scene}: {source}")]
    Compile { scene: String, source: ScenarioError },
    /// A series' run cannot be built.
    #[error("{label}: {source}")]
    Build { label: String, source: Box<BuildError> },
}

/// The MS scene's track length, m, and the simulated time of its run over it, s.
const MS_TRACK_M: f64 = 1000.0;
const MS_DURATION_S: f64 = 51.0;

/// Distance between the end faces of two coupled MS vehicles (the couplers' length), m — an
/// assumption: automatic (Scharfenberg-type) couplers of trams protrude ~0.4 m each.
pub const COUPLER_LENGTH_M: f64 = 0.8;
/// Coupler height above the top of rail, m (assumption for a low-floor tram).
pub const COUPLER_HEIGHT_M: f64 = 0.5;
/// The coupler's draft gear along its rod: stiffness N/m and damping N s/m (assumptions: rubber
/// draft gears of light-rail couplers, 5 MN/m with 50 kN s/m).
pub const COUPLER_STIFFNESS_N_PER_M: f64 = 5e6;
pub const COUPLER_DAMPING_N_S_PER_M: f64 = 5e4;

/// One run of a series.
#[derive(Debug, Clone, PartialEq)]
pub struct ScalingRow {
    /// What was run (e.g. `MS vehicle, 2 km`).
    pub label: String,
    /// The series' size: track length (m) or number of states.
    pub size: f64,
    pub states: usize,
    pub wheelsets: usize,
    pub bodies: usize,
    pub simulated_s: f64,
    /// Integration wall time, s.
    pub wall_s: f64,
    pub steps: usize,
    pub rhs_evaluations: usize,
    /// `completed`, or how the run ended.
    pub outcome: String,
}

impl ScalingRow {
    /// Wall time of one right-hand side (integrator overhead included), s.
    pub fn per_rhs_s(&self) -> f64 {
        self.wall_s / self.rhs_evaluations.max(1) as f64
    }

    /// Wall time per simulated second.
    pub fn per_simulated_s(&self) -> f64 {
        self.wall_s / self.simulated_s.max(1e-12)
    }
}

/// Both series and their fitted exponents.
#[derive(Debug, Clone, PartialEq)]
pub struct Scaling {
    pub length: Vec<ScalingRow>,
    /// p of wall ∝ length^p.
    pub length_exponent: f64,
    pub size: Vec<ScalingRow>,
    /// p of (wall per right-hand side) ∝ states^p and of (wall per simulated s) ∝ states^p.
    pub size_exponent_per_rhs: f64,
    pub size_exponent_per_simulated_s: f64,
    /// The simulated window of the size series, s.
    pub window_s: f64,
}

/// What the benchmark runs.
#[derive(Debug, Clone, PartialEq)]
pub struct ScalingSettings {
    /// Track lengths as multiples of the Tab. 6 kilometre.
    pub kilometres: Vec<usize>,
    /// The size series' simulated window, s.
    pub window_s: f64,
}

impl Default for ScalingSettings {
    fn default() -> Self {
        ScalingSettings {
            kilometres: vec![1, 2, 4],
            window_s: 7.0,
        }
    }
}

/// p of y ∝ x^p: the least-squares slope of ln y against ln x (NaN with fewer than two distinct x).
pub fn fitted_exponent(points: &[(f64, f64)]) -> f64 {
    let pts: Vec<(f64, f64)> = points
        .iter()
        .filter(|(x, y)| *x > 0.0 && *y > 0.0)
        .map(|(x, y)| (x.ln(), y.ln()))
        .collect();
    let n = pts.len() as f64;
    let (mx, my) = (
        pts.iter().map(|p| p.0).sum::<f64>() / n,
        pts.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    if pts.len() < 2 || sxx <= 0.0 {
        return f64::NAN;
    }
    sxy / sxx
}

fn parse(text: &str, what: &'static str) -> Result<Table, ScalingError> {
    text.parse::<Table>()
        .map_err(|source| ScalingError::Read { scene: what, source })
}

/// The embedded scene `what` lacks `problem`.
fn shape(what: &'static str, problem: String) -> ScalingError {
    ScalingError::Shape { scene: what, problem }
}

fn table_mut<'a>(t: &'a mut Table, key: &str, what: &'static str) -> Result<&'a mut Table, ScalingError> {
    t.get_mut(key)
        .and_then(Value::as_table_mut)
        .ok_or_else(|| shape(what, format!("no [{key}]")))
}

fn array_mut<'a>(
    t: &'a mut Table,
    key: &str,
    what: &'static str,
) -> Result<&'a mut Vec<Value>, ScalingError> {
    t.get_mut(key)
        .and_then(Value::as_array_mut)
        .ok_or_else(|| shape(what, format!("no {key} = [...]")))
}

fn write(doc: &Table, what: &'static str) -> Result<String, ScalingError> {
    toml::to_string(doc).map_err(|source| ScalingError::Write { scene: what, source })
}

/// A TOML number as f64 (integers too).
fn number(v: &Value) -> Option<f64> {
    v.as_float().or_else(|| v.as_integer().map(|i| i as f64))
}

/// Sets `simulation.duration_s` to `f(speed)` (the scene's speed, m/s).
fn set_duration(doc: &mut Table, what: &'static str, f: impl Fn(f64) -> f64) -> Result<(), ScalingError> {
    let sim = table_mut(doc, "simulation", what)?;
    let speed = sim
        .get("speed_m_s")
        .and_then(number)
        .ok_or_else(|| shape(what, "no simulation.speed_m_s".to_string()))?;
    sim.insert("duration_s".to_string(), Value::Float(f(speed)));
    Ok(())
}

/// Adds `dx` to the first component of the array at `key`, if the entry has one.
fn shift_x(entry: &mut Table, key: &str, dx: f64) {
    if let Some(v) = entry
        .get_mut(key)
        .and_then(Value::as_array_mut)
        .and_then(|a| a.first_mut())
    {
        if let Some(x) = number(v) {
            *v = Value::Float(x + dx);
        }
    }
}

/// The MS scene's text with its Tab. 6 track laid `k` times end to end (every horizontal section
/// repeated 1000 m further on, the vertical alignment and the irregularities over the whole
/// length) and the run lengthened to match.
pub fn ms_on_longer_track(k: usize) -> Result<String, ScalingError> {
    let what = "the MS scene";
    let mut doc = parse(DEFAULT_SCENARIO, what)?;
    let track = table_mut(&mut doc, "track", what)?;
    let horizontal = array_mut(track, "horizontal", what)?.clone();
    let mut laid = Vec::with_capacity(k * horizontal.len());
    for copy in 0..k {
        for section in &horizontal {
            let mut s = section
                .as_table()
                .cloned()
                .ok_or_else(|| shape(what, "a horizontal section is not a table".to_string()))?;
            for key in ["from_m", "to_m"] {
                let v = s
                    .get(key)
                    .and_then(number)
                    .ok_or_else(|| shape(what, format!("a horizontal section without {key}")))?;
                s.insert(key.to_string(), Value::Float(v + copy as f64 * MS_TRACK_M));
            }
            laid.push(Value::Table(s));
        }
    }
    track.insert("horizontal".to_string(), Value::Array(laid));
    // The scene's level track is one vertical section: lengthened to the whole track.
    let vertical = array_mut(track, "vertical", what)?;
    match vertical.as_mut_slice() {
        [section] => {
            if let Some(s) = section.as_table_mut() {
                s.insert("to_m".to_string(), Value::Float(k as f64 * MS_TRACK_M));
            }
        }
        _ => {
            return Err(shape(
                what,
                "expected one vertical section to lengthen".to_string(),
            ))
        }
    }
    set_duration(&mut doc, what, |speed| {
        MS_DURATION_S + (k as f64 - 1.0) * MS_TRACK_M / speed
    })?;
    write(&doc, what)
}

/// The MS scene's text with `units` MS vehicles coupled one behind the other: the second and
/// further units are copies of the first, their bodies, wheelsets, elements and joints named with
/// a suffix `_2`, `_3`, … and moved back by the vehicle's length plus [`COUPLER_LENGTH_M`]; each
/// coupler an axial spring–damper (the draft gear, [`COUPLER_STIFFNESS_N_PER_M`],
/// [`COUPLER_DAMPING_N_S_PER_M`]) between the rear end of one unit's last carbody and the front
/// end of the next one's first, at [`COUPLER_HEIGHT_M`] above the rail — a rod pinned at both ends,
/// free to articulate. The run starts with the rearmost body at the track's start and is shortened
/// so that the front unit still ends where the single vehicle's run ends.
pub fn coupled_ms(units: usize) -> Result<String, ScalingError> {
    let what = "the MS scene";
    let mut doc = parse(DEFAULT_SCENARIO, what)?;
    let vehicle = table_mut(&mut doc, "vehicle", what)?;
    let bodies = array_mut(vehicle, "bodies", what)?.clone();
    // The frontmost and the rearmost body (by their centres' x): the coupler joins the rear one of
    // a unit to the front one of the next.
    let (mut front, mut rear) = (f64::NEG_INFINITY, f64::INFINITY);
    let mut first_last = (String::new(), String::new());
    for b in &bodies {
        let (Some(name), Some(x)) = (
            b.get("name").and_then(Value::as_str),
            b.get("position_m")
                .and_then(Value::as_array)
                .and_then(|a| a.first())
                .and_then(number),
        ) else {
            return Err(shape(what, "a body without name or position_m".to_string()));
        };
        if x > front {
            front = x;
            first_last.0 = name.to_string();
        }
        if x < rear {
            rear = x;
            first_last.1 = name.to_string();
        }
    }
    // Ends of the vehicle (the scene's reading of Tab. 5): the end bogies' centres at ±11.024 m
    // plus b_c1 = 2.762 m from the bogie centre to the vehicle's end: ±13.786 m.
    let end = 11.024 + 2.762;
    let pitch = 2.0 * end + COUPLER_LENGTH_M;
    let names: Vec<String> = ["bodies", "wheelsets"]
        .iter()
        .filter_map(|k| vehicle.get(*k).and_then(Value::as_array))
        .flatten()
        .filter_map(|e| e.get("name").and_then(Value::as_str).map(String::from))
        .collect();
    let rename = |v: &mut Value, suffix: &str| {
        if let Some(s) = v.as_str() {
            if names.iter().any(|n| n == s) {
                *v = Value::String(format!("{s}{suffix}"));
            }
        }
    };
    for key in ["bodies", "wheelsets", "elements", "joints"] {
        let Some(list) = vehicle.get(key).and_then(Value::as_array).cloned() else {
            continue;
        };
        let mut all = list.clone();
        for unit in 2..=units {
            let suffix = format!("_{unit}");
            let dx = -((unit - 1) as f64) * pitch;
            for entry in &list {
                let mut e = entry
                    .as_table()
                    .cloned()
                    .ok_or_else(|| shape(what, format!("a vehicle.{key} entry is not a table")))?;
                if let Some(n) = e.get_mut("name") {
                    if let Some(s) = n.as_str() {
                        *n = Value::String(format!("{s}{suffix}"));
                    }
                }
                if let Some(b) = e.get_mut("bodies").and_then(Value::as_array_mut) {
                    for v in b {
                        rename(v, &suffix);
                    }
                }
                if let Some(b) = e.get_mut("body") {
                    rename(b, &suffix);
                }
                for k in ["position_m", "at_m", "from_m", "to_m"] {
                    shift_x(&mut e, k, dx);
                }
                if let Some(v) = e.get_mut("x_m") {
                    if let Some(x) = number(v) {
                        *v = Value::Float(x + dx);
                    }
                }
                all.push(Value::Table(e));
            }
        }
        if key == "elements" {
            for unit in 2..=units {
                let ahead = if unit == 2 {
                    first_last.1.clone()
                } else {
                    format!("{}_{}", first_last.1, unit - 1)
                };
                let behind = format!("{}_{unit}", first_last.0);
                let x_rear = -end - (unit - 2) as f64 * pitch;
                let mut c = Table::new();
                c.insert("type".into(), Value::String("axial".into()));
                c.insert(
                    "name".into(),
                    Value::String(format!("coupler_{}_{unit}", unit - 1)),
                );
                c.insert(
                    "bodies".into(),
                    Value::Array(vec![Value::String(ahead), Value::String(behind)]),
                );
                let point = |x: f64| {
                    Value::Array(vec![
                        Value::Float(x),
                        Value::Float(0.0),
                        Value::Float(COUPLER_HEIGHT_M),
                    ])
                };
                c.insert("from_m".into(), point(x_rear));
                c.insert("to_m".into(), point(x_rear - COUPLER_LENGTH_M));
                c.insert(
                    "stiffness_n_per_m".into(),
                    Value::Float(COUPLER_STIFFNESS_N_PER_M),
                );
                c.insert(
                    "damping_n_s_per_m".into(),
                    Value::Float(COUPLER_DAMPING_N_S_PER_M),
                );
                all.push(Value::Table(c));
            }
        }
        vehicle.insert(key.to_string(), Value::Array(all));
    }
    set_duration(&mut doc, what, |speed| {
        MS_DURATION_S - (units as f64 - 1.0) * pitch / speed
    })?;
    if let Some(v) = doc.get_mut("name") {
        *v = Value::String(format!(
            "{units} MS vehicles coupled on the Tab. 6 track with irregularities"
        ));
    }
    write(&doc, what)
}

/// A series' scene from its TOML text.
pub(super) fn compile(text: &str, name: &str) -> Result<Scene, ScalingError> {
    Scenario::parse(text, name)
        .and_then(|s| s.compile(name, std::path::Path::new(".")))
        .map_err(|source| ScalingError::Compile {
            scene: name.to_string(),
            source,
        })
}

/// Runs `scene` with KEC (over `window` s where given, with the integrator edited by `bdf`), no
/// recording.
fn measure(
    scene: &Scene,
    label: String,
    window: Option<f64>,
    bdf: bool,
    size: Option<f64>,
) -> Result<ScalingRow, ScalingError> {
    let mut scene = scene.clone();
    if let (Some(w), Some((sim, _))) = (window, scene.simulation.as_mut()) {
        sim.duration_s = w;
    }
    let mut built = scene
        .build_run(&RunOptions {
            contact: Some("kec".to_string()),
            speed_m_s: None,
            ..Default::default()
        })
        .map_err(|source| ScalingError::Build {
            label: label.clone(),
            source: Box::new(source),
        })?;
    if bdf {
        let i = &mut built.settings.integrator;
        i.method = Method::Bdf;
        i.rtol = 1e-4;
        i.atol = 1e-6;
    }
    let states = built.vehicle.dim();
    let (wheelsets, bodies) = (
        built.vehicle.wheelset_names().len(),
        built.vehicle.body_names().len(),
    );
    let o = built.run(&mut []);
    let s = &o.summary;
    Ok(ScalingRow {
        label,
        size: size.unwrap_or(states as f64),
        states,
        wheelsets,
        bodies,
        simulated_s: s.simulated_s,
        wall_s: s.wall_s,
        steps: s.steps,
        rhs_evaluations: s.rhs_evaluations,
        outcome: super::precision::outcome(&o),
    })
}

/// The vehicle-size series' scenes, smallest first: (label, scenario TOML).
pub fn vehicle_series() -> Result<Vec<(String, String)>, ScalingError> {
    let bench_scene = |name: &str| {
        super::dynamics::SCENES
            .iter()
            .find(|s| s.0 == name)
            .map(|s| s.1)
            .ok_or_else(|| ScalingError::NoScene {
                name: name.to_string(),
            })
    };
    Ok(vec![
        (
            "bogie (2 wheelsets)".into(),
            bench_scene("bogie_tab6_curve")?.to_string(),
        ),
        (
            "Manchester vehicle 1".into(),
            bench_scene("manchester_vehicle1_tab6")?.to_string(),
        ),
        ("MS vehicle".into(), DEFAULT_SCENARIO.to_string()),
        ("2 MS vehicles coupled".into(), coupled_ms(2)?),
    ])
}

/// Runs both series.
pub fn scaling(settings: &ScalingSettings) -> Result<Scaling, ScalingError> {
    if settings.kilometres.is_empty() || settings.kilometres.iter().any(|&k| !(1..=16).contains(&k)) {
        return Err(ScalingError::TrackLengths);
    }
    if !(settings.window_s.is_finite() && settings.window_s > 0.0 && settings.window_s <= 40.0) {
        return Err(ScalingError::Window {
            window_s: settings.window_s,
        });
    }
    let mut length = Vec::new();
    for &k in &settings.kilometres {
        let scene = compile(&ms_on_longer_track(k)?, &format!("ms_vehicle_{k}km"))?;
        length.push(measure(
            &scene,
            format!("MS vehicle, {k} km"),
            None,
            false,
            Some(k as f64 * MS_TRACK_M),
        )?);
    }
    let vehicles = vehicle_series()?;
    let mut size = Vec::new();
    for (label, text) in &vehicles {
        let scene = compile(text, label)?;
        size.push(measure(
            &scene,
            label.clone(),
            Some(settings.window_s),
            true,
            None,
        )?);
    }
    let completed = |rows: &[ScalingRow], f: &dyn Fn(&ScalingRow) -> f64| -> Vec<(f64, f64)> {
        rows.iter()
            .filter(|r| r.outcome == "completed")
            .map(|r| (r.size, f(r)))
            .collect()
    };
    Ok(Scaling {
        length_exponent: fitted_exponent(&completed(&length, &|r| r.wall_s)),
        size_exponent_per_rhs: fitted_exponent(&completed(&size, &|r| r.per_rhs_s())),
        size_exponent_per_simulated_s: fitted_exponent(&completed(&size, &|r| r.per_simulated_s())),
        length,
        size,
        window_s: settings.window_s,
    })
}

impl Scaling {
    /// Both tables and the fitted exponents (Markdown).
    pub fn markdown(&self) -> String {
        let mut s = String::from(
            "# kecsim bench scaling (KEC, no recording; wall = integration time, preprocessing apart)\n\n## Track length: the MS vehicle over the Tab. 6 kilometre laid k times (with the scene's own integrator, as `kecsim run` runs it)\n\n| run | track km | simulated s | wall s | real-time factor | steps | right-hand sides | µs per right-hand side | outcome |\n|---|---|---|---|---|---|---|---|---|\n",
        );
        for r in &self.length {
            let _ = writeln!(
                s,
                "| {} | {:.0} | {:.1} | {:.3} | {:.1} | {} | {} | {:.1} | {} |",
                r.label,
                r.size / 1e3,
                r.simulated_s,
                r.wall_s,
                r.simulated_s / r.wall_s.max(1e-12),
                r.steps,
                r.rhs_evaluations,
                r.per_rhs_s() * 1e6,
                r.outcome
            );
        }
        let _ = writeln!(
            s,
            "\nfitted exponent of the wall time against the track length: {:.3} (1: linear)\n",
            self.length_exponent
        );
        let _ = writeln!(
            s,
            "## Vehicle size: each vehicle on its own scene's track, {:.1} s, BDF rtol 1e-4, atol 1e-6\n\n| vehicle | bodies | wheelsets | states | steps | right-hand sides | wall s | wall per simulated s | µs per right-hand side | outcome |\n|---|---|---|---|---|---|---|---|---|---|",
            self.window_s
        );
        for r in &self.size {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {} | {:.3} | {:.4} | {:.1} | {} |",
                r.label,
                r.bodies,
                r.wheelsets,
                r.states,
                r.steps,
                r.rhs_evaluations,
                r.wall_s,
                r.per_simulated_s(),
                r.per_rhs_s() * 1e6,
                r.outcome
            );
        }
        let _ = writeln!(
            s,
            "\nfitted exponents against the number of states (1: linear): {:.3} for the cost of a right-hand side (integrator included), {:.3} for the wall time per simulated second (which also carries each vehicle's step count)",
            self.size_exponent_per_rhs, self.size_exponent_per_simulated_s
        );
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exponent_of_a_power_law() {
        let pts: Vec<(f64, f64)> = [1.0, 2.0, 4.0, 8.0]
            .iter()
            .map(|&x: &f64| (x, 3.0 * x.powf(1.5)))
            .collect();
        assert!((fitted_exponent(&pts) - 1.5).abs() < 1e-12);
        assert!(fitted_exponent(&pts[..1]).is_nan());
    }

    #[test]
    fn longer_track_repeats_the_kilometre() {
        let scene = compile(&ms_on_longer_track(2).unwrap(), "two").unwrap();
        let one = compile(DEFAULT_SCENARIO, "one").unwrap();
        let (track, track1) = (scene.track.as_ref().unwrap(), one.track.as_ref().unwrap());
        let (a, b) = (track.centreline.range(), track1.centreline.range());
        assert!((a.1 - a.0 - 2.0 * (b.1 - b.0)).abs() < 1e-6, "{a:?} vs {b:?}");
        let (ia, ib) = (
            track.irregularities.as_ref().unwrap().range(),
            track1.irregularities.as_ref().unwrap().range(),
        );
        assert!(ia.1 - ia.0 > 1.9 * (ib.1 - ib.0), "{ia:?} vs {ib:?}");
        // The second kilometre's curve has the first one's radius, 1000 m further on.
        let (f1, _) = track.eval(400.0).unwrap();
        let (f2, _) = track.eval(1400.0).unwrap();
        assert!(
            (f1.rho_h - f2.rho_h).abs() < 1e-12
                && f1.rho_h.abs() > 1e-3
                && (f1.cant_rad - f2.cant_rad).abs() < 1e-12
        );
        let (sim, _) = scene.simulation.as_ref().unwrap();
        assert!((sim.duration_s - (51.0 + 1000.0 / 19.0)).abs() < 1e-9);
    }

    #[test]
    fn two_coupled_ms_vehicles() {
        let scene = compile(&coupled_ms(2).unwrap(), "coupled").unwrap();
        let (_, vehicle) = scene.simulation.as_ref().unwrap();
        let crate::vehicle::spec::VehicleSpec::Multibody(m) = vehicle else {
            panic!("multibody")
        };
        assert_eq!((m.bodies.len(), m.wheelsets.len(), m.joints.len()), (16, 12, 8));
        let couplers: Vec<_> = m
            .elements
            .iter()
            .filter(|e| matches!(e, crate::vehicle::spec::ElementSpec::Axial { name, .. } if name.starts_with("coupler")))
            .collect();
        assert_eq!(couplers.len(), 1);
        let crate::vehicle::spec::ElementSpec::Axial {
            bodies, from_m, to_m, ..
        } = couplers[0]
        else {
            unreachable!()
        };
        assert_eq!(bodies, &["c5".to_string(), "c1_2".to_string()]);
        assert!((from_m[0] + 13.786).abs() < 1e-9 && (from_m[0] - to_m[0] - COUPLER_LENGTH_M).abs() < 1e-9);
        let w6_2 = m.wheelsets.iter().find(|w| w.name == "w6_2").unwrap();
        assert!((w6_2.x_m - (-11.924 - 2.0 * 13.786 - COUPLER_LENGTH_M)).abs() < 1e-9);
    }
}
