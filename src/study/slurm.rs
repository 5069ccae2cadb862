//! The sbatch script of `kecsim study slurm`: a Slurm job array of shards, each `kecsim study`
//! on its slice of the cases, and a merge job submitted by task 0, dependent on the whole array.
//!
//! Every value the script holds goes through one of three quotings, each for the parser that
//! reads it: [`sh_quote`] for the shell (the script's own lines, and the merge job's `--wrap`
//! command, which sbatch hands to `sh` again: quoted twice), [`directive_quote`] for sbatch's
//! reading of `#SBATCH` lines, and [`slurm_file_name`] for Slurm's `%` patterns in a log file's
//! name. What none of them can carry (a newline, a path that is not UTF-8, a backslash in a log
//! file's name: in --out) is refused with the reason.

use std::path::Path;

use super::StudyError;

/// A job array: what [`sbatch_script`] writes.
#[derive(Debug, Clone)]
pub struct SlurmJob<'a> {
    /// The study's name (in the script's first comment).
    pub name: &'a str,
    /// Number of cases of the study.
    pub cases: usize,
    /// Number of array tasks (1 ..= [`MAX_SHARDS`]).
    pub shards: usize,
    /// Cores per task (Slurm's `--cpus-per-task`).
    pub cpus_per_task: usize,
    /// Wall-time limit per task (Slurm's `--time`, checked by [`slurm_time`]).
    pub time: &'a str,
    /// Slurm's `--partition` (letters, digits, `_`, `.`, `-`, `,`), or the cluster's default.
    pub partition: Option<&'a str>,
    /// The kecsim binary the tasks run (absolute).
    pub exe: &'a Path,
    /// The study file (absolute).
    pub study: &'a Path,
    /// The output directory (absolute).
    pub out: &'a Path,
}

/// Most array tasks a script may have.
pub const MAX_SHARDS: usize = 10_000;

/// `s` as one word of a POSIX shell line, whatever it holds: in single quotes, each `'` as
/// `'\''` (close, an escaped quote, reopen). Inside single quotes the shell gives every
/// character its own meaning (`$`, `` ` ``, `\`, `"`, `!`, `*`, `#`, `~`, spaces, newlines…),
/// so the word the shell reads back is `s` exactly.
pub fn sh_quote(s: &str) -> String {
    format!("'{}'", s.replace('\'', r"'\''"))
}

/// `s` as the value of an `#SBATCH` directive: sbatch reads these lines itself (not the shell),
/// with double quotes and backslash escapes.
pub fn directive_quote(s: &str) -> String {
    format!("\"{}\"", s.replace('\\', "\\\\").replace('"', "\\\""))
}

/// `s` as a Slurm log file name taken literally: each `%` (which starts Slurm's patterns,
/// `%a` the array task) doubled.
pub fn slurm_file_name(s: &str) -> String {
    s.replace('%', "%%")
}

/// Whether `t` is one of Slurm's `--time` formats: `M`, `M:S`, `H:M:S`, `D-H`, `D-H:M`,
/// `D-H:M:S` (digits only).
pub fn slurm_time(t: &str) -> bool {
    let digits = |f: &str| !f.is_empty() && f.bytes().all(|b| b.is_ascii_digit());
    let (days, rest) = match t.split_once('-') {
        Some((d, r)) => (Some(d), r),
        None => (None, t),
    };
    let fields: Vec<&str> = rest.split(':').collect();
    days.is_none_or(digits) && (1..=3).contains(&fields.len()) && fields.iter().all(|f| digits(f))
}

fn refuse(message: String) -> StudyError {
    StudyError::Slurm(message)
}

/// A path of the job as text for the script: refused where it is not UTF-8 or holds a newline
/// (no quoting carries a newline through sbatch's directives); `what` names it.
fn path_text<'p>(what: &str, p: &'p Path) -> Result<&'p str, StudyError> {
    let t = p.to_str().ok_or_else(|| {
        refuse(format!(
            "{what} {p:?}: a path that is not UTF-8 cannot go into a job script"
        ))
    })?;
    if t.contains(['\n', '\r']) {
        return Err(refuse(format!(
            "{what} {p:?}: a path with a newline cannot go into a job script"
        )));
    }
    Ok(t)
}

/// The script of `job`, every value checked and quoted for the parser that reads it.
pub fn sbatch_script(job: &SlurmJob) -> Result<String, StudyError> {
    if !(1..=MAX_SHARDS).contains(&job.shards) {
        return Err(refuse(format!(
            "--shards {}: expected 1 ..= {MAX_SHARDS}",
            job.shards
        )));
    }
    if job.cpus_per_task == 0 {
        return Err(refuse("--cpus-per-task 0: expected at least 1".to_string()));
    }
    if !slurm_time(job.time) {
        return Err(refuse(format!(
            "--time {:?}: expected a Slurm time (minutes, minutes:seconds, hours:minutes:seconds, \
             days-hours, days-hours:minutes or days-hours:minutes:seconds)",
            job.time
        )));
    }
    if let Some(p) = job.partition {
        if p.is_empty() || !p.chars().all(|c| c.is_ascii_alphanumeric() || "_.,-".contains(c)) {
            return Err(refuse(format!(
                "--partition {p:?}: expected a Slurm partition name (letters, digits, `_`, `.`, `-`; \
                 several separated by `,`)"
            )));
        }
    }
    let out = path_text("--out", job.out)?;
    if out.contains('\\') {
        return Err(refuse(format!(
            "--out {}: a backslash in the output directory cannot go into the job's log file \
             names: Slurm reads a backslash there as \"no % patterns\" (the shards' logs, \
             shard-%a.log, would not be told apart); choose a directory without one",
            super::printable(out)
        )));
    }
    let study = path_text("the study file", job.study)?;
    let exe = path_text("the kecsim binary", job.exe)?;
    let q = |t: &str| sh_quote(t);
    // The merge job's command: sbatch writes `--wrap`'s text into a script of its own, run by
    // `sh`. So the command is made here, each path a quoted word, and handed over as ONE quoted
    // word of this script's line (quoted twice: this script's shell removes the outer quotes,
    // the merge job's `sh` the inner). Never built in the script from its expanded variables —
    // `sh` would re-parse the paths (`$(…)`, backticks, `"` in --out ran).
    let merge_command = format!("{} study merge {}", q(exe), q(out));
    let partition = job
        .partition
        .map_or(String::new(), |p| format!("#SBATCH --partition={p}\n"));
    Ok(format!(
        "#!/bin/bash\n\
         # kecsim study {name}: {cases} cases in {shards} shards (a Slurm job array), then merged.\n\
         # Submit with: sbatch THIS_SCRIPT  (it submits the merge job itself, after the array).\n\
         #SBATCH --job-name=kecsim-study\n\
         #SBATCH --array=0-{last}\n\
         #SBATCH --cpus-per-task={cpus}\n\
         #SBATCH --time={time}\n\
         {partition}\
         #SBATCH --output={shard_log}\n\
         set -euo pipefail\n\
         KECSIM={exe}\n\
         STUDY={study}\n\
         OUT={outq}\n\
         # Each task runs the cases k with k mod SLURM_ARRAY_TASK_COUNT = SLURM_ARRAY_TASK_ID.\n\
         \"$KECSIM\" study \"$STUDY\" --out \"$OUT\" --jobs \"${{SLURM_CPUS_PER_TASK:-1}}\"\n\
         # The last task to finish submits nothing: the merge runs as its own job once every\n\
         # task has ended well (submitted by task 0, dependent on the whole array).\n\
         if [ \"${{SLURM_ARRAY_TASK_ID}}\" = 0 ]; then\n\
         \x20 sbatch --dependency=afterok:${{SLURM_ARRAY_JOB_ID}} --job-name=kecsim-merge \\\n\
         \x20   --output={merge_log} --wrap {wrap}\n\
         fi\n",
        // (A comment line: every control character made a visible escape, a newline too.)
        name = super::printable(job.name),
        cases = job.cases,
        shards = job.shards,
        last = job.shards - 1,
        cpus = job.cpus_per_task,
        time = job.time,
        shard_log = directive_quote(&format!("{}/shard-%a.log", slurm_file_name(out))),
        merge_log = q(&format!("{}/merge.log", slurm_file_name(out))),
        wrap = q(&merge_command),
        exe = q(exe),
        study = q(study),
        outq = q(out),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;
    use std::process::Command;

    /// Every character a POSIX shell or bash gives a meaning to, alone and together.
    fn hostile() -> Vec<String> {
        let mut v: Vec<String> = [
            "\"",
            "`",
            "'",
            ";",
            "|",
            "&",
            "<",
            ">",
            "*",
            "?",
            "\n",
            "\\",
            "$",
            " ",
            "!",
            "#",
            "~",
            "(",
            ")",
            "{",
            "}",
            "[",
            "]",
            "=",
            "%",
            "^",
            "\t",
            "''",
            "'\\''",
            "\\'",
            "$(touch PWNED)",
            "`touch PWNED`",
            "${HOME}",
            "$HOME",
            "~root",
            "a b\tc",
            "-n",
            "--",
            "",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        v.push(format!("all: {}", v.concat()));
        v
    }

    fn scratch(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("kecsim-slurm-{tag}-{}", std::process::id()));
        std::fs::remove_dir_all(&d).ok();
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    /// The words `sh -c LINE` hands to a command: `printf '%s\0'` of them.
    fn words(line: &str, cwd: &Path) -> Vec<String> {
        let o = Command::new("sh")
            .arg("-c")
            .arg(format!("printf '%s\\0' {line}"))
            .current_dir(cwd)
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "{line}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let mut w: Vec<String> = String::from_utf8(o.stdout)
            .unwrap()
            .split('\0')
            .map(String::from)
            .collect();
        w.pop();
        w
    }

    /// `sh` reads each quoted word back as it was, whatever it holds: alone, several on one
    /// line, and quoted twice (a command line handed to `sh -c` as one quoted word, as the merge
    /// job's `--wrap`); nothing inside runs.
    #[test]
    fn sh_quote_round_trips_every_shell_metacharacter() {
        let d = scratch("quote");
        let all = hostile();
        for s in &all {
            assert_eq!(words(&sh_quote(s), &d), vec![s.clone()], "{s:?}");
        }
        let line: Vec<String> = all.iter().map(|s| sh_quote(s)).collect();
        assert_eq!(words(&line.join(" "), &d), all);
        // Twice: the inner line is one word of the outer, and runs as `sh -c WORD`.
        let inner = format!("printf '%s\\0' {}", line.join(" "));
        let o = Command::new("sh")
            .arg("-c")
            .arg(format!("sh -c {}", sh_quote(&inner)))
            .current_dir(&d)
            .output()
            .unwrap();
        let mut got: Vec<String> = String::from_utf8(o.stdout)
            .unwrap()
            .split('\0')
            .map(String::from)
            .collect();
        got.pop();
        assert_eq!(got, all);
        assert!(!d.join("PWNED").exists(), "a quoted value ran");
        std::fs::remove_dir_all(&d).ok();
    }

    /// The whole script, run by bash as a task would (task 0, with `sbatch` a stub that runs the
    /// merge job's `--wrap` command with `sh -c` as sbatch's wrapper script does, and the kecsim
    /// binary a stub that logs its arguments): both kecsim commands get the hostile paths exactly,
    /// and nothing inside them runs. (Before, the `--wrap` command was built inside the script
    /// from the expanded variables and `sh` re-parsed it: `$(touch PWNED)` in --out ran.)
    #[test]
    fn the_script_hands_hostile_paths_to_both_commands_exactly() {
        let d = scratch("script");
        let weird = "o$(touch PWNED) `touch PWNED` \"q\" 'x' ;|&<>*?\\$!#~ %a";
        let dir = d.join(weird);
        // (--out without the backslash, which Slurm's log file names cannot carry.)
        let out = d.join(weird.replace('\\', "")).join("out");
        std::fs::create_dir_all(&dir).unwrap();
        let exe = dir.join("kecsim stub");
        let log = d.join("args.log");
        std::fs::write(
            &exe,
            "#!/bin/sh\nfor a in \"$@\"; do printf '%s\\0' \"$a\"; done >>\"$KLOG\"\nprintf 'END\\0' >>\"$KLOG\"\n",
        )
        .unwrap();
        let bin = d.join("bin");
        std::fs::create_dir_all(&bin).unwrap();
        std::fs::write(
            bin.join("sbatch"),
            "#!/bin/sh\nwhile [ $# -gt 0 ]; do\n  if [ \"$1\" = --wrap ]; then exec sh -c \"$2\"; fi\n  shift\ndone\nexit 3\n",
        )
        .unwrap();
        for p in [&exe, &bin.join("sbatch")] {
            let mut perm = std::fs::metadata(p).unwrap().permissions();
            std::os::unix::fs::PermissionsExt::set_mode(&mut perm, 0o755);
            std::fs::set_permissions(p, perm).unwrap();
        }
        let study = dir.join("study.toml");
        let script = sbatch_script(&SlurmJob {
            name: "x",
            cases: 4,
            shards: 2,
            cpus_per_task: 1,
            time: "10",
            partition: None,
            exe: &exe,
            study: &study,
            out: &out,
        })
        .unwrap();
        let ran = Command::new("bash")
            .arg("-c")
            .arg(&script)
            .current_dir(&d)
            .env(
                "PATH",
                format!("{}:{}", bin.display(), std::env::var("PATH").unwrap()),
            )
            .env("KLOG", &log)
            .env("SLURM_ARRAY_TASK_ID", "0")
            .env("SLURM_ARRAY_JOB_ID", "7")
            .env("SLURM_CPUS_PER_TASK", "1")
            .output()
            .unwrap();
        assert!(
            ran.status.success(),
            "{}\n{script}",
            String::from_utf8_lossy(&ran.stderr)
        );
        let logged = std::fs::read_to_string(&log).unwrap();
        let calls: Vec<Vec<&str>> = logged
            .split("END\0")
            .filter(|c| !c.is_empty())
            .map(|c| c.trim_end_matches('\0').split('\0').collect())
            .collect();
        let (o, s) = (out.to_str().unwrap(), study.to_str().unwrap());
        assert_eq!(
            calls,
            vec![
                vec!["study", s, "--out", o, "--jobs", "1"],
                vec!["study", "merge", o],
            ],
            "{script}"
        );
        let planted: Vec<_> = walk(&d).into_iter().filter(|p| p.ends_with("PWNED")).collect();
        assert!(planted.is_empty(), "a value ran: {planted:?}\n{script}");
        std::fs::remove_dir_all(&d).ok();
    }

    fn walk(d: &Path) -> Vec<PathBuf> {
        let mut v = Vec::new();
        for e in std::fs::read_dir(d).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                v.extend(walk(&p));
            }
            v.push(p);
        }
        v
    }

    /// What no quoting carries is refused, naming the value: a newline in a path, a time or a
    /// partition that is not Slurm's.
    #[test]
    fn values_no_quoting_carries_are_refused() {
        let p = Path::new("/a");
        let job = SlurmJob {
            name: "x",
            cases: 4,
            shards: 2,
            cpus_per_task: 1,
            time: "10",
            partition: None,
            exe: p,
            study: p,
            out: p,
        };
        let nl = Path::new("/a\nb");
        for (j, want) in [
            (
                SlurmJob {
                    out: nl,
                    ..job.clone()
                },
                "--out",
            ),
            (
                SlurmJob {
                    out: Path::new("/a\\b"),
                    ..job.clone()
                },
                "a backslash",
            ),
            (
                SlurmJob {
                    study: nl,
                    ..job.clone()
                },
                "the study file",
            ),
            (
                SlurmJob {
                    time: "1:2:3:4",
                    ..job.clone()
                },
                "--time",
            ),
            (
                SlurmJob {
                    partition: Some("a;b"),
                    ..job.clone()
                },
                "--partition",
            ),
            (
                SlurmJob {
                    shards: 0,
                    ..job.clone()
                },
                "--shards",
            ),
        ] {
            let e = sbatch_script(&j).unwrap_err().to_string();
            assert!(e.contains(want), "{e}");
        }
        assert!(sbatch_script(&job).is_ok());
    }
}
