//! The real contact point of one wheel: the one type every contact model returns (online
//! constraints, lookup tables, KEC) and every force model reads (normal force along the normal,
//! Eq. 53; Hertz from the curvatures and the rolling radius; creep at the point).

/// One side's real contact point, in the wheelset-track frame (Y to the left, Z up).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ContactPoint {
    /// Wheel surface parameter s^w (paper convention: increases towards +Y), m.
    pub s_wheel: f64,
    /// Rail surface parameter s^r (paper convention), m.
    pub s_rail: f64,
    /// Position in the wheelset-track frame (Y, Z), m.
    pub position: (f64, f64),
    /// Unit rail normal (Y, Z) at the point, pointing into the wheel.
    pub normal: (f64, f64),
    /// Contact angle: the normal's angle from vertical, positive towards the track centre, rad.
    pub contact_angle: f64,
    /// Rolling radius h^w(s^w), m.
    pub rolling_radius: f64,
    /// Lateral curvature of the wheel profile at the point, positive where convex, 1/m.
    pub wheel_curvature: f64,
    /// Lateral curvature of the rail head at the point, positive where convex, 1/m.
    pub rail_curvature: f64,
}
