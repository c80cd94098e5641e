//! Small dense kernels on column-major storage, without allocation: Gaussian elimination with
//! partial pivoting of some columns of a tall block (condensation), and triangular solves with
//! its factors.

/// Dot product.
#[inline(always)]
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Runs `f` compiled for the widest vector instructions this processor has (AVX2 on x86-64
/// when present, detected at run time; the baseline otherwise): the small dense kernels'
/// loops vectorise over 4 lanes instead of 2 (used by the eliminations here, the condensed
/// sweeps and collocation's evaluation). `f` and what it calls must be inlined into it
/// (`#[inline(always)]`) to be compiled so. Floating-point operations are not contracted or
/// reordered on either path, so the numbers are the same.
#[inline(always)]
pub(crate) fn vectorized<R>(f: impl FnOnce() -> R) -> R {
    struct Run<F>(F);
    impl<R, F: FnOnce() -> R> pulp::WithSimd for Run<F> {
        type Output = R;
        #[inline(always)]
        fn with_simd<S: pulp::Simd>(self, _: S) -> R {
            (self.0)()
        }
    }
    pulp::Arch::new().dispatch(Run(f))
}

/// Gaussian elimination with partial pivoting of the first `c` columns of the column-major
/// `m x w` matrix `a` (`c <= m`, `c <= w`), applied to all `w` columns: afterwards rows `0..c`
/// hold $U$ (columns `0..c`) and $L^{-1} P$ applied to the other columns, the multipliers of
/// $L$ sit below the diagonal of columns `0..c`, and rows `c..m` of columns `c..w` hold the
/// Schur complement. `perm` receives the row order (row `i` of the result is row `perm[i]` of
/// the input), `pivots` the `c` pivots.
///
/// Returns the sign of the row order `perm` (counted from the row swaps), or `None` if a pivot
/// is not larger than `m` units of roundoff of the largest entry of the first `c` columns (the
/// columns are numerically dependent); `a` is then partly eliminated.
pub(crate) fn eliminate(
    a: &mut [f64],
    (m, c, w): (usize, usize, usize),
    perm: &mut [usize],
    pivots: &mut [f64],
) -> Option<f64> {
    let tiny = smallest_pivot(a, (m, c));
    eliminate_above(a, (m, c, w), perm, pivots, tiny)
}

/// The smallest pivot [`eliminate`] accepts: `m` units of roundoff of the largest entry of
/// the first `c` columns of the column-major `a` (`m` rows).
#[inline(always)]
fn smallest_pivot(a: &[f64], (m, c): (usize, usize)) -> f64 {
    super::max_norm(&a[..c * m]) * f64::EPSILON * m as f64
}

/// [`eliminate`] with the smallest acceptable pivot magnitude given: `0` refuses only zero
/// (and non-finite) pivots, as a plain LU.
pub(crate) fn eliminate_above(
    a: &mut [f64],
    (m, c, w): (usize, usize, usize),
    perm: &mut [usize],
    pivots: &mut [f64],
    tiny: f64,
) -> Option<f64> {
    vectorized(
        #[inline(always)]
        || eliminate_dispatched(a, (m, c, w), perm, pivots, tiny),
    )
}

/// [`eliminate_above`]'s body, by row count (inlined into [`vectorized`]'s context with
/// every kernel it calls).
#[inline(always)]
fn eliminate_dispatched(
    a: &mut [f64],
    (m, c, w): (usize, usize, usize),
    perm: &mut [usize],
    pivots: &mut [f64],
    tiny: f64,
) -> Option<f64> {
    match m {
        4 => eliminate_rows::<4>(a, (c, w), perm, pivots, tiny),
        8 => eliminate_rows::<8>(a, (c, w), perm, pivots, tiny),
        12 => eliminate_rows::<12>(a, (c, w), perm, pivots, tiny),
        16 => eliminate_rows::<16>(a, (c, w), perm, pivots, tiny),
        20 => eliminate_rows::<20>(a, (c, w), perm, pivots, tiny),
        24 => eliminate_rows::<24>(a, (c, w), perm, pivots, tiny),
        _ if m >= super::dense_blocked::BLOCKED_FROM => {
            super::dense_blocked::eliminate_blocked(a, (m, c, w), perm, pivots, tiny)
        }
        _ => eliminate_any(a, (m, c, w), perm, pivots, tiny),
    }
}

/// [`eliminate`] with the row count `M` (a multiple of 4) known at compile time: each column
/// update runs over the 4-row chunks from the one holding row `k + 1` down, in loops the
/// compiler unrolls, with the multipliers padded by zeros above the pivot (`x - 0 a = x`: the
/// same numbers as [`eliminate_any`] for finite entries).
#[inline(always)]
fn eliminate_rows<const M: usize>(
    a: &mut [f64],
    (c, w): (usize, usize),
    perm: &mut [usize],
    pivots: &mut [f64],
    tiny: f64,
) -> Option<f64> {
    pivoted_steps(
        a,
        (M, c, w),
        perm,
        pivots,
        tiny,
        #[inline(always)]
        |a, k, inv| match (k + 1) / 4 {
            0 => step_from::<M, 0>(a, k, w, inv),
            1 => step_from::<M, 4>(a, k, w, inv),
            2 => step_from::<M, 8>(a, k, w, inv),
            3 => step_from::<M, 12>(a, k, w, inv),
            4 => step_from::<M, 16>(a, k, w, inv),
            5 => step_from::<M, 20>(a, k, w, inv),
            _ => {} // k + 1 >= 24 >= M: no rows below the pivot.
        },
    )
}

/// Step `k` on the 4-row chunks from `S` (the one holding row `k + 1`) down: the multipliers
/// (column `k` below the pivot times `inv`, stored in place) and the update of the columns to
/// the right. The multipliers are formed whole chunks at a time, zeros at and above row `k`,
/// so that the update reads each chunk as it was written. (Written from row `k + 1`, at any
/// place within a chunk, they made the update's whole-chunk reads wait for the writes to
/// reach the cache; forming them so made a collocation branch 2-3 % faster.)
#[inline(always)]
fn step_from<const M: usize, const S: usize>(a: &mut [f64], k: usize, w: usize, inv: f64) {
    if S >= M {
        return;
    }
    let mut l = [0.0; M];
    let col = &mut a[k * M..(k + 1) * M];
    for ((li, v), i) in l[S..].iter_mut().zip(&mut col[S..]).zip(S..) {
        let scaled = *v * inv;
        let below = i > k;
        *li = if below { scaled } else { 0.0 };
        *v = if below { scaled } else { *v };
    }
    update_from::<M, S>(a, k, w, &l);
}

/// The update of columns `k + 1..w` by pivot row `k` on rows `S..M` (multipliers `l`, zero
/// at and above row `k`): `S` known at compile time, so the loop is unrolled. (The same loop as
/// [`eliminate_any`]'s, kept apart: one helper for both, with the start and the multipliers as
/// slices, measured 3-7 % slower on a 16 x 22 block.)
#[inline(always)]
fn update_from<const M: usize, const S: usize>(a: &mut [f64], k: usize, w: usize, l: &[f64; M]) {
    if S >= M {
        return;
    }
    for col in a[(k + 1) * M..w * M].chunks_exact_mut(M) {
        let akj = col[k];
        if akj != 0.0 {
            for (x, li) in col[S..].iter_mut().zip(&l[S..]) {
                *x -= li * akj;
            }
        }
    }
}

/// [`eliminate`] without the run-time vector dispatch or the row-count kernels, inlined where
/// it is called: for blocks so small (a few rows, sizes known at compile time there) that the
/// dispatch would cost more than the arithmetic. The same numbers as [`eliminate`] (a zero's
/// sign aside, see [`eliminate_rows`]).
#[inline(always)]
pub(crate) fn eliminate_inline(
    a: &mut [f64],
    (m, c, w): (usize, usize, usize),
    perm: &mut [usize],
    pivots: &mut [f64],
) -> Option<f64> {
    let tiny = smallest_pivot(a, (m, c));
    eliminate_any(a, (m, c, w), perm, pivots, tiny)
}

/// [`eliminate`] for any row count.
#[inline(always)]
fn eliminate_any(
    a: &mut [f64],
    (m, c, w): (usize, usize, usize),
    perm: &mut [usize],
    pivots: &mut [f64],
    tiny: f64,
) -> Option<f64> {
    pivoted_steps(
        a,
        (m, c, w),
        perm,
        pivots,
        tiny,
        #[inline(always)]
        |a, k, inv| {
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
        },
    )
}

/// The elimination's outer loop: for each of the first `c` columns, partial pivoting (the row
/// with the largest entry at or below the diagonal swapped into place, in all `w` columns and
/// `perm`), then `step(a, k, 1 / pivot)`, which forms the multipliers and updates the columns
/// to the right. The sign of `perm`, or `None` at a pivot not larger than `tiny` in magnitude
/// or not finite.
#[inline(always)]
fn pivoted_steps(
    a: &mut [f64],
    (m, c, w): (usize, usize, usize),
    perm: &mut [usize],
    pivots: &mut [f64],
    tiny: f64,
    mut step: impl FnMut(&mut [f64], usize, f64),
) -> Option<f64> {
    for (i, p) in perm.iter_mut().enumerate() {
        *p = i;
    }
    let mut sign = 1.0;
    for k in 0..c {
        // The first row with the largest magnitude at or below the diagonal: the largest
        // magnitude (in independent lanes, without branches), then where it is first. NaNs are
        // passed over as by a scan with `>`, except on the diagonal itself, which refuses.
        let col = &a[k * m + k..(k + 1) * m];
        let largest = super::max_norm(col);
        let p = k + col.iter().position(|v| v.abs() == largest).unwrap_or(0);
        let piv = if col[0].is_nan() {
            col[0]
        } else {
            a[k * m + p]
        };
        if !(piv.abs() > tiny && piv.is_finite()) {
            return None;
        }
        if p != k {
            sign = -sign;
            perm.swap(p, k);
            for col in a[..w * m].chunks_exact_mut(m) {
                col.swap(k, p);
            }
        }
        pivots[k] = piv;
        step(a, k, 1.0 / piv);
    }
    Some(sign)
}

/// Solves $U^\top y = g$ in place (`u` column-major with leading dimension `m`, `c x c` upper
/// triangle used; `inv` the reciprocals of its diagonal: a multiplication instead of a
/// division on the substitution's critical path).
pub(crate) fn solve_upper_transpose(u: &[f64], m: usize, inv: &[f64], y: &mut [f64]) {
    for k in 0..y.len() {
        let col = &u[k * m..k * m + k];
        y[k] = (y[k] - dot(col, &y[..k])) * inv[k];
    }
}

/// Solves $U x = t$ in place (as [`solve_upper_transpose`]).
pub(crate) fn solve_upper(u: &[f64], m: usize, inv: &[f64], t: &mut [f64]) {
    for k in (0..t.len()).rev() {
        let xk = t[k] * inv[k];
        t[k] = xk;
        if xk != 0.0 {
            for (ti, ui) in t[..k].iter_mut().zip(&u[k * m..k * m + k]) {
                *ti -= ui * xk;
            }
        }
    }
}

/// `inv[k] = 1 / pivots[k]`.
pub(crate) fn reciprocals(pivots: &[f64], inv: &mut [f64]) {
    for (i, p) in inv.iter_mut().zip(pivots) {
        *i = 1.0 / p;
    }
}

#[cfg(test)]
mod tests {
    use super::{
        eliminate_above, eliminate_any, eliminate_dispatched, eliminate_rows, reciprocals,
        solve_upper,
    };
    use proptest::prelude::*;

    /// Gaussian elimination with partial pivoting as a textbook states it, entry by entry: at
    /// step `k` the pivot is the first row at or below `k` whose entry in column `k` has the
    /// largest magnitude; rows are swapped across all `w` columns, the multipliers
    /// $a_{ik} / a_{kk}$ (as a product with the pivot's reciprocal) stored in place, and
    /// $a_{ij} \mathrel{-}= l_i a_{kj}$ for every row below and column to the right.
    fn textbook(a: &mut [f64], (m, c, w): (usize, usize, usize)) -> (Vec<usize>, Vec<f64>) {
        let mut perm: Vec<usize> = (0..m).collect();
        let mut pivots = Vec::new();
        for k in 0..c {
            let mut p = k;
            for i in k + 1..m {
                if a[i + k * m].abs() > a[p + k * m].abs() {
                    p = i;
                }
            }
            perm.swap(k, p);
            for j in 0..w {
                a.swap(k + j * m, p + j * m);
            }
            let inv = 1.0 / a[k + k * m];
            pivots.push(a[k + k * m]);
            for i in k + 1..m {
                a[i + k * m] *= inv;
                for j in k + 1..w {
                    a[i + j * m] -= a[i + k * m] * a[k + j * m];
                }
            }
        }
        (perm, pivots)
    }

    proptest! {
        /// Both kernels choose the textbook's pivots, in the textbook's order, among entries
        /// with many ties of magnitude (small integers of both signs, zeros among them), and
        /// give its numbers exactly, as `vectorized` runs them (with AVX2 where
        /// the processor has it: the wider vectors change no number).
        #[test]
        fn kernels_pivot_as_the_textbook(
            values in proptest::collection::vec(-3i32..=3, 16 * 22),
            c in 1usize..=12,
        ) {
            let w = 22;
            // 16 rows: the kernel for a row count known at compile time; the block's first 15
            // rows: the general one.
            for m in [16, 15] {
                let mut a: Vec<f64> = values
                    .chunks_exact(16)
                    .flat_map(|col| col[..m].iter().map(|&v| f64::from(v)))
                    .collect();
                let mut reference = a.clone();
                let (perm_r, piv_r) = textbook(&mut reference, (m, c, w));
                if piv_r.contains(&0.0) {
                    continue; // singular: refused (see `fixed_row_count_kernel_matches_the_general_one`)
                }
                let (mut perm, mut piv) = (vec![0; m], vec![0.0; c]);
                let ok = eliminate_above(&mut a, (m, c, w), &mut perm, &mut piv, 0.0);
                prop_assert!(ok.is_some());
                prop_assert_eq!(&perm, &perm_r);
                prop_assert_eq!(&piv, &piv_r);
                prop_assert_eq!(&a, &reference);
            }
        }
    }

    proptest! {
        /// The elimination as run (inside `vectorized`: with AVX2 on a processor that
        /// has it) and the same code compiled for the baseline instruction set (called here
        /// directly) give the same pivots, row order and factors to the bit, for every row
        /// count kernel and the general one, on blocks with many zeros: wider vectors change
        /// no number (no contraction into fused multiply-adds, no reordering).
        #[test]
        fn vector_width_changes_no_number(
            values in proptest::collection::vec(-1.0f64..1.0, 24 * 30),
            zeros in proptest::collection::vec(proptest::bool::weighted(0.4), 24 * 30),
            m in prop_oneof![Just(4usize), Just(8), Just(16), Just(24), Just(15), Just(7)],
            c_frac in 0.0f64..1.0,
        ) {
            let w = 30;
            let c = 1 + ((m - 1) as f64 * c_frac) as usize;
            let block: Vec<f64> = values[..m * w]
                .iter()
                .zip(&zeros)
                .map(|(&v, &z)| if z { 0.0 } else { v })
                .collect();
            let (mut wide, mut base) = (block.clone(), block);
            let (mut perm_w, mut perm_b) = (vec![0; m], vec![0; m]);
            let (mut piv_w, mut piv_b) = (vec![0.0; c], vec![0.0; c]);
            let ok_w = eliminate_above(&mut wide, (m, c, w), &mut perm_w, &mut piv_w, 0.0);
            let ok_b = eliminate_dispatched(&mut base, (m, c, w), &mut perm_b, &mut piv_b, 0.0);
            prop_assert_eq!(ok_w, ok_b);
            prop_assert_eq!(perm_w, perm_b);
            prop_assert_eq!(
                piv_w.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
                piv_b.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
            );
            prop_assert_eq!(
                wide.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
                base.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
            );
        }
    }

    /// A NaN on the diagonal at a step refuses the block, as a zero or infinite pivot does; a
    /// NaN below it is passed over by the pivot search (the scan's `>` is false for it).
    #[test]
    fn a_nan_pivot_is_refused() {
        for m in [4usize, 5] {
            let mut a = vec![0.0; m * m];
            for i in 0..m {
                a[i + i * m] = 1.0 + i as f64;
            }
            let (mut perm, mut piv) = (vec![0; m], vec![0.0; m]);
            let mut nan_diag = a.clone();
            nan_diag[0] = f64::NAN;
            nan_diag[1] = 5.0; // larger than the rest of column 0
            assert_eq!(
                eliminate_above(&mut nan_diag, (m, 1, m), &mut perm, &mut piv, 0.0),
                None
            );
            let mut nan_below = a.clone();
            nan_below[2] = f64::NAN;
            nan_below[1] = 5.0;
            assert!(eliminate_above(&mut nan_below, (m, 1, m), &mut perm, &mut piv, 0.0).is_some());
            assert_eq!((perm[0], piv[0]), (1, 5.0));
        }
    }

    proptest! {
        /// The kernel for a row count known at compile time gives the general kernel's numbers
        /// exactly (same pivots, row order, factors and Schur complement), on blocks with many
        /// zero entries too (as collocation blocks have), and the factors
        /// reproduce the block: with $x$ from $U x = (L^{-1} P a_c)_{0..c}$, the pivot rows'
        /// equations $A[P_i, :c]\, x = a_c[P_i]$ hold to roundoff.
        #[test]
        fn fixed_row_count_kernel_matches_the_general_one(
            values in proptest::collection::vec(-1.0f64..1.0, 16 * 22),
            zeros in proptest::collection::vec(proptest::bool::weighted(0.4), 16 * 22),
            c in 1usize..=12,
        ) {
            // Sparse as collocation blocks are: the kernels skip updates by zero entries.
            let values: Vec<f64> = values
                .iter()
                .zip(&zeros)
                .map(|(&v, &z)| if z { 0.0 } else { v })
                .collect();
            let (m, w) = (16, 22);
            let mut fixed = values.clone();
            let mut any = values.clone();
            let (mut perm_f, mut perm_a) = (vec![0; m], vec![0; m]);
            let (mut piv_f, mut piv_a) = (vec![0.0; c], vec![0.0; c]);
            let scale = values[..c * m].iter().fold(0.0f64, |s, v| s.max(v.abs()));
            let tiny = scale * f64::EPSILON * m as f64;
            let ok_f = eliminate_rows::<16>(&mut fixed, (c, w), &mut perm_f, &mut piv_f, tiny);
            let ok_a = eliminate_any(&mut any, (m, c, w), &mut perm_a, &mut piv_a, tiny);
            prop_assert_eq!(ok_f, ok_a);
            if let Some(sign) = ok_f {
                prop_assert_eq!(sign, crate::linalg::permutation_sign(&perm_f));
            }
            prop_assert_eq!(&perm_f, &perm_a);
            prop_assert_eq!(&piv_f, &piv_a);
            prop_assert_eq!(&fixed, &any);
            if ok_f.is_some() {
                let mut x: Vec<f64> = (0..c).map(|i| fixed[i + c * m]).collect();
                let mut inv = vec![0.0; c];
                reciprocals(&piv_f, &mut inv);
                solve_upper(&fixed, m, &inv, &mut x);
                // Backward error: roundoff times the size of the terms.
                let size = 1.0 + x.iter().fold(0.0f64, |s, v| s.max(v.abs()));
                for &r in &perm_f[..c] {
                    let ax: f64 = (0..c).map(|j| values[r + j * m] * x[j]).sum();
                    let b = values[r + c * m];
                    prop_assert!((ax - b).abs() <= 1e-13 * size * c as f64, "{} vs {}", ax, b);
                }
            }
        }
    }
}
