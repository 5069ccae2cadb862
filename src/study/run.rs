//! Running a study's cases and joining their results.
//!
//! Layout of the output directory (a documented interface):
//!
//! | path | what |
//! |---|---|
//! | `study.json` | the study's identity: id, name, number of cases, axes, extracts |
//! | `cases/NNNNN/scenario.toml` | the case's scenario (relative paths from the base scenario's directory) |
//! | `cases/NNNNN/WHEELSET.csv` | the run's wheelset CSVs (`kecsim run --csv` columns), written as it goes |
//! | `cases/NNNNN/summary.json` | the run summary (`kecsim run --json`) |
//! | `cases/NNNNN/result.json` | the case's row: axis values, status, extracts, diagnosis — written last: a case without it is not finished |
//! | `results.csv` | one row per case, in case order (written when every case is finished) |
//! | `statistics.csv` | with a `seeds` axis: each extract over the realisations, per combination of the other axes |
//! | `critical_speeds.csv` | a critical-speed study: the linear and nonlinear critical speeds |
//!
//! A case is run at most once per study: a rerun (or another shard) skips every case whose
//! `result.json` belongs to this study (same id, same scenario). Cases are split between shards
//! round-robin (case k belongs to shard k mod N), so that the shards of a sweep get alike loads.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use rayon::prelude::*;

use super::case::{check_name, check_result, printable, shown, CaseResult, Manifest};
use super::spec::{value_text, Case, Fnv, Study, MAX_CASES};
use super::StudyError;
use crate::dynamics::output::CsvWriter;
use crate::dynamics::run::RunFailure;
use crate::dynamics::{CancelToken, RunEnd, RunObserver, Stop, Threads};
use crate::scenario::{PreprocessingCache, RunOptions, Scenario};

/// How to run a study.
#[derive(Debug, Clone)]
pub struct StudyOptions {
    /// Cases run at once (each on one thread).
    pub jobs: usize,
    /// `(I, N)`: run only the I-th of N slices (0-based).
    pub shard: Option<(usize, usize)>,
    pub out: PathBuf,
    /// Stops the running cases at their next step (not marked finished) and starts no new one
    /// (the binary's Ctrl-C).
    pub cancel: CancelToken,
}

/// What one invocation did.
#[derive(Debug, Clone, Default)]
pub struct StudyRunReport {
    /// Cases of this shard.
    pub assigned: usize,
    /// Run now.
    pub ran: usize,
    /// Found finished (a rerun).
    pub skipped: usize,
    /// Of those run now, how many did not complete (failed, derailed, stopped).
    pub not_completed: usize,
    /// Wall time of the whole invocation, the sum of the cases' own and of their integrations, s.
    pub wall_s: f64,
    pub case_wall_s: f64,
    pub run_wall_s: f64,
    /// Simulated time of the cases run now, s.
    pub simulated_s: f64,
    /// Stopped by an interrupt before every case was run.
    pub interrupted: bool,
}

/// The folder of case `k`.
pub fn case_dir(out: &Path, k: usize) -> PathBuf {
    out.join("cases").join(format!("{k:05}"))
}

fn scenario_hash(text: &str) -> String {
    let mut h = Fnv::new();
    h.add(text.as_bytes());
    format!("{:016x}", h.finish())
}

fn io(path: &Path, e: impl std::fmt::Display) -> StudyError {
    StudyError::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    }
}

/// Writes `text` to `path` through a temporary file and a rename (a reader never sees half).
fn write_atomic(path: &Path, text: &str) -> Result<(), StudyError> {
    crate::files::write_atomic(path, text.as_bytes()).map_err(|e| io(path, e))
}

/// Largest `study.json` or `result.json` read (a case's row is a few kB; a manifest of
/// [`MAX_CASES`] axes' names well under this).
const MAX_STUDY_FILE_BYTES: u64 = 64 << 20;

/// A study file kecsim wrote (`study.json`, a case's `result.json`) as text: a regular file,
/// not a link, at most [`MAX_STUDY_FILE_BYTES`] — a FIFO, a link to `/dev/zero` or a huge file
/// planted in the tree is an error naming it, never a hang or an abort.
fn read_study_file(path: &Path) -> std::io::Result<String> {
    let bytes = crate::files::read_bounded(path, MAX_STUDY_FILE_BYTES, true)?;
    String::from_utf8(bytes).map_err(|_| std::io::Error::other("not UTF-8 text"))
}

/// Reads `study.json` of `out` (None where there is none).
pub fn read_manifest(out: &Path) -> Result<Option<Manifest>, StudyError> {
    let path = out.join("study.json");
    match read_study_file(&path) {
        Ok(text) => {
            let m: Manifest =
                serde_json::from_str(&text).map_err(|e| io(&path, format!("not a study manifest: {e}")))?;
            check_manifest(&m).map_err(|problem| io(&path, problem))?;
            Ok(Some(m))
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(io(&path, e)),
    }
}

/// A manifest's counts held to the study's own limits, as a study file's are: `cases` within
/// 1 ..= [`MAX_CASES`] (`--no-limits` lifts the upper one), no more axes or extracts than a study
/// may have, the seed axes among the axes. (A `cases` of 1e8 made `study merge` allocate for
/// 1e8 results and abort.)
fn check_manifest(m: &Manifest) -> Result<(), String> {
    if m.cases == 0 || (m.cases > MAX_CASES && !crate::limits::lifted()) {
        return Err(format!(
            "cases = {}: expected 1 ..= {MAX_CASES} (a study's limit; --no-limits lifts it)",
            m.cases
        ));
    }
    if m.axes.len() > MAX_MANIFEST_NAMES || m.extracts.len() > MAX_MANIFEST_NAMES {
        return Err(format!(
            "{} axes and {} extracts: expected at most {MAX_MANIFEST_NAMES} of each",
            m.axes.len(),
            m.extracts.len()
        ));
    }
    if let Some(k) = m.seed_axes.iter().find(|&&k| k >= m.axes.len()) {
        return Err(format!(
            "seed_axes names axis {k}, but there are {} axes",
            m.axes.len()
        ));
    }
    Ok(())
}

/// Most axes, and most extracts, a manifest may name.
const MAX_MANIFEST_NAMES: usize = 10_000;

/// The finished result of case `k` in `out`, where there is one for this study and scenario.
/// (A row that does not pass [`check_result`] is not finished: the case runs again.)
fn finished(out: &Path, manifest: &Manifest, case: &Case) -> Option<CaseResult> {
    let text = read_study_file(&case_dir(out, case.index).join("result.json")).ok()?;
    let r: CaseResult = serde_json::from_str(&text).ok()?;
    (r.study_id == manifest.id
        && r.case == case.index
        && r.scenario_hash == scenario_hash(&case.scenario)
        && check_result(&r, manifest).is_ok())
    .then_some(r)
}

/// Runs the study's cases (of its shard) that are not finished yet, `jobs` at a time; `done`
/// hears of each case as it ends (and of each skipped one, with `true`).
pub fn run_study(
    study: &Study,
    options: &StudyOptions,
    done: &(dyn Fn(&CaseResult, bool) + Sync),
) -> Result<StudyRunReport, StudyError> {
    let t0 = Instant::now();
    let out = &options.out;
    if let Some((i, n)) = options.shard {
        if n == 0 || i >= n {
            return Err(StudyError::Shard(format!(
                "shard {i}/{n}: expected 0 <= I < N (N >= 1)"
            )));
        }
    }
    std::fs::create_dir_all(out.join("cases")).map_err(|e| io(out, e))?;
    let manifest = Manifest::of(study);
    match read_manifest(out)? {
        Some(m) if m.id != manifest.id => {
            return Err(StudyError::OtherStudy {
                dir: out.display().to_string(),
                found: format!("{} ({})", printable(&m.name), printable(&m.id)),
                this: format!("{} ({})", manifest.name, manifest.id),
            })
        }
        // (Rewritten for the same study too: a manifest of an earlier kecsim may lack fields.)
        _ => write_atomic(
            &out.join("study.json"),
            &serde_json::to_string_pretty(&manifest).map_err(|e| io(out, e))?,
        )?,
    }
    let mine: Vec<&Case> = study
        .cases
        .iter()
        .filter(|c| options.shard.is_none_or(|(i, n)| c.index % n == i))
        .collect();
    let mut report = StudyRunReport {
        assigned: mine.len(),
        ..Default::default()
    };
    let mut pending = Vec::new();
    for c in mine {
        match finished(out, &manifest, c) {
            Some(r) => {
                report.skipped += 1;
                done(&r, true);
            }
            None => pending.push(c),
        }
    }
    // The wheelsets the extracts name: checked once, on the first pending case's vehicle, before
    // any case runs (a misspelt name must not cost a study).
    // The contact preprocessing of cases with the same profiles and contact settings is shared.
    let cache = PreprocessingCache::default();
    if let Some(first) = pending.first() {
        let names = vehicle_wheelsets(study, first, &cache)?;
        for (x, line) in study.extracts.iter().zip(&study.extract_lines) {
            x.check(&names).map_err(|m| StudyError::Input {
                path: study.path.display().to_string(),
                line: *line,
                message: m,
            })?;
        }
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(options.jobs.max(1))
        .build()
        .map_err(|e| StudyError::Shard(format!("cannot start {} threads: {e}", options.jobs)))?;
    let interrupted = AtomicBool::new(false);
    let results: Vec<Result<Option<CaseResult>, StudyError>> = pool.install(|| {
        pending
            .par_iter()
            .with_max_len(1)
            .map(|c| {
                if options.cancel.requested() {
                    interrupted.store(true, Ordering::Relaxed);
                    return Ok(None);
                }
                let r = run_case(study, c, out, Some(&cache), &options.cancel)?;
                if let Some(r) = &r {
                    done(r, false);
                } else {
                    interrupted.store(true, Ordering::Relaxed);
                }
                Ok(r)
            })
            .collect()
    });
    for r in results {
        if let Some(r) = r? {
            report.ran += 1;
            report.case_wall_s += r.wall_s;
            report.run_wall_s += r.run_wall_s;
            report.simulated_s += r.simulated_s;
            if r.status != "completed" {
                report.not_completed += 1;
            }
        }
    }
    report.interrupted = interrupted.into_inner();
    report.wall_s = t0.elapsed().as_secs_f64();
    Ok(report)
}

/// The wheelset names of a case's vehicle (its scene built once).
fn vehicle_wheelsets(
    study: &Study,
    case: &Case,
    cache: &PreprocessingCache,
) -> Result<Vec<String>, StudyError> {
    let origin = format!("{} case {}", study.path.display(), case.index);
    let fail = |m: String| StudyError::Input {
        path: study.path.display().to_string(),
        line: 0,
        message: format!("case {}: {m}", case.index),
    };
    let scene = Scenario::parse(&case.scenario, &origin)
        .and_then(|s| s.compile(&origin, study.scenario_dir()))
        .map_err(|e| fail(e.to_string()))?;
    let built = scene
        .build_run_cached(&RunOptions::default(), Some(cache))
        .map_err(|e| fail(e.to_string()))?;
    Ok(built.vehicle.wheelset_names())
}

/// Runs one case into its folder and writes its `result.json` (None: interrupted — nothing is
/// marked finished, so that a rerun runs it again: `cancel` asked). `cache` shares the contact
/// preprocessing between cases. The case runs on the calling thread's pool (a study's: one case
/// per thread).
pub fn run_case(
    study: &Study,
    case: &Case,
    out: &Path,
    cache: Option<&PreprocessingCache>,
    cancel: &CancelToken,
) -> Result<Option<CaseResult>, StudyError> {
    let dir = case_dir(out, case.index);
    std::fs::create_dir_all(&dir).map_err(|e| io(&dir, e))?;
    write_atomic(&dir.join("scenario.toml"), &case.scenario)?;
    let t0 = Instant::now();
    let mut result = CaseResult {
        study_id: study.id.clone(),
        case: case.index,
        scenario_hash: scenario_hash(&case.scenario),
        values: case.values.iter().map(value_text).collect(),
        status: "failed".into(),
        extracts: vec![None; study.extracts.len()],
        diagnosis: String::new(),
        wheelsets: Vec::new(),
        wall_s: 0.0,
        run_wall_s: 0.0,
        simulated_s: 0.0,
    };
    let origin = dir.join("scenario.toml").display().to_string();
    let built = Scenario::parse(&case.scenario, &origin)
        .and_then(|s| s.compile(&origin, study.scenario_dir()))
        .map_err(|e| e.to_string())
        .and_then(|scene| {
            let options = RunOptions {
                threads: Threads::Caller,
                cancel: cancel.clone(),
                ..RunOptions::default()
            };
            scene.build_run_cached(&options, cache).map_err(|e| e.to_string())
        });
    match built {
        Err(e) => result.diagnosis = format!("not run: {e}"),
        Ok(built) => {
            let names = built.vehicle.wheelset_names();
            // The linear stability at the case's speed, where an extract asks for it (a failure
            // is the case's diagnosis; the run goes on).
            let mut linear_note = None;
            let linear = if study.extracts.iter().any(|x| x.needs_linear()) {
                match crate::dynamics::linear::linear_stability(
                    built.vehicle.as_ref(),
                    &built.settings.integrator,
                ) {
                    Ok(l) => l,
                    Err(e) => {
                        linear_note = Some(format!("linearisation failed: {e}"));
                        None
                    }
                }
            } else {
                None
            };
            let carbodies = crate::dynamics::output::floor_carbodies(&built.vehicle.floor_points());
            let mut csv = CsvWriter::create(&dir, &names, &carbodies).map_err(|e| io(&dir, e))?;
            let output = {
                let mut observers: Vec<&mut (dyn RunObserver + Send)> = vec![&mut csv];
                built.run(&mut observers)
            };
            if let RunEnd::Stopped(Stop::Interrupted { .. }) = output.end {
                return Ok(None);
            }
            // The case's files could not be written (a full disk): an error of the study, not
            // the case's outcome — no result.json, so that a rerun runs the case again.
            if let RunEnd::Failed(RunFailure::Observer(e)) = &output.end {
                return Err(io(&dir, e));
            }
            let summary = &output.summary;
            write_atomic(
                &dir.join("summary.json"),
                &serde_json::to_string_pretty(summary).map_err(|e| io(&dir, e))?,
            )?;
            result.status = summary.outcome.to_string();
            result.diagnosis = [summary.error.clone(), summary.stopped.clone(), linear_note]
                .into_iter()
                .flatten()
                .collect::<Vec<_>>()
                .join("; ");
            result.extracts = study
                .extracts
                .iter()
                .map(|x| x.value(&output, linear.as_ref()))
                .collect();
            result.wheelsets = names;
            result.simulated_s = summary.simulated_s;
            result.run_wall_s = summary.wall_s;
        }
    }
    result.wall_s = t0.elapsed().as_secs_f64();
    write_atomic(
        &dir.join("result.json"),
        &serde_json::to_string_pretty(&result).map_err(|e| io(&dir, e))?,
    )?;
    Ok(Some(result))
}

/// Every case's result in `out`, in case order, checked to belong to its study; a missing case is
/// an error naming it (and the shard it belongs to, for `shards` N).
pub fn collect(out: &Path) -> Result<(Manifest, Vec<CaseResult>), StudyError> {
    let manifest = read_manifest(out)?.ok_or_else(|| {
        io(
            &out.join("study.json"),
            "no study here (a study's output directory has study.json)",
        )
    })?;
    // (Not more up front than a real study has, whatever the manifest says with --no-limits.)
    let mut rows = Vec::with_capacity(manifest.cases.min(MAX_CASES));
    let mut missing = Vec::new();
    for k in 0..manifest.cases {
        let path = case_dir(out, k).join("result.json");
        let text = match read_study_file(&path) {
            Ok(t) => t,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                missing.push(k);
                continue;
            }
            Err(e) => return Err(io(&path, e)),
        };
        let r: CaseResult = serde_json::from_str(&text)
            .map_err(|e| io(&path, format!("not a case result: {}", printable(&e.to_string()))))?;
        if r.study_id != manifest.id || r.case != k {
            return Err(StudyError::OtherStudy {
                dir: path.display().to_string(),
                found: format!("case {} of study {}", r.case, shown(&r.study_id)),
                this: format!(
                    "case {k} of study {} ({})",
                    printable(&manifest.name),
                    printable(&manifest.id)
                ),
            });
        }
        // (A tampered row — a value too many, an unknown status — said so here, naming the key:
        // before, it surfaced as "results.csv: CSV error".)
        check_result(&r, &manifest).map_err(|m| io(&path, format!("case {k}: {m}")))?;
        rows.push(r);
    }
    if !missing.is_empty() {
        return Err(StudyError::Missing {
            dir: out.display().to_string(),
            count: missing.len(),
            of: manifest.cases,
            cases: abbreviate(&missing),
        });
    }
    Ok((manifest, rows))
}

/// `0, 2, 4, … (12 in all)`.
fn abbreviate(k: &[usize]) -> String {
    let head: Vec<String> = k.iter().take(12).map(|k| k.to_string()).collect();
    if k.len() > 12 {
        format!("{}, … ({} in all)", head.join(", "), k.len())
    } else {
        head.join(", ")
    }
}

/// The results table: `case, status, AXIS…, EXTRACT…, diagnosis` (empty cells where a run gives
/// no value). Its content depends on the cases' results only (no timing), so that a sharded
/// study merged and the same study run whole give the same file.
pub fn results_csv(manifest: &Manifest, rows: &[CaseResult]) -> Result<String, StudyError> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let mut header = vec!["case".to_string(), "status".to_string()];
    header.extend(manifest.axes.iter().cloned());
    header.extend(manifest.extracts.iter().cloned());
    header.push("diagnosis".into());
    let e = |e: csv::Error| io(Path::new("results.csv"), e);
    w.write_record(&header).map_err(e)?;
    for r in rows {
        let mut rec = vec![r.case.to_string(), r.status.clone()];
        rec.extend(r.values.iter().cloned());
        rec.extend(
            r.extracts
                .iter()
                .map(|v| v.map_or(String::new(), |v| format!("{v}"))),
        );
        rec.push(r.diagnosis.clone());
        w.write_record(&rec).map_err(e)?;
    }
    let bytes = w
        .into_inner()
        .map_err(|x| io(Path::new("results.csv"), x.error()))?;
    String::from_utf8(bytes).map_err(|x| io(Path::new("results.csv"), x))
}

/// Joins the results of `out` into `out/results.csv` (every case must be finished), for a study
/// with a `seeds` axis `out/statistics.csv` (each extract over the realisations), and for a
/// critical-speed study `out/critical_speeds.csv`; each written whole or not at all. Returns the
/// path of `results.csv` ([`write_merged`] returns every file written).
pub fn merge(out: &Path) -> Result<(Manifest, Vec<CaseResult>, PathBuf), StudyError> {
    let (manifest, rows) = collect(out)?;
    write_merged(out, &manifest, &rows)?;
    Ok((manifest, rows, out.join("results.csv")))
}

/// The files of [`merge`] from the rows [`collect`] read (the files written, `results.csv`
/// first).
pub fn write_merged(
    out: &Path,
    manifest: &Manifest,
    rows: &[CaseResult],
) -> Result<Vec<PathBuf>, StudyError> {
    let path = out.join("results.csv");
    write_atomic(&path, &results_csv(manifest, rows)?)?;
    let mut written = vec![path];
    if !manifest.seed_axes.is_empty() {
        let list = super::statistics::over_realisations(manifest, rows);
        let path = out.join("statistics.csv");
        write_atomic(&path, &super::statistics::statistics_csv(manifest, &list)?)?;
        written.push(path);
    }
    if let Some(threshold) = manifest.critical_speed_threshold_mm {
        let list = super::critical::critical_speeds(manifest, rows, threshold);
        let path = out.join("critical_speeds.csv");
        write_atomic(&path, &super::critical::critical_csv(&list))?;
        written.push(path);
    }
    Ok(written)
}

/// Largest wheelset CSV of a case a merge reads, bytes (an hour simulated at 100 Hz is ~0.2 GB).
pub const MAX_CASE_CSV_BYTES: u64 = 4 << 30;

/// A case's first wheelset's (t, y): s and mm, from its CSV (empty where the case has no
/// wheelset or its CSV was removed). The CSV is read as a study file is: its name checked as a
/// name (`case::check_name`: never a path out of the case's folder), a regular file only (a FIFO, a
/// device or a link at it is an error naming it, never a hang), at most
/// [`MAX_CASE_CSV_BYTES`]; a row that does not read is an error naming the file, the line and
/// the value.
pub fn front_wheelset_y(out: &Path, r: &CaseResult) -> Result<Vec<(f64, f64)>, StudyError> {
    let Some(name) = r.wheelsets.first() else {
        return Ok(Vec::new());
    };
    let dir = case_dir(out, r.case);
    check_name(name).map_err(|m| {
        io(
            &dir.join("result.json"),
            format!(
                "case {}: \"wheelsets\"[0] = {}: not a wheelset name: {m}",
                r.case,
                shown(name)
            ),
        )
    })?;
    let path = dir.join(format!("{name}.csv"));
    let file = match crate::files::open_regular(&path, true) {
        Ok(f) => f,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(io(&path, e)),
    };
    let len = file.metadata().map_err(|e| io(&path, e))?.len();
    if len > MAX_CASE_CSV_BYTES {
        return Err(io(
            &path,
            format!("{len} bytes, more than the {MAX_CASE_CSV_BYTES} bytes a case's CSV may have"),
        ));
    }
    use std::io::Read;
    let mut rd = csv::Reader::from_reader(std::io::BufReader::new(file.take(MAX_CASE_CSV_BYTES)));
    let header = rd.headers().map_err(|e| io(&path, e))?.clone();
    let column = |c: &str| {
        header.iter().position(|h| h == c).ok_or_else(|| {
            io(
                &path,
                format!("line 1: no column `{c}` (not a wheelset CSV of `kecsim run --csv`)"),
            )
        })
    };
    let (t, y) = (column("t_s")?, column("y_mm")?);
    let mut points = Vec::new();
    for rec in rd.records() {
        let rec = rec.map_err(|e| io(&path, e))?;
        let line = rec.position().map_or(0, |p| p.line());
        let cell = |k: usize, c: &str| -> Result<f64, StudyError> {
            let v = rec.get(k).unwrap_or("");
            v.trim()
                .parse()
                .map_err(|_| io(&path, format!("line {line}: {c} = {}: not a number", shown(v))))
        };
        points.push((cell(t, "t_s")?, cell(y, "y_mm")?));
    }
    Ok(points)
}

/// The results table in Markdown (the recording's report, printed by the command), with the
/// study's name above it; every string from the study's files [`printable`].
pub fn results_markdown(manifest: &Manifest, rows: &[CaseResult]) -> String {
    // (What the files say, every control character made visible: the report is printed.)
    let (manifest, rows) = &super::case::printable_copies(manifest, rows);
    let mut header = vec!["case".to_string(), "status".to_string()];
    header.extend(manifest.axes.iter().cloned());
    header.extend(manifest.extracts.iter().cloned());
    header.push("diagnosis".into());
    let mut s = format!(
        "# Study: {}\n\n{} cases ({} completed); study id {}.\n\n",
        manifest.name,
        rows.len(),
        rows.iter().filter(|r| r.status == "completed").count(),
        manifest.id,
    );
    if let Some(threshold) = manifest.critical_speed_threshold_mm {
        let list = super::critical::critical_speeds(manifest, rows, threshold);
        s.push_str(&super::critical::critical_markdown(&list, threshold));
        s.push_str("\n## Cases\n\n");
    }
    if !manifest.seed_axes.is_empty() {
        let list = super::statistics::over_realisations(manifest, rows);
        s.push_str(&super::statistics::statistics_markdown(manifest, &list));
        s.push_str("\n## Cases\n\n");
    }
    s.push_str(&format!(
        "| {} |\n|{}\n",
        header.join(" | "),
        "---|".repeat(header.len())
    ));
    for r in rows {
        let mut cells = vec![r.case.to_string(), r.status.clone()];
        cells.extend(r.values.iter().cloned());
        cells.extend(
            r.extracts
                .iter()
                .map(|v| v.map_or("—".into(), |v| format!("{v:.4}"))),
        );
        cells.push(r.diagnosis.replace('|', "/"));
        s.push_str(&format!("| {} |\n", cells.join(" | ")));
    }
    s
}
