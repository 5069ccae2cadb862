//! The hard-case suite (issue 14; `kecsim bench hard`): each scene ends in a physical answer with
//! the elastic contact model, the constraint models' outcomes beside it are what they are (a
//! stated limit, never a silent one), and where both complete they agree.

use crate::common;
use common::{kecsim_ok, tmpdir};

use kecsim::bench::hard::{compile, run_suite, HARD_SCENES};
use kecsim::dynamics::integrator::Method;
use kecsim::scenario::RunOptions;

/// Every scene for its first 2 s: the elastic runs complete, but for the flange climbs of the
/// alignment kink and of the Manchester vehicle under FRA class 4 at 30 m/s (derailments); the flange impact lifts the far
/// wheel and puts it back (lift and landing from the profiles), with the impact's force; in the
/// tight curves KEC's flanging agrees with elastic (|y| and the Y/Q sliding means); over the gauge
/// widening elastic and KEC complete; the 2-entry table reports leaving its gauge range by name;
/// no KEC run fails numerically.
#[test]
#[ignore = "slow: the whole hard-case suite with the elastic model and three constraint models (~30 s)"]
fn hard_cases_end_in_physical_answers() {
    let runs = run_suite(Some(2.0)).unwrap();
    let find = |scene: &str, model: &str| {
        runs.iter()
            .find(|r| r.scene == scene && r.output.summary.contact_model == model)
            .unwrap_or_else(|| panic!("{scene} {model}"))
    };
    for r in runs.iter().filter(|r| {
        r.output.summary.contact_model == "elastic"
            && !["alignment_kink", "manchester_fra4"].contains(&r.scene)
    }) {
        assert_eq!(
            r.output.summary.outcome, "completed",
            "{}: {:?}",
            r.scene, r.output.summary.error
        );
    }
    // KEC ends every scene in a physical answer too — completed, or a derailment with the wheel
    // named (its flange impacts may throw the wheelset off both rails: it flies and lands) —
    // never in a numerical failure.
    for r in runs.iter().filter(|r| r.output.summary.contact_model == "kec") {
        let s = &r.output.summary;
        assert!(
            s.outcome == "completed"
                || (s.outcome == "derailed" && s.error.as_deref().is_some_and(|e| e.contains("wheel"))),
            "{}: {} {:?}",
            r.scene,
            s.outcome,
            s.error
        );
    }
    let impact = &find("flange_impact", "elastic").output;
    let s = &impact.summary;
    println!(
        "flange impact (elastic): max |y| {:.2} mm, normal force up to {:.0} kN, lift {:.2} mm for {:.3} s",
        s.max_abs_y_mm,
        s.max_normal_n * 1e-3,
        s.max_lift_mm,
        s.longest_lift_s
    );
    assert!(
        s.max_lift_mm > 1.0 && s.longest_lift_s > 0.005,
        "{} mm, {} s",
        s.max_lift_mm,
        s.longest_lift_s
    );
    assert!(s.max_normal_n > 300e3, "{}", s.max_normal_n);
    let last = impact.samples().last().unwrap();
    assert!(last.lift == [0.0, 0.0], "landed: {:?}", last.lift);
    assert!(s.max_abs_y_mm < 8.0, "the flange holds it: {}", s.max_abs_y_mm);
    // Lift and landing: at 0.7 m/s the flange impact throws the flanging (left) wheel up off its
    // rail with both models (after the far wheel's brief unloading, < 0.2 mm), and it lands;
    // KEC's rigid impact throws it higher (measured 1.35 mm for 14 ms against elastic's 0.76 mm,
    // which bounces twice): the same event, within a factor of 2.5 in height.
    let lift = |model: &str| {
        let o = &find("flange_lift", model).output;
        assert_eq!(o.summary.outcome, "completed", "{model}: {:?}", o.summary.error);
        let side = |i: usize| o.samples().iter().map(|p| p.lift[i]).fold(0.0, f64::max);
        assert!(side(1) < 2e-4, "{model}: the far wheel {}", side(1));
        assert_eq!(o.samples().last().unwrap().lift, [0.0, 0.0], "{model}: landed");
        (side(0), o.summary.longest_lift_s)
    };
    let ((he, te), (hk, tk)) = (lift("elastic"), lift("kec"));
    println!(
        "flange lift: left wheel {:.3} mm, longest lift {:.3} s (elastic); {:.3} mm, {:.3} s (KEC)",
        he * 1e3,
        te,
        hk * 1e3,
        tk
    );
    assert!(he > 3e-4 && hk > 3e-4, "{he} {hk}");
    // Rigid impact against the Hertz spring: different physics, so no equality to expect; their
    // ratio is a property of the scene (measured 1.78), held to ±15 % so that a change of either
    // model shows.
    assert!(hk / he > 1.5 && hk / he < 2.05, "{hk} vs {he}");
    assert!(find("flange_lift", "kec").output.summary.landings >= 1);
    // The cross-level dip: the right wheel flies over it and lands, with both models; the flights
    // last alike (measured 16 and 14 ms), KEC's lower (0.40 against 0.83 mm).
    let flight = |model: &str| {
        let o = &find("cross_level_dip", model).output;
        assert_eq!(o.summary.outcome, "completed", "{model}: {:?}", o.summary.error);
        let side = |i: usize| o.samples().iter().map(|p| p.lift[i]).fold(0.0, f64::max);
        assert_eq!(o.samples().last().unwrap().lift, [0.0, 0.0], "{model}: landed");
        (side(1), o.summary.longest_lift_s)
    };
    let ((de, te), (dk, tk)) = (flight("elastic"), flight("kec"));
    println!(
        "cross-level dip: right wheel {:.3} mm for {te:.3} s (elastic), {:.3} mm for {tk:.3} s (KEC)",
        de * 1e3,
        dk * 1e3
    );
    assert!(de > 2e-4 && dk > 2e-4, "{de} {dk}");
    // As above, measured bands (±15 %): flight times 14 against 16 ms (0.88), heights 0.48.
    assert!(tk / te > 0.75 && tk / te < 1.0, "{tk} vs {te}");
    assert!(dk / de > 0.41 && dk / de < 0.56, "{dk} vs {de}");
    for scene in ["tight_curve_low", "tight_curve_line"] {
        let (e, k) = (find(scene, "elastic"), find(scene, "kec"));
        assert_eq!(k.output.summary.outcome, "completed");
        let yq = |r: &kecsim::bench::hard::HardRun| {
            r.output
                .summary
                .safety
                .as_ref()
                .unwrap()
                .wheelsets
                .iter()
                .map(|w| w.y_over_q_2m)
                .fold(0.0, f64::max)
        };
        let dy = k.dy_to_elastic.unwrap();
        println!(
            "{scene}: KEC vs elastic |Δy| {:.3} mm, Y/Q (2 m) {:.3} vs {:.3}",
            dy * 1e3,
            yq(k),
            yq(e)
        );
        assert!(dy < 5e-4, "{scene}: {dy}");
        assert!(
            (yq(k) / yq(e) - 1.0).abs() < 0.05,
            "{scene}: {} vs {}",
            yq(k),
            yq(e)
        );
    }
    // The alignment kink: the rails drag the wheelset against its ties by the right flange; the
    // elastic wheel climbs past the flange's largest angle — a derailment, the wheel named, its Y/Q
    // over the last 2 m beyond Nadal's limit. KEC derails there too, or (with softer ties, before
    // issue 46) holds the wheel at the flange's largest angle and completes; either way its own
    // running safety figures flag the exceedance. Over the scene's own 4 s, not the suite's 2 s
    // window (with 2 × 2 MN/m ties the climb was a bifurcation, 1.4 s apart between two builds
    // that differed by round-off in the creep forces; at 2 × 2.5 MN/m it climbs at the kink).
    let kink_scene = HARD_SCENES.iter().find(|h| h.name == "alignment_kink").unwrap();
    let kink_scene = compile(kink_scene, None).unwrap();
    let kink_run = |model: &str| {
        kink_scene
            .build_run(&kecsim::scenario::RunOptions {
                contact: Some(model.to_string()),
                ..Default::default()
            })
            .unwrap()
            .run(&mut [])
    };
    let kink_elastic = kink_run("elastic");
    let kink = &kink_elastic.summary;
    let nadal = kink.safety.as_ref().unwrap().nadal_limit;
    assert_eq!(kink.outcome, "derailed", "{:?}", kink.error);
    assert!(
        kink.error
            .as_deref()
            .unwrap()
            .contains("the right wheel climbs its flange"),
        "{:?}",
        kink.error
    );
    assert!(
        kink.derailment_max_y_over_q_2m.unwrap() > nadal,
        "{:?}",
        kink.derailment_max_y_over_q_2m
    );
    let kink_kec = kink_run("kec");
    let kec_kink = &kink_kec.summary;
    let kec_yq = kec_kink.safety.as_ref().unwrap().wheelsets[0].y_over_q_2m;
    println!(
        "alignment kink: elastic derails at {:.2} s (Y/Q over its last 2 m {:.2}); KEC {} with Y/Q (2 m) {kec_yq:.2}; Nadal {nadal:.2}",
        kink.simulated_s,
        kink.derailment_max_y_over_q_2m.unwrap(),
        kec_kink.outcome
    );
    assert!(kec_yq > nadal, "{kec_yq}");
    // FRA class 4 at 30 m/s: the elastic leading wheelset climbs its flange (Y/Q over its last
    // 2 m beyond Nadal's limit) soon after the irregularities have grown in.
    let fra = &find("manchester_fra4", "elastic").output.summary;
    println!(
        "FRA class 4, 30 m/s: elastic {} at {:.2} s (Y/Q over 2 m {:?}); KEC {} at {:.2} s (Y/Q over 2 m {:?})",
        fra.outcome,
        fra.simulated_s,
        fra.derailment_max_y_over_q_2m,
        find("manchester_fra4", "kec").output.summary.outcome,
        find("manchester_fra4", "kec").output.summary.simulated_s,
        find("manchester_fra4", "kec").output.summary.derailment_max_y_over_q_2m
    );
    assert_eq!(fra.outcome, "derailed", "{:?}", fra.error);
    assert!(fra.derailment_max_y_over_q_2m.unwrap() > nadal);
    assert_eq!(find("gauge_widening", "kec").output.summary.outcome, "completed");
    // The per-wheel table (lookup2) follows the widened gauge as KEC does — each wheel at its
    // own rail, the field side continued beyond the centred table (measured over 2 s, the first
    // wheelset: 0.27 mm from KEC, 0.48 mm from the elastic model, KEC 0.36 mm from it); the
    // paper's 2-entry table ends at its last gauge column.
    let (k, t, el) = (
        find("gauge_widening", "kec"),
        find("gauge_widening", "lookup2"),
        find("gauge_widening", "elastic"),
    );
    assert_eq!(
        t.output.summary.outcome, "completed",
        "{:?}",
        t.output.summary.error
    );
    let apart = |a: &kecsim::bench::hard::HardRun, b: &kecsim::bench::hard::HardRun| {
        a.output
            .samples()
            .iter()
            .zip(b.output.samples())
            .map(|(p, q)| (p.y - q.y).abs())
            .fold(0.0, f64::max)
    };
    let (dk, de, dke) = (apart(k, t), apart(el, t), apart(el, k));
    println!(
        "gauge widening: lookup2 (per wheel) max |Δy| {:.4} mm from KEC, {:.4} mm from elastic (KEC {:.4} mm from elastic)",
        dk * 1e3,
        de * 1e3,
        dke * 1e3
    );
    assert!(dk < 0.4e-3 && de < 0.7e-3, "{dk} {de}");
    let paper = &find("gauge_widening", "lookup2-paper").output.summary;
    assert_eq!(paper.outcome, "failed");
    let e = paper.error.as_deref().unwrap();
    assert!(e.contains("gv = 10.0000 mm is outside the table"), "{e}");
}

/// The flange impact's figures do not depend on the integration: ROS34PW2 at rtol 1e-6 (the
/// scene's) against DOPRI5 at 1e-8 over the impact, lift and landing (0.3 s).
#[test]
fn the_flange_impact_does_not_depend_on_the_integration() {
    let hs = HARD_SCENES.iter().find(|s| s.name == "flange_impact").unwrap();
    let run = |tight: bool| {
        let mut sc = compile(hs, Some(0.3)).unwrap();
        if tight {
            let sim = &mut sc.simulation.as_mut().unwrap().0;
            sim.integrator.method = Method::Dopri5;
            sim.integrator.rtol = 1e-8;
            sim.integrator.atol = 1e-10;
        }
        sc.build_run(&RunOptions::default()).unwrap().run(&mut []).summary
    };
    let (a, b) = (run(false), run(true));
    println!(
        "flange impact: lift {:.4} / {:.4} mm, normal force {:.1} / {:.1} kN, max |y| {:.4} / {:.4} mm (scene / DOPRI5 1e-8)",
        a.max_lift_mm,
        b.max_lift_mm,
        a.max_normal_n * 1e-3,
        b.max_normal_n * 1e-3,
        a.max_abs_y_mm,
        b.max_abs_y_mm
    );
    assert!((a.max_lift_mm / b.max_lift_mm - 1.0).abs() < 0.01);
    assert!((a.max_normal_n / b.max_normal_n - 1.0).abs() < 0.02);
    assert!((a.max_abs_y_mm - b.max_abs_y_mm).abs() < 0.01);
}

/// `kecsim bench hard --duration S`: one row per scene and model, the outcome spelled out.
#[test]
#[ignore = "slow: every hard scene built for the elastic model and KEC (~16 s, the preprocessing)"]
fn bench_hard_prints_the_suite() {
    let out = kecsim_ok(&["bench", "hard", "--duration", "0.05"], &tmpdir("bench-hard"));
    for hs in &HARD_SCENES {
        assert!(
            out.contains(&format!("| {} | elastic | completed |", hs.name)),
            "{}: {out}",
            hs.name
        );
        for m in hs.also {
            assert!(
                out.contains(&format!("| {} | {m} |", hs.name)),
                "{} {m}: {out}",
                hs.name
            );
        }
    }
}
