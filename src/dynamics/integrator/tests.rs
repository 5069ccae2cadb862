//! Closed-form problems: order of convergence, tolerance proportionality, dense output, stiffness,
//! energy, and the diagnoses.

use super::*;

/// Harmonic oscillator x'' = −ω² x: exact solution and conserved energy.
struct Oscillator {
    w: f64,
}

impl OdeSystem for Oscillator {
    type Error = String;
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&mut self, _t: f64, x: &[f64], d: &mut [f64]) -> Result<(), String> {
        d[0] = x[1];
        d[1] = -self.w * self.w * x[0];
        Ok(())
    }
}

/// Prothero–Robinson: x' = −λ (x − cos t) − sin t, exact x = cos t; stiff for λ ≫ 1.
struct Prothero {
    lambda: f64,
}

impl OdeSystem for Prothero {
    type Error = String;
    fn dim(&self) -> usize {
        1
    }
    fn rhs(&mut self, t: f64, x: &[f64], d: &mut [f64]) -> Result<(), String> {
        d[0] = -self.lambda * (x[0] - t.cos()) - t.sin();
        Ok(())
    }
}

/// A forced mode x'' + 2ζω x' + ω² x = ω² u(t), u = 1 mm · sin(2π t): the motion follows u
/// (1 Hz ≪ ω/2π).
struct Forced {
    w: f64,
    zeta: f64,
}

impl OdeSystem for Forced {
    type Error = String;
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&mut self, t: f64, x: &[f64], d: &mut [f64]) -> Result<(), String> {
        let u = 1e-3 * (std::f64::consts::TAU * t).sin();
        d[0] = x[1];
        d[1] = -self.w * self.w * (x[0] - u) - 2.0 * self.zeta * self.w * x[1];
        Ok(())
    }
}

impl Forced {
    /// The steady response (x, x') at t: 1 mm · Im(H e^{iΩt}) with H = ω²/(ω² − Ω² + 2iζωΩ),
    /// Ω = 2π, and its rate.
    fn steady(&self, t: f64) -> (f64, f64) {
        let (w, om) = (self.w, std::f64::consts::TAU);
        let gain = nalgebra::Complex::new(w * w, 0.0)
            / nalgebra::Complex::new(w * w - om * om, 2.0 * self.zeta * w * om);
        let e = gain * nalgebra::Complex::new(0.0, om * t).exp();
        (1e-3 * e.im, 1e-3 * om * e.re)
    }
}

fn run(
    sys: &mut dyn OdeSystem<Error = String>,
    x0: &[f64],
    t_end: f64,
    dt_out: f64,
    s: &Settings,
) -> (Vec<(f64, Vec<f64>)>, Stats) {
    let mut out = Vec::new();
    let stats = integrate(sys, 0.0, x0, t_end, dt_out, s, &mut |t, x| {
        out.push((t, x.to_vec()));
        Ok(Flow::Continue)
    })
    .unwrap();
    (out, stats)
}

fn osc_error(out: &[(f64, Vec<f64>)], w: f64) -> f64 {
    out.iter()
        .map(|(t, x)| {
            (x[0] - (w * t).cos())
                .abs()
                .max((x[1] + w * (w * t).sin()).abs() / w)
        })
        .fold(0.0, f64::max)
}

/// Fixed steps: halving h divides the error by 2^p (p = 5 DOPRI5, 3 ROS3 and ROS34PW2).
#[test]
fn convergence_order() {
    for (method, p) in [
        (Method::Dopri5, 5.0),
        (Method::Ros3, 3.0),
        (Method::Ros34pw2, 3.0),
        (Method::Radau5, 5.0),
    ] {
        let mut errs = Vec::new();
        for h in [0.1, 0.05, 0.025] {
            // Radau's Newton iteration stops at a fraction of the tolerance: far below the
            // truncation error here.
            let tol = if method == Method::Radau5 { 1e-14 } else { 1e-6 };
            let mut s = Settings::new(method, tol, tol);
            s.fixed_step = Some(h);
            let (out, _) = run(&mut Oscillator { w: 2.0 }, &[1.0, 0.0], 2.0, 0.1, &s);
            let (t, x) = out.last().unwrap();
            assert!((t - 2.0).abs() < 1e-12);
            errs.push(
                (x[0] - (4.0f64).cos())
                    .abs()
                    .max((x[1] + 2.0 * 4.0f64.sin()).abs()),
            );
        }
        for w in errs.windows(2) {
            let order = (w[0] / w[1]).log2();
            assert!(
                (order - p).abs() < 0.35,
                "{method:?}: observed order {order} ({errs:?})"
            );
        }
    }
}

/// Non-autonomous problem: the Rosenbrock methods keep their order only with the f_t terms.
#[test]
fn rosenbrock_order_non_autonomous() {
    for method in [Method::Ros3, Method::Ros34pw2] {
        let mut errs = Vec::new();
        for h in [0.2, 0.1, 0.05] {
            let mut s = Settings::new(method, 1e-6, 1e-6);
            s.fixed_step = Some(h);
            let (out, _) = run(&mut Prothero { lambda: 1.0 }, &[1.0], 2.0, 0.2, &s);
            errs.push((out.last().unwrap().1[0] - 2.0f64.cos()).abs());
        }
        let order = (errs[1] / errs[2]).log2();
        assert!((order - 3.0).abs() < 0.4, "{method:?}: order {order} {errs:?}");
    }
}

/// The oscillator with a deliberately wrong "Jacobian" (W = scale × the true one).
struct WrongJacobian {
    w: f64,
    scale: f64,
}

impl OdeSystem for WrongJacobian {
    type Error = String;
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&mut self, _t: f64, x: &[f64], d: &mut [f64]) -> Result<(), String> {
        d[0] = x[1];
        d[1] = -self.w * self.w * x[0];
        Ok(())
    }
    fn jacobian(&mut self, _t: f64, _x: &[f64], jac: &mut DMatrix<f64>) -> Option<Result<(), String>> {
        jac.fill(0.0);
        jac[(0, 1)] = self.scale;
        jac[(1, 0)] = -self.w * self.w * self.scale;
        Some(Ok(()))
    }
}

/// ROS34PW2 is a W-method: order 3 with any matrix in place of the Jacobian (W = 0, W = 0.3 J),
/// which is what lets it keep one Jacobian for many steps. ROS3, a classical Rosenbrock method,
/// drops to order ≤ 2 with the same wrong matrices (the test can tell the difference).
#[test]
fn w_method_keeps_its_order_with_a_wrong_jacobian() {
    let order_with = |method: Method, scale: f64| {
        let mut errs = Vec::new();
        for h in [0.04, 0.02, 0.01] {
            let mut s = Settings::new(method, 1e-6, 1e-6);
            s.fixed_step = Some(h);
            let (out, _) = run(&mut WrongJacobian { w: 2.0, scale }, &[1.0, 0.0], 2.0, 0.1, &s);
            let x = &out.last().unwrap().1;
            errs.push((x[0] - 4.0f64.cos()).abs().max((x[1] + 2.0 * 4.0f64.sin()).abs()));
        }
        ((errs[1] / errs[2]).log2(), errs)
    };
    for scale in [0.0, 0.3] {
        let (p, errs) = order_with(Method::Ros34pw2, scale);
        assert!(
            (p - 3.0).abs() < 0.3,
            "ROS34PW2, W = {scale} J: order {p} {errs:?}"
        );
        let (p, errs) = order_with(Method::Ros3, scale);
        assert!(p < 2.3, "ROS3, W = {scale} J: order {p} {errs:?}");
    }
}

/// Adaptive: the global error follows the tolerance (roughly proportionally) and the output,
/// at a fixed rate between steps (dense output), is as accurate as the steps.
#[test]
fn tolerance_proportionality_and_dense_output() {
    for method in [Method::Dopri5, Method::Ros3, Method::Ros34pw2, Method::Radau5] {
        let mut prev: Option<f64> = None;
        for tol in [1e-5, 1e-7, 1e-9] {
            let s = Settings::new(method, tol, tol);
            let (out, stats) = run(&mut Oscillator { w: 3.0 }, &[1.0, 0.0], 10.0, 0.01, &s);
            assert_eq!(out.len(), 1001, "fixed-rate output");
            if matches!(method, Method::Dopri5 | Method::Radau5) {
                // Fewer steps than outputs: the output comes from the dense output between steps.
                assert!(stats.accepted < out.len(), "{method:?}: {} steps", stats.accepted);
            }
            let err = osc_error(&out, 3.0);
            assert!(err < 300.0 * tol, "{method:?} tol {tol}: error {err}");
            if let Some(p) = prev {
                assert!(
                    err < p,
                    "{method:?}: error must fall with the tolerance ({err} ≥ {p})"
                );
            }
            prev = Some(err);
        }
    }
}

/// Stiff: ROS3 takes steps set by accuracy; DOPRI5 is held to the stability limit h ≲ 3.3/λ.
#[test]
fn stiff_problem_needs_the_rosenbrock_method() {
    let lambda = 1e5;
    let s = Settings::new(Method::Ros3, 1e-6, 1e-6);
    let (out, ros) = run(&mut Prothero { lambda }, &[1.0], 10.0, 0.5, &s);
    let err = out
        .iter()
        .map(|(t, x)| (x[0] - t.cos()).abs())
        .fold(0.0, f64::max);
    assert!(err < 1e-5, "ROS3 error {err}");
    let s = Settings::new(Method::Dopri5, 1e-6, 1e-6);
    let (_, dop) = run(&mut Prothero { lambda }, &[1.0], 10.0, 0.5, &s);
    assert!(
        ros.accepted * 20 < dop.accepted,
        "ROS3 {} vs DOPRI5 {} steps",
        ros.accepted,
        dop.accepted
    );
    assert!(
        dop.largest_step < 10.0 / lambda,
        "DOPRI5 largest step {}",
        dop.largest_step
    );
}

/// Energy of the undamped oscillator is conserved to the tolerance.
#[test]
fn energy_conserved_to_tolerance() {
    let s = Settings::new(Method::Dopri5, 1e-10, 1e-10);
    let (out, _) = run(&mut Oscillator { w: 5.0 }, &[0.3, 0.0], 20.0, 0.05, &s);
    let e0 = 0.5 * 25.0 * 0.09;
    let drift = out
        .iter()
        .map(|(_, x)| (0.5 * x[1] * x[1] + 12.5 * x[0] * x[0] - e0).abs() / e0)
        .fold(0.0, f64::max);
    assert!(drift < 1e-7, "{drift}");
}

/// A model that blows up, one that fails, and an impossible tolerance are reported with the time.
#[test]
fn failures_are_diagnosed() {
    struct BlowUp;
    impl OdeSystem for BlowUp {
        type Error = String;
        fn dim(&self) -> usize {
            1
        }
        fn rhs(&mut self, t: f64, _x: &[f64], d: &mut [f64]) -> Result<(), String> {
            d[0] = if t > 1.0 { f64::NAN } else { 1.0 };
            Ok(())
        }
    }
    struct Lift;
    impl OdeSystem for Lift {
        type Error = String;
        fn dim(&self) -> usize {
            1
        }
        fn rhs(&mut self, t: f64, x: &[f64], d: &mut [f64]) -> Result<(), String> {
            if t > 0.5 {
                return Err(format!("negative normal force at x = {}", x[0]));
            }
            d[0] = 1.0;
            Ok(())
        }
    }
    for method in [Method::Dopri5, Method::Ros3, Method::Ros34pw2] {
        let s = Settings::new(method, 1e-8, 1e-8);
        let e = integrate(&mut BlowUp, 0.0, &[0.0], 3.0, 0.1, &s, &mut |_, _| {
            Ok(Flow::Continue)
        })
        .unwrap_err();
        match e {
            IntegrationError::NonFinite { t } => assert!((t - 1.0).abs() < 1e-6, "{t}"),
            other => panic!("{method:?}: {other}"),
        }
        let e = integrate(&mut Lift, 0.0, &[0.0], 3.0, 0.1, &s, &mut |_, _| {
            Ok(Flow::Continue)
        })
        .unwrap_err();
        assert!(
            matches!(e, IntegrationError::Model { t, ref error } if t <= 0.5 + 1e-9 && error.contains("normal force")),
            "{e}"
        );
        let mut tight = Settings::new(method, 1e-30, 1e-30);
        tight.h_min = 1e-6;
        let e = integrate(
            &mut Oscillator { w: 1.0 },
            0.0,
            &[1.0, 0.0],
            1.0,
            0.1,
            &tight,
            &mut |_, _| Ok(Flow::Continue),
        )
        .unwrap_err();
        assert!(
            matches!(e, IntegrationError::StepCollapse { .. }),
            "{method:?}: {e}"
        );
    }
}

/// The observer ends an integration normally with `Flow::Stop` at an output time (a stop
/// condition): `Completion::Stopped` at that time, no output after it, the work done kept; an
/// observer's error is an `Output` failure at its time.
#[test]
fn observer_stops_and_fails_at_output_times() {
    for method in [Method::Dopri5, Method::Ros3, Method::Ros34pw2] {
        let s = Settings::new(method, 1e-8, 1e-10);
        let mut seen = Vec::new();
        let mut stats = Stats::default();
        let end = integrate_into(
            &mut Oscillator { w: 2.0 },
            0.0,
            &[1.0, 0.0],
            10.0,
            0.1,
            &s,
            &mut |t, x| {
                seen.push(t);
                // Stop when x first falls below −0.5 (cos 2t = −0.5 at t = π/3).
                Ok(if x[0] < -0.5 { Flow::Stop } else { Flow::Continue })
            },
            &mut stats,
        )
        .unwrap();
        let t_stop = *seen.last().unwrap();
        assert_eq!(end, Completion::Stopped { t: t_stop }, "{method:?}");
        assert!((t_stop - 1.1).abs() < 1e-9, "{method:?}: stopped at {t_stop}");
        assert!(
            stats.accepted > 0 && stats.rhs_evaluations > 0,
            "{method:?}: {stats:?}"
        );
        let e = integrate(
            &mut Oscillator { w: 2.0 },
            0.0,
            &[1.0, 0.0],
            10.0,
            0.1,
            &s,
            &mut |t, _| {
                if t > 0.45 {
                    Err(format!("cannot write at {t}"))
                } else {
                    Ok(Flow::Continue)
                }
            },
        )
        .unwrap_err();
        assert!(
            matches!(e, IntegrationError::Output { t, ref error } if (t - 0.5).abs() < 1e-9 && error.contains("cannot write")),
            "{method:?}: {e}"
        );
    }
}

/// Stiff and nonlinear (Van der Pol, μ = 1000, over a relaxation cycle): ROS34PW2 keeps each
/// Jacobian for many steps and still meets the tolerance (reference: the same problem at a
/// 1000× tighter tolerance); with the Jacobian renewed every step it takes the same path.
#[test]
fn ros34pw2_reuses_jacobians_on_a_stiff_problem() {
    struct VanDerPol {
        mu: f64,
    }
    impl OdeSystem for VanDerPol {
        type Error = String;
        fn dim(&self) -> usize {
            2
        }
        fn rhs(&mut self, _t: f64, x: &[f64], d: &mut [f64]) -> Result<(), String> {
            d[0] = x[1];
            d[1] = self.mu * ((1.0 - x[0] * x[0]) * x[1] - x[0]);
            Ok(())
        }
    }
    let run_vdp = |tol: f64, age: usize| {
        let mut s = Settings::new(Method::Ros34pw2, tol, tol);
        s.jacobian_max_age = age;
        run(&mut VanDerPol { mu: 1000.0 }, &[2.0, 0.0], 1.0, 0.1, &s)
    };
    let (reference, _) = run_vdp(1e-9, 1);
    for age in [1, 25] {
        let (out, stats) = run_vdp(1e-6, age);
        let err = out
            .iter()
            .zip(&reference)
            .map(|((_, a), (_, b))| (a[0] - b[0]).abs())
            .fold(0.0, f64::max);
        assert!(err < 1e-3, "age {age}: error {err}");
        if age == 1 {
            // One per step; a rejected step retries with the Jacobian of the same point.
            assert_eq!(stats.jacobians, stats.accepted, "{stats:?}");
        } else {
            assert!(
                stats.jacobians * 3 < stats.accepted,
                "{} Jacobians for {} steps",
                stats.jacobians,
                stats.accepted
            );
        }
    }
}

/// Three stiff blocks (Prothero–Robinson pairs, a' = −λ (a − cos t) − sin t, b' = −λ (b − a) −
/// sin t: exact a = b = cos t) beside a non-stiff oscillator outside every block: the W-method
/// with W restricted to the blocks keeps the stiff components stable at the steps the full
/// Jacobian allows, and its Jacobian costs (widest block + 1) evaluations instead of (n + 1):
/// rhs = 1 + 4 (accepted + rejected) + jacobians (columns + 1), counted.
#[test]
fn w_method_on_diagonal_blocks() {
    struct Blocks {
        lambda: f64,
        w: f64,
        blocks: bool,
    }
    impl OdeSystem for Blocks {
        type Error = String;
        fn dim(&self) -> usize {
            8
        }
        fn rhs(&mut self, t: f64, x: &[f64], d: &mut [f64]) -> Result<(), String> {
            d[0] = x[1];
            d[1] = -self.w * self.w * x[0];
            for k in 0..3 {
                let (a, b) = (x[2 + 2 * k], x[3 + 2 * k]);
                d[2 + 2 * k] = -self.lambda * (a - t.cos()) - t.sin();
                d[3 + 2 * k] = -self.lambda * (b - a) - t.sin();
            }
            Ok(())
        }
        fn jacobian_blocks(&self) -> Option<Vec<(usize, usize)>> {
            self.blocks.then(|| vec![(2, 2), (4, 2), (6, 2)])
        }
    }
    let s = Settings::new(Method::Ros34pw2, 1e-6, 1e-8);
    let x0 = [1.0, 0.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0];
    let mut counts = Vec::new();
    for blocks in [true, false] {
        let mut sys = Blocks {
            lambda: 1e5,
            w: 2.0,
            blocks,
        };
        let (out, st) = run(&mut sys, &x0, 5.0, 0.25, &s);
        let err = out
            .iter()
            .map(|(t, x)| {
                (2..8)
                    .map(|i| (x[i] - t.cos()).abs())
                    .fold((x[0] - (2.0 * t).cos()).abs(), f64::max)
            })
            .fold(0.0, f64::max);
        let columns = if blocks { 2 } else { 8 };
        println!(
            "blocks {blocks}: {} steps ({} rejected), {} Jacobians, {} rhs, error {err:.2e}",
            st.accepted, st.rejected, st.jacobians, st.rhs_evaluations
        );
        assert!(err < 1e-4, "error {err}");
        assert_eq!(
            st.rhs_evaluations,
            1 + 4 * (st.accepted + st.rejected) + st.jacobians * (columns + 1)
        );
        counts.push(st.accepted);
    }
    assert!(counts[0] <= counts[1] * 6 / 5, "{counts:?}");
    let (_, dop) = run(
        &mut Blocks {
            lambda: 1e5,
            w: 2.0,
            blocks: true,
        },
        &x0,
        5.0,
        0.25,
        &Settings::new(Method::Dopri5, 1e-6, 1e-8),
    );
    assert!(
        counts[0] * 20 < dop.accepted,
        "{counts:?} vs DOPRI5 {}",
        dop.accepted
    );
}

/// Events: a ball dropped from 1 m bounces with restitution 0.5. The impacts are located on the
/// continuous extension at the closed-form times t₁ = √(2/g), t_{k+1} = t_k + 2 e^k v₁ / g, the
/// jumps reverse the velocity, and the output between impacts follows the parabolas.
#[test]
fn events_locate_impacts_and_jump() {
    struct Ball;
    const GRAV: f64 = 9.81;
    impl OdeSystem for Ball {
        type Error = String;
        fn dim(&self) -> usize {
            2
        }
        fn rhs(&mut self, _t: f64, _x: &[f64], d: &mut [f64]) -> Result<(), String> {
            d[0] = _x[1];
            d[1] = -GRAV;
            Ok(())
        }
        fn event_count(&self) -> usize {
            1
        }
        fn events(&self, x: &[f64], g: &mut [f64]) {
            g[0] = x[0];
        }
        fn jump(&mut self, _t: f64, _event: usize, x: &mut [f64]) -> Result<(), String> {
            x[0] = 0.0;
            x[1] *= -0.5;
            Ok(())
        }
    }
    for method in [Method::Dopri5, Method::Bdf, Method::Radau5] {
        let mut impacts = Vec::new();
        let mut prev_v = 0.0;
        let s = Settings::new(method, 1e-9, 1e-12);
        // The bounces accumulate at t = 3 √(2/g) = 1.355 s (Zeno): stop before.
        let stats = integrate(&mut Ball, 0.0, &[1.0, 0.0], 1.25, 1e-3, &s, &mut |t, x| {
            if x[1] > 0.0 && prev_v <= 0.0 && t > 0.0 {
                impacts.push(t);
            }
            prev_v = x[1];
            assert!(x[0] >= -1e-9, "below ground at {t}: {}", x[0]);
            Ok(Flow::Continue)
        })
        .unwrap();
        let v1 = (2.0 * GRAV).sqrt();
        let mut t_k = (2.0 / GRAV).sqrt();
        let mut exact = vec![t_k];
        for k in 1..4 {
            t_k += 2.0 * 0.5f64.powi(k) * v1 / GRAV;
            exact.push(t_k);
        }
        assert_eq!(stats.events, exact.iter().filter(|&&t| t < 1.25).count());
        assert_eq!(impacts.len(), stats.events);
        for (i, t) in impacts.iter().enumerate() {
            // Output is every 1 ms: the first sample after each impact.
            assert!(
                *t >= exact[i] && *t < exact[i] + 1e-3 + 1e-9,
                "{method:?} impact {i}: {t} vs {}",
                exact[i]
            );
        }
    }
}

/// BDF: the weights reproduce polynomials (derivative and value), and the error constants.
#[test]
fn bdf_weights_are_exact_on_polynomials() {
    let nodes = [1.3, 1.0, 0.8, 0.75, 0.5, 0.1];
    for m in 2..=nodes.len() {
        let (mut a, mut w) = (Vec::new(), Vec::new());
        bdf::derivative_weights(&nodes[..m], &mut a);
        bdf::value_weights(&nodes[..m], 1.7, &mut w);
        for p in 0..m {
            let d: f64 = (0..m).map(|j| a[j] * nodes[j].powi(p as i32)).sum();
            let exact = if p == 0 {
                0.0
            } else {
                p as f64 * nodes[0].powi(p as i32 - 1)
            };
            assert!(
                (d - exact).abs() < 1e-9 * (1.0 + exact.abs()),
                "m {m} p {p}: {d} vs {exact}"
            );
            let v: f64 = (0..m).map(|j| w[j] * nodes[j].powi(p as i32)).sum();
            assert!((v - 1.7f64.powi(p as i32)).abs() < 1e-9, "m {m} p {p}: {v}");
        }
    }
    assert!((bdf::beta(1) - 1.0).abs() < 1e-15 && (bdf::beta(3) - 6.0 / 11.0).abs() < 1e-15);
}

/// BDF: the error falls with the tolerance on the oscillator and on a stiff problem the steps are
/// set by accuracy (DOPRI5 is held to h ≲ 3.3/λ).
#[test]
fn bdf_tolerance_proportionality_and_stiffness() {
    let mut prev: Option<f64> = None;
    for tol in [1e-4, 1e-6, 1e-8] {
        let s = Settings::new(Method::Bdf, tol, tol);
        let (out, st) = run(&mut Oscillator { w: 3.0 }, &[1.0, 0.0], 10.0, 0.01, &s);
        let err = osc_error(&out, 3.0);
        println!(
            "BDF oscillator tol {tol:e}: error {err:.2e}, {} steps ({} rejected), {} rhs",
            st.accepted, st.rejected, st.rhs_evaluations
        );
        assert!(err < 1000.0 * tol, "tol {tol}: error {err}");
        if let Some(p) = prev {
            assert!(err < p, "error must fall with the tolerance ({err} ≥ {p})");
        }
        prev = Some(err);
    }
    let lambda = 1e5;
    let s = Settings::new(Method::Bdf, 1e-6, 1e-6);
    let (out, st) = run(&mut Prothero { lambda }, &[1.0], 10.0, 0.5, &s);
    let err = out
        .iter()
        .map(|(t, x)| (x[0] - t.cos()).abs())
        .fold(0.0, f64::max);
    println!(
        "BDF Prothero: error {err:.2e}, {} steps, {} rhs",
        st.accepted, st.rhs_evaluations
    );
    assert!(err < 1e-4, "BDF error {err}");
    assert!(st.accepted < 2000, "{} steps", st.accepted);
}

/// BDF on a stiff block (a wheelset's creep-damped states) driving a lightly damped 150 rad/s
/// oscillator (a bogie frame on its primary suspension) outside the block: Newton converges to the
/// BDF solution whatever its matrix holds, so all three matrices give the reference solution
/// (DOPRI5 at 1e-11); the oscillator's block differenced in a group of its own makes the iteration
/// converge where the fixed point outside the blocks fails at the steps accuracy allows (measured:
/// 40 % fewer right-hand sides; the exact q' = v coupling alone changes little here).
#[test]
fn bdf_newton_matrix_groups_and_kinematic_blocks() {
    struct Bogie {
        /// 0: blocks only; 1: + kinematic block; 2: body block differenced in its own group.
        matrix: usize,
    }
    const LAMBDA: f64 = 2e4;
    const W: f64 = 150.0;
    impl OdeSystem for Bogie {
        type Error = String;
        fn dim(&self) -> usize {
            4
        }
        fn rhs(&mut self, t: f64, x: &[f64], d: &mut [f64]) -> Result<(), String> {
            let (q, v, a, b) = (x[0], x[1], x[2], x[3]);
            d[0] = v;
            d[1] = -W * W * q - 2.0 * 0.02 * W * v + 500.0 * (a - q);
            d[2] = -LAMBDA * (a - (3.0 * t).sin() - 0.1 * q);
            d[3] = -LAMBDA * (b - a);
            Ok(())
        }
        fn jacobian_blocks(&self) -> Option<Vec<(usize, usize)>> {
            Some(vec![(2, 2)])
        }
        fn kinematic_blocks(&self) -> Vec<(usize, usize)> {
            if self.matrix >= 1 {
                vec![(0, 2)]
            } else {
                Vec::new()
            }
        }
        fn newton_groups(&self) -> Option<Vec<Vec<(usize, usize)>>> {
            (self.matrix == 2).then(|| vec![vec![(2, 2)], vec![(0, 2)]])
        }
    }
    let x0 = [0.0, 0.0, 0.0, 0.0];
    let (reference, _) = run(
        &mut Bogie { matrix: 0 },
        &x0,
        2.0,
        0.01,
        &Settings::new(Method::Dopri5, 1e-11, 1e-13),
    );
    let mut work = Vec::new();
    for (method, matrix) in [0, 1, 2]
        .map(|m| (Method::Bdf, m))
        .into_iter()
        .chain([(Method::Radau5, 2)])
    {
        let s = Settings::new(method, 1e-6, 1e-8);
        let (out, st) = run(&mut Bogie { matrix }, &x0, 2.0, 0.01, &s);
        let err = out
            .iter()
            .zip(&reference)
            .map(|((_, x), (_, r))| (x[0] - r[0]).abs().max((x[2] - r[2]).abs()))
            .fold(0.0, f64::max);
        println!(
            "{method:?} matrix {matrix}: {} steps ({} rejected), {} Jacobians, {} rhs, error {err:.2e}",
            st.accepted, st.rejected, st.jacobians, st.rhs_evaluations
        );
        assert!(err < 1e-5, "{method:?} matrix {matrix}: error {err}");
        work.push(st.rhs_evaluations);
    }
    assert!(10 * work[2] < 7 * work[0], "right-hand sides {work:?}");
}

/// Two uncoupled oscillators, ω = 1 and ω = 40 rad/s, unit amplitude: a method of order p makes a
/// local error ∝ (ωh)^{p+1} on each, 40^{p+1} times larger on the fast one, so the fast
/// oscillator's states must be named as what limits (nearly) every step, by every method; each
/// accepted step is counted once, each rejected one at most once.
#[test]
fn the_state_that_limits_the_step_is_named() {
    struct Two;
    impl OdeSystem for Two {
        type Error = String;
        fn dim(&self) -> usize {
            4
        }
        fn rhs(&mut self, _t: f64, x: &[f64], d: &mut [f64]) -> Result<(), String> {
            d[0] = x[1];
            d[1] = -x[0];
            d[2] = x[3];
            d[3] = -1600.0 * x[2];
            Ok(())
        }
    }
    for method in [Method::Dopri5, Method::Ros3, Method::Ros34pw2, Method::Bdf] {
        let s = Settings::new(method, 1e-6, 1e-6);
        let (_, st) = run(&mut Two, &[1.0, 0.0, 1.0, 0.0], 5.0, 0.1, &s);
        assert_eq!(st.limiting.len(), 4);
        let accepted: usize = st.limiting.iter().map(|c| c[0]).sum();
        let rejected: usize = st.limiting.iter().map(|c| c[1]).sum();
        assert_eq!(accepted, st.accepted, "{method:?}");
        assert!(rejected <= st.rejected, "{method:?}");
        let top = st.limiting_states(4, |i| ["slow", "slow_dot", "fast", "fast_dot"][i].to_string());
        println!("{method:?}: {} steps, limited by {top:?}", st.accepted);
        assert!(top.windows(2).all(|w| w[0].share >= w[1].share), "{top:?}");
        let total: f64 = top.iter().map(|l| l.share).sum();
        assert!((total - 1.0).abs() < 1e-12, "{total}");
        let fast: f64 = top
            .iter()
            .filter(|l| l.state.starts_with("fast"))
            .map(|l| l.share)
            .sum();
        assert!(fast > 0.95, "{method:?}: the fast oscillator limits {fast}");
    }
}

/// BDF: the solution Newton converges to does not depend on the iteration matrix, so a step the
/// error test rejects says nothing of the Jacobian. On a linear stiff problem (J = −λ, constant)
/// driven by a forcing that jumps at t = 1 and t = 2 (the error test rejects steps at each jump,
/// two and more in a row), one Jacobian serves the whole run when its age is unlimited.
#[test]
fn bdf_error_test_rejections_keep_the_jacobian() {
    struct Jumps;
    impl OdeSystem for Jumps {
        type Error = String;
        fn dim(&self) -> usize {
            1
        }
        fn rhs(&mut self, t: f64, x: &[f64], d: &mut [f64]) -> Result<(), String> {
            let g = if t < 1.0 {
                0.0
            } else if t < 2.0 {
                1.0
            } else {
                -0.5
            };
            d[0] = -1.0e4 * (x[0] - g);
            Ok(())
        }
    }
    let mut s = Settings::new(Method::Bdf, 1e-6, 1e-8);
    s.jacobian_max_age = usize::MAX;
    let (out, st) = run(&mut Jumps, &[0.0], 3.0, 0.5, &s);
    println!(
        "BDF on jumps: {} steps, {} rejected, {} Jacobians, {} rhs",
        st.accepted, st.rejected, st.jacobians, st.rhs_evaluations
    );
    assert!(
        st.rejected >= 4,
        "the jumps must be rejected into: {}",
        st.rejected
    );
    assert_eq!(st.jacobians, 1);
    // x follows g within its 0.1 ms time constant: at t = 3 it sits at −0.5.
    let last = out.last().map(|p| p.1[0]).unwrap_or(f64::NAN);
    assert!((last + 0.5).abs() < 1e-6, "{last}");
}

/// BDF-3…5 are not A-stable: on a lightly damped mode (ζ = 0.015, ω = 600 rad/s — the MS
/// vehicle's flanging wheelsets) the constant-step characteristic roots of BDF-k leave the unit
/// disc once ωh passes 0.42 (k = 3), 0.55 (4), 0.79 (5) (`bdf::stable_step`, checked against
/// these values from numpy's polynomial roots and against the published stability sectors), so a
/// slowly forced motion that does not excite the mode still holds the step below that: the step
/// control sees the spurious growth as error. The same motion with the mode
/// well damped (ζ = 0.7: inside BDF-5's 51.8° stability sector) is stepped by its accuracy alone.
#[test]
fn bdf_on_a_lightly_damped_mode_is_held_at_its_stability_boundary() {
    let (w, zeta): (f64, f64) = (600.0, 0.015);
    // The stability bounds of constant-step BDF-k on the mode, as ωh.
    let lambda = nalgebra::Complex::new(-zeta * w, w * (1.0 - zeta * zeta).sqrt());
    let boundary = |k: usize| w * bdf::stable_step(k, lambda);
    let bounds: Vec<f64> = (2..=5).map(boundary).collect();
    println!("BDF-2..5 stable up to ωh = {bounds:.3?} (ζ = {zeta})");
    assert!(bounds[0].is_infinite(), "BDF2 is A-stable: {}", bounds[0]);
    // Inside BDF-5's sector (ζ = 0.7: 45.6° from the negative axis, the sector 51.8°) no bound.
    let damped = nalgebra::Complex::new(-0.7 * w, w * (1.0f64 - 0.49).sqrt());
    assert!(bdf::stable_step(5, damped).is_infinite());
    // A-stable BDF-1; BDF-3, 4, 5 just outside and just inside their published A(α) sectors
    // (86.03°, 73.35°, 51.84°): bounded outside, unbounded inside.
    assert!(bdf::stable_step(1, lambda).is_infinite());
    assert_eq!(
        bdf::stable_step(5, nalgebra::Complex::new(0.1, w)),
        0.0,
        "a growing mode"
    );
    assert!(bdf::stable_step(5, nalgebra::Complex::new(0.0, 0.0)).is_infinite());
    let at = |deg: f64| {
        let a = deg.to_radians();
        nalgebra::Complex::new(-w * a.cos(), w * a.sin())
    };
    for (k, alpha) in [(3, 86.03), (4, 73.35), (5, 51.84)] {
        assert!(
            bdf::stable_step(k, at(alpha + 0.3)).is_finite(),
            "BDF-{k} at {alpha} + 0.3°"
        );
        assert!(
            bdf::stable_step(k, at(alpha - 0.3)).is_infinite(),
            "BDF-{k} at {alpha} − 0.3°"
        );
    }
    for (b, want) in bounds[1..].iter().zip([0.416, 0.552, 0.794]) {
        assert!((b - want).abs() < 0.01, "{b} vs {want}");
    }
    // The integrator, from the forced motion's own state (no transient of the mode): the steady
    // response to u ([`Forced::steady`]).
    let mut steps = Vec::new();
    for zeta in [zeta, 0.7] {
        let exact = |t: f64| (Forced { w, zeta }).steady(t);
        let x0 = [exact(0.0).0, exact(0.0).1];
        let s = Settings::new(Method::Bdf, 1e-4, 1e-7);
        let (out, st) = run(&mut Forced { w, zeta }, &x0, 2.0, 0.01, &s);
        let err = out
            .iter()
            .map(|(t, x)| (x[0] - exact(*t).0).abs())
            .fold(0.0, f64::max);
        let wh = w * 2.0 / st.accepted as f64;
        println!(
            "ζ = {zeta}: BDF {} steps ({} rejected), mean ωh {wh:.3}, max |x − exact| {err:.2e} m",
            st.accepted, st.rejected
        );
        assert!(err < 2e-6, "ζ = {zeta}: error {err}");
        steps.push((st.accepted, wh));
    }
    assert!(
        steps[0].1 < bounds[3],
        "mean ωh {} beyond BDF-5's boundary",
        steps[0].1
    );
    assert!(
        steps[0].0 > 3 * steps[1].0,
        "ζ 0.015: {:?}, ζ 0.7: {:?}",
        steps[0],
        steps[1]
    );
}

/// The method names are one list: each parses to its method and back, the scenario file's serde
/// names are the same, and an unknown name is an error naming the known ones (before, `kecsim
/// bench` mapped every unknown name to BDF in its own copy of the list).
#[test]
fn method_names_are_one_list() {
    #[derive(serde::Deserialize)]
    struct T {
        method: Method,
    }
    for (m, name) in Method::ALL.iter().zip(Method::NAMES) {
        assert_eq!(m.name(), name);
        assert_eq!(name.parse::<Method>(), Ok(*m));
        let t: T = toml::from_str(&format!("method = \"{name}\"")).expect("a listed name deserialises");
        assert_eq!(t.method, *m);
    }
    let e = "radau"
        .parse::<Method>()
        .expect_err("an unknown name must not parse");
    assert!(
        e.contains("radau") && e.contains("dopri5, ros3, ros34pw2, bdf"),
        "{e}"
    );
    assert_eq!(Method::ALL.len(), Method::NAMES.len());
}

/// Radau IIA's constants: A satisfies the collocation conditions Σⱼ aᵢⱼ cⱼ^(k−1) = cᵢᵏ/k
/// (k = 1, 2, 3) at c = ((4 − √6)/10, (4 + √6)/10, 1) (H–W II, §IV.5), T⁻¹T = I, and
/// T⁻¹A⁻¹T = [[γ̂, 0, 0], [0, α̂, −β̂], [0, β̂, α̂]] with the γ̂, α̂, β̂ the step uses — the
/// transformation that splits the 3n-dimensional Newton system into one real and one complex one.
#[test]
fn radau_transformation_diagonalises_the_inverse_of_a() {
    use nalgebra::Matrix3;
    let a = Matrix3::from_fn(|i, j| radau::butcher_a()[i][j]);
    let s6 = 6.0f64.sqrt();
    let c = [(4.0 - s6) / 10.0, (4.0 + s6) / 10.0, 1.0];
    for i in 0..3 {
        for k in 1..=3 {
            let lhs: f64 = (0..3).map(|j| a[(i, j)] * c[j].powi(k - 1)).sum();
            assert!((lhs - c[i].powi(k) / k as f64).abs() < 1e-15, "row {i}, k {k}");
        }
    }
    let t = Matrix3::from_fn(|i, j| radau::T[i][j]);
    let ti = Matrix3::from_fn(|i, j| radau::TI[i][j]);
    assert!((ti * t - Matrix3::identity()).amax() < 1e-14);
    let (g, al, be) = (radau::GAMMA, radau::ALPHA, radau::BETA);
    let want = Matrix3::new(g, 0.0, 0.0, 0.0, al, -be, 0.0, be, al);
    let got = ti * a.try_inverse().expect("A is regular") * t;
    assert!((got - want).amax() < 1e-12, "{got}");
}

/// x' = (re + i im) x as a real 2×2 system.
struct Linear2 {
    re: f64,
    im: f64,
}

impl OdeSystem for Linear2 {
    type Error = String;
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&mut self, _t: f64, x: &[f64], d: &mut [f64]) -> Result<(), String> {
        d[0] = self.re * x[0] - self.im * x[1];
        d[1] = self.im * x[0] + self.re * x[1];
        Ok(())
    }
}

/// One Radau IIA step on the test equation x' = λx is x₁ = R(hλ) x₀, R the (2, 3) Padé
/// approximant of e^z, R(z) = (1 + 2z/5 + z²/20) / (1 − 3z/5 + 3z²/20 − z³/60) (H–W II, §IV.5,
/// Table 5.13): checked in closed form for real and complex hλ — among them a lightly damped mode
/// and hλ = −10⁶, where L-stability makes R ≈ −3/z (BDF-3…5 are not even A-stable).
#[test]
fn radau_step_is_the_pade_approximant_on_the_test_equation() {
    use nalgebra::Complex;
    for (re, im) in [
        (-0.5, 0.0),
        (-10.0, 0.0),
        (-1e6, 0.0),
        (-1.0, 5.0),
        (-0.05, 3.0),
        (-2e4, 1e5),
    ] {
        let mut s = Settings::new(Method::Radau5, 1e-13, 1e-13);
        s.fixed_step = Some(1.0);
        let (out, st) = run(&mut Linear2 { re, im }, &[1.0, 0.0], 1.0, 1.0, &s);
        let z = Complex::new(re, im);
        let r = (1.0 + z * 0.4 + z * z / 20.0) / (1.0 - z * 0.6 + z * z * 0.15 - z * z * z / 60.0);
        let x = &out.last().expect("the end").1;
        let err = (x[0] - r.re).abs().max((x[1] - r.im).abs());
        println!(
            "hλ = {z}: R = {r:.6e}, step {:.6e} + {:.6e} i, |Δ| {err:.1e}",
            x[0], x[1]
        );
        assert_eq!(st.accepted, 1);
        assert!(err < 1e-10 * r.norm().max(1e-3), "hλ = {z}: {x:?} against {r}");
    }
}

/// van der Pol with μ = 1000, y(0) = (2, 0), to t = 2000: the Test Set for IVP Solvers' problem
/// VDPOL (Mazzia & Magherini, Univ. Bari, https://archimede.uniba.it/~testset/problems/vdpol.php),
/// reference y(2000) = (1.706167732170469, −0.8928097010248125e-3). Radau at rtol 1e-8 lands
/// within 1e-5 of it in a few thousand steps; the error falls with the tolerance.
#[test]
fn radau_van_der_pol_mu_1000_against_the_test_set() {
    struct VanDerPol;
    impl OdeSystem for VanDerPol {
        type Error = String;
        fn dim(&self) -> usize {
            2
        }
        fn rhs(&mut self, _t: f64, y: &[f64], d: &mut [f64]) -> Result<(), String> {
            d[0] = y[1];
            d[1] = 1000.0 * (1.0 - y[0] * y[0]) * y[1] - y[0];
            Ok(())
        }
    }
    let reference = [1.706_167_732_170_469, -0.892_809_701_024_812_5e-3];
    let mut errors = Vec::new();
    for tol in [1e-6, 1e-8] {
        let s = Settings::new(Method::Radau5, tol, tol);
        let (out, st) = run(&mut VanDerPol, &[2.0, 0.0], 2000.0, 100.0, &s);
        let y = &out.last().expect("the end").1;
        let err = (y[0] - reference[0])
            .abs()
            .max((y[1] - reference[1]).abs() / reference[1].abs());
        println!(
            "VDPOL rtol {tol:e}: {} steps ({} rejected), {} RHS, {} Jacobians, y(2000) = {y:?}, error {err:.2e}",
            st.accepted, st.rejected, st.rhs_evaluations, st.jacobians
        );
        assert!(st.accepted < 5_000, "{} steps", st.accepted);
        errors.push(err);
    }
    assert!(errors[1] < 1e-5, "{errors:?}");
    assert!(errors[1] < errors[0], "{errors:?}");
}

/// Robertson's reaction to t = 1e11: the Test Set for IVP Solvers' problem ROBER
/// (https://archimede.uniba.it/~testset/problems/rober.php), reference y(1e11) =
/// (0.2083340149701255e-7, 0.8333360770334713e-13, 0.9999999791665050); the mass Σyᵢ = 1 is a
/// conserved linear invariant, which a Runge–Kutta method keeps to round-off (up to the Newton
/// iteration's remainder).
#[test]
fn radau_robertson_against_the_test_set() {
    struct Robertson;
    impl OdeSystem for Robertson {
        type Error = String;
        fn dim(&self) -> usize {
            3
        }
        fn rhs(&mut self, _t: f64, y: &[f64], d: &mut [f64]) -> Result<(), String> {
            d[0] = -0.04 * y[0] + 1e4 * y[1] * y[2];
            d[2] = 3e7 * y[1] * y[1];
            d[1] = -d[0] - d[2];
            Ok(())
        }
    }
    let reference = [
        0.208_334_014_970_125_5e-7,
        0.833_336_077_033_471_3e-13,
        0.999_999_979_166_505,
    ];
    let s = Settings::new(Method::Radau5, 1e-8, 1e-14);
    let mut mass: f64 = 0.0;
    let (out, st) = {
        let mut out = Vec::new();
        let st = integrate(
            &mut Robertson,
            0.0,
            &[1.0, 0.0, 0.0],
            1e11,
            1e9,
            &s,
            &mut |t, y| {
                mass = mass.max((y.iter().sum::<f64>() - 1.0).abs());
                out.push((t, y.to_vec()));
                Ok(Flow::Continue)
            },
        )
        .unwrap();
        (out, st)
    };
    let y = &out.last().expect("the end").1;
    println!(
        "ROBER: {} steps ({} rejected), {} RHS, {} Jacobians, y(1e11) = {y:?}, mass drift {mass:.1e}",
        st.accepted, st.rejected, st.rhs_evaluations, st.jacobians
    );
    for i in 0..3 {
        let rel = (y[i] - reference[i]).abs() / reference[i];
        assert!(
            rel < 1e-6,
            "y{} = {} against {}: {rel:.1e}",
            i + 1,
            y[i],
            reference[i]
        );
    }
    assert!(mass < 1e-9, "mass drift {mass}");
    assert!(st.accepted < 2_000, "{} steps", st.accepted);
}

/// The forced lightly damped mode of `bdf_on_a_lightly_damped_mode_is_held_at_its_stability_boundary`
/// with Radau IIA: L-stable, its steps do not depend on the mode's damping (ζ = 0.015 against
/// 0.7), where BDF's grow > 3× with it; the error against the closed-form steady response holds.
#[test]
fn radau_steps_do_not_depend_on_the_damping_of_a_mode() {
    let w = 600.0;
    let mut steps = Vec::new();
    for zeta in [0.015, 0.7] {
        let exact = |t: f64| (Forced { w, zeta }).steady(t);
        let x0 = [exact(0.0).0, exact(0.0).1];
        let mut counts = Vec::new();
        for method in [Method::Radau5, Method::Bdf] {
            let s = Settings::new(method, 1e-4, 1e-7);
            let (out, st) = run(&mut Forced { w, zeta }, &x0, 2.0, 0.01, &s);
            let err = out
                .iter()
                .map(|(t, x)| (x[0] - exact(*t).0).abs())
                .fold(0.0, f64::max);
            println!(
                "ζ = {zeta}: {method:?} {} steps ({} rejected), {} RHS, max |x − exact| {err:.2e} m",
                st.accepted, st.rejected, st.rhs_evaluations
            );
            assert!(err < 2e-6, "{method:?} ζ = {zeta}: error {err}");
            counts.push(st.accepted);
        }
        steps.push(counts);
    }
    let (radau_light, radau_damped) = (steps[0][0] as f64, steps[1][0] as f64);
    assert!(
        (radau_light / radau_damped - 1.0).abs() < 0.3,
        "Radau: ζ 0.015 {radau_light} steps, ζ 0.7 {radau_damped}"
    );
    assert!(steps[0][1] > 3 * steps[1][1], "BDF {steps:?}");
    assert!(steps[0][0] * 3 < steps[0][1], "lightly damped: Radau {steps:?}");
}

/// BDF's Newton stopping tolerance ([`Settings::newton_tolerance`]) is the one it uses: looser,
/// fewer iterations per step (right-hand sides per step fall), the iteration's error a larger share
/// of the step's — the solution still within the tolerance's reach of the closed form.
#[test]
fn bdf_newton_tolerance_trades_iterations_for_error() {
    let sys = || Forced { w: 40.0, zeta: 0.05 };
    let mut per_step = Vec::new();
    for k in [0.03, 0.1, 0.5] {
        let mut s = Settings::new(Method::Bdf, 1e-6, 1e-9);
        s.newton_tolerance = k;
        let f = sys();
        let (x0, v0) = f.steady(0.0);
        let (out, st) = run(&mut sys(), &[x0, v0], 5.0, 0.01, &s);
        let err = out
            .iter()
            .map(|(t, x)| (x[0] - f.steady(*t).0).abs())
            .fold(0.0, f64::max);
        let r = st.rhs_evaluations as f64 / (st.accepted + st.rejected) as f64;
        println!(
            "BDF Newton tolerance {k}: error {err:.2e} m, {} steps, {} rhs, {r:.3} per step",
            st.accepted, st.rhs_evaluations
        );
        assert!(err < 1e-7, "Newton tolerance {k}: error {err}");
        per_step.push(r);
    }
    assert!(
        per_step[0] > per_step[1] && per_step[1] > per_step[2],
        "{per_step:?}"
    );
}

/// [`Settings::newton_reuse`]: a slow body driven by a stiff, nonlinear block that follows a
/// forcing and carrying one that sits near its equilibrium (two wheelsets, one flanging, one
/// quiet). The iterations after the first skip the quiet block's rows (the system writes NaN
/// there, so an integrator that does not fill them fails) and carry them forward by the
/// Jacobian; the solution is as far from DOPRI5 at 1e-11 as the full iteration's, while the quiet block is evaluated less often than the driven one.
#[test]
fn bdf_newton_reuse_skips_the_quiet_blocks_within_the_tolerance() {
    struct Carried {
        /// Evaluations of each block's rows (driven, quiet).
        evaluations: [usize; 2],
    }
    const LAMBDA: f64 = 3e3;
    impl Carried {
        fn rows(&mut self, t: f64, x: &[f64], d: &mut [f64], quiet: [bool; 2]) {
            let (q, v) = (x[0], x[1]);
            d[0] = v;
            d[1] = -100.0 * q - 0.4 * v + 50.0 * (x[2] - q) + 20.0 * (x[4] - q);
            if !quiet[0] {
                self.evaluations[0] += 1;
                d[2] = -LAMBDA * (x[2] - (5.0 * t).sin() - 0.1 * q) - x[2].powi(3);
                d[3] = -LAMBDA * (x[3] - x[2]) - 10.0 * x[3].powi(3);
            } else {
                d[2] = f64::NAN;
                d[3] = f64::NAN;
            }
            if !quiet[1] {
                self.evaluations[1] += 1;
                d[4] = -LAMBDA * (x[4] - 0.5 - 1e-3 * q) - x[4].powi(3);
                d[5] = -LAMBDA * (x[5] - x[4]) - 10.0 * x[5].powi(3);
            } else {
                d[4] = f64::NAN;
                d[5] = f64::NAN;
            }
        }
    }
    impl OdeSystem for Carried {
        type Error = String;
        fn dim(&self) -> usize {
            6
        }
        fn rhs(&mut self, t: f64, x: &[f64], d: &mut [f64]) -> Result<(), String> {
            self.rows(t, x, d, [false; 2]);
            Ok(())
        }
        fn rhs_reusing(&mut self, t: f64, x: &[f64], d: &mut [f64], quiet: &[bool]) -> Result<(), String> {
            self.rows(t, x, d, [quiet[0], quiet[1]]);
            Ok(())
        }
        fn reusable_blocks(&self) -> Vec<(usize, usize)> {
            vec![(2, 2), (4, 2)]
        }
        fn jacobian_blocks(&self) -> Option<Vec<(usize, usize)>> {
            Some(vec![(2, 2), (4, 2)])
        }
        fn kinematic_blocks(&self) -> Vec<(usize, usize)> {
            vec![(0, 2)]
        }
    }
    let x0 = [0.0, 0.0, 0.0, 0.0, 0.5, 0.5];
    let (reference, _) = run(
        &mut Carried { evaluations: [0; 2] },
        &x0,
        2.0,
        0.01,
        &Settings::new(Method::Dopri5, 1e-11, 1e-13),
    );
    let mut results = Vec::new();
    for reuse in [0.0, 0.5] {
        let mut s = Settings::new(Method::Bdf, 1e-6, 1e-8);
        s.newton_reuse = reuse;
        let mut sys = Carried { evaluations: [0; 2] };
        let (out, st) = run(&mut sys, &x0, 2.0, 0.01, &s);
        let err = out
            .iter()
            .zip(&reference)
            .flat_map(|((_, x), (_, r))| x.iter().zip(r).map(|(a, b)| (a - b).abs()))
            .fold(0.0, f64::max);
        println!(
            "newton_reuse {reuse}: {} steps, {} rhs, {} blocks reused, evaluations {:?}, largest error {err:.2e}",
            st.accepted, st.rhs_evaluations, st.reused_blocks, sys.evaluations
        );
        results.push((err, st, sys.evaluations));
    }
    let (full, reused) = (&results[0], &results[1]);
    assert_eq!(full.1.reused_blocks, 0);
    assert_eq!(full.2[0], full.2[1], "without reuse every evaluation is whole");
    // The quiet block is skipped in most iterations after the first, the driven one rarely.
    assert!(reused.1.reused_blocks > 0);
    assert!(
        10 * reused.2[1] < 8 * reused.2[0],
        "quiet block evaluated {} times against the driven one's {}",
        reused.2[1],
        reused.2[0]
    );
    assert_eq!(
        reused.2[0] + reused.2[1] + reused.1.reused_blocks,
        2 * reused.1.rhs_evaluations
    );
    // As accurate as the full iteration: the largest global error within 20 % of its.
    assert!(full.0 < 1e-3, "error {}", full.0);
    assert!(
        reused.0 < 1.2 * full.0,
        "errors {} (reused) against {}",
        reused.0,
        full.0
    );
}
