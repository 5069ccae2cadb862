//! `model = "elastic"`: the wheelset free in all its coordinates, a normal force at every region
//! where the real profiles interpenetrate (Hertz: N = K δ^{3/2}, K from the local curvatures and the
//! material; Hunt–Crossley damping, N = K δ^{3/2} (1 + χ δ̇)), found by the search of
//! `crate::contact::elastic`. Two-point contact and wheel lift come from the profiles themselves:
//! the independent reference for the constraint models' hard cases (issue 14). Not in the paper.
//!
//! Its [`ContactModel::configuration`] is the rigid touching configuration of the online
//! constraints (the static settling and the initial state start there, lowered by the static
//! Hertz approach).
//!
//! **Damping χ** (default 2 s/m): with the static approach δ₀ the contact's linearised stiffness is
//! 1.5 N/δ₀ and its damping χ N, so the vertical mode of a wheelset of mass m on its two contacts
//! has the damping ratio ζ = χ N / (2 √(1.5 N m / δ₀)) per wheel load N; for the MS tram's IRW
//! (N ≈ 31 kN, δ₀ ≈ 0.08 mm, m/2 ≈ 350 kg) χ = 2 s/m gives ζ ≈ 0.07 — a lightly damped 200 Hz
//! mode, as steel on steel. The coefficient of restitution of an impact at closing speed v is then
//! ≈ 1 − (2/3) χ v (Hunt–Crossley): 0.87 at 0.1 m/s.

use std::sync::Arc;

use serde::Deserialize;

use super::{ContactBuildError, ContactModelSettings};
use crate::contact::cache::TableCache;
use crate::contact::elastic::ElasticContact;
use crate::contact::geometry::ContactGeometry;
use crate::contact::model::{Configuration, ContactModel, ContactModelError, WarmStart};
use crate::profile::placement::WheelRailPair;
use crate::profile::Side;
use crate::track::RailOffsets;

/// The smallest flange angle a wheel profile must reach for the elastic model, degrees.
pub const MIN_FLANGE_ANGLE_DEG: f64 = 45.0;

/// `[simulation.contact] model = "elastic"`.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ElasticSettings {
    /// Hunt–Crossley normal damping χ, s/m (N = K δ^{3/2} (1 + χ δ̇)); must be > 0.
    #[serde(default = "default_damping")]
    pub damping_s_per_m: f64,
    /// Sampling step of the wheel profile in the contact search, m.
    #[serde(default = "default_scan_step")]
    pub scan_step_m: f64,
}

fn default_damping() -> f64 {
    2.0
}

fn default_scan_step() -> f64 {
    2.5e-4
}

impl Default for ElasticSettings {
    fn default() -> Self {
        ElasticSettings {
            damping_s_per_m: default_damping(),
            scan_step_m: default_scan_step(),
        }
    }
}

impl ContactModelSettings for ElasticSettings {
    fn problems(&self) -> Vec<String> {
        let mut p = Vec::new();
        if !(self.damping_s_per_m.is_finite() && self.damping_s_per_m > 0.0 && self.damping_s_per_m <= 100.0)
        {
            p.push(format!(
                "simulation.contact.damping_s_per_m = {}: the contact damping must be positive (at most 100 s/m)",
                self.damping_s_per_m
            ));
        }
        super::check_range(&mut p, "scan_step_m", self.scan_step_m, 1e-5, 1e-3);
        p
    }

    /// Also refuses a wheel profile whose flange is too shallow (its steepest contact angle below
    /// [`MIN_FLANGE_ANGLE_DEG`]; a profile without a flange at all is refused when it is read):
    /// the search would take that slope for the flange's largest angle and call every contact
    /// there a climb.
    fn build(
        &self,
        pair: &WheelRailPair,
        _cache: Option<&TableCache>,
    ) -> Result<Arc<dyn ContactModel>, ContactBuildError> {
        let search = ElasticContact::new(
            ContactGeometry::with_defaults(pair.clone()),
            self.scan_step_m,
            self.damping_s_per_m,
        );
        for side in Side::BOTH {
            let angle = search.flange_limit(side).1.to_degrees();
            if angle < MIN_FLANGE_ANGLE_DEG {
                return Err(ContactBuildError::Invalid(vec![format!(
                    "the wheel profile's flange is too shallow to guide the wheelset: its steepest contact angle on the {} wheel is {angle:.1}° (a flange reaches 60–75°; the elastic model needs at least {MIN_FLANGE_ANGLE_DEG}° to tell flange contact from a climb)",
                    side.name()
                )]));
            }
        }
        Ok(Arc::new(ElasticModel { search }))
    }
}

/// The elastic model: its search, and the rigid configuration for the settling.
#[derive(Debug, Clone)]
pub struct ElasticModel {
    pub search: ElasticContact,
}

impl ContactModel for ElasticModel {
    fn configuration(
        &self,
        y: f64,
        rails: &RailOffsets,
        warm: &mut WarmStart,
    ) -> Result<Configuration, ContactModelError> {
        super::online::tracked_configuration(&self.search.geometry, y, rails, warm)
    }

    fn elastic(&self) -> Option<&ElasticContact> {
        Some(&self.search)
    }
}
