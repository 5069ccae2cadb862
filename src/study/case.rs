//! The records a study keeps and every part of it reads: the study's identity (`study.json`,
//! [`Manifest`]) and one case's row (`result.json`, [`CaseResult`]) — written by [`super::run`],
//! tabulated by [`super::critical`] and [`super::statistics`], recorded by
//! [`crate::inspect::study`].

use serde::{Deserialize, Serialize};

use super::spec::Study;

/// `study.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    pub id: String,
    pub name: String,
    pub cases: usize,
    pub axes: Vec<String>,
    pub extracts: Vec<String>,
    /// A critical-speed study: the hunting amplitude threshold, mm.
    #[serde(default)]
    pub critical_speed_threshold_mm: Option<f64>,
    /// The axes whose values are derived seeds (realisations), by index.
    #[serde(default)]
    pub seed_axes: Vec<usize>,
}

impl Manifest {
    pub fn of(study: &Study) -> Manifest {
        Manifest {
            id: study.id.clone(),
            name: study.name.clone(),
            cases: study.cases.len(),
            axes: study.axes.iter().map(|a| a.key.clone()).collect(),
            extracts: study.extracts.iter().map(|x| x.name()).collect(),
            critical_speed_threshold_mm: study.critical_speed.map(|c| c.threshold_mm),
            seed_axes: (0..study.axes.len()).filter(|&k| study.axes[k].seeds).collect(),
        }
    }
}

/// `result.json`: one case's row.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CaseResult {
    pub study_id: String,
    pub case: usize,
    /// FNV-1a of the case's scenario text.
    pub scenario_hash: String,
    /// The axes' values, as table cells.
    pub values: Vec<String>,
    /// `completed`, `stopped`, `derailed` or `failed` (the run's outcome; `failed` also where the
    /// scenario could not be built).
    pub status: String,
    /// The extracts, in the study's order (None: the run gives none).
    pub extracts: Vec<Option<f64>>,
    /// Why the run ended early (empty where it completed).
    pub diagnosis: String,
    /// The vehicle's wheelsets (their CSVs are in the case's folder).
    pub wheelsets: Vec<String>,
    /// Not part of the results table (they are not reproducible): the case's wall time, and the
    /// part of it spent integrating (the rest: preprocessing — profiles, tables, track — and
    /// writing), s.
    pub wall_s: f64,
    #[serde(default)]
    pub run_wall_s: f64,
    pub simulated_s: f64,
}

impl CaseResult {
    /// `key = value, …` of the axes `keep` selects (by index; `axes` the study's keys).
    pub fn axes_text(&self, axes: &[String], keep: impl Fn(usize) -> bool) -> String {
        axes.iter()
            .zip(&self.values)
            .enumerate()
            .filter(|(k, _)| keep(*k))
            .map(|(_, (a, v))| format!("{a} = {v}"))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// The distinct items, in order of first appearance (the groups of a table's rows).
pub fn first_appearances<T: PartialEq>(items: impl IntoIterator<Item = T>) -> Vec<T> {
    let mut out: Vec<T> = Vec::new();
    for x in items {
        if !out.contains(&x) {
            out.push(x);
        }
    }
    out
}
