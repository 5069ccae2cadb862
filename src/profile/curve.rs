//! The profile curve itself: a [`Profile`] of a [`ProfileKind`], z(s) in its own frame as a C²
//! not-a-knot cubic spline through its source points, evaluated on either side of the track (the
//! conventions in [`super`]).

use std::fmt;

use crate::spline::{CubicSpline, CurvePoint};
use crate::track::Side;

/// Wheel or rail.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProfileKind {
    Wheel,
    Rail,
}

impl fmt::Display for ProfileKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ProfileKind::Wheel => "wheel",
            ProfileKind::Rail => "rail",
        })
    }
}

/// A wheel or rail profile: z(s) in its own frame, SI units (the conventions: [`crate::profile`]).
#[derive(Debug, Clone)]
pub struct Profile {
    /// Short name (standard name or file stem).
    pub name: String,
    pub kind: ProfileKind,
    /// Where it came from (standard definition or file path).
    pub source: String,
    /// What was done to the source data on the way in (trimmed vertical ends, mirroring, ...).
    pub notes: Vec<String>,
    curve: CubicSpline,
}

impl Profile {
    /// Builds a profile from points in SI (s strictly increasing, ≥ 4 points, finite).
    pub fn from_points(
        name: &str,
        kind: ProfileKind,
        source: &str,
        s: Vec<f64>,
        z: Vec<f64>,
    ) -> Result<Self, crate::spline::SplineError> {
        Ok(Profile {
            name: name.to_string(),
            kind,
            source: source.to_string(),
            notes: Vec::new(),
            curve: CubicSpline::new(s, z)?,
        })
    }

    /// Value, slope and second derivative at `s` (left-side orientation). Outside
    /// [`Profile::domain`] the end tangent continues the profile.
    #[inline]
    pub fn eval(&self, s: f64) -> CurvePoint {
        self.curve.eval(s)
    }

    /// Evaluation for a given side: the right side is the mirror image, z_R(s) = z(−s).
    #[inline]
    pub fn eval_side(&self, side: Side, s: f64) -> CurvePoint {
        match side {
            Side::Left => self.curve.eval(s),
            Side::Right => {
                let p = self.curve.eval(-s);
                CurvePoint {
                    z: p.z,
                    dz: -p.dz,
                    d2z: p.d2z,
                }
            }
        }
    }

    /// Range of s covered by data, left-side orientation, m.
    pub fn domain(&self) -> (f64, f64) {
        self.curve.domain()
    }

    /// Range of s on a given side.
    pub fn domain_side(&self, side: Side) -> (f64, f64) {
        let (a, b) = self.domain();
        match side {
            Side::Left => (a, b),
            Side::Right => (-b, -a),
        }
    }

    /// The interpolated source points (s, z), m.
    pub fn knots(&self) -> (&[f64], &[f64]) {
        self.curve.knots()
    }

    /// `n` evenly spaced points (s, z) over the domain, m.
    pub fn polyline(&self, n: usize) -> Vec<(f64, f64)> {
        let (a, b) = self.domain();
        (0..n)
            .map(|k| {
                let s = a + (b - a) * k as f64 / (n - 1) as f64;
                (s, self.eval(s).z)
            })
            .collect()
    }
}
