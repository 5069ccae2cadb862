//! Wheel–rail contact (paper §4–7).
//!
//! * [`geometry`]: the approximate contact constraints (Eq. 35–42) solved online by Newton,
//!   seeded by a global minimum-gap search; contact jumps and two-point contact.
//! * `elastic`: the interpenetration of the real profiles at a free wheelset pose (the elastic
//!   contact model's search).
//!
//! Conventions shared by the contact modules: the wheelset-track frame of the paper (Y to the left,
//! Z up, origin on the track centreline at the top-of-rail plane); the wheelset centre at (y, z),
//! linearised roll φ (positive lifts the left wheel). Surface parameters follow the paper: s^w and
//! s^r increase towards +Y on **both** sides (on the right side they are the mirror of the profile's
//! own field-side coordinate).

pub mod cache;
pub(crate) mod conicity;
pub mod design;
pub(crate) mod elastic;
pub mod forces;
pub mod geometry;
pub mod kec;
pub mod lookup;
pub(crate) mod model;
pub mod models;
pub mod nonhertz;
pub mod per_wheel;
pub(crate) mod point;
pub mod report;

pub use model::{Configuration, ContactModel, ContactModelError, WarmStart, WheelsetKinematics};
pub use models::{ContactBuildError, ContactModelSpec};
pub use point::ContactPoint;
