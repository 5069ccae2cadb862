//! Studies at scale: one base scenario run over many variations — a speed sweep, irregularity
//! realisations (EN 14363 statistics), friction, any scenario value by its key path — on all
//! cores, or sliced over a cluster's job array, with one table of results.
//!
//! [`spec`] reads the study file and expands its cases, [`run`] runs them (each case seeded from
//! the study seed and its index: the same results whatever the number of jobs or shards) and
//! joins their results, [`extract`] computes what each case keeps; `case` holds the records they
//! share (the manifest and a case's row), which `critical` and `statistics` tabulate.

pub(crate) mod case;
pub(crate) mod critical;
pub mod extract;
pub mod run;
pub mod slurm;
pub mod spec;
pub(crate) mod statistics;

use thiserror::Error;

pub use case::{first_appearances, printable, CaseResult, Manifest};
pub use extract::Extract;
pub use run::{merge, run_study, StudyOptions, StudyRunReport};
pub use spec::{Axis, AxisValues, Case, Sampling, Study};

/// Why a study cannot be read, run or merged.
#[derive(Debug, Error)]
pub enum StudyError {
    #[error("{path}: {message}")]
    Io { path: String, message: String },
    /// `line` 0: the file as a whole.
    #[error("{path}{}: {message}", at_line(*line))]
    Input {
        path: String,
        line: usize,
        message: String,
    },
    #[error("{0}")]
    Shard(String),
    /// A value `kecsim study slurm` cannot put into a job script (see [`slurm`]).
    #[error("{0}")]
    Slurm(String),
    #[error("{dir} belongs to another study: {found}, not {this} (use another --out, or remove it)")]
    OtherStudy {
        dir: String,
        found: String,
        this: String,
    },
    #[error("{dir}: {count} of {of} cases not finished (run their shards first): cases {cases}")]
    Missing {
        dir: String,
        count: usize,
        of: usize,
        cases: String,
    },
}

fn at_line(line: usize) -> String {
    if line == 0 {
        String::new()
    } else {
        format!(": line {line}")
    }
}
