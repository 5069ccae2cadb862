//! The design against closed forms and the independent contact solve.

use super::*;
use crate::contact::lookup::{LookupTable1, TableSettings};
use crate::profile::embedded::EmbeddedProfile;
use crate::profile::StandardProfile;

/// The MS stand-in's target and placement, as shipped.
fn ms_standin() -> (DesignTarget, Profile, Inclination, TrackGauge, WheelsetGeometry) {
    shipped_target(include_str!("../../../assets/designs/ms-standin.toml"))
}

/// A shipped target and its placement.
fn shipped_target(text: &str) -> (DesignTarget, Profile, Inclination, TrackGauge, WheelsetGeometry) {
    let (t, p) = parse_target(text, "shipped target").unwrap();
    let rail = p.rail.as_deref().unwrap();
    assert!(rail.starts_with("54e1"), "{rail}");
    let wheelset = WheelsetGeometry {
        back_to_back_m: p.back_to_back_mm.unwrap() * 1e-3,
        nominal_radius_m: p.nominal_radius_mm.unwrap() * 1e-3,
        ..WheelsetGeometry::default()
    };
    (
        t,
        Profile::resolve(rail, crate::profile::ProfileKind::Rail).unwrap(),
        p.inclination.unwrap().parse().unwrap(),
        TrackGauge::default(),
        wheelset,
    )
}

/// Circle on circle: on a rail head that is one arc of radius R, the target γ(y) = asin(y/Δ) is
/// met by the wheel arc of radius R + Δ (at zero roll the contact sits where both normals make γ,
/// y(γ) = ∫ (ρ_w − ρ_r) cos γ dγ = Δ sin γ). The design's wheel, with its roll iterated, must be
/// that arc: its curvature from the profile's spline within 1 % of 1/(R + Δ).
#[test]
#[ignore = "slow: a wheel designed on a circular rail (~20 s)"]
fn a_circular_rail_gets_the_conjugate_circle() {
    let (r, delta) = (0.080, 0.020);
    let s: Vec<f64> = (0..=800).map(|k| -0.04 + 0.08 * k as f64 / 800.0).collect();
    let z: Vec<f64> = s.iter().map(|&x| (r * r - x * x).sqrt() - r).collect();
    let rail = Profile::from_points("arc80", ProfileKind::Rail, "test", s, z).unwrap();
    let target = DesignTarget {
        name: "conjugate".into(),
        contact_angle: (-32..=32)
            .map(|k| {
                let y = k as f64 * 0.25e-3;
                (y, (y / delta).asin())
            })
            .collect(),
        flange_height_m: 0.013,
        flange_tip_radius_m: 0.003,
        field_end_m: 0.05,
        curvature_ramp_per_rad: CURVATURE_RAMP_PER_RAD,
        output_step_m: OUTPUT_STEP_M,
    };
    // The head's gauge point 5 mm below its top; a wide gauge leaves room for the shallow flank.
    let gauge = TrackGauge {
        gauge_m: 1.450,
        measuring_depth_m: 0.005,
    };
    let d = design_wheel(
        &rail,
        Inclination::UPRIGHT,
        gauge,
        WheelsetGeometry::default(),
        &target,
    )
    .unwrap();
    // Curvature at the designed nodes.
    let mut worst: f64 = 0.0;
    // (Both wheels touch at equal radii here, so the roll stays zero and the relation is exact;
    // the last 0.5 mm joins the flank.)
    for n in d.nodes.iter().filter(|n| n.y.abs() < 7.5e-3) {
        let k = d.profile.eval(n.s_wheel).curvature();
        worst = worst.max((k.abs() * (r + delta) - 1.0).abs());
    }
    assert!(
        worst < 0.01,
        "wheel curvature off 1/(R + Δ) by {:.3} %",
        worst * 100.0
    );
    // And the constraints solved on the designed pair give the target angle.
    assert!(d.max_angle_error_rad < 1e-3, "{}", d.max_angle_error_rad);
    // This head's normals span ±30°: a steeper target angle has no rail point.
    let mut steep = target.clone();
    steep.contact_angle.push((0.0085, 40f64.to_radians()));
    let e = design_wheel(
        &rail,
        Inclination::UPRIGHT,
        gauge,
        WheelsetGeometry::default(),
        &steep,
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("arc80")
            && e.contains("no point with that normal")
            && e.contains("spans -30.00° .. 30.00°"),
        "{e}"
    );
}

/// The shipped stand-in: designed again from its target it is the shipped profile (so the file
/// is the design's output, not an edited one); on its rail the independent global contact solve
/// gives the target angle to 0.15°, its table has no contact jump from flange to flange, the
/// anchors (y = 0 and the flank) are where the target puts them, and its flange is within
/// EN 13715's measures.
#[test]
#[ignore = "slow: the stand-in wheel designed again from its target (~34 s)"]
fn the_shipped_stand_in_is_its_target_designed() {
    let (t, rail, incl, gauge, ws) = ms_standin();
    let d = design_wheel(&rail, incl, gauge, ws, &t).unwrap();
    let shipped = EmbeddedProfile::from_name("ms-standin")
        .unwrap()
        .profile()
        .unwrap();
    let (a, b) = shipped.domain();
    let mut dz: f64 = 0.0;
    for k in 0..=4000 {
        let s = a + (b - a) * k as f64 / 4000.0;
        dz = dz.max((shipped.eval(s).z - d.profile.eval(s).z).abs());
    }
    assert!(
        dz < 1e-7,
        "the shipped profile differs from its design by {dz:e} m"
    );
    assert!(
        d.max_angle_error_rad < 0.15f64.to_radians(),
        "{}",
        d.max_angle_error_rad.to_degrees()
    );
    assert!(d.flank_shift_m.abs() < 1e-6 && d.max_departure_m < 1e-3, "{d:?}");
    assert!(d.measures.problems().is_empty(), "{:?}", d.measures.problems());
    let pair = WheelRailPair::new(shipped, rail, incl, gauge, ws).unwrap();
    let table = LookupTable1::build(
        &ContactGeometry::with_defaults(pair.clone()),
        &TableSettings::default(),
    )
    .unwrap();
    assert!(table.jumps.is_empty(), "{:?}", table.jumps);
    let (lo, hi) = table.range();
    assert!(hi > 4.5e-3 && lo < -4.5e-3, "flange to flange {lo} .. {hi}");
    // The centred gauge and the gauge variations the MS kilometre meets (|gv| ≤ 1.1 mm), far wider.
    let checks = jump_check(&pair, 0.010).unwrap();
    for c in checks.iter().filter(|c| c.gv >= -4e-3) {
        assert!(c.jumps.is_empty(), "gv {} mm: {:?}", c.gv * 1e3, c.jumps);
    }
}

/// A target no wheel can meet is refused, naming the value and why.
#[test]
fn impossible_targets_are_refused() {
    let (t, rail, incl, gauge, ws) = ms_standin();
    let low = DesignTarget {
        flange_height_m: 0.005,
        ..t.clone()
    };
    let e = design_wheel(&rail, incl, gauge, ws, &low)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("flange_height_mm = 5.00") && e.contains("lower than the rail's gauge corner"),
        "{e}"
    );
    let mut flat = t;
    flat.contact_angle[3].1 = flat.contact_angle[2].1;
    let e = design_wheel(&rail, incl, gauge, ws, &flat)
        .unwrap_err()
        .to_string();
    assert!(e.contains("non-monotone contact"), "{e}");
    let wheel = StandardProfile::S1002.profile();
    let e = design_wheel(&wheel, incl, gauge, ws, &ms_standin().0)
        .unwrap_err()
        .to_string();
    assert!(e.contains("not a rail profile"), "{e}");
}

/// The largest |Δz| between two profiles over the first's domain, m.
fn profile_difference(a: &Profile, b: &Profile) -> f64 {
    let (lo, hi) = a.domain();
    (0..=8000)
        .map(|k| {
            let s = lo + (hi - lo) * k as f64 / 8000.0;
            (a.eval(s).z - b.eval(s).z).abs()
        })
        .fold(0.0, f64::max)
}

/// The realistic stand-in (issue 48): `ms-tram` is its target designed (1e-7 m), within
/// EN 13715, jump-free on the ideal track and on gauge variations −4 … +10 mm, and passes
/// every realism check — margin ≥ 10 % on each rail arc, contact speed ≤ 10 / 11, no dwell on
/// the rail's joints, conicity ≤ 0.4 at 2 and 3 mm, a wall; while `ms-standin` fails the ones
/// the review found (margin, speed, dwell), so the checks can tell them apart.
#[test]
#[ignore = "slow: the ms-tram wheel designed again from its target (~21 s)"]
fn ms_tram_is_its_target_designed_and_realistic() {
    let (t, rail, incl, gauge, ws) = shipped_target(include_str!("../../../assets/designs/ms-tram.toml"));
    let d = design_wheel(&rail, incl, gauge, ws, &t).unwrap();
    let shipped = EmbeddedProfile::from_name("ms-tram").unwrap().profile().unwrap();
    let dz = profile_difference(&shipped, &d.profile);
    assert!(
        dz < 1e-7,
        "the shipped profile differs from its design by {dz:e} m"
    );
    assert!(d.measures.problems().is_empty(), "{:?}", d.measures.problems());
    let pair = WheelRailPair::new(shipped, rail.clone(), incl, gauge, ws).unwrap();
    let table = LookupTable1::build(
        &ContactGeometry::with_defaults(pair.clone()),
        &TableSettings::default(),
    )
    .unwrap();
    assert!(table.jumps.is_empty(), "{:?}", table.jumps);
    let checks = jump_check(&pair, 0.010).unwrap();
    for c in checks.iter().filter(|c| c.gv >= -4e-3) {
        assert!(c.jumps.is_empty(), "gv {} mm: {:?}", c.gv * 1e3, c.jumps);
    }
    let r = Realism::new(&table, &pair.rail).unwrap();
    assert!(r.problems().is_empty(), "{:?}", r.problems());
    let wall = r.wall_m().unwrap();
    assert!((3.9e-3..4.3e-3).contains(&wall), "wall at {} mm", wall * 1e3);
    // The old stand-in, measured by the same checks.
    let old = EmbeddedProfile::from_name("ms-standin")
        .unwrap()
        .profile()
        .unwrap();
    let old_pair = WheelRailPair::new(old, rail, incl, gauge, ws).unwrap();
    let old_table = LookupTable1::build(
        &ContactGeometry::with_defaults(old_pair.clone()),
        &TableSettings::default(),
    )
    .unwrap();
    let o = Realism::new(&old_table, &old_pair.rail).unwrap();
    let p = o.problems().join("; ");
    assert!(o.margin.value < 0.03, "{:?}", o.margin);
    assert!(o.wheel_speed.value > 50.0, "{:?}", o.wheel_speed);
    assert!(o.dwell.iter().any(|d| d.span_m > 3e-4), "{:?}", o.dwell);
    assert!(p.contains("curvature margin") && p.contains("dwells"), "{p}");
    assert!((3.1e-3..3.3e-3).contains(&o.wall_m().unwrap()), "{:?}", o.wall);
}

/// A wheel whose spline dips below the rail's radius is refused, naming it: ms-tram's target on
/// the published 54E1 (its arc joints unblended, the curvature jumping), the wheel's curvature
/// following the rail's jumps at 3000 per rad, drawn with 0.1 mm points, rings next to a joint.
#[test]
fn a_wheel_more_curved_than_the_rail_is_refused() {
    let (mut t, _, incl, gauge, ws) = shipped_target(include_str!("../../../assets/designs/ms-tram.toml"));
    t.output_step_m = OUTPUT_STEP_M;
    t.curvature_ramp_per_rad = 3000.0;
    let rail = StandardProfile::Rail54E1.profile();
    let e = match design_wheel(&rail, incl, gauge, ws, &t) {
        Ok(_) => panic!("the ringing wheel was not refused"),
        Err(e) => e.to_string(),
    };
    assert!(
        e.contains("falls below the rail's") && e.contains("two points"),
        "{e}"
    );
}

/// The relative curvature at the left contact (wheel + rail lateral curvatures, the conformity
/// that sets Hertz's B and so b) along a pair's table: the largest change of its logarithm
/// between neighbouring rows 0.01 mm of y apart, and where.
fn largest_conformity_step(pair: &WheelRailPair) -> (f64, f64) {
    let settings = TableSettings {
        step_m: 1e-5,
        ..TableSettings::default()
    };
    let table = LookupTable1::build(&ContactGeometry::with_defaults(pair.clone()), &settings).unwrap();
    // Up to the flange's root (35°): beyond it the flank's curvature is the wheel's own.
    let rows: Vec<_> = table
        .rows
        .iter()
        .filter(|r| r.contact_angle[0].abs() < 35f64.to_radians())
        .collect();
    let b = |r: &crate::contact::lookup::TableRow| (r.curvature[0] + r.curvature[1]).abs().max(1e-9).ln();
    rows.windows(2)
        .map(|w| ((b(w[1]) - b(w[0])).abs(), w[1].y))
        .fold((0.0, 0.0), |a, x| if x.0 > a.0 { x } else { a })
}

/// Issue 52: the curvature jumps of the published 54E1's tangent arcs, and of a wheel designed
/// conjugate to them, made the contact's conformity (Hertz's b) jump where the contact crossed a
/// joint — the 4 GPa p0 and a fifth of the default's right-hand sides. On the blended rail with
/// `ms-tram` designed on it, the conformity changes by at most 19 % (ln: 0.17) between table rows
/// 0.01 mm apart (the R80 → R13 blend crosses in ~0.25 mm of y); `ms-standin` on the published
/// rail, by a factor 4 (ln: 1.42) at a joint — the test that would have caught it.
#[test]
fn the_blended_pair_has_no_conformity_jump() {
    let (_, rail, incl, gauge, ws) = shipped_target(include_str!("../../../assets/designs/ms-tram.toml"));
    assert_eq!(rail.name, "54e1:blend=1");
    let tram = EmbeddedProfile::from_name("ms-tram").unwrap().profile().unwrap();
    let (smooth, at) = largest_conformity_step(&WheelRailPair::new(tram, rail, incl, gauge, ws).unwrap());
    let (_, published, incl, gauge, ws) = ms_standin();
    let standin = EmbeddedProfile::from_name("ms-standin")
        .unwrap()
        .profile()
        .unwrap();
    let (jump, at_jump) =
        largest_conformity_step(&WheelRailPair::new(standin, published, incl, gauge, ws).unwrap());
    println!(
        "largest change of ln(k_w + k_r) between rows 0.01 mm apart: ms-tram on 54e1:blend=1 {smooth:.3} (y {:.2} mm); ms-standin on 54e1 {jump:.3} (y {:.2} mm)",
        at * 1e3,
        at_jump * 1e3
    );
    assert!(smooth < 0.25, "{smooth} at y = {} mm", at * 1e3);
    assert!(jump > 4.0 * smooth, "{jump} against {smooth}");
}
