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
use crate::contact::kec::{KecModel, KecSolution, N_Q};
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

/// The last solution of an evaluator and its sensitivity: the start of the next solve is its
/// first-order prediction x₀ = x + (dx/dq)(q − q_last) (issue 52), the tangent of the solution
/// path the solve already computed for the equations of motion (Eq. 49–50: dx/dq = −J⁻¹ ∂F/∂q).
/// Between the RHS evaluations of a step and its neighbours q moves little, so Newton starts
/// within its quadratic range: fewer iterations than from the last x alone (measured on the
/// default kilometre in docs/performance.md, *The levers, measured*). Where the prediction lands
/// off a profile or fails, the solve's own fall-backs (the table guess) take over, as from any
/// start.
#[derive(Debug, Clone, Copy)]
struct KecWarm {
    q: [f64; N_Q],
    x: [f64; 4],
    dx_dq: [[f64; N_Q]; 4],
}

impl KecWarm {
    fn predict(&self, q: &[f64; N_Q]) -> [f64; 4] {
        let mut x = self.x;
        for (xi, row) in x.iter_mut().zip(&self.dx_dq) {
            for ((d, qa), qb) in row.iter().zip(q).zip(&self.q) {
                *xi += d * (qa - qb);
            }
        }
        x
    }
}

impl KecContact {
    fn solve(&self, y: f64, rails: [f64; 4], warm: &mut WarmStart) -> Result<KecSolution, ContactModelError> {
        let q = [y, rails[0], rails[1], rails[2], rails[3]];
        let start = warm.get::<KecWarm>().map(|w| w.predict(&q));
        let s = self.model.solve(y, rails, start)?;
        warm.set(KecWarm {
            q,
            x: s.x(self.model.r0),
            dx_dq: s.dx_dq,
        });
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::profile::StandardProfile;

    /// The first-order prediction of the next solve's start: from the tangent dx/dq of the last
    /// solution, a step of q as between two RHS evaluations (y by 20 µm, the rails by a few µm)
    /// starts Newton so close that it converges in fewer iterations than from the last x, to the
    /// same solution (against a cold solve from Eq. 51).
    #[test]
    fn the_tangent_prediction_starts_newton_closer_and_ends_at_the_same_solution() {
        let pair =
            WheelRailPair::standard(StandardProfile::S1002, StandardProfile::Rail60E1, "1:40").unwrap();
        let kec = KecSettings::default().kec_contact(&pair).unwrap();
        let r0 = kec.model.r0;
        let (mut with_tangent, mut with_last) = (0, 0);
        for k in 0..40 {
            let y0 = -4e-3 + 2e-4 * k as f64;
            let rails0 = [1e-6 * k as f64, -2e-6, 0.0, 3e-6];
            let (y1, rails1) = (y0 + 2e-5, [rails0[0] + 3e-6, rails0[1] - 1e-6, 2e-6, rails0[3]]);
            let mut warm = WarmStart::default();
            let first = kec.solve(y0, rails0, &mut warm).unwrap();
            let predicted = kec.solve(y1, rails1, &mut warm).unwrap();
            let from_last = kec.model.solve(y1, rails1, Some(first.x(r0))).unwrap();
            let cold = kec.model.solve(y1, rails1, None).unwrap();
            for (a, b) in predicted.x(r0).iter().zip(cold.x(r0)) {
                assert!((a - b).abs() < 1e-12, "y = {y1}: {a} vs {b}");
            }
            with_tangent += predicted.iterations;
            with_last += from_last.iterations;
        }
        println!("Newton iterations over 40 solves: {with_tangent} from the tangent's prediction, {with_last} from the last x");
        assert!(with_tangent < with_last, "{with_tangent} ≥ {with_last}");
    }
}
