//! The Jacobian ∂f/∂x for the implicit methods: the system's own, or forward differences —
//! column by column, or block by block where the system declares independent diagonal blocks
//! (one pass of evaluations per group of blocks, each evaluation computing only the rows the
//! blocks read: [`OdeSystem::rhs_rows`]).

use super::*;

impl Stepper {
    /// J = ∂f/∂x (the system's, else forward differences: n evaluations) and f_t = ∂f/∂t (a
    /// forward difference: one evaluation) at (t, x), f0 = f(t, x).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn jacobian<S: OdeSystem + ?Sized>(
        &mut self,
        sys: &mut S,
        t: f64,
        x: &[f64],
        f0: &[f64],
        h: f64,
        s: &Settings,
        stats: &mut Stats,
    ) -> Result<(), StepFailure<S::Error>> {
        let n = x.len();
        let analytic = if self.blocks.is_some() {
            None
        } else {
            sys.jacobian(t, x, &mut self.jac)
        };
        match analytic {
            Some(r) => r.map_err(StepFailure::Model)?,
            None if self.blocks.is_some() => {
                // One pass of evaluations per group: the blocks of a group are perturbed together.
                let groups = std::mem::take(&mut self.groups);
                let result = groups
                    .iter()
                    .try_for_each(|blocks| self.block_columns(sys, t, x, f0, blocks, s, stats));
                self.groups = groups;
                result?;
            }
            None => {
                for j in 0..n {
                    if sys.inactive(x, j) {
                        for i in 0..n {
                            self.jac[(i, j)] = 0.0;
                        }
                        continue;
                    }
                    let dx = 1.5e-8 * x[j].abs().max(s.atol / s.rtol).max(1e-12);
                    self.tmp.copy_from_slice(x);
                    self.tmp[j] += dx;
                    let col = &mut self.k[6];
                    sys.rhs(t, &self.tmp, col).map_err(StepFailure::Model)?;
                    stats.rhs_evaluations += 1;
                    for i in 0..n {
                        self.jac[(i, j)] = (col[i] - f0[i]) / dx;
                    }
                }
            }
        }
        // ∂f/∂t by a forward difference (the Rosenbrock methods' γ_i h f_t terms; zero for
        // autonomous systems). The BDF and Radau do not use it.
        if matches!(self.method, Method::Ros3 | Method::Ros34pw2) {
            let dt = 1.5e-8 * t.abs().max(h).max(1e-6);
            sys.rhs(t + dt, x, &mut self.ft).map_err(StepFailure::Model)?;
            stats.rhs_evaluations += 1;
            for (ft, f) in self.ft.iter_mut().zip(f0) {
                *ft = (*ft - f) / dt;
            }
        }
        stats.jacobians += 1;
        self.jac_age = Some(0);
        self.newton_matrix = None;
        self.bdf.newton_rate = 0.5;
        Ok(())
    }

    /// The finite-difference columns of `blocks` (perturbed together: no block's rows depend on
    /// another's states) at (t, x), f0 = f(t, x): as many evaluations as the widest block.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn block_columns<S: OdeSystem + ?Sized>(
        &mut self,
        sys: &mut S,
        t: f64,
        x: &[f64],
        f0: &[f64],
        blocks: &[(usize, usize)],
        s: &Settings,
        stats: &mut Stats,
    ) -> Result<(), StepFailure<S::Error>> {
        let widest = blocks.iter().map(|b| b.1).max().unwrap_or(0);
        let mut dxs = vec![0.0; blocks.len()];
        for c in 0..widest {
            self.tmp.copy_from_slice(x);
            let mut any = false;
            for (b, &(o, m)) in blocks.iter().enumerate() {
                dxs[b] = 0.0;
                if c < m && !sys.inactive(x, o + c) {
                    let j = o + c;
                    dxs[b] = 1.5e-8 * x[j].abs().max(s.atol / s.rtol).max(1e-12);
                    self.tmp[j] += dxs[b];
                    any = true;
                }
            }
            // Nothing perturbed (every block's column idle): the columns are zero.
            let col = &mut self.k[6];
            if any {
                sys.rhs_rows(t, &self.tmp, col, blocks)
                    .map_err(StepFailure::Model)?;
                stats.rhs_evaluations += 1;
            }
            for (b, &(o, m)) in blocks.iter().enumerate() {
                if c < m {
                    for i in 0..m {
                        self.jac[(o + i, o + c)] = if dxs[b] > 0.0 {
                            (col[o + i] - f0[o + i]) / dxs[b]
                        } else {
                            0.0
                        };
                    }
                }
            }
        }
        Ok(())
    }
}
