//! One step of the three-stage Radau IIA method of order 5 ([`Method::Radau5`]), after the design
//! of Hairer & Wanner's RADAU5 (*Solving Ordinary Differential Equations II*, 2nd ed., §IV.8, and
//! their Fortran code `radau5.f`). L-stable and stiffly accurate: the step is set by the motion's
//! accuracy whatever the damping of the stiff modes (BDF-3…5 are held at the stability boundary of
//! a lightly damped mode, [`super::bdf::stable_step`]; Radau IIA is not).
//!
//! **The stages** Z = (z₁, z₂, z₃), zᵢ ≈ x(t + cᵢh) − x₀, c = ((4 − √6)/10, (4 + √6)/10, 1), solve
//!
//! ```text
//! Z = h (A ⊗ I) F(Z),   F(Z)ᵢ = f(t + cᵢ h, x₀ + zᵢ),   x₁ = x₀ + z₃   (stiffly accurate)
//! ```
//!
//! with A the Radau IIA matrix (H–W II, Table IV.5.6). **Simplified Newton** on the transformed
//! stages W = (T⁻¹ ⊗ I) Z, with T⁻¹ A⁻¹ T = [[γ̂, 0, 0], [0, α̂, −β̂], [0, β̂, α̂]] (γ̂ = 3.6378…,
//! α̂ ± iβ̂ = 2.6811… ± 3.0504… i the eigenvalues of A⁻¹, H–W II (8.15)–(8.18)):
//!
//! ```text
//! (γ̂/h I − J) ΔW₁ = (T⁻¹F)₁ − γ̂/h W₁                                              (real)
//! ((α̂ + iβ̂)/h I − J)(ΔW₂ + iΔW₃) = (T⁻¹F)₂ − (α̂W₂ − β̂W₃)/h + i[(T⁻¹F)₃ − (β̂W₂ + α̂W₃)/h]  (complex)
//! ```
//!
//! — one real and one complex factorisation per Jacobian and step size, each by the integrator's
//! Newton blocks (the wheelsets and bogie frames by finite differences, the other bodies'
//! q̇ = v coupling exactly, [`IterationMatrix`]). As for the BDF, the iteration converges to the
//! Radau solution whatever J is; an inexact J costs iterations. Convergence is judged by the
//! contraction rate θ (H–W II (8.10)–(8.11)): stop when θ/(1 − θ) ‖ΔW‖ ≤ κ = max(10 ε/rtol′,
//! min(0.03, √rtol′)) (RADAU5's FNEWT); a rate ≥ 0.99, or 7 iterations without convergence, fail
//! the step (after renewing a Jacobian that is not fresh). One departure from RADAU5: no early
//! failure where the rate predicts that κ will not be reached by the 7th iteration — with the
//! block Jacobian the first iterations' rate is a poor predictor (on the MS vehicle's first 12 s
//! at rtol 1e-5 that rule failed 770 Newton solves; without it the 12 s take 41 630 right-hand
//! sides instead of 45 153). A looser κ = 0.1 (the BDF's) would save another 27 % there, but
//! costs accuracy at tight tolerances (van der Pol at rtol 1e-8: 2.2e-5 from the reference
//! instead of 4.2e-7): not taken.
//!
//! **Starting values**: the previous step's collocation polynomial extrapolated to the new stages
//! (RADAU5's STARTN = false); zero after a restart (an event, a rejected point).
//!
//! **Error estimate** (H–W II (8.19)–(8.20), RADAU5's ESTRAD; embedded order 3, so the exponent of
//! the step control is 1/4):
//!
//! ```text
//! err = (γ̂/h I − J)⁻¹ [f(t, x₀) + (d₁ z₁ + d₂ z₂ + d₃ z₃)/h],
//! d = (−(13 + 7√6)/3, (−13 + 7√6)/3, −1/3)
//! ```
//!
//! the filter (γ̂/h I − J)⁻¹ keeping it bounded on stiff components; at the first step and after
//! a rejection an estimate ≥ 1 is recomputed with f(t, x₀ + err) in place of f(t, x₀). Because the
//! estimate is of order 3 while the solution is of order 5, the user's tolerances are transformed
//! as RADAU5 does: rtol′ = 0.1 rtol^(2/3), atol′ = atol · rtol′/rtol.
//!
//! **Step size**: h_new = h · fac / err^(1/4), fac = 0.9 (2·7 + 1)/(iterations + 2·7), within
//! [h/5, 8h], with Gustafsson's predictive controller after the second accepted step (H–W II
//! (8.25)); a step size within 1.0–1.2× the last one is kept (the factorisations reused). The
//! Jacobian is kept across steps until the Newton iteration contracts slower than
//! [`JACOBIAN_THETA`] or [`Settings::jacobian_max_age`] steps (RADAU5's THET, set here for a
//! Jacobian that costs tens of right-hand sides).
//!
//! **Dense output**: the collocation polynomial through x₀, x₀ + z₁, x₀ + z₂, x₁ (order 3 at any
//! point, RADAU5's CONTR5).
//!
//! Cost per step: 3 right-hand sides per Newton iteration, one for f(t + h, x₁), and the
//! factorisations; against the BDF's ~3 per step, Radau pays where it takes ≥ 2–3× fewer steps.

// RADAU5's constants as published, to 20 digits (rounded to f64 by the compiler); the stage
// loops index the three stages and the states as the formulas read.
#![allow(clippy::excessive_precision, clippy::needless_range_loop)]

use super::*;
use nalgebra::{Complex, DVector};

/// √6.
const SQ6: f64 = 2.449_489_742_783_178;
/// The nodes c₁, c₂ (c₃ = 1).
const C1: f64 = (4.0 - SQ6) / 10.0;
const C2: f64 = (4.0 + SQ6) / 10.0;
const C1M1: f64 = C1 - 1.0;
const C2M1: f64 = C2 - 1.0;
const C1MC2: f64 = C1 - C2;
/// The real eigenvalue γ̂ of A⁻¹ and its complex pair α̂ ± iβ̂ (H–W II (8.16)).
pub(super) const GAMMA: f64 = 3.637_834_252_744_495_7;
pub(super) const ALPHA: f64 = 2.681_082_873_627_752;
pub(super) const BETA: f64 = 3.050_430_199_247_410_6;
/// The error estimate's weights d = γ̂ (e₁, e₂, e₃) (H–W II (8.20); RADAU5's DD1–DD3).
const DD: [f64; 3] = [-(13.0 + 7.0 * SQ6) / 3.0, (-13.0 + 7.0 * SQ6) / 3.0, -1.0 / 3.0];
/// T (columns: the real eigenvector of A⁻¹, the real and imaginary parts of a complex one) and
/// T⁻¹, as in RADAU5; the test `radau_transformation_diagonalises_the_inverse_of_a` checks them.
pub(super) const T: [[f64; 3]; 3] = [
    [
        9.123_239_487_089_294_279e-2,
        -0.141_255_295_020_954_208_43,
        -3.002_919_410_514_742_449_2e-2,
    ],
    [
        0.241_717_932_707_107_018_96,
        0.204_129_352_293_799_931_99,
        0.382_942_112_757_261_937_79,
    ],
    [0.966_048_182_615_092_936_19, 1.0, 0.0],
];
pub(super) const TI: [[f64; 3]; 3] = [
    [
        4.325_579_890_063_155_351,
        0.339_199_251_815_809_869_54,
        0.541_770_539_935_874_871_19,
    ],
    [
        -4.178_718_591_551_904_727_3,
        -0.327_682_820_761_062_387_08,
        0.476_623_554_500_550_451_96,
    ],
    [
        -0.502_872_634_945_786_875_95,
        2.571_926_949_855_605_429_2,
        -0.596_039_204_828_224_924_97,
    ],
];
/// The Radau IIA matrix A (H–W II Table IV.5.6), for the tests.
#[cfg(test)]
pub(super) fn butcher_a() -> [[f64; 3]; 3] {
    [
        [
            (88.0 - 7.0 * SQ6) / 360.0,
            (296.0 - 169.0 * SQ6) / 1800.0,
            (-2.0 + 3.0 * SQ6) / 225.0,
        ],
        [
            (296.0 + 169.0 * SQ6) / 1800.0,
            (88.0 + 7.0 * SQ6) / 360.0,
            (-2.0 - 3.0 * SQ6) / 225.0,
        ],
        [(16.0 - SQ6) / 36.0, (16.0 + SQ6) / 36.0, 1.0 / 9.0],
    ]
}
/// Newton iterations per step (RADAU5's NIT).
const NIT: usize = 7;
/// Safety factor of the step control.
const SAFE: f64 = 0.9;
/// The Jacobian is renewed after an accepted step whose Newton iteration contracted slower than
/// this (RADAU5's THET, which Hairer advises raising to 0.1 "when Jacobian evaluations are
/// costly": here a Jacobian costs ~20 partial right-hand sides, and the block Jacobian leaves
/// out the bodies' couplings, so a contraction of a few tenths is normal).
pub(super) const JACOBIAN_THETA: f64 = 0.3;

/// Radau IIA's state between steps.
pub(super) struct Radau {
    /// The last accepted step's collocation polynomial: x(t₁ + S h) = x₁ + S (p₀ + (S − c₂ + 1)
    /// (p₁ + (S − c₁ + 1) p₂)), S ∈ [−1, 0] (RADAU5's CONT).
    poly: [Vec<f64>; 3],
    /// The end time and length of the step `poly` belongs to (None: nothing to start from).
    last: Option<(f64, f64)>,
    /// The stages Z, the transformed W, f at the stages.
    z: [Vec<f64>; 3],
    w: [Vec<f64>; 3],
    fz: [Vec<f64>; 3],
    stage: Vec<f64>,
    /// The factored γ̂/h I − J and (α̂ + iβ̂)/h I − J and the h they were factored for (None after
    /// a new Jacobian).
    real: Option<(IterationMatrix<f64>, f64)>,
    complex: Option<IterationMatrix<Complex<f64>>>,
    /// The Newton iteration's last contraction rate θ and its convergence factor θ/(1 − θ).
    theta: f64,
    faccon: f64,
    /// The last accepted step and its error norm (Gustafsson's controller).
    accepted_step: Option<(f64, f64)>,
    /// The last step tried was rejected (the error estimate is then recomputed if ≥ 1).
    rejected: bool,
    /// No step accepted yet.
    first: bool,
    /// The step-size factor for the next step, after an accepted or a rejected one.
    pub(super) factor: f64,
}

impl Radau {
    pub(super) fn new(n: usize) -> Radau {
        let v = || [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
        Radau {
            poly: v(),
            last: None,
            z: v(),
            w: v(),
            fz: v(),
            stage: vec![0.0; n],
            real: None,
            complex: None,
            theta: JACOBIAN_THETA,
            faccon: 1.0,
            accepted_step: None,
            rejected: false,
            first: true,
            factor: 1.0,
        }
    }

    /// Forget the polynomial (after an event's jump the state is a new start).
    pub(super) fn restart(&mut self) {
        self.last = None;
        self.accepted_step = None;
    }

    /// The factorisations no longer match the Jacobian.
    pub(super) fn new_jacobian(&mut self) {
        self.real = None;
        self.complex = None;
    }

    /// The state at t₁ + (s − 1) h of the last accepted step (x1 its end).
    pub(super) fn dense(&self, x1: &[f64], s: f64) -> Vec<f64> {
        let sm = s - 1.0;
        let [p0, p1, p2] = &self.poly;
        (0..x1.len())
            .map(|i| x1[i] + sm * (p0[i] + (sm - C2M1) * (p1[i] + (sm - C1M1) * p2[i])))
            .collect()
    }

    /// The transformed tolerances (rtol′, atol′) of RADAU5.
    fn tolerances(s: &Settings) -> (f64, f64) {
        let rtol = 0.1 * s.rtol.powf(2.0 / 3.0);
        (rtol, s.atol * rtol / s.rtol)
    }
}

/// How one Newton solve of the stage equations ended.
enum Newton {
    Converged(usize),
    /// Diverging, or not converged in [`NIT`] iterations: the step is retried at half its size
    /// (RADAU5's unexpected-rejection factor).
    Failed,
}

impl Stepper {
    /// One Radau IIA step of size h from (t, x), f0 = f(t, x): x1, f1 = f(t + h, x1) (for an
    /// accepted step) and the error norm; the next step's factor in `self.radau.factor`. A Newton
    /// iteration that fails renews a Jacobian that is not fresh and tries again; with a fresh one
    /// it fails the step (infinite error norm, the factor RADAU5 would take).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn radau_step<S: OdeSystem + ?Sized>(
        &mut self,
        sys: &mut S,
        t: f64,
        x: &[f64],
        f0: &[f64],
        h: f64,
        s: &Settings,
        x1: &mut [f64],
        f1: &mut [f64],
        stats: &mut Stats,
    ) -> Result<f64, StepFailure<S::Error>> {
        let n = x.len();
        let (rtol, atol) = Radau::tolerances(s);
        let kappa = (10.0 * f64::EPSILON / rtol).max(0.03f64.min(rtol.sqrt()));
        if self.jac_age.is_none() {
            self.jacobian(sys, t, x, f0, h, s, stats)?;
            self.radau.new_jacobian();
        }
        let newt = loop {
            match self.radau_newton(sys, t, x, h, rtol, atol, kappa, stats)? {
                Newton::Converged(k) => break k,
                Newton::Failed => {
                    if self.jac_age == Some(0) {
                        self.radau.factor = 0.5;
                        self.radau.rejected = true;
                        self.bdf.newton_failed = true;
                        return Ok(f64::INFINITY);
                    }
                    self.jacobian(sys, t, x, f0, h, s, stats)?;
                    self.radau.new_jacobian();
                }
            }
        };
        self.bdf.newton_failed = false;
        let r = &mut self.radau;
        for i in 0..n {
            x1[i] = x[i] + r.z[2][i];
        }
        // The error estimate, filtered by (γ̂/h I − J)⁻¹.
        let Some((real, _)) = &r.real else {
            unreachable!("factored by the Newton iteration")
        };
        let combination: Vec<f64> = (0..n)
            .map(|i| (DD[0] * r.z[0][i] + DD[1] * r.z[1][i] + DD[2] * r.z[2][i]) / h)
            .collect();
        let filtered = |f: &[f64]| -> Option<DVector<f64>> {
            real.solve(&DVector::from_iterator(n, (0..n).map(|i| f[i] + combination[i])))
        };
        let norm = |e: &DVector<f64>| {
            let mut norm = ErrorNorm::default();
            for i in 0..n {
                norm.add_scaled(x[i], x1[i], e[i], rtol, atol);
            }
            norm
        };
        let mut e = filtered(f0).ok_or(StepFailure::Singular)?;
        let mut en = norm(&e);
        if en.value() >= 1.0 && (r.first || r.rejected) {
            // A stiff component can make the estimate ≥ 1 where the step is good: once more
            // with f at x₀ + err (H–W II (8.21)).
            for i in 0..n {
                r.stage[i] = x[i] + e[i];
            }
            sys.rhs(t, &r.stage, f1).map_err(StepFailure::Model)?;
            stats.rhs_evaluations += 1;
            e = filtered(f1).ok_or(StepFailure::Singular)?;
            en = norm(&e);
        }
        self.limiting = en.worst_index;
        let err = en.value().max(1e-10);
        // The step control (RADAU5): fewer Newton iterations, a bolder step.
        let fac = SAFE.min(SAFE * (1 + 2 * NIT) as f64 / (newt + 2 * NIT) as f64);
        let mut quot = (err.powf(0.25) / fac).clamp(1.0 / 8.0, 5.0);
        if err > 1.0 && s.fixed_step.is_none() {
            r.factor = if r.first { 0.1 } else { 1.0 / quot };
            r.rejected = true;
            return Ok(err);
        }
        if let Some((h_acc, err_acc)) = r.accepted_step {
            // Gustafsson's predictive controller (H–W II (8.25)).
            let gus = ((h_acc / h) * (err * err / err_acc).powf(0.25) / SAFE).clamp(1.0 / 8.0, 5.0);
            quot = quot.max(gus);
        }
        r.accepted_step = Some((h, err.max(1e-2)));
        r.factor = 1.0 / quot;
        if r.theta <= JACOBIAN_THETA && (1.0..=1.2).contains(&r.factor) {
            r.factor = 1.0;
        }
        // The accepted step's polynomial (RADAU5's CONT) and f at its end.
        for i in 0..n {
            let (z1, z2, z3) = (r.z[0][i], r.z[1][i], r.z[2][i]);
            let p0 = (z2 - z3) / C2M1;
            let ak = (z1 - z2) / C1MC2;
            let acont3 = (ak - z1 / C1) / C2;
            let p1 = (ak - p0) / C1M1;
            r.poly[0][i] = p0;
            r.poly[1][i] = p1;
            r.poly[2][i] = p1 - acont3;
        }
        r.last = Some((t + h, h));
        r.first = false;
        r.rejected = false;
        if r.theta > JACOBIAN_THETA {
            self.jac_age = None;
        }
        sys.rhs(t + h, x1, f1).map_err(StepFailure::Model)?;
        stats.rhs_evaluations += 1;
        Ok(err)
    }

    /// The simplified Newton iteration on the transformed stages, from the extrapolated
    /// polynomial (or zero), with the matrices factored for h.
    #[allow(clippy::too_many_arguments)]
    fn radau_newton<S: OdeSystem + ?Sized>(
        &mut self,
        sys: &mut S,
        t: f64,
        x: &[f64],
        h: f64,
        rtol: f64,
        atol: f64,
        kappa: f64,
        stats: &mut Stats,
    ) -> Result<Newton, StepFailure<S::Error>> {
        let n = x.len();
        let r = &mut self.radau;
        if r.real.as_ref().is_none_or(|(_, hf)| *hf != h) {
            let blocks = self.newton_blocks.as_deref();
            let kinematic = &self.newton_kinematic;
            r.real = Some((
                IterationMatrix::factor(&self.jac, blocks, kinematic, h / GAMMA),
                h,
            ));
            r.complex = Some(IterationMatrix::factor(
                &self.jac,
                blocks,
                kinematic,
                Complex::new(1.0, 0.0) / Complex::new(ALPHA / h, BETA / h),
            ));
        }
        let (Some((real, _)), Some(complex)) = (&r.real, &r.complex) else {
            unreachable!("factored above")
        };
        // Starting values: the last accepted step's polynomial at the new nodes.
        match r.last {
            Some((t_last, h_last)) if t_last == t => {
                let q = h / h_last;
                let cq = [C1 * q, C2 * q, q];
                for i in 0..n {
                    let (a1, a2, a3) = (r.poly[0][i], r.poly[1][i], r.poly[2][i]);
                    for (k, c) in cq.iter().enumerate() {
                        r.z[k][i] = c * (a1 + (c - C2M1) * (a2 + (c - C1M1) * a3));
                    }
                }
            }
            _ => r.z.iter_mut().for_each(|z| z.iter_mut().for_each(|v| *v = 0.0)),
        }
        for i in 0..n {
            for k in 0..3 {
                r.w[k][i] = TI[k][0] * r.z[0][i] + TI[k][1] * r.z[1][i] + TI[k][2] * r.z[2][i];
            }
        }
        r.faccon = r.faccon.max(f64::EPSILON).powf(0.8);
        let (fac1, alphn, betan) = (GAMMA / h, ALPHA / h, BETA / h);
        let nodes = [C1, C2, 1.0];
        let mut dyno_old = 0.0;
        let mut thq_old = 0.0;
        let mut rhs1 = DVector::<f64>::zeros(n);
        let mut rhs2 = DVector::<Complex<f64>>::zeros(n);
        for newt in 1..=NIT {
            for k in 0..3 {
                for i in 0..n {
                    r.stage[i] = x[i] + r.z[k][i];
                }
                sys.rhs(t + nodes[k] * h, &r.stage, &mut r.fz[k])
                    .map_err(StepFailure::Model)?;
                stats.rhs_evaluations += 1;
            }
            for i in 0..n {
                let f = [r.fz[0][i], r.fz[1][i], r.fz[2][i]];
                let tf = |k: usize| TI[k][0] * f[0] + TI[k][1] * f[1] + TI[k][2] * f[2];
                let (w1, w2, w3) = (r.w[0][i], r.w[1][i], r.w[2][i]);
                rhs1[i] = tf(0) - fac1 * w1;
                rhs2[i] = Complex::new(tf(1) - alphn * w2 + betan * w3, tf(2) - alphn * w3 - betan * w2);
            }
            let d1 = real.solve(&rhs1).ok_or(StepFailure::Singular)?;
            let d2 = complex.solve(&rhs2).ok_or(StepFailure::Singular)?;
            let mut norm = ErrorNorm::default();
            for i in 0..n {
                norm.add_scaled(x[i], x[i], d1[i], rtol, atol);
                norm.add_scaled(x[i], x[i], d2[i].re, rtol, atol);
                norm.add_scaled(x[i], x[i], d2[i].im, rtol, atol);
            }
            let dyno = norm.value();
            if !dyno.is_finite() {
                return Ok(Newton::Failed);
            }
            if newt > 1 && newt < NIT {
                let thq = dyno / dyno_old;
                r.theta = if newt == 2 { thq } else { (thq * thq_old).sqrt() };
                thq_old = thq;
                if r.theta >= 0.99 {
                    return Ok(Newton::Failed);
                }
                r.faccon = r.theta / (1.0 - r.theta);
            }
            dyno_old = dyno.max(f64::EPSILON);
            for i in 0..n {
                r.w[0][i] += d1[i];
                r.w[1][i] += d2[i].re;
                r.w[2][i] += d2[i].im;
                let w = [r.w[0][i], r.w[1][i], r.w[2][i]];
                for k in 0..3 {
                    r.z[k][i] = T[k][0] * w[0] + T[k][1] * w[1] + T[k][2] * w[2];
                }
            }
            if r.faccon * dyno <= kappa {
                return Ok(Newton::Converged(newt));
            }
        }
        Ok(Newton::Failed)
    }
}
