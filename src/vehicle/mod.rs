//! The vehicle as a set of rigid bodies, wheelsets and force elements (paper §2.4–2.5; METHOD.md
//! §3; DYNAMICS.md §1–2), described independently of how it is integrated.
//!
//! **Coordinates.** Every body i (carbody, bogie frame, wheelset) has a body-track frame: the track
//! frame (Eq. 1–2) at arc length s_i = s₀(t) + d_i + x_i (Eq. 13), d_i its nominal position along
//! the vehicle, x_i its small longitudinal coordinate. Relative to that frame the body's centre
//! sits at (0, y_i, h_i + z_i), h_i its nominal height above the rail-top plane, and its small
//! rotations are Θ_i = (φ_i, θ_i, ψ_i) (linearised, Eq. 15). Positions in the scenario file are
//! nominal vehicle coordinates: x forward from the vehicle reference, y to the left, z up from the
//! rail top; a body point's arm is its nominal position minus the body's nominal centre.
//!
//! **Where a point is.** A body point with arm p is at
//! G = R(s_i) + A(s_i) (c_i + p + Θ_i × p) (global), with c_i = (0, y_i, h_i + z_i), and moves with
//! Ġ = A(s_i) [(V + ẋ_i) e_x + (0, ẏ_i, ż_i) + ω_t × (c_i + p + Θ_i × p) + Θ̇_i × p], ω_t the track
//! frame's angular velocity (Eq. 4). Computing element deflections from global positions (rather
//! than from coordinate differences) puts the curve geometry in exactly: two bodies 1.28 m apart on
//! a 235.65 m curve have frames yawed by 5.4 mrad and offset by 3.5 mm, which is what makes a
//! stiff primary suspension steer a wheelset.
//!
//! **Force elements** ([`Element`]) act between two bodies or between a body and the ideal
//! track-following reference (`"track"`): 6-component bushings (with optional bump stops), axial
//! spring–dampers (traction rods, dampers), rotational springs (anti-roll bars, secondary
//! bending), and a mass carried along the track by a body (the weight and the inertial force of a
//! part that is not modelled, e.g. half a carbody on a bogie scene). Deflections are expressed in
//! the track axes of the element's first body. Their static preloads are computed, not written:
//! see the dynamics' multibody system. **Spherical joints** (`[[vehicle.joints]]`) join two rigid
//! bodies at a point; they are constraints with reactions, solved with the equations of motion.

pub mod elements;
pub mod spec;

pub use elements::{BodyRef, Element, ElementLoad, Pose};
pub use spec::{MultibodySpec, VehicleProblem, VehicleSpec};
