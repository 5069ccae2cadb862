//! The strip model inside the dynamics (`[contact_forces] patches = "dynamics"`): at each
//! right-hand side, a wheel whose contact is outside Hertz's validity gets the strip model's
//! patch (its equivalent ellipse: same area and width) instead of Hertz's ellipse, at the guessed
//! normal force, for the creep forces; the passes of the normal-force iteration scale it as Hertz's
//! (a, b ∝ N^⅓). The rigid contact point, its normal and the constraint forces stay the contact
//! model's. Costs ~0.1 ms a contact outside Hertz (`kecsim bench patch`).

use super::gap::{GapInput, GapSection, GAP_WINDOW_M};
use super::strips::{self, StripSettings};
use super::validity::{hertz_deviation, HERTZ_VALIDITY_LIMIT};
use crate::contact::ContactPoint;
use crate::profile::placement::WheelRailPair;
use crate::track::Side;

/// How the patches of a scene are modelled (`[contact_forces] patches`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PatchesMode {
    /// Hertz in the dynamics; the run's p0, area and wear from the strip model where Hertz does
    /// not hold, recomputed from the samples (the default).
    #[default]
    Post,
    /// The strip model in the dynamics too (the creep forces on its patch) where Hertz does not
    /// hold; and in the samples.
    Dynamics,
    /// Hertz everywhere (the run reports how much of it was outside Hertz's validity all the
    /// same).
    Hertz,
}

/// The profiles the dynamics' strip patches are made from.
#[derive(Debug, Clone)]
pub struct DynamicPatches {
    pub pair: WheelRailPair,
    pub strips: StripSettings,
}

impl DynamicPatches {
    pub fn new(pair: WheelRailPair) -> Self {
        DynamicPatches {
            pair,
            strips: StripSettings::default(),
        }
    }

    /// The equivalent ellipse (a, b, m) of wheel `side`'s patch(es) at `point` under normal force
    /// `normal` (N), or None where Hertz (lateral semi-axis `hertz_b`) holds or the strip model
    /// finds nothing (Hertz's then).
    pub fn ellipse(
        &self,
        side: Side,
        point: &ContactPoint,
        hertz_b: f64,
        normal: f64,
        e_star: f64,
    ) -> Option<(f64, f64)> {
        let (w, r) = (&self.pair.wheel, &self.pair.rail);
        if hertz_deviation(w, r, side, point.s_wheel, point.s_rail, hertz_b) <= HERTZ_VALIDITY_LIMIT {
            return None;
        }
        let input = GapInput {
            side,
            s_wheel: point.s_wheel,
            s_rail: point.s_rail,
            nominal_radius: self.pair.wheelset.nominal_radius_m,
            rail_angle: side.sign() * self.pair.inclination.angle_rad,
            approach_angle: GapInput::along_normal(r, side, point.s_rail),
            half_window: GAP_WINDOW_M,
        };
        let sec = GapSection::new(w, r, &input).ok()?;
        let patches = strips::solve(&sec, normal, e_star, &self.strips).ok()?;
        // Several patches: one ellipse of their total area and their summed widths.
        let area: f64 = patches.iter().map(|p| p.area).sum();
        let width: f64 = patches.iter().map(|p| p.width).sum();
        (area > 0.0 && width > 0.0).then(|| {
            let b = 0.5 * width;
            (area / (std::f64::consts::PI * b), b)
        })
    }
}
