//! The run's traction summary (`traction` in the JSON, two lines of the printed summary): what held
//! the speed ([`super::traction`]), what it took — traction, power, energy — and the **curving
//! resistance** in each circular curve of the track, R = F − M_e a: the traction less what
//! accelerated the vehicle (held: the traction; coasting: the deceleration's M_e a).

use super::sample::Sample;
use super::traction::{describe, DriveInfo};
use crate::track::sections::HorizontalKind;
use crate::track::Track;

/// What holds a run's speed, and what it took (`traction` in the JSON summary; the keys are a
/// documented interface).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct TractionSummary {
    /// `hold_speed`, `coast`, `force` or `tied` (the vehicle's tie to the track frame holds it).
    pub mode: &'static str,
    /// The speed loop's bandwidth (`hold_speed`), Hz.
    pub controller_hz: Option<f64>,
    /// The wheelsets the drive acts through (none: tied).
    pub driven_wheelsets: Vec<String>,
    /// The reference's speed at the start, m/s.
    pub reference_speed_m_s: f64,
    /// The vehicle's speed (its centre of mass's) over the run, m/s.
    pub mean_speed_m_s: f64,
    pub min_speed_m_s: f64,
    pub max_speed_m_s: f64,
    /// The largest |speed − reference| over the run, % of the reference.
    pub max_speed_deviation_percent: f64,
    /// The traction over the run (> 0 pushing forward), N.
    pub mean_traction_n: f64,
    pub min_traction_n: f64,
    pub max_traction_n: f64,
    /// The traction power at the wheels, kW.
    pub mean_power_kw: f64,
    pub max_power_kw: f64,
    /// ∫ P dt, kWh.
    pub energy_kwh: f64,
    /// The curving resistance in each circular curve: the mean traction while the whole vehicle
    /// (every wheelset) is in it.
    pub curves: Vec<CurveResistance>,
}

/// The traction a held speed takes through one circular curve of the track.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CurveResistance {
    /// The curve's extent, m.
    pub from_m: f64,
    pub to_m: f64,
    pub radius_m: f64,
    /// Where the whole vehicle was in it (the rearmost wheelset's s from, the front one's to), m.
    pub vehicle_in_from_m: f64,
    pub vehicle_in_to_m: f64,
    /// The mean traction there, N.
    pub mean_traction_n: f64,
    pub mean_power_kw: f64,
    /// The vehicle's mean speed there, m/s, and its acceleration (the slope of a straight line
    /// fitted to the speed), m/s².
    pub mean_speed_m_s: f64,
    pub acceleration_m_s2: f64,
    /// The curving resistance: the traction less what accelerated the vehicle, R = F − M_e a
    /// (held: the traction; coasting: −M_e a, the deceleration's), N, and per weight, N/kN.
    pub resistance_n: f64,
    pub resistance_n_per_kn: f64,
}

/// A circular curve of the track: from, to (m), radius (m).
pub type Curve = (f64, f64, f64);

/// The circular curves of `track` (none without one).
pub fn curves(track: Option<&Track>) -> Vec<Curve> {
    let Some(track) = track else {
        return Vec::new();
    };
    track
        .centreline
        .sections()
        .0
        .iter()
        .filter(|h| h.kind == HorizontalKind::Curve && h.curvature_1pm[0] != 0.0)
        .map(|h| (h.from_m, h.to_m, 1.0 / h.curvature_1pm[0].abs()))
        .collect()
}

/// The summary of a run's traction from its samples (every wheelset's, in time order; the
/// vehicle's traction is in each), the vehicle's drive and the track's circular curves.
pub fn assess(
    drive: DriveInfo,
    wheelsets: &[(String, Vec<Sample>)],
    curves: &[Curve],
) -> Option<TractionSummary> {
    let DriveInfo {
        mode,
        controller_hz,
        driven_wheelsets,
        weight_n,
        effective_mass_kg,
    } = drive;
    let n = wheelsets.iter().map(|w| w.1.len()).min()?;
    let first = &wheelsets.first()?.1;
    if n == 0 {
        return None;
    }
    let speed = |k: usize| first[k].vehicle_speed;
    let (mut min_v, mut max_v, mut sum_v, mut dev) = (f64::INFINITY, f64::NEG_INFINITY, 0.0, 0.0_f64);
    let (mut min_f, mut max_f, mut sum_f) = (f64::INFINITY, f64::NEG_INFINITY, 0.0);
    let (mut max_p, mut sum_p, mut energy) = (f64::NEG_INFINITY, 0.0, 0.0);
    for k in 0..n {
        let (v, s) = (speed(k), &first[k]);
        min_v = min_v.min(v);
        max_v = max_v.max(v);
        sum_v += v;
        if s.reference_speed > 0.0 {
            dev = dev.max((v - s.reference_speed).abs() / s.reference_speed);
        }
        min_f = min_f.min(s.traction);
        max_f = max_f.max(s.traction);
        sum_f += s.traction;
        max_p = max_p.max(s.traction_power);
        sum_p += s.traction_power;
        if k > 0 {
            energy += 0.5 * (s.traction_power + first[k - 1].traction_power) * (s.t - first[k - 1].t);
        }
    }
    let nf = n as f64;
    let curves = curves
        .iter()
        .filter_map(|&(from, to, radius)| {
            let inside: Vec<usize> = (0..n)
                .filter(|&k| wheelsets.iter().all(|w| (from..=to).contains(&w.1[k].s)))
                .collect();
            let (&a, &b) = (inside.first()?, inside.last()?);
            let m = inside.len() as f64;
            let traction = inside.iter().map(|&k| first[k].traction).sum::<f64>() / m;
            // The speed's slope: least squares over the samples inside.
            let t_mean = inside.iter().map(|&k| first[k].t).sum::<f64>() / m;
            let v_mean = inside.iter().map(|&k| speed(k)).sum::<f64>() / m;
            let (sxy, sxx) = inside.iter().fold((0.0, 0.0), |(sxy, sxx), &k| {
                let dt = first[k].t - t_mean;
                (sxy + dt * (speed(k) - v_mean), sxx + dt * dt)
            });
            let accel = if sxx > 0.0 { sxy / sxx } else { 0.0 };
            let resistance = traction - effective_mass_kg * accel;
            let rear = |k: usize| wheelsets.iter().map(|w| w.1[k].s).fold(f64::INFINITY, f64::min);
            let front = |k: usize| {
                wheelsets
                    .iter()
                    .map(|w| w.1[k].s)
                    .fold(f64::NEG_INFINITY, f64::max)
            };
            Some(CurveResistance {
                from_m: from,
                to_m: to,
                radius_m: radius,
                vehicle_in_from_m: rear(a),
                vehicle_in_to_m: front(b),
                mean_traction_n: traction,
                mean_power_kw: inside.iter().map(|&k| first[k].traction_power).sum::<f64>() / m * 1e-3,
                mean_speed_m_s: v_mean,
                acceleration_m_s2: accel,
                resistance_n: resistance,
                resistance_n_per_kn: if weight_n > 0.0 {
                    resistance / (weight_n * 1e-3)
                } else {
                    0.0
                },
            })
        })
        .collect();
    Some(TractionSummary {
        mode,
        controller_hz,
        driven_wheelsets,
        reference_speed_m_s: first[0].reference_speed,
        mean_speed_m_s: sum_v / nf,
        min_speed_m_s: min_v,
        max_speed_m_s: max_v,
        max_speed_deviation_percent: 100.0 * dev,
        mean_traction_n: sum_f / nf,
        min_traction_n: min_f,
        max_traction_n: max_f,
        mean_power_kw: sum_p / nf * 1e-3,
        max_power_kw: max_p * 1e-3,
        energy_kwh: energy / 3.6e6,
        curves,
    })
}

impl std::fmt::Display for TractionSummary {
    /// The lines `kecsim run` prints.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let how = describe(self.mode, self.controller_hz, &self.driven_wheelsets);
        writeln!(
            f,
            "traction ({how}): {:.3} kN mean, {:.3} .. {:.3} kN, {:.2} kW mean ({:.4} kWh); speed {:.3} .. {:.3} m/s, within {:.3} % of the reference {} m/s",
            self.mean_traction_n * 1e-3,
            self.min_traction_n * 1e-3,
            self.max_traction_n * 1e-3,
            self.mean_power_kw,
            self.energy_kwh,
            self.min_speed_m_s,
            self.max_speed_m_s,
            self.max_speed_deviation_percent,
            self.reference_speed_m_s
        )?;
        for c in &self.curves {
            writeln!(
                f,
                "  curve R {:.2} m (s {:.0}–{:.0} m; the whole vehicle in it over {:.0}–{:.0} m): curving resistance {:.3} kN = {:.3} N/kN of the weight (traction {:.3} kN, {:.2} kW; {:.3} m/s, accelerating {:.2} mm/s²)",
                c.radius_m,
                c.from_m,
                c.to_m,
                c.vehicle_in_from_m,
                c.vehicle_in_to_m,
                c.resistance_n * 1e-3,
                c.resistance_n_per_kn,
                c.mean_traction_n * 1e-3,
                c.mean_power_kw,
                c.mean_speed_m_s,
                c.acceleration_m_s2 * 1e3
            )?;
        }
        Ok(())
    }
}
