//! `model = "kec"`: the KEC constraints (Eq. 49–51) solved online on the knife-edge-equivalent
//! profiles, with analytic first and second derivatives (from [`KecSolution`]) for the velocity
//! terms, and the map back to the real contact points (Eq. 52).
//!
//! Settings: `two_point_approach_m` — the elastic approach δ over which a real contact jump becomes
//! a two-point transition ([`KecModel::with_two_point_transition`]; 0 keeps the paper's rigid
//! kinks); `two_point_max_width_m` — the largest width of a transition
//! ([`KecModel::with_two_point_transition_capped`]).

use std::sync::Arc;

use serde::Deserialize;

use super::{check_range, ContactBuildError, ContactModelSettings};
use crate::contact::cache::TableCache;
use crate::contact::geometry::ContactGeometry;
use crate::contact::kec::{KecModel, KecSolution};
use crate::contact::model::{Configuration, ContactModel, ContactModelError, WarmStart, WheelsetKinematics};
use crate::contact::point::ContactPoint;
use crate::profile::placement::WheelRailPair;
use crate::profile::Side;
use crate::track::{RailMotion, RailOffsets};

/// Default elastic approach of the two-point transition, m.
pub const DEFAULT_TWO_POINT_APPROACH_M: f64 = 5e-5;

/// `[simulation.contact] model = "kec"`.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KecSettings {
    /// The elastic approach δ of the two-point transitions at the contact jumps, m (0: rigid kinks).
    #[serde(default = "default_approach")]
    pub two_point_approach_m: f64,
    /// The largest width of a two-point transition in s^k, m (default 5e-5: wider fillets at jumps
    /// near the centre change the small-amplitude conicity).
    #[serde(default = "default_max_width")]
    pub two_point_max_width_m: f64,
}

fn default_max_width() -> f64 {
    crate::contact::kec::TWO_POINT_MAX_WIDTH_M
}

fn default_approach() -> f64 {
    DEFAULT_TWO_POINT_APPROACH_M
}

impl Default for KecSettings {
    fn default() -> Self {
        KecSettings {
            two_point_approach_m: DEFAULT_TWO_POINT_APPROACH_M,
            two_point_max_width_m: default_max_width(),
        }
    }
}

impl ContactModelSettings for KecSettings {
    fn problems(&self) -> Vec<String> {
        let mut p = Vec::new();
        check_range(
            &mut p,
            "two_point_approach_m",
            self.two_point_approach_m,
            0.0,
            1e-3,
        );
        check_range(
            &mut p,
            "two_point_max_width_m",
            self.two_point_max_width_m,
            0.0,
            2e-3,
        );
        p
    }

    fn build(
        &self,
        pair: &WheelRailPair,
        cache: Option<&TableCache>,
    ) -> Result<Arc<dyn ContactModel>, ContactBuildError> {
        Ok(Arc::new(self.kec_contact_cached(pair, cache)?))
    }
}

impl KecSettings {
    /// The model as its concrete type: the ideal-track 1-entry table of the real profiles, then
    /// the equivalent profiles (paper §6) with these settings' two-point transitions.
    pub fn kec_contact(&self, pair: &WheelRailPair) -> Result<KecContact, ContactBuildError> {
        self.kec_contact_cached(pair, None)
    }

    /// [`Self::kec_contact`] with the table from `cache` where given.
    pub fn kec_contact_cached(
        &self,
        pair: &WheelRailPair,
        cache: Option<&TableCache>,
    ) -> Result<KecContact, ContactBuildError> {
        let geometry = ContactGeometry::with_defaults(pair.clone());
        let table = super::table1(&geometry, cache)?;
        let model = KecModel::from_table(&table, pair.wheelset.l_w())?
            .with_two_point_transition_capped(self.two_point_approach_m, self.two_point_max_width_m);
        Ok(KecContact {
            model,
            pair: pair.clone(),
        })
    }
}

/// The KEC contact model of a wheelset.
#[derive(Debug, Clone)]
pub struct KecContact {
    pub model: KecModel,
    pub pair: WheelRailPair,
}

impl KecContact {
    fn solve(&self, y: f64, rails: [f64; 4], warm: &mut WarmStart) -> Result<KecSolution, ContactModelError> {
        let s = self.model.solve(y, rails, warm.get::<[f64; 4]>().copied())?;
        warm.set(s.x(self.model.r0));
        Ok(s)
    }

    /// The real contact points of a solution (Eq. 52): positions on the real wheel in the solved
    /// pose; the normals of the ideal track's contact turned with the rails by their roll
    /// δ = (z_lir − z_rir)/(2 L_r) (Eq. 11) — the contact angle by +δ on the left, −δ on the right.
    fn contacts(&self, sol: &KecSolution, rails: &[f64; 4]) -> [ContactPoint; 2] {
        let pair = &self.pair;
        let delta = RailOffsets::from_array(*rails).delta(pair.rail_placement.lateral_m);
        let c = |i: usize, side: Side| {
            let p = &sol.real[i];
            let contact_angle = p.contact_angle + side.sign() * delta;
            let (s, co) = contact_angle.sin_cos();
            ContactPoint {
                position: pair
                    .wheelset
                    .wheel_point(&pair.wheel, side, p.s_wheel, sol.y, sol.z, sol.phi),
                normal: (-side.sign() * s, co),
                contact_angle,
                rolling_radius: p.rolling_radius,
                wheel_curvature: p.wheel_curvature,
                rail_curvature: p.rail_curvature,
                s_wheel: p.s_wheel,
                s_rail: p.s_rail,
            }
        };
        [c(0, Side::Left), c(1, Side::Right)]
    }
}

impl ContactModel for KecContact {
    fn configuration(
        &self,
        y: f64,
        rails: &RailOffsets,
        warm: &mut WarmStart,
    ) -> Result<Configuration, ContactModelError> {
        let s = self.solve(y, rails.to_array(), warm)?;
        Ok(Configuration {
            z: s.z,
            phi: s.phi,
            z_y: s.dx_dq[0][0],
            phi_y: s.dx_dq[1][0],
            contacts: self.contacts(&s, &rails.to_array()),
        })
    }

    /// Eq. (49)–(51) and their exact derivatives with respect to q = [y, y_lir, z_lir, y_rir,
    /// z_rir]: ż = Σ z_q q̇, c_z = Σ z_q q̈_r + Σ z_qq q̇ q̇ (the same for φ).
    fn kinematics(
        &self,
        y: f64,
        y_dot: f64,
        rails: &RailMotion,
        warm: &mut WarmStart,
    ) -> Result<WheelsetKinematics, ContactModelError> {
        let s = self.solve(y, rails.q, warm)?;
        let qd = [
            y_dot,
            rails.q_dot[0],
            rails.q_dot[1],
            rails.q_dot[2],
            rails.q_dot[3],
        ];
        let qdd_r = [
            0.0,
            rails.q_ddot[0],
            rails.q_ddot[1],
            rails.q_ddot[2],
            rails.q_ddot[3],
        ];
        let (mut z_dot, mut phi_dot, mut c_z, mut c_phi) = (0.0, 0.0, 0.0, 0.0);
        for i in 0..5 {
            z_dot += s.dx_dq[0][i] * qd[i];
            phi_dot += s.dx_dq[1][i] * qd[i];
            c_z += s.dx_dq[0][i] * qdd_r[i];
            c_phi += s.dx_dq[1][i] * qdd_r[i];
            for j in 0..5 {
                c_z += s.d2z_dq2[i][j] * qd[i] * qd[j];
                c_phi += s.d2phi_dq2[i][j] * qd[i] * qd[j];
            }
        }
        Ok(WheelsetKinematics {
            z: s.z,
            phi: s.phi,
            z_y: s.dx_dq[0][0],
            phi_y: s.dx_dq[1][0],
            z_dot,
            phi_dot,
            c_z,
            c_phi,
            contacts: self.contacts(&s, &rails.q),
            s_knife: Some(s.s_k),
        })
    }
}
