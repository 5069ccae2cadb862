//! `kecsim study STUDY.toml [--jobs N] [--out DIR] [--shard I/N]`: run a study's cases on all
//! cores (or the I-th of N slices of them), then join the results into one table and one
//! recording; `kecsim study merge DIR` joins the shards' results; `kecsim study slurm STUDY.toml`
//! writes the sbatch script of a job array that runs the shards.

use std::path::{Path, PathBuf};
use std::sync::Mutex;

use anyhow::{Context, Result};
use clap::{Args, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};

use kecsim::dynamics::CancelToken;
use kecsim::inspect::{self, Sink};
use kecsim::study::run::{collect, results_markdown, write_merged};
use kecsim::study::slurm::{sbatch_script, SlurmJob};
use kecsim::study::{run_study, CaseResult, Study, StudyOptions};

use super::SinkArgs;

#[derive(Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub(super) struct StudyArgs {
    #[command(subcommand)]
    command: Option<StudyCommand>,
    /// The study file (TOML): base scenario, axes, extracts (see the README).
    study: Option<PathBuf>,
    #[command(flatten)]
    run: RunStudyArgs,
}

#[derive(Args)]
struct RunStudyArgs {
    /// Cases run at once [default: SLURM_CPUS_PER_TASK where set, else every core].
    #[arg(long, value_name = "N")]
    jobs: Option<usize>,
    /// Output directory [default: ./NAME-study for NAME.toml].
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Run only the I-th of N slices of the cases (0-based; case k belongs to slice k mod N)
    /// [default: SLURM_ARRAY_TASK_ID / SLURM_ARRAY_TASK_COUNT where set].
    #[arg(long, value_name = "I/N")]
    shard: Option<String>,
    #[command(flatten)]
    sink: SinkArgs,
}

#[derive(Subcommand)]
enum StudyCommand {
    /// Join the finished cases of DIR (all shards) into DIR/results.csv and the recording.
    Merge {
        /// The study's output directory.
        dir: PathBuf,
        #[command(flatten)]
        sink: SinkArgs,
    },
    /// Write the sbatch script of a Slurm job array running the study in N shards, then merging.
    Slurm {
        /// The study file.
        study: PathBuf,
        /// Number of shards (array tasks).
        #[arg(long, default_value_t = 4)]
        shards: usize,
        /// Cores per shard (each runs that many cases at once).
        #[arg(long, default_value_t = 1)]
        cpus_per_task: usize,
        /// Output directory (on a file system every node sees) [default: ./NAME-study].
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
        /// Wall-time limit per task (Slurm's --time).
        #[arg(long, default_value = "01:00:00")]
        time: String,
        /// Partition (Slurm's --partition) [default: the cluster's default].
        #[arg(long)]
        partition: Option<String>,
        /// Write the script here instead of printing it.
        #[arg(long, value_name = "FILE")]
        script: Option<PathBuf>,
    },
}

pub(super) fn run(a: StudyArgs) -> Result<()> {
    match a.command {
        Some(StudyCommand::Merge { dir, sink }) => merge_dir(&dir, &sink),
        Some(StudyCommand::Slurm {
            study,
            shards,
            cpus_per_task,
            out,
            time,
            partition,
            script,
        }) => slurm(
            &study,
            shards,
            cpus_per_task,
            out,
            &time,
            partition.as_deref(),
            script,
        ),
        None => {
            let path = a
                .study
                .context("kecsim study: give a study file (kecsim study STUDY.toml), or `merge DIR`, or `slurm STUDY.toml`")?;
            run_file(&path, a.run)
        }
    }
}

/// `./NAME-study` for `NAME.toml`.
fn default_out(study: &Path) -> PathBuf {
    let stem = study
        .file_stem()
        .map_or("study".into(), |s| s.to_string_lossy().to_string());
    PathBuf::from(format!("{stem}-study"))
}

/// `I/N`, from the option or from Slurm's job-array variables.
fn shard(option: Option<&str>) -> Result<Option<(usize, usize)>> {
    let parse = |i: &str, n: &str, what: &str| -> Result<(usize, usize)> {
        let i: usize = i
            .trim()
            .parse()
            .with_context(|| format!("{what}: `{i}` is not a shard index"))?;
        let n: usize = n
            .trim()
            .parse()
            .with_context(|| format!("{what}: `{n}` is not a number of shards"))?;
        anyhow::ensure!(n >= 1 && i < n, "{what}: shard {i} of {n}: expected 0 <= I < N");
        Ok((i, n))
    };
    if let Some(s) = option {
        let (i, n) = s
            .split_once('/')
            .with_context(|| format!("--shard {s}: expected I/N, e.g. 0/4"))?;
        return parse(i, n, &format!("--shard {s}")).map(Some);
    }
    match (
        std::env::var("SLURM_ARRAY_TASK_ID"),
        std::env::var("SLURM_ARRAY_TASK_COUNT"),
    ) {
        (Ok(i), Ok(n)) => parse(&i, &n, "SLURM_ARRAY_TASK_ID/SLURM_ARRAY_TASK_COUNT").map(Some),
        _ => Ok(None),
    }
}

fn jobs(option: Option<usize>) -> Result<usize> {
    if let Some(n) = option {
        anyhow::ensure!(n >= 1, "--jobs {n}: expected at least 1");
        kecsim::limits::check_threads("--jobs", n).map_err(anyhow::Error::msg)?;
        return Ok(n);
    }
    let slurm = std::env::var("SLURM_CPUS_PER_TASK")
        .ok()
        .and_then(|v| v.parse().ok())
        .filter(|&n| n >= 1);
    if let Some(n) = slurm {
        kecsim::limits::check_threads("SLURM_CPUS_PER_TASK", n).map_err(anyhow::Error::msg)?;
    }
    Ok(slurm.unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get())))
}

/// The recording's sink: the options', else `DIR/study.rrd`.
fn study_sink(sink: &SinkArgs, dir: &Path) -> Sink {
    if sink.save.is_none() && !sink.spawn && sink.connect.is_none() {
        Sink::Save(dir.join("study.rrd"))
    } else {
        sink.sink()
    }
}

fn run_file(path: &Path, a: RunStudyArgs) -> Result<()> {
    let jobs = jobs(a.jobs)?;
    let study = Study::read(path)?;
    let shard = shard(a.shard.as_deref())?;
    let out = a.out.clone().unwrap_or_else(|| default_out(path));
    std::fs::create_dir_all(&out).with_context(|| format!("cannot create --out {}", out.display()))?;
    let sink = study_sink(&a.sink, &out);
    let inputs = study.input_files();
    inputs_outside_cases(&inputs, &out)?;
    // A shard writes only its cases; the whole study also the table and the recording.
    // (Shards run at once in one directory by design: each writes its own cases.)
    let _outputs = if shard.is_none() {
        let mut outputs = merge_outputs(&out).to_vec();
        outputs.push(out.join("study.json"));
        let cases = out.join("cases");
        Some(super::guard_trees(
            &inputs,
            &[&cases],
            &named(&outputs),
            Some(&sink),
        )?)
    } else {
        None
    };
    println!(
        "study: {} ({}): {} cases ({}), {} axes, {} extracts; id {}",
        study.name,
        path.display(),
        study.cases.len(),
        match study.sampling {
            kecsim::study::Sampling::Grid => "grid".to_string(),
            kecsim::study::Sampling::Random { samples } =>
                format!("{samples} random samples, seed {}", study.seed),
        },
        study.axes.len(),
        study.extracts.len(),
        study.id
    );
    if let Some((i, n)) = shard {
        println!("shard {i}/{n}: cases k with k mod {n} = {i}");
    }
    // Ctrl-C: the running cases stop at their next step (not marked finished), no new one starts.
    let cancel = CancelToken::new();
    super::stop_on_signals(
        &cancel,
        "stopping the running cases; finished ones are kept (a rerun skips them)",
    );
    let assigned = study
        .cases
        .iter()
        .filter(|c| shard.is_none_or(|(i, n)| c.index % n == i))
        .count();
    let bar = ProgressBar::new(assigned as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} cases  {elapsed} elapsed, ETA {eta}  {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let axes: Vec<String> = study.axes.iter().map(|a| a.key.clone()).collect();
    let lock = Mutex::new(());
    let done = |r: &CaseResult, skipped: bool| {
        let _g = lock.lock();
        let line = format!(
            "case {:>5} {}: {}{}{}",
            r.case,
            if skipped {
                "finished before, skipped"
            } else {
                r.status.as_str()
            },
            r.axes_text(&axes, |_| true),
            if skipped {
                String::new()
            } else {
                format!(" ({:.2} s wall)", r.wall_s)
            },
            if r.diagnosis.is_empty() || skipped {
                String::new()
            } else {
                format!(": {}", r.diagnosis)
            }
        );
        // (A skipped case's values and status come from its result.json: made printable.)
        let line = kecsim::study::printable(&line);
        if bar.is_hidden() {
            println!("{line}");
        } else {
            bar.println(line);
        }
        bar.inc(1);
    };
    let report = run_study(
        &study,
        &StudyOptions {
            jobs,
            shard,
            out: out.clone(),
            cancel,
        },
        &done,
    )?;
    bar.finish_and_clear();
    let per_min = |n: usize, s: f64| if s > 0.0 { 60.0 * n as f64 / s } else { 0.0 };
    let per_case = |s: f64| {
        if report.ran > 0 {
            s / report.ran as f64
        } else {
            0.0
        }
    };
    println!(
        "ran {} cases ({} not completed), {} finished before: {:.2} s wall on {jobs} jobs, {:.1} cases/min, {:.1} s simulated",
        report.ran,
        report.not_completed,
        report.skipped,
        report.wall_s,
        per_min(report.ran, report.wall_s),
        report.simulated_s
    );
    if report.ran > 0 {
        println!(
            "per case: {:.3} s integrating, {:.3} s preprocessing and writing (the overhead beyond the simulation); \
             {:.0} % of {jobs} cores busy with cases (the rest: cases of unequal length at the end, the study's own work)",
            per_case(report.run_wall_s),
            per_case(report.case_wall_s - report.run_wall_s),
            100.0 * report.case_wall_s / (report.wall_s * jobs as f64).max(1e-9),
        );
    }
    if report.interrupted {
        anyhow::bail!(
            "interrupted: {} cases finished are kept in {}; run the same command again to run the rest",
            report.ran + report.skipped,
            out.display()
        );
    }
    if shard.is_some() {
        println!(
            "shard done; when every shard is: kecsim study merge {}",
            out.display()
        );
        return Ok(());
    }
    finish(&out, &sink)
}

/// Writes the table and the recording of a finished study.
fn finish(out: &Path, sink: &Sink) -> Result<()> {
    let (manifest, rows) = collect(out)?;
    // The cases' CSVs read (bounded, each a regular file) before anything is written.
    let front_y = inspect::study::front_y_extent(out, &rows)?;
    for p in write_merged(out, &manifest, &rows)? {
        println!("wrote {}", p.display());
    }
    let markdown = results_markdown(&manifest, &rows);
    let delivered = {
        let rec = inspect::open_recording("kecsim", sink, || {
            inspect::study::blueprint_with(&manifest, front_y)
        })?;
        inspect::study::record(&rec, &manifest, &rows, &markdown, out)?;
        inspect::finish_recording(rec, sink)
    };
    print!("{}", markdown.replace("**", ""));
    println!("{}", delivered.map_err(anyhow::Error::msg)?);
    Ok(())
}

/// The files a merge writes in the study's directory (the sink's apart), guarded against the
/// inputs and the sink's file (`--save DIR/results.csv` would replace the table).
fn merge_outputs(dir: &Path) -> [PathBuf; 3] {
    [
        dir.join("results.csv"),
        dir.join("statistics.csv"),
        dir.join("critical_speeds.csv"),
    ]
}

/// [`merge_outputs`] as the guard takes them.
fn named(files: &[PathBuf]) -> Vec<(&'static str, Option<&Path>)> {
    files.iter().map(|p| ("--out", Some(p.as_path()))).collect()
}

/// A study whose own input (the study file, its scene, a file an axis names) lies in its output
/// tree `OUT/cases/` would write over it (case 0's `scenario.toml` is the case's scene): refused.
fn inputs_outside_cases(inputs: &[PathBuf], out: &Path) -> Result<()> {
    let cases = kecsim::files::resolved(&out.join("cases"));
    if let Some(p) = inputs
        .iter()
        .find(|p| kecsim::files::resolved(p).starts_with(&cases))
    {
        anyhow::bail!(
            "{}: this input of the study lies inside its output tree {} (whose files the study writes); move it out or choose another --out",
            p.display(),
            out.join("cases").display()
        );
    }
    Ok(())
}

fn merge_dir(dir: &Path, sink: &SinkArgs) -> Result<()> {
    let sink = study_sink(sink, dir);
    let manifest = dir.join("study.json");
    let cases = dir.join("cases");
    let _outputs = super::guard_trees(&[&manifest], &[&cases], &named(&merge_outputs(dir)), Some(&sink))?;
    finish(dir, &sink)
}

/// The sbatch script: a job array of `shards` tasks, each `kecsim study` on its slice (the shard
/// from SLURM_ARRAY_TASK_ID/COUNT), and a merge job that runs once every task has ended well
/// ([`kecsim::study::slurm::sbatch_script`]: every value checked and quoted there).
fn slurm(
    study: &Path,
    shards: usize,
    cpus: usize,
    out: Option<PathBuf>,
    time: &str,
    partition: Option<&str>,
    script: Option<PathBuf>,
) -> Result<()> {
    // The options checked before the study is read (the same checks again in the script's
    // builder, with the paths).
    let check = |job: SlurmJob| sbatch_script(&job).map(|_| ());
    let here = Path::new("/");
    check(SlurmJob {
        name: "",
        cases: shards,
        shards,
        cpus_per_task: cpus,
        time,
        partition,
        exe: here,
        study: here,
        out: here,
    })?;
    // Checked now: a study that does not read must not reach the queue.
    let s = Study::read(study)?;
    anyhow::ensure!(
        shards <= s.cases.len(),
        "--shards {shards}: the study has {} cases (a shard without a case would do nothing)",
        s.cases.len()
    );
    let abs = |p: &Path| std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
    let out = abs(&out.unwrap_or_else(|| default_out(study)));
    let exe = abs(&std::env::current_exe().context("cannot find the kecsim binary's path")?);
    let study = abs(study);
    let text = sbatch_script(&SlurmJob {
        name: &s.name,
        cases: s.cases.len(),
        shards,
        cpus_per_task: cpus,
        time,
        partition,
        exe: &exe,
        study: &study,
        out: &out,
    })?;
    let inputs = s.input_files();
    inputs_outside_cases(&inputs, &out)?;
    let cases = out.join("cases");
    let _outputs = super::guard_trees(&inputs, &[&cases], &[("--script", script.as_deref())], None)?;
    std::fs::create_dir_all(&out).with_context(|| format!("cannot create {}", out.display()))?;
    match script {
        Some(p) => {
            kecsim::files::write_atomic(&p, text.as_bytes())
                .with_context(|| format!("cannot write {}", p.display()))?;
            println!(
                "wrote {} (sbatch {}: {shards} shards of {} cases)",
                p.display(),
                p.display(),
                s.cases.len()
            );
        }
        None => print!("{text}"),
    }
    Ok(())
}
