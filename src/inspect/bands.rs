//! The running bands: where along each rail head the wheels touched, over the track.
//!
//! | entity | archetype | what |
//! |---|---|---|
//! | `run/bands/left/K`, `run/bands/right/K` | Points2D, static | every wheel's contact on that rail, (s, −s^r) in (m, 0.1 mm): the track coordinate against the contact's position on the rail head (paper convention; drawn upward, in tenths of a millimetre so that a kilometre and a 40 mm rail head fit one view), coloured by the normal force ([`force_color`]) |
//!
//! Each batch of the recorder is a static entity `K` of its own (K counts the batches), so the
//! view of `run/bands/SIDE` shows the band as it has grown, whatever the time cursor: a band on a
//! rail is its history. A contact that jumps (tread to flange, two-point contact) shows as a jump
//! of s^r at one s. The band on each wheel over time is the `s_wheel_mm` series of each
//! wheelset.

use rerun::{Color, Points2D, Radius, RecordingStream};

use super::{log_static, InspectError};
use crate::dynamics::sample::Sample;

/// The band's vertical unit: tenths of a millimetre per metre of s^r.
pub const BAND_UNITS_PER_M: f64 = 1e4;

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
#[derive(Debug, Default)]
pub struct RunningBands {
    batches: usize,
}

impl RunningBands {
    /// Sends the contacts of `samples` (per wheelset) as the next batch of each rail's band.
    pub fn send(&mut self, rec: &RecordingStream, samples: &[Vec<Sample>]) -> Result<(), InspectError> {
        let n: usize = samples.iter().map(Vec::len).sum();
        if n == 0 {
            return Ok(());
        }
        for (wheel, side) in ["left", "right"].into_iter().enumerate() {
            let points = samples
                .iter()
                .flatten()
                .map(|s| [s.s as f32, (-s.s_rail[wheel] * BAND_UNITS_PER_M) as f32]);
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
