//! The track (paper §2.2–2.3): the ideal centreline built from sections, and its irregularities.
//!
//! * [`sections`]: horizontal (straight, curve, clothoid transition; cant and twist) and vertical
//!   (straight, transition) sections, Tab. 1–2, and the checks a list of them must pass.
//! * [`clothoid`]: position along a curve of linear curvature (Fresnel integral by its series).
//! * [`centreline`]: R^t(s), A^t(s) (Eq. 1–2), curvatures and their derivatives, the sliding
//!   frame's velocity and acceleration terms (Eq. 3–4).
//! * [`psd`]: FRA and German irregularity spectra; [`irregularity`]: generation (sum of cosines),
//!   C² interpolation with derivatives, rail displacements and rail-frame placement (METHOD.md §2);
//!   [`measured`]: irregularity CSV files; [`spectrum`]: PSD estimates to check them.
//! * [`file`](mod@file): the `[track]` table of track and scenario files; the paper's Tab. 6 track embedded.

pub mod centreline;
pub mod clothoid;
pub mod file;
pub mod irregularity;
pub mod measured;
pub mod psd;
pub mod rails;
pub mod report;
pub mod sections;
pub mod spectrum;

pub use centreline::{Centreline, FrameMotion, Start, TrackFrame};
pub use irregularity::{Generation, Irregularities, IrregularityState};
pub use psd::{Channel, Psd};
pub use rails::{RailMotion, RailOffsets, Side, TrackGauge};

/// Track errors. File problems name the file and, where there is one, the line.
#[derive(Debug, thiserror::Error)]
pub enum TrackError {
    #[error("{path}: cannot read: {source}")]
    Io {
        path: String,
        #[source]
        source: std::io::Error,
    },
    /// Syntax, unknown key, wrong type: the TOML message carries line and column.
    #[error("{path}: {message}")]
    Parse { path: String, message: String },
    /// Every validation problem found, one per line, each naming file and line.
    #[error("{path}: invalid track:\n  - {}", problems.join("\n  - "))]
    Invalid { path: String, problems: Vec<String> },
    #[error("{path}:{line}: {problem}")]
    AtLine {
        path: String,
        line: usize,
        problem: String,
    },
    #[error("{path}: {problem}")]
    InFile { path: String, problem: String },
    /// Sections built in code (no file): problems name the section by index.
    #[error("invalid sections:\n  - {}", .0.join("\n  - "))]
    Sections(Vec<String>),
    #[error("irregularities: {0}")]
    Irregularity(String),
    #[error("s = {s} m is outside the track (s = {from}..{to} m)")]
    OutOfRange { s: f64, from: f64, to: f64 },
}

/// A track: centreline, optional irregularities, cross-section gauge.
#[derive(Debug, Clone)]
pub struct Track {
    pub name: String,
    pub centreline: Centreline,
    pub irregularities: Option<Irregularities>,
    pub gauge: TrackGauge,
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
