//! Small dense products (issue: library): the n x n product the monodromy composition does per
//! segment ($M \leftarrow S_k \Phi_k M$), at the rocking block's n = 4, by the column-major
//! loop the library used before, nalgebra's dynamic `DMatrix` and its fixed-size `Matrix4`. Run with
//! `cargo bench -p hycont-core --bench dense`.

use criterion::{Criterion, criterion_group, criterion_main};
use hycont_core::nalgebra::{DMatrix, Matrix4};
use std::hint::black_box;

/// The loop of `orbit/floquet.rs` (column-major, skipping zero entries of `b`).
fn matmul(n: usize, a: &[f64], b: &[f64]) -> Vec<f64> {
    let mut c = vec![0.0; n * n];
    for j in 0..n {
        for l in 0..n {
            let blj = b[l + j * n];
            if blj != 0.0 {
                for i in 0..n {
                    c[i + j * n] += a[i + l * n] * blj;
                }
            }
        }
    }
    c
}

fn products(c: &mut Criterion) {
    let n = 4;
    let a: Vec<f64> = (0..n * n).map(|i| (i as f64 * 0.37).sin()).collect();
    let b: Vec<f64> = (0..n * n).map(|i| (i as f64 * 0.73).cos()).collect();
    let m: Vec<f64> = (0..n * n).map(|i| (i as f64 * 0.11).sin()).collect();
    let mut g = c.benchmark_group("dense_4x4_two_products");
    g.bench_function("loop", |bn| {
        bn.iter(|| black_box(matmul(n, &matmul(n, black_box(&a), &b), &m)));
    });
    let (da, db, dm) = (
        DMatrix::from_column_slice(n, n, &a),
        DMatrix::from_column_slice(n, n, &b),
        DMatrix::from_column_slice(n, n, &m),
    );
    g.bench_function("nalgebra_dmatrix", |bn| {
        bn.iter(|| black_box(&(black_box(&da) * &db) * &dm));
    });
    let (fa, fb, fm) = (
        Matrix4::from_column_slice(&a),
        Matrix4::from_column_slice(&b),
        Matrix4::from_column_slice(&m),
    );
    g.bench_function("nalgebra_matrix4", |bn| {
        bn.iter(|| black_box(black_box(fa) * fb * fm));
    });
    g.finish();
}

criterion_group!(benches, products);
criterion_main!(benches);
