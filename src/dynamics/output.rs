//! What a run gives out, and to whom: the run summary ([`RunSummary`], `--json`), the observers
//! that receive the samples ([`Sample`], [`super::sample`]) as they are produced ([`RunObserver`]:
//! the CSV writer here, the Rerun recorder in [`crate::inspect::run`], the progress bar and the
//! pacing of the command line), and the CSV of a wheelset, whose columns and rows are made from
//! the table of recorded quantities ([`QUANTITIES`]). Observers only read: the physics never
//! depends on them (argmin's `Observe`).

use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::LazyLock;

use serde::Serialize;

use super::safety::Safety;
use super::sample::{Csv, Quantity, Sample, Unit, QUANTITIES, WHEELS};
use super::system::BodySample;
use crate::files::AtomicFile;

/// The run summary (`--json`; the keys are a documented interface).
#[derive(Debug, Clone, Serialize)]
pub struct RunSummary {
    pub scene: String,
    pub contact_model: String,
    pub creep_model: String,
    pub integrator: String,
    pub simulated_s: f64,
    pub wall_s: f64,
    /// Simulated time over wall time.
    pub realtime_factor: f64,
    pub steps: usize,
    pub rejected_steps: usize,
    /// The smallest accepted step but for the last one (cut to land on the end), s (0 when none
    /// was taken).
    pub smallest_step_s: f64,
    pub rhs_evaluations: usize,
    /// Jacobians evaluated (implicit and linearly implicit methods; their finite-difference
    /// right-hand sides are counted in `rhs_evaluations`).
    pub jacobians: usize,
    /// BDF with `newton_reuse`: wheelset dynamics a Newton iteration carried forward by the
    /// Jacobian instead of evaluating them (0 without).
    pub wheelset_dynamics_reused: usize,
    /// What limited the step size: the states with the largest term of the error norm in most
    /// steps tried (accepted and rejected), most first (see
    /// [`crate::dynamics::integrator::Stats::limiting`]).
    pub step_limiting: Vec<crate::dynamics::integrator::StepLimit>,
    pub preprocessing_s: f64,
    pub max_abs_y_mm: f64,
    pub max_abs_yaw_mrad: f64,
    pub max_normal_n: f64,
    pub min_normal_n: f64,
    pub max_abs_y_over_q: f64,
    /// The largest spin of any contact as the share of its linear lateral force,
    /// φ̂ = G (ab)^{3/2} C₂₃ |φ| / (μN) (0 where the run has no contact patches).
    pub max_normalized_spin: f64,
    /// Why the run stopped early, if it did.
    pub error: Option<String>,
    /// A stop condition that ended the run normally (`stop_lateral_m`).
    pub stopped: Option<String>,
    /// With an accelerating speed ramp: the speed at which the lateral oscillation stopped
    /// decaying and started to grow (hunting onset), m/s — see [`super::run::hunting_onset`];
    /// with a decelerating one, the speed at which the hunting cycle died out (the nonlinear
    /// critical speed, [`super::run::hunting_extinction`]).
    pub critical_speed_m_s: Option<f64>,
    /// `critical_speed_m_s` is the decelerating ramp's (not in the JSON: the scene says so).
    #[serde(skip)]
    pub critical_speed_decelerating: bool,
    /// `completed`, `stopped` (a stop condition) or `failed` (`error` says why).
    pub outcome: &'static str,
    /// Output samples per wheelset.
    pub samples: usize,
    /// The largest gap of a lifted wheel to its rail, mm (0: no wheel lifted).
    pub max_lift_mm: f64,
    /// The longest time one wheel stayed lifted (from the output samples), s.
    pub longest_lift_s: f64,
    /// Landings of lifted wheels (plastic impacts).
    pub landings: usize,
    /// The largest closing speed at a landing, m/s.
    pub max_landing_speed_m_s: f64,
    /// The largest normal impulse of a landing, N s.
    pub max_landing_impulse_n_s: f64,
    /// A derailment (`outcome` = `derailed`): the derailing wheelset's largest |Y/Q| over its
    /// last 2 m (EN 14363's window for Y/Q), its Y/Q history's end.
    pub derailment_max_y_over_q_2m: Option<f64>,
    /// Running safety per wheelset (Y/Q against Nadal, ΣY against Prud'homme, ΔQ/Q₀), EN 14363
    /// style (`super::safety`); None where the run was not given the basis of the limits.
    pub safety: Option<Safety>,
    /// Wheel wear per wheel (the USFD function over the wear number; `super::wear`).
    pub wear: Option<super::wear::Wear>,
    /// Contact stress against the rail's shakedown limit per wheel (`super::contact_stress`).
    pub contact_stress: Option<super::contact_stress::ContactStress>,
    /// Ride comfort at the carbodies' floor points (EN 12299, Sperling; [`super::ride`]).
    pub comfort: Option<super::ride::Comfort>,
    /// What held the speed and what it took: traction, power, the curving resistance
    /// ([`super::traction`]).
    pub traction: Option<super::resistance::TractionSummary>,
    /// Physically doubtful input the run went on with (the scenario's warnings).
    pub warnings: Vec<String>,
}

/// The normalised spin φ̂ above which Polach's forces are unsafe (`kecsim bench creep-accuracy`:
/// its |ΔF|/μN against the exact theory is within 10 % without spin, 38 % at φ̂ ≈ 0.5, up to 63 %).
pub const POLACH_SPIN_LIMIT: f64 = 0.1;

impl fmt::Display for RunSummary {
    /// The plain-text summary `kecsim run` prints (and the recording's summary shows).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "simulated {:.3} s in {:.3} s wall: real-time factor {:.1} (preprocessing {:.2} s); {} steps ({} rejected), {} right-hand sides, {} Jacobians",
            self.simulated_s,
            self.wall_s,
            self.realtime_factor,
            self.preprocessing_s,
            self.steps,
            self.rejected_steps,
            self.rhs_evaluations,
            self.jacobians
        )?;
        if !self.step_limiting.is_empty() {
            let shown: Vec<String> = self
                .step_limiting
                .iter()
                .map(|l| format!("{} {:.0} %", l.state, 100.0 * l.share))
                .collect();
            writeln!(
                f,
                "step size limited by (largest error term of the steps tried): {}",
                shown.join(", ")
            )?;
        }
        if self.samples == 0 {
            writeln!(f, "no output samples")?;
        } else {
            writeln!(
                f,
                "max |y| {:.3} mm, max |yaw| {:.3} mrad, normal forces {:.1} .. {:.1} kN, max |Y/Q| {:.3}",
                self.max_abs_y_mm,
                self.max_abs_yaw_mrad,
                self.min_normal_n * 1e-3,
                self.max_normal_n * 1e-3,
                self.max_abs_y_over_q
            )?;
        }
        if self.creep_model == "polach" && self.max_normalized_spin > POLACH_SPIN_LIMIT {
            writeln!(
                f,
                "warning: creep model polach at spin φ̂ up to {:.2} (G (ab)^1.5 C23 |φ| / μN; above {POLACH_SPIN_LIMIT}): Polach's spin term is off Kalker's exact theory by 20–60 % of μN there, its lateral force falls as the lateral creepage rises — use model = \"exact-table\" (kecsim bench creep-accuracy)",
                self.max_normalized_spin
            )?;
        }
        if self.max_lift_mm > 0.0 || self.landings > 0 {
            writeln!(
                f,
                "wheel lift: up to {:.3} mm, longest {:.3} s; {} landings, closing speed up to {:.3} m/s, impulse up to {:.1} N s",
                self.max_lift_mm,
                self.longest_lift_s,
                self.landings,
                self.max_landing_speed_m_s,
                self.max_landing_impulse_n_s
            )?;
        }
        if let Some(traction) = &self.traction {
            write!(f, "{traction}")?;
        }
        match (self.critical_speed_m_s, self.critical_speed_decelerating) {
            (Some(v), false) => writeln!(
                f,
                "hunting onset on the speed ramp (critical speed): {v:.2} m/s ({:.0} km/h)",
                v * 3.6
            )?,
            (Some(v), true) => writeln!(
                f,
                "hunting dies out on the decelerating ramp (nonlinear critical speed): {v:.2} m/s ({:.0} km/h)",
                v * 3.6
            )?,
            (None, _) => {}
        }
        if let Some(safety) = &self.safety {
            write!(f, "{safety}")?;
        }
        if let Some(wear) = &self.wear {
            write!(f, "{wear}")?;
        }
        if let Some(stress) = &self.contact_stress {
            write!(f, "{stress}")?;
        }
        if let Some(comfort) = &self.comfort {
            write!(f, "{comfort}")?;
        }
        if let Some(note) = &self.stopped {
            writeln!(f, "stopped: {note}")?;
        }
        if let Some(q) = self.derailment_max_y_over_q_2m {
            writeln!(
                f,
                "derailed: the wheelset's largest |Y/Q| over its last 2 m: {q:.3}"
            )?;
        }
        if let Some(e) = &self.error {
            writeln!(f, "the run stopped at t = {:.4} s: {e}", self.simulated_s)?;
        }
        Ok(())
    }
}

/// The longest line of the command line's short summary ([`RunSummary::brief`], [`wrap`]).
pub const BRIEF_WIDTH: usize = 100;

impl RunSummary {
    /// The run's outcome in one line, what an engineer reads first: a failure or a derailment,
    /// else the running-safety verdict (`Safety::verdict`).
    pub fn verdict(&self) -> String {
        if let Some(e) = &self.error {
            return format!("the run FAILED at t = {:.4} s: {e}", self.simulated_s);
        }
        if let Some(q) = self.derailment_max_y_over_q_2m {
            return format!(
                "DERAILED at t = {:.3} s (largest |Y/Q| over its last 2 m: {q:.3})",
                self.simulated_s
            );
        }
        match &self.safety {
            Some(s) => s.verdict(),
            None if self.samples == 0 => "no output samples: nothing to assess".into(),
            None => "running safety: not assessed (the run has no limits' basis)".into(),
        }
    }

    /// The short summary `kecsim run` prints: the verdict first, then the figures an engineer
    /// looks for, each line at most [`BRIEF_WIDTH`] characters; the whole summary
    /// ([`fmt::Display`]) is `--verbose`'s and the JSON's.
    pub fn brief(&self) -> String {
        let mut lines = vec![self.verdict()];
        lines.push(format!(
            "simulated {:.2} s in {:.2} s wall (real-time factor {:.1}); {} steps, {} right-hand sides",
            self.simulated_s, self.wall_s, self.realtime_factor, self.steps, self.rhs_evaluations
        ));
        if self.samples > 0 {
            lines.push(format!(
                "max |y| {:.2} mm, |yaw| {:.2} mrad; wheel loads Q {:.1} .. {:.1} kN; max |Y/Q| {:.3}",
                self.max_abs_y_mm,
                self.max_abs_yaw_mrad,
                self.min_normal_n * 1e-3,
                self.max_normal_n * 1e-3,
                self.max_abs_y_over_q
            ));
        }
        if let Some(note) = &self.stopped {
            lines.push(format!("stopped: {note}"));
        }
        if self.max_lift_mm > 0.0 || self.landings > 0 {
            lines.push(format!(
                "wheel lift up to {:.3} mm, longest {:.3} s; {} landings",
                self.max_lift_mm, self.longest_lift_s, self.landings
            ));
        }
        match (self.critical_speed_m_s, self.critical_speed_decelerating) {
            (Some(v), false) => lines.push(format!(
                "critical speed (hunting onset): {v:.2} m/s ({:.0} km/h)",
                v * 3.6
            )),
            (Some(v), true) => lines.push(format!(
                "nonlinear critical speed (hunting dies out): {v:.2} m/s ({:.0} km/h)",
                v * 3.6
            )),
            (None, _) => {}
        }
        if let Some(t) = &self.traction {
            lines.push(format!(
                "traction {:.2} kN mean, {:.1} kW; speed within {:.3} % of {} m/s",
                t.mean_traction_n * 1e-3,
                t.mean_power_kw,
                t.max_speed_deviation_percent,
                t.reference_speed_m_s
            ));
            for c in &t.curves {
                lines.push(format!(
                    "curving resistance {:.2} kN ({:.2} N/kN of the weight) in the R {:.2} m curve",
                    c.resistance_n * 1e-3,
                    c.resistance_n_per_kn,
                    c.radius_m
                ));
            }
        }
        if let Some(w) = &self.wear {
            let worst = w
                .wheels
                .iter()
                .map(|w| w.max_wear_index_n_mm2)
                .fold(0.0, f64::max);
            lines.push(format!(
                "wear up to {:.2} mg/km ({}), {} regime (Tγ/A up to {:.1} N/mm²)",
                w.max_mass_mg_per_km,
                w.max_wheel,
                format!("{:?}", super::wear::WearRegime::of(worst)).to_lowercase(),
                worst
            ));
        }
        if let Some(c) = &self.contact_stress {
            let load = c.wheels.iter().map(|w| w.worst_load_factor).fold(0.0, f64::max);
            lines.push(format!(
                "rail stress p0 up to {:.0} MPa ({}); {:.2} × the shakedown limit; ratchetting on {:.1} %",
                c.max_p0_mpa,
                c.max_wheel,
                load,
                100.0 * c.max_share_ratchetting
            ));
        }
        if let Some(c) = &self.comfort {
            lines.push(match c.max_n_mv {
                Some(n) => format!(
                    "ride comfort N_MV up to {n:.2} ({}); Sperling Wz up to {:.2} lateral, {:.2} vertical",
                    super::comfort::n_mv_class(n),
                    c.max_wz_y,
                    c.max_wz_z
                ),
                None => format!(
                    "ride comfort: Sperling Wz up to {:.2} lateral, {:.2} vertical (no N_MV: under 5 s)",
                    c.max_wz_y, c.max_wz_z
                ),
            });
        }
        if self.creep_model == "polach" && self.max_normalized_spin > POLACH_SPIN_LIMIT {
            lines.push(format!(
                "warning: Polach's creep forces at spin φ̂ up to {:.2} (unsafe above {POLACH_SPIN_LIMIT}): use \"exact-table\"",
                self.max_normalized_spin
            ));
        }
        let mut text = String::new();
        for l in &lines {
            text.push_str(&wrap(l, BRIEF_WIDTH));
        }
        text
    }
}

/// `line` broken at spaces into lines of at most `width` characters (a word longer than that
/// stands alone), continuations indented by two spaces; each line ends with a newline.
pub fn wrap(line: &str, width: usize) -> String {
    let mut out = String::new();
    let mut current = String::new();
    for word in line.split(' ') {
        let len = current.chars().count();
        if len > 0 && len + 1 + word.chars().count() > width {
            out.push_str(current.trim_end());
            out.push('\n');
            current = format!("  {word}");
        } else {
            if len > 0 {
                current.push(' ');
            }
            current.push_str(word);
        }
    }
    out.push_str(current.trim_end());
    out.push('\n');
    out
}

/// An observer's failure (a file that cannot be written, a recording that cannot be logged): it
/// ends the run, keeping what was recorded.
pub type ObserverError = Box<dyn std::error::Error + Send + Sync>;

/// What a run tells its observers before the first sample.
#[derive(Debug, Clone)]
pub struct RunStart<'a> {
    pub wheelsets: &'a [String],
    pub bodies: &'a [String],
    /// The carbodies' floor points (ride comfort), in the order of [`OutputSample::floor`].
    pub floor_points: &'a [super::system::FloorPoint],
    /// Simulated time the run is to cover, s.
    pub duration_s: f64,
}

/// One output time: every wheelset's and body's sample (in the order of [`RunStart`]).
#[derive(Debug, Clone, Copy)]
pub struct OutputSample<'a> {
    pub t: f64,
    pub wheelsets: &'a [Sample],
    pub bodies: &'a [BodySample],
    /// Per force element of a multibody vehicle (in the scene's order): its deflection and force
    /// in its first body's axes (m, N); empty for the other vehicles.
    pub elements: &'a [(nalgebra::Vector3<f64>, nalgebra::Vector3<f64>)],
    /// Per floor point of [`RunStart::floor_points`]: the floor accelerations (x, y, z) in the
    /// carbody's axes less the static 1 g, m/s² ([`super::system::VehicleSample::floor`]).
    pub floor: &'a [[f64; 3]],
}

/// Receives a run's samples as they are produced (read-only; an `Err` ends the run).
pub trait RunObserver {
    fn start(&mut self, _run: &RunStart<'_>) -> Result<(), ObserverError> {
        Ok(())
    }
    fn sample(&mut self, sample: &OutputSample<'_>) -> Result<(), ObserverError>;
    /// After the last sample, with the summary (also when the run stopped or failed).
    fn finish(&mut self, _summary: &RunSummary) -> Result<(), ObserverError> {
        Ok(())
    }
}

/// One CSV column: its name and where its value is (a quantity of [`QUANTITIES`], a wheel).
#[derive(Debug, Clone)]
struct CsvColumn {
    name: String,
    quantity: &'static Quantity,
    unit: Unit,
    /// Which of the quantity's values (0 for a one-value quantity, else the wheel).
    index: usize,
}

/// The CSV columns of `table`'s quantities (see [`Csv`]): each quantity's after the previous one's,
/// a [`Csv::WheelByWheelWithPrevious`] one wheel by wheel with the previous quantity's.
fn csv_layout(table: &'static [Quantity]) -> Vec<CsvColumn> {
    // Blocks of quantities written wheel by wheel together.
    let mut blocks: Vec<Vec<(&'static Quantity, &'static str, Unit)>> = Vec::new();
    for q in table {
        match q.csv {
            Csv::No => {}
            Csv::Columns(stem, unit) => blocks.push(vec![(q, stem, unit)]),
            Csv::WheelByWheelWithPrevious(stem, unit) => match blocks.last_mut() {
                Some(block) => block.push((q, stem, unit)),
                None => blocks.push(vec![(q, stem, unit)]),
            },
        }
    }
    let mut columns = Vec::new();
    for block in blocks {
        match block[..] {
            [(quantity, stem, unit)] if quantity.value.width() == 1 => columns.push(CsvColumn {
                name: unit.name(stem),
                quantity,
                unit,
                index: 0,
            }),
            // Per wheel (a quantity written with the previous one is per wheel, as that one).
            _ => {
                for (index, wheel) in WHEELS.iter().enumerate() {
                    for &(quantity, stem, unit) in &block {
                        columns.push(CsvColumn {
                            name: unit.name(&format!("{stem}_{wheel}")),
                            quantity,
                            unit,
                            index,
                        });
                    }
                }
            }
        }
    }
    columns
}

/// The CSV header of `table`'s quantities (the tests' check of a table with more quantities).
#[cfg(all(test, feature = "rerun"))]
pub(crate) fn csv_header(table: &'static [Quantity]) -> Vec<String> {
    csv_layout(table).into_iter().map(|c| c.name).collect()
}

/// The columns of [`QUANTITIES`].
static CSV_LAYOUT: LazyLock<Vec<CsvColumn>> = LazyLock::new(|| csv_layout(QUANTITIES));

/// The CSV columns of a wheelset (`--csv DIR` writes `DIR/NAME.csv`; a documented interface),
/// made from [`QUANTITIES`].
pub static CSV_COLUMNS: LazyLock<Vec<&'static str>> =
    LazyLock::new(|| CSV_LAYOUT.iter().map(|c| c.name.as_str()).collect());

/// The values of `columns` in a sample (NaN where the sample has none).
fn row(columns: &[CsvColumn], s: &Sample) -> Vec<f64> {
    columns
        .iter()
        .map(|c| c.quantity.value.of(s, c.unit).map_or(f64::NAN, |v| v[c.index]))
        .collect()
}

/// One CSV row of a sample (the [`CSV_COLUMNS`], SI converted to the columns' units).
pub fn csv_row(s: &Sample) -> Vec<f64> {
    row(&CSV_LAYOUT, s)
}

fn write_row(w: &mut csv::Writer<AtomicFile>, s: &Sample) -> Result<(), csv::Error> {
    w.write_record(csv_row(s).iter().map(|x| format!("{x:.9e}")))
}

/// Writes one CSV per wheelset into a directory as the samples come (`DIR/NAME.csv`, the
/// [`CSV_COLUMNS`]). Each is written to its part file beside it (`DIR/.NAME.csv.part-PID`) and
/// takes its name when the run ends ([`crate::files::AtomicFile`]), however it ends: a reader
/// never sees half a file, and what was written is kept if the run stops or fails. The files are
/// created at the start (a directory that cannot be written fails before any work).
pub struct CsvWriter {
    writers: Vec<(PathBuf, Option<csv::Writer<AtomicFile>>)>,
    /// Per carbody: its name, its CSV ([`CARBODY_CSV_COLUMNS`]) and the indices of its floor
    /// points in [`OutputSample::floor`] (from the run's start).
    carbodies: Vec<CarbodyCsv>,
    /// The floor points (from the run's start).
    floor_points: Vec<super::system::FloorPoint>,
    /// The files renamed into place at the run's end.
    committed: Vec<PathBuf>,
}

/// A carbody's CSV in [`CsvWriter`]: its name, its path, its writer (None once committed) and
/// the indices of its floor points.
type CarbodyCsv = (String, PathBuf, Option<csv::Writer<AtomicFile>>, Vec<usize>);

/// The columns of a carbody's CSV (`--csv DIR` writes `DIR/CARBODY.csv` beside the wheelsets'
/// for each carbody with floor points; a documented interface): one row per sample and floor
/// point — the time, the floor point (`middle`, `over_BOGIE`), the carbody's arc length, and the
/// floor accelerations in the carbody's axes (what a floor accelerometer reads, the quasi-static
/// lateral acceleration of a curve included, less 1 g on z).
pub const CARBODY_CSV_COLUMNS: [&str; 6] = ["t_s", "point", "s_m", "acc_x_m_s2", "acc_y_m_s2", "acc_z_m_s2"];

impl CsvWriter {
    /// Creates `dir` and a CSV with its header for each wheelset and each carbody
    /// ([`crate::vehicle::VehicleSpec::wheelset_names`], [`crate::vehicle::VehicleSpec::carbody_names`]):
    /// every file is opened here, before the run, so that the files a command guards
    /// ([`crate::vehicle::VehicleSpec::csv_files`]) are all it writes.
    pub fn create(dir: &Path, wheelsets: &[String], carbodies: &[String]) -> Result<CsvWriter, csv::Error> {
        std::fs::create_dir_all(dir)?;
        let open = |name: &String,
                    header: &[&str]|
         -> Result<(PathBuf, Option<csv::Writer<AtomicFile>>), csv::Error> {
            let path = dir.join(format!("{name}.csv"));
            let mut w = crate::files::csv_writer(&path)?;
            w.write_record(header.iter())?;
            Ok((path, Some(w)))
        };
        let writers = wheelsets
            .iter()
            .map(|name| open(name, &CSV_COLUMNS))
            .collect::<Result<Vec<_>, csv::Error>>()?;
        let carbodies = carbodies
            .iter()
            .map(|name| open(name, &CARBODY_CSV_COLUMNS).map(|(p, w)| (name.clone(), p, w, Vec::new())))
            .collect::<Result<Vec<_>, csv::Error>>()?;
        Ok(CsvWriter {
            writers,
            carbodies,
            floor_points: Vec::new(),
            committed: Vec::new(),
        })
    }

    /// The files written whole and in place at the run's end (a file whose write failed — a
    /// full disk — is not among them: the file there before is kept).
    pub fn written(&self) -> &[PathBuf] {
        &self.committed
    }

    /// The files written.
    pub fn paths(&self) -> Vec<PathBuf> {
        self.writers
            .iter()
            .map(|(p, _)| p.clone())
            .chain(self.carbodies.iter().map(|(_, p, ..)| p.clone()))
            .collect()
    }
}

/// The carbodies that carry the floor points, each once, in order (a built model's
/// [`super::system::VehicleModel::floor_points`]: the carbody CSVs [`CsvWriter::create`] opens).
pub fn floor_carbodies(points: &[super::system::FloorPoint]) -> Vec<String> {
    let mut names: Vec<String> = Vec::new();
    for p in points {
        if !names.contains(&p.carbody) {
            names.push(p.carbody.clone());
        }
    }
    names
}

impl RunObserver for CsvWriter {
    /// Each floor point to its carbody's CSV; a floor point on a carbody without one (not among
    /// the names given to [`CsvWriter::create`]) fails the start: its file was not guarded.
    fn start(&mut self, run: &RunStart<'_>) -> Result<(), ObserverError> {
        self.floor_points = run.floor_points.to_vec();
        for (k, p) in run.floor_points.iter().enumerate() {
            let Some((.., points)) = self.carbodies.iter_mut().find(|(name, ..)| *name == p.carbody) else {
                return Err(format!(
                    "the floor point {} of carbody {} has no CSV (the carbodies announced: {}); a kecsim bug",
                    p.point,
                    p.carbody,
                    self.carbodies
                        .iter()
                        .map(|(n, ..)| n.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                )
                .into());
            };
            points.push(k);
        }
        Ok(())
    }

    fn sample(&mut self, sample: &OutputSample<'_>) -> Result<(), ObserverError> {
        for ((path, w), s) in self.writers.iter_mut().zip(sample.wheelsets) {
            let w = w
                .as_mut()
                .ok_or_else(|| format!("{}: written after its end", path.display()))?;
            write_row(w, s).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        }
        for (_, path, w, points) in &mut self.carbodies {
            let w = w
                .as_mut()
                .ok_or_else(|| format!("{}: written after its end", path.display()))?;
            for &k in points.iter() {
                let (Some(p), Some(a)) = (self.floor_points.get(k), sample.floor.get(k)) else {
                    continue;
                };
                let s = sample.bodies.get(p.body).map_or(f64::NAN, |b| b.s);
                w.write_record([
                    format!("{:.9e}", sample.t),
                    p.point.clone(),
                    format!("{s:.9e}"),
                    format!("{:.9e}", a[0]),
                    format!("{:.9e}", a[1]),
                    format!("{:.9e}", a[2]),
                ])
                .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
            }
        }
        Ok(())
    }

    /// Each file renamed into place (all are tried; the first failure is reported).
    fn finish(&mut self, _summary: &RunSummary) -> Result<(), ObserverError> {
        let mut first = None;
        let carbodies = self.carbodies.iter_mut().map(|(_, p, w, _)| (&*p, w));
        for (path, w) in self.writers.iter_mut().map(|(p, w)| (&*p, w)).chain(carbodies) {
            if let Some(w) = w.take() {
                match crate::files::commit_csv(w) {
                    Ok(()) => self.committed.push(path.clone()),
                    Err(e) => {
                        first.get_or_insert(format!("cannot write {}: {e}", path.display()));
                    }
                }
            }
        }
        match first {
            Some(e) => Err(e.into()),
            None => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The CSV header of `kecsim run --csv` is a documented interface (scripts read the columns by
    /// name and position): pinned here, name by name and in order.
    #[test]
    fn csv_header_is_pinned() {
        const PINNED: [&str; 60] = [
            "t_s",
            "s_m",
            "speed_m_s",
            "y_mm",
            "yaw_mrad",
            "z_mm",
            "roll_mrad",
            "n_left_n",
            "n_right_n",
            "fx_left_n",
            "fy_left_n",
            "fx_right_n",
            "fy_right_n",
            "y_left_n",
            "q_left_n",
            "y_right_n",
            "q_right_n",
            "s_wheel_left_mm",
            "s_rail_left_mm",
            "s_wheel_right_mm",
            "s_rail_right_mm",
            "rail_y_left_mm",
            "rail_z_left_mm",
            "rail_y_right_mm",
            "rail_z_right_mm",
            "lift_left_mm",
            "lift_right_mm",
            "track_shift_mm",
            // Issue 37's contact quantities (names from the issue).
            "creep_x_left",
            "creep_x_right",
            "creep_y_left",
            "creep_y_right",
            "spin_left_1pm",
            "spin_right_1pm",
            "a_left_mm",
            "a_right_mm",
            "b_left_mm",
            "b_right_mm",
            "p0_left_mpa",
            "p0_right_mpa",
            "tgamma_left_n",
            "tgamma_right_n",
            "tgamma_spin_left_n",
            "tgamma_spin_right_n",
            "tgamma_2m_left_n",
            "tgamma_2m_right_n",
            // Issue 46: the speed held and what it took.
            "reference_speed_m_s",
            "vehicle_speed_m_s",
            "drive_torque_left_n_m",
            "drive_torque_right_n_m",
            "traction_n",
            "traction_power_kw",
            // Issue 49: the patch of the model valid at the contact.
            "pmax_left_mpa",
            "pmax_right_mpa",
            "contact_area_left_mm2",
            "contact_area_right_mm2",
            "hertz_dev_left",
            "hertz_dev_right",
            "patches_left",
            "patches_right",
        ];
        let header: Vec<&str> = CSV_COLUMNS.iter().copied().collect();
        assert_eq!(header, PINNED);
    }

    /// Each CSV column's value of a sample, in the column's unit (pinned with the header). The
    /// contact quantities by hand: p0 = 3N/(2πab) (48 kN on 6.1 × 4.1 mm: 916.366 MPa; 52 kN on
    /// 7.1 × 3.1 mm: 1128.040 MPa), Tγ = |Fx ξx + Fy ξy| (|−1.5e3 · 1.1e-3 + 3.5e3 · (−2.1e-3)| =
    /// 9.0 N; |2.5e3 · (−1.3e-3) − 4.5e3 · 2.3e-3| = 13.6 N), |Mz φ| (11 · 0.31, 13 · 0.37).
    #[test]
    fn csv_row_is_pinned() {
        let row = csv_row(&Sample::distinct());
        let pinned = [
            1.5,
            23.25,
            19.0,
            2.0,
            -1.5,
            0.7,
            0.3,
            48e3,
            52e3,
            -1.5e3,
            3.5e3,
            2.5e3,
            -4.5e3,
            6e3,
            40e3,
            -8e3,
            50e3,
            4.0,
            6.0,
            -5.0,
            -7.0,
            750.0,
            1.0,
            -750.0,
            2.0,
            0.0,
            12.5,
            0.5,
            1.1e-3,
            -1.3e-3,
            -2.1e-3,
            2.3e-3,
            0.31,
            -0.37,
            6.1,
            7.1,
            4.1,
            3.1,
            916.3659258389814,
            1128.040487157459,
            9.0,
            13.6,
            3.41,
            4.81,
            7.5,
            12.5,
            19.25,
            19.125,
            55.0,
            65.0,
            450.0,
            8.55,
            1200.0,
            900.0,
            80.0,
            70.0,
            0.125,
            0.5,
            1.0,
            2.0,
        ];
        assert_eq!(row.len(), pinned.len());
        for (k, (a, b)) in row.iter().zip(pinned).enumerate() {
            assert!(
                (a - b).abs() <= 1e-12 * b.abs().max(1.0),
                "{}: {a} vs {b}",
                CSV_COLUMNS[k]
            );
        }
    }
}
