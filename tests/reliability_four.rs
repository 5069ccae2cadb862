//! Reliability, round four (issue 66): the carbody CSVs under the output guard, part files of
//! their own per writer, a closed stderr, every output a run could not write reported whatever
//! ended it, `--spawn`'s waits bounded and interruptible, a run option a scene without a
//! simulation cannot use. Each test was written to fail on the kecsim before its fix; each runs
//! the binary with a deadline (a hang fails the test).

use crate::common;
use crate::reliability::{finish, rejects, run, scenario, spawn, HANG_S};
use crate::reliability_files::in_mount_namespace;

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::tmpdir;

fn s(p: &Path) -> &str {
    p.to_str().expect("UTF-8 test path")
}

/// Every file under `dir` (recursively) with its bytes, sorted.
fn tree(dir: &Path) -> Vec<(std::path::PathBuf, Vec<u8>)> {
    let mut v = Vec::new();
    let mut todo = vec![dir.to_path_buf()];
    while let Some(d) = todo.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                todo.push(p);
            } else {
                let bytes = std::fs::read(&p).unwrap_or_default();
                v.push((p, bytes));
            }
        }
    }
    v.sort();
    v
}

/// Class 1: the carbodies' CSVs (`--csv DIR` writes `DIR/c1.csv` … beside the wheelsets') go
/// through the guard as the wheelsets' do: the scene itself at a carbody CSV's name, `--json` or
/// `--save` naming one, and a carbody CSV another run holds are all refused before any work,
/// naming the file, and nothing is touched. (Before: the scene was overwritten with exit 0, the
/// JSON and the CSV shared a name, and two runs both "wrote" the file.)
#[test]
fn the_carbody_csvs_are_guarded_and_locked() {
    let dir = tmpdir("rel4-carbody");
    common::write_ms_scene(&dir, "0.2");
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    std::fs::copy(dir.join("ms.toml"), out.join("c1.csv")).unwrap();
    let before = tree(&dir);
    let routes: &[(&[&str], &[&str])] = &[
        (
            &["run", "out/c1.csv", "--csv", "out"],
            &["--csv", "c1.csv", "the input"],
        ),
        (
            &["run", "ms.toml", "--json", "out/c2.csv", "--csv", "out"],
            &["both name", "c2.csv"],
        ),
        (
            &["run", "ms.toml", "--save", "out/c3.csv", "--csv", "out"],
            &["both name", "c3.csv"],
        ),
    ];
    for (args, needles) in routes {
        rejects(args, &dir, 30, needles);
        assert_eq!(tree(&dir), before, "after `kecsim {}`", args.join(" "));
    }
    // Another writer holds c5.csv (its lock, as a running kecsim holds it): refused, naming it.
    let held = kecsim::files::OutputLock::acquire(&out.join("c5.csv")).expect("the lock is free");
    rejects(
        &["run", "ms.toml", "--csv", "out"],
        &dir,
        30,
        &["c5.csv", "another kecsim run"],
    );
    drop(held);
    assert_eq!(tree(&dir), before, "after the locked run");
}

/// Class 4: a closed stderr (`kecsim run 2>&1 | head -1`) never panics: the progress lines, the
/// warnings and the signal handler's line are dropped, the run goes to its end (or to its
/// interrupt) and every file is written, with the exit status it would have had. (Before: the
/// first progress line panicked, exit 101, the recording, the JSON and the CSVs lost, a part
/// file left.)
#[test]
fn a_closed_stderr_loses_nothing() {
    let dir = tmpdir("rel4-stderr");
    let sc = scenario(&dir, "sc.toml", &[]);
    let start = |args: &[&str]| {
        let mut child = Command::new(env!("CARGO_BIN_EXE_kecsim"))
            .args(args)
            .current_dir(&dir)
            // A progress line at every sample.
            .env("KECSIM_PROGRESS_S", "0")
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("kecsim starts");
        // The reading end of stderr closed: every write there fails (EPIPE).
        drop(child.stderr.take());
        child
    };
    let wait = |mut child: std::process::Child, what: &str| {
        let t = Instant::now();
        loop {
            if let Some(status) = child.try_wait().unwrap() {
                return status;
            }
            assert!(t.elapsed() < Duration::from_secs(HANG_S), "`kecsim {what}` hung");
            std::thread::sleep(Duration::from_millis(20));
        }
    };
    let args = [
        "run",
        s(&sc),
        "--json",
        "a.json",
        "--csv",
        "csv",
        "--save",
        "a.rrd",
    ];
    let status = wait(start(&args), "run (stderr closed)");
    assert_eq!(status.code(), Some(0), "a completed run with stderr closed");
    let j: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("a.json")).unwrap()).unwrap();
    assert_eq!(j["outcome"], "completed", "{j}");
    let rows = std::fs::read_to_string(dir.join("csv/wheelset_1.csv"))
        .unwrap()
        .lines()
        .count()
        - 1;
    assert_eq!(
        rows as u64,
        j["samples"].as_u64().unwrap(),
        "CSV rows vs JSON samples"
    );
    common::rerun_verify(&dir.join("a.rrd"));

    // Interrupted with stderr closed (the handler's line dropped): exit 1, the files written.
    let long = scenario(&dir, "long.toml", &[("duration_s = 0.5", "duration_s = 20.0")]);
    let args = [
        "run",
        s(&long),
        "--json",
        "b.json",
        "--csv",
        "csvb",
        "--save",
        "b.rrd",
        "--pace",
        "2",
    ];
    let child = start(&args);
    let part = dir.join(format!("csvb/.wheelset_1.csv.part-{}-1", child.id()));
    let t = Instant::now();
    while std::fs::read_to_string(&part).map_or(0, |s| s.lines().count()) < 20 {
        assert!(t.elapsed() < Duration::from_secs(120), "no CSV rows after 120 s");
        std::thread::sleep(Duration::from_millis(50));
    }
    let pid = child.id().to_string();
    assert!(Command::new("kill")
        .args(["-INT", &pid])
        .status()
        .unwrap()
        .success());
    let status = wait(child, "run (stderr closed, interrupted)");
    assert_eq!(status.code(), Some(1), "an interrupted run with stderr closed");
    let j: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("b.json")).unwrap()).unwrap();
    assert_eq!(j["stopped"], "interrupted", "{j}");
    assert!(dir.join("csvb/wheelset_1.csv").exists() && !part.exists());
    common::rerun_verify(&dir.join("b.rrd"));
}

/// Class 7: a run that ends early (Ctrl-C here) says each output it could not write: the
/// recording on a full disk, then the interrupt — the message names the recording as NOT
/// written (the old file kept), and the JSON that could be written is. (Before: only
/// "everything recorded up to it is written".) Needs a private mount namespace for the small
/// disk; skipped with a note where there is none.
#[test]
fn an_interrupted_run_names_the_outputs_it_could_not_write() {
    let dir = tmpdir("rel4-lost");
    let long = scenario(&dir, "long.toml", &[("duration_s = 0.5", "duration_s = 20.0")]);
    std::fs::create_dir_all(dir.join("full")).unwrap();
    std::fs::create_dir_all(dir.join("kept")).unwrap();
    let script = format!(
        r#"set -u
mount -t tmpfs -o size=64k none "$D/full" || exit 90
printf 'previous recording' > "$D/full/r.rrd"
"$K" run "{long}" --save "$D/full/r.rrd" --json "$D/kept/j.json" --pace 2 > "$D/kept/out" 2> "$D/kept/err" &
pid=$!
sleep 3
kill -INT $pid
wait $pid
echo "rc $?" > "$D/kept/rc"
cp "$D/full/r.rrd" "$D/kept/r.rrd"
ls -a "$D/full" > "$D/kept/ls"
"#,
        long = s(&long)
    );
    let Some((ok, _out, err)) = in_mount_namespace(&dir, &script) else {
        return;
    };
    assert!(ok, "the script failed: {err}");
    let read = |f: &str| std::fs::read_to_string(dir.join("kept").join(f)).unwrap_or_default();
    assert_eq!(read("rc").trim(), "rc 1", "{}", read("err"));
    let stderr = read("err");
    assert!(stderr.contains("interrupted at t ="), "{stderr}");
    assert!(
        stderr.contains("NOT written") && stderr.contains("r.rrd"),
        "the recording's failure is not said:\n{stderr}"
    );
    assert!(
        stderr.contains("No space left") || stderr.contains("disk is full"),
        "{stderr}"
    );
    assert!(
        !stderr.contains("everything recorded up to it is written"),
        "{stderr}"
    );
    assert_eq!(read("r.rrd"), "previous recording", "the old recording is kept");
    let j: serde_json::Value = serde_json::from_str(&read("j.json")).unwrap();
    assert_eq!(j["stopped"], "interrupted", "{j}");
    assert!(!read("ls").contains(".part-"), "part files left:\n{}", read("ls"));
}

/// Class 8: `--spawn` with a `rerun` whose `--version` leaves a process holding its output open
/// (the SDK read that output to its end: the run waited for minutes) falls back to the file
/// within the viewer wait; a `rerun` that never listens, with a long wait asked for, lets a
/// SIGTERM end the wait at once, the run then stopping with its files written.
#[test]
fn spawn_waits_are_bounded_and_a_signal_ends_them() {
    let dir = tmpdir("rel4-spawn");
    let sc = scenario(&dir, "sc.toml", &[("duration_s = 0.5", "duration_s = 0.05")]);
    let bin = dir.join("bin");
    std::fs::create_dir_all(&bin).unwrap();
    let path = format!("{}:{}", s(&bin), std::env::var("PATH").unwrap_or_default());
    use std::os::unix::fs::PermissionsExt;
    let fake = bin.join("rerun");
    // `--version` answers at once and leaves a child holding its stdout; started as the viewer,
    // it never listens (and lets go of the test's pipes).
    std::fs::write(
        &fake,
        "#!/bin/sh\nexec 2>/dev/null </dev/null\ncase \"$1\" in\n  --version) echo 'rerun-cli 0.36.3'; sleep 90 & ;;\n  *) exec >/dev/null; sleep 90 ;;\nesac\n",
    )
    .unwrap();
    std::fs::set_permissions(&fake, std::fs::Permissions::from_mode(0o755)).unwrap();
    let env = [
        ("PATH", path.as_str()),
        ("DISPLAY", ":99"),
        ("KECSIM_VIEWER_WAIT_S", "2"),
    ];
    let t = Instant::now();
    let child = spawn(&["run", s(&sc), "--spawn", "--json", "a.json"], &dir, &env);
    let o = finish(
        child,
        Duration::from_secs(40),
        "run --spawn (a rerun holding its output)",
    );
    assert!(o.ok, "{}", o.stderr);
    assert!(
        o.stderr.contains("saving the recording to kecsim.rrd"),
        "{}",
        o.stderr
    );
    assert!(t.elapsed() < Duration::from_secs(30), "{:?}", t.elapsed());
    common::rerun_verify(&dir.join("kecsim.rrd"));
    std::fs::remove_file(dir.join("kecsim.rrd")).unwrap();

    // A long wait asked for; SIGTERM after 1 s ends it.
    let env = [
        ("PATH", path.as_str()),
        ("DISPLAY", ":99"),
        ("KECSIM_VIEWER_WAIT_S", "120"),
    ];
    let child = spawn(&["run", s(&sc), "--spawn", "--json", "b.json"], &dir, &env);
    std::thread::sleep(Duration::from_secs(1));
    let t = Instant::now();
    assert!(Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap()
        .success());
    let o = finish(
        child,
        Duration::from_secs(40),
        "run --spawn (SIGTERM while waiting)",
    );
    assert!(
        t.elapsed() < Duration::from_secs(10),
        "the wait went on {:?} after SIGTERM:\n{}",
        t.elapsed(),
        o.stderr
    );
    assert!(!o.ok, "a stopped run says so in its exit status:\n{}", o.stdout);
    assert!(o.stderr.contains("stopped while waiting"), "{}", o.stderr);
    assert!(o.stderr.contains("interrupted"), "{}", o.stderr);
    assert!(
        dir.join("b.json").exists(),
        "the JSON of the stopped run is written"
    );
}

/// From class 14: `--tab` on a scene without a `[simulation]` (it records the profiles and the
/// KEC preprocessing, which have no tabs) is refused with the reason, as `--csv` and the other
/// run options are.
#[test]
fn run_options_without_a_simulation_are_refused() {
    let dir = tmpdir("rel4-tab");
    std::fs::write(
        dir.join("pair.toml"),
        "schema_version = 1\nname = \"pair\"\n\n[profiles]\nwheel = \"s1002\"\nrail = \"60e1\"\ninclination = \"1:40\"\n",
    )
    .unwrap();
    rejects(
        &["run", "pair.toml", "--tab", "forces"],
        &dir,
        30,
        &["no [simulation]", "--tab"],
    );
    // Without it, the scene is preprocessed and recorded.
    let o = run(&["run", "pair.toml", "--save", "p.rrd"], &dir, 60);
    assert!(o.ok, "{}", o.stderr);
}
