//! The paper's §8 for a scene: the data of its Figures 14–19 and of its Tab. 7, assembled from
//! the scene's contact preprocessing, its track and a KEC-against-tables comparison
//! ([`crate::compare::compare`]). `kecsim paper` prints [`PaperFigures::markdown`] and records it
//! ([`crate::inspect::paper`]). Everything here is SI (m, rad, N, s); the recorder converts.
//!
//! * Fig. 14 — the contact point on the real wheel s^w(y) and on the real rail s^r(y), left and
//!   right, from the scene's 1-entry lookup table (Eq. 43–45, ideal track);
//! * Fig. 15 — the real and the KEC-equivalent right wheel profile (§6), the wheelset centred:
//!   real (Y, Z) = (−L_w + s^w, r0 − h^w(s^w)), equivalent (Y, Z) = (−L_w + s^k, −f^k(s^k)) —
//!   Eq. (50) at y = 0, φ = 0, z̃ = 0 — in the wheelset-track frame, with the rail and the knife
//!   edge at (−L_w, 0);
//! * Fig. 16 — the wheelset kinematics z̃(y) = z − r0 and φ(y) from the real profiles (the table)
//!   and from the equivalent ones (the KEC constraints Eq. 49–50 solved on the ideal track at the
//!   same y). §6 builds the equivalent profiles from these very rows, so the two agree to the
//!   Newton tolerance: the figure checks the construction, as the paper's does;
//! * Fig. 17 — the four irregularities (§2.3: alignment, vertical profile, gauge variation, cross
//!   level) against the arc length;
//! * Fig. 18 — the front bogie's lateral displacement y and yaw ψ (front wheelset, rear wheelset,
//!   frame), KEC and the tables, and |KEC − tables| (the paper: < 1 mm, < 0.5 mrad);
//! * Fig. 19 — the normal contact forces (the constraint reactions, Eq. 53) of the front bogie's
//!   wheels, KEC and the tables, and |KEC − tables|;
//! * Tab. 7 — each run's computational time (integration only; the preprocessing — tables,
//!   equivalent profiles, the vehicle's static settling — apart), simulated time, and their ratio,
//!   beside the paper's (Matlab R2016b, i7-6700HQ, ode15s-type solver, max step 0.02 s).
//!
//! Fig. 18–19 are sampled at the runs' output times; a row's distance is the front wheelset's arc
//! length in the KEC run (the paper's "Distance (m)"), so that a track feature of Fig. 17 at s
//! lines up with the front wheelset passing it.

use std::fmt::Write as _;
use std::time::Instant;

use crate::compare::ModelRun;
use crate::contact::geometry::ContactGeometry;
use crate::contact::kec::{KecError, KecModel};
use crate::contact::lookup::{LookupTable1, TableError, TableSettings};
use crate::dynamics::system::BodySample;
use crate::dynamics::{RunOutput, Sample};
use crate::profile::placement::WheelRailPair;
use crate::profile::Side;
use crate::scenario::{BuildError, Scene};
use crate::track::sections::HorizontalKind;
use crate::track::{Track, TrackError};
use crate::vehicle::spec::{ElementSpec, VehicleSpec};

/// The paper's Tab. 7 (§8.4): computational time of the KEC-method and of the lookup tables, s,
/// for 52.6 s simulated (Matlab R2016b on an Intel Core i7-6700HQ at 2.60 GHz).
pub const PAPER_TAB7: PaperCost = PaperCost {
    kec_s: 347.0,
    tables_s: 434.0,
    simulated_s: 52.6,
    kec_per_real_time: 6.59,
    tables_per_real_time: 8.25,
};

/// The largest wheelset yaw the paper reports on the front bogie (§8.3, Fig. 18: "a maximum
/// absolute value of 7 mrad"), rad.
pub const PAPER_MAX_YAW_RAD: f64 = 7e-3;

/// Sampling step of the irregularities along the track (Fig. 17), m: ten points on the shortest
/// wavelength of the default scene's band (3 m) would need 0.3 m; 0.1 m draws it smoothly.
pub const IRREGULARITY_STEP_M: f64 = 0.1;

/// Fig. 15 shows the real wheel and rail this far to either side of the equivalent profile, m:
/// the flange root and most of the flange (the equivalent profile spans only the table's lateral
/// travel, some 20 mm: beside the whole 140 mm wheel it would be a few pixels).
pub const PROFILE_MARGIN_M: f64 = 0.04;

/// Tab. 7 of the paper.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PaperCost {
    pub kec_s: f64,
    pub tables_s: f64,
    pub simulated_s: f64,
    /// Computational time over real time as the paper prints them (347 / 52.6 = 6.597 is printed
    /// 6.59).
    pub kec_per_real_time: f64,
    pub tables_per_real_time: f64,
}

impl PaperCost {
    /// Computational time over simulated ("real") time as printed: KEC, tables (6.59, 8.25).
    pub fn per_real_time(&self) -> (f64, f64) {
        (self.kec_per_real_time, self.tables_per_real_time)
    }

    /// KEC's cost over the tables' (0.80).
    pub fn ratio(&self) -> f64 {
        self.kec_s / self.tables_s
    }
}

/// Why the paper's figures could not be assembled.
#[derive(Debug, thiserror::Error)]
pub enum PaperError {
    #[error(transparent)]
    Build(#[from] BuildError),
    #[error("the 1-entry contact table (Fig. 14): {0}")]
    Table(#[from] TableError),
    #[error("the KEC-equivalent profiles (Fig. 15-16): {0}")]
    Kec(#[from] KecError),
    #[error("the track (Fig. 17): {0}")]
    Track(#[from] TrackError),
    /// The scene lacks what the figures need, or the runs do not line up.
    #[error("{0}")]
    Scene(String),
}

/// One row of the contact sweep over y on the ideal track (Fig. 14, 16).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SweepRow {
    /// Wheelset lateral displacement y, m.
    pub y: f64,
    /// Contact on the real wheel s^w and rail s^r (paper convention, Fig. 14): left, right, m.
    pub s_wheel: [f64; 2],
    pub s_rail: [f64; 2],
    /// z̃ = z − r0 (m) and roll φ (rad) from the real profiles (the table row).
    pub z_real: f64,
    pub roll_real: f64,
    /// The same from the equivalent profiles: the KEC constraints solved at y, ideal track.
    pub z_kec: f64,
    pub roll_kec: f64,
}

/// Fig. 15: the right wheel, real and equivalent, in the wheelset-track frame (Y, Z), m, the
/// wheelset centred (y = 0, z̃ = 0, φ = 0); the real wheel and the rail within
/// [`PROFILE_MARGIN_M`] of the equivalent profile's lateral span.
#[derive(Debug, Clone, PartialEq)]
pub struct ProfileFigure {
    /// The real right wheel at its profile's knots (within the span).
    pub real: Vec<(f64, f64)>,
    /// The equivalent right wheel at its nodes: (−L_w + s^k, −f^k(s^k)).
    pub equivalent: Vec<(f64, f64)>,
    /// The right rail head at its profile's knots (within the span).
    pub rail: Vec<(f64, f64)>,
    /// Where the knife edge stands: (−L_w, 0).
    pub knife_edge: (f64, f64),
}

/// A quantity of the two runs, sample by sample (the same times).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Both {
    pub kec: Vec<f64>,
    pub tables: Vec<f64>,
}

impl Both {
    /// |KEC − tables| per sample.
    pub fn abs_difference(&self) -> Vec<f64> {
        self.kec
            .iter()
            .zip(&self.tables)
            .map(|(a, b)| (a - b).abs())
            .collect()
    }

    /// The largest |KEC − tables| (0 without samples).
    pub fn max_abs_difference(&self) -> f64 {
        self.abs_difference().into_iter().fold(0.0, f64::max)
    }
}

/// What a body is in the front bogie (Fig. 18's legend).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BogieRole {
    FrontWheelset,
    RearWheelset,
    Frame,
}

impl BogieRole {
    pub fn name(self) -> &'static str {
        match self {
            BogieRole::FrontWheelset => "front wheelset",
            BogieRole::RearWheelset => "rear wheelset",
            BogieRole::Frame => "frame",
        }
    }
}

/// Fig. 18: one body of the front bogie, y (m) and ψ (rad).
#[derive(Debug, Clone, PartialEq)]
pub struct BodyKinematics {
    pub name: String,
    pub role: BogieRole,
    pub y: Both,
    pub yaw: Both,
}

/// Fig. 19: one wheel's normal contact force, N.
#[derive(Debug, Clone, PartialEq)]
pub struct WheelNormal {
    pub wheelset: String,
    pub side: Side,
    pub normal: Both,
}

/// The front bogie of a vehicle: the leading wheelset (largest x), the rigid body it is
/// suspended from (the first body an element ties it to), and the other wheelset on that body
/// (the foremost of them). A single-wheelset scene has its wheelset only.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FrontBogie {
    pub front: String,
    pub rear: Option<String>,
    pub frame: Option<String>,
}

impl FrontBogie {
    /// The front bogie of `vehicle`, whose output names its wheelsets `wheelsets` (in order).
    pub fn of(vehicle: &VehicleSpec, wheelsets: &[String]) -> Option<FrontBogie> {
        let VehicleSpec::Multibody(m) = vehicle else {
            return wheelsets.first().map(|w| FrontBogie {
                front: w.clone(),
                rear: None,
                frame: None,
            });
        };
        let front = m.wheelsets.iter().max_by(|a, b| a.x_m.total_cmp(&b.x_m))?;
        let is_wheelset = |n: &str| m.wheelsets.iter().any(|w| w.name == n);
        let frame = m.elements.iter().filter_map(element_bodies).find_map(|[a, b]| {
            match (*a == front.name, *b == front.name) {
                (true, false) if !is_wheelset(b) => Some(b.clone()),
                (false, true) if !is_wheelset(a) => Some(a.clone()),
                _ => None,
            }
        });
        let rear = frame.as_ref().and_then(|f| {
            m.wheelsets
                .iter()
                .filter(|w| w.name != front.name)
                .filter(|w| {
                    m.elements
                        .iter()
                        .filter_map(element_bodies)
                        .any(|[a, b]| (a == f && *b == w.name) || (b == f && *a == w.name))
                })
                .max_by(|a, b| a.x_m.total_cmp(&b.x_m))
                .map(|w| w.name.clone())
        });
        Some(FrontBogie {
            front: front.name.clone(),
            rear,
            frame,
        })
    }
}

/// The two bodies an element ties (None: a carried mass, on one body).
fn element_bodies(e: &ElementSpec) -> Option<&[String; 2]> {
    match e {
        ElementSpec::Bushing { bodies, .. }
        | ElementSpec::Axial { bodies, .. }
        | ElementSpec::Rotational { bodies, .. } => Some(bodies),
        ElementSpec::CarriedMass { .. } => None,
    }
}

/// Fig. 18–19 over the runs' common samples.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct BogieFigures {
    /// Simulated time of each sample, s.
    pub t: Vec<f64>,
    /// The front wheelset's arc length in the KEC run, m (the figures' distance).
    pub distance_m: Vec<f64>,
    /// Fig. 18: front wheelset, rear wheelset, frame (those the vehicle has).
    pub kinematics: Vec<BodyKinematics>,
    /// Fig. 19: the front and rear wheelsets' wheels, left then right.
    pub normal_forces: Vec<WheelNormal>,
}

/// One run's cost (Tab. 7).
#[derive(Debug, Clone, PartialEq)]
pub struct Cost {
    pub model: String,
    /// Wall time of the integration, s (the paper's "computational time").
    pub integration_s: f64,
    /// Wall time of the contact-model and vehicle preprocessing, s (not in the paper's table).
    pub preprocessing_s: f64,
    pub simulated_s: f64,
    pub steps: usize,
    pub rhs_evaluations: usize,
    /// `completed`, `stopped`, `failed`, `derailed`.
    pub outcome: &'static str,
}

impl Cost {
    fn of(run: &ModelRun) -> Cost {
        let m = &run.output.summary;
        Cost {
            model: run.model.clone(),
            integration_s: m.wall_s,
            preprocessing_s: m.preprocessing_s,
            simulated_s: m.simulated_s,
            steps: m.steps,
            rhs_evaluations: m.rhs_evaluations,
            outcome: m.outcome,
        }
    }

    /// Computational time over simulated time (Tab. 7's "computational time / real time").
    pub fn per_real_time(&self) -> f64 {
        if self.simulated_s > 0.0 {
            self.integration_s / self.simulated_s
        } else {
            f64::NAN
        }
    }
}

/// Tab. 7: both runs' costs.
#[derive(Debug, Clone, PartialEq)]
pub struct CostTable {
    pub kec: Cost,
    pub tables: Cost,
}

impl CostTable {
    /// KEC's integration time over the tables' (the paper: 347 / 434 = 0.80).
    pub fn ratio(&self) -> f64 {
        self.kec.integration_s / self.tables.integration_s
    }

    /// KEC's right-hand-side evaluations over the tables' (a count: unlike the wall times, the
    /// same on a loaded machine).
    pub fn rhs_ratio(&self) -> f64 {
        self.kec.rhs_evaluations as f64 / self.tables.rhs_evaluations as f64
    }

    /// Tab. 7 beside the paper's (Markdown).
    pub fn markdown(&self) -> String {
        let (k, t, p) = (&self.kec, &self.tables, PAPER_TAB7);
        let (pk, pt) = p.per_real_time();
        let mut s = String::from("## Tab. 7: computational cost\n\n");
        let _ = writeln!(
            s,
            "| | KEC-method | {} (tables) | paper: KEC-method | paper: lookup tables |",
            t.model
        );
        s += "|---|---|---|---|---|\n";
        let _ = writeln!(
            s,
            "| computational time (integration) [s] | {:.2} | {:.2} | {} | {} |",
            k.integration_s, t.integration_s, p.kec_s, p.tables_s
        );
        let _ = writeln!(
            s,
            "| simulated time [s] | {:.2} | {:.2} | {} | {} |",
            k.simulated_s, t.simulated_s, p.simulated_s, p.simulated_s
        );
        let _ = writeln!(
            s,
            "| computational time / real time | {:.3} | {:.3} | {pk:.2} | {pt:.2} |",
            k.per_real_time(),
            t.per_real_time()
        );
        let _ = writeln!(
            s,
            "| preprocessing (tables, equivalent profiles, settling) [s] | {:.2} | {:.2} | — | — |",
            k.preprocessing_s, t.preprocessing_s
        );
        let _ = writeln!(
            s,
            "| steps / right-hand sides | {} / {} | {} / {} | — | — |",
            k.steps, k.rhs_evaluations, t.steps, t.rhs_evaluations
        );
        let _ = writeln!(s, "| outcome | {} | {} | | |", k.outcome, t.outcome);
        let _ = writeln!(
            s,
            "\nKEC / tables cost ratio (integration): **{:.2}** (the paper: {:.2}); in right-hand sides {:.2}. The paper's runs: Matlab R2016b on an i7-6700HQ, a variable-step solver with a 0.02 s maximum step; these: kecsim, release build, the scene's integrator.",
            self.ratio(),
            p.ratio(),
            self.rhs_ratio()
        );
        s
    }
}

/// One model's yaw figures on the front bogie (§8.3).
#[derive(Debug, Clone, PartialEq)]
pub struct YawFigures {
    pub model: String,
    /// Every wheelset's largest |ψ|, rad, in the vehicle's order.
    pub max_abs_yaw: Vec<(String, f64)>,
    /// The share of the samples with both front-bogie wheelsets in a circular curve where their
    /// yaws are of opposite sign (None: no such sample, or no rear wheelset).
    pub opposite_share: Option<f64>,
    /// The samples that share counts.
    pub curve_samples: usize,
}

/// Every figure's data and the table.
pub struct PaperFigures {
    pub scene: String,
    pub tables_model: String,
    /// Fig. 14 and 16, one row per table row.
    pub sweep: Vec<SweepRow>,
    /// Fig. 15.
    pub profiles: ProfileFigure,
    /// Fig. 17: (s, [al, vp, gv, cl]) every [`IRREGULARITY_STEP_M`], m (empty without
    /// irregularities).
    pub irregularities: Vec<(f64, [f64; 4])>,
    /// The circular curves of the track, (from, to) m.
    pub curves: Vec<(f64, f64)>,
    pub bogie: FrontBogie,
    /// Fig. 18–19.
    pub figures: BogieFigures,
    /// Tab. 7.
    pub cost: CostTable,
    /// KEC's and the tables' yaw figures.
    pub yaw: [YawFigures; 2],
    /// Wall time of the sweep (table and equivalent profiles built here for Fig. 14–16), s.
    pub sweep_s: f64,
    /// The runs, KEC first.
    pub runs: Vec<ModelRun>,
}

/// Fig. 14–16: the scene's 1-entry table of the real profiles (ideal track, Eq. 43–45), the
/// equivalent profiles from it (§6), and KEC's kinematics at the table's rows.
pub fn contact_figures(pair: &WheelRailPair) -> Result<(Vec<SweepRow>, ProfileFigure), PaperError> {
    let geom = ContactGeometry::with_defaults(pair.clone());
    let table = LookupTable1::build(&geom, &TableSettings::default())?;
    let l_w = pair.wheelset.l_w();
    let model = KecModel::from_table(&table, l_w)?;
    let r0 = model.r0;
    let mut sweep = Vec::with_capacity(table.rows.len());
    let mut start = None;
    for r in &table.rows {
        let k = model.solve(r.y, [0.0; 4], start)?;
        start = Some(k.x(r0));
        sweep.push(SweepRow {
            y: r.y,
            s_wheel: [r.x[2], r.x[4]],
            s_rail: [r.x[3], r.x[5]],
            z_real: r.z() - r0,
            roll_real: r.phi(),
            z_kec: k.z - r0,
            roll_kec: k.phi,
        });
    }
    let right = model.profile(Side::Right);
    let equivalent: Vec<(f64, f64)> = right.nodes().map(|(s, f)| (-l_w + s, -f)).collect();
    let (lo, hi) = equivalent
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.0), b.max(p.0))
        });
    let within = |pts: Vec<(f64, f64)>| -> Vec<(f64, f64)> {
        pts.into_iter()
            .filter(|p| p.0 >= lo - PROFILE_MARGIN_M && p.0 <= hi + PROFILE_MARGIN_M)
            .collect()
    };
    let profiles = ProfileFigure {
        real: within(pair.centred_wheel_positions(Side::Right)),
        equivalent,
        rail: within(pair.rail_positions(Side::Right)),
        knife_edge: (-l_w, 0.0),
    };
    Ok((sweep, profiles))
}

/// Fig. 17: the track's irregularities every `step_m` (empty on a track without them).
pub fn irregularities(track: &Track, step_m: f64) -> Result<Vec<(f64, [f64; 4])>, PaperError> {
    if track.irregularities.is_none() {
        return Ok(Vec::new());
    }
    Ok(crate::track::report::sample(track, step_m)?
        .into_iter()
        .map(|s| (s.frame.s, s.irregularity))
        .collect())
}

/// The paper's case on `scene`: the contact figures, the irregularities, and the scene run with
/// KEC and with `tables_model` for `duration_s` (None: the scene's).
pub fn assemble(
    scene: &Scene,
    tables_model: &str,
    duration_s: Option<f64>,
) -> Result<PaperFigures, PaperError> {
    assemble_observed(scene, tables_model, duration_s, None)
}

/// [`assemble`], the two runs' samples also handed to `observer` (a progress bar).
pub fn assemble_observed(
    scene: &Scene,
    tables_model: &str,
    duration_s: Option<f64>,
    observer: Option<&mut (dyn crate::dynamics::RunObserver + Send)>,
) -> Result<PaperFigures, PaperError> {
    if tables_model == "kec" {
        return Err(PaperError::Scene(
            "the tables model must be another contact model than kec (lookup2, lookup)".into(),
        ));
    }
    let (_, vehicle) = scene
        .simulation
        .as_ref()
        .ok_or(PaperError::Build(BuildError::NoSimulation))?;
    let track = scene.track.as_ref().ok_or_else(|| {
        PaperError::Scene(format!(
            "{}: the scene has no track sections (Fig. 17-18 run along a track)",
            scene.name
        ))
    })?;
    let t = Instant::now();
    let (sweep, profiles) = contact_figures(&scene.pair)?;
    let sweep_s = t.elapsed().as_secs_f64();
    let irregularities = irregularities(track, IRREGULARITY_STEP_M)?;
    let c = crate::compare::compare_observed(
        scene,
        &["kec".to_string(), tables_model.to_string()],
        duration_s,
        observer,
    )?;
    let runs = c.runs;
    let (kec, tables) = match runs.as_slice() {
        [k, t] => (k, t),
        _ => return Err(PaperError::Scene("the comparison did not return two runs".into())),
    };
    let names: Vec<String> = kec.output.wheelsets.iter().map(|w| w.0.clone()).collect();
    let bogie = FrontBogie::of(vehicle, &names)
        .ok_or_else(|| PaperError::Scene(format!("{}: the vehicle has no wheelset", scene.name)))?;
    let curves: Vec<(f64, f64)> = track
        .centreline
        .sections()
        .0
        .iter()
        .filter(|s| s.kind == HorizontalKind::Curve)
        .map(|s| (s.from_m, s.to_m))
        .collect();
    let figures = bogie_figures(&bogie, &kec.output, &tables.output)?;
    let yaw = [
        yaw_figures(&kec.model, &kec.output, &bogie, &curves, figures.t.len()),
        yaw_figures(&tables.model, &tables.output, &bogie, &curves, figures.t.len()),
    ];
    let cost = CostTable {
        kec: Cost::of(kec),
        tables: Cost::of(tables),
    };
    Ok(PaperFigures {
        scene: scene.name.clone(),
        tables_model: tables_model.to_string(),
        sweep,
        profiles,
        irregularities,
        curves,
        bogie,
        figures,
        cost,
        yaw,
        sweep_s,
        runs,
    })
}

/// A wheelset's samples by name.
fn wheelset<'a>(out: &'a RunOutput, name: &str) -> Result<&'a [Sample], PaperError> {
    out.wheelsets
        .iter()
        .find(|w| w.0 == name)
        .map(|w| w.1.as_slice())
        .ok_or_else(|| PaperError::Scene(format!("the run has no wheelset {name}")))
}

/// A rigid body's samples by name, at least `n` of them.
fn body<'a>(out: &'a RunOutput, name: &str, n: usize) -> Result<&'a [(f64, BodySample)], PaperError> {
    out.bodies
        .iter()
        .find(|b| b.0 == name)
        .map(|b| b.1.as_slice())
        .filter(|b| b.len() >= n)
        .ok_or_else(|| PaperError::Scene(format!("the run has no samples of the body {name}")))
}

/// Fig. 18–19 from the two runs, over the samples both have (the same output times).
pub fn bogie_figures(
    bogie: &FrontBogie,
    kec: &RunOutput,
    tables: &RunOutput,
) -> Result<BogieFigures, PaperError> {
    let front_k = wheelset(kec, &bogie.front)?;
    let front_t = wheelset(tables, &bogie.front)?;
    let n = front_k.len().min(front_t.len());
    if let Some((a, b)) = front_k
        .iter()
        .zip(front_t)
        .find(|(a, b)| (a.t - b.t).abs() > 1e-9)
    {
        return Err(PaperError::Scene(format!(
            "the runs' output times differ ({} s against {} s): they cannot be compared sample by sample",
            a.t, b.t
        )));
    }
    let mut f = BogieFigures {
        t: front_k[..n].iter().map(|s| s.t).collect(),
        distance_m: front_k[..n].iter().map(|s| s.s).collect(),
        ..BogieFigures::default()
    };
    let both = |a: &[Sample], b: &[Sample], g: &dyn Fn(&Sample) -> f64| Both {
        kec: a[..n].iter().map(g).collect(),
        tables: b[..n].iter().map(g).collect(),
    };
    let mut wheelsets = vec![(bogie.front.clone(), BogieRole::FrontWheelset)];
    if let Some(r) = &bogie.rear {
        wheelsets.push((r.clone(), BogieRole::RearWheelset));
    }
    for (name, role) in &wheelsets {
        let (a, b) = (wheelset(kec, name)?, wheelset(tables, name)?);
        if a.len() < n || b.len() < n {
            return Err(PaperError::Scene(format!(
                "wheelset {name}: fewer samples than the front wheelset"
            )));
        }
        f.kinematics.push(BodyKinematics {
            name: name.clone(),
            role: *role,
            y: both(a, b, &|s| s.y),
            yaw: both(a, b, &|s| s.yaw),
        });
        for (i, side) in Side::BOTH.into_iter().enumerate() {
            f.normal_forces.push(WheelNormal {
                wheelset: name.clone(),
                side,
                normal: both(a, b, &|s| s.normal[i]),
            });
        }
    }
    if let Some(frame) = &bogie.frame {
        let (a, b) = (body(kec, frame, n)?, body(tables, frame, n)?);
        let col =
            |v: &[(f64, BodySample)], k: usize| -> Vec<f64> { v[..n].iter().map(|(_, s)| s.q[k]).collect() };
        // q = (x, y, z, φ, θ, ψ): y is q[1], the yaw ψ q[5].
        f.kinematics.push(BodyKinematics {
            name: frame.clone(),
            role: BogieRole::Frame,
            y: Both {
                kec: col(a, 1),
                tables: col(b, 1),
            },
            yaw: Both {
                kec: col(a, 5),
                tables: col(b, 5),
            },
        });
    }
    Ok(f)
}

/// One run's yaw figures over its first `n` samples (see [`YawFigures`]).
fn yaw_figures(
    model: &str,
    out: &RunOutput,
    bogie: &FrontBogie,
    curves: &[(f64, f64)],
    n: usize,
) -> YawFigures {
    let in_curve = |s: f64| curves.iter().any(|&(a, b)| s >= a && s <= b);
    let max_abs_yaw = out
        .wheelsets
        .iter()
        .map(|(name, v)| {
            (
                name.clone(),
                v.iter().take(n).map(|s| s.yaw.abs()).fold(0.0, f64::max),
            )
        })
        .collect();
    let front = out.wheelsets.iter().find(|w| w.0 == bogie.front);
    let rear = bogie
        .rear
        .as_ref()
        .and_then(|r| out.wheelsets.iter().find(|w| w.0 == *r));
    let (mut count, mut opposite) = (0usize, 0usize);
    if let (Some(f), Some(r)) = (front, rear) {
        for (a, b) in f.1.iter().zip(&r.1).take(n) {
            if in_curve(a.s) && in_curve(b.s) {
                count += 1;
                if a.yaw * b.yaw < 0.0 {
                    opposite += 1;
                }
            }
        }
    }
    YawFigures {
        model: model.to_string(),
        max_abs_yaw,
        opposite_share: (count > 0).then(|| opposite as f64 / count as f64),
        curve_samples: count,
    }
}

impl PaperFigures {
    /// The largest |KEC − tables| of y (m) and ψ (rad) over the front bogie's bodies.
    pub fn max_differences(&self) -> (f64, f64) {
        self.figures.kinematics.iter().fold((0.0, 0.0), |(dy, dpsi), b| {
            (
                f64::max(dy, b.y.max_abs_difference()),
                f64::max(dpsi, b.yaw.max_abs_difference()),
            )
        })
    }

    /// Fig. 18's summary: the front bogie's differences against the paper's bounds, each
    /// wheelset's largest yaw, and the curve's share of opposite front and rear yaw (Markdown).
    pub fn fig18_markdown(&self) -> String {
        let (b_y, b_psi) = crate::compare::PAPER_BOUNDS;
        let mut s = format!(
            "## Fig. 18: the front bogie, KEC against {}\n\n| body | max \\|Δy\\| [mm] | max \\|Δψ\\| [mrad] |\n|---|---|---|\n",
            self.tables_model
        );
        for b in &self.figures.kinematics {
            let _ = writeln!(
                s,
                "| {} ({}) | {:.4} | {:.4} |",
                b.name,
                b.role.name(),
                b.y.max_abs_difference() * 1e3,
                b.yaw.max_abs_difference() * 1e3
            );
        }
        let (dy, dpsi) = self.max_differences();
        let _ = writeln!(
            s,
            "\nFront bogie: max |Δy| {:.4} mm (the paper: < {} mm), max |Δψ| {:.4} mrad (the paper: < {} mrad): {}.\n",
            dy * 1e3,
            b_y * 1e3,
            dpsi * 1e3,
            b_psi * 1e3,
            if dy < b_y && dpsi < b_psi { "within" } else { "NOT within" }
        );
        let curves: Vec<String> = self
            .curves
            .iter()
            .map(|(a, b)| format!("{a:.0}–{b:.0} m"))
            .collect();
        let names: Vec<&str> = self.yaw[0].max_abs_yaw.iter().map(|w| w.0.as_str()).collect();
        let _ = writeln!(
            s,
            "| model | {} | front/rear yaw of opposite sign in the curve ({}) |",
            names
                .iter()
                .map(|n| format!("max \\|ψ\\| {n} [mrad]"))
                .collect::<Vec<_>>()
                .join(" | "),
            if curves.is_empty() {
                "none".to_string()
            } else {
                curves.join(", ")
            }
        );
        let _ = writeln!(s, "|---|{}---|", "---|".repeat(names.len()));
        for y in &self.yaw {
            let _ = writeln!(
                s,
                "| {} | {} | {} |",
                y.model,
                y.max_abs_yaw
                    .iter()
                    .map(|w| format!("{:.2}", w.1 * 1e3))
                    .collect::<Vec<_>>()
                    .join(" | "),
                match y.opposite_share {
                    Some(f) => format!("{:.1} % of {} samples", 100.0 * f, y.curve_samples),
                    None => "— (no samples with both wheelsets in a curve)".to_string(),
                }
            );
        }
        let _ = writeln!(
            s,
            "\nThe paper: wheelset yaw \"up to 7 mrad\" ({} mrad), front and rear wheelset yaw \"opposite in sign\" in the curve.",
            PAPER_MAX_YAW_RAD * 1e3
        );
        s
    }

    /// Fig. 16's check: the largest |z̃_real − z̃_KEC| (m) and |φ_real − φ_KEC| (rad) over the sweep.
    pub fn sweep_differences(&self) -> (f64, f64) {
        self.sweep.iter().fold((0.0, 0.0), |(dz, dphi), r| {
            (
                f64::max(dz, (r.z_real - r.z_kec).abs()),
                f64::max(dphi, (r.roll_real - r.roll_kec).abs()),
            )
        })
    }

    /// The report: Tab. 7, Fig. 18's summary, and a line on the contact figures (Markdown).
    pub fn markdown(&self) -> String {
        let mut s = format!("# kecsim paper: {}\n\n", self.scene);
        s += &self.cost.markdown();
        s += "\n";
        s += &self.fig18_markdown();
        let (dz, dphi) = self.sweep_differences();
        let (lo, hi) = (
            self.sweep.first().map_or(0.0, |r| r.y),
            self.sweep.last().map_or(0.0, |r| r.y),
        );
        let _ = write!(
            s,
            "\n## Fig. 14-16: contact geometry\n\n{} table rows over y = {:.2} .. {:.2} mm (table and equivalent profiles built in {:.2} s). Fig. 16, real against equivalent profiles at the rows: max |Δz| {:.2e} mm, max |Δφ| {:.2e} mrad (equal by construction, §6).\n",
            self.sweep.len(),
            lo * 1e3,
            hi * 1e3,
            self.sweep_s,
            dz * 1e3,
            dphi * 1e3
        );
        s
    }
}
