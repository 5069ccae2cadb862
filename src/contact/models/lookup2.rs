//! `model = "lookup2"` and `model = "lookup2-paper"`: the contact lookup table under gauge
//! variation (paper §4.3); velocity terms by the directional differences of
//! [`crate::contact::model`].
//!
//! * **`lookup2`** (the default table model since issue 48): `gauge_entry = "per_wheel"` (default)
//!   reads each wheel from the centred table at its own offset from its own displaced rail, the
//!   wheelset's z and roll from the two wheels ([`crate::contact::per_wheel`]) — no gauge
//!   columns, the preprocessing of the 1-entry table; `gauge_entry = "columns"` interpolates
//!   across gauge columns built every `gv_step_m` (default 0.1 mm) up to ±`gv_max_m` (default
//!   10 mm), each column up to its own gauge's flange climb ([`LookupTable2::build`]).
//! * **`lookup2-paper`**: the paper's literal 2-entry table, columns every `gv_step_m` (default
//!   1 mm — the spacing the earlier releases used as `lookup2`) interpolated across gv.
//!
//! Both take the two-point transitions of every column as for `lookup` (`two_point_approach_m`,
//! default 0; `two_point_max_width_m`, default 5e-5 m), and `cross_level_entry` as for `lookup`
//! (`"rotated"`, default, or `"paper"`). `kecsim kec --accuracy` measures each against the online
//! constraints under gauge variation and cross level.

use std::sync::Arc;

use serde::Deserialize;

use super::{check_range, ContactBuildError, ContactModelSettings};
use crate::contact::cache::TableCache;
use crate::contact::geometry::ContactGeometry;
use crate::contact::lookup::{
    CrossLevelEntry, LookupTable1, LookupTable2, TableError, TableRow, TableSettings,
};
use crate::contact::model::{Configuration, ContactModel, ContactModelError, WarmStart};
use crate::contact::per_wheel::{contact_per_wheel, per_wheel_row};
use crate::profile::placement::WheelRailPair;
use crate::track::RailOffsets;

/// How a table under gauge variation is entered: `gauge_entry` of `lookup2`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GaugeEntry {
    /// Each wheel from the centred table at its own offset from its rail
    /// ([`crate::contact::per_wheel`]).
    #[default]
    PerWheel,
    /// Gauge columns interpolated across gv ([`LookupTable2::lookup`]).
    Columns,
}

/// `[simulation.contact] model = "lookup2"`.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Lookup2Settings {
    /// How the gauge variation enters (default: per wheel).
    #[serde(default)]
    pub gauge_entry: GaugeEntry,
    /// Largest |gauge variation| tabulated (columns only), m.
    #[serde(default = "default_gv_max")]
    pub gv_max_m: f64,
    /// Gauge-variation step (columns only), m.
    #[serde(default = "default_gv_step_fine")]
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

/// `[simulation.contact] model = "lookup2-paper"`: the paper's literal 2-entry table.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Lookup2PaperSettings {
    /// Largest |gauge variation| tabulated, m.
    #[serde(default = "default_gv_max")]
    pub gv_max_m: f64,
    /// Gauge-variation step, m.
    #[serde(default = "default_gv_step")]
    pub gv_step_m: f64,
    /// See [`Lookup2Settings`].
    #[serde(default)]
    pub two_point_approach_m: f64,
    #[serde(default = "super::lookup::default_max_width")]
    pub two_point_max_width_m: f64,
    #[serde(default)]
    pub cross_level_entry: CrossLevelEntry,
}

fn default_gv_max() -> f64 {
    0.010
}
fn default_gv_step() -> f64 {
    0.001
}
fn default_gv_step_fine() -> f64 {
    0.0001
}

impl Default for Lookup2Settings {
    fn default() -> Self {
        Lookup2Settings {
            gauge_entry: GaugeEntry::default(),
            gv_max_m: default_gv_max(),
            gv_step_m: default_gv_step_fine(),
            two_point_approach_m: 0.0,
            two_point_max_width_m: super::lookup::default_max_width(),
            cross_level_entry: CrossLevelEntry::default(),
        }
    }
}

impl Default for Lookup2PaperSettings {
    fn default() -> Self {
        Lookup2PaperSettings {
            gv_max_m: default_gv_max(),
            gv_step_m: default_gv_step(),
            two_point_approach_m: 0.0,
            two_point_max_width_m: super::lookup::default_max_width(),
            cross_level_entry: CrossLevelEntry::default(),
        }
    }
}

/// The tabulated gauge variations −n Δ … n Δ, n = round(max / Δ), m.
pub fn gauge_variations(gv_max_m: f64, gv_step_m: f64) -> Vec<f64> {
    let n = (gv_max_m / gv_step_m).round() as i64;
    (-n..=n).map(|k| k as f64 * gv_step_m).collect()
}

/// The problems of either model's keys: the gauge columns' range and step, the two-point
/// transitions.
fn table_problems(gv_max_m: f64, gv_step_m: f64, approach_m: f64, width_m: f64) -> Vec<String> {
    let mut p = Vec::new();
    check_range(&mut p, "gv_max_m", gv_max_m, 1e-4, 0.03);
    check_range(&mut p, "gv_step_m", gv_step_m, 1e-5, 0.01);
    if p.is_empty() && gv_max_m / gv_step_m > 200.0 {
        p.push(format!(
            "simulation.contact: gv_max_m / gv_step_m = {:.0}: at most 200 columns each side",
            gv_max_m / gv_step_m
        ));
    }
    super::lookup::transition_problems(&mut p, approach_m, width_m);
    p
}

/// The gauge columns' table as a model.
fn build_columns(
    pair: &WheelRailPair,
    cache: Option<&TableCache>,
    gvs: &[f64],
    (approach, width): (f64, f64),
    entry: CrossLevelEntry,
) -> Result<Arc<dyn ContactModel>, ContactBuildError> {
    let geometry = ContactGeometry::with_defaults(pair.clone());
    // Each column up to its own gauge's flange climb.
    let settings = TableSettings::default();
    let table = match cache {
        Some(c) => c.table2(&geometry, gvs, &settings)?.0,
        None => LookupTable2::build(&geometry, gvs, &settings)?,
    }
    .with_two_point_transition(approach, width);
    Ok(Arc::new(Lookup2Contact {
        table: GaugeTable::Columns(table),
        entry,
    }))
}

impl Lookup2Settings {
    /// The tabulated gauge variations of `gauge_entry = "columns"`, m.
    pub fn gauge_variations(&self) -> Vec<f64> {
        gauge_variations(self.gv_max_m, self.gv_step_m)
    }
}

impl Lookup2PaperSettings {
    /// The tabulated gauge variations −n Δ … n Δ, m.
    pub fn gauge_variations(&self) -> Vec<f64> {
        gauge_variations(self.gv_max_m, self.gv_step_m)
    }
}

impl ContactModelSettings for Lookup2Settings {
    fn problems(&self) -> Vec<String> {
        table_problems(
            self.gv_max_m,
            self.gv_step_m,
            self.two_point_approach_m,
            self.two_point_max_width_m,
        )
    }

    fn build(
        &self,
        pair: &WheelRailPair,
        cache: Option<&TableCache>,
    ) -> Result<Arc<dyn ContactModel>, ContactBuildError> {
        let tp = (self.two_point_approach_m, self.two_point_max_width_m);
        match self.gauge_entry {
            GaugeEntry::Columns => {
                build_columns(pair, cache, &self.gauge_variations(), tp, self.cross_level_entry)
            }
            GaugeEntry::PerWheel => {
                let geometry = ContactGeometry::with_defaults(pair.clone());
                let table = super::table1(&geometry, cache)?.with_two_point_transition(tp.0, tp.1);
                Ok(Arc::new(Lookup2Contact {
                    table: GaugeTable::PerWheel(table),
                    entry: self.cross_level_entry,
                }))
            }
        }
    }
}

impl ContactModelSettings for Lookup2PaperSettings {
    fn problems(&self) -> Vec<String> {
        table_problems(
            self.gv_max_m,
            self.gv_step_m,
            self.two_point_approach_m,
            self.two_point_max_width_m,
        )
    }

    fn build(
        &self,
        pair: &WheelRailPair,
        cache: Option<&TableCache>,
    ) -> Result<Arc<dyn ContactModel>, ContactBuildError> {
        build_columns(
            pair,
            cache,
            &self.gauge_variations(),
            (self.two_point_approach_m, self.two_point_max_width_m),
            self.cross_level_entry,
        )
    }
}

/// What a table under gauge variation holds.
#[derive(Debug, Clone)]
pub enum GaugeTable {
    /// The centred table, entered per wheel.
    PerWheel(LookupTable1),
    /// Gauge columns.
    Columns(LookupTable2),
}

impl GaugeTable {
    /// The contact at `y` on rails displaced by `rails`, entered under cross level by `entry`.
    pub fn contact_with(
        &self,
        y: f64,
        rails: &RailOffsets,
        entry: CrossLevelEntry,
    ) -> Result<TableRow, TableError> {
        match (self, entry) {
            (GaugeTable::Columns(t), e) => t.contact_with(y, rails, e),
            (GaugeTable::PerWheel(t), CrossLevelEntry::Rotated) => contact_per_wheel(t, y, rails),
            (GaugeTable::PerWheel(t), CrossLevelEntry::Paper) => {
                let (al, vp, gv, cl) = rails.combinations();
                Ok(per_wheel_row(t, y - al, gv)?.displaced(y, vp, cl / (2.0 * t.l_r)))
            }
        }
    }
}

/// The table under gauge variation as a contact model.
#[derive(Debug, Clone)]
pub struct Lookup2Contact {
    pub table: GaugeTable,
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
