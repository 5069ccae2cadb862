//! What can go wrong reading a profile file or resolving a profile's name.

use super::curve::ProfileKind;

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
    /// `known`: the standard and shipped profiles' names.
    #[error("unknown profile '{name}': not a standard profile ({known}) and no such file")]
    UnknownName { name: String, known: String },
    #[error("{path}: the file holds a {found} profile, but a {expected} profile was asked for")]
    WrongKind {
        path: String,
        expected: ProfileKind,
        found: ProfileKind,
    },
}
