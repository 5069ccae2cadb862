//! `model = "online"`: the approximate contact constraints (paper §4.2, Eq. 35–42) solved at every
//! evaluation by Newton, warm-started from the evaluator's last solution and kept on the true
//! contact with [`ContactGeometry::solve_tracked`] (past a contact-point jump the old branch
//! survives as a local tangency with the profiles interpenetrating). The warm start makes the
//! result depend on the evaluation history near contact jumps: [`ContactModel::history_dependent`].
//! Velocity terms by the directional differences of [`crate::contact::model`]. No settings.
//!
//! The history dependence exists only where the profiles have a contact jump: the model builds the
//! pair's 1-entry table on the ideal track once (the preprocessing) and reports itself
//! history-dependent only if that table has a jump. A jump-free pair's solution is one smooth
//! function of the state, and the run keeps its Jacobian across steps as for the other models
//! (a fresh one every step made the online kilometre of the MS stand-in 8× costlier: 25 right-hand
//! sides per step, 22 of them the Jacobian's columns).

use std::sync::Arc;

use serde::Deserialize;

use super::{ContactBuildError, ContactModelSettings};
use crate::contact::cache::TableCache;
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

    fn build(
        &self,
        pair: &WheelRailPair,
        cache: Option<&TableCache>,
    ) -> Result<Arc<dyn ContactModel>, ContactBuildError> {
        let geometry = ContactGeometry::with_defaults(pair.clone());
        let jumps = !super::table1(&geometry, cache)?.jumps.is_empty();
        Ok(Arc::new(OnlineContact { geometry, jumps }))
    }
}

/// The online constraints as a contact model.
#[derive(Debug, Clone)]
pub struct OnlineContact {
    pub geometry: ContactGeometry,
    /// Whether the pair has a contact jump on the ideal track (then the tracked solve depends on
    /// the evaluation history near it).
    pub jumps: bool,
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
        self.jumps
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
