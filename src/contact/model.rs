//! The contact model of a wheelset as the equations of motion see it (paper §5, coordinate
//! partitioning): given the independent lateral displacement y, its rate ẏ and the rail motion
//! q_r = [y_lir, z_lir, y_rir, z_rir] with its time derivatives (METHOD.md §2), the dependent
//! coordinates z and φ, their first and second time derivatives along the motion, and the real
//! contact points where the normal forces (Eq. 53) and the creep forces act.
//!
//! Every model — the online approximate constraints, the lookup tables, KEC, and whatever comes
//! next — implements [`ContactModel`]; the dynamics never knows which one it has. What a model must
//! implement:
//!
//! * [`ContactModel::configuration`]: z, φ, ∂z/∂y, ∂φ/∂y and the two real [`ContactPoint`]s at one
//!   lateral displacement on rails displaced by [`RailOffsets`];
//! * optionally [`ContactModel::kinematics`], when the model has analytic velocity terms (KEC:
//!   Eq. 49–51 with exact first and second derivatives); the default is the one
//!   finite-difference adaptor of this module, [`directional_differences`];
//! * optionally [`ContactModel::history_dependent`], when its result depends on the evaluation
//!   history through its warm start (the online solve near contact jumps);
//!
//! plus, in its own file under [`super::models`], its settings table and its constructor from the
//! wheel–rail pair, and one line in the list there.
//!
//! Each evaluator (a wheelset of the integrated system, the output's copy) keeps its own
//! [`WarmStart`]: the model itself is immutable and shared.

use std::any::Any;
use std::fmt::Debug;

use thiserror::Error;

use super::elastic::{ElasticContact, ElasticError};
use super::geometry::ContactError;
use super::kec::KecError;
use super::lookup::TableError;
use super::point::ContactPoint;
use crate::track::{RailMotion, RailOffsets};

/// A contact-model failure during the dynamics.
#[derive(Debug, Error)]
pub enum ContactModelError {
    #[error("KEC: {0}")]
    Kec(#[from] KecError),
    #[error("lookup table: {0}")]
    Table(#[from] TableError),
    #[error("online contact: {0}")]
    Online(#[from] ContactError),
    #[error("elastic contact: {0}")]
    Elastic(#[from] ElasticError),
    /// A model outside this crate's own.
    #[error("{0}")]
    Other(Box<dyn std::error::Error + Send + Sync>),
}

impl ContactModelError {
    /// Whether the wheelset has left the model's range beyond flange contact — the equivalent
    /// profiles and the tables end where the flange's contact angle is largest (past it the
    /// wheel climbs the flange): the wheel whose flange it is, `"left"` (the wheelset moved to
    /// +y) or `"right"`; the elastic model's contact past its flange's largest angle, or a wheel
    /// off its rail. `None` for any other failure (and for the online model, which has no
    /// such range).
    pub fn flange_climb(&self) -> Option<&'static str> {
        let side = |beyond_positive: bool| if beyond_positive { "left" } else { "right" };
        match self {
            ContactModelError::Kec(KecError::OffProfile { y_mm, .. }) => Some(side(*y_mm > 0.0)),
            ContactModelError::Table(TableError::OutOfRange {
                what: "y",
                value_mm,
                min_mm,
                max_mm,
            }) if *value_mm > *max_mm || *value_mm < *min_mm => Some(side(*value_mm > *max_mm)),
            ContactModelError::Table(TableError::BeyondFlangeLimit { y_mm, .. }) => Some(side(*y_mm > 0.0)),
            ContactModelError::Elastic(
                ElasticError::FlangeClimb { side, .. } | ElasticError::OffRail { side, .. },
            ) => Some(side),
            _ => None,
        }
    }
}

/// z, φ, their slopes in y and the real contact points at one configuration.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Configuration {
    /// Height of the wheelset centre above the top-of-rail plane z, m, and roll φ, rad.
    pub z: f64,
    pub phi: f64,
    /// ∂z/∂y, ∂φ/∂y.
    pub z_y: f64,
    pub phi_y: f64,
    /// Left, right.
    pub contacts: [ContactPoint; 2],
}

/// z, φ and their motion for one evaluation.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct WheelsetKinematics {
    /// Centre height z and roll φ.
    pub z: f64,
    pub phi: f64,
    /// ∂z/∂y, ∂φ/∂y.
    pub z_y: f64,
    pub phi_y: f64,
    /// ż, φ̇ along the motion.
    pub z_dot: f64,
    pub phi_dot: f64,
    /// Velocity-dependent parts: z̈ = z_y ÿ + c_z, φ̈ = φ_y ÿ + c_φ.
    pub c_z: f64,
    pub c_phi: f64,
    /// Left, right.
    pub contacts: [ContactPoint; 2],
    /// KEC only: the knife-edge contact parameters s^lk, s^rk on the equivalent profiles, m.
    pub s_knife: Option<[f64; 2]>,
}

/// The contact model of a wheelset (shared by all wheelsets with the same profiles; each
/// evaluator brings its own [`WarmStart`]).
pub trait ContactModel: Send + Sync + Debug {
    /// z, φ, ∂z/∂y, ∂φ/∂y and the real contact points at lateral displacement `y` on rails
    /// displaced by `rails`.
    fn configuration(
        &self,
        y: f64,
        rails: &RailOffsets,
        warm: &mut WarmStart,
    ) -> Result<Configuration, ContactModelError>;

    /// The kinematics at lateral displacement y with velocity ẏ, the rails moving as `rails`.
    /// Default: `directional_differences` of [`Self::configuration`].
    fn kinematics(
        &self,
        y: f64,
        y_dot: f64,
        rails: &RailMotion,
        warm: &mut WarmStart,
    ) -> Result<WheelsetKinematics, ContactModelError> {
        directional_differences(self, y, y_dot, rails, warm)
    }

    /// Whether the result depends on the history of evaluations through the warm start (then an
    /// integrator must not reuse a Jacobian across steps).
    fn history_dependent(&self) -> bool {
        false
    }

    /// The elastic model: the wheelset is free in z and φ and its contacts come from
    /// `ElasticContact::search` at its pose (then [`Self::configuration`] is the rigid touching
    /// configuration, for the static settling and the initial state). `None` for a constraint model.
    fn elastic(&self) -> Option<&ElasticContact> {
        None
    }
}

/// ż and the velocity-dependent part c_z of z̈ = Z_y ÿ + c_z (and the same for φ) from the
/// directional difference of the configuration along the motion: with
/// g(ε) = Z(y + ε ẏ, q_r(t + ε)) (the rails advanced to second order), ż = g'(0) and c_z = g''(0),
/// by central differences (three evaluations, each moving the wheelset ~10 µm). The stencil
/// depends on the state only, never on an earlier evaluation, so that the right-hand side is a
/// function the integrator's error control can trust. A departure from the paper (which
/// differentiates its tables), chosen so that every model shares one interface; the stencil's
/// evaluations start from a copy of the warm start, which keeps the centre's.
pub fn directional_differences<M: ContactModel + ?Sized>(
    model: &M,
    y: f64,
    y_dot: f64,
    rails: &RailMotion,
    warm: &mut WarmStart,
) -> Result<WheelsetKinematics, ContactModelError> {
    let c = model.configuration(y, &RailOffsets::from_array(rails.q), warm)?;
    // A time step ε over which the wheelset moves ~10 µm (bounded to [1e-6, 1e-2] s).
    let speed = y_dot.abs() + rails.q_dot.iter().map(|v| v.abs()).sum::<f64>();
    let eps = (1e-5 / speed.max(1e-9)).clamp(1e-6, 1e-2);
    let shift = |e: f64| {
        let mut q = rails.q;
        for ((qk, vk), ak) in q.iter_mut().zip(rails.q_dot).zip(rails.q_ddot) {
            *qk += vk * e + 0.5 * ak * e * e;
        }
        (y + y_dot * e, RailOffsets::from_array(q))
    };
    let mut w = warm.clone();
    let (yp, qp) = shift(eps);
    let p = model.configuration(yp, &qp, &mut w)?;
    let (ym, qm) = shift(-eps);
    let m = model.configuration(ym, &qm, &mut w)?;
    Ok(WheelsetKinematics {
        z: c.z,
        phi: c.phi,
        z_y: c.z_y,
        phi_y: c.phi_y,
        z_dot: (p.z - m.z) / (2.0 * eps),
        phi_dot: (p.phi - m.phi) / (2.0 * eps),
        c_z: (p.z - 2.0 * c.z + m.z) / (eps * eps),
        c_phi: (p.phi - 2.0 * c.phi + m.phi) / (eps * eps),
        contacts: c.contacts,
        s_knife: None,
    })
}

/// What a model keeps between evaluations of one evaluator (e.g. the last solution, to start
/// Newton from). Any `Clone` type is one.
pub trait WarmState: Any + Send + Sync + Debug {
    fn clone_box(&self) -> Box<dyn WarmState>;
    fn as_any(&self) -> &dyn Any;
    fn as_any_mut(&mut self) -> &mut dyn Any;
}

impl<T: Any + Clone + Send + Sync + Debug> WarmState for T {
    fn clone_box(&self) -> Box<dyn WarmState> {
        Box::new(self.clone())
    }
    fn as_any(&self) -> &dyn Any {
        self
    }
    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}

/// One evaluator's warm start: empty at first, then whatever its model stored (the model's own
/// type; a model finds nothing if another model's state is there).
#[derive(Debug, Default)]
pub struct WarmStart(Option<Box<dyn WarmState>>);

impl Clone for WarmStart {
    fn clone(&self) -> Self {
        WarmStart(self.0.as_deref().map(|s| s.clone_box()))
    }
}

impl WarmStart {
    /// The stored state, if it is a `T`.
    pub fn get<T: Any>(&self) -> Option<&T> {
        self.0.as_deref().and_then(|s| s.as_any().downcast_ref())
    }

    /// Stores `value` (in place when a `T` is already there: no allocation after the first).
    pub fn set<T: Any + Clone + Send + Sync + Debug>(&mut self, value: T) {
        match self
            .0
            .as_deref_mut()
            .and_then(|s| s.as_any_mut().downcast_mut::<T>())
        {
            Some(slot) => *slot = value,
            None => self.0 = Some(Box::new(value)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn warm_start_keeps_its_type_and_clones_deeply() {
        let mut w = WarmStart::default();
        assert!(w.get::<[f64; 4]>().is_none());
        w.set([1.0, 2.0, 3.0, 4.0]);
        assert_eq!(w.get::<[f64; 4]>(), Some(&[1.0, 2.0, 3.0, 4.0]));
        assert!(w.get::<Vec<f64>>().is_none(), "another type is not found");
        let copy = w.clone();
        w.set([5.0, 6.0, 7.0, 8.0]);
        assert_eq!(copy.get::<[f64; 4]>(), Some(&[1.0, 2.0, 3.0, 4.0]));
        assert_eq!(w.get::<[f64; 4]>(), Some(&[5.0, 6.0, 7.0, 8.0]));
        w.set(vec![1.0]);
        assert_eq!(w.get::<Vec<f64>>(), Some(&vec![1.0]));
        assert!(w.get::<[f64; 4]>().is_none(), "replaced by the other type");
    }

    /// A model with a closed-form configuration: z = a y², φ = b y (+ the rails' vertical
    /// displacement) — the adaptor's ż, c_z against the exact time derivatives along a motion.
    #[derive(Debug)]
    struct Parabola;
    const A: f64 = 3.0;
    const B: f64 = 0.4;

    impl ContactModel for Parabola {
        fn configuration(
            &self,
            y: f64,
            rails: &RailOffsets,
            _warm: &mut WarmStart,
        ) -> Result<Configuration, ContactModelError> {
            let zr = 0.5 * (rails.z_left + rails.z_right);
            Ok(Configuration {
                z: A * y * y + zr,
                phi: B * y,
                z_y: 2.0 * A * y,
                phi_y: B,
                contacts: Default::default(),
            })
        }
    }

    #[test]
    fn directional_differences_give_the_time_derivatives() {
        let (y, y_dot) = (2e-3, 0.05);
        let rails = RailMotion {
            q: [0.0, 1e-3, 0.0, 1e-3],
            q_dot: [0.0, 2e-3, 0.0, 2e-3],
            q_ddot: [0.0, -0.3, 0.0, -0.3],
        };
        let k = Parabola
            .kinematics(y, y_dot, &rails, &mut WarmStart::default())
            .unwrap();
        // z(t) = A y(t)² + z_r(t): ż = 2 A y ẏ + ż_r; z̈ = Z_y ÿ + c_z with c_z = 2 A ẏ² + z̈_r.
        assert!(
            (k.z_dot - (2.0 * A * y * y_dot + 2e-3)).abs() < 1e-9,
            "{}",
            k.z_dot
        );
        assert!(
            (k.c_z - (2.0 * A * y_dot * y_dot - 0.3)).abs() < 1e-6,
            "{}",
            k.c_z
        );
        assert!((k.phi_dot - B * y_dot).abs() < 1e-10);
        assert!(k.c_phi.abs() < 1e-6);
        assert!(k.s_knife.is_none());
    }
}
