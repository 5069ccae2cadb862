//! The factored iteration matrix (1/(γh)) I − J of the implicit methods' Newton iterations:
//! dense, or by diagonal blocks (each an LU) and kinematic blocks (closed form). Real for the BDF
//! and the Rosenbrock methods; complex for Radau IIA's pair of complex eigenvalues
//! (1/(γh) = (α + iβ)/h, [`super::radau`]).

use nalgebra::{ComplexField, DMatrix, DVector};

/// The iteration matrix (1/(γh)) I − W, factored: dense, or block by block where W is
/// restricted to diagonal blocks (outside them it is 1/(γh) I). `T`: f64, or
/// `nalgebra::Complex<f64>` for a complex 1/(γh).
pub(super) enum IterationMatrix<T: ComplexField<RealField = f64> + Copy = f64> {
    Dense(nalgebra::LU<T, nalgebra::Dyn, nalgebra::Dyn>),
    Blocks {
        blocks: Vec<(usize, usize)>,
        lus: Vec<nalgebra::LU<T, nalgebra::Dyn, nalgebra::Dyn>>,
        /// Blocks whose Jacobian is only the exact q̇ = v coupling (a body outside the
        /// finite-difference blocks): solved in closed form, nothing to factor.
        kinematic: Vec<(usize, usize)>,
        gh: T,
    },
}

impl<T: ComplexField<RealField = f64> + Copy> IterationMatrix<T> {
    /// (1/(γh)) I − J factored: dense, or by its diagonal `blocks` (each an LU) and its
    /// `kinematic` blocks (closed form) with the identity elsewhere.
    pub(super) fn factor(
        jac: &DMatrix<f64>,
        blocks: Option<&[(usize, usize)]>,
        kinematic: &[(usize, usize)],
        gh: T,
    ) -> IterationMatrix<T> {
        match blocks {
            None => {
                let mut g = (-jac.clone()).map(T::from_real);
                for i in 0..g.nrows() {
                    g[(i, i)] += T::one() / gh;
                }
                IterationMatrix::Dense(g.lu())
            }
            Some(blocks) => IterationMatrix::Blocks {
                blocks: blocks.to_vec(),
                lus: blocks
                    .iter()
                    .map(|&(o, m)| {
                        let mut g = (-jac.view((o, o), (m, m)).into_owned()).map(T::from_real);
                        for i in 0..m {
                            g[(i, i)] += T::one() / gh;
                        }
                        g.lu()
                    })
                    .collect(),
                kinematic: kinematic.to_vec(),
                gh,
            },
        }
    }

    pub(super) fn solve(&self, rhs: &DVector<T>) -> Option<DVector<T>> {
        match self {
            IterationMatrix::Dense(lu) => lu.solve(rhs),
            IterationMatrix::Blocks {
                blocks,
                lus,
                kinematic,
                gh,
            } => {
                // Outside the blocks: (1/(γh)) k = r.
                // Each block solved in place (nalgebra's `solve` is a copy and this; the copies
                // and allocations of 14 blocks per Newton iteration measured ~25 % of its cost).
                let mut k = rhs * *gh;
                for (&(o, m), lu) in blocks.iter().zip(lus) {
                    let mut part = k.rows_mut(o, m);
                    part.copy_from(&rhs.rows(o, m));
                    if !lu.solve_mut(&mut part) {
                        return None;
                    }
                }
                // A kinematic block [c I, −I; 0, c I] (c = 1/(γh)): v = r_v / c, then
                // q = (r_q + v) / c — the operations its LU (no pivoting: L = I) would do, in
                // its order, so the result is the LU's bit for bit.
                let c = T::one() / *gh;
                for &(o, m) in kinematic {
                    let half = m / 2;
                    for i in 0..half {
                        let v = rhs[o + half + i] / c;
                        k[o + half + i] = v;
                        k[o + i] = (rhs[o + i] + v) / c;
                    }
                }
                Some(k)
            }
        }
    }
}

impl IterationMatrix<f64> {
    /// W v.
    pub(super) fn w_times(&self, jac: &DMatrix<f64>, v: &[f64]) -> Vec<f64> {
        let n = v.len();
        match self {
            IterationMatrix::Dense(_) => (0..n).map(|m| (0..n).map(|c| jac[(m, c)] * v[c]).sum()).collect(),
            IterationMatrix::Blocks {
                blocks, kinematic, ..
            } => {
                let mut out = vec![0.0; n];
                for &(o, m) in blocks.iter().chain(kinematic) {
                    for r in 0..m {
                        out[o + r] = (0..m).map(|c| jac[(o + r, o + c)] * v[o + c]).sum();
                    }
                }
                out
            }
        }
    }
}
