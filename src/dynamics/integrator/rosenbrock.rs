//! The Rosenbrock methods: ROS3 ([`Method::Ros3`], L-stable, order 3) and the W-method
//! ROS34PW2 ([`Method::Ros34pw2`]), one code path ([`Stepper::rosenbrock`]) run from each one's
//! tableau in the standard form ([`Tableau`]).

use super::*;

// ROS3 (Sandu et al. 1997), Hairer–Wanner form; the published digits are kept.
#[allow(clippy::excessive_precision)]
mod ros3_tableau {
    pub(super) const R_GAMMA: f64 = 0.435_866_521_508_458_999_416_019_451_193_56;
    #[cfg_attr(not(test), allow(dead_code))]
    pub(super) const R_ALPHA2: f64 = 0.435_866_521_508_458_999_416_019_451_193_56;
    pub(super) const R_C21: f64 = -1.015_617_108_387_770_209_197_560_011_554_5;
    pub(super) const R_C31: f64 = 4.075_995_645_253_769_982_480_583_535_806_7;
    pub(super) const R_C32: f64 = 9.207_679_429_833_079_124_215_681_847_400_3;
    /// γ_i = Σ_j γ_ij, multiplying h f_t in stage i (published; the standard form's check).
    #[cfg_attr(not(test), allow(dead_code))]
    pub(super) const R_GAMMAS: [f64; 3] = [
        0.435_866_521_508_458_999_416_019_451_193_56,
        0.242_919_964_548_168_043_665_922_496_833_14,
        2.185_138_002_766_405_851_151_316_948_583_2,
    ];
    pub(super) const R_M: [f64; 3] = [
        1.0,
        6.169_794_704_382_824_559_255_361_568_973,
        -0.427_722_565_432_185_733_262_383_738_065_14,
    ];
    pub(super) const R_E: [f64; 3] = [
        0.5,
        -2.907_955_871_680_546_982_171_823_620_801_7,
        0.223_540_698_978_115_696_273_609_092_761_99,
    ];
}
use ros3_tableau::*;

// ROS34PW2 (Rang & Angermann 2005, *New Rosenbrock W-methods of order 3 for partial
// differential algebraic equations of index 1*, BIT 45:761–787), Hairer–Wanner form:
// (I − γ h W) k_i = h f(t + α_i h, x + Σ_j a_ij k_j) + h W Σ_j γ_ij k_j + γ_i h² f_t.
// A W-method: order 3 with *any* matrix W in place of ∂f/∂x (the tests check it with W = 0),
// so one Jacobian serves many steps. L-stable and stiffly accurate (b = the last row of a + γ);
// b̂ is an embedded order-2 solution. The digits satisfy the order conditions to 1e-15 (test).
#[allow(clippy::excessive_precision)]
mod ros34pw2_tableau {
    pub(super) const W_GAMMA: f64 = 4.358_665_215_084_590_0e-1;
    /// a_ij (strictly lower).
    pub(super) const W_A: [[f64; 3]; 4] = [
        [0.0, 0.0, 0.0],
        [8.717_330_430_169_180_1e-1, 0.0, 0.0],
        [8.445_706_001_536_942_3e-1, -1.129_906_423_648_418_5e-1, 0.0],
        [0.0, 0.0, 1.0],
    ];
    /// γ_ij (strictly lower; the diagonal is γ).
    pub(super) const W_G: [[f64; 3]; 4] = [
        [0.0, 0.0, 0.0],
        [-8.717_330_430_169_180_1e-1, 0.0, 0.0],
        [-9.033_805_701_304_408_2e-1, 5.418_067_238_809_532_6e-2, 0.0],
        [
            2.421_238_070_609_534_6e-1,
            -1.223_250_583_904_514_7,
            5.452_602_553_351_021_4e-1,
        ],
    ];
    pub(super) const W_B: [f64; 4] = [
        2.421_238_070_609_534_6e-1,
        -1.223_250_583_904_514_7,
        1.545_260_255_335_102_3,
        4.358_665_215_084_590_0e-1,
    ];
    pub(super) const W_BHAT: [f64; 4] = [
        3.781_090_314_581_936_9e-1,
        -9.604_229_221_242_317_8e-2,
        0.5,
        2.179_332_607_542_295_0e-1,
    ];
}
use ros34pw2_tableau::*;

/// A Rosenbrock method in the standard form (Hairer–Wanner II, §IV.7, (7.4) with W in place of
/// ∂f/∂x): s stages
///
/// ```text
/// (I − γ h W) k_i = h f(t + α_i h, x + Σ_{j<i} a_ij k_j) + h W Σ_{j<i} γ_ij k_j + γ_i h² f_t,
/// α_i = Σ_j a_ij,  γ_i = γ + Σ_j γ_ij,  x₁ = x + Σ b_i k_i,  err = Σ (b_i − b̂_i) k_i.
/// ```
///
/// One code path runs every Rosenbrock method from its tableau ([`Stepper::rosenbrock`]).
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Tableau {
    pub(super) gamma: f64,
    /// a_ij, strictly lower (row i has i entries).
    pub(super) a: Vec<Vec<f64>>,
    /// γ_ij, strictly lower.
    pub(super) g: Vec<Vec<f64>>,
    pub(super) b: Vec<f64>,
    pub(super) bhat: Vec<f64>,
    /// A classical Rosenbrock method (the exact Jacobian at every step), not a W-method (one
    /// Jacobian kept for many steps).
    pub(super) jacobian_every_step: bool,
}

impl Tableau {
    /// ROS34PW2 as published (Rang & Angermann 2005).
    pub(super) fn ros34pw2() -> Tableau {
        Tableau {
            gamma: W_GAMMA,
            a: (0..4).map(|i| W_A[i][..i].to_vec()).collect(),
            g: (0..4).map(|i| W_G[i][..i].to_vec()).collect(),
            b: W_B.to_vec(),
            bhat: W_BHAT.to_vec(),
            jacobian_every_step: false,
        }
    }

    /// ROS3 in the standard form, from its published transformed coefficients (Hairer–Wanner
    /// II, (7.3'): Γ⁻¹ = diag(1/γ) − C, a = ã Γ, bᵀ = mᵀ Γ, (b − b̂)ᵀ = eᵀ Γ, with ã21 = ã31 = 1,
    /// ã32 = 0: stages 2 and 3 at the same point). Checked against the published γ_i (the rows
    /// of Γ) and the order conditions (tests).
    pub(super) fn ros3() -> Tableau {
        let c = [[0.0; 3], [R_C21, 0.0, 0.0], [R_C31, R_C32, 0.0]];
        // Γ = (diag(1/γ) − C)⁻¹, lower triangular: forward substitution column by column.
        let mut gamma = [[0.0; 3]; 3];
        #[allow(clippy::needless_range_loop)] // Γ's columns by index, as the formula reads
        for col in 0..3 {
            for row in col..3 {
                let rhs = if row == col { 1.0 } else { 0.0 };
                // Σ_k (Γ⁻¹)_{row,k} Γ_{k,col} = δ: (1/γ) Γ_{row,col} − Σ_{k<row} c_{row,k} Γ_{k,col}.
                let sum: f64 = (col..row).map(|k| c[row][k] * gamma[k][col]).sum();
                gamma[row][col] = R_GAMMA * (rhs + sum);
            }
        }
        let a_tilde = [[0.0; 3], [1.0, 0.0, 0.0], [1.0, 0.0, 0.0]];
        let times = |v: &[f64; 3], col: usize| (0..3).map(|k| v[k] * gamma[k][col]).sum::<f64>();
        let a: Vec<Vec<f64>> = (0..3)
            .map(|i| (0..i).map(|j| times(&a_tilde[i], j)).collect())
            .collect();
        let g: Vec<Vec<f64>> = (0..3).map(|i| gamma[i][..i].to_vec()).collect();
        let b: Vec<f64> = (0..3).map(|j| times(&R_M, j)).collect();
        let e: Vec<f64> = (0..3).map(|j| times(&R_E, j)).collect();
        Tableau {
            gamma: R_GAMMA,
            a,
            g,
            bhat: b.iter().zip(&e).map(|(b, e)| b - e).collect(),
            b,
            jacobian_every_step: true,
        }
    }

    /// The tableau of a Rosenbrock method (None for the others).
    pub(super) fn of(method: Method) -> Option<Tableau> {
        match method {
            Method::Ros3 => Some(Tableau::ros3()),
            Method::Ros34pw2 => Some(Tableau::ros34pw2()),
            Method::Dopri5 | Method::Bdf | Method::Radau5 => None,
        }
    }

    fn stages(&self) -> usize {
        self.b.len()
    }
}

impl Stepper {
    /// One step of the Rosenbrock method of `tableau`: the Jacobian evaluated first when the
    /// method wants it every step or none is valid, W restricted to the system's blocks where it
    /// declares them; a stage at the previous stage's point reuses its f.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn rosenbrock<S: OdeSystem + ?Sized>(
        &mut self,
        tableau: &Tableau,
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
        if tableau.jacobian_every_step || self.jac_age.is_none() {
            self.jacobian(sys, t, x, f0, h, s, stats)?;
        }
        // (I − γ h W) k = r  ⇔  (1/(γ h) I − W) k = r / (γ h).
        let gh = tableau.gamma * h;
        let iteration = IterationMatrix::factor(&self.jac, self.blocks.as_deref(), &[], gh);
        let mut fs = vec![0.0; n];
        let mut v = vec![0.0; n];
        let mut rhs = nalgebra::DVector::zeros(n);
        for i in 0..tableau.stages() {
            // Stage point and f there (the previous stage's where the point is the same).
            let a = &tableau.a[i];
            let alpha: f64 = a.iter().sum();
            if i == 0 {
                fs.copy_from_slice(f0);
            } else if !(i > 1 && a[..i - 1] == tableau.a[i - 1][..] && a[i - 1] == 0.0) {
                for (m, (tm, xm)) in self.tmp.iter_mut().zip(x).enumerate() {
                    *tm = xm + (0..i).map(|j| a[j] * self.k[j][m]).sum::<f64>();
                }
                sys.rhs(t + alpha * h, &self.tmp, &mut fs)
                    .map_err(StepFailure::Model)?;
                stats.rhs_evaluations += 1;
            }
            // r = h f + h W Σ_j γ_ij k_j + γ_i h² f_t, γ_i = γ + Σ_j γ_ij.
            let g = &tableau.g[i];
            for (m, vm) in v.iter_mut().enumerate() {
                *vm = (0..i).map(|j| g[j] * self.k[j][m]).sum::<f64>();
            }
            let gamma_i = tableau.gamma + g.iter().sum::<f64>();
            let wv = iteration.w_times(&self.jac, &v);
            for m in 0..n {
                rhs[m] = (h * (fs[m] + wv[m]) + gamma_i * h * h * self.ft[m]) / gh;
            }
            let k = iteration.solve(&rhs).ok_or(StepFailure::Singular)?;
            self.k[i].copy_from_slice(k.as_slice());
        }
        let mut norm = ErrorNorm::default();
        let stages = tableau.stages();
        for m in 0..n {
            x1[m] = x[m] + (0..stages).map(|j| tableau.b[j] * self.k[j][m]).sum::<f64>();
            let e: f64 = (0..stages)
                .map(|j| (tableau.b[j] - tableau.bhat[j]) * self.k[j][m])
                .sum();
            norm.add(x[m], x1[m], e, s);
        }
        self.limiting = norm.worst_index;
        sys.rhs(t + h, x1, f1).map_err(StepFailure::Model)?;
        stats.rhs_evaluations += 1;
        Ok(norm.value())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The ROS34PW2 digits satisfy the order conditions (Hairer–Wanner II, Table IV.7.1, with
    /// β_ij = a_ij + γ_ij, β'_i = Σ_j<i β_ij, α_i = Σ_j a_ij): order 3 for b, order 2 for b̂, and the
    /// explicit-method conditions of a W-method (Σ b α = 1/2, Σ b a α = 1/6, Σ b γ_i = 0).
    #[test]
    fn ros34pw2_tableau_satisfies_the_order_conditions() {
        let g = W_GAMMA;
        let alpha: Vec<f64> = W_A.iter().map(|r| r.iter().sum()).collect();
        let beta = |i: usize, j: usize| if j < 3 { W_A[i][j] + W_G[i][j] } else { 0.0 };
        let beta_p: Vec<f64> = (0..4).map(|i| (0..i).map(|j| beta(i, j)).sum()).collect();
        let gamma_i: Vec<f64> = (0..4).map(|i| g + W_G[i].iter().sum::<f64>()).collect();
        let dot = |b: &[f64; 4], v: &dyn Fn(usize) -> f64| (0..4).map(|i| b[i] * v(i)).sum::<f64>();
        for (b, order) in [(&W_B, 3), (&W_BHAT, 2)] {
            assert!((dot(b, &|_| 1.0) - 1.0).abs() < 1e-15);
            assert!((dot(b, &|i| beta_p[i]) - (0.5 - g)).abs() < 1e-15);
            assert!((dot(b, &|i| alpha[i]) - 0.5).abs() < 1e-15);
            assert!(dot(b, &|i| gamma_i[i]).abs() < 1e-15);
            if order == 3 {
                assert!((dot(b, &|i| alpha[i] * alpha[i]) - 1.0 / 3.0).abs() < 1e-15);
                let bb = |i: usize| (0..i).map(|j| beta(i, j) * beta_p[j]).sum::<f64>();
                assert!((dot(b, &bb) - (1.0 / 6.0 - g + g * g)).abs() < 1e-15);
                let aa = |i: usize| (0..i).map(|j| W_A[i][j] * alpha[j]).sum::<f64>();
                assert!((dot(b, &aa) - 1.0 / 6.0).abs() < 1e-15);
            }
        }
        // Stiffly accurate: b is the last row of a + γ (with γ on the diagonal).
        for (j, b) in W_B.iter().take(3).enumerate() {
            assert!((b - beta(3, j)).abs() < 1e-15);
        }
        assert!((W_B[3] - g).abs() < 1e-15);
    }

    /// The classical order conditions (Hairer–Wanner II, Table IV.7.1) of a tableau: order 3 for
    /// b, order 2 for b̂. Returns the largest residual.
    fn classical_residual(t: &Tableau) -> f64 {
        let g = t.gamma;
        let n = t.stages();
        let alpha: Vec<f64> = t.a.iter().map(|r| r.iter().sum()).collect();
        let beta = |i: usize, j: usize| if j < i { t.a[i][j] + t.g[i][j] } else { 0.0 };
        let beta_p: Vec<f64> = (0..n).map(|i| (0..i).map(|j| beta(i, j)).sum()).collect();
        let dot = |b: &[f64], v: &dyn Fn(usize) -> f64| (0..n).map(|i| b[i] * v(i)).sum::<f64>();
        let mut worst: f64 = 0.0;
        for (b, order) in [(&t.b, 3), (&t.bhat, 2)] {
            worst = worst.max((dot(b, &|_| 1.0) - 1.0).abs());
            worst = worst.max((dot(b, &|i| beta_p[i]) - (0.5 - g)).abs());
            if order == 3 {
                worst = worst.max((dot(b, &|i| alpha[i] * alpha[i]) - 1.0 / 3.0).abs());
                let bb = |i: usize| (0..i).map(|j| beta(i, j) * beta_p[j]).sum::<f64>();
                worst = worst.max((dot(b, &bb) - (1.0 / 6.0 - g + g * g)).abs());
            }
        }
        worst
    }

    /// ROS3 converted to the standard form the one Rosenbrock path runs: its rows of Γ sum to the
    /// published γ_i, stage 2 sits at the published α₂, stage 3 at stage 2's point, and the
    /// converted tableau meets the classical order conditions (3, embedded 2); ROS34PW2's too.
    #[test]
    fn ros3_in_the_standard_form_is_the_published_method() {
        let t = Tableau::ros3();
        for (i, published) in R_GAMMAS.iter().enumerate() {
            let gamma_i = t.gamma + t.g[i].iter().sum::<f64>();
            assert!(
                (gamma_i - published).abs() < 1e-14,
                "γ_{i}: {gamma_i} against {published}"
            );
        }
        assert!((t.a[1][0] - R_ALPHA2).abs() < 1e-15);
        assert_eq!(t.a[2], vec![t.a[1][0], 0.0], "stage 3 at stage 2's point");
        let r = classical_residual(&t);
        assert!(r < 1e-13, "ROS3: order-condition residual {r:e}");
        let r = classical_residual(&Tableau::ros34pw2());
        assert!(r < 1e-15, "ROS34PW2: {r:e}");
        // A tableau with a wrong digit fails the check (the check can fail).
        let mut wrong = Tableau::ros3();
        wrong.b[1] += 1e-6;
        assert!(classical_residual(&wrong) > 1e-7);
    }
}
