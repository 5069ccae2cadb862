//! Profiles kecsim ships as data (CSV in `profiles/`, compiled into the binary), resolved by
//! name like the standard profiles:
//!
//! * **ms-standin** — the Metro de Sevilla vehicle's stand-in wheel for 54E1 at 1:20 (the paper's
//!   CAF wheel is not public): designed by `kecsim design-wheel` from
//!   `assets/designs/ms-standin.toml`, jump-free by construction, flange S_h 28 mm, S_d 32.5 mm at
//!   a 1366 mm back-to-back, 70° flank. The file's header holds the target and the result.
//! * **ms-tram** — its redesign for realism (issue 48), from `assets/designs/ms-tram.toml`: the
//!   same rail and flange, the wheel's radius at least 10 % above the rail's on every rail arc
//!   (ms-standin: 2–6 %), no dwell on the rail's arc joints, conicity 0.29 at 2 mm; its wall at
//!   ±4.1 mm (ms-standin ±3.2), S_d 31.7 mm at 1366 mm. Points every 0.02 mm.

use super::curve::{Profile, ProfileKind};
use super::error::ProfileError;
use super::io;

/// One shipped profile.
#[derive(Debug, Clone, Copy)]
pub struct EmbeddedProfile {
    pub name: &'static str,
    pub kind: ProfileKind,
    /// Where it came from (the repository file).
    pub file: &'static str,
    csv: &'static str,
}

/// Every shipped profile.
pub const ALL: [EmbeddedProfile; 2] = [
    EmbeddedProfile {
        name: "ms-standin",
        kind: ProfileKind::Wheel,
        file: "profiles/ms-standin.csv",
        csv: include_str!("../../profiles/ms-standin.csv"),
    },
    EmbeddedProfile {
        name: "ms-tram",
        kind: ProfileKind::Wheel,
        file: "profiles/ms-tram.csv",
        csv: include_str!("../../profiles/ms-tram.csv"),
    },
];

impl EmbeddedProfile {
    /// Looks a shipped profile up by name (case-insensitive).
    pub fn from_name(name: &str) -> Option<Self> {
        ALL.into_iter().find(|p| p.name.eq_ignore_ascii_case(name))
    }

    /// The profile, read from the compiled-in CSV.
    pub fn profile(&self) -> Result<Profile, ProfileError> {
        io::parse_profile(self.csv, "csv", self.name, self.file, self.kind)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shipped_profiles_read_and_resolve_by_name() {
        for e in ALL {
            let p = e.profile().unwrap();
            assert_eq!(p.kind, e.kind);
            let r = Profile::resolve(&e.name.to_ascii_uppercase(), e.kind).unwrap();
            assert_eq!(r.knots().0.len(), p.knots().0.len());
        }
        let e = Profile::resolve("ms-standin", ProfileKind::Rail).unwrap_err();
        assert!(e.to_string().contains("wheel profile"), "{e}");
    }
}
