//! One step of the variable-order BDF ([`Method::Bdf`]) on the integrator's state: the Newton
//! iteration on the corrector with a kept, block-factored matrix, the Jacobian's renewal, and
//! the bookkeeping of an accepted step. The BDF's own formulas are in [`super::bdf`].

use super::*;

impl Stepper {
    /// BDF: the step to (t1, x1) was accepted with error norm `err`.
    pub(super) fn bdf_accepted(&mut self, t1: f64, x1: &[f64], err: f64, h: f64, s: &Settings) {
        self.bdf.accepted(t1, x1, err, h, s.bdf_max_order, |d| {
            let mut norm = ErrorNorm::default();
            for (v, xi) in d.iter().zip(x1) {
                norm.add(*xi, *xi, *v, s);
            }
            norm.value()
        });
    }

    /// One BDF step of size h from the newest accepted point (t, x) ([`bdf`]): x1, f1 (the
    /// derivative of the BDF polynomial at t + h, which equals f there to the Newton tolerance)
    /// and the error norm. A Newton iteration that does not converge in [`NEWTON_MAX`] iterations
    /// renews a Jacobian that is not fresh and tries again; with a fresh one it fails the step
    /// (infinite error norm: the integrator retries shorter).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn bdf_step<S: OdeSystem + ?Sized>(
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
        if self.bdf.history.front().is_none_or(|p| p.0 != t) {
            self.bdf.restart();
            self.bdf.history.push_front((t, x.to_vec()));
        }
        let k = self.bdf.usable_order();
        let t1 = t + h;
        // Σ_{j≥1} α_j x_j: the corrector's known part.
        let mut known = vec![0.0; n];
        let (alpha0, with_f) = self.bdf.prepare(t1, x, f0, h, k, &mut known);
        // The Jacobian's differences need f(t, x) itself: f0 is the BDF polynomial's derivative,
        // equal to f only to the Newton tolerance, which divided by a difference's 1e-10 would
        // swamp the columns.
        let mut fx = Vec::new();
        if self.jac_age.is_none() {
            self.bdf_jacobian(sys, t, x, &mut fx, h, s, stats)?;
        }
        let mut rhs = nalgebra::DVector::zeros(n);
        // With reusable blocks: the last correction, the last f and which blocks are quiet.
        let reusing = !self.reusable.is_empty();
        let mut last_delta = vec![0.0; if reusing { n } else { 0 }];
        let mut f_last = vec![0.0; if reusing { n } else { 0 }];
        let mut quiet = vec![false; self.reusable.len()];
        let converged = loop {
            // The matrix α_M I − J factored for an α_M within 20 % of α₀ serves (CVODE's rule),
            // its corrections scaled by 2 α_M / (α_M + α₀): exact for stiff components (1) and
            // between 1 and α_M/α₀ (exact for non-stiff ones).
            let alpha_m = match &self.newton_matrix {
                Some((_, a)) if (alpha0 / a - 1.0).abs() <= 0.2 => *a,
                _ => {
                    let m = IterationMatrix::factor(
                        &self.jac,
                        self.newton_blocks.as_deref(),
                        &self.newton_kinematic,
                        1.0 / alpha0,
                    );
                    self.newton_matrix = Some((m, alpha0));
                    alpha0
                }
            };
            let scale = 2.0 * alpha_m / (alpha_m + alpha0);
            let Some((iteration, _)) = &self.newton_matrix else {
                unreachable!("factored above")
            };
            x1.copy_from_slice(&self.bdf.predicted);
            let mut previous = f64::INFINITY;
            let mut converged = false;
            for iter in 0..NEWTON_MAX {
                // After the first iteration, the reusable blocks whose last correction was small
                // are carried forward by their Jacobian block ([`Settings::newton_reuse`]).
                let quiet_count = if iter > 0 {
                    self.mark_quiet(x1, &last_delta, s, &mut quiet)
                } else {
                    0
                };
                if quiet_count > 0 {
                    f_last.copy_from_slice(f1);
                    sys.rhs_reusing(t1, x1, f1, &quiet).map_err(StepFailure::Model)?;
                    for (&(o, size), _) in self.reusable.iter().zip(&quiet).filter(|(_, &q)| q) {
                        // Its block of the Jacobian: the Newton matrix evaluates no other.
                        for r in o..o + size {
                            let row = o..o + size;
                            f1[r] = f_last[r] + row.map(|c| self.jac[(r, c)] * last_delta[c]).sum::<f64>();
                        }
                    }
                    stats.reused_blocks += quiet_count;
                } else {
                    sys.rhs(t1, x1, f1).map_err(StepFailure::Model)?;
                }
                stats.rhs_evaluations += 1;
                for m in 0..n {
                    rhs[m] = f1[m] - alpha0 * x1[m] - known[m];
                }
                let delta = iteration.solve(&rhs).ok_or(StepFailure::Singular)?;
                let mut norm = ErrorNorm::default();
                for m in 0..n {
                    let dm = scale * delta[m];
                    x1[m] += dm;
                    if reusing {
                        last_delta[m] = dm;
                    }
                    norm.add(x1[m], x1[m], dm, s);
                }
                let d = norm.value();
                if !d.is_finite() {
                    break;
                }
                // Converged when the remaining error (a geometric tail at the contraction rate) is
                // small against the tolerance the error estimate is held to. A first correction
                // is judged at the rate the last steps observed with this Jacobian (CVODE's
                // carried rate; 0.5 after a new one).
                let rate = if previous.is_finite() {
                    let r = d / previous;
                    self.bdf.newton_rate = r;
                    r
                } else {
                    self.bdf.newton_rate.max(0.05)
                };
                if rate >= 0.9 && previous.is_finite() {
                    break;
                }
                let tol = s.newton_tolerance;
                if d <= 0.1 * tol || (rate < 0.9 && d * rate / (1.0 - rate) <= tol) {
                    converged = true;
                    break;
                }
                previous = d;
            }
            if converged || self.jac_age == Some(0) {
                break converged;
            }
            self.bdf_jacobian(sys, t, x, &mut fx, h, s, stats)?;
        };
        self.bdf.newton_failed = !converged;
        if !converged {
            return Ok(f64::INFINITY);
        }
        let mut norm = ErrorNorm::default();
        let c = bdf::milne(k, with_f);
        for m in 0..n {
            f1[m] = alpha0 * x1[m] + known[m];
            norm.add(x[m], x1[m], c * (x1[m] - self.bdf.predicted[m]), s);
        }
        self.limiting = norm.worst_index;
        Ok(norm.value())
    }

    /// Marks in `quiet` the reusable blocks whose every correction term |δᵢ| / (atol + rtol |xᵢ|)
    /// is at most [`Settings::newton_reuse`] × the Newton tolerance; returns how many (0 without
    /// reusable blocks).
    fn mark_quiet(&self, x1: &[f64], delta: &[f64], s: &Settings, quiet: &mut [bool]) -> usize {
        let limit = s.newton_reuse * s.newton_tolerance;
        let mut count = 0;
        for (q, &(o, size)) in quiet.iter_mut().zip(&self.reusable) {
            *q = (o..o + size).all(|i| delta[i].abs() <= limit * (s.atol + s.rtol * x1[i].abs()));
            count += usize::from(*q);
        }
        count
    }

    /// The BDF's Jacobian at (t, x), with f(t, x) evaluated into `fx` (once per step).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn bdf_jacobian<S: OdeSystem + ?Sized>(
        &mut self,
        sys: &mut S,
        t: f64,
        x: &[f64],
        fx: &mut Vec<f64>,
        h: f64,
        s: &Settings,
        stats: &mut Stats,
    ) -> Result<(), StepFailure<S::Error>> {
        if fx.is_empty() {
            fx.resize(x.len(), 0.0);
            sys.rhs(t, x, fx).map_err(StepFailure::Model)?;
            stats.rhs_evaluations += 1;
        }
        self.jacobian(sys, t, x, fx, h, s, stats)
    }
}
