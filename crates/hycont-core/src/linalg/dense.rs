//! Small dense kernels on column-major storage, without allocation: Gaussian elimination with
//! partial pivoting of some columns of a tall block (condensation), and triangular solves with
//! its factors.

/// Dot product.
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Gaussian elimination with partial pivoting of the first `c` columns of the column-major
/// `m x w` matrix `a` (`c <= m`, `c <= w`), applied to all `w` columns: afterwards rows `0..c`
/// hold $U$ (columns `0..c`) and $L^{-1} P$ applied to the other columns, the multipliers of
/// $L$ sit below the diagonal of columns `0..c`, and rows `c..m` of columns `c..w` hold the
/// Schur complement. `perm` receives the row order (row `i` of the result is row `perm[i]` of
/// the input), `pivots` the `c` pivots.
///
/// Returns `false` if a pivot is not larger than `m` units of roundoff of the largest entry of
/// the first `c` columns (the columns are numerically dependent); `a` is then partly eliminated.
pub(crate) fn eliminate(
    a: &mut [f64],
    (m, c, w): (usize, usize, usize),
    perm: &mut [usize],
    pivots: &mut [f64],
) -> bool {
    let scale = a[..c * m].iter().fold(0.0_f64, |s, v| s.max(v.abs()));
    let tiny = scale * f64::EPSILON * m as f64;
    for (i, p) in perm.iter_mut().enumerate() {
        *p = i;
    }
    for k in 0..c {
        let col = &a[k * m..(k + 1) * m];
        let mut p = k;
        for i in k + 1..m {
            if col[i].abs() > col[p].abs() {
                p = i;
            }
        }
        let piv = col[p];
        if !(piv.abs() > tiny && piv.is_finite()) {
            return false;
        }
        if p != k {
            perm.swap(p, k);
            for j in 0..w {
                a.swap(k + j * m, p + j * m);
            }
        }
        pivots[k] = piv;
        let inv = 1.0 / piv;
        for v in &mut a[k * m + k + 1..(k + 1) * m] {
            *v *= inv;
        }
        let (left, right) = a.split_at_mut((k + 1) * m);
        let lk = &left[k * m + k + 1..];
        for col in right.chunks_exact_mut(m) {
            let akj = col[k];
            if akj != 0.0 {
                for (x, l) in col[k + 1..].iter_mut().zip(lk) {
                    *x -= l * akj;
                }
            }
        }
    }
    true
}

/// Solves $U^\top y = g$ in place (`u` column-major with leading dimension `m`, `c x c` upper
/// triangle used).
pub(crate) fn solve_upper_transpose(u: &[f64], m: usize, y: &mut [f64]) {
    for k in 0..y.len() {
        let col = &u[k * m..k * m + k];
        y[k] = (y[k] - dot(col, &y[..k])) / u[k + k * m];
    }
}

/// Solves $U x = t$ in place (as [`solve_upper_transpose`]).
pub(crate) fn solve_upper(u: &[f64], m: usize, t: &mut [f64]) {
    for k in (0..t.len()).rev() {
        let xk = t[k] / u[k + k * m];
        t[k] = xk;
        if xk != 0.0 {
            for (ti, ui) in t[..k].iter_mut().zip(&u[k * m..k * m + k]) {
                *ti -= ui * xk;
            }
        }
    }
}
