//! [`super::dense::eliminate_above`] for large blocks by faer's blocked, vectorised kernels:
//! the LU with partial pivoting of the first `c` columns (a recursive blocked factorisation),
//! then the row order, a unit lower triangular solve and one matrix product for the other
//! columns. Large systems' collocation blocks (`ncol n` rows: 400 for a 100-state system)
//! cost $O(m c w)$ either way; the hand-written column-by-column loop reaches a fraction of
//! the machine's speed at that size, faer's kernels most of it.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::factor::{lu_in_place, lu_in_place_scratch};
use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::solve_unit_lower_triangular_in_place;
use faer::{Accum, MatMut, Par};

/// Smallest row count eliminated by [`eliminate_blocked`] (below it the hand-written kernels
/// are faster: measured on the impact chain's blocks, `benches/impact_chain.rs`).
pub(crate) const BLOCKED_FROM: usize = 64;

/// The contract of [`super::dense::eliminate_above`] (the same factors, row order and Schur
/// complement up to rounding; the same pivots chosen in exact arithmetic), by faer. A pivot
/// not larger than `tiny` or not finite gives `None`, with `a` eliminated throughout.
pub(crate) fn eliminate_blocked(
    a: &mut [f64],
    (m, c, w): (usize, usize, usize),
    perm: &mut [usize],
    pivots: &mut [f64],
    tiny: f64,
) -> Option<f64> {
    let mat = MatMut::from_column_major_slice_mut(&mut a[..m * w], m, w);
    let (mut panel, mut rest) = mat.split_at_col_mut(c);
    let mut perm_inv = vec![0usize; m];
    let params = faer::Spec::default();
    let mut buf = MemBuffer::new(lu_in_place_scratch::<usize, f64>(m, c, Par::Seq, params));
    let (info, _) = lu_in_place(
        panel.as_mut(),
        &mut perm[..m],
        &mut perm_inv,
        Par::Seq,
        MemStack::new(&mut buf),
        params,
    );
    for (k, p) in pivots[..c].iter_mut().enumerate() {
        *p = panel[(k, k)];
        if !(p.abs() > tiny && p.is_finite()) {
            return None;
        }
    }
    // The other columns in the pivots' row order.
    let mut column = vec![0.0; m];
    for j in 0..w - c {
        for (t, &r) in column.iter_mut().zip(perm.iter()) {
            *t = rest[(r, j)];
        }
        for (i, &t) in column.iter().enumerate() {
            rest[(i, j)] = t;
        }
    }
    let (l11, l21) = panel.as_ref().split_at_row(c);
    let (mut top, bottom) = rest.split_at_row_mut(c);
    solve_unit_lower_triangular_in_place(l11, top.as_mut(), Par::Seq);
    matmul(bottom, Accum::Add, l21, top.as_ref(), -1.0, Par::Seq);
    Some(if info.transposition_count % 2 == 0 {
        1.0
    } else {
        -1.0
    })
}

#[cfg(test)]
mod tests {
    use super::eliminate_blocked;
    use crate::linalg::dense::eliminate_above;
    use proptest::prelude::*;

    proptest! {
        /// On random blocks of the sizes large systems give, faer's elimination and the
        /// hand-written one agree: the same row order and sign, pivots, factors and Schur
        /// complement to roundoff (1e-12 relative to the block's entries, of order 1).
        #[test]
        fn blocked_elimination_matches_the_hand_written_one(
            values in proptest::collection::vec(-1.0f64..1.0, 70 * 90),
            c in 1usize..=70,
        ) {
            let (m, w) = (70, 90);
            let c = c.min(m);
            let (mut blocked, mut plain) = (values.clone(), values.clone());
            let (mut perm_b, mut perm_p) = (vec![0; m], vec![0; m]);
            let (mut piv_b, mut piv_p) = (vec![0.0; c], vec![0.0; c]);
            let sb = eliminate_blocked(&mut blocked, (m, c, w), &mut perm_b, &mut piv_b, 0.0);
            let sp = eliminate_above(&mut plain, (m, c, w), &mut perm_p, &mut piv_p, 0.0);
            prop_assert_eq!(sb, sp);
            prop_assert_eq!(&perm_b, &perm_p);
            for (x, y) in piv_b.iter().zip(&piv_p).chain(blocked.iter().zip(&plain)) {
                prop_assert!((x - y).abs() <= 1e-12 * (1.0 + y.abs()), "{} vs {}", x, y);
            }
        }
    }

    /// A panel with a zero column is refused (`None`), as the hand-written kernel refuses it.
    #[test]
    fn a_singular_panel_is_refused() {
        let (m, c, w) = (66, 3, 5);
        let mut a: Vec<f64> = (0..m * w).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
        for v in &mut a[m..2 * m] {
            *v = 0.0;
        }
        let (mut perm, mut piv) = (vec![0; m], vec![0.0; c]);
        assert_eq!(
            eliminate_blocked(&mut a, (m, c, w), &mut perm, &mut piv, 0.0),
            None
        );
    }
}
