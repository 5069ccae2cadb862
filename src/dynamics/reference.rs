//! The vehicle reference: the point that moves along the track centreline at the prescribed speed
//! (DYNAMICS.md §1), s₀(t) with ṡ₀ = V(t), and what a body-track frame at arc length s sees of the
//! track: its position and orientation (Eq. 1–2), its motion (the whole motion, or Eq. 3–4 as printed: [`crate::track::FrameModel`]), gravity in its components,
//! and the rail irregularities with their time derivatives (METHOD.md §2).

use std::sync::Arc;

use nalgebra::{Matrix3, Vector3};

use super::wheelset::FrameMotion;
use crate::track::{FrameModel, RailMotion, Track, TrackError};

/// Gravity, m/s².
pub const G: f64 = 9.81;

/// Forward speed of the reference: V(t) = V₀ + a t (a = 0: constant), never negative.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpeedProfile {
    pub initial_m_s: f64,
    pub ramp_m_s2: f64,
}

impl SpeedProfile {
    pub fn at(&self, t: f64) -> f64 {
        (self.initial_m_s + self.ramp_m_s2 * t).max(0.0)
    }
    /// Distance travelled by the reference, m.
    pub fn distance(&self, t: f64) -> f64 {
        // A braking ramp stops the vehicle at t_stop = V0/|a| and holds it there (as `at` does).
        let t = match self.stop_time() {
            Some(ts) => t.min(ts),
            None => t,
        };
        self.initial_m_s * t + 0.5 * self.ramp_m_s2 * t * t
    }

    /// When a braking ramp brings the speed to zero (None: it never does).
    pub fn stop_time(&self) -> Option<f64> {
        (self.ramp_m_s2 < 0.0).then(|| self.initial_m_s / -self.ramp_m_s2)
    }
}

/// The track frame at one arc length, as a body there sees it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameAt {
    /// R(s), m, and A(s) (Eq. 1–2).
    pub origin: Vector3<f64>,
    pub rotation: Matrix3<f64>,
    /// The frame's motion at the reference speed (whole, or Eq. 3–4) and gravity.
    pub motion: FrameMotion,
    /// The rail displacements there and their time derivatives.
    pub rails: RailMotion,
}

/// The reference's motion along an optional track (none: tangent, level, ideal track along X).
#[derive(Debug, Clone)]
pub struct Reference {
    pub track: Option<Arc<Track>>,
    /// Arc length of the reference at t = 0, m.
    pub s0: f64,
    pub speed: SpeedProfile,
    /// The track frame's rotation and motion: the whole (default) or the paper's Eq. (2)–(4)
    /// ([`FrameModel`]).
    pub frame_model: FrameModel,
}

impl Reference {
    /// The track's lateral flexibility, if it has one.
    pub fn lateral_flexibility(&self) -> Option<crate::track::LateralFlexibility> {
        self.track.as_ref().and_then(|t| t.lateral_flexibility)
    }

    /// V(t) and V̇(t) (no deceleration below standstill).
    pub fn speed_at(&self, t: f64) -> (f64, f64) {
        let v = self.speed.at(t);
        (v, if v > 0.0 { self.speed.ramp_m_s2 } else { 0.0 })
    }

    /// Arc length of the reference at t, m.
    pub fn s_ref(&self, t: f64) -> f64 {
        self.s0 + self.speed.distance(t)
    }

    /// The track frame at arc length `s` for a body moving at V = `v`, V̇ = `v_dot`.
    pub fn frame(&self, s: f64, v: f64, v_dot: f64) -> Result<FrameAt, TrackError> {
        self.frame_with(s, v, v_dot, true)
    }

    /// [`Reference::frame`] without the rails' motion (`rails` left at rest): for a body that
    /// does not touch the rails (carbodies, bogie frames), whose right-hand side would evaluate
    /// the irregularities for nothing.
    pub fn frame_of_body(&self, s: f64, v: f64, v_dot: f64) -> Result<FrameAt, TrackError> {
        self.frame_with(s, v, v_dot, false)
    }

    fn frame_with(&self, s: f64, v: f64, v_dot: f64, rails: bool) -> Result<FrameAt, TrackError> {
        match &self.track {
            None => {
                let mut motion = FrameMotion::tangent(v);
                motion.accel[0] = v_dot;
                Ok(FrameAt {
                    origin: Vector3::new(s, 0.0, 0.0),
                    rotation: Matrix3::identity(),
                    motion,
                    rails: RailMotion::default(),
                })
            }
            Some(track) => {
                let tf = track.centreline.frame(s)?;
                let rails = match (&track.irregularities, rails) {
                    (Some(i), true) => i.eval(s)?.rail_motion(v, v_dot),
                    _ => RailMotion::default(),
                };
                let m = tf.motion_of(self.frame_model, v, v_dot);
                Ok(FrameAt {
                    origin: tf.position,
                    rotation: tf.rotation_of(self.frame_model),
                    motion: FrameMotion {
                        speed: v,
                        accel: m.acceleration.into(),
                        omega: m.angular_velocity.into(),
                        alpha: m.angular_acceleration.into(),
                        gravity: tf.gravity_of(self.frame_model, G).into(),
                    },
                    rails,
                })
            }
        }
    }
}
