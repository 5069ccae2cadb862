//! Reliability round four (issue 66), the scene, profile, cache and contact-command classes:
//! absurd inputs refused with their limit (class 14), messages that say what is wrong (class
//! 13), forged cache files rebuilt and named (class 9). Each runs the binary.

use std::path::Path;

use crate::common::{kecsim, tmpdir, write_ms_scene};

/// The binary's exit, stdout and stderr, with `KECSIM_CACHE_DIR` set to `cache`.
fn run_cached(args: &[&str], cwd: &Path, cache: &Path) -> (bool, String, String) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_kecsim"))
        .args(args)
        .current_dir(cwd)
        .env("KECSIM_CACHE_DIR", cache)
        .output()
        .expect("kecsim runs");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// `dir/NAME`: the MS scene of 0.05 s with `edits` (text replacements, each must apply).
fn ms_scene(dir: &Path, name: &str, edits: &[(&str, &str)]) -> String {
    write_ms_scene(dir, "0.05");
    let mut text = std::fs::read_to_string(dir.join("ms.toml")).unwrap();
    for (from, to) in edits {
        assert!(text.contains(from), "{from}");
        text = text.replacen(from, to, 1);
    }
    std::fs::write(dir.join(name), text).unwrap();
    name.to_string()
}

/// A scene refused with every piece of `want` in its stderr.
fn refused(dir: &Path, args: &[&str], want: &[&str]) -> String {
    let out = kecsim(args, dir);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(
        !out.status.success(),
        "`kecsim {}` was accepted: {err}",
        args.join(" ")
    );
    for w in want {
        assert!(
            err.contains(w),
            "`kecsim {}`: no {w:?} in:\n{err}",
            args.join(" ")
        );
    }
    err
}

/// Class 13/14: traction beyond adhesion, friction 1e-300, controller_hz 1e-300, a ramp past
/// 200 m/s and motored = false on every wheelset are refused at the scene, naming the key and
/// the limit (they ran into "wheel lifts 5 mm: derailment", "singular wheelset equations", an
/// unheld speed, a 203 m/s run, and every wheelset motored).
#[test]
fn absurd_scene_values_are_refused_with_their_limit() {
    let dir = tmpdir("rel4-scene");
    let traction = "[simulation]\n";
    let force = ms_scene(
        &dir,
        "force.toml",
        &[(
            traction,
            "[simulation.traction]\nmode = \"force\"\nforce_n = 1e7\n\n[simulation]\n",
        )],
    );
    refused(
        &dir,
        &["run", &force, "--save", "f.rrd"],
        &[
            "force_n = 10000000 N",
            "beyond what adhesion can transmit",
            "expected |force_n| ≤",
        ],
    );
    let mu = ms_scene(&dir, "mu.toml", &[("friction = 0.3", "friction = 1e-300")]);
    refused(
        &dir,
        &["run", &mu, "--save", "f.rrd"],
        &[
            "mu.toml:",
            "friction = 1e-300: expected 0 (no creep forces) or 0.01 ..= 1.5",
        ],
    );
    let hz = ms_scene(
        &dir,
        "hz.toml",
        &[(
            traction,
            "[simulation.traction]\ncontroller_hz = 1e-300\n\n[simulation]\n",
        )],
    );
    refused(
        &dir,
        &["run", &hz, "--save", "f.rrd"],
        &["controller_hz = 1e-300: expected a bandwidth in [0.01, 2] Hz"],
    );
    let ramp = ms_scene(
        &dir,
        "ramp.toml",
        &[("speed_m_s = 19.0", "speed_m_s = 199.5\nspeed_ramp_m_s2 = 20.0")],
    );
    refused(
        &dir,
        &["run", &ramp, "--save", "f.rrd"],
        &[
            "speed_ramp_m_s2 = 20",
            "reaches 200.5 m/s",
            "beyond the 200 m/s limit",
        ],
    );
    // motored = false on every wheelset: no longer every wheelset driven, but refused.
    write_ms_scene(&dir, "0.05");
    let text = std::fs::read_to_string(dir.join("ms.toml"))
        .unwrap()
        .replace("motored = true\n", "")
        .replace(
            "[[vehicle.wheelsets]]\n",
            "[[vehicle.wheelsets]]\nmotored = false\n",
        );
    std::fs::write(dir.join("idle.toml"), text).unwrap();
    refused(
        &dir,
        &["run", "idle.toml", "--save", "f.rrd"],
        &[
            "motored = false on every wheelset (w1, w2, w3, w4, w5, w6)",
            "mode = \"hold_speed\"",
        ],
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// Class 13: a profile with CR-only line endings is read (it was "empty file").
#[test]
fn a_profile_with_cr_line_endings_is_read() {
    let dir = tmpdir("rel4-cr");
    let s1002 =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("profiles/s1002.csv")).unwrap();
    std::fs::write(dir.join("cr.csv"), s1002.replace('\n', "\r")).unwrap();
    let out = kecsim(&["profiles", "--wheel", "cr.csv", "--save", "p.rrd"], &dir);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    std::fs::remove_dir_all(&dir).ok();
}

/// Class 13/14, the contact commands: `kec --accuracy` with a range that leaves no case, a
/// patch yaw of 0.5 rad — refused with the limit; a patch point that fails is a warning and the
/// rest of the sweep is kept.
#[test]
fn contact_commands_refuse_empty_ranges_and_keep_a_sweep() {
    let dir = tmpdir("rel4-contact");
    refused(
        &dir,
        &["kec", "--accuracy", "--y-max", "0.5", "--save", "k.rrd"],
        &[
            "--accuracy: the table spans -0.500 .. 0.500 mm",
            "give --y-max ≥ 1.225",
        ],
    );
    refused(
        &dir,
        &[
            "patch",
            "--y-mm",
            "5",
            "--yaw-per-mm",
            "100",
            "--load-n",
            "50000",
            "--save",
            "p.rrd",
        ],
        &["a yaw of 500 mrad", "expected |yaw| ≤ 50 mrad"],
    );
    let out = kecsim(
        &[
            "patch", "--y-mm", "0,5.07,2", "--load-n", "50000", "--csv", "p.csv", "--save", "p.rrd",
        ],
        &dir,
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("warning: --y-mm 5.07 (kp patches): failed, left out of the table and the CSV"),
        "{err}"
    );
    let csv = std::fs::read_to_string(dir.join("p.csv")).unwrap();
    assert!(csv.lines().count() > 3, "the other points kept: {csv}");
    std::fs::remove_dir_all(&dir).ok();
}

/// Class 14: `generate-profiles` keeps an edited profile unless `--force`, naming it.
#[test]
fn generate_profiles_keeps_an_edited_profile() {
    let dir = tmpdir("rel4-gen");
    let ok = kecsim(&["generate-profiles", "--dir", "p"], &dir);
    assert!(ok.status.success());
    let file = dir.join("p/s1002.csv");
    let mut edited = std::fs::read_to_string(&file).unwrap();
    edited.push_str("# my edit\n");
    std::fs::write(&file, &edited).unwrap();
    refused(
        &dir,
        &["generate-profiles", "--dir", "p"],
        &["p/s1002.csv: differs from the standard profile", "--force"],
    );
    assert_eq!(std::fs::read_to_string(&file).unwrap(), edited, "kept");
    let out = kecsim(&["generate-profiles", "--dir", "p", "--force"], &dir);
    assert!(out.status.success());
    assert_ne!(
        std::fs::read_to_string(&file).unwrap(),
        edited,
        "replaced with --force"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// FNV-1a over 64-bit little-endian words (the cache's checksum).
fn fnv(words: &[u64]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for w in words {
        for b in w.to_le_bytes() {
            h ^= b as u64;
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    h
}

/// Class 9: a cache file edited with its checksum recomputed (the flange-angle file behind the
/// Nadal limit, a table with a forged row count) is rebuilt, and the run's warning names it.
#[test]
fn a_forged_cache_file_is_rebuilt_and_named_by_the_run() {
    let dir = tmpdir("rel4-cache");
    let cache = dir.join("cache");
    let sc = ms_scene(&dir, "sc.toml", &[]);
    let (ok, _, err) = run_cached(&["run", &sc, "--save", "a.rrd"], &dir, &cache);
    assert!(ok, "{err}");
    let tables = cache.join("tables");
    let files: Vec<_> = std::fs::read_dir(&tables)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "bin"))
        .collect();
    let forge = |p: &Path, edit: &dyn Fn(&mut Vec<u64>)| {
        let b = std::fs::read(p).unwrap();
        let mut w: Vec<u64> = b
            .chunks_exact(8)
            .map(|c| u64::from_le_bytes(c.try_into().unwrap()))
            .collect();
        w.pop();
        edit(&mut w);
        let sum = fnv(&w);
        w.push(sum);
        std::fs::write(p, w.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>()).unwrap();
    };
    let flange = files
        .iter()
        .find(|p| p.to_string_lossy().contains("flange-angle"))
        .expect("a flange-angle file");
    forge(flange, &|w| w[2] = 0f64.to_bits());
    let table = files
        .iter()
        .find(|p| p.to_string_lossy().contains("table1"))
        .expect("a table file");
    forge(table, &|w| w[9] = 1 << 40);
    let (ok, _, err) = run_cached(&["run", &sc, "--save", "b.rrd"], &dir, &cache);
    assert!(ok, "{err}");
    for (file, why) in [(flange, "not a flange contact"), (table, "rows, but the")] {
        let line = err
            .lines()
            .find(|l| l.contains(&file.display().to_string()))
            .unwrap_or_else(|| panic!("no warning names {}:\n{err}", file.display()));
        assert!(
            line.starts_with("kecsim: warning: contact table cache:")
                && line.contains("rebuilt")
                && line.contains(why),
            "{line}"
        );
    }
    // Rebuilt: a third run reads them without a word.
    let (ok, _, err) = run_cached(&["run", &sc, "--save", "c.rrd"], &dir, &cache);
    assert!(ok && !err.contains("contact table cache"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}
