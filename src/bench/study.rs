//! `kecsim bench study STUDY.toml`: a study's throughput on one core and on all of them, measured
//! in one command — the same study run twice into temporary directories (one job, then one per
//! core), the cases per minute of each, the speed-up against the cores, and the overhead per case
//! beyond its simulation. The two results tables must be identical (the error that goes with the
//! speed figure: none is allowed).

use std::fmt::Write;

use crate::study::run::{merge, run_study, StudyOptions, StudyRunReport};
use crate::study::{Study, StudyError};

/// One run of the study.
#[derive(Debug, Clone)]
pub struct ThroughputRow {
    pub jobs: usize,
    pub report: StudyRunReport,
}

impl ThroughputRow {
    pub fn cases_per_min(&self) -> f64 {
        60.0 * self.report.ran as f64 / self.report.wall_s.max(1e-9)
    }
    /// Per case: preprocessing and writing, s (the case's wall time beyond its integration).
    pub fn overhead_per_case_s(&self) -> f64 {
        (self.report.case_wall_s - self.report.run_wall_s) / (self.report.ran.max(1) as f64)
    }
}

/// Runs `study` with one job and with `cores` jobs; the table.
pub fn throughput(study: &Study, cores: usize) -> Result<String, StudyError> {
    let base = std::env::temp_dir().join(format!("kecsim-bench-study-{}", std::process::id()));
    let mut rows = Vec::new();
    let mut tables = Vec::new();
    for jobs in [1, cores.max(1)] {
        let out = base.join(format!("jobs-{jobs}"));
        std::fs::remove_dir_all(&out).ok();
        let report = run_study(
            study,
            &StudyOptions {
                jobs,
                shard: None,
                out: out.clone(),
                cancel: Default::default(),
            },
            &|_, _| {},
        )?;
        let (_, _, path) = merge(&out)?;
        tables.push(std::fs::read_to_string(&path).map_err(|e| StudyError::Io {
            path: path.display().to_string(),
            message: e.to_string(),
        })?);
        rows.push(ThroughputRow { jobs, report });
    }
    std::fs::remove_dir_all(&base).ok();
    let mut s = format!(
        "study throughput: {} ({} cases)\n| jobs | wall [s] | cases/min | integrating per case [s] | overhead per case [s] | cores busy |\n|---|---|---|---|---|---|\n",
        study.name,
        study.cases.len()
    );
    for r in &rows {
        let _ = writeln!(
            s,
            "| {} | {:.2} | {:.1} | {:.3} | {:.3} | {:.0} % |",
            r.jobs,
            r.report.wall_s,
            r.cases_per_min(),
            r.report.run_wall_s / r.report.ran.max(1) as f64,
            r.overhead_per_case_s(),
            100.0 * r.report.case_wall_s / (r.report.wall_s * r.jobs as f64).max(1e-9)
        );
    }
    let (one, all) = (&rows[0], &rows[rows.len() - 1]);
    let _ = writeln!(
        s,
        "speed-up on {} cores: {:.2} (cases per minute, measured in this run); results tables {}",
        all.jobs,
        all.cases_per_min() / one.cases_per_min().max(1e-9),
        if tables.windows(2).all(|w| w[0] == w[1]) {
            "identical"
        } else {
            "DIFFER (a defect: results must not depend on the number of jobs)"
        }
    );
    Ok(s)
}
