//! The Rosenbrock methods: ROS3 ([`Method::Ros3`], L-stable, order 3) and the W-method
//! ROS34PW2 ([`Method::Ros34pw2`]), each from its tableau.

use super::*;

// ROS3 (Sandu et al. 1997), Hairer–Wanner form; the published digits are kept.
#[allow(clippy::excessive_precision)]
mod ros3_tableau {
    pub(super) const R_GAMMA: f64 = 0.435_866_521_508_458_999_416_019_451_193_56;
    pub(super) const R_ALPHA2: f64 = 0.435_866_521_508_458_999_416_019_451_193_56;
    pub(super) const R_C21: f64 = -1.015_617_108_387_770_209_197_560_011_554_5;
    pub(super) const R_C31: f64 = 4.075_995_645_253_769_982_480_583_535_806_7;
    pub(super) const R_C32: f64 = 9.207_679_429_833_079_124_215_681_847_400_3;
    /// γ_i = Σ_j γ_ij, multiplying h f_t in stage i.
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

impl Stepper {
    #[allow(clippy::too_many_arguments)]
    pub(super) fn ros3<S: OdeSystem + ?Sized>(
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
        // A classical Rosenbrock method: the exact Jacobian at every step.
        self.jacobian(sys, t, x, f0, h, s, stats)?;
        let mut g = -self.jac.clone();
        let d = 1.0 / (h * R_GAMMA);
        for i in 0..n {
            g[(i, i)] += d;
        }
        let lu = g.lu();
        let solve = |lu: &nalgebra::LU<f64, nalgebra::Dyn, nalgebra::Dyn>,
                     rhs: &mut Vec<f64>|
         -> Result<(), StepFailure<S::Error>> {
            let b = nalgebra::DVector::from_column_slice(rhs);
            let sol = lu.solve(&b).ok_or(StepFailure::Singular)?;
            rhs.copy_from_slice(sol.as_slice());
            Ok(())
        };
        let ft = &self.ft;
        // Stage 1.
        let mut k1: Vec<f64> = (0..n).map(|i| f0[i] + h * R_GAMMAS[0] * ft[i]).collect();
        solve(&lu, &mut k1)?;
        // Stages 2 and 3 share f at x + K1 (a21 = a31 = 1, a32 = 0), t + α2 h.
        for i in 0..n {
            self.tmp[i] = x[i] + k1[i];
        }
        let mut f2 = vec![0.0; n];
        sys.rhs(t + R_ALPHA2 * h, &self.tmp, &mut f2)
            .map_err(StepFailure::Model)?;
        stats.rhs_evaluations += 1;
        let mut k2: Vec<f64> = (0..n)
            .map(|i| f2[i] + R_C21 / h * k1[i] + h * R_GAMMAS[1] * ft[i])
            .collect();
        solve(&lu, &mut k2)?;
        let mut k3: Vec<f64> = (0..n)
            .map(|i| f2[i] + (R_C31 * k1[i] + R_C32 * k2[i]) / h + h * R_GAMMAS[2] * ft[i])
            .collect();
        solve(&lu, &mut k3)?;
        let mut norm = ErrorNorm::default();
        for i in 0..n {
            x1[i] = x[i] + R_M[0] * k1[i] + R_M[1] * k2[i] + R_M[2] * k3[i];
            let e = R_E[0] * k1[i] + R_E[1] * k2[i] + R_E[2] * k3[i];
            norm.add(x[i], x1[i], e, s);
        }
        self.limiting = norm.worst_index;
        sys.rhs(t + h, x1, f1).map_err(StepFailure::Model)?;
        stats.rhs_evaluations += 1;
        Ok(norm.value())
    }

    /// One ROS34PW2 step with the stored Jacobian (evaluated here only when none is valid).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn ros34pw2<S: OdeSystem + ?Sized>(
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
        if self.jac_age.is_none() {
            self.jacobian(sys, t, x, f0, h, s, stats)?;
        }
        // (I − γ h W) k = r  ⇔  (1/(γ h) I − W) k = r / (γ h).
        let gh = W_GAMMA * h;
        let iteration = IterationMatrix::factor(&self.jac, self.blocks.as_deref(), &[], gh);
        let mut fs = vec![0.0; n];
        let mut v = vec![0.0; n];
        let mut rhs = nalgebra::DVector::zeros(n);
        for i in 0..4 {
            // Stage point and f there.
            let alpha: f64 = W_A[i].iter().sum();
            if i == 0 {
                fs.copy_from_slice(f0);
            } else {
                for (m, (tm, xm)) in self.tmp.iter_mut().zip(x).enumerate() {
                    *tm = xm + (0..i).map(|j| W_A[i][j] * self.k[j][m]).sum::<f64>();
                }
                sys.rhs(t + alpha * h, &self.tmp, &mut fs)
                    .map_err(StepFailure::Model)?;
                stats.rhs_evaluations += 1;
            }
            // r = h f + h W Σ_j γ_ij k_j + γ_i h² f_t, γ_i = γ + Σ_j γ_ij.
            for (m, vm) in v.iter_mut().enumerate() {
                *vm = (0..i).map(|j| W_G[i][j] * self.k[j][m]).sum::<f64>();
            }
            let gamma_i = W_GAMMA + W_G[i].iter().sum::<f64>();
            let wv = iteration.w_times(&self.jac, &v);
            for m in 0..n {
                rhs[m] = (h * (fs[m] + wv[m]) + gamma_i * h * h * self.ft[m]) / gh;
            }
            let k = iteration.solve(&rhs).ok_or(StepFailure::Singular)?;
            self.k[i].copy_from_slice(k.as_slice());
        }
        let mut norm = ErrorNorm::default();
        for m in 0..n {
            x1[m] = x[m] + (0..4).map(|j| W_B[j] * self.k[j][m]).sum::<f64>();
            let e: f64 = (0..4).map(|j| (W_B[j] - W_BHAT[j]) * self.k[j][m]).sum();
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
}
