//! The wheelset's 10×10 system of accelerations and normal-force reactions (Eq. 53, see
//! [`super::wheelset`]) solved by its structure instead of a pivoted dense LU.
//!
//! Unknowns u = [ẍ ÿ z̈ φ̈ ψ̈ Ω̇_l λ_l λ_r d̈ Ω̇_r]. The system is a saddle point
//!
//! ```text
//! ⎡ A_aa  A_ac ⎤ ⎡ u_a ⎤   ⎡ b_a ⎤      a = {0 1 2 3 4 5 8 9}: the accelerations,
//! ⎣ A_ca  A_cc ⎦ ⎣ u_c ⎦ = ⎣ b_c ⎦      c = {6 7}: the normal forces λ (a lifted wheel: its θ̈),
//! ```
//!
//! whose acceleration block A_aa is triangular in the order Ω̇_l, Ω̇_r, d̈, ẍ, ÿ, z̈, φ̈, ψ̈: the
//! masses and inertias on its diagonal, the spin's gyroscopic couplings I_y a_x, I_y a_z in the
//! φ̈ and ψ̈ rows, and a solid axle's tie Ω̇_r − Ω̇_l = 0. With W = A_aa⁻¹ A_ac (8×2) and the 2×2
//! Schur complement S = A_cc − A_ca W, made once per evaluation,
//!
//! u_c = S⁻¹ (b_c − A_ca A_aa⁻¹ b_a),   u_a = A_aa⁻¹ b_a − W u_c,
//!
//! about 100 multiplications for each right-hand side of the creep/normal-force iteration
//! against a 10×10 LU and its substitutions (~4 000 instructions per evaluation, 14 % of the MS
//! vehicle's right-hand side). Not in the paper, which does not say how Eq. 53 is solved; the
//! result is the same solution up to round-off (tested against the dense LU).
//!
//! Should a matrix not have this structure (an entry above the order's diagonal, a zero pivot)
//! or S be singular, the solve falls back to the dense LU of the whole matrix.

use nalgebra::{SMatrix, SVector, LU};

/// The accelerations in the order in which A_aa is lower triangular.
const ORDER: [usize; 8] = [5, 9, 8, 0, 1, 2, 3, 4];
/// The normal forces (or a lifted wheel's θ̈).
const REACTIONS: [usize; 2] = [6, 7];

type Matrix10 = SMatrix<f64, 10, 10>;
type Vector10 = SVector<f64, 10>;

/// The system factored for any number of right-hand sides.
pub(crate) enum Reactions {
    /// By its structure: the matrix, W = A_aa⁻¹ A_ac (rows in [`ORDER`]) and S⁻¹.
    Structured {
        a: Matrix10,
        w: [[f64; 2]; 8],
        s_inv: [[f64; 2]; 2],
    },
    /// A dense LU (a matrix without the structure).
    Dense(LU<f64, nalgebra::Const<10>, nalgebra::Const<10>>),
}

impl Reactions {
    /// Factors `a`.
    pub(crate) fn new(a: Matrix10) -> Reactions {
        Self::structured(&a).unwrap_or_else(|| Reactions::Dense(a.lu()))
    }

    fn structured(a: &Matrix10) -> Option<Reactions> {
        // Lower triangular in ORDER, nonzero pivots.
        for (k, &r) in ORDER.iter().enumerate() {
            if a[(r, r)] == 0.0 || !a[(r, r)].is_finite() {
                return None;
            }
            if ORDER[k + 1..].iter().any(|&c| a[(r, c)] != 0.0) {
                return None;
            }
        }
        let mut w = [[0.0; 2]; 8];
        for (q, &c) in REACTIONS.iter().enumerate() {
            let col = solve_aa(a, |r| a[(r, c)]);
            for k in 0..8 {
                w[k][q] = col[k];
            }
        }
        let mut s = [[0.0; 2]; 2];
        for (p, &r) in REACTIONS.iter().enumerate() {
            for (q, &c) in REACTIONS.iter().enumerate() {
                s[p][q] = a[(r, c)] - (0..8).map(|k| a[(r, ORDER[k])] * w[k][q]).sum::<f64>();
            }
        }
        let det = s[0][0] * s[1][1] - s[0][1] * s[1][0];
        let scale = (s[0][0].abs() + s[0][1].abs()) * (s[1][0].abs() + s[1][1].abs());
        if !(det.is_finite() && det.abs() > 1e-13 * scale) {
            return None;
        }
        let s_inv = [[s[1][1] / det, -s[0][1] / det], [-s[1][0] / det, s[0][0] / det]];
        Some(Reactions::Structured { a: *a, w, s_inv })
    }

    /// u with A u = b; `None` where the matrix is singular.
    pub(crate) fn solve(&self, b: &Vector10) -> Option<Vector10> {
        match self {
            Reactions::Dense(lu) => lu.solve(b),
            Reactions::Structured { a, w, s_inv } => {
                let y = solve_aa(a, |r| b[r]);
                let mut rc = [0.0; 2];
                for (p, &r) in REACTIONS.iter().enumerate() {
                    rc[p] = b[r] - (0..8).map(|k| a[(r, ORDER[k])] * y[k]).sum::<f64>();
                }
                let uc = [
                    s_inv[0][0] * rc[0] + s_inv[0][1] * rc[1],
                    s_inv[1][0] * rc[0] + s_inv[1][1] * rc[1],
                ];
                let mut u = Vector10::zeros();
                for (k, &r) in ORDER.iter().enumerate() {
                    u[r] = y[k] - w[k][0] * uc[0] - w[k][1] * uc[1];
                }
                u[REACTIONS[0]] = uc[0];
                u[REACTIONS[1]] = uc[1];
                Some(u)
            }
        }
    }
}

/// A_aa⁻¹ r by forward substitution in [`ORDER`]; the result indexed as ORDER.
fn solve_aa(a: &Matrix10, r: impl Fn(usize) -> f64) -> [f64; 8] {
    let mut y = [0.0; 8];
    for (k, &row) in ORDER.iter().enumerate() {
        let mut v = r(row);
        for j in 0..k {
            v -= a[(row, ORDER[j])] * y[j];
        }
        y[k] = v / a[(row, row)];
    }
    y
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A matrix of the wheelset's pattern with pseudo-random entries: `irw` (own spin rows), a
    /// flexible track (row/column 8), a lifted wheel (its λ column a θ̈ column).
    fn wheelset_like(seed: u64, irw: bool, track: bool, lifted: Option<usize>) -> Matrix10 {
        let mut state = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let mut rnd = move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        };
        let mut a = Matrix10::zeros();
        let m = 1000.0 * (1.5 + rnd());
        for k in 0..3 {
            a[(k, k)] = m;
        }
        a[(3, 3)] = 700.0 * (1.5 + rnd());
        a[(4, 4)] = 700.0 * (1.5 + rnd());
        let spin = 100.0 * (1.5 + rnd());
        let (ax, az) = (0.01 * rnd(), 0.01 * rnd());
        a[(3, 5)] = spin * ax;
        a[(4, 5)] = spin * az;
        a[(5, 5)] = spin;
        for i in 0..2 {
            for k in 0..5 {
                a[(k, 6 + i)] = rnd();
            }
        }
        if irw {
            a[(3, 9)] = spin * ax;
            a[(4, 9)] = spin * az;
            a[(9, 9)] = spin;
            a[(5, 6)] = 0.5 * rnd();
            a[(9, 7)] = 0.5 * rnd();
        } else {
            a[(5, 6)] = 0.5 * rnd();
            a[(5, 7)] = 0.5 * rnd();
            a[(9, 9)] = 1.0;
            a[(9, 5)] = -1.0;
        }
        a[(8, 8)] = 1.0;
        a[(6, 2)] = 1.0;
        a[(6, 1)] = 0.1 * rnd();
        a[(7, 3)] = 1.0;
        a[(7, 1)] = 0.1 * rnd();
        if track {
            a[(8, 8)] = 500.0 * (1.5 + rnd());
            a[(8, 6)] = rnd();
            a[(8, 7)] = rnd();
            a[(6, 8)] = -a[(6, 1)];
            a[(7, 8)] = -a[(7, 1)];
        }
        if let Some(side) = lifted {
            let c = 6 + side;
            for r in 0..10 {
                a[(r, c)] = 0.0;
            }
            a[(6, c)] = -0.3 * (1.5 + rnd());
            a[(7, c)] = -(1.5 + rnd());
        }
        a
    }

    /// The structured solve against the dense LU of the same matrix, every variant of the
    /// wheelset's matrix, random right-hand sides: the same solution to round-off (the difference
    /// within the condition number times a few ε), and a backward error of a few ε.
    #[test]
    fn the_structured_solve_is_the_dense_solution() {
        let (mut worst_diff, mut worst_res): (f64, f64) = (0.0, 0.0);
        let mut cases = 0;
        for seed in 0..200u64 {
            for irw in [false, true] {
                for track in [false, true] {
                    for lifted in [None, Some(0), Some(1)] {
                        let a = wheelset_like(seed, irw, track, lifted);
                        let r = Reactions::new(a);
                        assert!(
                            matches!(r, Reactions::Structured { .. }),
                            "the wheelset's pattern falls back to the dense LU (irw {irw}, track {track}, lifted {lifted:?})"
                        );
                        let b =
                            Vector10::from_fn(|k, _| ((seed as f64 + 1.0) * (k as f64 + 0.37)).sin() * 1e4);
                        let u = r.solve(&b).expect("the structured solve of a regular system");
                        let d = a.lu().solve(&b).expect("the dense solve of a regular system");
                        // The difference in units of the LU's own round-off: relative to the
                        // solution, over the condition number (1-norm estimate from the inverse).
                        let cond = a.abs().column_sum().max()
                            * a.try_inverse()
                                .expect("a regular system")
                                .abs()
                                .column_sum()
                                .max();
                        worst_diff = worst_diff.max((u - d).amax() / d.amax() / cond);
                        // The residual relative to |A| |u| + |b| (backward error).
                        let scale = (a.abs() * u.abs()).amax() + b.amax();
                        worst_res = worst_res.max((a * u - b).amax() / scale);
                        cases += 1;
                    }
                }
            }
        }
        println!(
            "{cases} systems: largest difference to the dense LU {worst_diff:.2e} × the condition number, backward error {worst_res:.2e}"
        );
        assert!(
            worst_diff < f64::EPSILON && worst_res < 1e-15,
            "{worst_diff:e} {worst_res:e}"
        );
    }

    /// A matrix without the structure (an entry above the order's diagonal) is solved by the
    /// dense LU, correctly; a singular one is reported as such.
    #[test]
    fn a_matrix_without_the_structure_falls_back_to_the_dense_lu() {
        let mut a = wheelset_like(7, false, false, None);
        a[(0, 4)] = 3.0; // ẍ row reading ψ̈, which comes after it in ORDER
        let r = Reactions::new(a);
        assert!(matches!(r, Reactions::Dense(_)));
        let b = Vector10::from_fn(|k, _| k as f64 + 1.0);
        let u = r.solve(&b).expect("the dense fallback of a regular system");
        assert!((a * u - b).amax() < 1e-9 * b.amax());
        // Both normal-force columns zero and no lift: singular.
        let mut s = wheelset_like(7, false, false, None);
        for r in 0..10 {
            s[(r, 6)] = 0.0;
            s[(r, 7)] = 0.0;
        }
        assert!(Reactions::new(s).solve(&b).is_none());
    }
}
