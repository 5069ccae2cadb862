//! `model = "lookup"`: the 1-entry contact lookup table over y (paper §4.3, Eq. 43–46), built
//! from the online constraints on the ideal track up to flange contact; the irregularities enter
//! by Eq. (44)–(46) — by default rederived as the rail pair's rigid motion — the gauge variation
//! not at all. Velocity terms by the directional differences of [`crate::contact::model`].
//!
//! Settings: `two_point_approach_m` (default 0: the paper's rigid jumps) and
//! `two_point_max_width_m` (default 5e-5 m): the table's two-point transitions
//! ([`LookupTable1::with_two_point_transition`]), the same departure as KEC's;
//! `cross_level_entry`: `"rotated"` (default: the wheelset's pose taken into the turned rails'
//! frame, [`crate::contact::lookup::enter_rotated`]) or `"paper"` (Eq. 44–46 as printed:
//! ȳ = y − al, z = z_clu + vp, φ = φ_clu + cl/(2 L_r), 1.2 mm of z error at cl = 5 mm on
//! S1002/54E1).

use std::sync::Arc;

use serde::Deserialize;

use super::{check_range, ContactBuildError, ContactModelSettings};
use crate::contact::cache::TableCache;
use crate::contact::geometry::ContactGeometry;
use crate::contact::lookup::{CrossLevelEntry, LookupTable1, TableRow};
use crate::contact::model::{Configuration, ContactModel, ContactModelError, WarmStart};
use crate::contact::point::ContactPoint;
use crate::profile::placement::WheelRailPair;
use crate::profile::Side;
use crate::track::RailOffsets;

/// `[simulation.contact] model = "lookup"`.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LookupSettings {
    /// The elastic approach δ of the two-point transitions at the table's jumps, m (0: rigid).
    #[serde(default)]
    pub two_point_approach_m: f64,
    /// The largest width of a two-point transition, m.
    #[serde(default = "default_max_width")]
    pub two_point_max_width_m: f64,
    /// How the table is entered under cross level: `"rotated"` (default) or `"paper"`.
    #[serde(default)]
    pub cross_level_entry: CrossLevelEntry,
}

pub(super) fn default_max_width() -> f64 {
    crate::contact::kec::TWO_POINT_MAX_WIDTH_M
}

impl Default for LookupSettings {
    fn default() -> Self {
        LookupSettings {
            two_point_approach_m: 0.0,
            two_point_max_width_m: default_max_width(),
            cross_level_entry: CrossLevelEntry::default(),
        }
    }
}

/// The checks of the two-point keys (shared with the 2-entry table).
pub(super) fn transition_problems(p: &mut Vec<String>, approach: f64, width: f64) {
    check_range(p, "two_point_approach_m", approach, 0.0, 1e-3);
    check_range(p, "two_point_max_width_m", width, 0.0, 2e-3);
}

impl ContactModelSettings for LookupSettings {
    fn problems(&self) -> Vec<String> {
        let mut p = Vec::new();
        transition_problems(&mut p, self.two_point_approach_m, self.two_point_max_width_m);
        p
    }

    fn build(
        &self,
        pair: &WheelRailPair,
        cache: Option<&TableCache>,
    ) -> Result<Arc<dyn ContactModel>, ContactBuildError> {
        let geometry = ContactGeometry::with_defaults(pair.clone());
        let table = super::table1(&geometry, cache)?
            .with_two_point_transition(self.two_point_approach_m, self.two_point_max_width_m);
        Ok(Arc::new(LookupContact {
            table,
            entry: self.cross_level_entry,
        }))
    }
}

/// The 1-entry table as a contact model.
#[derive(Debug, Clone)]
pub struct LookupContact {
    pub table: LookupTable1,
    /// The entry under cross level.
    pub entry: CrossLevelEntry,
}

impl ContactModel for LookupContact {
    fn configuration(
        &self,
        y: f64,
        rails: &RailOffsets,
        _warm: &mut WarmStart,
    ) -> Result<Configuration, ContactModelError> {
        Ok(configuration(&self.table.contact_with(y, rails, self.entry)?))
    }
}

/// A table row as a configuration (shared with the 2-entry table): the row's contact points,
/// normals at the row's contact angles.
pub(super) fn configuration(row: &TableRow) -> Configuration {
    let c = |i: usize, side: Side| {
        let (s, co) = row.contact_angle[i].sin_cos();
        ContactPoint {
            position: (row.position[2 * i], row.position[2 * i + 1]),
            normal: (-side.sign() * s, co),
            contact_angle: row.contact_angle[i],
            rolling_radius: row.rolling_radius[i],
            wheel_curvature: row.curvature[2 * i],
            rail_curvature: row.curvature[2 * i + 1],
            s_wheel: row.x[2 + 2 * i],
            s_rail: row.x[3 + 2 * i],
        }
    };
    Configuration {
        z: row.z(),
        phi: row.phi(),
        z_y: row.dx_dy[0],
        phi_y: row.dx_dy[1],
        contacts: [c(0, Side::Left), c(1, Side::Right)],
    }
}
