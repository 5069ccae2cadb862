//! Reliability, round three (issue 50): outputs that are not plain files, full disks, broken
//! pipes, side files at predictable names, the files a study reads, `--spawn`'s fallback, the
//! table cache, counts and messages. One test per class, each written to fail on the kecsim
//! before the fix; each runs the binary with a deadline (a hang fails the test).
//!
//! Devices and full disks are made where they harm nothing: a character device node (`mknod`)
//! and a FIFO in the test's own directory, a small tmpfs mounted in a private mount namespace
//! (`unshare -m`). Where the machine does not allow them (not root, no namespaces) the test says
//! so on stderr and checks what it can.

use crate::common;
use crate::reliability::{finish, measured_scenario, rejects, run, scenario, spawn, HANG_S};

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Duration;

use common::tmpdir;

fn kecsim_bin() -> &'static str {
    env!("CARGO_BIN_EXE_kecsim")
}

fn s(p: &Path) -> &str {
    p.to_str().expect("UTF-8 test path")
}

/// Makes a named pipe (FIFO) at `p`.
pub(crate) fn mkfifo(p: &Path) {
    let made = Command::new("mkfifo").arg(p).status().is_ok_and(|s| s.success());
    assert!(made, "mkfifo {}", p.display());
}

/// Whether `p` is (still) a symlink.
fn is_link(p: &Path) -> bool {
    std::fs::symlink_metadata(p).is_ok_and(|m| m.file_type().is_symlink())
}

/// Runs `sh -c script` (with `$K` the kecsim binary, `$D` the test directory) in a private mount
/// namespace, where it may mount a small tmpfs; None where namespaces are not allowed here.
pub(crate) fn in_mount_namespace(dir: &Path, script: &str) -> Option<(bool, String, String)> {
    let probe = Command::new("unshare")
        .args(["-m", "sh", "-c", "mount -t tmpfs -o size=64k none \"$0\"", s(dir)])
        .output();
    if !probe.is_ok_and(|o| o.status.success()) {
        eprintln!("note: no private mount namespace with a tmpfs here (needs root and unshare); the full-disk checks are skipped");
        return None;
    }
    let child = Command::new("unshare")
        .args(["-m", "sh", "-c", script])
        .env("K", kecsim_bin())
        .env("D", dir)
        .current_dir(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("unshare starts");
    let out = finish(child, Duration::from_secs(240), "full-disk script");
    Some((out.ok, out.stdout, out.stderr))
}

// ---- class 1: outputs that are not regular files ----

#[test]
fn outputs_that_are_pipes_or_devices_are_written_never_replaced() {
    let dir = tmpdir("rel3-streams");
    let sc = scenario(&dir, "sc.toml", &[("duration_s = 0.5", "duration_s = 0.05")]);

    // `--json` onto a link to the process's stdout (what /dev/stdout is): the JSON reaches the
    // pipe, the link stays a link.
    let out_link = dir.join("stdout-link");
    std::os::unix::fs::symlink("/proc/self/fd/1", &out_link).unwrap();
    let o = run(
        &[
            "run",
            s(&sc),
            "--save",
            s(&dir.join("r.rrd")),
            "--json",
            s(&out_link),
        ],
        &dir,
        60,
    );
    assert!(o.ok, "{}", o.stderr);
    assert!(is_link(&out_link), "the link to stdout was replaced by a file");
    assert!(
        o.stdout.contains("\"outcome\""),
        "the JSON did not reach the pipe:\n{}",
        o.stdout
    );

    // `--save` onto stdout: the pipe gets the whole recording (and only it: the printed lines go
    // to stderr), the link stays.
    let mut child = spawn(&["run", s(&sc), "--save", s(&out_link)], &dir, &[]);
    let mut bytes = Vec::new();
    child.stdout.take().unwrap().read_to_end(&mut bytes).unwrap();
    let mut err = String::new();
    child.stderr.take().unwrap().read_to_string(&mut err).unwrap();
    assert!(child.wait().unwrap().success(), "{err}");
    assert!(is_link(&out_link), "the link to stdout was replaced by a file");
    assert!(
        bytes.starts_with(b"RRF2") && bytes.len() > 1000,
        "stdout holds no recording ({} bytes): {:?}",
        bytes.len(),
        String::from_utf8_lossy(&bytes[..bytes.len().min(200)])
    );
    assert!(err.contains("saved"), "the summary is not on stderr:\n{err}");
    let piped = dir.join("piped.rrd");
    std::fs::write(&piped, &bytes).unwrap();
    common::rerun_verify(&piped);

    // A FIFO with a reader gets the JSON; the FIFO stays a FIFO.
    let fifo = dir.join("f.json");
    mkfifo(&fifo);
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap_or_default())
    };
    let o = run(
        &[
            "run",
            s(&sc),
            "--save",
            s(&dir.join("r2.rrd")),
            "--json",
            s(&fifo),
        ],
        &dir,
        60,
    );
    assert!(o.ok, "{}", o.stderr);
    let got = reader.join().unwrap();
    assert!(
        got.contains("\"outcome\""),
        "the FIFO's reader got {} bytes",
        got.len()
    );
    use std::os::unix::fs::FileTypeExt;
    assert!(
        std::fs::symlink_metadata(&fifo).unwrap().file_type().is_fifo(),
        "the FIFO was replaced by a file"
    );

    // A FIFO nobody reads: an error naming it within the wait (made 1 s here), not a hang.
    let lonely = dir.join("lonely.json");
    mkfifo(&lonely);
    let r3 = dir.join("r3.rrd");
    let args = ["run", s(&sc), "--save", s(&r3), "--json", s(&lonely)];
    let child = spawn(&args, &dir, &[("KECSIM_STREAM_WAIT_S", "1")]);
    let o = finish(child, Duration::from_secs(HANG_S), "run into a FIFO nobody reads");
    assert!(!o.ok, "a FIFO nobody reads was accepted: {}", o.stdout);
    for n in ["lonely.json", "nobody read", "within 1 s"] {
        assert!(
            o.stderr.contains(n),
            "the message does not say {n:?}: {}",
            o.stderr
        );
    }

    // A character device (the null device, made here): written, never replaced.
    let null = dir.join("null");
    if Command::new("mknod")
        .arg(&null)
        .args(["c", "1", "3"])
        .status()
        .is_ok_and(|s| s.success())
    {
        let o = run(&["run", s(&sc), "--json", s(&null), "--save", s(&null)], &dir, 60);
        assert!(o.ok, "{}", o.stderr);
        let t = std::fs::symlink_metadata(&null).unwrap().file_type();
        assert!(t.is_char_device(), "the device node was replaced by a file");
        // The study's script onto a device likewise.
        let o = run(
            &[
                "study",
                "slurm",
                s(&study_file(&dir)),
                "--shards",
                "1",
                "--script",
                s(&null),
            ],
            &dir,
            60,
        );
        assert!(o.ok, "{}", o.stderr);
        assert!(std::fs::symlink_metadata(&null)
            .unwrap()
            .file_type()
            .is_char_device());
    } else {
        eprintln!("note: mknod not allowed here; the device-node check is skipped");
    }
}

/// A one-case study on the single-wheelset scene of [`scenario`].
fn study_file(dir: &Path) -> PathBuf {
    study_of(dir, "0.05")
}

/// [`study_file`] with its case's duration.
fn study_of(dir: &Path, duration_s: &str) -> PathBuf {
    let sc = scenario(
        dir,
        "study-base.toml",
        &[("duration_s = 0.5", &format!("duration_s = {duration_s}"))],
    );
    let p = dir.join("study.toml");
    std::fs::write(
        &p,
        format!(
            "schema_version = 1\nname = \"rel3\"\nscenario = \"{}\"\nextract = [\"max_abs_y_mm\"]\n\n[[axis]]\nkey = \"simulation.speed_m_s\"\nvalues = [10.0]\n",
            s(&sc)
        ),
    )
    .unwrap();
    p
}

// ---- class 2: a full disk ----

#[test]
fn a_full_disk_keeps_the_old_files_and_fails_the_command() {
    let dir = tmpdir("rel3-full");
    let sc = scenario(&dir, "sc.toml", &[("duration_s = 0.5", "duration_s = 0.3")]);
    // 1 s at 100 Hz: the CSV (~100 kB) does not fit the 64 kB disk.
    let long = scenario(&dir, "long.toml", &[("duration_s = 0.5", "duration_s = 1.0")]);
    let full = dir.join("full");
    let kept = dir.join("kept");
    std::fs::create_dir_all(&full).unwrap();
    std::fs::create_dir_all(&kept).unwrap();
    let script = format!(
        r#"set -u
mount -t tmpfs -o size=64k none "$D/full" || exit 90
printf 'previous recording' > "$D/full/x.rrd"
mkdir "$D/full/csv"
printf 'previous csv' > "$D/full/csv/wheelset_1.csv"
printf 'previous json' > "$D/full/s.json"
"$K" run "{sc}" --save "$D/full/x.rrd" > "$D/kept/save.out" 2> "$D/kept/save.err"; echo "save $?" >> "$D/kept/rc"
"$K" run "{long}" --save "$D/r.rrd" --csv "$D/full/csv" > "$D/kept/csv.out" 2> "$D/kept/csv.err"; echo "csv $?" >> "$D/kept/rc"
"$K" track "{sc}" --save "$D/full/x.rrd" > "$D/kept/track.out" 2> "$D/kept/track.err"; echo "track $?" >> "$D/kept/rc"
cp "$D/full/x.rrd" "$D/full/csv/wheelset_1.csv" "$D/full/s.json" "$D/kept/"
ls -a "$D/full" "$D/full/csv" > "$D/kept/ls"
"#,
        sc = s(&sc),
        long = s(&long)
    );
    let Some((ok, _out, err)) = in_mount_namespace(&dir, &script) else {
        return;
    };
    assert!(ok, "the script failed: {err}");
    let read = |f: &str| std::fs::read_to_string(kept.join(f)).unwrap_or_default();
    let rc = read("rc");
    for (what, file, previous) in [
        ("save", "x.rrd", "previous recording"),
        ("csv", "wheelset_1.csv", "previous csv"),
        ("track", "x.rrd", "previous recording"),
    ] {
        assert!(
            rc.lines().any(|l| l == format!("{what} 1")),
            "`{what}` on a full disk did not fail (rc: {rc}); stdout:\n{}",
            read(&format!("{what}.out"))
        );
        assert_eq!(read(file), previous, "`{what}` replaced the previous {file}");
        let stderr = read(&format!("{what}.err"));
        assert!(
            stderr.contains("No space left") || stderr.contains("disk is full"),
            "`{what}`: the error does not say the disk is full:\n{stderr}"
        );
        assert!(!stderr.contains("panicked"), "{stderr}");
        assert!(
            !read(&format!("{what}.out")).contains(&format!("wrote {}", s(&full.join("csv/wheelset_1.csv")))),
            "`{what}` said it wrote a file it did not write"
        );
    }
    // No part file left behind on the full disk.
    assert!(!read("ls").contains(".part-"), "part files left:\n{}", read("ls"));
}

#[test]
fn a_study_case_that_failed_for_a_full_disk_is_run_again() {
    let dir = tmpdir("rel3-full-study");
    // 1 s at 100 Hz: a case's CSV (~100 kB) does not fit the 64 kB disk.
    let study = study_of(&dir, "1.0");
    let out = dir.join("o");
    std::fs::create_dir_all(&out).unwrap();
    let script = format!(
        r#"set -u
mount -t tmpfs -o size=64k none "$D" || exit 90
"$K" study "{study}" --out "$D" --save "{rrd}" > /dev/null 2>&1; echo "first $?"
mount -o remount,size=64m "$D"
"$K" study "{study}" --out "$D" --save "{rrd}"; echo "second $?"
"#,
        study = s(&study),
        rrd = s(&dir.join("s.rrd"))
    );
    let Some((ok, stdout, err)) = in_mount_namespace(&out, &script) else {
        return;
    };
    assert!(ok, "{err}");
    assert!(
        stdout.contains("first 1"),
        "the study on a full disk did not fail:\n{stdout}"
    );
    assert!(stdout.contains("second 0"), "{stdout}\n{err}");
    assert!(
        !stdout.contains("finished before, skipped"),
        "a case that failed only for the full disk was kept as finished:\n{stdout}"
    );
}

// ---- class 3: a closed or failing stdout ----

#[test]
fn a_closed_or_failing_stdout_ends_cleanly_with_every_file_written() {
    let dir = tmpdir("rel3-pipe");
    let sc = scenario(&dir, "sc.toml", &[("duration_s = 0.5", "duration_s = 0.05")]);
    // `| head -1`: the reader takes one line and closes the pipe.
    for (args, files) in [
        (
            vec!["run", s(&sc), "--save", "r.rrd", "--json", "r.json"],
            vec!["r.rrd", "r.json"],
        ),
        (vec!["profiles", "--save", "p.rrd"], vec!["p.rrd"]),
        (
            vec!["generate-profiles", "--dir", "gen"],
            vec!["gen/s1002.csv", "gen/60e1.csv", "gen/54e1.csv"],
        ),
    ] {
        let mut child = spawn(&args, &dir, &[]);
        let mut first = [0u8; 1];
        child.stdout.as_mut().unwrap().read_exact(&mut first).ok();
        drop(child.stdout.take());
        let mut err = String::new();
        let what = args.join(" ");
        let t = std::time::Instant::now();
        let status = loop {
            if let Some(st) = child.try_wait().unwrap() {
                break st;
            }
            assert!(
                t.elapsed().as_secs() < HANG_S,
                "`kecsim {what}` hung after its stdout closed"
            );
            std::thread::sleep(Duration::from_millis(20));
        };
        child.stderr.take().unwrap().read_to_string(&mut err).ok();
        assert!(
            !err.contains("panicked"),
            "`kecsim {what}` panicked on a closed stdout:\n{err}"
        );
        assert!(
            status.success(),
            "`kecsim {what}` failed on a closed stdout:\n{err}"
        );
        for f in files {
            assert!(dir.join(f).is_file(), "`kecsim {what}`: {f} was not written");
        }
    }
    // stdout on a full device: the files are written, the command says stdout failed and exits 1.
    let full = std::fs::OpenOptions::new().write(true).open("/dev/full");
    if let Ok(full) = full {
        let child = Command::new(kecsim_bin())
            .args(["run", s(&sc), "--save", "f.rrd"])
            .current_dir(&dir)
            .stdout(Stdio::from(full))
            .stderr(Stdio::piped())
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&child.stderr);
        assert!(!err.contains("panicked"), "{err}");
        assert!(!child.status.success(), "a lost summary went unreported:\n{err}");
        assert!(err.contains("standard output failed"), "{err}");
        assert!(dir.join("f.rrd").is_file(), "the recording was not written");
    }
}

// ---- class 4: side files at predictable names ----

#[test]
fn side_files_are_never_followed() {
    let dir = tmpdir("rel3-side");
    let sc = scenario(&dir, "sc.toml", &[("duration_s = 0.5", "duration_s = 0.05")]);
    let text = std::fs::read_to_string(&sc).unwrap();
    // A link at the lock's name, pointing at the scene.
    std::os::unix::fs::symlink(&sc, dir.join(".a.json.kecsim-lock")).unwrap();
    let o = run(&["run", s(&sc), "--save", "r.rrd", "--json", "a.json"], &dir, 60);
    assert_eq!(
        std::fs::read_to_string(&sc).unwrap(),
        text,
        "the scene was written through the lock's link"
    );
    assert!(!o.ok && o.stderr.contains("symlink"), "{}", o.stderr);
    std::fs::remove_file(dir.join(".a.json.kecsim-lock")).unwrap();
    // Links at the part files' and the write probe's names for the next pids (they are
    // predictable): the scene is never truncated.
    let last: u32 = std::fs::read_to_string("/proc/sys/kernel/ns_last_pid")
        .ok()
        .and_then(|t| t.trim().parse().ok())
        .unwrap_or(0);
    std::fs::create_dir_all(dir.join("csv")).unwrap();
    if last > 0 {
        for pid in last + 1..last + 400 {
            for name in [
                format!(".a.json.part-{pid}"),
                format!(".a.json.part-{pid}-1"),
                format!(".r.rrd.part-{pid}"),
                format!("csv/.kecsim-write-check-{pid}"),
                format!("csv/.wheelset_1.csv.part-{pid}-1"),
            ] {
                std::os::unix::fs::symlink(&sc, dir.join(name)).ok();
            }
        }
    }
    let o = run(
        &[
            "run",
            s(&sc),
            "--save",
            "r.rrd",
            "--json",
            "a.json",
            "--csv",
            "csv",
        ],
        &dir,
        60,
    );
    assert!(o.ok, "{}", o.stderr);
    assert_eq!(
        std::fs::read_to_string(&sc).unwrap(),
        text,
        "the scene was written through a part file's link"
    );
    assert!(std::fs::read_to_string(dir.join("a.json"))
        .unwrap()
        .contains("\"outcome\""));
    // An output named like another output's lock or part file is refused.
    for name in [".a.json.kecsim-lock", ".a.json.part-123"] {
        rejects(
            &["run", s(&sc), "--save", name, "--json", "a.json"],
            &dir,
            60,
            &[name, "named like a lock"],
        );
    }
}

// ---- class 5: the files a study reads ----

#[test]
fn a_study_never_writes_over_a_file_an_axis_names_or_its_own_cases() {
    let dir = tmpdir("rel3-study");
    let gen = dir.join("p");
    crate::common::kecsim_ok(&["generate-profiles", "--dir", s(&gen)], &dir);
    std::fs::copy(gen.join("s1002.csv"), dir.join("w1.csv")).unwrap();
    std::fs::copy(gen.join("s1002.csv"), dir.join("w2.csv")).unwrap();
    let w2 = std::fs::read(dir.join("w2.csv")).unwrap();
    let sc = scenario(&dir, "base.toml", &[("duration_s = 0.5", "duration_s = 0.05")]);
    let study = dir.join("axes.toml");
    std::fs::write(
        &study,
        format!(
            "schema_version = 1\nname = \"axes\"\nscenario = \"{}\"\nextract = [\"max_abs_y_mm\"]\n\n[[axis]]\nkey = \"profiles.wheel\"\nvalues = [\"w1.csv\", \"w2.csv\"]\n",
            s(&sc)
        ),
    )
    .unwrap();
    rejects(
        &["study", s(&study), "--out", "o", "--save", "w2.csv"],
        &dir,
        60,
        &["w2.csv", "which this command reads"],
    );
    rejects(
        &[
            "study",
            "slurm",
            s(&study),
            "--shards",
            "1",
            "--out",
            "o",
            "--script",
            "w2.csv",
        ],
        &dir,
        60,
        &["w2.csv", "which this command reads"],
    );
    assert_eq!(
        std::fs::read(dir.join("w2.csv")).unwrap(),
        w2,
        "the axis's profile was replaced"
    );
    // The study runs; a merge may not save into its cases.
    let o = run(&["study", s(&study), "--out", "o", "--save", "o.rrd"], &dir, 120);
    assert!(o.ok, "{}", o.stderr);
    let case1 = dir.join("o/cases/00001/scenario.toml");
    let before = std::fs::read(&case1).unwrap();
    rejects(
        &["study", "merge", "o", "--save", s(&case1)],
        &dir,
        60,
        &["scenario.toml", "whose files this command reads"],
    );
    assert_eq!(std::fs::read(&case1).unwrap(), before);
    let o = run(&["study", s(&study), "--out", "o", "--save", "o.rrd"], &dir, 120);
    assert!(
        o.stdout.matches("finished before, skipped").count() == 2,
        "{}",
        o.stdout
    );
    // A base scene stored inside the output tree is refused before it is overwritten.
    let inside = dir.join("o/cases/00000/scenario.toml");
    let text = std::fs::read_to_string(&inside).unwrap();
    let s2 = dir.join("inside.toml");
    std::fs::write(
        &s2,
        format!(
            "schema_version = 1\nname = \"inside\"\nscenario = \"{}\"\nextract = [\"max_abs_y_mm\"]\n\n[[axis]]\nkey = \"simulation.speed_m_s\"\nvalues = [11.0]\n",
            s(&inside)
        ),
    )
    .unwrap();
    rejects(
        &["study", s(&s2), "--out", "o2", "--save", "o2.rrd"],
        &dir,
        60,
        &[],
    );
    let o = run(&["study", s(&s2), "--out", "o", "--save", "o3.rrd"], &dir, 60);
    assert!(
        !o.ok && o.stderr.contains("inside its output tree"),
        "{}",
        o.stderr
    );
    assert_eq!(
        std::fs::read_to_string(&inside).unwrap(),
        text,
        "the base scene in the cases was overwritten"
    );
}

// ---- class 6: `--spawn`'s fallback ----

#[test]
fn the_spawn_fallback_is_guarded_and_never_waits_without_end() {
    let dir = tmpdir("rel3-spawn");
    let sc = scenario(&dir, "sc.toml", &[("duration_s = 0.5", "duration_s = 0.05")]);
    let bin = dir.join("bin");
    std::fs::create_dir_all(&bin).unwrap();
    let path = format!("{}:{}", s(&bin), std::env::var("PATH").unwrap_or_default());
    use std::os::unix::fs::PermissionsExt;
    // The fake viewer lets go of the output pipes (as the real one, detached, does): the test
    // waits for kecsim, not for the fake's sleep.
    for (body, case) in [
        ("exit 1", "cannot run"),
        ("exec >/dev/null 2>&1 </dev/null; sleep 40", "never listens"),
    ] {
        let fake = bin.join("rerun");
        std::fs::write(&fake, format!("#!/bin/sh\n{body}\n")).unwrap();
        std::fs::set_permissions(&fake, std::fs::Permissions::from_mode(0o755)).unwrap();
        // A short wait for the viewer to listen (the default is 10 s).
        let env = [
            ("PATH", path.as_str()),
            ("DISPLAY", ":99"),
            ("KECSIM_VIEWER_WAIT_S", "1"),
        ];
        // The fallback recording and the JSON are one file: refused before any work.
        let child = spawn(&["run", s(&sc), "--spawn", "--json", "kecsim.rrd"], &dir, &env);
        let o = finish(child, Duration::from_secs(HANG_S), "run --spawn (fake rerun)");
        assert!(
            !o.ok,
            "a `rerun` that {case}: the JSON was written over the fallback recording:\n{}",
            o.stdout
        );
        assert!(o.stderr.contains("both name the file"), "{case}: {}", o.stderr);
        // Without the clash: the recording is saved, said so, rc 0.
        let child = spawn(&["run", s(&sc), "--spawn", "--json", "s.json"], &dir, &env);
        let o = finish(child, Duration::from_secs(HANG_S), "run --spawn (fake rerun)");
        assert!(o.ok, "{case}: {}", o.stderr);
        assert!(
            o.stderr.contains("saving the recording to kecsim.rrd"),
            "{case}: {}",
            o.stderr
        );
        assert!(
            o.stdout.contains("saved kecsim.rrd") && !o.stdout.contains("streamed"),
            "{case}: {}",
            o.stdout
        );
        std::fs::remove_file(dir.join("kecsim.rrd")).unwrap();
    }
}

// ---- class 7: the table cache ----

#[test]
fn the_table_cache_is_checked_bounded_and_rebuilt() {
    let dir = tmpdir("rel3-cache");
    let cache = dir.join("cache");
    let sc = scenario(&dir, "sc.toml", &[("duration_s = 0.5", "duration_s = 0.05")]);
    let env = [("KECSIM_CACHE_DIR", s(&cache))];
    let nadal = |dir: &Path| -> f64 {
        let child = spawn(&["run", s(&sc), "--save", "r.rrd", "--json", "n.json"], dir, &env);
        let o = finish(child, Duration::from_secs(HANG_S), "run with the cache");
        assert!(o.ok, "{}", o.stderr);
        let j: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("n.json")).unwrap()).unwrap();
        j["safety"]["nadal_limit"]
            .as_f64()
            .unwrap_or_else(|| panic!("no safety.nadal_limit in {j}"))
    };
    let clean = nadal(&dir);
    let tables = cache.join("tables");
    let flange: Vec<PathBuf> = std::fs::read_dir(&tables)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            p.file_name()
                .unwrap()
                .to_string_lossy()
                .starts_with("flange-angle")
        })
        .collect();
    assert_eq!(flange.len(), 1, "{flange:?}");
    // An edited angle (the third word) is caught by the checksum and rebuilt.
    let mut bytes = std::fs::read(&flange[0]).unwrap();
    let angle = f64::from_le_bytes(bytes[16..24].try_into().unwrap());
    bytes[16..24].copy_from_slice(&(angle * 0.7).to_le_bytes());
    std::fs::write(&flange[0], &bytes).unwrap();
    let edited = nadal(&dir);
    assert!(
        (edited - clean).abs() < 1e-9,
        "an edited cache file changed the Nadal limit: {clean} → {edited}"
    );
    // Whatever stands at a table's name — a FIFO, a link to /dev/zero, a 300 MB file — costs
    // nothing and is replaced.
    let table = std::fs::read_dir(&tables)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.file_name().unwrap().to_string_lossy().starts_with("table1"))
        .expect("a cached table");
    for (what, make) in [
        ("a FIFO", "fifo"),
        ("a link to /dev/zero", "zero"),
        ("a 300 MB file", "big"),
    ] {
        std::fs::remove_file(&table).ok();
        match make {
            "fifo" => mkfifo(&table),
            "zero" => std::os::unix::fs::symlink("/dev/zero", &table).unwrap(),
            _ => std::fs::File::create(&table).unwrap().set_len(300 << 20).unwrap(),
        }
        let t = std::time::Instant::now();
        let n = nadal(&dir);
        assert!((n - clean).abs() < 1e-9, "{what}: {n}");
        assert!(
            std::fs::symlink_metadata(&table).unwrap().is_file()
                && std::fs::metadata(&table).unwrap().len() < 100 << 20,
            "{what} in the cache was not replaced by the table ({:.1} s)",
            t.elapsed().as_secs_f64()
        );
    }
    // A case's result.json that is a FIFO or a link to /dev/zero: `study merge` names it.
    let study = study_file(&dir);
    let o = run(
        &["study", s(&study), "--out", "so", "--save", "so.rrd"],
        &dir,
        120,
    );
    assert!(o.ok, "{}", o.stderr);
    let result = dir.join("so/cases/00000/result.json");
    std::fs::remove_file(&result).unwrap();
    std::os::unix::fs::symlink("/dev/zero", &result).unwrap();
    rejects(
        &["study", "merge", "so", "--save", "m.rrd"],
        &dir,
        60,
        &["result.json"],
    );
    std::fs::remove_file(&result).unwrap();
    mkfifo(&result);
    rejects(
        &["study", "merge", "so", "--save", "m.rrd"],
        &dir,
        60,
        &["result.json", "not a regular file"],
    );
}

// ---- class 8: counts the limits let through ----

#[test]
fn thread_job_part_and_rate_counts_are_capped() {
    let dir = tmpdir("rel3-counts");
    let sc = scenario(&dir, "sc.toml", &[("duration_s = 0.5", "duration_s = 0.05")]);
    let child = spawn(
        &["run", s(&sc), "--save", "r.rrd"],
        &dir,
        &[("KECSIM_THREADS", "100000")],
    );
    let o = finish(
        child,
        Duration::from_secs(HANG_S),
        "run with KECSIM_THREADS=100000",
    );
    assert!(
        !o.ok && o.stderr.contains("KECSIM_THREADS 100000") && o.stderr.contains("per core"),
        "{}",
        o.stderr
    );
    let study = study_file(&dir);
    rejects(
        &["study", s(&study), "--jobs", "18446744073709551615"],
        &dir,
        20,
        &["--jobs 18446744073709551615", "per core"],
    );
    rejects(
        &[
            "run",
            s(&scenario(
                &dir,
                "rate.toml",
                &[("record_rate_hz = 100.0", "record_rate_hz = 1e5")],
            )),
        ],
        &dir,
        20,
        &["record_rate_hz"],
    );
    // 100 000 track sections, each with a problem (a gap before it): reported in linear time
    // (each problem's line was counted from the file's start: 354 s), the first 50 listed.
    let mut sections = String::new();
    for k in 0..100_000 {
        sections.push_str(&format!(
            "  {{ type = \"straight\", from_m = {}.0, to_m = {}.0 }},\n",
            k * 5 + 1,
            k * 5 + 5
        ));
    }
    let long = scenario(
        &dir,
        "long.toml",
        &[(
            "  { type = \"straight\", from_m = 0.0, to_m = 1000.0 },\n",
            &sections,
        )],
    );
    let t = std::time::Instant::now();
    let o = rejects(
        &["track", s(&long), "--save", "t.rrd"],
        &dir,
        HANG_S,
        &["gap", "more problems"],
    );
    assert!(
        o.stderr.lines().count() < 200,
        "{} lines of problems",
        o.stderr.lines().count()
    );
    eprintln!(
        "100 000 sections with a problem each: refused in {:.2} s",
        t.elapsed().as_secs_f64()
    );
}

// ---- class 9: misleading or missing messages ----

#[test]
fn messages_name_the_key_and_its_line() {
    let dir = tmpdir("rel3-messages");
    let ms = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/ms_vehicle_tab6.toml"),
    )
    .unwrap();
    let line_of = |text: &str, needle: &str| {
        text[..text.find(needle).expect("in the scene")]
            .matches('\n')
            .count()
            + 1
    };
    // nan and inf are refused where they are written (not "singular wheelset equations").
    for bad in ["nan", "inf", "-inf"] {
        let text = ms.replacen(
            "at_m = [11.924, 0.95, 0.295]",
            &format!("at_m = [{bad}, 0.95, 0.295]"),
            1,
        );
        let p = dir.join(format!("ms_{}.toml", bad.replace('-', "m")));
        std::fs::write(&p, &text).unwrap();
        let line = line_of(&text, &format!("at_m = [{bad}"));
        rejects(
            &["run", s(&p), "--save", "r.rrd"],
            &dir,
            60,
            &[&format!(":{line}: at_m = {bad}: not a number")],
        );
    }
    // nominal_radius_m = 1.0, the documented upper end, runs (it failed as "never touch").
    let r1 = scenario(
        &dir,
        "r1.toml",
        &[
            ("duration_s = 0.5", "duration_s = 0.05"),
            (
                "[simulation]",
                "[wheelset]\nnominal_radius_m = 1.0\n\n[simulation]",
            ),
        ],
    );
    let o = run(&["run", s(&r1), "--save", "r.rrd"], &dir, 60);
    assert!(o.ok, "{}", o.stderr);
    // A typo in a tagged table, and a wrong type there, at their own lines.
    let creep = |name: &str, body: &str| {
        scenario(
            &dir,
            name,
            &[(
                "[simulation]",
                &format!("[contact_forces]\nfriction = 0.3\n[contact_forces.creep]\n{body}\n\n[simulation]"),
            )],
        )
    };
    let typo = creep("typo.toml", "modle = \"fastsim\"");
    let line = line_of(&std::fs::read_to_string(&typo).unwrap(), "modle");
    rejects(
        &["run", s(&typo)],
        &dir,
        30,
        &[&format!(
            "line {line}: unknown key `modle`: did you mean `model`?"
        )],
    );
    let strips = creep("strips.toml", "model = \"fastsim\"\nstrips = 1.5");
    let line = line_of(&std::fs::read_to_string(&strips).unwrap(), "strips");
    rejects(
        &["run", s(&strips)],
        &dir,
        30,
        &[&format!("line {line}:"), "strips = 1.5"],
    );
    // A speed that never rolls is refused as 0 is.
    let slow = scenario(&dir, "slow.toml", &[("speed_m_s = 20.0", "speed_m_s = 1e-9")]);
    rejects(
        &["run", s(&slow)],
        &dir,
        30,
        &["simulation.speed_m_s = 0.000000001", "does not roll"],
    );
    // A cant beyond the service cants: a warning with its line.
    let cant = scenario(
        &dir,
        "cant.toml",
        &[
            ("duration_s = 0.5", "duration_s = 0.05"),
            (
                "{ type = \"straight\", from_m = 0.0, to_m = 1000.0 }",
                "{ type = \"straight\", from_m = 0.0, to_m = 1000.0, cant_rad = 0.149 }",
            ),
        ],
    );
    let o = run(&["run", s(&cant), "--save", "r.rrd"], &dir, 60);
    assert!(
        o.stderr.contains("warning")
            && o.stderr.contains("cant 0.149 rad")
            && o.stderr.contains("beyond the service cants"),
        "{}",
        o.stderr
    );
    // An irregularity file with rows 1e6 m apart: refused at the row.
    let gap = measured_scenario(
        &dir,
        "gap.toml",
        "gap.csv",
        "s_m,al_mm,vp_mm,gv_mm,cl_mm\n0,0,0,0,0\n1,0.1,0,0,0\n2,0,0,0,0\n1000002,0,0,0,0\n",
    );
    rejects(
        &["run", s(&gap)],
        &dir,
        30,
        &["gap.csv:5:", "s_m = 1000002", "at most 1000 m apart"],
    );
    // Control characters in a name are refused, shown escaped (never echoed raw).
    let ctrl = scenario(
        &dir,
        "ctrl.toml",
        &[("name = \"reliability\"", "name = \"bad\\u001b[31mred\"")],
    );
    let o = rejects(
        &["run", s(&ctrl)],
        &dir,
        30,
        &["ctrl.toml:2:", "control character U+001B"],
    );
    assert!(
        !o.stderr.contains('\u{1b}'),
        "the escape reached the terminal: {:?}",
        o.stderr
    );
}
