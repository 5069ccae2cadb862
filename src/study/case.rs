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

/// The outcomes a case's `status` may be (a run's, [`crate::dynamics::run`]).
pub const STATUSES: [&str; 4] = ["completed", "stopped", "derailed", "failed"];

/// Longest wheelset name read from a case's `result.json`, in characters (its CSV is `NAME.csv`
/// in the case's folder: a file name, at most 255 bytes on common file systems).
pub const MAX_NAME_CHARS: usize = 200;

/// Most wheelsets a case's `result.json` may name.
pub const MAX_WHEELSETS: usize = 1000;

/// Checks `name`, read from a file, as a wheelset name before it becomes a file name (`NAME.csv`
/// in a case's folder): the vehicle's own rule for body names — ASCII letters, digits, `_`, `-`
/// and `.`, not `.` first, so no `/`, no `..` part, no NUL or control character — and 1 to
/// [`MAX_NAME_CHARS`] characters. The error says what is wrong with it.
pub fn check_name(name: &str) -> Result<(), String> {
    let n = name.chars().count();
    if n == 0 || n > MAX_NAME_CHARS {
        return Err(format!("{n} characters: expected 1 ..= {MAX_NAME_CHARS}"));
    }
    if name.starts_with('.') {
        return Err("starts with '.' (a hidden file, or `..`: outside the case's folder)".into());
    }
    if let Some(c) = name
        .chars()
        .find(|c| !(c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.')))
    {
        return Err(format!(
            "holds {}: expected ASCII letters, digits, '_', '-' or '.' (a name, never a path)",
            shown(&c.to_string())
        ));
    }
    Ok(())
}

/// `s` as it may be printed to a terminal or a report: every control character (ESC, CR,
/// newline, NUL, …) and every bidirectional override written as a visible escape (`\u{1b}`,
/// `\r`, `\n`), the rest as it is. A string read from a file goes through this before it is
/// printed, so that a tampered `result.json` cannot move the cursor, recolour or hide text.
pub fn printable(s: &str) -> std::borrow::Cow<'_, str> {
    let hidden = |c: char| {
        c.is_control()
            || matches!(c, '\u{200e}' | '\u{200f}' | '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}')
    };
    if !s.chars().any(hidden) {
        return std::borrow::Cow::Borrowed(s);
    }
    let mut out = String::with_capacity(s.len() + 8);
    for c in s.chars() {
        if hidden(c) {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    std::borrow::Cow::Owned(out)
}

/// Most characters of a value from a file an error message quotes.
const SHOWN_CHARS: usize = 80;

/// `s` quoted for an error message: [`printable`], in double quotes, cut after
/// [`SHOWN_CHARS`] characters (`…` and the full length).
pub fn shown(s: &str) -> String {
    let n = s.chars().count();
    if n <= SHOWN_CHARS {
        format!("\"{}\"", printable(s))
    } else {
        let head: String = s.chars().take(SHOWN_CHARS).collect();
        format!("\"{}…\" ({n} characters)", printable(&head))
    }
}

/// Checks a case's row read from its `result.json` against the study's manifest before any of
/// it is tabulated or used: one value per axis, one extract per extract column, a known status,
/// its wheelset names names ([`check_name`]). The error names the key, the value and what was
/// expected.
pub fn check_result(r: &CaseResult, manifest: &Manifest) -> Result<(), String> {
    if r.values.len() != manifest.axes.len() {
        return Err(format!(
            "\"values\" has {} entries, but the study (study.json) has {} axes: one value per axis",
            r.values.len(),
            manifest.axes.len()
        ));
    }
    if r.extracts.len() != manifest.extracts.len() {
        return Err(format!(
            "\"extracts\" has {} entries, but the study (study.json) has {} extracts: one per extract",
            r.extracts.len(),
            manifest.extracts.len()
        ));
    }
    if !STATUSES.contains(&r.status.as_str()) {
        return Err(format!(
            "\"status\" = {}: expected one of {}",
            shown(&r.status),
            STATUSES.join(", ")
        ));
    }
    if r.wheelsets.len() > MAX_WHEELSETS {
        return Err(format!(
            "\"wheelsets\" has {} names: expected at most {MAX_WHEELSETS}",
            r.wheelsets.len()
        ));
    }
    for (k, w) in r.wheelsets.iter().enumerate() {
        check_name(w).map_err(|m| format!("\"wheelsets\"[{k}] = {}: not a wheelset name: {m}", shown(w)))?;
    }
    for (key, v) in [
        ("wall_s", r.wall_s),
        ("run_wall_s", r.run_wall_s),
        ("simulated_s", r.simulated_s),
    ] {
        if !(v.is_finite() && v >= 0.0) {
            return Err(format!("\"{key}\" = {v}: expected a finite time ≥ 0 s"));
        }
    }
    Ok(())
}

/// Copies of a study's manifest and rows with every string [`printable`] (names, values,
/// statuses, diagnoses): what a report or the terminal shows of files a user can edit.
pub fn printable_copies(manifest: &Manifest, rows: &[CaseResult]) -> (Manifest, Vec<CaseResult>) {
    let p = |s: &String| printable(s).into_owned();
    let all = |v: &[String]| v.iter().map(p).collect::<Vec<_>>();
    let m = Manifest {
        id: p(&manifest.id),
        name: p(&manifest.name),
        axes: all(&manifest.axes),
        extracts: all(&manifest.extracts),
        ..manifest.clone()
    };
    let rows = rows
        .iter()
        .map(|r| CaseResult {
            study_id: p(&r.study_id),
            scenario_hash: p(&r.scenario_hash),
            values: all(&r.values),
            status: p(&r.status),
            diagnosis: p(&r.diagnosis),
            wheelsets: all(&r.wheelsets),
            ..r.clone()
        })
        .collect();
    (m, rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Names from a file are names: anything that would make `NAME.csv` a path elsewhere, a hidden
    /// file or a terminal's control sequence is refused, saying why.
    #[test]
    fn names_read_from_files_are_never_paths() {
        for ok in ["wheelset_1", "w1", "front-axle.2", "A"] {
            assert_eq!(check_name(ok), Ok(()), "{ok}");
        }
        let long = "a".repeat(MAX_NAME_CHARS + 1);
        for (bad, why) in [
            ("../../evil", "starts with '.'"),
            ("..", "starts with '.'"),
            (".hidden", "starts with '.'"),
            ("a/b", "holds \"/\""),
            ("a\\b", "holds \"\\\""),
            ("a\0b", "holds \"\\u{0}\""),
            ("a\u{1b}b", "holds \"\\u{1b}\""),
            ("a b", "holds \" \""),
            ("", "0 characters"),
            (long.as_str(), "201 characters"),
        ] {
            let e = check_name(bad).unwrap_err();
            assert!(e.contains(why), "{bad:?}: {e}");
        }
    }

    /// Control characters and bidirectional overrides become visible escapes; other text, accents
    /// and symbols included, is kept as it is.
    #[test]
    fn printable_escapes_every_control_character() {
        assert!(matches!(
            printable("speed = 19 m/s, μ 0.3 ≤ 1"),
            std::borrow::Cow::Borrowed(_)
        ));
        assert_eq!(
            printable("a\u{1b}[2Jb\r\n\t\0\u{7f}\u{9b}"),
            "a\\u{1b}[2Jb\\r\\n\\t\\u{0}\\u{7f}\\u{9b}"
        );
        assert_eq!(printable("x\u{202e}y"), "x\\u{202e}y");
        for c in (0u32..0x2070).filter_map(char::from_u32) {
            let p = printable(&c.to_string()).into_owned();
            assert!(!p.chars().any(|c| c.is_control()), "{c:?} → {p:?}");
        }
        let long = "é".repeat(100);
        assert!(shown(&long).ends_with("…\" (100 characters)"), "{}", shown(&long));
    }
}
