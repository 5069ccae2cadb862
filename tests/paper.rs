//! `kecsim paper`: the paper's §8 on the default scene (the MS vehicle on the Tab. 6 track),
//! shortened to 3 s: every figure's data is there and has the right length, Fig. 18–19's
//! differences are the runs' samples', Tab. 7's ratios the summaries', and the command's
//! recording reads back with the same figures.

use std::path::Path;
use std::sync::OnceLock;

use crate::common;
use common::{kecsim, kecsim_ok, rerun_verify, tmpdir};

use kecsim::paper::{BogieRole, PaperFigures, IRREGULARITY_STEP_M, PAPER_TAB7};
use kecsim::profile::Side;
use kecsim::scenario::{Scenario, Scene, DEFAULT_SCENARIO};

/// Simulated time of the test runs, s.
const DURATION_S: f64 = 3.0;

fn default_scene() -> Scene {
    Scenario::parse(DEFAULT_SCENARIO, "<default>")
        .unwrap()
        .compile("<default>", Path::new("."))
        .unwrap()
}

/// The figures of the default scene over 3 s, computed once for every test of this file.
fn figures() -> &'static PaperFigures {
    static F: OnceLock<PaperFigures> = OnceLock::new();
    F.get_or_init(|| kecsim::paper::assemble(&default_scene(), "lookup2", Some(DURATION_S)).unwrap())
}

#[test]
fn every_figure_has_its_data() {
    let f = figures();
    assert_eq!(f.tables_model, "lookup2");
    assert_eq!(
        (f.runs[0].model.as_str(), f.runs[1].model.as_str()),
        ("kec", "lookup2")
    );
    // Fig. 14, 16: a row per table row, increasing y from flange to flange through 0; the pair is
    // jump-free (the paper's Fig. 14: continuous), and the equivalent profiles reproduce the real
    // kinematics at the rows (§6).
    let sw = &f.sweep;
    assert!(sw.len() > 100, "{} rows", sw.len());
    assert!(sw.windows(2).all(|w| w[1].y > w[0].y));
    // Flange contact at ±5 mm on the stand-in wheel (its flange walls at ±2.7 mm).
    assert!(
        sw[0].y <= -4e-3 && sw[sw.len() - 1].y >= 4e-3,
        "{} .. {}",
        sw[0].y,
        sw[sw.len() - 1].y
    );
    let jump = sw
        .windows(2)
        .map(|w| (w[1].s_wheel[0] - w[0].s_wheel[0]).abs())
        .fold(0.0, f64::max);
    assert!(jump < 2e-3, "s^w moves {jump} m between rows");
    let (dz, dphi) = f.sweep_differences();
    assert!(dz < 1e-9 && dphi < 1e-8, "{dz} m, {dphi} rad");
    // Fig. 15: the real wheel, the equivalent one under the knife edge at −L_w.
    let p = &f.profiles;
    assert!(p.real.len() > 50 && p.equivalent.len() > 50 && !p.rail.is_empty());
    assert!(p.equivalent.iter().any(|q| (q.0 - p.knife_edge.0).abs() < 1e-3));
    // Fig. 17: the whole kilometre every 0.1 m.
    let n17 = (1000.0 / IRREGULARITY_STEP_M).round() as usize + 1;
    assert_eq!(f.irregularities.len(), n17);
    assert!(f.irregularities.iter().any(|r| r.1.iter().all(|v| v.abs() > 0.0)));
    assert_eq!(f.curves, vec![(150.0, 600.0)]);
    // Fig. 18–19: the front bogie (w1, w2 on b1), every sample of the 3 s at 100 Hz.
    assert_eq!(
        (
            f.bogie.front.as_str(),
            f.bogie.rear.as_deref(),
            f.bogie.frame.as_deref()
        ),
        ("w1", Some("w2"), Some("b1"))
    );
    let g = &f.figures;
    let n = (DURATION_S * 100.0).round() as usize + 1;
    assert_eq!((g.t.len(), g.distance_m.len()), (n, n));
    assert!(g.distance_m.windows(2).all(|w| w[1] > w[0]));
    let roles: Vec<(&str, BogieRole)> = g.kinematics.iter().map(|b| (b.name.as_str(), b.role)).collect();
    assert_eq!(
        roles,
        [
            ("w1", BogieRole::FrontWheelset),
            ("w2", BogieRole::RearWheelset),
            ("b1", BogieRole::Frame)
        ]
    );
    let wheels: Vec<(&str, Side)> = g
        .normal_forces
        .iter()
        .map(|w| (w.wheelset.as_str(), w.side))
        .collect();
    assert_eq!(
        wheels,
        [
            ("w1", Side::Left),
            ("w1", Side::Right),
            ("w2", Side::Left),
            ("w2", Side::Right)
        ]
    );
    for b in &g.kinematics {
        for s in [&b.y, &b.yaw] {
            assert_eq!((s.kec.len(), s.tables.len()), (n, n), "{}", b.name);
        }
    }
    for w in &g.normal_forces {
        assert_eq!((w.normal.kec.len(), w.normal.tables.len()), (n, n));
        // A loaded wheel: some 30-60 kN on the MS vehicle's motor bogie.
        assert!(
            w.normal.kec.iter().all(|&q| q > 1e4 && q < 1e5),
            "{q:?}",
            q = w.normal.kec[0]
        );
    }
    // The KEC and the tables agree on the straight within the paper's bounds.
    let (dy, dpsi) = f.max_differences();
    assert!(dy < 1e-3 && dpsi < 0.5e-3, "{dy} m, {dpsi} rad");
}

/// Fig. 18–19's differences are |KEC − tables| of the runs' own samples, at the same times; the
/// distance is the front wheelset's arc length in the KEC run.
#[test]
fn differences_are_recomputed_from_the_runs_samples() {
    let f = figures();
    let (kec, tab) = (&f.runs[0].output, &f.runs[1].output);
    let ws = |o: &'static kecsim::dynamics::RunOutput, name: &str| {
        o.wheelsets.iter().find(|w| w.0 == name).unwrap().1.as_slice()
    };
    let g = &f.figures;
    let w1 = ws(kec, "w1");
    for (i, s) in w1.iter().take(g.t.len()).enumerate() {
        assert_eq!((g.t[i], g.distance_m[i]), (s.t, s.s));
    }
    for b in &g.kinematics {
        let (y_k, y_t, psi_k, psi_t): (Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>) = match b.role {
            BogieRole::Frame => {
                let body = |o: &'static kecsim::dynamics::RunOutput| {
                    o.bodies.iter().find(|x| x.0 == b.name).unwrap().1.as_slice()
                };
                let col = |o, k: usize| body(o).iter().map(|(_, s)| s.q[k]).collect::<Vec<_>>();
                (col(kec, 1), col(tab, 1), col(kec, 5), col(tab, 5))
            }
            _ => {
                let col = |o, g: fn(&kecsim::dynamics::Sample) -> f64| {
                    ws(o, &b.name).iter().map(g).collect::<Vec<_>>()
                };
                (
                    col(kec, |s| s.y),
                    col(tab, |s| s.y),
                    col(kec, |s| s.yaw),
                    col(tab, |s| s.yaw),
                )
            }
        };
        let dy = b.y.abs_difference();
        let dpsi = b.yaw.abs_difference();
        assert_eq!(dy.len(), g.t.len());
        for i in 0..g.t.len() {
            assert_eq!(dy[i], (y_k[i] - y_t[i]).abs(), "{} Δy at {i}", b.name);
            assert_eq!(dpsi[i], (psi_k[i] - psi_t[i]).abs(), "{} Δψ at {i}", b.name);
        }
        assert_eq!(b.y.max_abs_difference(), dy.iter().copied().fold(0.0, f64::max));
    }
    for w in &g.normal_forces {
        let i = if w.side == Side::Left { 0 } else { 1 };
        let (a, b) = (ws(kec, &w.wheelset), ws(tab, &w.wheelset));
        let d = w.normal.abs_difference();
        for k in 0..g.t.len() {
            assert_eq!(d[k], (a[k].normal[i] - b[k].normal[i]).abs());
        }
    }
}

/// Tab. 7 from the runs' summaries: the integration's wall time over the simulated time, KEC's
/// over the tables', beside the paper's 347 s / 434 s for 52.6 s (6.59, 8.25, 0.80).
#[test]
fn table7_is_the_runs_cost() {
    let f = figures();
    let (k, t) = (&f.runs[0].output.summary, &f.runs[1].output.summary);
    let c = &f.cost;
    assert_eq!(
        (c.kec.integration_s, c.kec.preprocessing_s, c.kec.simulated_s),
        (k.wall_s, k.preprocessing_s, k.simulated_s)
    );
    assert_eq!(
        (c.tables.integration_s, c.tables.simulated_s),
        (t.wall_s, t.simulated_s)
    );
    assert!((c.kec.simulated_s - DURATION_S).abs() < 1e-9);
    assert_eq!(c.kec.per_real_time(), k.wall_s / k.simulated_s);
    assert_eq!(c.tables.per_real_time(), t.wall_s / t.simulated_s);
    assert_eq!(c.ratio(), k.wall_s / t.wall_s);
    assert_eq!(c.rhs_ratio(), k.rhs_evaluations as f64 / t.rhs_evaluations as f64);
    assert_eq!(
        (c.kec.steps, c.tables.rhs_evaluations),
        (k.steps, t.rhs_evaluations)
    );
    let (pk, pt) = PAPER_TAB7.per_real_time();
    assert_eq!(
        (
            format!("{pk:.2}"),
            format!("{pt:.2}"),
            format!("{:.2}", PAPER_TAB7.ratio())
        ),
        ("6.59".to_string(), "8.25".to_string(), "0.80".to_string())
    );
    let md = c.markdown();
    for s in [
        "| 347 | 434 |",
        "| 52.6 | 52.6 |",
        "(the paper: 0.80)",
        "| lookup2 (tables) |",
    ] {
        assert!(md.contains(s), "{s} missing:\n{md}");
    }
    // The yaw summary: no sample in the curve within 3 s (w1 starts near 28 m).
    for y in &f.yaw {
        assert_eq!((y.opposite_share, y.curve_samples), (None, 0));
        assert_eq!(y.max_abs_yaw.len(), 6);
    }
}

/// The command: Tab. 7 and Fig. 18's summary printed, and a recording that reads back with every
/// figure's series, as long as the library's figures.
#[test]
fn command_prints_table7_and_records_every_figure() {
    let f = figures();
    let dir = tmpdir("paper");
    let rrd = dir.join("paper.rrd");
    let stdout = kecsim_ok(
        &["paper", "--duration", "3", "--save", rrd.to_str().unwrap()],
        &dir,
    );
    for s in [
        "## Tab. 7: computational cost",
        "| 347 | 434 |",
        "## Fig. 18: the front bogie, KEC against lookup2",
        "| b1 (frame) |",
        "max \\|ψ\\| w6 [mrad]",
        "## Fig. 14-16",
    ] {
        assert!(stdout.contains(s), "{s} missing:\n{stdout}");
    }
    rerun_verify(&rrd);
    let chunks = kecsim::inspect::readback::recording_chunks(&rrd).unwrap();
    let rows = |e: &str| kecsim::inspect::readback::scalar_rows(&chunks, e);
    let n = f.figures.t.len();
    let m = f.sweep.len();
    let expect: [(&str, usize, usize); 12] = [
        ("/paper/fig14/s_wheel_mm", m, 2),
        ("/paper/fig14/s_rail_mm", m, 2),
        ("/paper/fig16/z_mm", m, 2),
        ("/paper/fig16/roll_mrad", m, 2),
        ("/paper/fig17/al_mm", f.irregularities.len(), 1),
        ("/paper/fig17/cl_mm", f.irregularities.len(), 1),
        ("/paper/fig18/y_mm/w1", n, 2),
        ("/paper/fig18/yaw_mrad/b1", n, 2),
        ("/paper/fig18/dy_mm/w2", n, 1),
        ("/paper/fig18/dyaw_mrad/b1", n, 1),
        ("/paper/fig19/normal_kn/w1", n, 4),
        ("/paper/fig19/dnormal_kn/w2", n, 2),
    ];
    for (entity, len, width) in expect {
        let r = rows(entity);
        assert_eq!(r.len(), len, "{entity}");
        assert!(r.iter().all(|v| v.len() == width), "{entity}: {width} series");
    }
    // The same figures as the library's (the runs are deterministic): Fig. 17 and the sweep
    // exactly, the recorded difference the recorded series'.
    let al = rows("/paper/fig17/al_mm");
    for (r, s) in al.iter().zip(&f.irregularities) {
        assert_eq!(r[0], s.1[0] * 1e3);
    }
    let sw = rows("/paper/fig14/s_wheel_mm");
    assert_eq!(
        sw[0],
        vec![f.sweep[0].s_wheel[0] * 1e3, f.sweep[0].s_wheel[1] * 1e3]
    );
    let y = rows("/paper/fig18/y_mm/w1");
    let dy = rows("/paper/fig18/dy_mm/w1");
    for (a, d) in y.iter().zip(&dy) {
        assert!((d[0] - (a[0] - a[1]).abs()).abs() < 1e-12);
    }
    let fig15: Vec<String> = chunks
        .iter()
        .map(|c| c.entity_path().to_string())
        .filter(|e| e.starts_with("/paper/fig15/"))
        .collect();
    for e in ["real", "equivalent", "rail", "knife_edge"] {
        assert!(fig15.contains(&format!("/paper/fig15/{e}")), "{e}: {fig15:?}");
    }
    // Fig. 17–19 as the layout shows them: static x–y figures against the distance, a line per
    // series (Fig. 18: kec and tables for each of the three bodies), the legends beside them.
    let statics: std::collections::HashSet<String> = chunks
        .iter()
        .filter(|c| c.is_static())
        .map(|c| c.entity_path().to_string())
        .collect();
    for e in [
        "/paper/fig17/plot_al/series/0",
        "/paper/fig18/plot_y/series/5",
        "/paper/fig18/plot_y/legend",
        "/paper/fig18/plot_dyaw/series/2",
        "/paper/fig19/plot_normal/w1/series/3",
        "/paper/fig19/plot_dnormal/w2/legend",
    ] {
        assert!(statics.contains(e), "missing {e}");
    }
    let summary = chunks
        .iter()
        .any(|c| c.entity_path().to_string() == "/paper/summary");
    assert!(summary);
}

/// Bad input is refused before any work: KEC against itself, an unwritable output, a duration.
#[test]
fn command_refuses_bad_input_at_once() {
    let dir = tmpdir("paper-bad");
    for (args, msg) in [
        (vec!["paper", "--tables", "kec"], "invalid value 'kec'"),
        (
            vec!["paper", "--save", "/nonexistent-dir/x.rrd"],
            "does not exist",
        ),
        (vec!["paper", "--duration", "-1"], "--duration -1"),
    ] {
        let t = std::time::Instant::now();
        let out = kecsim(&args, &dir);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && err.contains(msg), "{args:?}: {err}");
        assert!(t.elapsed().as_secs_f64() < 5.0, "{args:?} did work first");
    }
}
