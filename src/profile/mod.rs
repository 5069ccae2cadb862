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
//! The curve is a C² not-a-knot cubic spline (see `crate::spline`) through the source points
//! (`curve`): the standard profiles are sampled from their analytic definitions (`standard`);
//! files are read by [`io`], shipped ones are `embedded`; [`Profile::resolve`] finds a profile
//! by name or path, with its problems in `error`. Placement on the track cross-section (gauge,
//! inclination, back-to-back, mirroring) is [`placement`].

pub(crate) mod blend;
pub(crate) mod curve;
pub(crate) mod embedded;
pub(crate) mod error;
pub mod io;
pub(crate) mod measures;
pub mod placement;
pub(crate) mod standard;

use std::path::Path;

pub use crate::spline::{CubicSpline, CurvePoint};
pub use curve::{Profile, ProfileKind};
pub use error::ProfileError;
pub use standard::StandardProfile;

/// Side of the track (a track concept; here because every profile has one).
pub use crate::track::Side;

/// The standard and shipped profiles' names, for errors.
fn standard_names() -> String {
    StandardProfile::ALL
        .map(|p| p.name())
        .into_iter()
        .chain(embedded::ALL.map(|p| p.name))
        .collect::<Vec<_>>()
        .join(", ")
}

impl Profile {
    /// Resolves `spec`, a standard name (`s1002`, `60e1`, `54e1`), a shipped profile's name
    /// (`ms-standin`, see `embedded`) or a file path, to a profile of the expected kind.
    ///
    /// A standard rail's name may carry a blend of its arc joints' curvature, `54e1:blend=1`
    /// (± 1 mm of arc length, see `blend`): a model change, off unless asked for.
    pub fn resolve(spec: &str, expected: ProfileKind) -> Result<Profile, ProfileError> {
        if let Some((name, blend)) = spec.split_once(":blend=") {
            let std = StandardProfile::from_name(name).filter(|p| p.kind() == ProfileKind::Rail);
            let bad = |problem: String| ProfileError::InFile {
                path: spec.to_string(),
                problem,
            };
            let std = std.ok_or_else(|| {
                bad(format!(
                    "a blend of the arc joints applies to a standard rail head (60e1, 54e1), not to '{name}'"
                ))
            })?;
            if std.kind() != expected {
                return Err(ProfileError::WrongKind {
                    path: spec.to_string(),
                    expected,
                    found: std.kind(),
                });
            }
            let w: f64 = blend.trim().parse().map_err(|_| {
                bad(format!(
                    "blend '{blend}': expected the half-width in mm, e.g. {name}:blend=1"
                ))
            })?;
            return std.blended(w).ok_or_else(|| {
                bad(format!(
                    "blend {w} mm: expected a half-width in mm above 0 and at most {}",
                    blend::MAX_BLEND_MM
                ))
            });
        }
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
                known: standard_names(),
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
        assert!(
            e.to_string().contains("s1002, 60e1, 54e1, ms-standin, ms-tram"),
            "{e}"
        );
        let e = Profile::resolve("60e1", ProfileKind::Wheel).unwrap_err();
        assert!(e.to_string().contains("rail profile"), "{e}");
    }
}
