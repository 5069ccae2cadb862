//! Property-based fuzzing of every parser (issue 17): profile files (CSV, columns, SIMPACK), the
//! TOML scenario (parsed and compiled: profiles placed, track and irregularities built) and track
//! files, and irregularity CSVs. Inputs are arbitrary text, and valid files with their numbers
//! replaced by hostile ones (0, negative, huge, tiny, NaN, inf) or with bytes cut and inserted.
//! The property: no panic, an answer within a few seconds (no hang), and no allocation beyond
//! the resource limits (an oversized request is an error, not an abort). Inputs that once failed
//! are kept below as regression cases.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use proptest::prelude::*;

use kecsim::profile::{io::read_profile, ProfileKind};
use kecsim::scenario::{RunOptions, Scenario};

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// Longest a parser may take on one input.
const DEADLINE: Duration = Duration::from_secs(10);

fn text(rel: &str) -> String {
    std::fs::read_to_string(Path::new(ROOT).join(rel)).unwrap()
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("kecsim-fuzz-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

/// Numbers a hostile or careless user writes.
const HOSTILE: [&str; 14] = [
    "0",
    "-0",
    "-1",
    "1e308",
    "-1e308",
    "1e-320",
    "nan",
    "inf",
    "-inf",
    "1e9",
    "1e-9",
    "99999999999999999999",
    "0.0000001",
    "",
];

/// The byte ranges of the numbers in `s`.
fn numbers(s: &str) -> Vec<(usize, usize)> {
    let b = s.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let start_ok = i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_');
        if start_ok
            && (b[i].is_ascii_digit() || (b[i] == b'-' && i + 1 < b.len() && b[i + 1].is_ascii_digit()))
        {
            let j0 = i;
            i += 1;
            while i < b.len() && (b[i].is_ascii_digit() || matches!(b[i], b'.' | b'e' | b'E' | b'+' | b'-')) {
                i += 1;
            }
            out.push((j0, i));
        } else {
            i += 1;
        }
    }
    out
}

/// A mutation of a valid text: some numbers replaced by hostile ones, then a cut and an insert.
#[derive(Debug, Clone)]
struct Mutation {
    replace: Vec<(usize, usize)>,
    cut: Option<(usize, usize)>,
    insert: Option<(usize, String)>,
}

fn mutation() -> impl Strategy<Value = Mutation> {
    (
        prop::collection::vec((any::<usize>(), 0..HOSTILE.len()), 0..6),
        prop::option::of((any::<usize>(), 0usize..40)),
        prop::option::of((any::<usize>(), "[-0-9.e=\\[\\]{}\",\n# a-z]{0,12}")),
    )
        .prop_map(|(replace, cut, insert)| Mutation { replace, cut, insert })
}

fn apply(src: &str, m: &Mutation) -> String {
    let nums = numbers(src);
    let mut s = src.to_string();
    if !nums.is_empty() {
        // Replace from the back so that earlier ranges stay valid.
        let mut picks: Vec<(usize, usize)> = m.replace.iter().map(|&(k, h)| (k % nums.len(), h)).collect();
        picks.sort_by_key(|p| std::cmp::Reverse(p.0));
        picks.dedup_by_key(|p| p.0);
        for (k, h) in picks {
            let (a, b) = nums[k];
            s.replace_range(a..b, HOSTILE[h]);
        }
    }
    let floor = |s: &str, i: usize| {
        let mut i = i.min(s.len());
        while !s.is_char_boundary(i) {
            i -= 1;
        }
        i
    };
    if let Some((at, len)) = m.cut {
        if !s.is_empty() {
            let a = floor(&s, at % s.len());
            let b = floor(&s, a + len);
            s.replace_range(a..b, "");
        }
    }
    if let Some((at, ins)) = &m.insert {
        let a = floor(&s, if s.is_empty() { 0 } else { at % s.len() });
        s.insert_str(a, ins);
    }
    s
}

/// Runs `f`, failing on a panic (proptest reports the input) or on a run past the deadline.
fn bounded<T>(what: &str, f: impl FnOnce() -> T) -> T {
    let t = Instant::now();
    let out = f();
    assert!(t.elapsed() < DEADLINE, "{what} took {:?}", t.elapsed());
    out
}

fn check_profile(name: &str, content: &str, kind: ProfileKind) {
    let path = tmp(name);
    std::fs::write(&path, content).unwrap();
    let r = bounded("read_profile", || read_profile(&path, kind));
    if let Err(e) = r {
        // Errors name the file.
        assert!(e.to_string().contains(name), "{e}");
    }
}

fn check_scenario(content: &str, build: bool) {
    let base = Path::new(ROOT).join("assets/scenes");
    bounded("scenario", || {
        let Ok(s) = Scenario::parse(content, "fuzz.toml") else {
            return;
        };
        let Ok(scene) = s.compile("fuzz.toml", &base) else {
            return;
        };
        if build {
            let _ = scene.build_run(&RunOptions::default());
        }
    });
}

fn check_track(content: &str) {
    bounded("track", || {
        let _ = kecsim::track::file::track_from_text(content, "fuzz.toml", Path::new(ROOT));
    });
}

fn check_irregularity_csv(content: &str) {
    bounded("irregularity csv", || {
        let _ = kecsim::track::measured::parse_csv(content, "fuzz.csv");
    });
}

/// A study's manifest (`study.json`) as `kecsim study` writes it, `mutated`, in an output
/// directory of its own with one finished case: `study merge` on it answers (an error naming the
/// file, or the table) within the deadline, allocating nothing beyond the limits.
fn check_manifest(mutated: &str, tag: usize) {
    let dir = tmp(&format!("manifest-{tag}"));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(dir.join("cases/00000")).unwrap();
    std::fs::write(dir.join("study.json"), mutated).unwrap();
    bounded("study merge", || {
        let _ = kecsim::study::merge(&dir);
    });
    std::fs::remove_dir_all(&dir).ok();
}

/// The manifest of the wheelset speed sweep, as `kecsim study` writes it.
fn manifest_text() -> String {
    let study = kecsim::study::Study::read(&Path::new(ROOT).join("assets/studies/wheelset_speed_sweep.toml"))
        .unwrap();
    serde_json::to_string_pretty(&kecsim::study::Manifest::of(&study)).unwrap()
}

/// The bogie scene's vehicle tables mutated (the text before `[vehicle]` kept): compiled, its
/// force elements built — an error names the file, never a panic, within the deadline.
fn check_vehicle_tables(m: &Mutation) {
    let src = text("assets/scenes/bogie_tab6_curve.toml");
    let at = src.find("[vehicle]").unwrap();
    let content = format!("{}{}", &src[..at], apply(&src[at..], m));
    bounded("vehicle tables", || {
        let Ok(s) = Scenario::parse(&content, "fuzz.toml") else {
            return;
        };
        let Ok(scene) = s.compile("fuzz.toml", &Path::new(ROOT).join("assets/scenes")) else {
            return;
        };
        if let Some((_, kecsim::vehicle::spec::VehicleSpec::Multibody(spec))) = &scene.simulation {
            let _ = spec.elements(scene.pair.wheelset.nominal_radius_m);
        }
    });
}

/// The single-wheelset scene with a short run, whose build (tables, KEC profiles, settling) is
/// cheap enough to fuzz.
fn small_scene() -> String {
    text("assets/scenes/wheelset_critical_speed.toml").replace("duration_s = 80.0", "duration_s = 1.0")
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn profile_files_never_panic(m in mutation(), which in 0usize..4) {
        let (name, src, kind) = [
            ("w.csv", text("profiles/s1002.csv"), ProfileKind::Wheel),
            ("r.dat", text("tests/data/profiles/SUIC519A.dat"), ProfileKind::Rail),
            ("w.prw", text("tests/data/profiles/MBench_S1002_v3.prw"), ProfileKind::Wheel),
            ("r.prr", text("tests/data/profiles/MBench_UIC60_v3.prr"), ProfileKind::Rail),
        ][which].clone();
        check_profile(name, &apply(&src, &m), kind);
    }

    #[test]
    fn arbitrary_text_as_a_profile_never_panics(s in "[-0-9.,;e \n#!a-z]{0,300}", which in 0usize..3) {
        let name = ["x.csv", "x.dat", "x.prw"][which];
        check_profile(name, &s, ProfileKind::Wheel);
    }

    #[test]
    #[ignore = "slow: thousands of mutated scenarios compiled (~15 s)"]
    fn scenarios_never_panic(m in mutation()) {
        check_scenario(&apply(&small_scene(), &m), true);
    }

    #[test]
    fn the_ms_scenario_compiles_or_fails_cleanly(m in mutation()) {
        check_scenario(&apply(&text("assets/scenes/ms_vehicle_tab6.toml"), &m), false);
    }

    #[test]
    fn track_files_never_panic(m in mutation()) {
        check_track(&apply(&text("assets/scenes/bogie_tab6_curve.toml"), &m));
    }

    #[test]
    fn study_manifests_never_panic(m in mutation(), tag in any::<usize>()) {
        check_manifest(&apply(&manifest_text(), &m), tag);
    }

    #[test]
    fn vehicle_tables_never_panic(m in mutation()) {
        check_vehicle_tables(&m);
    }

    /// Issue 50: a `nan` or `inf` put in place of any number of the MS scene is refused by the
    /// parser itself, naming the line it is on (no range check can let it through).
    #[test]
    fn a_non_finite_number_anywhere_is_refused_at_its_line(k in any::<usize>(), which in 0usize..3) {
        let src = text("assets/scenes/ms_vehicle_tab6.toml");
        let nums = numbers(&src);
        let (a, b) = nums[k % nums.len()];
        // A number in a string or a comment is text, not a value.
        let line_start = src[..a].rfind('\n').map_or(0, |i| i + 1);
        let before = &src[line_start..a];
        prop_assume!(before.matches('"').count().is_multiple_of(2) && !before.contains('#') && before.contains('='));
        let token = ["nan", "inf", "-inf"][which];
        let mutated = format!("{}{token}{}", &src[..a], &src[b..]);
        let line = src[..a].matches('\n').count() + 1;
        match Scenario::parse(&mutated, "ms.toml") {
            Ok(_) => prop_assert!(false, "{token} at line {line} accepted"),
            Err(e) => {
                let msg = e.to_string();
                // (Where an integer is expected, the parser's type error names the line first.)
                prop_assert!(
                    (msg.contains(&format!("ms.toml:{line}:")) && msg.contains("not a number"))
                        || msg.contains(&format!("at line {line},")),
                    "{msg}"
                );
            }
        }
    }

    #[test]
    fn irregularity_csvs_never_panic(m in mutation(), s in "[-0-9.,e\n#a-z_]{0,200}") {
        let valid = "s_m,al_mm,vp_mm,gv_mm,cl_mm\n0,0.1,0.2,0.0,0.1\n1,0.2,0.1,0.1,0.0\n2,0.0,0.0,0.0,0.0\n3,-0.1,0.1,0.2,0.1\n4,0,0,0,0\n";
        check_irregularity_csv(&apply(valid, &m));
        check_irregularity_csv(&s);
    }
}

/// Inputs found by the fuzzing above (and by the hostile tries of issue 17), kept as regressions.
#[test]
fn regressions() {
    // Oversized irregularities: an error naming the limit, not an abort.
    let sc = small_scene().replace(
        "[simulation]",
        "[track]\nhorizontal = [ { type = \"straight\", from_m = 0.0, to_m = 1000.0 } ]\n\n[track.irregularities]\npsd = \"german-low\"\nseed = 1\nwavelength_min_m = 1e-6\nwavelength_max_m = 80.0\n\n[simulation]",
    );
    let e = Scenario::parse(&sc, "x.toml")
        .unwrap()
        .compile("x.toml", Path::new(ROOT))
        .err()
        .unwrap();
    assert!(e.to_string().contains("limit"), "{e}");
    // A joint at NaN or at 1e308 m: nalgebra's SVD (the over-constraint check) looped forever on
    // them — found by `the_ms_scenario_compiles_or_fails_cleanly`.
    for bad in ["nan", "1e308", "-inf"] {
        let ms = text("assets/scenes/ms_vehicle_tab6.toml").replacen(
            "at_m = [8.821, 0, 0.6]",
            &format!("at_m = [{bad}, 0, 0.6]"),
            1,
        );
        bounded("MS scenario with a joint at {bad}", || {
            // (Issue 50: nan and inf are refused by the parser itself, at their line.)
            match Scenario::parse(&ms, "x.toml") {
                Ok(sc) => {
                    assert_eq!(bad, "1e308", "{bad} was parsed");
                    let _ = sc.compile("x.toml", &Path::new(ROOT).join("assets/scenes"));
                }
                Err(e) => assert!(bad != "1e308" && e.to_string().contains("not a number"), "{e}"),
            }
        });
    }
    // A profile of one repeated point, and one with a NaN.
    check_profile("dup.csv", "0,0\n0,0\n0,0\n0,0\n0,0\n", ProfileKind::Wheel);
    check_profile("nan.dat", "0 0\n1 nan\n2 0\n3 0\n", ProfileKind::Rail);
    // An empty SIMPACK point list and a zero length unit.
    check_profile(
        "empty.prw",
        "header.begin\ntype = 1\nheader.end\npoint.begin\npoint.end\n",
        ProfileKind::Wheel,
    );
    let zero_unit = text("tests/data/profiles/MBench_S1002_v3.prw")
        .replace("units.len.f    = +1.000000000000000e+03", "units.len.f    = 0");
    check_profile("zero_unit.prw", &zero_unit, ProfileKind::Wheel);
}
