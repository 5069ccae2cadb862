//! The contact kinematics of a wheelset, of one of two kinds, and what each kind's equations do
//! with it — the one place the vehicle systems ([`super::single_wheelset`], [`super::multibody`])
//! go through, so that they never ask which kind they have:
//!
//! * **constrained** ([`super::wheelset`]): a constraint model (online, tables, KEC) gives z, φ as
//!   functions of y, Z(y, q_r), Φ(y, q_r), with the two contact points; the normal forces are the
//!   constraints' reactions, and the slot's lift entries hold each wheel's lift θ, θ̇ (a wheel off
//!   its rail, landing as an event);
//! * **free** ([`super::elastic`](mod@super::elastic)): the elastic model leaves z, φ to the
//!   wheelset (the slot's lift entries hold z, φ, ż, φ̇) and finds the contacts where the real
//!   profiles interpenetrate at that pose; the normal forces are Hertz's from the penetrations.
//!
//! A contact model declares its kind through [`ContactModel::elastic`]: `Some` — the elastic
//! search it runs at a free pose.

use super::elastic::{evaluate_free, free_kinematics, initial_free_pose, FreeKinematics};
use super::reference::FrameAt;
use super::wheelset::{
    evaluate, land, pose_kinematics, FrameMotion, Landing, Load, NormalForceStart, WheelsetDynamics,
    WheelsetError, WheelsetInertia, WheelsetState,
};
use crate::contact::elastic::ElasticContact;
use crate::contact::forces::ContactForceSettings;
use crate::contact::{ContactModel, ContactModelError, WarmStart, WheelsetKinematics};
use crate::track::{LateralFlexibility, RailMotion, RailOffsets};

/// The kind of kinematics a contact model gives its wheelsets.
#[derive(Debug, Clone, Copy)]
pub enum Kind<'a> {
    /// z, φ constrained to y (with the lift of a wheel off its rail).
    Constrained,
    /// z, φ free; the contacts from this elastic search at the pose.
    Free(&'a ElasticContact),
}

impl Kind<'_> {
    /// The kind of `model`'s kinematics.
    pub fn of(model: &dyn ContactModel) -> Kind<'_> {
        match model.elastic() {
            Some(search) => Kind::Free(search),
            None => Kind::Constrained,
        }
    }

    /// Whether the slot's lift entries are wheel lifts that land (integrator events): the
    /// constrained kind's; the free kind's hold the pose.
    pub fn lands(self) -> bool {
        matches!(self, Kind::Constrained)
    }
}

/// The contact kinematics of one wheelset at its state.
#[derive(Debug, Clone, PartialEq)]
pub enum Kinematics {
    /// A constraint model's two-point configuration at the state's y (a lifted wheel's θ not yet
    /// applied: [`Kinematics::pose`]).
    Constrained(WheelsetKinematics),
    /// The elastic model's free pose and the contacts found at it.
    Free(FreeKinematics),
}

impl Kinematics {
    /// The kinematics of `model` at the state `st` on the rails `rails` under the wheelset
    /// ([`WheelsetState::shifted_rails`]).
    pub fn of(
        model: &dyn ContactModel,
        st: &WheelsetState,
        rails: &RailMotion,
        warm: &mut WarmStart,
    ) -> Result<Kinematics, ContactModelError> {
        Ok(match Kind::of(model) {
            Kind::Constrained => Kinematics::Constrained(model.kinematics(st.y, st.y_dot, rails, warm)?),
            Kind::Free(search) => Kinematics::Free(free_kinematics(search, st, rails)?),
        })
    }

    /// The kinematics of the wheelset's pose: the constrained configuration moved by the state's
    /// lift where a wheel is off its rail; the free pose as it is.
    pub fn pose(&self, state: &WheelsetState) -> Result<WheelsetKinematics, WheelsetError> {
        match self {
            Kinematics::Constrained(kin) => pose_kinematics(state, kin),
            Kinematics::Free(free) => Ok(free.pose.clone()),
        }
    }

    /// The wheelset's accelerations and contact forces ([`evaluate`] with the constraints,
    /// [`evaluate_free`] on elastic contacts); `start` seeds the constrained normal-force
    /// iteration and is updated to this evaluation's normal forces.
    #[allow(clippy::too_many_arguments)]
    pub fn evaluate(
        &self,
        inertia: &WheelsetInertia,
        state: &WheelsetState,
        frame: &FrameMotion,
        load: &Load,
        forces: &ContactForceSettings,
        start: &mut NormalForceStart,
        track: Option<&LateralFlexibility>,
    ) -> Result<WheelsetDynamics, WheelsetError> {
        match self {
            Kinematics::Constrained(kin) => evaluate(inertia, state, kin, frame, load, forces, start, track),
            Kinematics::Free(free) => {
                let r = evaluate_free(inertia, state, free, frame, load, forces, track)?;
                start.lambda = r.normal;
                Ok(r)
            }
        }
    }

    /// The landing of wheel `side` ([`land`]); a free wheelset has no landings (its contacts come
    /// and go with the penetrations).
    pub fn land(
        &self,
        inertia: &WheelsetInertia,
        state: &mut WheelsetState,
        track: Option<&LateralFlexibility>,
        side: usize,
    ) -> Result<Option<Landing>, WheelsetError> {
        match self {
            Kinematics::Constrained(kin) => land(inertia, state, kin, track, side),
            Kinematics::Free(_) => Ok(None),
        }
    }
}

/// The slot's initial lift entries (z, φ for the free kind: [`initial_free_pose`] under the static
/// wheel loads `loads`, left and right, N; none for the constrained kind, whose wheels start on
/// their rails).
pub fn initial_pose(
    model: &dyn ContactModel,
    y: f64,
    rails: &RailOffsets,
    loads: [f64; 2],
    forces: &ContactForceSettings,
) -> Result<Option<(f64, f64)>, ContactModelError> {
    match Kind::of(model) {
        Kind::Constrained => Ok(None),
        Kind::Free(_) => initial_free_pose(model, y, rails, loads, forces).map(Some),
    }
}

/// A wheelset's kinematics from the last full evaluation, kept with the exact time and state slot
/// it was computed at: an evaluation at the same (t, slot) — bit for bit — takes it instead of
/// solving again. The finite-difference pass over the bogie frames' columns meets this: it moves
/// the frames only, so every wheelset's kinematics is the one of f(t, x) just before
/// ([`super::multibody`]).
#[derive(Debug, Clone, PartialEq)]
pub struct KinematicsMemo {
    t: f64,
    slot: Vec<f64>,
    /// The contact model's kinematics at the slot's state.
    pub kin: Kinematics,
    /// The pose ([`Kinematics::pose`]).
    pub pose: WheelsetKinematics,
    /// The track frame at the wheelset.
    pub frame: FrameAt,
}

impl KinematicsMemo {
    /// Keeps `kin` and `pose`, computed at time `t` from the state slot `slot`.
    pub fn new(
        t: f64,
        slot: &[f64],
        kin: &Kinematics,
        pose: &WheelsetKinematics,
        frame: FrameAt,
    ) -> KinematicsMemo {
        KinematicsMemo {
            t,
            slot: slot.to_vec(),
            kin: kin.clone(),
            pose: pose.clone(),
            frame,
        }
    }

    /// Keeps `kin`, `pose` and `frame` at (t, slot) in `memo`, reusing its storage.
    pub fn keep(
        memo: &mut Option<KinematicsMemo>,
        t: f64,
        slot: &[f64],
        kin: &Kinematics,
        pose: &WheelsetKinematics,
        frame: FrameAt,
    ) {
        match memo {
            Some(m) if m.slot.len() == slot.len() => {
                m.t = t;
                m.slot.copy_from_slice(slot);
                m.kin.clone_from(kin);
                m.pose.clone_from(pose);
                m.frame = frame;
            }
            _ => *memo = Some(KinematicsMemo::new(t, slot, kin, pose, frame)),
        }
    }

    /// Whether this was computed at exactly (t, slot): the same bits, not merely close.
    pub fn matches(&self, t: f64, slot: &[f64]) -> bool {
        self.t.to_bits() == t.to_bits()
            && self.slot.len() == slot.len()
            && self
                .slot
                .iter()
                .zip(slot)
                .all(|(a, b)| a.to_bits() == b.to_bits())
    }
}
