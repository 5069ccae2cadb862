//! Dynamics scenes checked against independent references: the Klingel wavelength of the
//! equivalent conicity, energy conservation without creep, integrator convergence, the three
//! contact models against each other, the critical speed against fixed-speed runs, and the
//! `kecsim run` interface.

use std::path::Path;

mod common;
use common::{kecsim, rerun_verify, tmpdir};

use kecsim::contact::forces::{ContactForceSettings, CreepModel, Material};
use kecsim::contact::geometry::ContactGeometry;
use kecsim::contact::lookup::{LookupTable1, TableSettings};
use kecsim::contact::report::conicity;
use kecsim::dynamics::contact_model::ContactKind;
use kecsim::dynamics::integrator::{integrate, Method, Settings};
use kecsim::dynamics::run::{build_contact, run, RunOutput, Sample};
use kecsim::dynamics::single_wheelset::{SingleWheelset, SpeedProfile, Tie};
use kecsim::dynamics::spec::SimulationSpec;
use kecsim::dynamics::wheelset::WheelsetInertia;
use kecsim::scenario::{Scenario, Scene};

fn scene(file: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes").join(file);
    Scenario::read(&path).unwrap().compile(&path.display().to_string(), path.parent().unwrap()).unwrap()
}

fn simulate(scene: &Scene, edit: impl Fn(&mut SimulationSpec), contact: ContactKind) -> RunOutput {
    let (mut sim, veh) = scene.simulation.clone().unwrap();
    edit(&mut sim);
    let v = sim.speed_m_s;
    let out = run(scene, &sim, &veh, contact, v, &mut |_| {}).unwrap();
    assert!(out.summary.error.is_none(), "{:?}", out.summary.error);
    out
}

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
    let sc = scene("wheelset_klingel.toml");
    let out = simulate(&sc, |_| {}, ContactKind::Kec);
    let s = &out.samples;
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
        let e = inside.iter().map(|p| 0.5 * (p.position[0].0 - p.position[1].0)).sum::<f64>() / inside.len() as f64;
        let lam = conicity(&table, &[amplitude])[0].annex_b.clone().unwrap();
        let klingel = 2.0 * std::f64::consts::PI * (r0 * e / lam).sqrt();
        let measured = (t1 - t0) * v;
        let rel = measured / klingel - 1.0;
        println!(
            "cycle at {t0:.2} s: amplitude {:.3} mm, λ_eq {lam:.4}, e {e:.4} m: Klingel {klingel:.3} m, simulated {measured:.3} m ({:+.2} %)",
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
    let forces = ContactForceSettings::new(CreepModel::by_name("polach").unwrap(), 0.0, Material::STEEL).unwrap();
    let tie = Tie {
        longitudinal_stiffness_n_per_m: 2e5,
        lateral_stiffness_n_per_m: 3e5,
        longitudinal_damping_n_s_per_m: 0.0,
        lateral_damping_n_s_per_m: 0.0,
        half_spacing_m: 1.0,
    };
    let inertia = WheelsetInertia { mass_kg: 1813.0, inertia_kg_m2: [1120.0, 112.0, 1120.0] };
    let load = 100e3;
    let r0 = sc.pair.wheelset.nominal_radius_m;
    for kind in [ContactKind::Kec, ContactKind::Lookup] {
        let mut sys = SingleWheelset::new(
            inertia,
            tie,
            load,
            SpeedProfile { initial_m_s: 10.0, ramp_m_s2: 0.0 },
            build_contact(&sc, kind).unwrap(),
            forces.clone(),
            r0,
        );
        let mut obs = sys.clone_for_output();
        let x0 = sys.initial_state(0.004, 0.002);
        let mut energies = Vec::new();
        let mut kinetic_max: f64 = 0.0;
        let settings = Settings::new(Method::Dopri5, 1e-9, 1e-11);
        integrate(&mut sys, 0.0, &x0, 3.0, 0.005, &settings, &mut |t, x| {
            let s = obs.sample(t, x)?;
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
            Ok(())
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
            "{}: energy drift {drift:.2e} J, swing {swing:.2e} J over 3 s (largest kinetic energy of the oscillation {kinetic_max:.2e} J)",
            kind.name()
        );
        assert!(drift < 1e-4 * kinetic_max, "{}: drift {drift} J", kind.name());
        assert!(swing < 5e-3 * kinetic_max, "{}: swing {swing} J", kind.name());
    }
}
