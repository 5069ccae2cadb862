//! Dynamics scenes checked against independent references: the Klingel wavelength of the
//! equivalent conicity, energy conservation without creep, integrator convergence, the three
//! contact models against each other, the critical speed against fixed-speed runs, and the
//! `kecsim run` interface.

use std::path::Path;

use crate::common;
use common::{kecsim, kecsim_ok, rerun_verify, run_ok, scene, tmpdir, write_ms_scene};

use kecsim::contact::forces::{ContactForceSettings, CreepModel, Material};
use kecsim::contact::geometry::ContactGeometry;
use kecsim::contact::lookup::{LookupTable1, TableSettings};
use kecsim::contact::models::kec::KecSettings;
use kecsim::contact::report::conicity;
use kecsim::contact::ContactModelSpec;
use kecsim::dynamics::integrator::{integrate, Flow, Method, Settings};
use kecsim::dynamics::single_wheelset::{SingleWheelset, Tie};
use kecsim::dynamics::system::{Evaluator, InitialDisturbance, VehicleModel};
use kecsim::dynamics::wheelset::WheelsetInertia;
use kecsim::dynamics::{Reference, RunEnd, RunOutput, Sample, SpeedProfile, Stop};
use kecsim::scenario::{RunOptions, SimulationSpec};

/// Up-crossing times of y.
fn up_crossings(samples: &[Sample]) -> Vec<f64> {
    samples
        .windows(2)
        .filter(|w| w[0].y < 0.0 && w[1].y >= 0.0)
        .map(|w| w[0].t + (w[1].t - w[0].t) * (-w[0].y) / (w[1].y - w[0].y))
        .collect()
}

/// Released from 3 mm at 5 m/s, the wheelset's first oscillation cycles have the wavelength
/// 2π √(r0 e / λ_eq), λ_eq the EN 15302 equivalent conicity (Annex B) of the same profiles at the
/// cycle's amplitude, e the half-distance of the contact points.
#[test]
fn klingel_wavelength_matches_equivalent_conicity() {
    klingel_wavelength("kec");
}

/// The same with the elastic contact model (the wheelset free, Hertz contacts on the real
/// profiles): its wavelength is the rigid profiles' Klingel wavelength too — the approach
/// (0.08 mm) moves the contact points by too little to change the conicity.
#[test]
fn klingel_wavelength_with_elastic_contact() {
    klingel_wavelength("elastic");
}

fn klingel_wavelength(contact: &str) {
    let sc = scene("wheelset_klingel.toml");
    let out = run_ok(&sc, contact, |_| {});
    let s = out.samples();
    let ups = up_crossings(s);
    assert!(ups.len() >= 6, "{} up-crossings", ups.len());
    let geom = ContactGeometry::with_defaults(sc.pair.clone());
    let table = LookupTable1::build(&geom, &TableSettings::default()).unwrap();
    let r0 = sc.pair.wheelset.nominal_radius_m;
    let v = s[0].speed;
    let mut worst: f64 = 0.0;
    for cycle in ups.windows(2).take(4) {
        let (t0, t1) = (cycle[0], cycle[1]);
        let inside: Vec<&Sample> = s.iter().filter(|p| p.t >= t0 && p.t <= t1).collect();
        let ymax = inside.iter().map(|p| p.y).fold(f64::MIN, f64::max);
        let ymin = inside.iter().map(|p| p.y).fold(f64::MAX, f64::min);
        let amplitude = 0.5 * (ymax - ymin);
        // e: half the lateral distance between the contact points, averaged over the cycle.
        let e = inside
            .iter()
            .map(|p| 0.5 * (p.position[0].0 - p.position[1].0))
            .sum::<f64>()
            / inside.len() as f64;
        let lam = conicity(&table, &[amplitude])[0].annex_b.clone().unwrap();
        let klingel = 2.0 * std::f64::consts::PI * (r0 * e / lam).sqrt();
        let measured = (t1 - t0) * v;
        let rel = measured / klingel - 1.0;
        println!(
            "{contact}: cycle at {t0:.2} s: amplitude {:.3} mm, λ_eq {lam:.4}, e {e:.4} m: Klingel {klingel:.3} m, simulated {measured:.3} m ({:+.2} %)",
            amplitude * 1e3,
            rel * 100.0
        );
        worst = worst.max(rel.abs());
    }
    assert!(worst < 0.05, "wavelength off by {:.1} %", worst * 100.0);
}

/// Without creep (μ = 0) and damping the wheelset on its rails and springs is conservative: the
/// energy (kinetic, gravity and axle load, springs) stays constant to the integrator tolerance —
/// the normal forces, applied at the real contact points along the real normals (Eq. 53), do no
/// work only if they are consistent with the constraint.
#[test]
fn energy_is_conserved_without_creep() {
    let sc = scene("wheelset_klingel.toml");
    let forces =
        ContactForceSettings::new(CreepModel::by_name("polach").unwrap(), 0.0, Material::STEEL).unwrap();
    let tie = Tie {
        longitudinal_stiffness_n_per_m: 2e5,
        lateral_stiffness_n_per_m: 3e5,
        longitudinal_damping_n_s_per_m: 0.0,
        lateral_damping_n_s_per_m: 0.0,
        half_spacing_m: 1.0,
    };
    let inertia = WheelsetInertia {
        mass_kg: 1813.0,
        inertia_kg_m2: [1120.0, 112.0, 1120.0],
        irw: None,
    };
    let load = 100e3;
    let r0 = sc.pair.wheelset.nominal_radius_m;
    for kind in ["kec", "lookup"] {
        let model = SingleWheelset {
            name: "wheelset_1".into(),
            inertia,
            tie,
            axle_load_n: load,
            contact: ContactModelSpec::default_for(kind)
                .unwrap()
                .build(&sc.pair, None)
                .unwrap(),
            forces: forces.clone(),
            r0,
            reference: Reference {
                track: None,
                s0: 0.0,
                speed: SpeedProfile {
                    initial_m_s: 10.0,
                    ramp_m_s2: 0.0,
                },
                frame_model: Default::default(),
            },
        };
        let mut sys = Evaluator::new(&model);
        let mut obs = model.new_data();
        let x0 = model.initial_state(&InitialDisturbance {
            lateral_m: 0.004,
            yaw_rad: 0.002,
            ..InitialDisturbance::default()
        });
        let mut energies = Vec::new();
        let mut kinetic_max: f64 = 0.0;
        let settings = Settings::new(Method::Dopri5, 1e-9, 1e-11);
        integrate(&mut sys, 0.0, &x0, 3.0, 0.005, &settings, &mut |t, x| {
            let s = model.evaluate(&mut obs, t, x)?;
            let st = s.state;
            let (m, [ix, iy, iz]) = (inertia.mass_kg, inertia.inertia_kg_m2);
            let kinetic = 0.5 * m * (st.x_dot.powi(2) + st.y_dot.powi(2) + s.kin.z_dot.powi(2))
                + 0.5 * ix * s.kin.phi_dot.powi(2)
                + 0.5 * iz * st.psi_dot.powi(2)
                + 0.5 * iy * st.omega.powi(2);
            let springs: f64 = [1.0, -1.0]
                .iter()
                .map(|b| 0.5 * tie.longitudinal_stiffness_n_per_m * (st.x - st.psi * b).powi(2))
                .sum::<f64>()
                + tie.lateral_stiffness_n_per_m * st.y.powi(2);
            energies.push(kinetic + (m * 9.81 + load) * s.kin.z + springs);
            kinetic_max = kinetic_max.max(kinetic - 0.5 * iy * st.omega.powi(2));
            Ok(Flow::Continue)
        })
        .unwrap();
        // Secular drift: mean over the last second against the first. What remains periodic is the
        // O(ψ ψ̇) work of the normal forces of a contact model that ignores yaw (the paper's
        // cross-section assumption) — bounded separately.
        let n = energies.len();
        let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
        let drift = (mean(&energies[n - 100..]) - mean(&energies[..100])).abs();
        let e0 = energies[0];
        let swing = energies.iter().map(|e| (e - e0).abs()).fold(0.0, f64::max);
        let kinetic_max = kinetic_max.max(1e-9);
        println!(
            "{kind}: energy drift {drift:.2e} J, swing {swing:.2e} J over 3 s (largest kinetic energy of the oscillation {kinetic_max:.2e} J)"
        );
        assert!(drift < 1e-4 * kinetic_max, "{kind}: drift {drift} J");
        assert!(swing < 5e-3 * kinetic_max, "{kind}: swing {swing} J");
    }
}

/// KEC, the lookup table and the online constraints on the same scene: lateral displacement and
/// yaw agree to a small fraction of the motion (the paper saw < 1 mm and < 0.5 mrad on its
/// vehicle; here one wheelset, 4 s of the Klingel scene).
#[test]
#[ignore = "slow: four contact models over the same scene (~32 s)"]
fn contact_models_agree() {
    let sc = scene("wheelset_klingel.toml");
    let short = |s: &mut SimulationSpec| s.duration_s = 4.0;
    let rigid = |s: &mut SimulationSpec| {
        s.duration_s = 4.0;
        common::set_contact(
            s,
            ContactModelSpec::Kec(KecSettings {
                two_point_approach_m: 0.0,
                ..KecSettings::default()
            }),
        );
    };
    // The paper's KEC (rigid kinks) moves as the rigid models do; the default KEC, with its
    // two-point transitions at the contact jumps, differs from them by what the transitions change.
    let kec_rigid = run_ok(&sc, "kec", rigid);
    let kec = run_ok(&sc, "kec", short);
    let max_diff = |a: &RunOutput, b: &RunOutput| {
        assert_eq!(a.samples().len(), b.samples().len());
        let mut d = (0.0_f64, 0.0_f64, 0.0_f64);
        for (p, q) in a.samples().iter().zip(b.samples()) {
            d.0 = d.0.max((p.y - q.y).abs());
            d.1 = d.1.max((p.yaw - q.yaw).abs());
            d.2 = d.2.max((p.normal[0] - q.normal[0]).abs());
        }
        d
    };
    for kind in ["lookup", "online"] {
        let other = run_ok(&sc, kind, short);
        for (label, k, bound) in [("KEC, rigid kinks", &kec_rigid, 0.05e-3), ("KEC", &kec, 0.2e-3)] {
            let (dy, dpsi, dn) = max_diff(k, &other);
            println!(
                "{label} vs {kind}: max |Δy| {:.4} mm, max |Δψ| {:.4} mrad, max |ΔN_left| {:.1} N; real-time factors {:.1} (KEC) and {:.1}",
                dy * 1e3,
                dpsi * 1e3,
                dn,
                k.summary.realtime_factor,
                other.summary.realtime_factor
            );
            assert!(
                dy < bound && dpsi < bound,
                "{label} vs {kind}: Δy {dy}, Δψ {dpsi}"
            );
        }
    }
}

/// Halving the tolerance changes the result by what the method's order says: the differences
/// between successive tolerances (10⁻⁵, 10⁻⁶, 10⁻⁷) shrink, by roughly the tolerance ratio.
#[test]
#[ignore = "slow: an integrator convergence study on the scene (~14 s)"]
fn integrator_convergence_on_the_scene() {
    let sc = scene("wheelset_klingel.toml");
    for method in [Method::Ros3, Method::Ros34pw2, Method::Dopri5] {
        let runs: Vec<RunOutput> = [1e-5, 1e-6, 1e-7]
            .iter()
            .map(|&tol| {
                run_ok(&sc, "kec", |s| {
                    s.duration_s = 3.0;
                    s.integrator.method = method;
                    s.integrator.rtol = tol;
                    s.integrator.atol = tol * 1e-2;
                })
            })
            .collect();
        let diff = |a: &RunOutput, b: &RunOutput| {
            a.samples()
                .iter()
                .zip(b.samples())
                .map(|(p, q)| (p.y - q.y).abs())
                .fold(0.0, f64::max)
        };
        let (d1, d2) = (diff(&runs[0], &runs[2]), diff(&runs[1], &runs[2]));
        println!(
            "{method:?}: max |Δy| against rtol 1e-7: rtol 1e-5 {:.2e} mm, rtol 1e-6 {:.2e} mm (ratio {:.1}); steps {} / {} / {}",
            d1 * 1e3,
            d2 * 1e3,
            d1 / d2,
            runs[0].summary.steps,
            runs[1].summary.steps,
            runs[2].summary.steps
        );
        assert!(d2 < d1 && d1 / d2 > 3.0, "{method:?}: {d1} {d2}");
        assert!(
            d2 < 1e-5,
            "{method:?}: the scenes' tolerance (rtol 1e-6) is off by {d2} m"
        );
    }
}

/// The hunting of the critical-speed wheelset (S1002/60E1 1:40) against its two critical speeds,
/// each measured by a method independent of the accelerating ramp: the **nonlinear** one v_nl (the
/// decelerating ramp, `wheelset_critical_speed_down.toml`: the hunting cycle slowed down until it
/// dies out) and the **linear** one v_lin (Re λ of the linearised wheelset crossing zero). Between
/// them the wheelset is bistable — the centred running is stable, a large enough disturbance runs
/// onto the hunting cycle — so where the accelerating ramp's onset falls within [v_nl, v_lin]
/// depends on the motion's history down to round-off (the README says so): it is asserted inside
/// that range, and the fixed-speed runs are placed by v_nl and v_lin, not by the onset. (Placed
/// by the onset — 15 % below and 25 % above it — a last-bit change of the solver's arithmetic that
/// moved the onset from 37 to 50 m/s put the "decays" run inside the bistable range, where a
/// 0.3 mm disturbance is already on the cycle's side.) Well above v_lin the hunting reaches the
/// flanges and the run ends on its stop condition (|y| > 5 mm), normally, with the samples up to it.
#[test]
#[ignore = "slow: speed ramps through the critical speed (~22 s)"]
fn critical_speed_by_speed_ramp() {
    use kecsim::dynamics::linear::linear_stability;
    let sc = scene("wheelset_critical_speed.toml");
    // Re λ of the least-damped oscillatory mode at constant speed v (1 s settling).
    let re_lambda = |v: f64| {
        let mut at = sc.clone();
        let sim = &mut at.simulation.as_mut().unwrap().0;
        sim.speed_ramp_m_s2 = 0.0;
        sim.initial.lateral_m = 0.0;
        let run = at
            .build_run(&RunOptions {
                contact: Some("kec".into()),
                speed_m_s: Some(v),
                ..Default::default()
            })
            .unwrap();
        linear_stability(run.vehicle.as_ref(), &run.settings.integrator)
            .unwrap()
            .expect("an oscillatory mode")
            .max_real_1_s
    };
    let v_nl = run_ok(&scene("wheelset_critical_speed_down.toml"), "kec", |_| {})
        .summary
        .critical_speed_m_s
        .expect("the decelerating ramp finds where the cycle dies out");
    let ramp = run_ok(&sc, "kec", |_| {});
    let vc = ramp
        .summary
        .critical_speed_m_s
        .expect("hunting onset found on the ramp");
    let (re_vc, re_above) = (re_lambda(vc), re_lambda(70.0));
    println!(
        "nonlinear critical speed (decelerating ramp) {v_nl:.2} m/s; hunting onset on the accelerating ramp {vc:.2} m/s \
         (Re λ there {re_vc:.3} 1/s); Re λ at 70 m/s {re_above:.3} 1/s; stopped: {:?}",
        ramp.summary.stopped
    );
    // Measured 30.17 m/s. The decelerating ramp starts from a developed cycle (no bistable
    // history to remember, unlike the accelerating onset); at −0.5 m/s² one cycle (~0.5 s at
    // 2 Hz) is 0.25 m/s of speed, the resolution of where the cycle dies out: ±0.6 m/s.
    assert!((29.6..30.8).contains(&v_nl), "{v_nl}");
    assert!(
        vc >= 0.95 * v_nl,
        "onset {vc} below the nonlinear critical speed {v_nl}"
    );
    assert!(
        re_vc < 0.0,
        "onset {vc} above the linear critical speed (Re λ {re_vc})"
    );
    assert!(re_above > 0.0, "70 m/s: Re λ {re_above}");
    // Peak |y| early (1/12..1/4 of a 12 s run), in its third quarter and in its last quarter at
    // constant speed v from the lateral offset y0.
    let envelope = |v: f64, y0: f64| {
        let out = run_ok(&sc, "kec", |s| {
            s.speed_m_s = v;
            s.speed_ramp_m_s2 = 0.0;
            s.duration_s = 12.0;
            s.initial.lateral_m = y0;
            s.stop_lateral_m = None;
        });
        let s = out.samples();
        let n = s.len();
        let peak = |r: &[Sample]| r.iter().map(|p| p.y.abs()).fold(0.0, f64::max);
        (
            peak(&s[n / 12..n / 4]),
            peak(&s[n / 2..3 * n / 4]),
            peak(&s[3 * n / 4..]),
        )
    };
    // Below v_nl every motion decays, a large one too.
    let v_low = 0.85 * v_nl;
    let (a0, _, a1) = envelope(v_low, 0.004);
    println!(
        "at {v_low:.1} m/s from 4 mm: |y| {:.4} → {:.4} mm",
        a0 * 1e3,
        a1 * 1e3
    );
    assert!(
        a1 < 0.1 * a0,
        "below the nonlinear critical speed the motion must decay"
    );
    // Between v_nl and v_lin: bistable — a small disturbance decays, a large one keeps hunting.
    let v_mid = 1.25 * v_nl;
    assert!(
        re_lambda(v_mid) < 0.0,
        "{v_mid} m/s must be below the linear critical speed"
    );
    let (b0, _, b1) = envelope(v_mid, 1e-6);
    let (c0, c1, c2) = envelope(v_mid, 0.004);
    println!(
        "at {v_mid:.1} m/s: from 1 µm |y| {:.6} → {:.6} mm; from 4 mm |y| {:.4} → {:.4} → {:.4} mm",
        b0 * 1e3,
        b1 * 1e3,
        c0 * 1e3,
        c1 * 1e3,
        c2 * 1e3
    );
    assert!(
        b1 < 0.5 * b0,
        "between the critical speeds a small disturbance must decay"
    );
    assert!(
        c2 > 0.9 * c1 && c2 > 1e-4,
        "between the critical speeds a large disturbance must stay on the hunting cycle"
    );
    // Above v_lin: the hunting grows to the flanges.
    let hunting = run_ok(&sc, "kec", |s| {
        s.speed_m_s = 70.0;
        s.speed_ramp_m_s2 = 0.0;
        s.duration_s = 10.0;
    });
    match &hunting.end {
        RunEnd::Stopped(Stop::Lateral { y_m, limit_m, t, .. }) => {
            assert!(y_m.abs() > *limit_m && (*limit_m - 0.005).abs() < 1e-12);
            assert!((hunting.samples().last().unwrap().t - t).abs() < 1e-12);
        }
        other => panic!("expected the lateral stop, got {other:?}"),
    }
    assert_eq!(hunting.summary.outcome, "stopped");
}

/// `kecsim run SCENE --contact --speed --csv --json`: the Interface columns and keys, a recording
/// that reads back, and errors for bad scenarios.
#[test]
fn run_interface_csv_json_and_recording() {
    let dir = tmpdir("run");
    let scene_path = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/wheelset_klingel.toml");
    let text = std::fs::read_to_string(&scene_path)
        .unwrap()
        .replace("duration_s = 12.0", "duration_s = 1.0");
    let short = dir.join("short.toml");
    std::fs::write(&short, text).unwrap();
    let (csv_dir, json, rrd) = (dir.join("csv"), dir.join("run.json"), dir.join("run.rrd"));
    let out = kecsim(
        &[
            "run",
            short.to_str().unwrap(),
            "--contact",
            "lookup",
            "--speed",
            "8",
            "--csv",
            csv_dir.to_str().unwrap(),
            "--json",
            json.to_str().unwrap(),
            "--save",
            rrd.to_str().unwrap(),
        ],
        &dir,
    );
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let csv = std::fs::read_to_string(csv_dir.join("wheelset_1.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    for c in [
        "t_s",
        "s_m",
        "y_mm",
        "yaw_mrad",
        "z_mm",
        "roll_mrad",
        "n_left_n",
        "n_right_n",
    ] {
        assert!(header.contains(&c), "missing {c}");
    }
    assert_eq!(csv.lines().count(), 1 + 201, "200 Hz over 1 s, both ends");
    let last: Vec<f64> = csv
        .lines()
        .last()
        .unwrap()
        .split(',')
        .map(|v| v.parse().unwrap())
        .collect();
    assert!(
        (last[0] - 1.0).abs() < 1e-9 && (last[1] - 8.0).abs() < 1e-3,
        "t = 1 s at 8 m/s: s = 8 m"
    );
    let js: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    for k in [
        "simulated_s",
        "wall_s",
        "realtime_factor",
        "steps",
        "contact_model",
        "max_abs_y_mm",
        "max_normal_n",
    ] {
        assert!(js.get(k).is_some(), "missing {k}");
    }
    assert_eq!(js["contact_model"], "lookup");
    assert!((js["simulated_s"].as_f64().unwrap() - 1.0).abs() < 1e-9);
    // Running safety (added key): Nadal's limit for the scene's friction and the pair's flange.
    let safety = &js["safety"];
    assert!(safety["nadal_limit"].as_f64().unwrap() > 1.0, "{safety}");
    assert_eq!(safety["wheelsets"][0]["name"], "wheelset_1");
    for k in [
        "y_over_q_2m",
        "sum_y_2m_n",
        "prudhomme_limit_n",
        "delta_q_over_q0",
    ] {
        assert!(
            safety["wheelsets"][0][k].as_f64().is_some(),
            "missing safety {k}: {safety}"
        );
    }
    let rt = js["realtime_factor"].as_f64().unwrap();
    assert!((rt - 1.0 / js["wall_s"].as_f64().unwrap()).abs() < 1e-6 * rt);
    assert!(
        !String::from_utf8_lossy(&out.stderr).contains("ETA"),
        "no progress bar when stderr is not a terminal"
    );
    rerun_verify(&rrd);
    let chunks = kecsim::inspect::readback::recording_chunks(&rrd).unwrap();
    // The recording holds the samples the CSV holds (streamed in batches during the run).
    let y_rrd: Vec<f64> = kecsim::inspect::readback::scalar_rows(&chunks, "/run/wheelset_1/y_mm")
        .iter()
        .map(|r| r[0])
        .collect();
    let y_csv: Vec<f64> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(3).unwrap().parse::<f64>().unwrap())
        .collect();
    assert_eq!(y_rrd.len(), y_csv.len());
    for (a, b) in y_rrd.iter().zip(&y_csv) {
        assert!((a - b).abs() <= 1e-9 * a.abs().max(1e-3), "{a} vs {b}");
    }
    let paths: std::collections::BTreeSet<String> =
        chunks.iter().map(|c| c.entity_path().to_string()).collect();
    for e in [
        "/run/wheelset_1/y_mm",
        "/run/wheelset_1/normal_kn",
        "/run/section/left/wheel",
        "/run/summary",
    ] {
        assert!(paths.contains(e), "missing {e}: {paths:?}");
    }

    // --pace 4: the simulated second takes at least a quarter of a second of wall time.
    let paced = dir.join("paced.json");
    let out = kecsim(
        &[
            "run",
            short.to_str().unwrap(),
            "--pace",
            "4",
            "--json",
            paced.to_str().unwrap(),
            "--save",
            rrd.to_str().unwrap(),
        ],
        &dir,
    );
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let js: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&paced).unwrap()).unwrap();
    let wall = js["wall_s"].as_f64().unwrap();
    assert!(
        wall > 0.24,
        "paced at 4x real time: {wall} s of wall time for 1 s"
    );

    // A missing file: named, its cause said once.
    let out = kecsim(&["run", "no_such_scene.toml"], &dir);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("no_such_scene.toml"),
        "{err}"
    );
    assert_eq!(err.matches("No such file").count(), 1, "{err}");

    // Bad input: a [simulation] without [vehicle], an out-of-range value, an unknown key.
    let base = std::fs::read_to_string(&short).unwrap();
    let cut = &base[..base.find("[vehicle]").unwrap()];
    for (name, text, expect) in [
        ("novehicle.toml", cut.to_string(), "needs a [vehicle]"),
        (
            "neg.toml",
            base.replace("duration_s = 1.0", "duration_s = -1.0"),
            "duration_s = -1",
        ),
        (
            "key.toml",
            base.replace("record_rate_hz", "record_hz"),
            "record_hz",
        ),
    ] {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        let out = kecsim(
            &["run", p.to_str().unwrap(), "--save", rrd.to_str().unwrap()],
            &dir,
        );
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && err.contains(expect), "{name}: {err}");
        assert!(err.contains(name), "{name}: the error names the file: {err}");
    }
}

/// The recorder streams: while a run is going its samples reach the sink in batches (every
/// 50 ms of wall time), not all at the end; when it is over the sink holds every sample once,
/// with the values the run returned.
#[test]
fn recording_is_streamed_while_the_run_goes() {
    use kecsim::dynamics::output::{ObserverError, OutputSample, RunObserver};
    use kecsim::inspect::readback::{message_chunks, scalar_rows};
    use kecsim::inspect::run::LiveRecorder;

    struct Probe {
        storage: rerun::sink::MemorySinkStorage,
        rows: Vec<Vec<f64>>,
        /// (samples produced, y rows received by the sink) every 25 samples.
        seen: Vec<(usize, usize)>,
        produced: usize,
    }
    impl Probe {
        fn drain(&mut self) {
            let chunks = message_chunks(&self.storage.take(), "memory").unwrap();
            self.rows.extend(scalar_rows(&chunks, "/run/wheelset_1/y_mm"));
        }
    }
    impl RunObserver for Probe {
        fn sample(&mut self, _s: &OutputSample<'_>) -> Result<(), ObserverError> {
            self.produced += 1;
            std::thread::sleep(std::time::Duration::from_millis(1));
            if self.produced.is_multiple_of(25) {
                self.drain();
                self.seen.push((self.produced, self.rows.len()));
            }
            Ok(())
        }
    }

    let sc = scene("wheelset_klingel.toml");
    let mut built = sc.build_run(&RunOptions::default()).unwrap();
    built.settings.duration_s = 2.0;
    let (rec, storage) = rerun::RecordingStreamBuilder::new("kecsim-test")
        .memory()
        .unwrap();
    let mut recorder = LiveRecorder::on(rec, &sc, &built.vehicle.wheelset_names()).unwrap();
    let mut probe = Probe {
        storage,
        rows: Vec::new(),
        seen: Vec::new(),
        produced: 0,
    };
    let out = built.run(&mut [&mut recorder, &mut probe]);
    drop(recorder);
    probe.drain();
    let n = out.samples().len();
    println!(
        "{n} samples; rows received by the sink while the run went: {:?}",
        probe.seen
    );
    assert_eq!(n, 401);
    let mid: Vec<&(usize, usize)> = probe.seen.iter().filter(|(_, r)| *r > 0 && *r < n).collect();
    assert!(mid.len() >= 3, "batches arrive during the run: {:?}", probe.seen);
    assert!(
        probe.seen.iter().all(|&(p, r)| r <= p),
        "nothing arrives before it is produced"
    );
    let y: Vec<f64> = probe.rows.iter().map(|r| r[0]).collect();
    let expect: Vec<f64> = out.samples().iter().map(|s| s.y * 1e3).collect();
    assert_eq!(y, expect, "every sample once, as the run computed it");
}

/// A stop asked for through the run's cancel token (what the binary's Ctrl-C does) ends the run
/// normally at the next output time: `"stopped": "interrupted"`, no error, every sample up to it
/// kept; a token asked before the run starts stops it at once. Another run's token is another
/// request.
#[test]
fn a_cancelled_run_stops_normally_with_what_it_recorded() {
    use kecsim::dynamics::output::{ObserverError, OutputSample, RunObserver};
    use kecsim::dynamics::CancelToken;

    /// Asks for the stop once the run passes `at` (as a Ctrl-C would, from outside the run).
    struct StopAt {
        at: f64,
        cancel: CancelToken,
    }
    impl RunObserver for StopAt {
        fn sample(&mut self, s: &OutputSample<'_>) -> Result<(), ObserverError> {
            if s.t >= self.at {
                self.cancel.request();
            }
            Ok(())
        }
    }

    let sc = scene("wheelset_klingel.toml");
    let cancel = CancelToken::new();
    let options = RunOptions {
        cancel: cancel.clone(),
        ..Default::default()
    };
    let mut built = sc.build_run(&options).unwrap();
    built.settings.duration_s = 2.0;
    let dt = 1.0 / built.settings.record_rate_hz;
    let mut stop = StopAt {
        at: 0.5,
        cancel: cancel.clone(),
    };
    let out = built.run(&mut [&mut stop]);
    let t = match out.end {
        RunEnd::Stopped(Stop::Interrupted { t }) => t,
        ref e => panic!("expected an interrupt, got {e:?}"),
    };
    // The request is seen at the first output time after it: the observers run on the output
    // worker, behind the integration by at most the queue between them (and the sample in each
    // hand), however loaded the machine.
    let lag = (kecsim::dynamics::OUTPUT_QUEUE + 2) as f64 * dt;
    assert!(lag < 1.0, "the bound says something on a 2 s run");
    assert!(
        t >= 0.5 - 0.5 * dt && t <= 0.5 + lag + 0.5 * dt,
        "stopped at t = {t}"
    );
    let json = serde_json::to_value(&out.summary).unwrap();
    assert_eq!(json["stopped"], "interrupted", "{json}");
    assert!(out.summary.error.is_none());
    let samples = out.samples();
    assert_eq!(
        samples.len(),
        (t / dt).round() as usize + 1,
        "every sample up to the stop"
    );
    assert_eq!(samples.last().unwrap().t, t);
    // Asked before the start (a Ctrl-C during the preprocessing): the run stops at once.
    let out = built.run(&mut []);
    assert!(
        matches!(out.end, RunEnd::Stopped(Stop::Interrupted { .. })),
        "{:?}",
        out.end
    );
    assert!(out.samples().len() <= 2, "{} samples", out.samples().len());
    // A run built with a fresh token is not stopped by this one.
    let other = sc.build_run(&RunOptions::default()).unwrap();
    assert_ne!(other.settings.integrator.cancel, cancel);
    cancel.clear();
    let mut built = built;
    built.settings.duration_s = 0.2;
    assert!(
        matches!(built.run(&mut []).end, RunEnd::Completed),
        "cleared: runs to its end"
    );
}

/// `kecsim compare`: the same scene with two contact models; the differences it reports are the
/// samples' (recomputed here), within the paper's bounds on the Klingel scene; the recording holds
/// the overlays and the differences.
#[test]
fn compare_reports_the_differences_of_the_runs() {
    // KEC with rigid kinks: `--contact lookup` then carries the same (rigid jumps) to the table.
    let mut sc = scene("wheelset_klingel.toml");
    common::set_contact(
        &mut sc.simulation.as_mut().unwrap().0,
        kecsim::contact::ContactModelSpec::Kec(kecsim::contact::models::kec::KecSettings {
            two_point_approach_m: 0.0,
            ..Default::default()
        }),
    );
    let c = kecsim::compare::compare(&sc, &["kec".to_string(), "lookup".to_string()], Some(1.0)).unwrap();
    assert!(c.pair_jumps, "S1002 on 60E1 jumps");
    assert_eq!(c.runs.len(), 2);
    assert!((c.common_s - 1.0).abs() < 1e-12);
    let (a, b) = (c.runs[0].output.samples(), c.runs[1].output.samples());
    let max_dy = a
        .iter()
        .zip(b)
        .map(|(p, q)| (p.y - q.y).abs())
        .fold(0.0, f64::max);
    let d = &c.differences[0];
    assert_eq!(
        (d.model.as_str(), d.wheelset.as_str(), d.samples),
        ("lookup", "wheelset_1", 201)
    );
    assert_eq!(d.max_dy, max_dy);
    assert!(d.rms_dy <= d.max_dy && d.within_paper_bounds(), "{d:?}");
    assert!(c.markdown().contains("| wheelset_1 | lookup |"));
    // The single-point window ends at the earlier run's first contact jump (S1002/60E1 1:40 jumps
    // at y = ±0.23 mm: the Klingel oscillation crosses it), the differences up to it recomputed.
    let jump = |o| kecsim::compare::first_contact_jump(o).map_or(f64::INFINITY, |j| j.0);
    let end = jump(&c.runs[0].output)
        .min(jump(&c.runs[1].output))
        .min(c.common_s);
    assert!(end < c.common_s, "the wheelset crosses a jump: {end}");
    assert_eq!(d.single_point_s, end);
    let single_dy = a
        .iter()
        .zip(b)
        .filter(|(p, _)| p.t <= end + 1e-9)
        .map(|(p, q)| (p.y - q.y).abs())
        .fold(0.0, f64::max);
    assert_eq!(d.single_point_max_dy, single_dy);
    assert!(d.single_point_max_dy <= d.max_dy && d.single_point_max_dpsi <= d.max_dpsi);

    let dir = tmpdir("compare");
    let rrd = dir.join("c.rrd");
    let scene_path = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/wheelset_klingel.toml");
    let stdout = kecsim_ok(
        &[
            "compare",
            scene_path.to_str().unwrap(),
            "--contact",
            "kec,lookup",
            "--duration",
            "0.5",
            "--save",
            rrd.to_str().unwrap(),
        ],
        &dir,
    );
    assert!(
        stdout.contains("within the paper's bounds") && stdout.contains("| lookup |"),
        "{stdout}"
    );
    rerun_verify(&rrd);
    let chunks = kecsim::inspect::readback::recording_chunks(&rrd).unwrap();
    let rows = kecsim::inspect::readback::scalar_rows(&chunks, "/compare/wheelset_1/y_mm");
    assert_eq!(rows.len(), 101);
    assert!(rows.iter().all(|r| r.len() == 2), "one series per model");
    let diff = kecsim::inspect::readback::scalar_rows(&chunks, "/compare/wheelset_1/dy_mm");
    for (r, d) in rows.iter().zip(&diff) {
        assert!((d[0] - (r[1] - r[0])).abs() < 1e-9);
    }
    // Both models' wheelsets in the 3D view (issue 36), and each
    // model's displacement transform at its own lateral displacement (× the default
    // exaggeration), 50 Hz over the 0.5 s.
    let entities: std::collections::BTreeSet<String> =
        chunks.iter().map(|c| c.entity_path().to_string()).collect();
    for e in [
        "/compare/world/kec/track/rails",
        "/compare/world/kec/follow",
        "/compare/world/kec/vehicle/wheelset_1/pose",
        "/compare/world/lookup/vehicle/wheelset_1/pose",
        "/compare/world/lookup/vehicle/wheelset_1/contact",
    ] {
        assert!(entities.contains(e), "missing {e}: {entities:?}");
    }
    // Issue 47: each model on a track of its own, side by side (they overlapped on one track).
    assert!(
        entities.contains("/compare/world/lookup/track/rails"),
        "a track per model"
    );
    let e = kecsim::inspect::world3d::DEFAULT_EXAGGERATION;
    for (k, model) in ["kec", "lookup"].into_iter().enumerate() {
        let y: Vec<f64> = chunks
            .iter()
            .filter(|c| {
                c.entity_path().to_string() == format!("/compare/world/{model}/vehicle/wheelset_1/pose")
            })
            .flat_map(|c| {
                c.iter_slices::<[f32; 3]>(rerun::Transform3D::descriptor_translation().component)
                    .map(|v| v[0][1] as f64 / e)
                    .collect::<Vec<_>>()
            })
            .collect();
        assert_eq!(y.len(), 26, "{model}");
        // A frame every 20 ms, an output sample every 5 ms (the scene's 200 Hz): the y_mm series'
        // value for this model at every 4th sample.
        let every = (rows.len() - 1) / (y.len() - 1);
        assert_eq!(every, 4);
        for (i, yi) in y.iter().enumerate() {
            let want = rows[every * i][k] * 1e-3;
            assert!(
                (yi - want).abs() < 1e-9 + 1e-6 * want.abs(),
                "{model} frame {i}: {yi} vs {want}"
            );
        }
    }
}

/// `kecsim bench precision --draws`: one sweep per draw (the initial lateral velocity), each
/// against its own reference; a row's error is the largest over the draws and the median beside
/// it — recomputed here from the one-draw sweeps of the same velocities.
#[test]
#[ignore = "slow: precision draws against DOPRI5 references (~22 s)"]
fn precision_draws_take_the_largest_and_the_median_of_the_single_draws() {
    use kecsim::bench::precision::{precision, protocol_draws, PrecisionSettings};
    let sc = scene("wheelset_klingel.toml");
    let base = PrecisionSettings {
        contacts: vec!["kec".to_string()],
        methods: vec![Method::Dopri5],
        rtols: vec![1e-3, 1e-5],
        reference: ("kec".to_string(), Method::Dopri5, 1e-9),
        duration_s: Some(0.5),
        draws: Vec::new(),
    };
    let with = |draws: Vec<f64>| {
        precision(
            &sc,
            &PrecisionSettings {
                draws,
                ..base.clone()
            },
        )
        .unwrap()
    };
    let (a, b, both) = (with(vec![0.0]), with(vec![2e-6]), with(vec![0.0, 2e-6]));
    assert_eq!(both.draws, vec![Some(0.0), Some(2e-6)]);
    for k in 0..both.rows.len() {
        let (ra, rb, r) = (&a.rows[k], &b.rows[k], &both.rows[k]);
        assert_eq!(r.max_dy, ra.max_dy.max(rb.max_dy), "{r:?}");
        assert_eq!(r.max_dpsi, ra.max_dpsi.max(rb.max_dpsi), "{r:?}");
        assert_eq!(r.median_max_dy, 0.5 * (ra.max_dy + rb.max_dy), "{r:?}");
        assert_eq!(r.median_max_dpsi, 0.5 * (ra.max_dpsi + rb.max_dpsi), "{r:?}");
        assert!(r.median_max_dy <= r.max_dy && r.outcome == "completed", "{r:?}");
    }
    // A draw is another trajectory: 2 µm/s moves the error (each against its own reference).
    assert_ne!(a.rows[0].max_dy, b.rows[0].max_dy);
    let md = both.markdown();
    assert!(md.contains("2 draws") && md.contains("0, 2 µm/s"), "{md}");
    assert_eq!(
        protocol_draws(8),
        (0..8).map(|k| k as f64 * 1e-6).collect::<Vec<_>>()
    );
    // The command: --draws N, 1 ..= 64.
    let dir = tmpdir("precision_draws");
    let out = kecsim(&["bench", "precision", "--draws", "0"], &dir);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--draws 0"));
}

/// `kecsim bench precision`: a tolerance sweep against one reference run. The error of each row is
/// its difference from an independent tight run; a row with the reference's own settings is
/// identical to it (error exactly 0: runs are deterministic); the error of a model falls with the
/// tolerance down to the model's own floor (lookup against a KEC reference); the cost at equal
/// error picks the cheapest run within the level; the command prints and records it.
#[test]
#[ignore = "slow: a tolerance sweep against a DOPRI5 reference (~18 s)"]
fn precision_sweep_measures_error_against_the_reference() {
    use kecsim::bench::precision::{precision, PrecisionSettings};
    let sc = scene("wheelset_klingel.toml");
    let settings = PrecisionSettings {
        contacts: vec!["kec".to_string(), "lookup".to_string()],
        methods: vec![Method::Dopri5],
        rtols: vec![1e-3, 1e-5, 1e-9],
        reference: ("kec".to_string(), Method::Dopri5, 1e-9),
        duration_s: Some(1.0),
        draws: Vec::new(),
    };
    let p = precision(&sc, &settings).unwrap();
    assert_eq!(p.rows.len(), 6);
    assert!(p.rows.iter().all(|r| r.outcome == "completed"), "{:?}", p.rows);
    let err = |c: &str, rtol: f64| {
        let r = p.rows.iter().find(|r| r.contact == c && r.rtol == rtol).unwrap();
        (r.max_dy, r.max_dpsi)
    };
    println!("{}", p.markdown());
    // The reference's own settings reproduce it exactly.
    assert_eq!(err("kec", 1e-9), (0.0, 0.0));
    // Convergence: the error falls with the tolerance.
    let (e3, e5) = (err("kec", 1e-3), err("kec", 1e-5));
    assert!(e3.0 > 0.0 && e5.0 < e3.0 / 10.0, "{e3:?} {e5:?}");
    // The lookup table's floor: its difference from KEC (the model's, not the integrator's)
    // stays when the tolerance tightens, and is within the paper's bound on this scene.
    let (l5, l9) = (err("lookup", 1e-5), err("lookup", 1e-9));
    assert!(l9.0 > 10.0 * e5.0 && l9.0 < 1e-3, "{l9:?}");
    assert!((l5.0 - l9.0).abs() < 0.5 * l9.0, "{l5:?} {l9:?}");
    // The cheapest run within a level every row meets: the fastest KEC row.
    let fastest = p
        .rows
        .iter()
        .filter(|r| r.contact == "kec")
        .map(|r| r.wall_s)
        .fold(f64::INFINITY, f64::min);
    assert_eq!(p.cheapest_within("kec", 1.0, 1.0).unwrap().wall_s, fastest);
    assert!(p.cheapest_within("lookup", 1e-12, 1e-12).is_none());
    assert!(p.markdown().contains("| kec | Dopri5 | 1e-5 |"));
    // Up to the first contact jump of either run (the Klingel wheelset crosses S1002/60E1's jump
    // at ±0.23 mm): within the whole run's error, recomputed from the runs' own samples' window.
    for r in &p.rows {
        assert!(r.single_point_s <= r.simulated_s + 1e-9, "{r:?}");
        assert!(
            r.single_point_max_dy <= r.max_dy && r.single_point_max_dpsi <= r.max_dpsi,
            "{r:?}"
        );
    }
    let own = p
        .rows
        .iter()
        .find(|r| r.contact == "kec" && r.rtol == 1e-9)
        .unwrap();
    assert_eq!((own.single_point_max_dy, own.single_point_max_dpsi), (0.0, 0.0));

    let dir = tmpdir("precision");
    let rrd = dir.join("p.rrd");
    let scene_path = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/wheelset_klingel.toml");
    let stdout = kecsim_ok(
        &[
            "bench",
            "precision",
            scene_path.to_str().unwrap(),
            "--duration",
            "0.5",
            "--contact",
            "kec",
            "--method",
            "dopri5",
            "--rtol",
            "1e-3,1e-6",
            "--reference-contact",
            "kec",
            "--reference-rtol",
            "1e-9",
            "--save",
            rrd.to_str().unwrap(),
        ],
        &dir,
    );
    assert!(
        stdout.contains("| kec | Dopri5 | 1e-6 |") && stdout.contains("Cost at equal error"),
        "{stdout}"
    );
    rerun_verify(&rrd);
    assert!(std::fs::metadata(&rrd).unwrap().len() > 0);
    // The sweep's options belong to `precision` only.
    let out = kecsim(&["bench", "creep", "--rtol", "1e-3"], &dir);
    assert!(!out.status.success());
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("apply to `kecsim bench precision` only"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// `kecsim bench scaling`: both series run and complete, each with its fitted exponent (printed;
/// timings are for people, not for tests), the vehicles with their bodies and wheelsets; its
/// options are its own. What does not depend on the machine is asserted: the kilometre laid twice
/// is the same track twice, so the integrator's steps and right-hand sides per simulated second are
/// the same on 2 km as on 1 km (measured 0.99×: 71 241 steps in 103.6 s against 35 432 in 51.0 s); two MS vehicles
/// coupled have twice the states of one.
#[test]
#[ignore = "slow: the MS vehicle over 1 km and 2 km and four vehicles (~14 s)"]
fn bench_scaling_measures_both_series() {
    let dir = tmpdir("scaling");
    let stdout = kecsim_ok(&["bench", "scaling", "--km", "1,2", "--duration", "0.5"], &dir);
    println!("{stdout}");
    let exponent = |prefix: &str| -> f64 {
        let line = stdout
            .lines()
            .find(|l| l.starts_with(prefix))
            .unwrap_or_else(|| panic!("{stdout}"));
        line[prefix.len()..]
            .split_whitespace()
            .next()
            .unwrap()
            .parse()
            .unwrap()
    };
    let length = exponent("fitted exponent of the wall time against the track length: ");
    let size = exponent("fitted exponents against the number of states (1: linear): ");
    assert!(
        length.is_finite() && length > 0.0,
        "track length exponent {length}"
    );
    assert!(size.is_finite() && size > 0.0, "vehicle size exponent {size}");
    assert_eq!(stdout.matches("| completed |").count(), 6, "{stdout}");
    // The table's cells of the row starting with `label`.
    let row = |label: &str| -> Vec<String> {
        let line = stdout
            .lines()
            .find(|l| l.starts_with(&format!("| {label} |")))
            .unwrap_or_else(|| panic!("no row {label}: {stdout}"));
        line.trim_matches('|')
            .split('|')
            .map(|c| c.trim().to_string())
            .collect()
    };
    let num =
        |cells: &[String], k: usize| -> f64 { cells[k].parse().unwrap_or_else(|_| panic!("{cells:?}")) };
    // Track length rows: run | km | simulated s | wall s | real-time factor | steps | RHS | µs | outcome.
    let (one, two) = (row("MS vehicle, 1 km"), row("MS vehicle, 2 km"));
    let sim_ratio = num(&two, 2) / num(&one, 2);
    assert!(
        sim_ratio > 2.0 && sim_ratio < 2.05,
        "simulated time ratio {sim_ratio}"
    );
    // The second kilometre is not the first again: no static settling, no run-in of the
    // irregularities, the rear bogie's slightly unstable 9 Hz mode entering the curve at another
    // amplitude. Measured (issue 52, the default at atol 3e-7): 2 km against 1 km 0.952 (steps),
    // 0.932 (right-hand sides) per simulated second — the second kilometre alone 13 % cheaper
    // per second than the first; within 5 % at atol 1e-6. A cost growing with the track's length
    // (a search over the whole track per evaluation) would show as a ratio above 1.
    for (k, what) in [(5, "steps"), (6, "right-hand sides")] {
        let per_second = (num(&two, k) / num(&two, 2)) / (num(&one, k) / num(&one, 2));
        assert!(
            per_second > 0.88 && per_second < 1.05,
            "{what} per simulated second, 2 km against 1 km: {per_second}"
        );
    }
    // Vehicle size rows: vehicle | bodies | wheelsets | states | …
    let (single, coupled) = (row("MS vehicle"), row("2 MS vehicles coupled"));
    assert_eq!(num(&coupled, 3), 2.0 * num(&single, 3), "{single:?} {coupled:?}");
    for v in [
        "| bogie (2 wheelsets) | 1 | 2 |",
        "| MS vehicle | 8 | 6 |",
        "| 2 MS vehicles coupled | 16 | 12 |",
    ] {
        assert!(stdout.contains(v), "{v}: {stdout}");
    }
    let out = kecsim(&["bench", "scaling", "--rtol", "1e-3"], &dir);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("takes --duration and --km only"));
}

/// `kecsim bench patch-run` (issue 52): the default run's samples post-processed as the output
/// worker does — its counts consistent (two wheels a sample, the recomputed among the contacts,
/// most of them on the near-conformal designed wheel, none unresolved), a largest pmax of a wheel
/// on its rail (0.88 GPa over the first second); options of other targets refused.
#[test]
fn bench_patch_run_post_processes_the_default_samples() {
    let dir = tmpdir("patch_run");
    let out = kecsim(&["bench", "patch-run", "--duration", "1"], &dir);
    let stdout = String::from_utf8_lossy(&out.stdout).to_string();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let field = |after: &str| -> f64 {
        let rest = &stdout[stdout.find(after).unwrap_or_else(|| panic!("{after}: {stdout}")) + after.len()..];
        rest.split_whitespace()
            .next()
            .unwrap()
            .trim_end_matches([',', ';'])
            .parse()
            .unwrap()
    };
    let line = stdout.lines().find(|l| l.contains("wheelset samples")).unwrap();
    let nums: Vec<f64> = line
        .split([' ', ',', ';', '('])
        .filter_map(|w| w.parse().ok())
        .collect();
    // [run s, samples, contacts, recomputed, share %, unresolved]
    let (samples, contacts, recomputed, unresolved) = (nums[1], nums[2], nums[3], nums[5]);
    assert_eq!(samples, 6.0 * 101.0, "{line}");
    assert!(contacts <= 2.0 * samples && contacts > 1.9 * samples, "{line}");
    assert!(recomputed > 0.3 * contacts && recomputed <= contacts, "{line}");
    assert_eq!(unresolved, 0.0, "{line}");
    let pmax = field("max pmax");
    assert!(pmax > 500.0 && pmax < 2500.0, "{stdout}");
    let out = kecsim(&["bench", "patch-run", "--contact", "kec"], &dir);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("takes --duration only"));
}

/// `kecsim bench rhs` (issue 34): every vehicle of the size series measured; the parts' times add
/// up to the whole evaluation (each part is timed between clock reads, nothing falls between
/// them); one pass evaluates every kept state; the coupled pair has twice one vehicle's states.
#[test]
fn bench_rhs_measures_each_vehicle_and_its_parts() {
    use kecsim::bench::rhs::{rhs, RhsSettings};
    let b = rhs(&RhsSettings {
        window_s: 0.2,
        batches: 3,
    })
    .unwrap();
    let labels: Vec<&str> = b.rows.iter().map(|r| r.label.as_str()).collect();
    assert_eq!(
        labels,
        [
            "bogie (2 wheelsets)",
            "Manchester vehicle 1",
            "MS vehicle",
            "2 MS vehicles coupled"
        ]
    );
    for r in &b.rows {
        let p = &r.parts;
        assert_eq!(p.evaluations, r.samples, "{}", r.label);
        assert!(
            r.samples >= 200,
            "{}: {} states kept every 1 ms over 0.2 s",
            r.label,
            r.samples
        );
        let sum =
            p.body_frames_s + p.contact_kinematics_s + p.elements_s + p.bodies_s + p.wheelset_dynamics_s;
        assert!(
            (sum - p.total_s).abs() <= 0.02 * p.total_s,
            "{}: parts {sum} s against {} s",
            r.label,
            p.total_s
        );
        for s in [r.one_thread_us, r.threads_us] {
            assert!(
                s.min > 0.0 && s.min <= s.median && s.median <= s.max && s.max.is_finite(),
                "{}: {s:?}",
                r.label
            );
        }
    }
    // Two coupled MS vehicles: twice the states, wheelsets and bodies of one. (No timing is
    // asserted: the suite's tests run side by side, and a bench prints, it does not judge.)
    let (one, two) = (&b.rows[2], &b.rows[3]);
    assert_eq!(
        (two.states, two.wheelsets, two.bodies),
        (2 * one.states, 2 * one.wheelsets, 2 * one.bodies)
    );
    let md = b.markdown();
    assert!(md.contains("| MS vehicle | 180 | 6 | 8 |"), "{md}");
    assert!(md.contains("wheelset dynamics"), "{md}");
}

/// The output worker (issue 34: the samples computed and handed to the observers off the
/// integration's thread) changes nothing but where they are computed: the same run with a stop
/// condition that never fires (which keeps the samples on the integration's thread, as each must
/// be read before the next step) gives the same samples to the bit, the observers see the same
/// sequence, and without the condition they see it on another thread than the one that finishes
/// the run.
#[test]
fn the_output_worker_records_what_the_run_computes() {
    use kecsim::dynamics::output::{ObserverError, OutputSample, RunObserver, RunSummary};
    use std::thread::ThreadId;

    #[derive(Default)]
    struct Seen {
        rows: Vec<(f64, Vec<u64>)>,
        sample_threads: Vec<ThreadId>,
        finish_thread: Option<ThreadId>,
    }
    impl RunObserver for Seen {
        fn sample(&mut self, s: &OutputSample<'_>) -> Result<(), ObserverError> {
            let bits = s
                .wheelsets
                .iter()
                .flat_map(|w| [w.y, w.yaw, w.normal[0], w.normal[1], w.y_force[0], w.s_rail[1]])
                .chain(s.bodies.iter().flat_map(|b| b.q))
                .map(f64::to_bits)
                .collect();
            self.rows.push((s.t, bits));
            let id = std::thread::current().id();
            if !self.sample_threads.contains(&id) {
                self.sample_threads.push(id);
            }
            Ok(())
        }
        fn finish(&mut self, _s: &RunSummary) -> Result<(), ObserverError> {
            self.finish_thread = Some(std::thread::current().id());
            Ok(())
        }
    }

    let sc = scene("ms_vehicle_tab6.toml");
    let mut built = sc.build_run(&RunOptions::default()).unwrap();
    built.settings.duration_s = 1.0;
    let mut on_worker = Seen::default();
    let a = built.run(&mut [&mut on_worker]);
    built.settings.stop.lateral_m = Some(1.0);
    let mut in_line = Seen::default();
    let b = built.run(&mut [&mut in_line]);
    assert!(matches!(a.end, RunEnd::Completed) && matches!(b.end, RunEnd::Completed));
    assert_eq!(a.samples().len(), 101);
    assert_eq!(on_worker.rows, in_line.rows, "the observers see the same samples");
    for (w, v) in a.wheelsets.iter().zip(&b.wheelsets) {
        assert_eq!(w.1.len(), v.1.len());
        for (p, q) in w.1.iter().zip(&v.1) {
            assert_eq!(format!("{p:?}"), format!("{q:?}"), "{}", w.0);
        }
    }
    assert_eq!(format!("{:?}", a.bodies), format!("{:?}", b.bodies));
    assert_eq!(on_worker.sample_threads.len(), 1);
    assert_ne!(
        Some(on_worker.sample_threads[0]),
        on_worker.finish_thread,
        "samples on the worker"
    );
    assert_eq!(
        Some(in_line.sample_threads[0]),
        in_line.finish_thread,
        "samples in line"
    );
}

/// Issue 37, the contact quantities per wheel in `--csv`: the default scene's first 0.3 s. The
/// wear number and the maximum pressure are recomputed from the CSV's own columns — Tγ =
/// |Fx ξx + Fy ξy| from `fx_*`, `fy_*`, `creep_x_*`, `creep_y_*`, and p0 = 3N/(2πab) (Johnson,
/// Eq. 4.29) from `n_*`, `a_*`, `b_*` —, and the values are those of a loaded metro wheel on its
/// rail: p0 0.4–3 GPa, semi-axes 0.5–30 mm (the stand-in tread on the rail crown is conformal: b to
/// ~16 mm), creepages below 5 %, the spin term |Mz φ| within its bound μ N max(a, b) |φ| (full
/// sliding in pure spin) and not zero everywhere (the default's exact theory carries a spin moment).
#[test]
fn the_csv_carries_creepages_contact_ellipses_and_wear_numbers() {
    let dir = tmpdir("contact-quantities");
    write_ms_scene(&dir, "0.3");
    kecsim_ok(&["run", "ms.toml", "--csv", "csv", "--save", "r.rrd"], &dir);
    for w in ["w1", "w4", "w6"] {
        let text = std::fs::read_to_string(dir.join("csv").join(format!("{w}.csv"))).unwrap();
        let mut lines = text.lines();
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        let rows: Vec<Vec<f64>> = lines
            .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
            .collect();
        assert!(rows.len() > 20, "{w}");
        let col = |name: &str| {
            header
                .iter()
                .position(|h| *h == name)
                .unwrap_or_else(|| panic!("{w}: no column {name}"))
        };
        let mut spin_work: f64 = 0.0;
        for side in ["left", "right"] {
            let c = |stem: &str, unit: &str| {
                if unit.is_empty() {
                    col(&format!("{stem}_{side}"))
                } else {
                    col(&format!("{stem}_{side}_{unit}"))
                }
            };
            let (n, fx, fy) = (c("n", "n"), c("fx", "n"), c("fy", "n"));
            let (cx, cy, spin) = (c("creep_x", ""), c("creep_y", ""), c("spin", "1pm"));
            let (a, b, p0) = (c("a", "mm"), c("b", "mm"), c("p0", "mpa"));
            let (tg, tgs) = (c("tgamma", "n"), c("tgamma_spin", "n"));
            for r in &rows {
                let want = (r[fx] * r[cx] + r[fy] * r[cy]).abs();
                assert!(
                    (r[tg] - want).abs() <= 1e-8 * want.max(1e-3),
                    "{w} {side}: Tγ {} vs {want}",
                    r[tg]
                );
                let bound = 0.3 * r[n] * r[a].max(r[b]) * 1e-3 * r[spin].abs();
                assert!(
                    r[tgs] >= 0.0 && r[tgs] <= bound * (1.0 + 1e-9) + 1e-9,
                    "{w} {side}: |Mz φ| {} above μ N max(a, b) |φ| = {bound}",
                    r[tgs]
                );
                spin_work = spin_work.max(r[tgs]);
                assert!(
                    r[cx].abs() < 0.05 && r[cy].abs() < 0.05 && r[spin].abs() < 5.0,
                    "{r:?}"
                );
                if r[n] > 1e3 {
                    let hertz = 3.0 * r[n] / (2.0 * std::f64::consts::PI * r[a] * 1e-3 * r[b] * 1e-3) * 1e-6;
                    assert!(
                        (r[p0] - hertz).abs() <= 1e-8 * hertz,
                        "{w} {side}: p0 {} vs {hertz}",
                        r[p0]
                    );
                    assert!((400.0..3000.0).contains(&r[p0]), "{w} {side}: p0 {} MPa", r[p0]);
                    assert!(
                        (0.5..30.0).contains(&r[a]) && (0.5..30.0).contains(&r[b]),
                        "{r:?}"
                    );
                }
            }
        }
        assert!(spin_work > 0.0, "{w}: no spin moment anywhere");
    }
}

/// A CSV of `kecsim run --csv` as its header and rows (the carbodies' `point` column read as NaN).
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>, Vec<String>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(str::to_string).collect();
    let point = header.iter().position(|h| h == "point");
    let (mut rows, mut points) = (Vec::new(), Vec::new());
    for l in lines {
        let cells: Vec<&str> = l.split(',').collect();
        if let Some(p) = point {
            points.push(cells[p].to_string());
        }
        rows.push(cells.iter().map(|v| v.parse().unwrap_or(f64::NAN)).collect());
    }
    (header, rows, points)
}

/// The USFD wear function as published (Lewis & Dwyer-Joyce 2004; Braghin et al. 2006, Table 1),
/// written out again here: K (µg/(m mm²)) of Tγ/A (N/mm²).
fn usfd_published(index: f64) -> f64 {
    if index <= 0.0 {
        0.0
    } else if index < 10.4 {
        5.3 * index
    } else if index <= 77.2 {
        55.0
    } else {
        61.9 * index - 4723.0
    }
}

/// Issue 37: `kecsim run` prints, writes and records wear, contact stress and ride comfort for every
/// wheel and carbody of the default scene (16 s: the whole vehicle enters the 235.65 m curve), and
/// each figure agrees with what is recomputed here from the CSVs:
/// - the 2 m mean of Tγ (`tgamma_2m_*`) from the `tgamma_*` and `s_m` columns (1e-9);
/// - each wheel's wear: the published USFD function of Tγ/A (A = π a b) times A, integrated over
///   s by trapezoids, against the JSON's `mass_mg` (1e-9 relative) and `mass_mg_per_km`;
/// - each wheel's largest p0 and its share of distance in ratchetting (p0/k > 1/μ, μ = √(Fx² +
///   Fy²)/N, k = 300 MPa) against the JSON's `contact_stress`;
/// - the floor's quasi-static lateral acceleration in the steady curve against its closed form
///   κV² cos c − g sin c (the uncompensated lateral acceleration, 0.783 m/s² at 19 m/s on R
///   235.65 m with 76 mrad of cant) within 0.1 m/s² (the carbodies lean out on their suspension
///   by a few mrad, g φ ≈ 0.05 m/s², and the track frame's motion approximations stay below 0.01
///   m/s² laterally);
/// - every floor point of the JSON has its rows in its carbody's CSV, and the comfort figures are
///   a tram's: N_MV 0.3–4, Wz 1–4.5.
#[test]
fn a_run_reports_wear_contact_stress_and_ride_comfort() {
    let dir = tmpdir("wear-stress-comfort");
    write_ms_scene(&dir, "16.0");
    let out = kecsim_ok(
        &[
            "run",
            "ms.toml",
            "--csv",
            "csv",
            "--json",
            "s.json",
            "--save",
            "r.rrd",
            "--verbose",
        ],
        &dir,
    );
    for line in [
        "ΔQ/Q₀ limit 0.6",
        "wear (USFD function",
        "contact stress (R260, k 300 MPa)",
        "ride comfort (EN 12299",
    ] {
        assert!(out.contains(line), "the summary lacks {line}: {out}");
    }
    let js: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("s.json")).unwrap()).unwrap();
    let wear = js["wear"]["wheels"].as_array().unwrap();
    let stress = js["contact_stress"]["wheels"].as_array().unwrap();
    assert_eq!((wear.len(), stress.len()), (12, 12));
    for (i, w) in ["w1", "w2", "w3", "w4", "w5", "w6"].iter().enumerate() {
        let (header, rows, _) = read_csv(&dir.join("csv").join(format!("{w}.csv")));
        let col = |name: &str| {
            header
                .iter()
                .position(|h| h == name)
                .unwrap_or_else(|| panic!("{w}: no {name}"))
        };
        let s = col("s_m");
        for (k, side) in ["left", "right"].iter().enumerate() {
            let c = |stem: &str, unit: &str| col(&format!("{stem}_{side}_{unit}"));
            let (n, fx, fy) = (c("n", "n"), c("fx", "n"), c("fy", "n"));
            // p0: the model valid at each contact (`pmax`: Hertz's p0 where D ≤ 0.25, the strip
            // model's beyond); `p0` stays Hertz's; the area is the same model's.
            let (p0, hertz_p0, area_mm2, dev, tg, tg2) = (
                c("pmax", "mpa"),
                c("p0", "mpa"),
                c("contact_area", "mm2"),
                col(&format!("hertz_dev_{side}")),
                c("tgamma", "n"),
                c("tgamma_2m", "n"),
            );
            for r in &rows {
                // Where Hertz holds, the valid model's pressure is Hertz's.
                if r[n] > 0.0 && r[dev] <= kecsim::contact::nonhertz::HERTZ_VALIDITY_LIMIT {
                    assert!(
                        (r[p0] - r[hertz_p0]).abs() <= 1e-6 * r[hertz_p0],
                        "{w} {side}: pmax {} vs p0 {}",
                        r[p0],
                        r[hertz_p0]
                    );
                }
            }
            // The 2 m mean, causal, over the samples within 2 m behind.
            for (j, r) in rows.iter().enumerate() {
                let window: Vec<f64> = rows[..=j]
                    .iter()
                    .filter(|q| r[s] - q[s] < 2.0)
                    .map(|q| q[tg])
                    .collect();
                let mean = window.iter().sum::<f64>() / window.len() as f64;
                assert!(
                    (r[tg2] - mean).abs() <= 1e-9 * mean.max(1.0) + 1e-6,
                    "{w} {side} row {j}: {} vs {mean}",
                    r[tg2]
                );
            }
            // Wear: K(Tγ/A)·A µg/m integrated over s.
            let rate = |r: &Vec<f64>| {
                let area = r[area_mm2];
                if r[n] > 0.0 && area > 0.0 {
                    usfd_published(r[tg] / area) * area
                } else {
                    0.0
                }
            };
            let mass_ug: f64 = rows
                .windows(2)
                .map(|p| 0.5 * (rate(&p[0]) + rate(&p[1])) * (p[1][s] - p[0][s]).abs())
                .sum();
            let jw = &wear[2 * i + k];
            assert_eq!(
                (jw["wheelset"].as_str(), jw["wheel"].as_str()),
                (Some(*w), Some(*side))
            );
            let got = jw["mass_mg"].as_f64().unwrap();
            // The CSV's 10 significant digits bound the agreement.
            assert!(
                (got - mass_ug * 1e-3).abs() <= 1e-7 * got.max(1e-3),
                "{w} {side}: {got} mg vs {}",
                mass_ug * 1e-3
            );
            let distance = (rows.last().unwrap()[s] - rows[0][s]).abs();
            let per_km = jw["mass_mg_per_km"].as_f64().unwrap();
            assert!(
                (per_km - mass_ug / distance).abs() <= 1e-7 * per_km,
                "{w} {side}: {per_km} mg/km"
            );
            assert!(per_km > 0.0, "{w} {side}: no wear");
            // Contact stress.
            let js = &stress[2 * i + k];
            let max_p0 = rows.iter().map(|r| r[p0]).fold(0.0, f64::max);
            assert!(
                (js["max_p0_mpa"].as_f64().unwrap() - max_p0).abs() <= 1e-7 * max_p0,
                "{w} {side}: p0"
            );
            let on: Vec<(f64, bool)> = rows
                .iter()
                .map(|r| {
                    let mu = r[fx].hypot(r[fy]) / r[n];
                    (r[s], r[n] > 0.0 && r[p0] > 0.0 && r[p0] / 300.0 > 1.0 / mu)
                })
                .collect();
            let ratchet: f64 = on
                .windows(2)
                .map(|p| 0.5 * (p[1].0 - p[0].0).abs() * (p[0].1 as u8 + p[1].1 as u8) as f64)
                .sum();
            let share = js["share_ratchetting"].as_f64().unwrap();
            assert!(
                (share - ratchet / distance).abs() < 1e-6,
                "{w} {side}: ratchetting {share} vs {}",
                ratchet / distance
            );
            // The share outside Hertz's validity and Hertz's own largest p0, from the CSV.
            let non_hertz: f64 = rows
                .windows(2)
                .map(|p| {
                    let out = |r: &Vec<f64>| {
                        (r[n] > 0.0
                            && r[p0] > 0.0
                            && r[dev] > kecsim::contact::nonhertz::HERTZ_VALIDITY_LIMIT)
                            as u8
                    };
                    0.5 * (p[1][s] - p[0][s]).abs() * (out(&p[0]) + out(&p[1])) as f64
                })
                .sum();
            let share = js["share_non_hertzian"].as_f64().unwrap();
            assert!(
                (share - non_hertz / distance).abs() < 1e-6,
                "{w} {side}: non-Hertzian {share} vs {}",
                non_hertz / distance
            );
            let max_hertz = rows
                .iter()
                .filter(|r| r[n] > 0.0)
                .map(|r| r[hertz_p0])
                .fold(0.0, f64::max);
            assert!(
                (js["max_p0_hertz_mpa"].as_f64().unwrap() - max_hertz).abs() <= 1e-7 * max_hertz,
                "{w} {side}: Hertz p0"
            );
        }
    }
    // Ride comfort: every floor point, its rows, and the steady curve's lateral acceleration.
    let points = js["comfort"]["points"].as_array().unwrap();
    let names: Vec<(String, String)> = points
        .iter()
        .map(|p| {
            (
                p["carbody"].as_str().unwrap().to_string(),
                p["point"].as_str().unwrap().to_string(),
            )
        })
        .collect();
    for want in [
        ("c1", "middle"),
        ("c1", "over_b1"),
        ("c2", "middle"),
        ("c3", "middle"),
        ("c5", "over_b3"),
    ] {
        assert!(
            names.contains(&(want.0.to_string(), want.1.to_string())),
            "{want:?} not in {names:?}"
        );
    }
    assert_eq!(names.len(), 7);
    for p in points {
        let (n_mv, wy, wz) = (
            p["n_mv"].as_f64().unwrap(),
            p["wz_y"].as_f64().unwrap(),
            p["wz_z"].as_f64().unwrap(),
        );
        assert!(
            (0.3..4.0).contains(&n_mv) && (1.0..4.5).contains(&wy) && (1.0..4.5).contains(&wz),
            "{p}"
        );
    }
    let (v, r, cant, g) = (19.0f64, 235.65f64, 0.07599f64, 9.81f64);
    let uncompensated = v * v / r * cant.cos() - g * cant.sin();
    for c in ["c1", "c3", "c5"] {
        let (header, rows, pts) = read_csv(&dir.join("csv").join(format!("{c}.csv")));
        let col = |name: &str| header.iter().position(|h| h == name).unwrap();
        let (t, s, ay) = (col("t_s"), col("s_m"), col("acc_y_m_s2"));
        assert_eq!(rows.len(), pts.len());
        for name in names.iter().filter(|n| n.0 == c) {
            assert!(pts.contains(&name.1), "{c}: no rows of {}", name.1);
        }
        // Steady curve: the carbody 30 m past the curve's start (150 m + 50 m of transition).
        let steady: Vec<f64> = rows
            .iter()
            .zip(&pts)
            .filter(|(r, p)| *p == "middle" && r[s] > 180.0 && r[t] > 12.0)
            .map(|(r, _)| r[ay])
            .collect();
        assert!(
            steady.len() > 100,
            "{c}: {} samples in the steady curve",
            steady.len()
        );
        let mean = steady.iter().sum::<f64>() / steady.len() as f64;
        assert!(
            (mean.abs() - uncompensated).abs() < 0.1,
            "{c}: mean lateral {mean} vs {uncompensated} m/s²"
        );
    }
    // The recording: the wear number, its 2 m mean and p0 per wheelset, the shakedown map with
    // every wheelset's contacts, every floor point's accelerations and continuous comfort (the
    // floor point's lateral acceleration as in its CSV).
    let chunks = kecsim::inspect::readback::recording_chunks(&dir.join("r.rrd")).unwrap();
    let entities: std::collections::BTreeSet<String> =
        chunks.iter().map(|c| c.entity_path().to_string()).collect();
    let mut want: Vec<String> = [
        "/run/shakedown/limit",
        "/run/shakedown/w1",
        "/run/shakedown/w6",
        "/run/w3/tgamma_n",
        "/run/w3/tgamma_2m_n",
        "/run/w3/p0_mpa",
    ]
    .map(str::to_string)
    .to_vec();
    for (c, p) in &names {
        for stem in ["acc_y_m_s2", "acc_z_m_s2", "cc_y_m_s2", "cc_z_m_s2"] {
            want.push(format!("/run/comfort/{stem}/{c}_{p}"));
        }
    }
    for e in &want {
        assert!(entities.contains(e), "the recording lacks {e}");
    }
    let recorded: Vec<f64> =
        kecsim::inspect::readback::scalar_rows(&chunks, "/run/comfort/acc_y_m_s2/c3_middle")
            .into_iter()
            .flatten()
            .collect();
    let (header, rows, pts) = read_csv(&dir.join("csv").join("c3.csv"));
    let ay = header.iter().position(|h| h == "acc_y_m_s2").unwrap();
    let from_csv: Vec<f64> = rows
        .iter()
        .zip(&pts)
        .filter(|(_, p)| *p == "middle")
        .map(|(r, _)| r[ay])
        .collect();
    assert_eq!(recorded.len(), from_csv.len());
    for (a, b) in recorded.iter().zip(&from_csv) {
        assert!((a - b).abs() <= 1e-8 * b.abs().max(1e-3), "{a} vs {b}");
    }
}

/// Issue 37's study extracts read the run's wear, contact stress and comfort figures: on 6 s of the
/// default scene each named extract is the summary's figure (the largest over wheels or floor
/// points), and N_MV exists (a 5 s block).
#[test]
fn studies_extract_wear_contact_stress_and_comfort() {
    use kecsim::study::extract::Extract;
    let sc = scene("ms_vehicle_tab6.toml");
    let out = run_ok(&sc, "kec", |s| s.duration_s = 6.0);
    let s = &out.summary;
    let (wear, stress, comfort) = (
        s.wear.as_ref().unwrap(),
        s.contact_stress.as_ref().unwrap(),
        s.comfort.as_ref().unwrap(),
    );
    let max = |v: Vec<f64>| v.into_iter().fold(f64::NEG_INFINITY, f64::max);
    let want = [
        (
            "max_wear_mg_per_km",
            max(wear.wheels.iter().map(|w| w.mass_mg_per_km).collect()),
        ),
        (
            "max_tgamma_2m_n",
            max(wear.wheels.iter().map(|w| w.max_tgamma_2m_n).collect()),
        ),
        (
            "max_p0_mpa",
            max(stress.wheels.iter().map(|w| w.max_p0_mpa).collect()),
        ),
        (
            "max_ratchetting_share",
            max(stress.wheels.iter().map(|w| w.share_ratchetting).collect()),
        ),
        (
            "max_n_mv",
            max(comfort.points.iter().map(|p| p.n_mv.unwrap()).collect()),
        ),
        ("max_wz_y", max(comfort.points.iter().map(|p| p.wz_y).collect())),
        ("max_wz_z", max(comfort.points.iter().map(|p| p.wz_z).collect())),
        (
            "max_cc_y_m_s2",
            max(comfort.points.iter().map(|p| p.cc_y_max_m_s2.unwrap()).collect()),
        ),
        (
            "max_cc_z_m_s2",
            max(comfort.points.iter().map(|p| p.cc_z_max_m_s2.unwrap()).collect()),
        ),
    ];
    for (name, value) in want {
        let got = Extract::parse(name).unwrap().value(&out, None).unwrap();
        let positive = name != "max_ratchetting_share";
        assert!(
            value.is_finite() && got == value && (value > 0.0 || !positive),
            "{name}: {got} vs {value}"
        );
    }
    assert_eq!(comfort.blocks, 1);
}

/// The carbodies where ride comfort is read, from the scenes' structure: the MS tram's five modules
/// (the end modules and the middle one over their bogies), the Manchester vehicle's and the
/// Cooperrider car's one body on two bogies, and none on the bogie scene (its carbody is a carried
/// mass).
#[test]
fn carbodies_are_found_from_the_vehicles_structure() {
    use kecsim::vehicle::spec::VehicleSpec;
    let carbodies = |file: &str| -> Vec<(String, Vec<String>)> {
        let sc = scene(file);
        let Some((_, VehicleSpec::Multibody(m))) = &sc.simulation else {
            panic!("{file}: not a multibody vehicle")
        };
        m.carbodies()
            .into_iter()
            .map(|(c, b)| {
                (
                    m.bodies[c].name.clone(),
                    b.into_iter().map(|k| m.bodies[k].name.clone()).collect(),
                )
            })
            .collect()
    };
    let ms = carbodies("ms_vehicle_tab6.toml");
    let names: Vec<&str> = ms.iter().map(|c| c.0.as_str()).collect();
    assert_eq!(names, ["c1", "c2", "c3", "c4", "c5"]);
    assert_eq!(ms[0].1, ["b1"]);
    assert!(ms[1].1.is_empty() && ms[3].1.is_empty());
    assert_eq!(
        (ms[2].1.as_slice(), ms[4].1.as_slice()),
        (&["b2".to_string()][..], &["b3".to_string()][..])
    );
    for file in ["manchester_vehicle1_tab6.toml", "cooperrider_car.toml"] {
        let c = carbodies(file);
        assert!(c.len() == 1 && c[0].1.len() == 2, "{file}: {c:?}");
    }
    assert!(carbodies("bogie_tab6_curve.toml").is_empty());
}
