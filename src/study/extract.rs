//! What a study keeps of each run: named figures of the run summary (EN 14363 style running
//! safety, largest displacements, derailment) and statistics of any wheelset CSV column.
//!
//! | extract | value |
//! |---|---|
//! | `max_abs_y_mm`, `max_abs_yaw_mrad` | largest \|y\|, \|ψ\| of any wheelset |
//! | `max_y_over_q` | largest 2 m sliding mean of Y/Q of any wheel (EN 14363; the instantaneous largest where the run has no safety basis) |
//! | `max_sum_y_kn`, `max_sum_y_over_prudhomme` | largest 2 m mean of ΣY, and its ratio to Prud'homme's limit |
//! | `max_delta_q_over_q0` | largest wheel unloading (Q₀ − Q)/Q₀ |
//! | `min_normal_kn`, `max_lift_mm` | smallest normal force, largest wheel lift |
//! | `critical_speed_m_s` | a speed ramp's hunting onset or extinction (empty where none) |
//! | `derailed` | 1 where the run ended in a derailment, else 0 |
//! | `simulated_s` | how far the run got |
//! | `max_wear_mg_per_km`, `max_tgamma_2m_n` | the most worn wheel's wear per km (USFD function, `crate::dynamics::wear`) and the largest 2 m mean of a wheel's wear number Tγ |
//! | `max_p0_mpa`, `max_ratchetting_share` | the largest maximum Hertz pressure of a wheel, and the largest share of a wheel's distance in surface ratchetting on the shakedown map (`crate::dynamics::contact_stress`) |
//! | `max_n_mv`, `max_wz_y`, `max_wz_z`, `max_cc_y_m_s2`, `max_cc_z_m_s2` | ride comfort at the carbodies' floor points ([`crate::dynamics::ride`]): the largest EN 12299 N_MV (empty for a run shorter than 5 s or without carbodies), Sperling's Wz lateral and vertical, the largest continuous comfort Cc_y, Cc_z |
//! | `curving_resistance_n`, `max_speed_deviation_percent` | the largest curving resistance of the track's circular curves (the traction less what accelerated the vehicle, where the whole vehicle was in the curve; empty without one) and the vehicle's largest deviation from the reference speed (`crate::dynamics::resistance`) |
//! | `linear_max_real_1_s`, `linear_hunting_hz`, `linear_damping_ratio` | the least-damped oscillatory mode (above 0.2 Hz) of the vehicle linearised at its undisturbed initial state — centred on ideal track at the case's speed ([`crate::dynamics::linear`]): Re λ (> 0: unstable), its frequency and damping ratio |
//! | `F(W.COLUMN)` | F of a wheelset CSV column (`y_mm`, `yaw_mrad`, `q_left_n`, … see `kecsim run --csv`); F = `max`, `min`, `maxabs`, `mean`, `rms` or `amplitude`; W a wheelset or `*` (the largest over the wheelsets, the smallest for `min`) |
//!
//! `amplitude` is half the peak-to-peak range over the run's last quarter (in time): the hunting
//! amplitude of a limit cycle, ~0 where the motion has decayed.

use crate::dynamics::linear::LinearStability;
use crate::dynamics::output::{csv_row, CSV_COLUMNS};
use crate::dynamics::run::RunOutput;
use crate::dynamics::sample::Sample;

/// A figure of the run summary.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Named {
    MaxAbsY,
    MaxAbsYaw,
    MaxYOverQ,
    MaxSumY,
    MaxSumYOverPrudhomme,
    MaxDeltaQOverQ0,
    MinNormal,
    MaxLift,
    CriticalSpeed,
    Derailed,
    Simulated,
    LinearMaxReal,
    LinearHz,
    LinearDamping,
    MaxWear,
    MaxTgamma2m,
    MaxP0,
    MaxShareRatchetting,
    MaxNmv,
    MaxWzY,
    MaxWzZ,
    MaxCcY,
    MaxCcZ,
    CurvingResistance,
    MaxSpeedDeviation,
}

const NAMED: [(&str, Named); 25] = [
    ("max_abs_y_mm", Named::MaxAbsY),
    ("max_abs_yaw_mrad", Named::MaxAbsYaw),
    ("max_y_over_q", Named::MaxYOverQ),
    ("max_sum_y_kn", Named::MaxSumY),
    ("max_sum_y_over_prudhomme", Named::MaxSumYOverPrudhomme),
    ("max_delta_q_over_q0", Named::MaxDeltaQOverQ0),
    ("min_normal_kn", Named::MinNormal),
    ("max_lift_mm", Named::MaxLift),
    ("critical_speed_m_s", Named::CriticalSpeed),
    ("derailed", Named::Derailed),
    ("simulated_s", Named::Simulated),
    ("linear_max_real_1_s", Named::LinearMaxReal),
    ("linear_hunting_hz", Named::LinearHz),
    ("linear_damping_ratio", Named::LinearDamping),
    ("max_wear_mg_per_km", Named::MaxWear),
    ("max_tgamma_2m_n", Named::MaxTgamma2m),
    ("max_p0_mpa", Named::MaxP0),
    ("max_ratchetting_share", Named::MaxShareRatchetting),
    ("max_n_mv", Named::MaxNmv),
    ("max_wz_y", Named::MaxWzY),
    ("max_wz_z", Named::MaxWzZ),
    ("max_cc_y_m_s2", Named::MaxCcY),
    ("max_cc_z_m_s2", Named::MaxCcZ),
    ("curving_resistance_n", Named::CurvingResistance),
    ("max_speed_deviation_percent", Named::MaxSpeedDeviation),
];

/// A statistic of a sampled signal.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stat {
    Max,
    Min,
    MaxAbs,
    Mean,
    Rms,
    Amplitude,
}

const STATS: [(&str, Stat); 6] = [
    ("max", Stat::Max),
    ("min", Stat::Min),
    ("maxabs", Stat::MaxAbs),
    ("mean", Stat::Mean),
    ("rms", Stat::Rms),
    ("amplitude", Stat::Amplitude),
];

/// One extract (its text is its column in the results table).
#[derive(Debug, Clone, PartialEq)]
pub enum Extract {
    Named(Named),
    Stat {
        stat: Stat,
        /// None: every wheelset (`*`).
        wheelset: Option<String>,
        /// Index into [`CSV_COLUMNS`].
        column: usize,
    },
}

impl Extract {
    /// Parses `max_y_over_q` or `rms(w1.y_mm)`; the error lists what is known.
    pub fn parse(text: &str) -> Result<Extract, String> {
        let t = text.trim();
        if let Some((_, n)) = NAMED.iter().find(|(name, _)| *name == t) {
            return Ok(Extract::Named(*n));
        }
        let bad = || {
            format!(
                "extract `{text}`: expected one of {} or F(WHEELSET.COLUMN) with F one of {} (WHEELSET a name or *; COLUMN a `kecsim run --csv` column)",
                NAMED.map(|n| n.0).join(", "),
                STATS.map(|s| s.0).join(", ")
            )
        };
        let (f, rest) = t.split_once('(').ok_or_else(bad)?;
        let inner = rest.strip_suffix(')').ok_or_else(bad)?;
        let stat = STATS.iter().find(|(n, _)| *n == f.trim()).ok_or_else(bad)?.1;
        let (w, c) = inner.split_once('.').ok_or_else(bad)?;
        let (w, c) = (w.trim(), c.trim());
        let column = CSV_COLUMNS.iter().position(|&k| k == c).ok_or_else(|| {
            format!(
                "extract `{text}`: no CSV column `{c}` (the columns: {})",
                CSV_COLUMNS.join(", ")
            )
        })?;
        if w.is_empty() {
            return Err(bad());
        }
        Ok(Extract::Stat {
            stat,
            wheelset: (w != "*").then(|| w.to_string()),
            column,
        })
    }

    /// Its column name in the results table.
    pub fn name(&self) -> String {
        match self {
            Extract::Named(n) => NAMED
                .iter()
                .find(|(_, m)| m == n)
                .map_or("?", |p| p.0)
                .to_string(),
            Extract::Stat {
                stat,
                wheelset,
                column,
            } => format!(
                "{}({}.{})",
                STATS.iter().find(|(_, s)| s == stat).map_or("?", |p| p.0),
                wheelset.as_deref().unwrap_or("*"),
                CSV_COLUMNS[*column]
            ),
        }
    }

    /// Checks the wheelset it names against a vehicle's.
    pub fn check(&self, wheelsets: &[String]) -> Result<(), String> {
        match self {
            Extract::Stat {
                wheelset: Some(w), ..
            } if !wheelsets.contains(w) => Err(format!(
                "extract `{}`: the vehicle has no wheelset `{w}` (it has {})",
                self.name(),
                wheelsets.join(", ")
            )),
            _ => Ok(()),
        }
    }

    /// Whether it needs the linearised vehicle ([`LinearStability`]).
    pub fn needs_linear(&self) -> bool {
        matches!(
            self,
            Extract::Named(Named::LinearMaxReal | Named::LinearHz | Named::LinearDamping)
        )
    }

    /// Its value for a run (None where the run gives none: no samples, no critical speed, no
    /// oscillatory mode); `linear`: the vehicle's linear stability where it was computed.
    pub fn value(&self, out: &RunOutput, linear: Option<&LinearStability>) -> Option<f64> {
        let s = &out.summary;
        let safety = s.safety.as_ref().filter(|x| !x.wheelsets.is_empty());
        let largest = |f: &dyn Fn(&crate::dynamics::safety::WheelsetSafety) -> f64| {
            safety.map(|x| x.wheelsets.iter().map(f).fold(f64::NEG_INFINITY, f64::max))
        };
        let any = s.samples > 0;
        match self {
            Extract::Named(n) => match n {
                Named::MaxAbsY => any.then_some(s.max_abs_y_mm),
                Named::MaxAbsYaw => any.then_some(s.max_abs_yaw_mrad),
                Named::MaxYOverQ => largest(&|w| w.y_over_q_2m).or(any.then_some(s.max_abs_y_over_q)),
                Named::MaxSumY => largest(&|w| w.sum_y_2m_n * 1e-3),
                Named::MaxSumYOverPrudhomme => largest(&|w| w.sum_y_2m_n / w.prudhomme_limit_n),
                Named::MaxDeltaQOverQ0 => largest(&|w| w.delta_q_over_q0),
                Named::MinNormal => any.then_some(s.min_normal_n * 1e-3),
                Named::MaxLift => Some(s.max_lift_mm),
                Named::CriticalSpeed => s.critical_speed_m_s,
                Named::Derailed => Some(if s.outcome == "derailed" { 1.0 } else { 0.0 }),
                Named::Simulated => Some(s.simulated_s),
                Named::LinearMaxReal => linear.map(|l| l.max_real_1_s),
                Named::LinearHz => linear.map(|l| l.frequency_hz),
                Named::LinearDamping => linear.map(|l| l.damping_ratio),
                Named::MaxWear => s.wear.as_ref().map(|w| w.max_mass_mg_per_km),
                Named::MaxTgamma2m => s
                    .wear
                    .as_ref()
                    .map(|w| w.wheels.iter().map(|x| x.max_tgamma_2m_n).fold(0.0, f64::max)),
                Named::MaxP0 => s.contact_stress.as_ref().map(|c| c.max_p0_mpa),
                Named::MaxShareRatchetting => s.contact_stress.as_ref().map(|c| c.max_share_ratchetting),
                Named::MaxNmv => s.comfort.as_ref().and_then(|c| c.max_n_mv),
                Named::MaxWzY => s.comfort.as_ref().map(|c| c.max_wz_y),
                Named::MaxWzZ => s.comfort.as_ref().map(|c| c.max_wz_z),
                Named::MaxCcY => s
                    .comfort
                    .as_ref()
                    .and_then(|c| c.points.iter().filter_map(|p| p.cc_y_max_m_s2).reduce(f64::max)),
                Named::MaxCcZ => s
                    .comfort
                    .as_ref()
                    .and_then(|c| c.points.iter().filter_map(|p| p.cc_z_max_m_s2).reduce(f64::max)),
                Named::CurvingResistance => s
                    .traction
                    .as_ref()
                    .and_then(|t| t.curves.iter().map(|c| c.resistance_n).reduce(f64::max)),
                Named::MaxSpeedDeviation => s.traction.as_ref().map(|t| t.max_speed_deviation_percent),
            },
            Extract::Stat {
                stat,
                wheelset,
                column,
            } => {
                let values = out
                    .wheelsets
                    .iter()
                    .filter(|(name, _)| wheelset.as_ref().is_none_or(|w| w == name))
                    .filter_map(|(_, samples)| statistic(*stat, samples, *column));
                if *stat == Stat::Min {
                    values.reduce(f64::min)
                } else {
                    values.reduce(f64::max)
                }
            }
        }
    }
}

/// `stat` of one CSV column over a wheelset's samples (None without samples).
pub fn statistic(stat: Stat, samples: &[Sample], column: usize) -> Option<f64> {
    let (first, last) = (samples.first()?, samples.last()?);
    let from = match stat {
        Stat::Amplitude => first.t + 0.75 * (last.t - first.t),
        _ => f64::NEG_INFINITY,
    };
    let v: Vec<f64> = samples
        .iter()
        .filter(|s| s.t >= from)
        .map(|s| csv_row(s)[column])
        .collect();
    let n = v.len() as f64;
    Some(match stat {
        Stat::Max => v.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        Stat::Min => v.iter().copied().fold(f64::INFINITY, f64::min),
        Stat::MaxAbs => v.iter().map(|x| x.abs()).fold(0.0, f64::max),
        Stat::Mean => v.iter().sum::<f64>() / n,
        Stat::Rms => (v.iter().map(|x| x * x).sum::<f64>() / n).sqrt(),
        Stat::Amplitude => {
            let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
            0.5 * (hi - lo)
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn samples(f: impl Fn(f64) -> f64) -> Vec<Sample> {
        (0..=400)
            .map(|k| {
                let t = k as f64 * 0.01;
                Sample {
                    y: f(t),
                    ..Sample::at(t, 0.0, 0.0)
                }
            })
            .collect()
    }

    #[test]
    fn statistics_of_a_sine_match_their_closed_forms() {
        // y = 2 mm sin(2π 5 t) over 4 s (20 whole periods, sampled at 100 Hz).
        let s = samples(|t| 2e-3 * (2.0 * std::f64::consts::PI * 5.0 * t).sin());
        let col = CSV_COLUMNS.iter().position(|&c| c == "y_mm").unwrap();
        let get = |stat| statistic(stat, &s, col).unwrap();
        // 401 samples over 20 whole periods: Σ sin² = 200 (the last sample is 0).
        let rms = 2.0 * (200.0f64 / 401.0).sqrt();
        assert!(
            (get(Stat::Rms) - rms).abs() < 1e-12,
            "{} vs {rms}",
            get(Stat::Rms)
        );
        assert!(get(Stat::Mean).abs() < 1e-9);
        assert!((get(Stat::MaxAbs) - 2.0).abs() < 1e-9);
        assert!((get(Stat::Max) - 2.0).abs() < 1e-9 && (get(Stat::Min) + 2.0).abs() < 1e-9);
        assert!((get(Stat::Amplitude) - 2.0).abs() < 1e-9);
        // A decayed motion: the amplitude is the last quarter's, not the largest.
        let d = samples(|t| 4e-3 * (-2.0 * t).exp() * (2.0 * std::f64::consts::PI * 5.0 * t).sin());
        let a = statistic(Stat::Amplitude, &d, col).unwrap();
        assert!(
            a < 4.0 * (-6.0f64).exp() + 1e-9 && a > 0.5 * 4.0 * (-8.0f64).exp(),
            "{a}"
        );
    }

    #[test]
    fn extracts_parse_and_name_themselves() {
        for text in [
            "max_y_over_q",
            "rms(w1.y_mm)",
            "amplitude(*.yaw_mrad)",
            "min(front.q_left_n)",
            "curving_resistance_n",
            "max_speed_deviation_percent",
            "mean(*.traction_n)",
        ] {
            assert_eq!(Extract::parse(text).unwrap().name(), text);
        }
        for bad in ["max_y", "rms(w1)", "rms(w1.nope)", "avg(w1.y_mm)", "rms(.y_mm)"] {
            let e = Extract::parse(bad).unwrap_err();
            assert!(
                e.contains(bad.split('(').next().unwrap()) || e.contains("nope"),
                "{e}"
            );
        }
        let x = Extract::parse("rms(w9.y_mm)").unwrap();
        assert!(x.check(&["w1".into()]).unwrap_err().contains("no wheelset `w9`"));
    }
}
