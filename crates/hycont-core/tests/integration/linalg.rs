//! Sparse LU: residuals of solves and the determinant's sign against a dense reference, on
//! seeded random matrices of several sizes, with the factorisation reused across value changes.

use crate::common;

use approx::assert_abs_diff_eq;
use common::Rng;
use hycont_core::linalg::{EliminationBlock, SparsePattern, eigenvalues};

/// A random sparse matrix: a random row permutation of a diagonally weighted matrix with a few
/// random off-diagonal entries per column (non-singular, determinant of either sign).
fn random_matrix(n: usize, rng: &mut Rng) -> (Vec<(usize, usize)>, Vec<f64>) {
    let mut perm: Vec<usize> = (0..n).collect();
    for i in (1..n).rev() {
        let j = (rng.next() * (i + 1) as f64) as usize;
        perm.swap(i, j.min(i));
    }
    let mut entries = Vec::new();
    let mut values = Vec::new();
    for (j, &row) in perm.iter().enumerate() {
        let sign = if rng.next() < 0.5 { -1.0 } else { 1.0 };
        entries.push((row, j));
        values.push(sign * (4.0 + rng.next()));
        for _ in 0..3 {
            let i = (rng.next() * n as f64) as usize % n;
            entries.push((i, j)); // duplicates allowed: summed
            values.push(rng.next() - 0.5);
        }
    }
    (entries, values)
}

fn dense(n: usize, entries: &[(usize, usize)], values: &[f64]) -> faer::Mat<f64> {
    let mut a = faer::Mat::<f64>::zeros(n, n);
    for (&(i, j), v) in entries.iter().zip(values) {
        a[(i, j)] += v;
    }
    a
}

#[test]
fn solves_have_small_residuals_and_the_determinant_sign_is_right() {
    let mut rng = Rng(0x5eed_1234_abcd_0042);
    for n in [1usize, 5, 40, 300, 1200] {
        let (entries, values) = random_matrix(n, &mut rng);
        let mut pattern = SparsePattern::new(n, n, &entries).unwrap();
        // Two different value sets on the same pattern: the symbolic analysis is reused.
        for round in 0..2 {
            let vals: Vec<f64> = values
                .iter()
                .map(|v| v * (1.0 + 0.1 * round as f64))
                .collect();
            pattern.factorize(&vals).unwrap();
            let a = dense(n, &entries, &vals);
            let b: Vec<f64> = (0..n).map(|_| rng.next() - 0.5).collect();
            let mut x = b.clone();
            pattern.solve_in_place(&mut x).unwrap();
            let mut worst: f64 = 0.0;
            for i in 0..n {
                let ax: f64 = (0..n).map(|j| a[(i, j)] * x[j]).sum();
                worst = worst.max((ax - b[i]).abs());
            }
            assert!(
                worst < 1e-12 * (n as f64).sqrt().max(1.0),
                "n = {n}: residual {worst:e}"
            );
            let det = a.determinant();
            assert_eq!(
                pattern.determinant_sign().unwrap(),
                det.signum(),
                "n = {n}, det {det:e}"
            );
        }
    }
}

/// Filled patterns (a quarter of the places and more, as the last reduced system of a large
/// system's collocation: factorised densely up to 2048 unknowns) and one just below a quarter
/// (factorised sparsely) give solves and transposed solves with roundoff residuals and the
/// determinant of the dense reference, with the factorisation reused for new values.
#[test]
fn filled_patterns_solve_as_sparse_ones() {
    let mut rng = Rng(0xf111_ed00);
    for (n, fill) in [
        (49usize, 0.3),
        (64, 0.6),
        (200, 0.25),
        (200, 0.2),
        (300, 1.0),
    ] {
        let mut entries = Vec::new();
        for j in 0..n {
            for i in 0..n {
                if i == j || rng.next() < fill {
                    entries.push((i, j));
                }
            }
        }
        let mut pattern = SparsePattern::new(n, n, &entries).unwrap();
        for round in 0..2 {
            let values: Vec<f64> = entries
                .iter()
                .map(|&(i, j)| {
                    // Diagonally dominant (off-diagonal rows sum below 1/2), the determinant
                    // of either sign and of moderate size.
                    let v = rng.next() - 0.5;
                    if i == j {
                        v.signum() * (1.0 + 0.1 * round as f64)
                    } else {
                        v / n as f64
                    }
                })
                .collect();
            pattern.factorize(&values).unwrap();
            let a = dense(n, &entries, &values);
            let b: Vec<f64> = (0..n).map(|_| rng.next() - 0.5).collect();
            for transpose in [false, true] {
                let mut x = b.clone();
                if transpose {
                    pattern.solve_transpose_in_place(&mut x).unwrap();
                } else {
                    pattern.solve_in_place(&mut x).unwrap();
                }
                for i in 0..n {
                    let ax: f64 = (0..n)
                        .map(|j| if transpose { a[(j, i)] } else { a[(i, j)] } * x[j])
                        .sum();
                    assert_abs_diff_eq!(ax, b[i], epsilon = 1e-13 * n as f64);
                }
            }
            let det = a.determinant();
            let (sign, log) = pattern.determinant().unwrap();
            assert_eq!(sign, det.signum(), "n = {n}, fill {fill}");
            assert_abs_diff_eq!(log, det.abs().ln(), epsilon = 1e-10 * log.abs().max(1.0));
        }
        // An index out of range is refused however filled the pattern.
        let mut bad = entries.clone();
        bad.push((n, 0));
        assert!(
            SparsePattern::new(n, n, &bad).is_err(),
            "n = {n}, fill {fill}"
        );
    }
}

#[test]
fn several_right_hand_sides_at_once() {
    let mut rng = Rng(7);
    let n = 60;
    let (entries, values) = random_matrix(n, &mut rng);
    let mut pattern = SparsePattern::new(n, n, &entries).unwrap();
    pattern.factorize(&values).unwrap();
    let a = dense(n, &entries, &values);
    let k = 3;
    let b: Vec<f64> = (0..n * k).map(|_| rng.next()).collect();
    let mut x = b.clone();
    pattern.solve_many_in_place(&mut x, k).unwrap();
    for c in 0..k {
        for i in 0..n {
            let ax: f64 = (0..n).map(|j| a[(i, j)] * x[j + c * n]).sum();
            assert_abs_diff_eq!(ax, b[i + c * n], epsilon = 1e-12);
        }
    }
}

#[test]
fn transposed_solves_use_the_same_factorisation() {
    let mut rng = Rng(11);
    for n in [1usize, 7, 150] {
        let (entries, values) = random_matrix(n, &mut rng);
        let mut pattern = SparsePattern::new(n, n, &entries).unwrap();
        pattern.factorize(&values).unwrap();
        let a = dense(n, &entries, &values);
        let b: Vec<f64> = (0..n).map(|_| rng.next() - 0.5).collect();
        let mut x = b.clone();
        pattern.solve_transpose_in_place(&mut x).unwrap();
        // A^T x = b, column i of A dotted with x.
        for i in 0..n {
            let atx: f64 = (0..n).map(|j| a[(j, i)] * x[j]).sum();
            assert_abs_diff_eq!(atx, b[i], epsilon = 1e-12);
        }
    }
}

#[test]
fn singular_and_unfactorised_matrices_are_errors() {
    let mut pattern = SparsePattern::new(2, 2, &[(0, 0), (1, 0)]).unwrap();
    assert!(
        pattern.solve_in_place(&mut [1.0, 1.0]).is_err(),
        "nothing factorised yet"
    );
    // Structurally singular (an empty column).
    let res = pattern
        .factorize(&[1.0, 1.0])
        .and_then(|()| pattern.solve_in_place(&mut [1.0, 2.0]));
    assert!(res.is_err());
    assert!(SparsePattern::new(2, 2, &[(2, 0)]).is_err());
}

#[test]
fn eigenvalues_of_a_rotation_scaling() {
    // [[a, -b], [b, a]] has eigenvalues a +- i b.
    let ev = eigenvalues(2, &[0.6, 0.8, -0.8, 0.6]).unwrap();
    for (re, im) in ev {
        assert!((re - 0.6).abs() < 1e-14 && (im.abs() - 0.8).abs() < 1e-14);
    }
}

/// Condensation needs a square matrix: a 3 x 2 pattern with an elimination block is refused by
/// both constructors (borrowing and taking the entries), naming the setting; the same entries
/// without blocks make a valid (rectangular) pattern.
#[test]
fn non_square_patterns_with_blocks_are_refused() {
    let entries = vec![(0, 0), (1, 0), (1, 1), (2, 1)];
    let block = || {
        vec![EliminationBlock {
            rows: vec![0, 1],
            cols: vec![0],
        }]
    };
    let err = SparsePattern::with_blocks(3, 2, &entries, &block()).unwrap_err();
    assert!(err.to_string().contains("square"), "{err}");
    let err = SparsePattern::with_blocks_owned(3, 2, entries.clone(), &block()).unwrap_err();
    assert!(err.to_string().contains("square"), "{err}");
    let plain = SparsePattern::with_blocks_owned(3, 2, entries, &[]).unwrap();
    assert_eq!((plain.nrows(), plain.ncols(), plain.len()), (3, 2, 4));
}
