//! Wheel–rail contact (paper §4–7).
//!
//! * [`geometry`]: the approximate contact constraints (Eq. 35–42) solved online by Newton,
//!   seeded by a global minimum-gap search; contact jumps and two-point contact.
//!
//! Conventions shared by the contact modules: the wheelset-track frame of the paper (Y to the left,
//! Z up, origin on the track centreline at the top-of-rail plane); the wheelset centre at (y, z),
//! linearised roll φ (positive lifts the left wheel). Surface parameters follow the paper: s^w and
//! s^r increase towards +Y on **both** sides (on the right side they are the mirror of the profile's
//! own field-side coordinate).

pub mod conicity;
pub mod forces;
pub mod geometry;
pub mod kec;
pub mod lookup;
pub mod report;

use crate::profile::Side;

/// Rail profile-frame displacements at a wheelset's cross-section: the irregularities of
/// METHOD.md §2 (Eq. 5–11) as the contact geometry sees them.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RailOffsets {
    /// Lateral displacement of the left rail, y_lir, m.
    pub y_left: f64,
    /// Vertical displacement of the left rail, z_lir, m.
    pub z_left: f64,
    /// Lateral displacement of the right rail, y_rir, m.
    pub y_right: f64,
    /// Vertical displacement of the right rail, z_rir, m.
    pub z_right: f64,
}

impl RailOffsets {
    /// From the industry combinations: alignment, vertical profile, gauge variation, cross level
    /// (al = (y_l + y_r)/2, vp = (z_l + z_r)/2, gv = y_l − y_r, cl = z_l − z_r), m.
    pub fn from_irregularities(al: f64, vp: f64, gv: f64, cl: f64) -> Self {
        RailOffsets {
            y_left: al + 0.5 * gv,
            y_right: al - 0.5 * gv,
            z_left: vp + 0.5 * cl,
            z_right: vp - 0.5 * cl,
        }
    }

    /// Gauge variation only (rails moved apart symmetrically by gv/2 each).
    pub fn gauge_variation(gv: f64) -> Self {
        Self::from_irregularities(0.0, 0.0, gv, 0.0)
    }

    /// Lateral and vertical displacement of one side's rail.
    pub fn side(&self, side: Side) -> (f64, f64) {
        match side {
            Side::Left => (self.y_left, self.z_left),
            Side::Right => (self.y_right, self.z_right),
        }
    }

    /// Extra rotation δ = (z_lir − z_rir)/(2 L_r) of both rail profile frames (Eq. 11).
    pub fn delta(&self, l_r: f64) -> f64 {
        (self.z_left - self.z_right) / (2.0 * l_r)
    }

    /// al, vp, gv, cl.
    pub fn combinations(&self) -> (f64, f64, f64, f64) {
        (
            0.5 * (self.y_left + self.y_right),
            0.5 * (self.z_left + self.z_right),
            self.y_left - self.y_right,
            self.z_left - self.z_right,
        )
    }
}
