//! The running bands: where along each rail head the wheels touched, over the track.
//!
//! | entity | archetype | what |
//! |---|---|---|
//! | `run/bands/{left,right}/axes`, `…/tick_labels` | LineStrips2D, Points2D, static | the axes: the track in metres at round ticks over the run's distance from its first sample, s^r at −20, 0, 20 mm (both rails' views span the same track) |
//! | `run/bands/left/K`, `run/bands/right/K` | Points2D, static | every wheel's contact on that rail, (s/u, −s^r): the track coordinate in units of u metres against the contact's position on the rail head in mm (paper convention; drawn upward), coloured by the normal force ([`force_color`]) |
//!
//! A 2D view keeps its axes' scales equal, so the track's unit u is chosen for the run's length
//! ([`RunningBands::unit_for`]: 1, 2 or 5 × a power of ten metres, ~200 units over the run) that the
//! band of a ~40 mm rail head reads at about 5:1.
//!
//! Each batch of the recorder is a static entity `K` of its own (K counts the batches), so the
//! view of `run/bands/SIDE` shows the band as it has grown, whatever the time cursor: a band on a
//! rail is its history. A contact that jumps (tread to flange, two-point contact) shows as a jump
//! of s^r at one s. The band on each wheel over time is the `s_wheel_mm` series of each
//! wheelset.

use rerun::{Color, Points2D, Radius, RecordingStream};

use super::{log_static, InspectError};
use crate::dynamics::sample::Sample;

/// The normal force at which the colour scale ends, N.
pub const FORCE_SCALE_MAX_N: f64 = 100e3;

/// A colour for a normal force: dark blue (0) through green and yellow to red
/// ([`FORCE_SCALE_MAX_N`] and above); grey for a wheel off its rail (N = 0).
pub fn force_color(normal_n: f64) -> Color {
    if normal_n <= 0.0 {
        return Color::from_rgb(130, 130, 130);
    }
    let u = (normal_n / FORCE_SCALE_MAX_N).clamp(0.0, 1.0);
    // Piecewise linear through (0: 40, 60, 200), (1/3: 40, 180, 120), (2/3: 240, 210, 50),
    // (1: 220, 50, 40).
    const STOPS: [[f64; 3]; 4] = [
        [40.0, 60.0, 200.0],
        [40.0, 180.0, 120.0],
        [240.0, 210.0, 50.0],
        [220.0, 50.0, 40.0],
    ];
    let x = u * 3.0;
    let k = (x.floor() as usize).min(2);
    let f = x - k as f64;
    let c = |i: usize| (STOPS[k][i] + f * (STOPS[k + 1][i] - STOPS[k][i])).round() as u8;
    Color::from_rgb(c(0), c(1), c(2))
}

/// The running bands' batches.
#[derive(Debug)]
pub struct RunningBands {
    batches: usize,
    /// The track coordinate's unit u, m.
    unit_m: f64,
    /// The distance the run is to cover, m (the axes' length; 0: none drawn).
    distance_m: f64,
}

impl RunningBands {
    /// Bands whose track coordinate is in units of `unit_m` metres.
    pub fn new(unit_m: f64) -> RunningBands {
        RunningBands {
            batches: 0,
            unit_m,
            distance_m: 0.0,
        }
    }

    /// [`Self::new`], with axes over `distance_m` from the first sample on: the track in metres
    /// at round ticks, s^r at −20, 0, 20 mm; both rails' views then span the same track.
    pub fn with_axes(unit_m: f64, distance_m: f64) -> RunningBands {
        RunningBands {
            distance_m,
            ..RunningBands::new(unit_m)
        }
    }

    /// The axes of both bands from the track coordinate `s0` (m) over the run's distance and
    /// the wheelsets' `spread` (m: the front one's lead on the rearmost).
    fn log_axes(&self, rec: &RecordingStream, s0: f64, spread: f64) -> Result<(), InspectError> {
        let s1 = s0 + self.distance_m + spread.max(0.0);
        let x = |s: f64| (s / self.unit_m) as f32;
        // Below the band (s^r up to ±45 mm on a rail head, drawn −s^r).
        let base = 50.0f32;
        let ticks = super::xyplot::ticks(s0, s1);
        let mut lines = vec![
            vec![[x(s0), base], [x(s1), base]],
            vec![[x(s0), -45.0], [x(s0), base]],
        ];
        let mut at = Vec::new();
        let mut labels = Vec::new();
        for &s in &ticks {
            lines.push(vec![[x(s), base], [x(s), base + 4.0]]);
            at.push([x(s), base + 10.0]);
            labels.push(format!("{} m", super::xyplot::short(s).trim_end_matches(".0")));
        }
        for sr in [-20.0f32, 0.0, 20.0] {
            lines.push(vec![[x(s0) - 2.0, -sr], [x(s0), -sr]]);
            at.push([x(s0) - 9.0, -sr]);
            labels.push(format!("{sr:+.0} mm"));
        }
        let grey = Color::from_rgb(150, 150, 150);
        for side in ["left", "right"] {
            log_static(
                rec,
                &format!("run/bands/{side}/axes"),
                &rerun::LineStrips2D::new(lines.clone())
                    .with_colors([grey])
                    .with_radii([Radius::new_ui_points(1.0)]),
            )?;
            log_static(
                rec,
                &format!("run/bands/{side}/tick_labels"),
                &Points2D::new(at.clone())
                    .with_labels(labels.clone())
                    .with_colors([grey])
                    .with_radii([Radius::new_ui_points(0.5)])
                    .with_show_labels(true),
            )?;
        }
        Ok(())
    }

    /// The track coordinate's unit for a run over `distance_m`: 1, 2 or 5 × 10^k m, the one
    /// nearest (in ratio) to distance/200, at least 1 m.
    pub fn unit_for(distance_m: f64) -> f64 {
        let target = (distance_m / 200.0).max(1.0);
        let decade = 10f64.powf(target.log10().floor());
        [1.0, 2.0, 5.0, 10.0]
            .into_iter()
            .map(|m| m * decade)
            .min_by(|a, b| (a / target).ln().abs().total_cmp(&(b / target).ln().abs()))
            .unwrap_or(1.0)
    }

    /// The view's title for the `side` rail ("left", "right").
    pub fn title(side: &str, unit_m: f64) -> String {
        let unit = if unit_m == 1.0 {
            "m".to_string()
        } else {
            format!("× {unit_m} m")
        };
        format!(
            "Running band, {side} rail: s^r [mm, up] along the track [{unit}]; colour: normal force 0 (blue) to {:.0} kN (red)",
            FORCE_SCALE_MAX_N * 1e-3
        )
    }

    /// Sends the contacts of `samples` (per wheelset) as the next batch of each rail's band.
    pub fn send(&mut self, rec: &RecordingStream, samples: &[Vec<Sample>]) -> Result<(), InspectError> {
        let n: usize = samples.iter().map(Vec::len).sum();
        if n == 0 {
            return Ok(());
        }
        if self.batches == 0 && self.distance_m > 0.0 {
            // From the rearmost wheelset's first sample to the front one's last.
            let (s0, front) = samples
                .iter()
                .flatten()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), s| {
                    (a.min(s.s), b.max(s.s))
                });
            if s0.is_finite() {
                self.log_axes(rec, s0, front - s0)?;
            }
        }
        for (wheel, side) in ["left", "right"].into_iter().enumerate() {
            let points = samples
                .iter()
                .flatten()
                .map(|s| [(s.s / self.unit_m) as f32, (-s.s_rail[wheel] * 1e3) as f32]);
            let colors = samples.iter().flatten().map(|s| force_color(s.normal[wheel]));
            log_static(
                rec,
                &format!("run/bands/{side}/{}", self.batches),
                &Points2D::new(points)
                    .with_colors(colors)
                    .with_radii(std::iter::repeat_n(Radius::new_ui_points(1.5), n)),
            )?;
        }
        self.batches += 1;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The track's unit for a run's length.
    #[test]
    fn the_band_unit_follows_the_run_length() {
        assert_eq!(RunningBands::unit_for(10.0), 1.0);
        assert_eq!(RunningBands::unit_for(276.0), 1.0);
        assert_eq!(RunningBands::unit_for(400.0), 2.0);
        assert_eq!(RunningBands::unit_for(969.0), 5.0);
        assert_eq!(RunningBands::unit_for(4000.0), 20.0);
        assert_eq!(RunningBands::unit_for(1.5e4), 100.0);
    }

    /// The colour scale's ends and its middle, and grey for a lifted wheel.
    #[test]
    fn force_colors_run_from_blue_to_red() {
        assert_eq!(force_color(0.0), Color::from_rgb(130, 130, 130));
        assert_eq!(force_color(1e-9), Color::from_rgb(40, 60, 200));
        assert_eq!(
            force_color(FORCE_SCALE_MAX_N / 3.0),
            Color::from_rgb(40, 180, 120)
        );
        assert_eq!(force_color(FORCE_SCALE_MAX_N), Color::from_rgb(220, 50, 40));
        assert_eq!(force_color(5.0 * FORCE_SCALE_MAX_N), Color::from_rgb(220, 50, 40));
        assert_eq!(
            force_color(0.5 * FORCE_SCALE_MAX_N),
            Color::from_rgb(140, 195, 85)
        );
    }
}
