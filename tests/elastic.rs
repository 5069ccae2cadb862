//! The elastic contact model (issue 14): the wheelset free, Hertz normal forces wherever the real
//! profiles interpenetrate. Checked against statics (the wheel loads carry the weight at the Hertz
//! approach), against a tight-tolerance integration of itself (a reference must not depend on its
//! integrator), against its own settings (damping, scan step), and against KEC on the paper's
//! irregular track while the wheels are in single-point contact. Bad settings: clear errors.

use crate::common;
use common::{kecsim, run_completed, run_ok, scene, tmpdir};

use kecsim::contact::forces::{HertzContact, RelativeCurvature};
use kecsim::contact::models::elastic::ElasticSettings;
use kecsim::contact::ContactModelSpec;
use kecsim::dynamics::integrator::Method;
use kecsim::dynamics::reference::G;
use kecsim::dynamics::RunOutput;
use kecsim::scenario::{RunOptions, SimulationSpec};

/// Largest |Δy| (mm) and |Δψ| (mrad) over every wheelset's common samples up to `end` s.
fn differences(a: &RunOutput, b: &RunOutput, end: f64) -> (f64, f64) {
    let (mut dy, mut dpsi) = (0.0f64, 0.0f64);
    for ((_, sa), (_, sb)) in a.wheelsets.iter().zip(&b.wheelsets) {
        for (p, q) in sa.iter().zip(sb).filter(|(p, _)| p.t <= end) {
            assert!((p.t - q.t).abs() < 1e-9);
            dy = dy.max((p.y - q.y).abs() * 1e3);
            dpsi = dpsi.max((p.yaw - q.yaw).abs() * 1e3);
        }
    }
    (dy, dpsi)
}

/// Centred on tangent ideal track, the free wheelset rests on its two Hertz contacts: the wheels'
/// vertical forces carry the axle load and the wheelset's weight (statics), and the wheelset sits
/// below KEC's rigid one by the Hertz approach at that load (δ / n_Z, from the Hertz solution at the
/// KEC run's contact point — Hertz itself is checked against Johnson's tables in the creep tests).
/// On S1002/54E1 at 1:20 (the MS pair), whose centred contact is a single point on each wheel (on
/// 60E1 at 1:40 two tread points share the centred load: the contact jump near the centre).
#[test]
fn the_free_wheelset_rests_on_its_hertz_contacts() {
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/wheelset_klingel.toml"),
    )
    .unwrap()
    .replace("rail = \"60e1\"", "rail = \"54e1\"")
    .replace("inclination = \"1:40\"", "inclination = \"1:20\"");
    let dir = tmpdir("elastic-rest");
    let path = dir.join("rest.toml");
    std::fs::write(&path, text).unwrap();
    let sc = kecsim::scenario::Scenario::read(&path)
        .unwrap()
        .compile("rest.toml", &dir)
        .unwrap();
    assert_eq!(sc.pair.rail_placement.inclination_rad, (0.05f64).atan());
    let centred = |s: &mut SimulationSpec| {
        s.initial.lateral_m = 0.0;
        s.duration_s = 1.0;
    };
    let elastic = run_completed(&sc, "elastic", centred);
    let kec = run_completed(&sc, "kec", centred);
    let (e, k) = (elastic.samples().last().unwrap(), kec.samples().last().unwrap());
    let weight = 100_000.0 + 1813.0 * G;
    let carried = e.q_force[0] + e.q_force[1];
    assert!(
        (carried - weight).abs() < 1e-4 * weight,
        "Q_l + Q_r = {carried} N vs {weight} N"
    );
    assert!(
        e.y.abs() < 1e-6 && e.roll.abs() < 1e-6,
        "y {} roll {}",
        e.y,
        e.roll
    );
    // The approach at the rigid contact point under the measured normal force.
    let material = sc.contact_forces.material;
    let kin_point = {
        // The KEC run's left contact: radius, angle, curvatures.
        let built = sc
            .build_run(&RunOptions {
                contact: Some("kec".into()),
                speed_m_s: None,
                ..Default::default()
            })
            .unwrap();
        built
            .vehicle
            .contact()
            .configuration(0.0, &Default::default(), &mut Default::default())
            .unwrap()
            .contacts[0]
    };
    let hertz = HertzContact::solve(
        RelativeCurvature::at_contact(&kin_point),
        e.normal[0],
        &material,
        &material,
    )
    .unwrap();
    let sink = hertz.penetration / kin_point.normal.1;
    let measured = k.z - e.z;
    println!(
        "rest: Q {:.1} + {:.1} kN, sunk {:.4} mm below KEC, Hertz approach / n_Z {:.4} mm",
        e.q_force[0] * 1e-3,
        e.q_force[1] * 1e-3,
        measured * 1e3,
        sink * 1e3
    );
    assert!(
        (measured - sink).abs() < 0.01 * sink,
        "sunk {measured} m vs {sink} m"
    );
}

/// A reference must not depend on how it is integrated or on its numerical settings: the MS
/// vehicle on the irregular Tab. 6 track for 3 s (through its first tread–flange-root contact
/// jumps) with BDF at rtol 1e-4 against DOPRI5 at rtol 1e-7, and with the contact damping halved
/// and the scan step halved. (The constraint models, by contrast, differ among themselves by
/// millimetres after the jumps: the README.)
#[test]
#[ignore = "slow: the elastic reference at several numerical settings (~19 s)"]
fn the_elastic_reference_does_not_depend_on_its_numerics() {
    let sc = scene("ms_vehicle_tab6_s1002.toml");
    let short = |s: &mut SimulationSpec| s.duration_s = 3.0;
    let base = run_completed(&sc, "elastic", short);
    let tight = run_completed(&sc, "elastic", |s| {
        short(s);
        s.integrator.method = Method::Dopri5;
        s.integrator.rtol = 1e-7;
        s.integrator.atol = 1e-9;
    });
    let settings = |damping: f64, step: f64| {
        move |s: &mut SimulationSpec| {
            short(s);
            s.contact = Some(ContactModelSpec::Elastic(ElasticSettings {
                damping_s_per_m: damping,
                scan_step_m: step,
            }));
        }
    };
    let soft = run_completed(&sc, "elastic", settings(1.0, 2.5e-4));
    let fine = run_completed(&sc, "elastic", settings(2.0, 1.25e-4));
    let (dy, dpsi) = differences(&base, &tight, 3.0);
    let (dys, dpsis) = differences(&base, &soft, 3.0);
    let (dyf, dpsif) = differences(&base, &fine, 3.0);
    let max_y = base
        .wheelsets
        .iter()
        .flat_map(|(_, s)| s.iter())
        .map(|p| p.y.abs())
        .fold(0.0, f64::max);
    println!(
        "elastic MS 3 s (max |y| {:.2} mm): BDF 1e-4 vs DOPRI5 1e-7 {dy:.4} mm {dpsi:.4} mrad; damping 1 s/m {dys:.4} mm {dpsis:.4} mrad; scan 0.125 mm {dyf:.4} mm {dpsif:.4} mrad",
        max_y * 1e3
    );
    assert!(
        max_y > 5.2e-3,
        "the window must pass the contact jump at 5.16 mm: {max_y}"
    );
    assert!(dy < 0.01 && dpsi < 0.02, "integrator: {dy} mm, {dpsi} mrad");
    assert!(dys < 0.03 && dpsis < 0.03, "damping: {dys} mm, {dpsis} mrad");
    assert!(dyf < 0.01 && dpsif < 0.01, "scan step: {dyf} mm, {dpsif} mrad");
}

/// The paper's case (MS vehicle, Tab. 6 track with irregularities): elastic against KEC while
/// every wheel is in single-point contact — up to the first real contact jump of either run. The
/// trailing four wheelsets agree to micrometres; the leading two, which approach the jump at
/// 5.16 mm, within 0.2 mm: on this pair the flange root is only tens of micrometres from the rail
/// when the tread carries the wheel (`kecsim contact --rail 54e1 --inclination 1:20`), so under
/// the tread's Hertz approach (0.09 mm) it starts to carry load ~0.5 mm of y before the rigid jump.
#[test]
fn ms_vehicle_elastic_matches_kec_until_the_first_contact_jump() {
    let sc = scene("ms_vehicle_tab6_s1002.toml");
    let go = |kind| run_completed(&sc, kind, |s| s.duration_s = 1.3);
    let (mut elastic, mut kec) = (go("elastic"), go("kec"));
    let first_jump = |o: &RunOutput| {
        kecsim::compare::first_contact_jump(o)
            .expect("the window reaches a contact jump")
            .0
    };
    let end = first_jump(&elastic).min(first_jump(&kec));
    let (dy, dpsi) = differences(&elastic, &kec, end);
    elastic.wheelsets.drain(..2);
    kec.wheelsets.drain(..2);
    let (dyt, dpsit) = differences(&elastic, &kec, end);
    println!("elastic vs KEC to the first jump ({end:.2} s): all {dy:.4} mm {dpsi:.4} mrad; w3-w6 {dyt:.4} mm {dpsit:.4} mrad");
    assert!(end > 0.5, "a jump at {end} s leaves no window");
    assert!(dy < 0.2 && dpsi < 0.05, "{dy} mm, {dpsi} mrad");
    assert!(dyt < 0.01 && dpsit < 0.005, "{dyt} mm, {dpsit} mrad");
}

/// Bad settings: the contact damping zero or negative, the scan step out of range — errors that
/// name the file and the key.
#[test]
fn bad_elastic_settings_are_clear_errors() {
    let dir = tmpdir("elastic-bad");
    let base = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/wheelset_klingel.toml"),
    )
    .unwrap();
    for (line, key) in [
        ("damping_s_per_m = 0.0", "damping_s_per_m"),
        ("damping_s_per_m = -1.0", "damping_s_per_m"),
        ("scan_step_m = 0.01", "scan_step_m"),
    ] {
        let text = base
            .replace("model = \"kec\"", &format!("model = \"elastic\"\n{line}"))
            .replace("two_point_approach_m = 5e-5", "");
        let path = dir.join("bad.toml");
        std::fs::write(&path, text).unwrap();
        let out = kecsim(&["run", path.to_str().unwrap(), "--save", "x.rrd"], &dir);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{line}: accepted");
        assert!(
            err.contains("bad.toml") && err.contains(&format!("simulation.contact.{key}")),
            "{line}: {err}"
        );
    }
}

/// The critical speed (issue 14 item 3), as it is usually measured for a nonlinear wheelset: the
/// hunting limit cycle slowed down until it dies out (`wheelset_critical_speed_down.toml`, from
/// 42 m/s at −0.5 m/s², S1002/60E1 1:40, whose contact jumps between two tread points a few tenths
/// of a millimetre off the centre). The elastic model shares the load between the two points over
/// the Hertz approach; KEC's two-point transitions stand for that sharing with one resultant. Once
/// they span the sharing (the default: δ 0.05 mm, limit 2 mm) the speed no longer depends on
/// their width: δ from 0.03 to 0.5 mm and limits from 0.5 to 2 mm give the same speed, some 13 %
/// below elastic's; the 0.05 mm limit of before, some 23 % below. (The accelerating ramp's onset
/// is no measure here: the centred wheelset's motion decays to round-off before the onset and
/// what the ramp then sees grows from rounding errors.)
#[test]
#[ignore = "slow: speed ramps with the elastic model and five transition settings (~25 s)"]
fn critical_speed_elastic_against_kec_transitions() {
    let sc = scene("wheelset_critical_speed_down.toml");
    let extinction = |contact: &str, kec: Option<(f64, f64)>| {
        let out = run_ok(&sc, contact, |s| {
            s.speed_m_s = 42.0;
            s.duration_s = 36.0;
            if let Some((approach, width)) = kec {
                s.contact = Some(ContactModelSpec::Kec(kecsim::contact::models::kec::KecSettings {
                    two_point_approach_m: approach,
                    two_point_max_width_m: width,
                }));
            }
        });
        out.summary
            .critical_speed_m_s
            .expect("the hunting cycle dies out on the ramp")
    };
    let elastic = extinction("elastic", None);
    let d = kecsim::contact::models::kec::KecSettings::default();
    let default = extinction("kec", Some((d.two_point_approach_m, d.two_point_max_width_m)));
    let wide: Vec<f64> = [(3e-5, 2e-3), (5e-4, 5e-4)]
        .iter()
        .map(|&k| extinction("kec", Some(k)))
        .collect();
    let narrow = extinction("kec", Some((5e-5, 5e-5)));
    println!(
        "nonlinear critical speed: elastic {elastic:.2} m/s; KEC default {default:.2} m/s, other wide transitions {wide:.2?} m/s; KEC 0.05 mm limit {narrow:.2} m/s"
    );
    for v in &wide {
        assert!((v / default - 1.0).abs() < 0.01, "{v} vs {default}");
    }
    assert!(
        (default / elastic - 1.0).abs() < 0.15,
        "KEC {default} vs elastic {elastic}"
    );
    assert!(
        elastic - narrow > 1.5 * (elastic - default),
        "{narrow} {default} {elastic}"
    );
}

/// The paper's case over the whole kilometre, KEC against the elastic reference. In the curve
/// (150–600 m) the paths agree to a tenth of a millimetre (measured 2026-12-04, the speed held:
/// every sample within 0.5 mm, median 0.042 mm); on the straights the wheelsets, without lateral
/// guidance, wander on their own ways (millimetres: the README). So the comparison asserted is the
/// share of the curve within 0.5 mm (≥ 99 % for every wheelset) and the running-safety figures
/// engineers read (EN 14363 style sliding means): every wheelset's Y/Q and ΣY within 3 % (measured
/// 1.0 % and 0.8 %). Before issue 46 the coasting vehicle's leading IRW-wheelset crossed its
/// clearance from flange to flange at 534–553 m, the two models a few metres apart: 95.7 % within
/// 0.5 mm, Y/Q within 3.5 %, ΣY within 3.3 % — the bounds were then 90 %, 6 % and 10 %. Both complete with no wheel lifting (KEC's run once stopped at a
/// flange impact at 26.5 s that unloaded the leading wheelset's inner wheel: `tests/lift.rs`).
/// The suite's one run of this kilometre with KEC: every claim on it is asserted here.
#[test]
#[ignore = "slow: the MS kilometre with KEC and the elastic model (~58 s)"]
fn ms_vehicle_kilometre_kec_against_elastic() {
    let sc = scene("ms_vehicle_tab6_s1002.toml");
    let (elastic, kec) = (
        run_completed(&sc, "elastic", |_| {}),
        run_completed(&sc, "kec", |_| {}),
    );
    let mut least_share = 1.0f64;
    let mut median_curve = 0.0f64;
    for ((_, a), (_, b)) in elastic.wheelsets.iter().zip(&kec.wheelsets) {
        let mut d: Vec<f64> = a
            .iter()
            .zip(b)
            .filter(|(p, _)| (160.0..590.0).contains(&p.s))
            .map(|(p, q)| {
                assert!((p.t - q.t).abs() < 1e-9);
                (p.y - q.y).abs()
            })
            .collect();
        assert!(d.len() > 1000, "{} curve samples", d.len());
        let close = d.iter().filter(|v| **v < 5e-4).count() as f64 / d.len() as f64;
        least_share = least_share.min(close);
        d.sort_by(f64::total_cmp);
        median_curve = median_curve.max(d[d.len() / 2]);
    }
    let (se, sk) = (
        elastic.summary.safety.as_ref().unwrap(),
        kec.summary.safety.as_ref().unwrap(),
    );
    let mut worst_yq = 0.0f64;
    let mut worst_sum_y = 0.0f64;
    for (e, k) in se.wheelsets.iter().zip(&sk.wheelsets) {
        println!(
            "{}: Y/Q {:.3} / {:.3}, ΣY {:.1} / {:.1} kN (elastic / KEC)",
            e.name,
            e.y_over_q_2m,
            k.y_over_q_2m,
            e.sum_y_2m_n * 1e-3,
            k.sum_y_2m_n * 1e-3
        );
        worst_yq = worst_yq.max((e.y_over_q_2m / k.y_over_q_2m - 1.0).abs());
        worst_sum_y = worst_sum_y.max((e.sum_y_2m_n / k.sum_y_2m_n - 1.0).abs());
    }
    println!(
        "MS kilometre, elastic vs KEC: in the curve ≥ {:.1} % of every wheelset's samples within 0.5 mm, median |Δy| ≤ {:.3} mm; Y/Q within {:.1} %, ΣY within {:.1} %; wall {:.1} s vs {:.1} s",
        least_share * 100.0,
        median_curve * 1e3,
        worst_yq * 100.0,
        worst_sum_y * 100.0,
        elastic.summary.wall_s,
        kec.summary.wall_s
    );
    assert!(
        least_share > 0.99 && median_curve < 1e-4,
        "in the curve: {least_share}, {median_curve} m"
    );
    assert!(
        worst_yq < 0.03 && worst_sum_y < 0.03,
        "Y/Q {worst_yq}, ΣY {worst_sum_y}"
    );
    for o in [&elastic, &kec] {
        let s = &o.summary;
        assert_eq!(s.outcome, "completed", "{}: {:?}", s.contact_model, s.error);
        assert!(s.simulated_s >= 51.0 - 1e-9, "{}", s.simulated_s);
        assert!(o.landings.is_empty() && s.landings == 0, "{}", s.contact_model);
        assert!(s.min_normal_n > 20e3, "{}", s.min_normal_n);
        // No wheel left its rail: every sample of every wheel, not the summary's count.
        let lift = o.samples().iter().flat_map(|p| p.lift).fold(0.0, f64::max);
        assert_eq!(lift, 0.0, "{}", s.contact_model);
    }
}

/// A wheel profile whose flange is too shallow to tell flange contact from a climb (S1002's tread
/// with a 30° cone for a flange, 17 mm high): the elastic model refuses it at the build, naming
/// the problem. (A profile without a flange at all is refused when it is read.)
#[test]
fn a_wheel_profile_with_a_shallow_flange_is_refused() {
    let dir = tmpdir("elastic-shallow-flange");
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut profile: String = std::fs::read_to_string(root.join("profiles/s1002.csv"))
        .unwrap()
        .lines()
        .filter(|l| {
            l.starts_with('#')
                || l.starts_with("y_mm")
                || l.split(',')
                    .next()
                    .and_then(|y| y.trim().parse::<f64>().ok())
                    .is_some_and(|y| y >= -26.0)
        })
        .map(|l| format!("{l}\n"))
        .collect();
    // The cone: from (−26, −2.741) down at 30° to y = −50 mm, prepended in y order.
    let slope = 30f64.to_radians().tan();
    let cone: String = (1..=48)
        .rev()
        .map(|k| {
            let y = -26.0 - 0.5 * k as f64;
            format!("{y:.3},{:.6}\n", -2.741025090 - slope * (-26.0 - y))
        })
        .collect();
    let header_end = profile.find("y_mm,z_mm\n").unwrap() + "y_mm,z_mm\n".len();
    profile.insert_str(header_end, &cone);
    std::fs::write(dir.join("cone.csv"), profile).unwrap();
    let text = std::fs::read_to_string(root.join("assets/scenes/wheelset_klingel.toml"))
        .unwrap()
        .replace("wheel = \"s1002\"", "wheel = \"cone.csv\"")
        .replace("model = \"kec\"", "model = \"elastic\"")
        .replace("two_point_approach_m = 5e-5", "");
    std::fs::write(dir.join("cone.toml"), text).unwrap();
    let out = kecsim(&["run", "cone.toml", "--save", "x.rrd"], &dir);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains("cone.toml") && err.contains("too shallow to guide the wheelset"),
        "{err}"
    );
}
