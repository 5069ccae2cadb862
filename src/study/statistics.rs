//! Statistics over realisations: where an axis gives derived seeds (`seeds = N`, e.g. the track
//! irregularities'), each extract is summarised over them for every combination of the other
//! axes — the number of realisations, mean x̄, sample standard deviation s, minimum, maximum and
//! x̄ + 3s (an envelope of the realisations' scatter; not EN 14363's section-wise estimate, which
//! needs the track cut into sections). Failed cases count with what they simulated; a case
//! without a value (None) is left out of its extract's figures.

use std::fmt::Write;

use super::case::{first_appearances, CaseResult, Manifest};
use super::StudyError;

/// One extract's figures over one group's realisations.
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    /// The other axes' values (in axis order).
    pub group: Vec<String>,
    pub extract: String,
    pub n: usize,
    pub mean: f64,
    /// Sample standard deviation (n − 1); 0 for one realisation.
    pub std: f64,
    pub min: f64,
    pub max: f64,
}

/// The figures of every extract over the seed axes' values, per combination of the other axes
/// (groups in order of first appearance).
pub fn over_realisations(manifest: &Manifest, rows: &[CaseResult]) -> Vec<Summary> {
    let others: Vec<usize> = (0..manifest.axes.len())
        .filter(|k| !manifest.seed_axes.contains(k))
        .collect();
    let group_of = |r: &CaseResult| -> Vec<String> {
        others
            .iter()
            .map(|&k| r.values.get(k).cloned().unwrap_or_default())
            .collect()
    };
    let groups = first_appearances(rows.iter().map(group_of));
    let mut out = Vec::new();
    for g in groups {
        let members: Vec<&CaseResult> = rows.iter().filter(|r| group_of(r) == g).collect();
        for (e, name) in manifest.extracts.iter().enumerate() {
            let v: Vec<f64> = members
                .iter()
                .filter_map(|r| r.extracts.get(e).copied().flatten())
                .filter(|v| v.is_finite())
                .collect();
            if v.is_empty() {
                continue;
            }
            let n = v.len();
            let mean = v.iter().sum::<f64>() / n as f64;
            let std = if n > 1 {
                (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1) as f64).sqrt()
            } else {
                0.0
            };
            out.push(Summary {
                group: g.clone(),
                extract: name.clone(),
                n,
                mean,
                std,
                min: v.iter().copied().fold(f64::INFINITY, f64::min),
                max: v.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            });
        }
    }
    out
}

/// The other axes' names (the group columns).
fn group_axes(manifest: &Manifest) -> Vec<String> {
    (0..manifest.axes.len())
        .filter(|k| !manifest.seed_axes.contains(k))
        .map(|k| manifest.axes[k].clone())
        .collect()
}

/// `statistics.csv` (written by [`super::run::merge`]): `AXIS…, extract, n, mean, std, min, max,
/// mean_plus_3std`.
pub fn statistics_csv(manifest: &Manifest, list: &[Summary]) -> Result<String, StudyError> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let e = |e: csv::Error| StudyError::Io {
        path: "statistics.csv".into(),
        message: e.to_string(),
    };
    let mut header = group_axes(manifest);
    header.extend(["extract", "n", "mean", "std", "min", "max", "mean_plus_3std"].map(String::from));
    w.write_record(&header).map_err(e)?;
    for s in list {
        let mut rec = s.group.clone();
        rec.push(s.extract.clone());
        rec.push(s.n.to_string());
        for v in [s.mean, s.std, s.min, s.max, s.mean + 3.0 * s.std] {
            rec.push(format!("{v}"));
        }
        w.write_record(&rec).map_err(e)?;
    }
    let bytes = w.into_inner().map_err(|x| StudyError::Io {
        path: "statistics.csv".into(),
        message: x.error().to_string(),
    })?;
    String::from_utf8(bytes).map_err(|x| StudyError::Io {
        path: "statistics.csv".into(),
        message: x.to_string(),
    })
}

/// The statistics in Markdown (the report).
pub fn statistics_markdown(manifest: &Manifest, list: &[Summary]) -> String {
    let seeds: Vec<&str> = manifest
        .seed_axes
        .iter()
        .map(|&k| manifest.axes[k].as_str())
        .collect();
    let mut header = group_axes(manifest);
    header.extend(["extract", "n", "mean", "std", "min", "max", "mean + 3 std"].map(String::from));
    let mut s = format!(
        "## Over the realisations ({})\n\n| {} |\n|{}\n",
        seeds.join(", "),
        header.join(" | "),
        "---|".repeat(header.len())
    );
    for x in list {
        let _ = writeln!(
            s,
            "| {}{}{} | {} | {:.4} | {:.4} | {:.4} | {:.4} | {:.4} |",
            x.group.join(" | "),
            if x.group.is_empty() { "" } else { " | " },
            x.extract,
            x.n,
            x.mean,
            x.std,
            x.min,
            x.max,
            x.mean + 3.0 * x.std
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mean_and_sample_deviation_per_group() {
        let m = Manifest {
            id: "x".into(),
            name: "x".into(),
            cases: 6,
            axes: vec!["speed".into(), "seed".into()],
            extracts: vec!["a".into()],
            critical_speed_threshold_mm: None,
            seed_axes: vec![1],
        };
        let row = |case: usize, speed: &str, a: Option<f64>| CaseResult {
            study_id: "x".into(),
            case,
            scenario_hash: String::new(),
            values: vec![speed.into(), format!("{case}")],
            status: "completed".into(),
            extracts: vec![a],
            diagnosis: String::new(),
            wheelsets: vec![],
            wall_s: 0.0,
            run_wall_s: 0.0,
            simulated_s: 0.0,
        };
        let rows = [
            row(0, "10", Some(1.0)),
            row(1, "10", Some(2.0)),
            row(2, "10", Some(4.0)),
            row(3, "20", Some(5.0)),
            row(4, "20", None),
            row(5, "20", Some(5.0)),
        ];
        let s = over_realisations(&m, &rows);
        assert_eq!(s.len(), 2);
        assert_eq!((s[0].group.clone(), s[0].n), (vec!["10".to_string()], 3));
        // x̄ = 7/3, s² = ((4/3)² + (1/3)² + (5/3)²) / 2 = 7/3.
        assert!((s[0].mean - 7.0 / 3.0).abs() < 1e-12);
        assert!((s[0].std - (7.0f64 / 3.0).sqrt()).abs() < 1e-12);
        assert_eq!((s[0].min, s[0].max), (1.0, 4.0));
        assert_eq!((s[1].n, s[1].mean, s[1].std), (2, 5.0, 0.0));
        let csv = statistics_csv(&m, &s).unwrap();
        assert!(
            csv.starts_with("speed,extract,n,mean,std,min,max,mean_plus_3std\n10,a,3,"),
            "{csv}"
        );
    }
}
