//! What can go wrong with a track: reading and writing its files, validating its sections and
//! irregularities, evaluating it outside its extent. Every part of [`super`] reports in it.

/// Track errors. File problems name the file and, where there is one, the line.
#[derive(Debug, thiserror::Error)]
pub enum TrackError {
    #[error("{path}: cannot read: {source}")]
    Io {
        path: String,
        #[source]
        source: std::io::Error,
    },
    /// A size the input implies is above a resource limit ([`crate::limits`]).
    #[error("{0}")]
    Limit(String),
    #[error("{path}: cannot write: {source}")]
    Write {
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
