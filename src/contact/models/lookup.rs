//! `model = "lookup"`: the 1-entry contact lookup table over y (paper §4.3, Eq. 43–46), built
//! from the online constraints on the ideal track up to flange contact; the irregularities enter
//! by Eq. (44)–(46), the gauge variation not at all. Velocity terms by the directional
//! differences of [`crate::contact::model`]. No settings.

use std::sync::Arc;

use serde::Deserialize;

use super::{ContactBuildError, ContactModelSettings};
use crate::contact::geometry::ContactGeometry;
use crate::contact::lookup::{LookupTable1, TableRow, TableSettings};
use crate::contact::model::{Configuration, ContactModel, ContactModelError, WarmStart};
use crate::contact::point::ContactPoint;
use crate::profile::placement::WheelRailPair;
use crate::profile::Side;
use crate::track::RailOffsets;

/// `[simulation.contact] model = "lookup"` (no keys).
#[derive(Debug, Clone, PartialEq, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LookupSettings {}

impl ContactModelSettings for LookupSettings {
    fn problems(&self) -> Vec<String> {
        Vec::new()
    }

    fn build(&self, pair: &WheelRailPair) -> Result<Arc<dyn ContactModel>, ContactBuildError> {
        let geometry = ContactGeometry::with_defaults(pair.clone());
        let table = LookupTable1::build(&geometry, &TableSettings::default())?;
        Ok(Arc::new(LookupContact { table }))
    }
}

/// The 1-entry table as a contact model.
#[derive(Debug, Clone)]
pub struct LookupContact {
    pub table: LookupTable1,
}

impl ContactModel for LookupContact {
    fn configuration(
        &self,
        y: f64,
        rails: &RailOffsets,
        _warm: &mut WarmStart,
    ) -> Result<Configuration, ContactModelError> {
        Ok(configuration(&self.table.contact(y, rails)?))
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
