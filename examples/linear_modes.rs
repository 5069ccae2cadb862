//! The linear modes of a scene's vehicle at one instant of its run: the eigenvalues of the
//! right-hand side's Jacobian ∂f/∂x there, least damped first, each with its frequency, damping
//! ratio and the states it moves most — and the same for each wheelset's own block (its states
//! with the bodies held), which is what the BDF's Newton matrix keeps.
//!
//! ```text
//! cargo run --release --example linear_modes -- assets/scenes/ms_vehicle_tab6.toml 14.0 [MODES [CONTACT]]
//! ```
//!
//! The scene is integrated to t with its own integrator and contact model (no recording); the
//! Jacobian is that of the same vehicle with CONTACT (`kec`, `lookup`, `lookup2`, `online`;
//! default: the scene's) at that state — the modes of two contact models side by side. It is
//! differenced centrally (relative step 1e-7, at least 1e-9 absolute); the lift states of wheels on
//! their rails are left out (a perturbation there releases the wheel: a switch, not a
//! derivative). Each eigenvalue λ = −ζω₀ ± iω₀√(1−ζ²) is printed as its frequency Im λ/2π and
//! damping ratio ζ = −Re λ/|λ|; a mode's states are the largest components of its eigenvector
//! (inverse iteration), in the state's units (m, rad, m/s, rad/s), normalised to 1 — and with the
//! longest constant step at which BDF-3, 4, 5 stay stable on it ([`stable_step`]; "any" inside
//! their stability sectors, "-" for a growing mode): a BDF run cannot step longer where such a mode is present, whether or
//! not the motion excites it.
//!
//! What it showed (2026-12-01, the MS kilometre at 14 s, in the curve): the leading wheelset of
//! each bogie has a mode at 91–100 Hz with ζ = 0.011–0.02 — its flanging wheel's spin against its
//! lateral and yaw velocities (the wheel spin 0.93 of the eigenvector, the lateral velocity 0.35),
//! absent from the trailing wheelsets (their slowest-damped wheelset modes are 16–24 Hz, ζ ≥ 0.09).
//! The motion does not excite it (DOPRI5 at rtol 1e-7: nanometres above 50 Hz), but BDF-3…5, not
//! A-stable, are unstable on it beyond ωh ≈ 0.5: their step control holds ~0.9 ms through the curve,
//! whatever the tolerance (test `ms_vehicle_flanging_mode_holds_bdf_at_its_stability_boundary`).
//! With the wheels' spin inertia 100× smaller the mode stays at 92–96 Hz: the wheelset's mass
//! against the flange transition, the free wheel's spin following the rolling radius.

use anyhow::{anyhow, bail, Context, Result};
use kecsim::dynamics::integrator::bdf::stable_step;
use kecsim::dynamics::integrator::{integrate, Flow};
use kecsim::dynamics::linear::{damping_ratio as damping, eigenvector, jacobian};
use kecsim::dynamics::system::Evaluator;
use kecsim::scenario::{RunOptions, Scenario};
use nalgebra::{Complex, DMatrix};

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let [_, scene, t, rest @ ..] = args.as_slice() else {
        bail!("usage: linear_modes SCENE.toml T [MODES]");
    };
    let t_at: f64 = t.parse().with_context(|| format!("T: not a number: {t}"))?;
    let modes: usize = match rest.first() {
        Some(m) => m.parse().with_context(|| format!("MODES: not a count: {m}"))?,
        None => 12,
    };
    let contact = rest.get(1).cloned();
    let path = std::path::Path::new(scene);
    let base = path.parent().unwrap_or(std::path::Path::new("."));
    let scene = Scenario::read(path)?.compile(scene, base)?;
    let run = scene.build_run(&RunOptions::default())?;
    let vehicle = run.vehicle.as_ref();
    let names = vehicle.state_names();
    let mut sys = Evaluator::new(vehicle);
    let x0 = vehicle.initial_state(&run.settings.initial);
    let mut x = x0.clone();
    integrate(
        &mut sys,
        0.0,
        &x0,
        t_at,
        t_at,
        &run.settings.integrator,
        &mut |ti, xi| {
            if ti >= t_at * (1.0 - 1e-12) {
                x = xi.to_vec();
            }
            Ok(Flow::Continue)
        },
    )
    .map_err(|e| anyhow!("the run to t = {t_at} s failed: {e}"))?;
    let other = match &contact {
        Some(name) => Some(scene.build_run(&RunOptions {
            contact: Some(name.clone()),
            ..RunOptions::default()
        })?),
        None => None,
    };
    let mut sys = Evaluator::new(other.as_ref().map_or(vehicle, |r| r.vehicle.as_ref()));
    let jac = jacobian(&mut sys, t_at, &x)?;
    println!(
        "{} states at t = {t_at} s, linearised with the {} contact model; least-damped oscillatory modes of the whole system:",
        x.len(),
        contact.as_deref().unwrap_or("scene's")
    );
    print_modes(&jac, &names, modes, 0.0);
    for (name, (o, m)) in vehicle.wheelset_names().iter().zip(vehicle.wheelset_slots()) {
        println!("wheelset {name} (its own block, bodies held), modes above 1 Hz:");
        let block = jac.view((o, o), (m, m)).clone_owned();
        print_modes(&block, &names[o..o + m], modes, 1.0);
    }
    Ok(())
}

/// The `count` least-damped eigenvalue pairs of `jac` above `min_hz`, with their largest
/// eigenvector components (`names`: the states of `jac`'s rows).
fn print_modes(jac: &DMatrix<f64>, names: &[String], count: usize, min_hz: f64) {
    let mut pairs: Vec<Complex<f64>> = jac
        .complex_eigenvalues()
        .iter()
        .copied()
        .filter(|l| l.im / std::f64::consts::TAU > min_hz.max(1e-3))
        .collect();
    pairs.sort_by(|a, b| damping(a).total_cmp(&damping(b)));
    for l in pairs.iter().take(count) {
        let mode = eigenvector(jac, *l);
        let mut parts: Vec<(usize, f64)> = mode.iter().map(|c| c.norm()).enumerate().collect();
        parts.sort_by(|a, b| b.1.total_cmp(&a.1));
        let states: Vec<String> = parts
            .iter()
            .take(4)
            .filter(|p| p.1 > 0.05)
            .map(|&(i, v)| format!("{} {v:.2}", names[i]))
            .collect();
        // The longest steps BDF-3, 4, 5 stay stable on this mode at.
        let bounds: Vec<String> = (3..=5)
            .map(|k| match stable_step(k, *l) {
                // A growing mode: the exact solution grows too, no bound applies.
                _ if l.re >= 0.0 => "-".into(),
                h if h.is_finite() => format!("{:.2}", h * 1e3),
                _ => "any".into(),
            })
            .collect();
        println!(
            "  {:8.2} Hz  zeta {:7.4}  (λ = {:.2} {:+.2}i)  BDF-3/4/5 stable to h = {} ms  {}",
            l.im / std::f64::consts::TAU,
            damping(l),
            l.re,
            l.im,
            bounds.join("/"),
            states.join(", ")
        );
    }
}
