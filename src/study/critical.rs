//! The critical speeds of a critical-speed study (see [`super::spec::CriticalSpeedSettings`]),
//! from its results table: per group of cases (the values of the axes after the speed sweep's
//! own, e.g. a friction), the **linear** critical speed — where the least-damped oscillatory
//! mode's Re λ crosses zero between two speeds of the sweep, interpolated linearly — and the
//! **nonlinear** one — the lowest speed at which a hunting limit cycle lives (amplitude over the
//! run's last quarter above the threshold; a derailment or a failed run counts as hunting),
//! bracketed by the sweep's step.

use std::fmt::Write;

use super::case::{first_appearances, CaseResult, Manifest};

/// The axes a critical-speed study sets itself (its first four).
pub const OWN_AXES: usize = 4;

/// One group's critical speeds.
#[derive(Debug, Clone, PartialEq)]
pub struct CriticalSpeeds {
    /// The other axes' values (`key = value, …`; empty without other axes).
    pub group: String,
    /// Linear critical speed, m/s, and the frequency of the unstable mode at the sweep's first
    /// unstable speed, Hz.
    pub linear_m_s: Option<f64>,
    pub linear_hz: Option<f64>,
    /// The sweep's speeds bracketing the nonlinear critical speed, m/s: the fastest without a
    /// limit cycle below the slowest with one (None at an end: outside the sweep).
    pub nonlinear_above_m_s: Option<f64>,
    pub nonlinear_at_most_m_s: Option<f64>,
    /// What the figures mean where the sweep does not bracket them.
    pub note: String,
}

fn column(manifest: &Manifest, name: &str) -> Option<usize> {
    manifest.extracts.iter().position(|x| x == name)
}

/// The critical speeds of each group (`threshold_mm`: the hunting amplitude).
pub fn critical_speeds(manifest: &Manifest, rows: &[CaseResult], threshold_mm: f64) -> Vec<CriticalSpeeds> {
    let (Some(amp), Some(re), Some(hz)) = (
        column(manifest, "amplitude(*.y_mm)"),
        column(manifest, "linear_max_real_1_s"),
        column(manifest, "linear_hunting_hz"),
    ) else {
        return Vec::new();
    };
    let group_of = |r: &CaseResult| r.axes_text(&manifest.axes, |k| k >= OWN_AXES);
    let groups = first_appearances(rows.iter().map(group_of));
    groups
        .into_iter()
        .map(|g| {
            let mut cases: Vec<(f64, &CaseResult)> = rows
                .iter()
                .filter(|r| group_of(r) == g)
                .filter_map(|r| Some((r.values.first()?.parse::<f64>().ok()?, r)))
                .collect();
            cases.sort_by(|a, b| a.0.total_cmp(&b.0));
            let mut notes = Vec::new();
            // Linear: the first crossing of Re λ from ≤ 0 to > 0.
            let lin: Vec<(f64, f64, f64)> = cases
                .iter()
                .filter_map(|(v, r)| Some((*v, r.extracts.get(re).copied()??, r.extracts.get(hz).copied()??)))
                .collect();
            let mut linear = None;
            for w in lin.windows(2) {
                let ((va, ra, _), (vb, rb, fb)) = (w[0], w[1]);
                if ra <= 0.0 && rb > 0.0 {
                    // (The largest Re λ over the modes is continuous in speed even where the
                    // least-damped mode changes: interpolating it is sound; the frequency is the
                    // unstable mode's, at the faster speed.)
                    let u = -ra / (rb - ra);
                    linear = Some((va + u * (vb - va), fb));
                    break;
                }
            }
            if linear.is_none() {
                match (lin.first(), lin.last()) {
                    (Some(f), _) if f.1 > 0.0 => {
                        notes.push(format!("linearly unstable already at {} m/s", f.0))
                    }
                    (_, Some(l)) => notes.push(format!("linearly stable up to {} m/s", l.0)),
                    _ => notes.push("no linear stability figures".to_string()),
                }
            }
            // Nonlinear: the slowest speed with a limit cycle.
            let hunts = |r: &CaseResult| {
                matches!(r.status.as_str(), "derailed" | "failed")
                    || r.extracts
                        .get(amp)
                        .copied()
                        .flatten()
                        .is_some_and(|a| a > threshold_mm)
            };
            let first = cases.iter().position(|(_, r)| hunts(r));
            let (above, at_most) = match first {
                Some(0) => {
                    notes.push(format!(
                        "a limit cycle already at {} m/s, the sweep's slowest",
                        cases[0].0
                    ));
                    (None, Some(cases[0].0))
                }
                Some(k) => (Some(cases[k - 1].0), Some(cases[k].0)),
                None => {
                    if let Some(l) = cases.last() {
                        notes.push(format!("no limit cycle up to {} m/s", l.0));
                    }
                    (cases.last().map(|c| c.0), None)
                }
            };
            if let Some(k) = first {
                if let Some((v, _)) = cases[k..].iter().find(|(_, r)| !hunts(r)) {
                    notes.push(format!(
                        "no limit cycle again at {v} m/s (released from the same amplitude)"
                    ));
                }
            }
            CriticalSpeeds {
                group: g,
                linear_m_s: linear.map(|l| l.0),
                linear_hz: linear.map(|l| l.1),
                nonlinear_above_m_s: above,
                nonlinear_at_most_m_s: at_most,
                note: notes.join("; "),
            }
        })
        .collect()
}

/// The critical speeds as CSV (`critical_speeds.csv`).
pub fn critical_csv(list: &[CriticalSpeeds]) -> String {
    let f = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v}"));
    let mut s = String::from(
        "group,linear_critical_speed_m_s,linear_hunting_hz,nonlinear_above_m_s,nonlinear_at_most_m_s,note\n",
    );
    for c in list {
        let q = |t: &str| format!("\"{}\"", t.replace('"', "\"\""));
        let _ = writeln!(
            s,
            "{},{},{},{},{},{}",
            q(&c.group),
            f(c.linear_m_s),
            f(c.linear_hz),
            f(c.nonlinear_above_m_s),
            f(c.nonlinear_at_most_m_s),
            q(&c.note)
        );
    }
    s
}

/// The critical speeds in Markdown (printed and in the recording's report).
pub fn critical_markdown(list: &[CriticalSpeeds], threshold_mm: f64) -> String {
    let mut s = format!(
        "## Critical speeds\n\nLinear: Re λ of the least-damped oscillatory mode crosses 0 (interpolated). \
         Nonlinear: the slowest speed of the sweep with a limit cycle (amplitude over the last quarter > {threshold_mm} mm), \
         bracketed by the sweep's step.\n\n| group | linear [m/s] | unstable mode [Hz] | nonlinear [m/s] | note |\n|---|---|---|---|---|\n"
    );
    for c in list {
        let nonlinear = match (c.nonlinear_above_m_s, c.nonlinear_at_most_m_s) {
            (Some(a), Some(b)) => format!("{a} < v ≤ {b}"),
            (None, Some(b)) => format!("≤ {b}"),
            (Some(a), None) => format!("> {a}"),
            (None, None) => "—".into(),
        };
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} |",
            if c.group.is_empty() { "all" } else { &c.group },
            c.linear_m_s.map_or("—".into(), |v| format!("{v:.2}")),
            c.linear_hz.map_or("—".into(), |v| format!("{v:.2}")),
            nonlinear,
            c.note
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(case: usize, speed: f64, amp: f64, re: f64, status: &str) -> CaseResult {
        CaseResult {
            study_id: "x".into(),
            case,
            scenario_hash: String::new(),
            values: vec![format!("{speed}"), "0".into(), "0.004".into(), "10".into()],
            status: status.into(),
            extracts: vec![Some(amp), Some(re), Some(2.0 + speed / 10.0)],
            diagnosis: String::new(),
            wheelsets: vec![],
            wall_s: 0.0,
            run_wall_s: 0.0,
            simulated_s: 0.0,
        }
    }

    #[test]
    fn the_crossings_are_found_between_the_right_speeds() {
        let m = Manifest {
            id: "x".into(),
            name: "x".into(),
            cases: 5,
            axes: vec![
                "simulation.speed_m_s".into(),
                "simulation.speed_ramp_m_s2".into(),
                "simulation.initial.lateral_m".into(),
                "simulation.duration_s".into(),
            ],
            extracts: vec![
                "amplitude(*.y_mm)".into(),
                "linear_max_real_1_s".into(),
                "linear_hunting_hz".into(),
            ],
            critical_speed_threshold_mm: Some(0.1),
            seed_axes: vec![],
        };
        // Re λ = (v − 47) / 10: crosses at 47 m/s; cycles from 40 m/s on.
        let rows: Vec<CaseResult> = [30.0, 35.0, 40.0, 45.0, 50.0]
            .iter()
            .enumerate()
            .map(|(k, &v)| {
                row(
                    k,
                    v,
                    if v >= 40.0 { 3.0 } else { 0.01 },
                    (v - 47.0) / 10.0,
                    "completed",
                )
            })
            .collect();
        let c = critical_speeds(&m, &rows, 0.1);
        assert_eq!(c.len(), 1);
        assert!((c[0].linear_m_s.unwrap() - 47.0).abs() < 1e-9);
        assert!((c[0].linear_hz.unwrap() - 7.0).abs() < 1e-9);
        assert_eq!(
            (c[0].nonlinear_above_m_s, c[0].nonlinear_at_most_m_s),
            (Some(35.0), Some(40.0))
        );
        assert!(c[0].note.is_empty(), "{}", c[0].note);
        // A derailment counts as hunting; no crossing: said so.
        let mut rows2 = rows.clone();
        for r in &mut rows2 {
            r.extracts[0] = Some(0.0);
            r.extracts[1] = Some(-1.0);
        }
        rows2[4].status = "derailed".into();
        let c = critical_speeds(&m, &rows2, 0.1);
        assert_eq!(
            (c[0].nonlinear_above_m_s, c[0].nonlinear_at_most_m_s),
            (Some(45.0), Some(50.0))
        );
        assert_eq!(c[0].linear_m_s, None);
        assert!(
            c[0].note.contains("linearly stable up to 50 m/s"),
            "{}",
            c[0].note
        );
    }
}
