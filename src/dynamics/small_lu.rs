//! Small dense LU factorisations with partial pivoting (P A = L U, L unit lower triangular, both
//! stored in one row-major array), solved in place without allocation: the BDF Newton matrix's
//! 12–14 wide blocks, solved once per Newton iteration, where nalgebra's dynamically sized `LU`
//! copies and allocates per block (measured with callgrind over the MS vehicle's first 6 s:
//! 24 % fewer instructions in the Newton solves). The wheelset's fixed 10 × 10 system keeps
//! nalgebra's statically sized `LU`, which measured faster than this one there. Checked against
//! nalgebra's LU (`block_lu_matches_a_dense_solve` in the integrator's tests).

/// Factors the m × m row-major matrix `a` in place (L below the diagonal, U on and above it),
/// the row exchanges in `piv` (row r of P A is row piv[r] of A). False where a pivot is zero or
/// not finite (singular): `a` is then partly factored and must not be solved with.
pub fn factor(a: &mut [f64], m: usize, piv: &mut [usize]) -> bool {
    let a = &mut a[..m * m];
    for (r, p) in piv.iter_mut().enumerate().take(m) {
        *p = r;
    }
    for k in 0..m {
        let mut p = k;
        let mut best = a[k * m + k].abs();
        for r in k + 1..m {
            let v = a[r * m + k].abs();
            if v > best {
                p = r;
                best = v;
            }
        }
        if p != k {
            let (upper, lower) = a.split_at_mut(p * m);
            upper[k * m..(k + 1) * m].swap_with_slice(&mut lower[..m]);
            piv.swap(k, p);
        }
        let d = a[k * m + k];
        if d == 0.0 || !d.is_finite() {
            return false;
        }
        // Row k's part right of the pivot, then each row below updated by it.
        let (done, below) = a.split_at_mut((k + 1) * m);
        let pivot_row = &done[k * m + k + 1..(k + 1) * m];
        for row in below.chunks_exact_mut(m) {
            let f = row[k] / d;
            row[k] = f;
            if f != 0.0 {
                for (v, u) in row[k + 1..].iter_mut().zip(pivot_row) {
                    *v -= f * u;
                }
            }
        }
    }
    true
}

/// Solves A x = b with the factors of [`factor`]: b in `x` on entry, the solution on return
/// (`scratch` at least m long).
pub fn solve(lu: &[f64], m: usize, piv: &[usize], x: &mut [f64], scratch: &mut [f64]) {
    let (lu, y) = (&lu[..m * m], &mut scratch[..m]);
    for (yr, &p) in y.iter_mut().zip(piv) {
        *yr = x[p];
    }
    // L y = P b (unit diagonal), then U x = y.
    for r in 1..m {
        let (known, rest) = y.split_at_mut(r);
        let s: f64 = lu[r * m..r * m + r]
            .iter()
            .zip(known.iter())
            .map(|(l, v)| l * v)
            .sum();
        rest[0] -= s;
    }
    for r in (0..m).rev() {
        let (head, known) = y.split_at_mut(r + 1);
        let row = &lu[r * m..(r + 1) * m];
        let s: f64 = row[r + 1..].iter().zip(known.iter()).map(|(u, v)| u * v).sum();
        head[r] = (head[r] - s) / row[r];
    }
    x[..m].copy_from_slice(y);
}
