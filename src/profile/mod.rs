//! Wheel and rail profiles (paper §3).
//!
//! A [`Profile`] is a plane curve z(s) in the profile's own frame, SI units:
//! * `s` \[m\], the lateral surface parameter, increasing towards the **field side** (outside of the
//!   track) for a profile on the **left** side of the track; the right side is the mirror image
//!   (see [`Side`]), which gives the paper's convention that s^w and s^r both increase towards +Y
//!   on each side once mirrored.
//! * `z` \[m\], **up**. For a rail, z is the rail head height h^r(s^r) of Eq. (20). For a wheel, z is
//!   the height of the running surface above the taping line (nominal rolling circle), so that the
//!   paper's wheel radius function of Eq. (21) is h^w(s^w) = r0 − z(s^w) (flanges point down,
//!   as on a real wheel).
//!
//! The curve is a C² not-a-knot cubic spline (see [`crate::spline`]) through the source points: the
//! standard profiles are sampled from their analytic definitions ([`standard`]); files are read by
//! [`io`]. Placement on the track cross-section (gauge, inclination, back-to-back, mirroring) is
//! [`placement`].

pub mod embedded;
pub mod io;
pub mod measures;
pub mod placement;
pub mod standard;

use std::fmt;
use std::path::Path;

pub use crate::spline::{CubicSpline, CurvePoint};
pub use standard::StandardProfile;

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

/// Side of the track (a track concept; here because every profile has one).
pub use crate::track::Side;

/// A profile-file or profile-name problem. Every variant names the file; line-specific
/// problems name the line (1-based).
#[derive(Debug, thiserror::Error)]
pub enum ProfileError {
    #[error("{path}: cannot read profile file: {source}")]
    Io {
        path: String,
        #[source]
        source: std::io::Error,
    },
    #[error("{path}:{line}: {problem}")]
    AtLine {
        path: String,
        line: usize,
        problem: String,
    },
    #[error("{path}: {problem}")]
    InFile { path: String, problem: String },
    #[error(
        "unknown profile '{name}': not a standard profile ({known}) and no such file",
        known = standard_names()
    )]
    UnknownName { name: String },
    #[error("{path}: the file holds a {found} profile, but a {expected} profile was asked for")]
    WrongKind {
        path: String,
        expected: ProfileKind,
        found: ProfileKind,
    },
}

fn standard_names() -> String {
    StandardProfile::ALL
        .map(|p| p.name())
        .into_iter()
        .chain(embedded::ALL.map(|p| p.name))
        .collect::<Vec<_>>()
        .join(", ")
}

/// A wheel or rail profile: z(s) in its own frame, SI units (see the module doc).
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

    /// Resolves `spec`, a standard name (`s1002`, `60e1`, `54e1`), a shipped profile's name
    /// (`ms-standin`, see [`embedded`]) or a file path, to a profile of the expected kind.
    pub fn resolve(spec: &str, expected: ProfileKind) -> Result<Profile, ProfileError> {
        if let Some(std) = StandardProfile::from_name(spec) {
            if std.kind() != expected {
                return Err(ProfileError::WrongKind {
                    path: spec.to_string(),
                    expected,
                    found: std.kind(),
                });
            }
            return Ok(std.profile());
        }
        if let Some(e) = embedded::EmbeddedProfile::from_name(spec) {
            if e.kind != expected {
                return Err(ProfileError::WrongKind {
                    path: spec.to_string(),
                    expected,
                    found: e.kind,
                });
            }
            return e.profile();
        }
        let path = Path::new(spec);
        if !path.exists() && path.extension().is_none() {
            return Err(ProfileError::UnknownName {
                name: spec.to_string(),
            });
        }
        io::read_profile(path, expected)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mirrored_side_is_the_mirror_image() {
        let p = StandardProfile::S1002.profile();
        for s in [-0.05, -0.01, 0.0, 0.02] {
            let l = p.eval_side(Side::Left, s);
            let r = p.eval_side(Side::Right, -s);
            assert_eq!(l.z, r.z);
            assert_eq!(l.dz, -r.dz);
            assert_eq!(l.d2z, r.d2z);
        }
        let (a, b) = p.domain_side(Side::Right);
        assert_eq!((a, b), (-p.domain().1, -p.domain().0));
    }

    #[test]
    fn spline_matches_analytic_definition() {
        // The runtime spline against the published sections, away from and at the joints.
        for std in StandardProfile::ALL {
            let p = std.profile();
            let sc = std.sections();
            let (a, b) = sc.range();
            let mut worst: f64 = 0.0;
            for k in 0..=20_000 {
                let x = a + (b - a) * k as f64 / 20_000.0;
                let (g, dg, _) = sc.eval(x);
                // Distance normal to the curve ≈ vertical deviation / sqrt(1 + slope²): on the
                // 1:20 rail flank a vertical deviation is 20× the geometric one.
                let vertical = (p.eval(x * 1e-3).z + g * 1e-3).abs();
                worst = worst.max(vertical / (1.0 + dg * dg).sqrt());
            }
            // 0.1 µm: far below any measured profile's accuracy.
            assert!(
                worst < 1e-7,
                "{std:?}: spline vs analytic {worst:e} m (normal distance)"
            );
        }
    }

    #[test]
    fn resolve_reports_unknown_names_and_wrong_kinds() {
        let e = Profile::resolve("s1003", ProfileKind::Wheel).unwrap_err();
        assert!(e.to_string().contains("unknown profile 's1003'"), "{e}");
        assert!(e.to_string().contains("s1002, 60e1, 54e1, ms-standin"), "{e}");
        let e = Profile::resolve("60e1", ProfileKind::Wheel).unwrap_err();
        assert!(e.to_string().contains("rail profile"), "{e}");
    }
}
