//! Multibody scenes checked against hand calculations: static settling (axle loads, sag), the
//! equilibrium of the preloaded vehicle, quasi-static curving of a bogie in the Tab. 6 curve (the
//! cant-deficiency balance, load transfer to the outer wheels, the wheelsets' yaw against the
//! curve geometry), KEC against the lookup table on the same scene, and bad vehicle tables.

use std::path::Path;

use crate::common;
use common::{kecsim, run_scene, scene, tmpdir};

use kecsim::bench::dynamics::differences;
use kecsim::contact::models::kec::KecSettings;
use kecsim::contact::ContactModelSpec;
use kecsim::dynamics::integrator::{integrate, Flow, Settings};
use kecsim::dynamics::multibody::Multibody;
use kecsim::dynamics::system::{Evaluator, InitialDisturbance, VehicleModel, VehicleSample};
use kecsim::dynamics::{Reference, RunOutput, Sample, SpeedProfile};
use kecsim::scenario::simulation::reference;
use kecsim::scenario::{RunOptions, Scenario, Scene};
use kecsim::vehicle::VehicleSpec;

const G: f64 = 9.81;

/// The system of a multibody scene with the contact model `kind`, settled, on the scene's track
/// (`with_track`) or on tangent ideal track at 19 m/s.
fn multibody(sc: &Scene, kind: &str, with_track: bool) -> Multibody {
    let (sim, veh) = sc.simulation.as_ref().unwrap();
    let VehicleSpec::Multibody(spec) = veh else {
        panic!("not a multibody scene")
    };
    let reference = if with_track {
        reference(sim, veh, sc.track.clone(), sim.speed_m_s)
    } else {
        Reference {
            track: None,
            s0: 0.0,
            speed: SpeedProfile {
                initial_m_s: 19.0,
                ramp_m_s2: 0.0,
            },
            frame_model: Default::default(),
        }
    };
    Multibody::new(
        spec,
        ContactModelSpec::default_for(kind)
            .unwrap()
            .build(&sc.pair, None)
            .unwrap(),
        sc.contact_forces.clone(),
        sc.pair.wheelset.nominal_radius_m,
        reference,
    )
    .unwrap()
}

/// Runs the scene's duration and returns the samples at the recording rate and the final sample.
fn simulate(sc: &Scene, kind: &str) -> (Vec<VehicleSample>, VehicleSample) {
    let (sim, _) = sc.simulation.clone().unwrap();
    let model = multibody(sc, kind, true);
    let mut sys = Evaluator::new(&model);
    let mut out = model.new_data();
    let x0 = model.initial_state(&InitialDisturbance::default());
    let settings = Settings::new(sim.integrator.method, sim.integrator.rtol, sim.integrator.atol);
    let mut samples = Vec::new();
    integrate(
        &mut sys,
        0.0,
        &x0,
        sim.duration_s,
        1.0 / sim.record_rate_hz,
        &settings,
        &mut |t, x| {
            samples.push(model.sample(&mut out, t, x)?);
            Ok(Flow::Continue)
        },
    )
    .unwrap();
    let last = samples.last().unwrap().clone();
    (samples, last)
}

/// Settling: the axle loads are half the sprung weight plus the wheelset's, the sag the preloads
/// replace is the weight over the primary vertical stiffness; preloaded, the vehicle centred on
/// tangent track at speed, centred, has no acceleration.
#[test]
fn static_settling_and_equilibrium() {
    let sc = scene("bogie_tab6_curve.toml");
    let sys = multibody(&sc, "kec", false);
    let st = &sys.settling;
    let sprung = (2615.0 + 16000.0) * G;
    for q in &st.axle_loads {
        let hand = 0.5 * sprung + 1813.0 * G;
        assert!((q - hand).abs() < 1e-6 * hand, "axle load {q} vs {hand}");
    }
    let sag = st.sag[0][2];
    let hand_sag = -sprung / (4.0 * 1.22e6);
    println!(
        "axle loads {:.1} kN; static sag the preloads replace {:.2} mm (hand {:.2} mm); residual {:.1e} N",
        st.axle_loads[0] * 1e-3,
        sag * 1e3,
        hand_sag * 1e3,
        st.residual
    );
    // (Within 1 %: the wheelset centre of the centred contact is not exactly r0 above the rail
    // plane, which pre-deflects the primary springs by that difference, 0.2 mm here.)
    assert!((sag - hand_sag).abs() < 1e-2 * hand_sag.abs());
    let x0 = sys.initial_state(&InitialDisturbance::default());
    let mut dx = vec![0.0; sys.dim()];
    sys.rhs(&mut sys.new_data(), 0.0, &x0, &mut dx).unwrap();
    let worst = dx.iter().map(|v| v.abs()).fold(0.0, f64::max);
    assert!(worst < 1e-6, "nominal state not at rest: {dx:?}");
}

/// The bogie in the Tab. 6 curve at 19 m/s settles quasi-statically. Checked against hand
/// calculations: the lateral wheel–rail forces plus the secondary's balance the cant deficiency
/// m (κV² cos φ − g sin φ); the vertical ones m (g cos φ + κV² sin φ) (issue 46: before the track
/// frame's whole motion they came out as the weight m g, 1.2 % light); the outer (right) wheels carry more; the
/// wheelsets' relative yaw is the curve's 2a/R less what the primary's longitudinal flexibility
/// lets them steer; the leading wheelset runs to the outer rail.
#[test]
fn bogie_curving_is_quasi_static_and_balanced() {
    let sc = scene("bogie_tab6_curve.toml");
    let (samples, last) = simulate(&sc, "kec");
    let r0 = sc.pair.wheelset.nominal_radius_m;
    let n = samples.len();
    // Steady: the last second changes by < 1 µm.
    let y_of = |s: &VehicleSample, j: usize| s.wheelsets[j].state.y;
    for j in 0..2 {
        let drift = (y_of(&samples[n - 1], j) - y_of(&samples[n - 101], j)).abs();
        assert!(drift < 1e-6, "wheelset {j} still moving: {drift}");
    }
    let ws: Vec<_> = last.wheelsets.iter().map(|w| Sample::new(0.0, w, r0)).collect();
    let m_tot = 2615.0 + 2.0 * 1813.0 + 16000.0;
    let (v, radius, cant) = (19.0, 235.65, 0.07599f64);
    let hand_y = m_tot * (v * v / radius * cant.cos() - G * cant.sin());
    let hand_q = m_tot * (G * cant.cos() + v * v / radius * cant.sin());
    let rails_y: f64 = ws.iter().map(|s| s.y_force[0] + s.y_force[1]).sum();
    let rails_q: f64 = ws.iter().map(|s| s.q_force[0] + s.q_force[1]).sum();
    // The secondary bushings' lateral forces on the bogie (track axes).
    let names: Vec<String> = {
        let (_, veh) = sc.simulation.clone().unwrap();
        let VehicleSpec::Multibody(spec) = veh else {
            panic!()
        };
        spec.elements
            .iter()
            .map(|e| match e {
                kecsim::vehicle::spec::ElementSpec::Bushing { name, .. }
                | kecsim::vehicle::spec::ElementSpec::Rotational { name, .. }
                | kecsim::vehicle::spec::ElementSpec::Axial { name, .. }
                | kecsim::vehicle::spec::ElementSpec::CarriedMass { name, .. } => name.clone(),
            })
            .collect()
    };
    let secondary_y: f64 = names
        .iter()
        .zip(&last.elements)
        .filter(|(n, _)| n.starts_with("secondary_left") || n.starts_with("secondary_right"))
        .map(|(_, (_, f))| f.y)
        .sum();
    println!(
        "lateral: rails {:.2} kN + secondary {:.2} kN = {:.2} kN; hand m (κV² cos φ − g sin φ) = {:.2} kN",
        rails_y * 1e-3,
        secondary_y * 1e-3,
        (rails_y + secondary_y) * 1e-3,
        hand_y * 1e-3
    );
    assert!(
        (rails_y + secondary_y - hand_y).abs() < 5e-3 * hand_y,
        "cant-deficiency balance"
    );
    let secondary_z: f64 = names
        .iter()
        .zip(&last.elements)
        .filter(|(n, _)| n.starts_with("secondary_left") || n.starts_with("secondary_right"))
        .map(|(_, (_, f))| f.z)
        .sum();
    println!(
        "vertical: rails {:.2} kN + secondary {:.2} kN; m (g cos φ + κV² sin φ) {:.2} kN (the weight {:.2} kN)",
        rails_q * 1e-3,
        secondary_z * 1e-3,
        hand_q * 1e-3,
        m_tot * G * 1e-3
    );
    assert!((rails_q + secondary_z - hand_q).abs() < 5e-3 * hand_q);
    for (j, s) in ws.iter().enumerate() {
        println!(
            "wheelset {}: y {:.3} mm, yaw {:.3} mrad, Q {:.1} / {:.1} kN (left/right), Y/Q {:.3} / {:.3}",
            j + 1,
            s.y * 1e3,
            s.yaw * 1e3,
            s.q_force[0] * 1e-3,
            s.q_force[1] * 1e-3,
            s.y_force[0] / s.q_force[0],
            s.y_force[1] / s.q_force[1]
        );
        assert!(s.normal[1] > s.normal[0], "outer (right) wheel carries more");
        assert!(
            (s.y_force[1] / s.q_force[1]).abs() < 0.8,
            "Y/Q within Nadal's limit"
        );
    }
    assert!(
        ws[0].y < -3e-3,
        "the leading wheelset runs towards the outer rail"
    );
    let relative_yaw = ws[1].yaw - ws[0].yaw;
    let geometric = 2.0 * 1.28 / radius;
    println!(
        "relative yaw of the wheelsets {:.3} mrad; curve geometry 2a/R = {:.3} mrad",
        relative_yaw * 1e3,
        geometric * 1e3
    );
    assert!((0.8 * geometric..1.0 * geometric).contains(&relative_yaw));
}

/// KEC and the lookup table on the bogie scene: lateral displacement and yaw of both wheelsets
/// over curve entry and steady curving (the paper saw < 1 mm and < 0.5 mrad on its vehicle).
#[test]
fn bogie_kec_against_lookup() {
    let sc = scene("bogie_tab6_curve.toml");
    let (kec, _) = simulate(&sc, "kec");
    let (lookup, _) = simulate(&sc, "lookup");
    assert_eq!(kec.len(), lookup.len());
    for j in 0..2 {
        let (mut dy, mut dpsi) = (0.0_f64, 0.0_f64);
        for (a, b) in kec.iter().zip(&lookup) {
            dy = dy.max((a.wheelsets[j].state.y - b.wheelsets[j].state.y).abs());
            dpsi = dpsi.max((a.wheelsets[j].state.psi - b.wheelsets[j].state.psi).abs());
        }
        println!(
            "wheelset {}: KEC vs 2-entry lookup max |Δy| {:.4} mm, max |Δψ| {:.4} mrad",
            j + 1,
            dy * 1e3,
            dpsi * 1e3
        );
        assert!(dy < 0.5e-3 && dpsi < 0.5e-3, "wheelset {j}: {dy} {dpsi}");
    }
}

/// `kecsim run` on a multibody scene: one CSV per wheelset; bad vehicle tables are clear errors.
#[test]
fn multibody_run_interface_and_bad_tables() {
    let dir = tmpdir("vehicle");
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/bogie_tab6_curve.toml");
    let base = std::fs::read_to_string(&path).unwrap();
    let short = dir.join("short.toml");
    std::fs::write(&short, base.replace("duration_s = 7.0", "duration_s = 0.5")).unwrap();
    let csv = dir.join("csv");
    let out = kecsim(
        &[
            "run",
            short.to_str().unwrap(),
            "--csv",
            csv.to_str().unwrap(),
            "--save",
            dir.join("r.rrd").to_str().unwrap(),
        ],
        &dir,
    );
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    for name in ["wheelset_1", "wheelset_2"] {
        let text = std::fs::read_to_string(csv.join(format!("{name}.csv"))).unwrap();
        assert!(text.starts_with("t_s,s_m,"));
        assert_eq!(text.lines().count(), 1 + 51);
    }
    // The recording: every wheelset's series, and the vehicle's side by side (one per wheelset).
    let rrd = dir.join("r.rrd");
    common::rerun_verify(&rrd);
    let chunks = kecsim::inspect::readback::recording_chunks(&rrd).unwrap();
    let paths: std::collections::BTreeSet<String> =
        chunks.iter().map(|c| c.entity_path().to_string()).collect();
    for e in [
        "/run/wheelset_1/y_mm",
        "/run/wheelset_2/normal_kn",
        "/run/vehicle/y_mm",
        "/run/vehicle/max_abs_y_over_q",
    ] {
        assert!(paths.contains(e), "missing {e}: {paths:?}");
    }
    let vehicle_rows: usize = chunks
        .iter()
        .filter(|c| c.entity_path().to_string() == "/run/vehicle/y_mm" && !c.is_static())
        .map(|c| c.num_rows())
        .sum();
    assert_eq!(vehicle_rows, 51, "one row per output time");
    for (name, text, expect) in [
        (
            "unknown.toml",
            base.replace(
                "bodies = [\"bogie\", \"wheelset_2\"]",
                "bodies = [\"bogie\", \"wheelset_3\"]",
            ),
            "unknown body \"wheelset_3\"",
        ),
        (
            "negative.toml",
            base.replacen("mass_kg = 1813.0", "mass_kg = -1.0", 1),
            "wheelsets[wheelset_1].mass_kg = -1",
        ),
        (
            "joint.toml",
            format!(
                "{base}\n[[vehicle.joints]]\nname = \"j\"\nbodies = [\"bogie\", \"wheelset_1\"]\nat_m = [0.0, 0.0, 0.5]\n"
            ),
            "\"wheelset_1\" is not a rigid body",
        ),
        (
            "key.toml",
            base.replace(
                "at_m = [0.0, 0.0, 0.8275]\nmass_kg",
                "at_m = [0.0, 0.0, 0.8275]\nmass = 1.0\nmass_kg",
            ),
            "mass",
        ),
        (
            "unheld.toml",
            base.replace(
                "bodies = [\"bogie\", \"wheelset_2\"]",
                "bodies = [\"bogie\", \"wheelset_1\"]",
            ),
            "wheelsets[wheelset_2]: no element holds it",
        ),
        (
            "redundant.toml",
            format!(
                "{base}\n[[vehicle.bodies]]\nname = \"extra\"\nmass_kg = 100.0\ninertia_kg_m2 = [10.0, 10.0, 10.0]\nposition_m = [0.0, 0.0, 1.0]\n\
                 [[vehicle.joints]]\nname = \"j1\"\nbodies = [\"bogie\", \"extra\"]\nat_m = [0.0, 0.5, 1.0]\n\
                 [[vehicle.joints]]\nname = \"j2\"\nbodies = [\"bogie\", \"extra\"]\nat_m = [0.0, -0.5, 1.0]\n"
            ),
            "over-constrained — 2 spherical joints give 5 independent constraints of 6",
        ),
    ] {
        let p = dir.join(name);
        std::fs::write(&p, &text).unwrap();
        let out = kecsim(&["run", p.to_str().unwrap()], &dir);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && err.contains(expect), "{name}: {err}");
        assert!(err.contains(name), "{name}: names the file: {err}");
        // Problems of an entry name its line: that of the entry's `name = "…"`.
        let entry = ["wheelset_1", "wheelset_2"]
            .iter()
            .find(|w| expect.contains(&format!("[{w}]")));
        if let Some(w) = entry {
            let at = text.find(&format!("name = \"{w}\"")).unwrap();
            let line = 1 + text[..at].matches('\n').count();
            assert!(err.contains(&format!("{name}:{line}: ")), "{name}: line {line}: {err}");
        }
    }
}

/// Manchester benchmark vehicle 1 (carbody, two bogies, four wheelsets): static axle loads from
/// the masses by hand; on the Tab. 6 track as its irregularities grow in, KEC (transitions
/// narrowed to the rigid jumps') against the online contact constraints (the reference: Eq. 35–42 solved at every evaluation) on the same run. The
/// tables are reported, not asserted: their irregularity corrections (Eq. 44–46) keep the centred
/// contact points under cross level, which S1002/60E1, with its contact jumps near the centre,
/// does not forgive (a 1 mm raised rail moves the contact by 11 mm on the online solution).
#[test]
#[ignore = "slow: the online reference over the Manchester vehicle on irregular track (~55 s)"]
fn manchester_vehicle_settles_and_runs_on_irregular_track() {
    let sc = scene("manchester_vehicle1_tab6.toml");
    let sys = multibody(&sc, "kec", false);
    let hand = (32000.0 / 4.0 + 2615.0 / 2.0 + 1813.0) * G;
    for q in &sys.settling.axle_loads {
        assert!((q - hand).abs() < 1e-6 * hand, "axle load {q} vs {hand}");
    }
    let go = |kind| run_scene(&sc, kind, |s| s.duration_s = 1.0);
    // KEC with its two-point transitions narrowed to 0.05 mm, i.e. nearly the rigid jumps that
    // the online constraints keep: the method's equivalence to the real profiles is the claim
    // here (the default transitions follow the elastic load sharing, up to 2 mm wide at this
    // pair's jumps near the centre: 0.15 mm from online over this second).
    let narrow = |s: &mut kecsim::scenario::SimulationSpec| {
        s.duration_s = 1.0;
        s.contact = Some(ContactModelSpec::Kec(KecSettings {
            two_point_approach_m: 5e-5,
            two_point_max_width_m: 5e-5,
        }));
    };
    let (kec, online, lookup2) = (run_scene(&sc, "kec", narrow), go("online"), go("lookup2"));
    for o in [&kec, &online] {
        assert!(o.summary.error.is_none(), "{:?}", o.summary.error);
        assert_eq!(o.wheelsets.len(), 4);
        assert_eq!(o.bodies.len(), 3);
    }
    let (dy, dpsi) = differences(&kec, &online);
    let (dy2, dpsi2) = differences(&kec, &lookup2);
    println!(
        "Manchester vehicle 1, 1 s: max |y| {:.3} mm; KEC vs online max |Δy| {:.4} mm, max |Δψ| {:.4} mrad (real-time factors {:.1} / {:.2}); KEC vs 2-entry lookup {:.3} mm, {:.3} mrad over {:.2} s{}",
        kec.summary.max_abs_y_mm,
        dy * 1e3,
        dpsi * 1e3,
        kec.summary.realtime_factor,
        online.summary.realtime_factor,
        dy2 * 1e3,
        dpsi2 * 1e3,
        lookup2.summary.simulated_s,
        lookup2.summary.error.as_ref().map_or(String::new(), |e| format!(" (stopped: {e})"))
    );
    assert!(
        kec.summary.max_abs_y_mm > 0.5,
        "the irregularities move the wheelsets"
    );
    assert!(dy < 0.05e-3 && dpsi < 0.1e-3, "{dy} {dpsi}");
}

/// The paper's case (MS vehicle, Tab. 6 track with irregularities): KEC and the 1-entry table
/// against the online constraints (the real profiles' contact solved on the displaced rails at
/// every evaluation) while every wheel is in single-point contact — up to the first real contact
/// jump, found in the online run itself (a wheel's contact point moving by more than 5 mm on the
/// wheel between two 10 ms samples: S1002 on 54E1 at 1:20 jumps from the tread to the flange root
/// at a relative displacement of 5.16 mm, which the IRW-wheelsets, without lateral guidance, reach
/// on straight track). There the three agree to a few micrometres; through the jumps each model
/// has its own two-point treatment (KEC and the table: a transition 0.5 mm wide; online: rigid,
/// the branch it was on kept until it closes), and the IRW-wheelsets, neutrally stable laterally,
/// keep the difference (millimetres after a few jumps: the README's `kecsim compare` section).
#[test]
#[ignore = "slow: the online reference over the MS vehicle up to its first contact jump (~50 s)"]
fn ms_vehicle_kec_and_table_match_online_until_the_first_contact_jump() {
    let sc = scene("ms_vehicle_tab6_s1002.toml");
    let go = |kind| run_scene(&sc, kind, |s| s.duration_s = 1.3);
    let (kec, lookup, online) = (go("kec"), go("lookup"), go("online"));
    for o in [&kec, &lookup, &online] {
        assert_eq!(o.summary.outcome, "completed", "{:?}", o.summary.error);
        assert_eq!(o.wheelsets.len(), 6);
    }
    let first_jump =
        |o: &RunOutput| kecsim::compare::first_contact_jump(o).expect("the window reaches a contact jump");
    let (t_jump, at) = first_jump(&online);
    // Largest |Δy|, |Δψ| (mm, mrad) over every wheelset's samples up to the first jump of either.
    let before = |a: &RunOutput, b: &RunOutput| {
        let end = first_jump(a).0.min(first_jump(b).0);
        let (mut dy, mut dpsi) = (0.0f64, 0.0f64);
        for ((_, sa), (_, sb)) in a.wheelsets.iter().zip(&b.wheelsets) {
            for (p, q) in sa.iter().zip(sb).filter(|(p, _)| p.t <= end) {
                assert!((p.t - q.t).abs() < 1e-9);
                dy = dy.max((p.y - q.y).abs() * 1e3);
                dpsi = dpsi.max((p.yaw - q.yaw).abs() * 1e3);
            }
        }
        (dy, dpsi, end)
    };
    let max_y = kec
        .wheelsets
        .iter()
        .flat_map(|(_, s)| s.iter().filter(|p| p.t <= t_jump))
        .map(|p| p.y.abs())
        .fold(0.0, f64::max);
    let (dy, dpsi, end) = before(&kec, &online);
    let (dyt, dpsit, end_t) = before(&lookup, &online);
    println!(
        "MS vehicle, first contact jump at t = {t_jump:.2} s ({at}); before it (max |y| {:.2} mm): KEC vs online {dy:.4} mm, {dpsi:.4} mrad (to {end:.2} s); 1-entry table vs online {dyt:.4} mm, {dpsit:.4} mrad (to {end_t:.2} s)",
        max_y * 1e3
    );
    assert!(
        end.min(end_t) > 0.5,
        "a jump at {end} / {end_t} s leaves no window to compare"
    );
    assert!(max_y > 2e-3, "the irregularities move the wheelsets: {max_y}");
    assert!(dy < 0.03 && dpsi < 0.03, "KEC vs online: {dy} mm, {dpsi} mrad");
    assert!(
        dyt < 0.05 && dpsit < 0.05,
        "table vs online: {dyt} mm, {dpsit} mrad"
    );
}

/// The paper's case as shipped (the MS vehicle on the designed stand-in wheel `ms-tram`, a
/// jump-free pair): KEC and the tables against the online constraints — the independent
/// reference — over the first 10 s (the straight with the irregularities growing in, the
/// transition and the curve's entry, where the middle bogie's leading wheelset crosses from one
/// flange wall to the other). Every wheelset in single-point contact throughout (the pair has no
/// jump), so the whole window compares the models themselves: KEC and `lookup2` (each wheel read
/// at its own rail) within 0.3 mm and 0.3 mrad of online (issue 48's bound; measured 0.037 mm,
/// 0.024 mrad, and on the first stand-in `ms-standin` 1.3 mm, 0.72 mrad), the paper's 2-entry
/// table `lookup2-paper` within the paper's 1 mm and 0.5 mrad, the 1-entry table, blind to the
/// gauge variation (±1.1 mm here), further off than either.
#[test]
#[ignore = "slow: the online reference solved at every evaluation over 10 s of the six-wheelset vehicle (~40 s)"]
fn ms_tram_kec_and_tables_match_online() {
    let sc = scene("ms_vehicle_tab6.toml");
    assert_eq!(sc.pair.wheel.name, "ms-tram");
    assert!(
        !kecsim::compare::pair_has_jumps(&sc.pair),
        "the stand-in pair is jump-free"
    );
    let go = |kind| run_scene(&sc, kind, |s| s.duration_s = 10.0);
    let online = go("online");
    assert_eq!(online.summary.outcome, "completed", "{:?}", online.summary.error);
    let max_y = online
        .wheelsets
        .iter()
        .flat_map(|(_, s)| s.iter())
        .map(|p| p.y.abs())
        .fold(0.0, f64::max);
    assert!(
        max_y > 3e-3,
        "the irregularities and the curve move the wheelsets to their walls: {max_y}"
    );
    let mut worst = std::collections::HashMap::new();
    for model in ["kec", "lookup2", "lookup2-paper", "lookup"] {
        let o = go(model);
        assert_eq!(o.summary.outcome, "completed", "{model}: {:?}", o.summary.error);
        let (mut dy, mut dpsi) = (0.0f64, 0.0f64);
        for ((_, a), (_, b)) in o.wheelsets.iter().zip(&online.wheelsets) {
            assert_eq!(a.len(), b.len());
            for (p, q) in a.iter().zip(b) {
                dy = dy.max((p.y - q.y).abs() * 1e3);
                dpsi = dpsi.max((p.yaw - q.yaw).abs() * 1e3);
            }
        }
        println!(
            "{model} vs online over 10 s (max |y| {:.2} mm): {dy:.4} mm, {dpsi:.4} mrad",
            max_y * 1e3
        );
        let bound = match model {
            "kec" | "lookup2" => (0.3, 0.3),
            "lookup2-paper" => (1.0, 0.5),
            _ => (f64::INFINITY, f64::INFINITY),
        };
        assert!(
            dy < bound.0 && dpsi < bound.1,
            "{model} vs online: {dy} mm, {dpsi} mrad"
        );
        worst.insert(model, dy);
    }
    assert!(
        worst["lookup"] > worst["lookup2-paper"] && worst["lookup2-paper"] > worst["lookup2"],
        "{worst:?}"
    );
}

/// The wheelsets of a right-hand side are evaluated in parallel (the run in a pool of its own of
/// two threads): the result does not depend on it — the MS vehicle's run on two threads (the
/// wheelsets split) and on one (every wheelset in turn) agree to the last bit. Called from a
/// thread of a pool, the default run takes that pool (a study's cases).
#[test]
fn parallel_wheelsets_change_nothing() {
    use kecsim::dynamics::{RunPool, Threads};
    let mut sc = scene("ms_vehicle_tab6.toml");
    sc.simulation.as_mut().unwrap().0.duration_s = 0.5;
    let go = |threads: usize| {
        let built = sc
            .build_run(&RunOptions {
                contact: Some("kec".to_string()),
                threads: Threads::Count(threads),
                ..Default::default()
            })
            .unwrap();
        assert_eq!(built.settings.pool.threads(), threads);
        built.run(&mut [])
    };
    let split = go(2);
    let serial = go(1);
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    one.install(|| {
        assert_eq!(
            RunPool::new(Threads::Default),
            RunPool::default(),
            "the caller's pool"
        );
        assert_eq!(RunPool::new(Threads::Default).threads(), 1);
    });
    assert_eq!(split.summary.steps, serial.summary.steps);
    assert_eq!(split.summary.rhs_evaluations, serial.summary.rhs_evaluations);
    for ((_, a), (_, b)) in split.wheelsets.iter().zip(&serial.wheelsets) {
        assert_eq!(a.len(), b.len());
        for (p, q) in a.iter().zip(b) {
            assert_eq!(
                (p.y, p.yaw, p.normal, p.creep_y),
                (q.y, q.yaw, q.normal, q.creep_y)
            );
        }
    }
}

/// Two MS vehicles coupled (`kecsim bench scaling`'s largest vehicle): the coupler is a pinned rod
/// along the track, internal to the pair — the axle loads add up to twice the single vehicle's,
/// each within 0.2 % of its single-vehicle value — and over the first second of the irregular track
/// the rear unit, which starts where the single vehicle starts, moves as it does within 0.1 mm and
/// 0.1 mrad (the coupler's longitudinal force barely reaches the lateral dynamics).
#[test]
fn two_coupled_ms_vehicles_settle_and_run() {
    let text = kecsim::bench::scaling::coupled_ms(2).unwrap();
    let pair = kecsim::scenario::Scenario::parse(&text, "coupled")
        .unwrap()
        .compile("coupled", Path::new("."))
        .unwrap();
    let single = scene("ms_vehicle_tab6.toml");
    let (one, two) = (multibody(&single, "kec", false), multibody(&pair, "kec", false));
    let q1 = &one.settling.axle_loads;
    let q2 = &two.settling.axle_loads;
    assert_eq!((q1.len(), q2.len()), (6, 12));
    // The coupler is internal: the pair weighs twice the single vehicle, exactly.
    let (w1, w2): (f64, f64) = (q1.iter().sum(), q2.iter().sum());
    assert!((w2 - 2.0 * w1).abs() < 1e-9 * w2, "{w2} vs 2 x {w1}");
    // Each wheelset as the single vehicle's but for the settled rod's small force (the end points
    // move along x as the carbodies pitch on their suspensions).
    for (k, q) in q2.iter().enumerate() {
        let hand = q1[k % 6];
        assert!((q - hand).abs() < 2e-3 * hand, "wheelset {k}: {q} vs {hand}");
    }
    let go = |sc: &Scene| run_scene(sc, "kec", |s| s.duration_s = 1.0);
    let (a, b) = (go(&single), go(&pair));
    assert_eq!(b.summary.outcome, "completed", "{:?}", b.summary.error);
    assert_eq!(b.wheelsets.len(), 12);
    // Both runs start with their rearmost body at the track's start: the rear unit of the pair
    // runs where the single vehicle runs; the coupler's pull on its front carbody is all that
    // differs.
    let (mut dy, mut dpsi) = (0.0f64, 0.0f64);
    for k in 0..6 {
        let (single, rear) = (&a.wheelsets[k], &b.wheelsets[6 + k]);
        assert_eq!(rear.0, format!("{}_2", single.0));
        for (p, q) in single.1.iter().zip(&rear.1) {
            assert!(
                (p.s - q.s).abs() < 1e-3,
                "{} at {} s: s {} vs {}",
                rear.0,
                p.t,
                p.s,
                q.s
            );
            dy = dy.max((p.y - q.y).abs());
            dpsi = dpsi.max((p.yaw - q.yaw).abs());
        }
    }
    println!(
        "2 MS vehicles, rear unit vs the single vehicle over 1 s: {:.4} mm, {:.4} mrad",
        dy * 1e3,
        dpsi * 1e3
    );
    assert!(dy < 0.1e-3 && dpsi < 0.1e-3, "{dy} m, {dpsi} rad");
}

/// Running safety of the MS vehicle into the curve (8 s: straight, transition, the leading
/// wheelsets' flange contact): S1002's flange angle (70°, EN 13715) gives Nadal's limit 1.34 at
/// μ = 0.3 (the facts sheet's value); each wheelset's 2 m sliding mean of Y/Q lies between the
/// instantaneous values it averages (below their largest, above zero); the Prud'homme limits come
/// from the settled axle loads (10 kN + 2Q₀/3); the leading wheelsets flange harder than the
/// trailing ones of their bogies; wheel unloading stays below the lift (ΔQ/Q₀ < 1, no lift here).
#[test]
fn ms_vehicle_running_safety_into_the_curve() {
    let sc = scene("ms_vehicle_tab6_s1002.toml");
    let out = run_scene(&sc, "kec", |s| s.duration_s = 8.0);
    assert_eq!(out.summary.outcome, "completed");
    let safety = out.summary.safety.as_ref().expect("safety figures");
    println!("{safety}");
    assert!(
        (safety.flange_angle_deg - 70.0).abs() < 0.5,
        "{}",
        safety.flange_angle_deg
    );
    assert!(
        (safety.nadal_limit - 1.342).abs() < 0.02,
        "{}",
        safety.nadal_limit
    );
    let loads = &multibody(&sc, "kec", false).settling.axle_loads;
    assert_eq!(safety.wheelsets.len(), 6);
    for ((w, (name, samples)), q) in safety.wheelsets.iter().zip(&out.wheelsets).zip(loads) {
        assert_eq!(&w.name, name);
        let peak = samples.iter().map(|p| p.max_abs_y_over_q()).fold(0.0, f64::max);
        assert!(
            w.y_over_q_2m > 0.0 && w.y_over_q_2m <= peak + 1e-12,
            "{name}: {} vs {peak}",
            w.y_over_q_2m
        );
        assert!((w.prudhomme_limit_n - (10e3 + q / 3.0)).abs() < 1e-6, "{name}");
        assert!(
            (0.0..1.0).contains(&w.delta_q_over_q0),
            "{name}: {}",
            w.delta_q_over_q0
        );
        assert!(
            w.sum_y_2m_n > 0.0 && w.sum_y_2m_n < w.prudhomme_limit_n,
            "{name}: {}",
            w.sum_y_2m_n
        );
    }
    let yq = |k: usize| safety.wheelsets[k].y_over_q_2m;
    assert!(
        yq(0) > yq(1) && yq(2) > yq(3),
        "leading vs trailing: {:?}",
        (0..6).map(yq).collect::<Vec<_>>()
    );
}

/// The same bogie on IRW-wheelsets (independently rotating wheels on non-rotating bridges) over
/// the curve entry (2.5 s): each wheel spins at its own rate and rolls without longitudinal creep
/// (Ω r = V per wheel), where the solid axles' wheels carry kN of longitudinal creep force.
#[test]
fn irw_bogie_rolls_without_longitudinal_creep() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/bogie_tab6_curve.toml");
    let base = std::fs::read_to_string(&path)
        .unwrap()
        .replace("duration_s = 7.0", "duration_s = 2.5");
    let irw_text = base.replace(
        "inertia_kg_m2 = [1120.0, 112.0, 1120.0]",
        "inertia_kg_m2 = [1120.0, 112.0, 1120.0]\nindependent_wheels = { wheel_spin_inertia_kg_m2 = 50.0 }",
    );
    let compile = |t: &str| {
        Scenario::parse(t, "irw")
            .unwrap()
            .compile("irw", path.parent().unwrap())
            .unwrap()
    };
    let (_, last) = simulate(&compile(&irw_text), "kec");
    let (_, solid) = simulate(&compile(&base), "kec");
    for (j, (w, ws)) in last.wheelsets.iter().zip(&solid.wheelsets).enumerate() {
        let fx_irw = w.dynamics.creep[0].fx.abs().max(w.dynamics.creep[1].fx.abs());
        let fx_solid = ws.dynamics.creep[0].fx.abs().max(ws.dynamics.creep[1].fx.abs());
        let roll = [
            w.state.omega * w.kin.contacts[0].rolling_radius / w.speed,
            w.state.omega_right * w.kin.contacts[1].rolling_radius / w.speed,
        ];
        println!(
            "wheelset {}: IRW y {:.3} mm, yaw {:.3} mrad, Ω r / V = {:.6} / {:.6}, max |Fx| {:.1} N (solid axle: y {:.3} mm, max |Fx| {:.1} N)",
            j + 1,
            w.state.y * 1e3,
            w.state.psi * 1e3,
            roll[0],
            roll[1],
            fx_irw,
            ws.state.y * 1e3,
            fx_solid
        );
        assert!(fx_irw < 0.1 * fx_solid, "IRW wheels roll free");
        // Each wheel's own path: V (1 ∓ l/R) on the inner (left) and outer (right) rail.
        let l_over_r = 0.75 / 235.65;
        println!(
            "    path speeds / V in the curve: {:.6} / {:.6}; longitudinal creepages {:.2e} / {:.2e}",
            1.0 - l_over_r,
            1.0 + l_over_r,
            w.dynamics.creepage[0].longitudinal,
            w.dynamics.creepage[1].longitudinal
        );
        for c in &w.dynamics.creepage {
            assert!(
                c.longitudinal.abs() < 1e-4,
                "rolling without longitudinal creep: {c:?}"
            );
        }
        assert!(roll[1] > roll[0], "the outer wheel turns faster");
        assert!(
            (w.state.omega - w.state.omega_right).abs() > 1e-3,
            "the wheels spin at different rates"
        );
    }
}

/// Spherical joints: the Manchester carbody cut in two halves joined at its centre by a spherical
/// joint (with a stiff bending spring across it, the articulation's) behaves as the whole body:
/// the same static axle loads, the joint held to Baumgarte's tolerance while the vehicle runs on
/// irregular track, and the wheelsets move as with the single carbody.
#[test]
fn spherical_joint_between_carbody_halves() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/manchester_vehicle1_tab6.toml");
    let whole = std::fs::read_to_string(&path)
        .unwrap()
        .replace("duration_s = 51.0", "duration_s = 1.0");
    let halves = whole
        .replace(
            "name = \"carbody\"\nmass_kg = 32000.0\ninertia_kg_m2 = [56800.0, 1.97e6, 1.97e6]\nposition_m = [0.0, 0.0, 1.8]",
            "name = \"carbody_front\"\nmass_kg = 16000.0\ninertia_kg_m2 = [28400.0, 585000.0, 585000.0]\nposition_m = [5.0, 0.0, 1.8]\n\n\
             [[vehicle.bodies]]\nname = \"carbody_rear\"\nmass_kg = 16000.0\ninertia_kg_m2 = [28400.0, 585000.0, 585000.0]\nposition_m = [-5.0, 0.0, 1.8]\n\n\
             [[vehicle.joints]]\nname = \"articulation\"\nbodies = [\"carbody_front\", \"carbody_rear\"]\nat_m = [0.0, 0.0, 1.8]\n\n\
             [[vehicle.elements]]\ntype = \"bushing\"\nname = \"articulation_bending\"\nbodies = [\"carbody_front\", \"carbody_rear\"]\nat_m = [0.0, 0.0, 1.8]\nstiffness = [0.0, 0.0, 0.0, 1.0e10, 1.0e10, 1.0e10]",
        )
        .replace("bodies = [\"carbody\", \"bogie_front\"]", "bodies = [\"carbody_front\", \"bogie_front\"]")
        .replace("bodies = [\"carbody\", \"bogie_rear\"]", "bodies = [\"carbody_rear\", \"bogie_rear\"]");
    assert!(halves.contains("carbody_rear\", \"bogie_rear") && !halves.contains("\"carbody\""));
    let compile = |t: &str| {
        Scenario::parse(t, "joint")
            .unwrap()
            .compile("joint", path.parent().unwrap())
            .unwrap()
    };
    let (sc_whole, sc_halves) = (compile(&whole), compile(&halves));
    let (sim, veh) = sc_halves.simulation.clone().unwrap();
    let VehicleSpec::Multibody(spec) = &veh else {
        panic!()
    };
    assert_eq!(spec.joints.len(), 1);
    let hand = (32000.0 / 4.0 + 2615.0 / 2.0 + 1813.0) * G;
    for q in &multibody(&sc_halves, "kec", false).settling.axle_loads {
        assert!((q - hand).abs() < 1e-4 * hand, "axle load {q} vs {hand}");
    }
    let a = run_scene(&sc_whole, "kec", |s| s.duration_s = 1.0);
    let b = run_scene(&sc_halves, "kec", |s| s.duration_s = 1.0);
    assert!(b.summary.error.is_none(), "{:?}", b.summary.error);
    // The joint's violation along the run (not in the run's output: integrate here for it).
    let sys = multibody(&sc_halves, "kec", true);
    let mut out = sys.new_data();
    let x0 = sys.initial_state(&InitialDisturbance::default());
    let settings = Settings::new(sim.integrator.method, sim.integrator.rtol, sim.integrator.atol);
    let mut worst: f64 = 0.0;
    integrate(
        &mut Evaluator::new(&sys),
        0.0,
        &x0,
        1.0,
        0.01,
        &settings,
        &mut |t, x| {
            let s = sys.sample(&mut out, t, x)?;
            worst = worst.max(s.joint_error[0]);
            Ok(Flow::Continue)
        },
    )
    .unwrap();
    let (dy, dpsi) = differences(&a, &b);
    println!(
        "carbody halves vs whole: max |Δy| {:.4} mm, max |Δψ| {:.4} mrad; joint violation ≤ {:.2e} m; real-time factors {:.1} / {:.1}",
        dy * 1e3,
        dpsi * 1e3,
        worst,
        a.summary.realtime_factor,
        b.summary.realtime_factor
    );
    assert!(worst < 1e-6, "joint violation {worst}");
    assert!(dy < 0.05e-3 && dpsi < 0.05e-3, "{dy} {dpsi}");
}

/// A hard case for the numerics: the bogie through the whole Tab. 6 curve and out of it (32 s,
/// 90 → 700 m). With the paper's rigid kinks, a wheelset whose equilibrium lies on a contact jump
/// (the trailing wheelset at the flange root in the curve, both at the curve exit) slides along
/// the kink: the right-hand side jumps at every crossing and many steps are rejected. With the
/// two-point transitions (the default) the same run is smooth — and the quasi-static curving it
/// settles into is the same (the transitions change only what happens inside them).
#[test]
fn two_point_transition_removes_the_sliding_mode() {
    let sc = scene("bogie_tab6_curve.toml");
    let go = |approach: f64| {
        run_scene(&sc, "kec", |s| {
            s.duration_s = 32.0;
            common::set_contact(
                s,
                ContactModelSpec::Kec(KecSettings {
                    two_point_approach_m: approach,
                    ..KecSettings::default()
                }),
            );
        })
    };
    let (rigid, smooth) = (go(0.0), go(KecSettings::default().two_point_approach_m));
    for (label, o) in [("rigid kinks", &rigid), ("two-point transitions", &smooth)] {
        println!(
            "{label}: {} steps, {} rejected, {} right-hand sides, real-time factor {:.0}",
            o.summary.steps, o.summary.rejected_steps, o.summary.rhs_evaluations, o.summary.realtime_factor
        );
        assert!(o.summary.error.is_none(), "{label}: {:?}", o.summary.error);
        assert!((o.summary.simulated_s - 32.0).abs() < 1e-9);
    }
    // The kinks' rejections (measured: 2902 of 18394 steps, against 168 of 15445; before the
    // KEC profiles merged each jump's two nodes into one kink — two nodes 40 nm apart had made
    // a 40 nm cubic of f'' ~ 10⁸ 1/m — more than half the rigid run's steps were rejected).
    assert!(
        rigid.summary.rejected_steps > 10 * smooth.summary.rejected_steps.max(1),
        "the rigid kinks' rejections (this test must be able to tell): {} vs {}",
        rigid.summary.rejected_steps,
        smooth.summary.rejected_steps
    );
    assert!(
        smooth.summary.rejected_steps * 10 < smooth.summary.steps,
        "smooth: {} of {} rejected",
        smooth.summary.rejected_steps,
        smooth.summary.steps
    );
    assert!(smooth.summary.rhs_evaluations * 5 < rigid.summary.rhs_evaluations * 4);
    // Quasi-static in the curve (t = 20 s, s = 470 m): the same offsets and yaw angles.
    for ((name, a), (_, b)) in rigid.wheelsets.iter().zip(&smooth.wheelsets) {
        let at = |v: &[Sample]| *v.iter().find(|p| (p.t - 20.0).abs() < 1e-9).unwrap();
        let (p, q) = (at(a), at(b));
        println!(
            "{name} at 20 s: y {:.4} / {:.4} mm, yaw {:.4} / {:.4} mrad",
            p.y * 1e3,
            q.y * 1e3,
            p.yaw * 1e3,
            q.yaw * 1e3
        );
        assert!((p.y - q.y).abs() < 0.01e-3 && (p.yaw - q.yaw).abs() < 0.01e-3);
    }
}

/// The Manchester vehicle over the whole kilometre of the Tab. 6 track with irregularities
/// (51 s): the scene as shipped runs to the end. With the paper's rigid kinks the same run needed
/// 6.4 min of wall time for its first 22 s and then stopped on a lifting wheel at a flange impact
/// of the rearmost wheelset (measured, see the README) — too slow to repeat here.
#[test]
fn manchester_vehicle_runs_the_whole_kilometre() {
    let sc = scene("manchester_vehicle1_tab6.toml");
    let (sim, _) = sc.simulation.clone().unwrap();
    let o = run_scene(&sc, "kec", |_| {});
    let s = &o.summary;
    println!(
        "Manchester vehicle 1, {:.0} s: real-time factor {:.1}, {} steps ({} rejected); max |y| {:.2} mm, max |yaw| {:.2} mrad, normal forces {:.1} .. {:.1} kN, max |Y/Q| {:.2}",
        s.simulated_s,
        s.realtime_factor,
        s.steps,
        s.rejected_steps,
        s.max_abs_y_mm,
        s.max_abs_yaw_mrad,
        s.min_normal_n * 1e-3,
        s.max_normal_n * 1e-3,
        s.max_abs_y_over_q
    );
    assert!(s.error.is_none(), "{:?}", s.error);
    assert!((s.simulated_s - sim.duration_s).abs() < 1e-9);
    // The leading wheelsets reach flange contact in the curve (beyond the 6.26 mm jump of the
    // ideal track, the irregularities adding their alignment), and no wheel lifts.
    assert!(s.max_abs_y_mm > 6.3, "{}", s.max_abs_y_mm);
    assert!(s.min_normal_n > 0.0);
    // Every wheelset covered the kilometre's curve: its last sample is past the curve exit (650 m).
    for (name, w) in &o.wheelsets {
        assert!(w.last().unwrap().s > 650.0, "{name}");
    }
    // Quasi-static curving, a balance the model does not state anywhere: in the full curve
    // (R 235.65 m, cant 0.076 rad, 19 m/s; 200–550 m, the transitions' and the irregularities'
    // swings averaged out) the rails' lateral forces on the eight wheels carry the vehicle's
    // uncompensated centrifugal force in the track plane, Σ Y = m (v²/R cos φ − g sin φ).
    // Measured 34.71 kN against 34.82 kN (−0.3 %, the irregularities' swings in the mean; on the
    // ideal track −0.09 %: tests/speed.rs). Before issue 46: 33.1 kN, 4.8 % short — the vehicle
    // coasted 1.3 % below 19 m/s, nothing holding its speed.
    let mass = multibody(&sc, "kec", true)
        .settling
        .axle_loads
        .iter()
        .sum::<f64>()
        / G;
    let (v, r, cant) = (19.0f64, 235.65f64, 0.07599f64);
    let expected = mass * (v * v / r * cant.cos() - G * cant.sin());
    let sum_y: f64 = o
        .wheelsets
        .iter()
        .map(|(_, w)| {
            let curve: Vec<&Sample> = w.iter().filter(|p| (200.0..550.0).contains(&p.s)).collect();
            curve.iter().map(|p| p.y_force[0] + p.y_force[1]).sum::<f64>() / curve.len() as f64
        })
        .sum();
    println!(
        "Manchester vehicle 1 in the curve: mean ΣY {:.2} kN, m (v²/R cos φ − g sin φ) {:.2} kN ({:.0} kg)",
        sum_y * 1e-3,
        expected * 1e-3,
        mass
    );
    assert!(
        (sum_y.abs() / expected - 1.0).abs() < 5e-3,
        "{sum_y} vs {expected}"
    );
}

/// The states of `model` (built from `sc`) integrated with the scene's integrator settings from
/// its initial state, every `dt` s from `from` to `to`.
fn states_between(sc: &Scene, model: &Multibody, from: f64, to: f64, dt: f64) -> Vec<(f64, Vec<f64>)> {
    let x0 = model.initial_state(&InitialDisturbance::default());
    let (sim, _) = sc.simulation.clone().unwrap();
    let settings = Settings::new(sim.integrator.method, sim.integrator.rtol, sim.integrator.atol);
    let mut states = Vec::new();
    integrate(
        &mut Evaluator::new(model),
        0.0,
        &x0,
        to,
        dt,
        &settings,
        &mut |t, x| {
            if t >= from {
                states.push((t, x.to_vec()));
            }
            Ok(Flow::Continue)
        },
    )
    .unwrap();
    states
}

/// The creep/normal-force iteration converges: the right-hand side is a function of the state,
/// not of the previous evaluation's normal forces that the iteration starts from. (Issue 13,
/// defect 3: the plain fixed point stopped silently after 8 passes, leaving up to 1.3e-7 relative
/// on this run.) States: the Manchester vehicle on the irregular track entering the curve (8–12 s,
/// the leading wheelsets in flange contact).
#[test]
fn right_hand_side_does_not_depend_on_the_previous_evaluation() {
    let sc = scene("manchester_vehicle1_tab6.toml");
    let model = multibody(&sc, "kec", true);
    let states = states_between(&sc, &model, 8.0, 12.0, 0.01);
    let n = model.dim();
    let mut worst: f64 = 0.0;
    for (t, x) in &states {
        let mut fresh = model.new_data();
        let mut off = model.new_data();
        for (k, start) in off.normal_start.iter_mut().enumerate() {
            let f = if k % 2 == 0 { 0.5 } else { 1.5 };
            let l = start.lambda;
            start.lambda = [f * l[0], (2.0 - f) * l[1]];
            // A secant matrix from somewhere else (the iteration's B carried between states).
            start.secant = nalgebra::Matrix2::new(-1.3, 0.2, 0.4, -0.7);
        }
        let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
        model.rhs(&mut fresh, *t, x, &mut a).unwrap();
        model.rhs(&mut off, *t, x, &mut b).unwrap();
        let scale = a.iter().map(|v| v.abs()).fold(1.0, f64::max);
        let d = a.iter().zip(&b).map(|(p, q)| (p - q).abs()).fold(0.0, f64::max) / scale;
        worst = worst.max(d);
        let s = model.sample(&mut fresh, *t, x).unwrap();
        for w in &s.wheelsets {
            let lam = w.dynamics.normal[0].abs() + w.dynamics.normal[1].abs();
            assert!(
                w.dynamics.lambda_change <= 1e-12 * lam + 1e-9,
                "t = {t}: residual {}",
                w.dynamics.lambda_change
            );
        }
    }
    println!(
        "{} states: largest relative difference of the right-hand side between λ guesses 50 % apart (and secant matrices): {worst:.1e}",
        states.len()
    );
    // (What remains, ~1e-10, is the Hertz ellipse solved once at the guessed load and scaled.
    // The fixed point of 8 passes gave 3e-6 here.)
    assert!(worst < 1e-8, "{worst}");
}

/// The finite-difference passes of the BDF's Newton matrix evaluate only the rows they read
/// (issue 34): the bogie frames' pass skips the wheelsets' dynamics and takes their kinematics from
/// the memo of f(t, x), the wheelsets' pass skips the bodies. Checked against the whole right-hand
/// side, evaluated afresh, on the rows each pass reads, at states of the MS vehicle entering the
/// curve with every column of each group perturbed as the Jacobian perturbs it.
#[test]
fn partial_right_hand_sides_are_the_whole_one_on_their_rows() {
    let sc = scene("ms_vehicle_tab6.toml");
    let model = multibody(&sc, "kec", true);
    // The first wheelset reaches the curve's transition at ~8.9 s.
    let states = states_between(&sc, &model, 0.0, 10.0, 0.5);
    let groups = model.newton_groups();
    assert!(groups.len() >= 2, "wheelsets and bogie frames: {groups:?}");
    let n = model.dim();
    let (mut worst, mut compared) = (0.0f64, 0);
    for (t, x) in states.iter().step_by(2) {
        let mut data = model.new_data();
        let mut f0 = vec![0.0; n];
        model.rhs(&mut data, *t, x, &mut f0).unwrap();
        for rows in &groups {
            let widest = rows.iter().map(|r| r.1).max().unwrap();
            for c in 0..widest {
                let mut xp = x.clone();
                for &(o, m) in rows {
                    if c < m {
                        xp[o + c] += 1.5e-8 * x[o + c].abs().max(0.1);
                    }
                }
                let mut part = vec![f64::NAN; n];
                model.rhs_rows(&mut data, *t, &xp, &mut part, rows).unwrap();
                let mut whole = vec![0.0; n];
                model.rhs(&mut model.new_data(), *t, &xp, &mut whole).unwrap();
                for &(o, m) in rows {
                    for i in o..o + m {
                        let d = (part[i] - whole[i]).abs() / whole[i].abs().max(1.0);
                        assert!(d < 1e-9, "t = {t}, row {i}: {} against {}", part[i], whole[i]);
                        worst = worst.max(d);
                        compared += 1;
                    }
                }
            }
        }
    }
    println!("{compared} rows compared: largest relative difference {worst:.1e}");
    assert!(compared > 1000, "{compared}");
}

/// The MS vehicle (paper §8): 5 carbodies, 4 spherical joints, 3 bogies, 6 IRW-wheelsets. Its
/// static settling carries the whole loaded weight (Tab. 4 masses, bogies, wheelsets) on the six
/// axles, the preloaded vehicle is in equilibrium at its nominal geometry, its state counts the
/// coordinates stated in the scene (8 bodies x 6 + 6 IRW-wheelsets x 5 = 78), and it runs the
/// first 2 s of the irregular track with the wheelsets inside the flange.
#[test]
fn ms_vehicle_settles_and_runs() {
    let sc = scene("ms_vehicle_tab6.toml");
    let sys = multibody(&sc, "kec", true);
    assert_eq!(sys.bodies.len(), 8);
    assert_eq!(sys.wheelsets.len(), 6);
    assert_eq!(sys.joints.len(), 4);
    // Positions and rates of the 8 x 6 body and 6 x 3 wheelset coordinates, the 12 wheel spins'
    // rates (their angles enter no force), each wheel's lift θ and θ̇ (0 on the rail), the
    // track's lateral shift under each wheelset and its rate.
    assert_eq!(sys.dim(), 2 * (8 * 6 + 6 * 3) + 6 * 2 + 6 * 4 + 6 * 2);
    let carbodies = 10380.0 + 12080.0 + 7160.0 + 11580.0 + 10280.0;
    let total = (carbodies + 2.0 * 2200.0 + 1300.0 + 6.0 * 680.0) * G;
    let axles: f64 = sys.settling.axle_loads.iter().sum();
    println!(
        "MS vehicle: axle loads {:?} kN (sum {:.1} kN, weight {:.1} kN), residual {:.1e} N",
        sys.settling
            .axle_loads
            .iter()
            .map(|q| (q * 1e-2).round() / 10.0)
            .collect::<Vec<_>>(),
        axles * 1e-3,
        total * 1e-3,
        sys.settling.residual
    );
    assert!((axles - total).abs() < 1e-6 * total, "{axles} vs {total}");
    assert!(sys.settling.residual < 1e-4 * total);
    // The middle bogie carries the middle module and half of each suspended one: the heaviest.
    let q = &sys.settling.axle_loads;
    assert!(q[2] > q[0] && q[2] > q[5], "{q:?}");
    let out = run_scene(&sc, "kec", |s| s.duration_s = 2.0);
    assert!(out.summary.error.is_none(), "{:?}", out.summary.error);
    assert!(out.summary.min_normal_n > 0.0);
    assert!(out.summary.max_abs_y_mm < 7.0, "{}", out.summary.max_abs_y_mm);
    // On the straight the rails carry the weight: Σ Q over the twelve wheels, averaged over the
    // run's last 1.5 s (the vertical motion's mean acceleration is nil), against the masses.
    let sum_q: f64 = out
        .wheelsets
        .iter()
        .map(|(_, w)| {
            let late: Vec<&Sample> = w.iter().filter(|p| p.t >= 0.5).collect();
            late.iter().map(|p| p.q_force[0] + p.q_force[1]).sum::<f64>() / late.len() as f64
        })
        .sum();
    println!(
        "MS vehicle, 0.5–2 s: mean ΣQ {:.2} kN, weight {:.2} kN",
        sum_q * 1e-3,
        total * 1e-3
    );
    assert!((sum_q / total - 1.0).abs() < 2e-3, "{sum_q} vs {total}");
    // Every state named once, by the layout the model reads its states with: a wheelset's lateral
    // position second in its slot, its wheels' lifts where the model keeps them.
    let names = sys.state_names();
    assert_eq!(names.len(), sys.dim());
    let unique: std::collections::HashSet<&String> = names.iter().collect();
    assert_eq!(unique.len(), names.len(), "{names:?}");
    for (((o, _), w), lift) in sys
        .wheelset_slots()
        .into_iter()
        .zip(sys.wheelset_names())
        .zip(sys.lift_offsets())
    {
        assert_eq!(names[o + 1], format!("{w}.y"));
        assert_eq!(names[o + 4], format!("{w}.y_dot"));
        assert_eq!(names[lift], format!("{w}.lift_left"));
        assert_eq!(names[lift + 3], format!("{w}.lift_rate_right"));
    }
    for ((o, _), b) in sys.kinematic_blocks().into_iter().zip(sys.body_names()) {
        assert_eq!(names[o + 5], format!("{b}.psi"));
        assert_eq!(names[o + 11], format!("{b}.psi_dot"));
    }
    // The summary names what limited the step: states of this vehicle, most first.
    let limits = &out.summary.step_limiting;
    println!("MS vehicle, 2 s: step limited by {limits:?}");
    assert!(!limits.is_empty());
    assert!(limits.iter().all(|l| names.contains(&l.state)), "{limits:?}");
    assert!(limits.windows(2).all(|w| w[0].share >= w[1].share));
    let counted: usize = limits.iter().map(|l| l.accepted_steps).sum();
    assert!(counted <= out.summary.steps && limits.iter().map(|l| l.share).sum::<f64>() <= 1.0 + 1e-12);
}

/// Zero-phase 4th-order Butterworth high-pass (two RBJ biquads, Q = 0.5412 and 1.3066, run
/// forwards and backwards) of `x` sampled at `fs`, corner `fc`. (Not `track::spectrum::
/// band_variance`: its rectangular-window periodogram leaks a trending record's drift into the
/// high band — ~0.08 mm rms here, where the motion has nanometres.)
fn high_pass(x: &[f64], fs: f64, fc: f64) -> Vec<f64> {
    let w0 = std::f64::consts::TAU * fc / fs;
    let mut y = x.to_vec();
    for q in [0.541_196_1, 1.306_563] {
        let alpha = w0.sin() / (2.0 * q);
        let c = w0.cos();
        let a0 = 1.0 + alpha;
        let (b0, b1, b2) = ((1.0 + c) / 2.0 / a0, -(1.0 + c) / a0, (1.0 + c) / 2.0 / a0);
        let (a1, a2) = (-2.0 * c / a0, (1.0 - alpha) / a0);
        for pass in 0..2 {
            if pass == 1 {
                y.reverse();
            }
            let (mut x1, mut x2, mut y1, mut y2) = (y[0], y[0], 0.0, 0.0);
            for v in y.iter_mut() {
                let out = b0 * *v + b1 * x1 + b2 * x2 - a1 * y1 - a2 * y2;
                (x2, x1, y2, y1) = (x1, *v, y1, out);
                *v = out;
            }
            if pass == 1 {
                y.reverse();
            }
        }
    }
    y
}

/// What holds the MS kilometre's step in the curve (README, *Speed*): the leading IRW-wheelset of
/// each bogie against its flange has a lateral mode at ~90–100 Hz with ζ ≈ 0.01–0.02
/// (`examples/linear_modes.rs`: its flanging wheel's spin swings with its lateral velocity as the
/// rolling radius changes; the frequency does not move with the wheel's spin inertia — the mass is
/// the wheelset's, the stiffness the flange's). The motion hardly excites it: DOPRI5 at rtol 1e-7
/// finds nanometres above 50 Hz. BDF of orders 3–5 is not A-stable: a mode that lightly damped is
/// unstable for them once ωh passes ≈ 0.4–0.5, so the step control holds the step there (~0.9 ms)
/// with a spurious ripple of a few micrometres, whatever the tolerance — while BDF2 (A-stable)
/// at the same tolerance takes several times longer steps through the same curve (and is less
/// accurate: README).
#[test]
#[ignore = "slow: the curve with BDF, with DOPRI5 at rtol 1e-7 and with BDF2, sampled at 2 kHz (~35 s)"]
fn ms_vehicle_flanging_mode_holds_bdf_at_its_stability_boundary() {
    use kecsim::dynamics::integrator::Method;
    let sc = scene("ms_vehicle_tab6_s1002.toml");
    let fs = 2000.0;
    let (from, to) = (9.0, 13.0);
    // Steps, and per wheelset the rms of y above 50 Hz over [from, to) with the mean frequency
    // of that part (zero crossings), of a run to `end` with the integrator edited by `edit`.
    let run = |end: f64, edit: &dyn Fn(&mut kecsim::scenario::SimulationSpec)| {
        let out = run_scene(&sc, "kec", |s| {
            s.duration_s = end;
            s.record_rate_hz = fs;
            edit(s);
        });
        assert!(out.summary.error.is_none(), "{:?}", out.summary.error);
        let ripple: Vec<(String, f64, f64)> = out
            .wheelsets
            .iter()
            .filter(|_| end > to)
            .map(|(name, s)| {
                let window: Vec<&Sample> = s.iter().filter(|p| p.t >= from - 0.5).collect();
                let hp = high_pass(&window.iter().map(|p| p.y).collect::<Vec<_>>(), fs, 50.0);
                let inner: Vec<f64> = window
                    .iter()
                    .zip(&hp)
                    .filter(|(p, _)| p.t >= from && p.t < to)
                    .map(|(_, v)| *v)
                    .collect();
                let rms = (inner.iter().map(|v| v * v).sum::<f64>() / inner.len() as f64).sqrt();
                let crossings = inner.windows(2).filter(|w| w[0] * w[1] < 0.0).count();
                (name.clone(), rms, crossings as f64 / (2.0 * (to - from)))
            })
            .collect();
        (out.summary.steps, ripple)
    };
    let (bdf_steps, bdf) = run(to + 0.5, &|_| {});
    let (dopri_steps, dopri) = run(to + 0.5, &|s| {
        s.integrator.method = Method::Dopri5;
        s.integrator.rtol = 1e-7;
    });
    for ((w, a, fa), (_, b, fb)) in bdf.iter().zip(&dopri) {
        println!(
            "{w}: lateral motion above 50 Hz, {from}-{to} s: rms {:.4} µm at {fa:.0} Hz (BDF, rtol 1e-4), {:.4} µm at {fb:.0} Hz (DOPRI5, rtol 1e-7)",
            a * 1e6,
            b * 1e6
        );
        // Not in the motion; in the BDF's, well inside its tolerance.
        assert!(*b < 1e-7, "{w}: {b} m rms above 50 Hz with DOPRI5 1e-7");
        assert!(*a < 1e-5, "{w}: {a} m rms above 50 Hz with BDF");
    }
    // The BDF's ripple is the flanging wheelsets' mode (w3, w5 lead the trailer and the rear motor
    // bogie into the flange), at its frequency, far above the motion's.
    for ((w, a, fa), (_, b, _)) in bdf.iter().zip(&dopri).filter(|(w, _)| w.0 == "w3" || w.0 == "w5") {
        assert!((70.0..130.0).contains(fa), "{w}: {fa} Hz");
        assert!(*a > 10.0 * b, "{w}: BDF {a}, DOPRI5 {b}");
    }
    // The step through the curve: BDF up to order 5 against BDF2, same tolerance.
    let curve_steps = |max_order: usize| {
        let edit = move |s: &mut kecsim::scenario::SimulationSpec| s.integrator.max_order = Some(max_order);
        run(to, &edit).0 - run(from, &edit).0
    };
    let (bdf5, bdf2) = (curve_steps(5), curve_steps(2));
    println!(
        "steps {from}-{to} s: BDF up to order 5 {bdf5} ({:.2} ms), BDF2 {bdf2} ({:.2} ms); whole {to} s: BDF {bdf_steps}, DOPRI5 1e-7 {dopri_steps}",
        (to - from) / bdf5 as f64 * 1e3,
        (to - from) / bdf2 as f64 * 1e3
    );
    assert!(bdf5 > 2 * bdf2, "order 5: {bdf5} steps, order 2: {bdf2}");
}
