//! `model = "online"`: the approximate contact constraints (paper §4.2, Eq. 35–42) solved at every
//! evaluation by Newton, warm-started from the evaluator's last solution and kept on the true
//! contact with [`ContactGeometry::solve_tracked`] (past a contact-point jump the old branch
//! survives as a local tangency with the profiles interpenetrating). The warm start makes the
//! result depend on the evaluation history near contact jumps: [`ContactModel::history_dependent`].
//! Velocity terms by the directional differences of [`crate::contact::model`]. No settings.

use std::sync::Arc;

use serde::Deserialize;

use super::{ContactBuildError, ContactModelSettings};
use crate::contact::geometry::{ContactGeometry, ContactSolution};
use crate::contact::model::{Configuration, ContactModel, ContactModelError, WarmStart};
use crate::profile::placement::WheelRailPair;
use crate::track::RailOffsets;

/// `[simulation.contact] model = "online"` (no keys).
#[derive(Debug, Clone, PartialEq, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OnlineSettings {}

impl ContactModelSettings for OnlineSettings {
    fn problems(&self) -> Vec<String> {
        Vec::new()
    }

    fn build(&self, pair: &WheelRailPair) -> Result<Arc<dyn ContactModel>, ContactBuildError> {
        Ok(Arc::new(OnlineContact {
            geometry: ContactGeometry::with_defaults(pair.clone()),
        }))
    }
}

/// The online constraints as a contact model.
#[derive(Debug, Clone)]
pub struct OnlineContact {
    pub geometry: ContactGeometry,
}

impl ContactModel for OnlineContact {
    fn configuration(
        &self,
        y: f64,
        rails: &RailOffsets,
        warm: &mut WarmStart,
    ) -> Result<Configuration, ContactModelError> {
        tracked_configuration(&self.geometry, y, rails, warm)
    }

    fn history_dependent(&self) -> bool {
        true
    }
}

/// The online constraints' configuration, warm-started from the evaluator's last solution and
/// kept on its branch ([`ContactGeometry::solve_tracked`]); cold, the full solve.
pub(super) fn tracked_configuration(
    geometry: &ContactGeometry,
    y: f64,
    rails: &RailOffsets,
    warm: &mut WarmStart,
) -> Result<Configuration, ContactModelError> {
    let sol = match warm.get::<ContactSolution>() {
        Some(prev) => geometry.solve_tracked(y, rails, prev)?,
        None => geometry.solve(y, rails)?,
    };
    let out = Configuration {
        z: sol.z,
        phi: sol.phi,
        z_y: sol.dx_dy[0],
        phi_y: sol.dx_dy[1],
        contacts: [sol.left, sol.right],
    };
    warm.set(sol);
    Ok(out)
}
