//! The track (paper §2.2–2.3): the ideal centreline built from sections, and its irregularities.
//!
//! * [`sections`]: horizontal (straight, curve, clothoid transition; cant and twist) and vertical
//!   (straight, transition) sections, Tab. 1–2, and the checks a list of them must pass.
//! * `clothoid`: position along a curve of linear curvature (Fresnel integral by its series).
//! * `centreline`: R^t(s), A^t(s) (Eq. 1–2), curvatures and their derivatives, the sliding
//!   frame's motion: the exact rotation's whole motion, or Eq. 2–4 as printed ([`FrameModel`]).
//! * `psd`: FRA and German irregularity spectra; `irregularity`: generation (sum of cosines),
//!   C² interpolation with derivatives, rail displacements and rail-frame placement (METHOD.md §2);
//!   [`measured`]: irregularity CSV files; [`spectrum`]: PSD estimates to check them.
//! * [`file`](mod@file): the `[track]` table of track and scenario files; the paper's Tab. 6 track embedded.
//! * `error`: [`TrackError`], what every part reports in.

pub(crate) mod centreline;
pub(crate) mod clothoid;
pub(crate) mod error;
pub mod file;
pub(crate) mod irregularity;
pub mod measured;
pub(crate) mod psd;
pub(crate) mod rails;
pub mod report;
pub mod sections;
pub mod spectrum;

pub use centreline::{Centreline, FrameModel, FrameMotion, Start, TrackFrame};
pub use error::TrackError;
pub use irregularity::{Generation, Irregularities, IrregularityState};
pub use psd::{Channel, Psd};
pub use rails::{RailMotion, RailOffsets, Side, TrackGauge};

/// A track: centreline, optional irregularities, cross-section gauge, optional lateral
/// flexibility.
#[derive(Debug, Clone)]
pub struct Track {
    pub name: String,
    pub centreline: Centreline,
    pub irregularities: Option<Irregularities>,
    pub gauge: TrackGauge,
    /// `None`: rigid rails (the paper's).
    pub lateral_flexibility: Option<LateralFlexibility>,
    /// The files its build read beyond the track file itself (a measured irregularity file):
    /// inputs that no output may overwrite ([`crate::files::OutputGuard`]).
    pub source_files: Vec<std::path::PathBuf>,
}

/// The track's lateral flexibility under each wheelset (a departure from the paper's rigid
/// track): both rails, with the sleepers and ballast they carry along, shift laterally by d as
/// one mass on a spring–damper that travels with the wheelset (a "moving track" model),
/// m_t d̈ + c_t ḋ + k_t d = −Σ F_Y (the wheels' lateral forces on the rails). The contact sees the
/// shift as an alignment: its geometry depends on y − d. It takes up the wheelset's flange
/// impacts, which on rigid rails meet the flange's geometric stiffness alone.
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LateralFlexibility {
    /// k_t, N/m.
    pub stiffness_n_per_m: f64,
    /// c_t, N s/m.
    pub damping_n_s_per_m: f64,
    /// m_t, kg.
    pub mass_kg: f64,
}

impl LateralFlexibility {
    /// What is wrong with the values (each names its key).
    pub fn problems(&self) -> Vec<String> {
        let mut p = Vec::new();
        for (key, v, lo, hi) in [
            ("stiffness_n_per_m", self.stiffness_n_per_m, 1e5, 1e10),
            ("damping_n_s_per_m", self.damping_n_s_per_m, 0.0, 1e8),
            ("mass_kg", self.mass_kg, 1.0, 1e5),
        ] {
            if !(v.is_finite() && v >= lo && v <= hi) || (key != "damping_n_s_per_m" && v <= 0.0) {
                p.push(format!(
                    "track.lateral_flexibility.{key} = {v}: expected a value in [{lo:e}, {hi:e}]"
                ));
            }
        }
        p
    }
}

impl Track {
    /// The track frame and the irregularities (zero where the track has none) at `s`.
    #[inline]
    pub fn eval(&self, s: f64) -> Result<(TrackFrame, IrregularityState), TrackError> {
        let frame = self.centreline.frame(s)?;
        let irr = match &self.irregularities {
            Some(i) => i.eval(s)?,
            None => IrregularityState::default(),
        };
        Ok((frame, irr))
    }
}
