//! What a run gives out, and to whom: the output row of one wheelset ([`Sample`]), the run summary
//! ([`RunSummary`], `--json`), and the observers that receive the samples as they are produced
//! ([`RunObserver`]: the CSV writer here, the Rerun recorder in [`crate::inspect::run`], the
//! progress bar and the pacing of the command line). Observers only read: the physics never
//! depends on them (argmin's `Observe`).

use std::fmt;
use std::path::{Path, PathBuf};

use serde::Serialize;

use super::system::{BodySample, WheelsetSample};

/// One output sample of one wheelset.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    pub t: f64,
    /// Arc length of the wheelset, m.
    pub s: f64,
    pub speed: f64,
    pub y: f64,
    pub yaw: f64,
    /// Centre height minus r0, m.
    pub z: f64,
    pub roll: f64,
    /// Normal forces left, right, N.
    pub normal: [f64; 2],
    /// Creep forces (contact frame) left, right: Fx, Fy, N.
    pub creep_x: [f64; 2],
    pub creep_y: [f64; 2],
    /// Lateral (Y) and vertical (Q) wheel–rail force on each wheel, track frame, N.
    pub y_force: [f64; 2],
    pub q_force: [f64; 2],
    /// Contact on the real wheel and rail (paper convention), m.
    pub s_wheel: [f64; 2],
    pub s_rail: [f64; 2],
    /// Contact positions (Y, Z) in the wheelset-track frame, m.
    pub position: [(f64, f64); 2],
    /// KEC: knife-edge contact parameters, m.
    pub s_knife: Option<[f64; 2]>,
    pub rails: [f64; 4],
    /// Each wheel's gap to its rail (0 on the rail; a lifted wheel's lift), m.
    pub lift: [f64; 2],
    /// Lateral shift of the track under the wheelset (0 on a rigid track), m.
    pub track_shift: f64,
}

impl Sample {
    /// The output sample of one wheelset evaluation (Y and Q per wheel in the track frame).
    pub fn new(t: f64, s: &WheelsetSample, r0: f64) -> Sample {
        let d = &s.dynamics;
        let y_force = [d.wheel_force[0].0, d.wheel_force[1].0];
        let q_force = [d.wheel_force[0].1, d.wheel_force[1].1];
        Sample {
            t,
            s: s.s,
            speed: s.speed,
            y: s.state.y,
            yaw: s.state.psi,
            z: s.kin.z - r0,
            roll: s.kin.phi,
            normal: d.normal,
            creep_x: [d.creep[0].fx, d.creep[1].fx],
            creep_y: [d.creep[0].fy, d.creep[1].fy],
            y_force,
            q_force,
            s_wheel: [s.kin.contacts[0].s_wheel, s.kin.contacts[1].s_wheel],
            s_rail: [s.kin.contacts[0].s_rail, s.kin.contacts[1].s_rail],
            position: [s.kin.contacts[0].position, s.kin.contacts[1].position],
            s_knife: s.kin.s_knife,
            rails: s.rails,
            lift: d.lift_gap,
            track_shift: s.state.track_shift,
        }
    }

    /// The larger |Y/Q| of the two wheels (a lifted wheel, Q = 0, has none).
    pub fn max_abs_y_over_q(&self) -> f64 {
        let ratio = |i: usize| {
            if self.q_force[i] > 0.0 {
                (self.y_force[i] / self.q_force[i]).abs()
            } else {
                0.0
            }
        };
        ratio(0).max(ratio(1))
    }
}

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
    /// style ([`super::safety`]); None where the run was not given the basis of the limits.
    pub safety: Option<super::safety::Safety>,
    /// Physically doubtful input the run went on with (the scenario's warnings).
    pub warnings: Vec<String>,
}

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

/// An observer's failure (a file that cannot be written, a recording that cannot be logged): it
/// ends the run, keeping what was recorded.
pub type ObserverError = Box<dyn std::error::Error + Send + Sync>;

/// What a run tells its observers before the first sample.
#[derive(Debug, Clone)]
pub struct RunStart<'a> {
    pub wheelsets: &'a [String],
    pub bodies: &'a [String],
    /// Simulated time the run is to cover, s.
    pub duration_s: f64,
}

/// One output time: every wheelset's and body's sample (in the order of [`RunStart`]).
#[derive(Debug, Clone, Copy)]
pub struct OutputSample<'a> {
    pub t: f64,
    pub wheelsets: &'a [Sample],
    pub bodies: &'a [BodySample],
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

/// The CSV columns of a wheelset (`--csv DIR` writes `DIR/NAME.csv`; a documented interface).
pub const CSV_COLUMNS: [&str; 28] = [
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
];

/// One CSV row of a sample (the [`CSV_COLUMNS`], SI converted to the columns' units).
pub fn csv_row(s: &Sample) -> [f64; 28] {
    [
        s.t,
        s.s,
        s.speed,
        s.y * 1e3,
        s.yaw * 1e3,
        s.z * 1e3,
        s.roll * 1e3,
        s.normal[0],
        s.normal[1],
        s.creep_x[0],
        s.creep_y[0],
        s.creep_x[1],
        s.creep_y[1],
        s.y_force[0],
        s.q_force[0],
        s.y_force[1],
        s.q_force[1],
        s.s_wheel[0] * 1e3,
        s.s_rail[0] * 1e3,
        s.s_wheel[1] * 1e3,
        s.s_rail[1] * 1e3,
        s.rails[0] * 1e3,
        s.rails[1] * 1e3,
        s.rails[2] * 1e3,
        s.rails[3] * 1e3,
        s.lift[0] * 1e3,
        s.lift[1] * 1e3,
        s.track_shift * 1e3,
    ]
}

fn write_row(w: &mut csv::Writer<std::fs::File>, s: &Sample) -> Result<(), csv::Error> {
    w.write_record(csv_row(s).iter().map(|x| format!("{x:.9e}")))
}

/// Writes one CSV per wheelset into a directory as the samples come (`DIR/NAME.csv`, the
/// [`CSV_COLUMNS`]); the files are created at the start (a directory that cannot be written fails
/// before any work), and what was written is kept if the run stops or fails.
pub struct CsvWriter {
    writers: Vec<(PathBuf, csv::Writer<std::fs::File>)>,
}

impl CsvWriter {
    /// Creates `dir` and a CSV with its header for each wheelset.
    pub fn create(dir: &Path, wheelsets: &[String]) -> Result<CsvWriter, csv::Error> {
        std::fs::create_dir_all(dir)?;
        let writers = wheelsets
            .iter()
            .map(|name| {
                let path = dir.join(format!("{name}.csv"));
                let mut w = csv::Writer::from_path(&path)?;
                w.write_record(CSV_COLUMNS)?;
                Ok((path, w))
            })
            .collect::<Result<Vec<_>, csv::Error>>()?;
        Ok(CsvWriter { writers })
    }

    /// The files written.
    pub fn paths(&self) -> Vec<PathBuf> {
        self.writers.iter().map(|(p, _)| p.clone()).collect()
    }
}

impl RunObserver for CsvWriter {
    fn sample(&mut self, sample: &OutputSample<'_>) -> Result<(), ObserverError> {
        for ((path, w), s) in self.writers.iter_mut().zip(sample.wheelsets) {
            write_row(w, s).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        }
        Ok(())
    }

    fn finish(&mut self, _summary: &RunSummary) -> Result<(), ObserverError> {
        for (path, w) in &mut self.writers {
            w.flush()
                .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        }
        Ok(())
    }
}

#[cfg(test)]
impl Sample {
    /// A centred wheelset at time `t`, arc length `s` and speed `speed`, every other field zero
    /// (for tests that build their own samples).
    pub(crate) fn at(t: f64, s: f64, speed: f64) -> Sample {
        Sample {
            t,
            s,
            speed,
            y: 0.0,
            yaw: 0.0,
            z: 0.0,
            roll: 0.0,
            normal: [0.0; 2],
            creep_x: [0.0; 2],
            creep_y: [0.0; 2],
            y_force: [0.0; 2],
            q_force: [0.0; 2],
            s_wheel: [0.0; 2],
            s_rail: [0.0; 2],
            position: [(0.0, 0.0); 2],
            s_knife: None,
            rails: [0.0; 4],
            lift: [0.0; 2],
            track_shift: 0.0,
        }
    }

    /// A sample whose every field has a value of its own.
    pub(crate) fn distinct() -> Sample {
        Sample {
            t: 1.5,
            s: 23.25,
            speed: 19.0,
            y: 0.002,
            yaw: -0.0015,
            z: 0.0007,
            roll: 0.0003,
            normal: [48e3, 52e3],
            creep_x: [-1.5e3, 2.5e3],
            creep_y: [3.5e3, -4.5e3],
            y_force: [6e3, -8e3],
            q_force: [40e3, 50e3],
            s_wheel: [0.004, -0.005],
            s_rail: [0.006, -0.007],
            position: [(0.75, 0.01), (-0.74, 0.02)],
            s_knife: Some([0.0085, -0.0095]),
            rails: [0.75, 0.001, -0.75, 0.002],
            lift: [0.0, 0.0125],
            track_shift: 0.0005,
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
        const PINNED: [&str; 28] = [
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
        ];
        let header: Vec<&str> = CSV_COLUMNS.iter().copied().collect();
        assert_eq!(header, PINNED);
    }

    /// Each CSV column's value of a sample, in the column's unit (pinned with the header).
    #[test]
    fn csv_row_is_pinned() {
        let row = csv_row(&Sample::distinct());
        let pinned = [
            1.5, 23.25, 19.0, 2.0, -1.5, 0.7, 0.3, 48e3, 52e3, -1.5e3, 3.5e3, 2.5e3, -4.5e3, 6e3, 40e3, -8e3,
            50e3, 4.0, 6.0, -5.0, -7.0, 750.0, 1.0, -750.0, 2.0, 0.0, 12.5, 0.5,
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
