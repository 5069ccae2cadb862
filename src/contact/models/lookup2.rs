//! `model = "lookup2"`: the 2-entry contact lookup table over (y, gauge variation) (paper §4.3),
//! one 1-entry table per gauge variation, each over y up to its own gauge's flange climb
//! ([`LookupTable2::build`]); velocity terms by the directional differences of
//! [`crate::contact::model`].
//!
//! Settings: `gv_max_m` (the gauge variations −max … +max, default 0.010 m), `gv_step_m`
//! (default 0.001 m), the two-point transitions of every column as for `lookup`
//! (`two_point_approach_m`, default 0; `two_point_max_width_m`, default 5e-5 m), and
//! `cross_level_entry` as for `lookup` (`"rotated"`, default, or `"paper"`).

use std::sync::Arc;

use serde::Deserialize;

use super::{check_range, ContactBuildError, ContactModelSettings};
use crate::contact::cache::TableCache;
use crate::contact::geometry::ContactGeometry;
use crate::contact::lookup::{CrossLevelEntry, LookupTable2, TableSettings};
use crate::contact::model::{Configuration, ContactModel, ContactModelError, WarmStart};
use crate::profile::placement::WheelRailPair;
use crate::track::RailOffsets;

/// `[simulation.contact] model = "lookup2"`.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Lookup2Settings {
    /// Largest |gauge variation| tabulated, m.
    #[serde(default = "default_gv_max")]
    pub gv_max_m: f64,
    /// Gauge-variation step, m.
    #[serde(default = "default_gv_step")]
    pub gv_step_m: f64,
    /// The two-point transitions of each column (see [`super::lookup::LookupSettings`]), m.
    #[serde(default)]
    pub two_point_approach_m: f64,
    #[serde(default = "super::lookup::default_max_width")]
    pub two_point_max_width_m: f64,
    /// How the table is entered under cross level (see [`super::lookup::LookupSettings`]).
    #[serde(default)]
    pub cross_level_entry: CrossLevelEntry,
}

fn default_gv_max() -> f64 {
    0.010
}
fn default_gv_step() -> f64 {
    0.001
}

impl Default for Lookup2Settings {
    fn default() -> Self {
        Lookup2Settings {
            gv_max_m: default_gv_max(),
            gv_step_m: default_gv_step(),
            two_point_approach_m: 0.0,
            two_point_max_width_m: super::lookup::default_max_width(),
            cross_level_entry: CrossLevelEntry::default(),
        }
    }
}

impl Lookup2Settings {
    /// The tabulated gauge variations −n Δ … n Δ, n = round(max / Δ), m.
    pub fn gauge_variations(&self) -> Vec<f64> {
        let n = (self.gv_max_m / self.gv_step_m).round() as i64;
        (-n..=n).map(|k| k as f64 * self.gv_step_m).collect()
    }
}

impl ContactModelSettings for Lookup2Settings {
    fn problems(&self) -> Vec<String> {
        let mut p = Vec::new();
        check_range(&mut p, "gv_max_m", self.gv_max_m, 1e-4, 0.03);
        check_range(&mut p, "gv_step_m", self.gv_step_m, 1e-5, 0.01);
        super::lookup::transition_problems(&mut p, self.two_point_approach_m, self.two_point_max_width_m);
        if p.is_empty() && self.gv_max_m / self.gv_step_m > 200.0 {
            p.push(format!(
                "simulation.contact: gv_max_m / gv_step_m = {:.0}: at most 200 columns each side",
                self.gv_max_m / self.gv_step_m
            ));
        }
        p
    }

    fn build(
        &self,
        pair: &WheelRailPair,
        cache: Option<&TableCache>,
    ) -> Result<Arc<dyn ContactModel>, ContactBuildError> {
        let geometry = ContactGeometry::with_defaults(pair.clone());
        // Each column up to its own gauge's flange climb.
        let (gvs, settings) = (self.gauge_variations(), TableSettings::default());
        let table = match cache {
            Some(c) => c.table2(&geometry, &gvs, &settings)?.0,
            None => LookupTable2::build(&geometry, &gvs, &settings)?,
        }
        .with_two_point_transition(self.two_point_approach_m, self.two_point_max_width_m);
        Ok(Arc::new(Lookup2Contact {
            table,
            entry: self.cross_level_entry,
        }))
    }
}

/// The 2-entry table as a contact model.
#[derive(Debug, Clone)]
pub struct Lookup2Contact {
    pub table: LookupTable2,
    /// The entry under cross level.
    pub entry: CrossLevelEntry,
}

impl ContactModel for Lookup2Contact {
    fn configuration(
        &self,
        y: f64,
        rails: &RailOffsets,
        _warm: &mut WarmStart,
    ) -> Result<Configuration, ContactModelError> {
        Ok(super::lookup::configuration(
            &self.table.contact_with(y, rails, self.entry)?,
        ))
    }
}
