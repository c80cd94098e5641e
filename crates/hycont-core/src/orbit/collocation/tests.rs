//! Unit tests of the collocation part's block layout and column writers.

use super::{NodeColumns, group_of_node, node_of_group};

/// The block's column groups list every node once: interior nodes first, then the first
/// and the last node.
#[test]
fn node_groups_are_a_permutation_with_interior_nodes_first() {
    for ncol in 1..=7 {
        let order: Vec<usize> = (0..=ncol).map(|g| node_of_group(g, ncol)).collect();
        let mut want: Vec<usize> = (1..ncol).collect();
        want.extend([0, ncol]);
        assert_eq!(order, want);
        for (g, &node) in order.iter().enumerate() {
            assert_eq!(group_of_node(node, ncol), g);
        }
    }
}

/// The kernel with the state dimension known at compile time writes the general kernel's
/// numbers, into the same places, and nothing else.
fn same_columns<const N: usize>() {
    let ncol = 3;
    let rows = ncol * N;
    let a: Vec<f64> = (0..N * N).map(|i| (i as f64 * 0.37).sin()).collect();
    let l = [0.1, -0.4, 0.9, 0.4];
    let dl = [-2.0, 1.5, 0.25, 0.25];
    let len = rows * (ncol + 1) * N;
    let (mut fixed, mut any) = (vec![f64::NAN; len], vec![f64::NAN; len]);
    for (block, generic) in [(&mut fixed, false), (&mut any, true)] {
        let cols = NodeColumns {
            block,
            rows,
            at: N,
            a: &a,
            l: &l,
            dl: &dl,
            ht: -0.3,
        };
        if generic {
            cols.write_any(N);
        } else {
            cols.write::<N>();
        }
    }
    let same = |x: f64, y: f64| x == y || (x.is_nan() && y.is_nan());
    assert!(fixed.iter().zip(&any).all(|(x, y)| same(*x, *y)), "N = {N}");
    // Only the point's rows (N..2N of each column) are written.
    for (i, x) in fixed.iter().enumerate() {
        assert_eq!(
            x.is_nan(),
            !(N..2 * N).contains(&(i % rows)),
            "N = {N}, {i}"
        );
    }
}

#[test]
fn fixed_size_node_columns_match_the_general_kernel() {
    same_columns::<1>();
    same_columns::<2>();
    same_columns::<3>();
    same_columns::<4>();
    same_columns::<5>();
    same_columns::<6>();
}
