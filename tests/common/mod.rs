//! Helpers shared by the scene tests that run the `kecsim` binary.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs the binary with `args` in `cwd`.
pub fn kecsim(args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_kecsim"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("kecsim runs")
}

/// Runs the kecsim binary, which must succeed (else the test fails with its stderr); its stdout.
pub fn kecsim_ok(args: &[&str], cwd: &Path) -> String {
    let out = kecsim(args, cwd);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// A fresh temporary directory for one test: the name, the process and a counter (the tests of
/// every topic share one process, and two of them may pick the same name).
pub fn tmpdir(name: &str) -> PathBuf {
    static NEXT: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let n = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let d = std::env::temp_dir().join(format!("kecsim-test-{name}-{}-{n}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// `rerun rrd verify` on the file, when the CLI is available. CI sets KECSIM_REQUIRE_RERUN_CLI=1
/// (after `pip install rerun-sdk`), which turns a missing CLI into a failure.
pub fn rerun_verify(path: &Path) {
    match Command::new("rerun").args(["rrd", "verify"]).arg(path).output() {
        Ok(out) => assert!(
            out.status.success(),
            "rerun rrd verify failed:\n{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        ),
        Err(e) => {
            assert!(
                std::env::var_os("KECSIM_REQUIRE_RERUN_CLI").is_none(),
                "rerun CLI required but not runnable: {e}"
            );
            eprintln!("note: `rerun` CLI not found ({e}); skipped `rerun rrd verify` (pip install rerun-sdk==0.36.3)");
        }
    }
}

/// A scene file of `assets/scenes/`, compiled.
pub fn scene(file: &str) -> kecsim::scenario::Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets/scenes")
        .join(file);
    kecsim::scenario::Scenario::read(&path)
        .unwrap()
        .compile(&path.display().to_string(), path.parent().unwrap())
        .unwrap()
}

/// Sets the contact model of a `[simulation]` (the table form; the legacy keys cleared).
pub fn set_contact(sim: &mut kecsim::scenario::SimulationSpec, spec: kecsim::contact::ContactModelSpec) {
    sim.contact = Some(spec);
    sim.contact_model = None;
    sim.kec_two_point_approach_m = None;
}

/// A scene run with the contact model `contact` (a `--contact` spec), its `[simulation]` edited
/// by `edit` first: the output as the run ended (a derailment or a failure included).
pub fn run_scene(
    sc: &kecsim::scenario::Scene,
    contact: &str,
    edit: impl Fn(&mut kecsim::scenario::SimulationSpec),
) -> kecsim::dynamics::RunOutput {
    let mut sc = sc.clone();
    edit(&mut sc.simulation.as_mut().expect("a scene with a [simulation]").0);
    sc.build_run(&kecsim::scenario::RunOptions {
        contact: Some(contact.to_string()),
        speed_m_s: None,
        ..Default::default()
    })
    .unwrap_or_else(|e| panic!("{contact}: {e}"))
    .run(&mut [])
}

/// [`run_scene`], which must end without an error (a stop condition may end it).
pub fn run_ok(
    sc: &kecsim::scenario::Scene,
    contact: &str,
    edit: impl Fn(&mut kecsim::scenario::SimulationSpec),
) -> kecsim::dynamics::RunOutput {
    let out = run_scene(sc, contact, edit);
    assert!(out.summary.error.is_none(), "{contact}: {:?}", out.summary.error);
    out
}

/// Writes `dir/ms.toml`: the default scene (the MS vehicle on the Tab. 6 kilometre) cut to
/// `duration` seconds (as written in TOML, e.g. `"0.5"`).
pub fn write_ms_scene(dir: &Path, duration: &str) {
    let ms = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/ms_vehicle_tab6.toml"),
    )
    .unwrap()
    .replacen("duration_s = 51.0", &format!("duration_s = {duration}"), 1);
    std::fs::write(dir.join("ms.toml"), ms).unwrap();
}

/// [`run_scene`], which must run to its end (outcome `completed`).
pub fn run_completed(
    sc: &kecsim::scenario::Scene,
    contact: &str,
    edit: impl Fn(&mut kecsim::scenario::SimulationSpec),
) -> kecsim::dynamics::RunOutput {
    let out = run_scene(sc, contact, edit);
    assert_eq!(
        out.summary.outcome, "completed",
        "{contact}: {:?}",
        out.summary.error
    );
    out
}
