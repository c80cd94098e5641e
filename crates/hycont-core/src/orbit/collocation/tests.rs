//! Unit tests of the collocation part's block layout, column writers and interpolation kernels,
//! and of its evaluation compiled for wider vectors.

use super::columns::{NodeColumns, group_of_node, interpolate, interpolate_any, node_of_group};
use crate::system::{Direction, EventAction, EventId, EventSpec, HybridModel, Mode, Scalar};

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

/// The polynomial and its derivative at the collocation points reproduce a polynomial of the
/// basis' degree from its values at the nodes: component `i` of the nodes samples
/// $q_i(s) = \sum_{k \le \mathrm{ncol}} (i + 1)^{-k} s^k$ at $s = j / \mathrm{ncol}$, and the
/// interpolant of degree ncol through those values is $q_i$ itself, so
/// $\xi_i = q_i(z_c)$ and $d_i = q_i'(z_c)$ exactly but for roundoff. The kernel for a state
/// dimension known at compile time gives the general kernel's numbers bit for bit (the same
/// sums in the same order).
fn interpolates_polynomials<const N: usize>() {
    for ncol in 1..=7 {
        let basis = super::Basis::new(ncol);
        let z = super::gauss_legendre_points(ncol);
        let q = |i: usize, s: f64| -> (f64, f64) {
            let r = 1.0 / (i + 1) as f64;
            let value = (0..=ncol).map(|k| (r * s).powi(k as i32)).sum();
            let slope = (1..=ncol)
                .map(|k| k as f64 * r * (r * s).powi(k as i32 - 1))
                .sum();
            (value, slope)
        };
        let nodes: Vec<f64> = (0..=ncol)
            .flat_map(|j| (0..N).map(move |i| (j, i)))
            .map(|(j, i)| q(i, j as f64 / ncol as f64).0)
            .collect();
        for c in 0..ncol {
            let lc = (&basis.l[c][..], &basis.dl[c][..]);
            let (mut xi, mut d) = ([0.0; N], [0.0; N]);
            let (mut xi_any, mut d_any) = ([0.0; N], [0.0; N]);
            interpolate::<N>(&nodes, lc, &mut xi, &mut d);
            interpolate_any(&nodes, lc, &mut xi_any, &mut d_any);
            assert_eq!((xi, d), (xi_any, d_any), "N = {N}, ncol = {ncol}");
            for i in 0..N {
                let (value, slope) = q(i, z[c]);
                approx::assert_abs_diff_eq!(xi[i], value, epsilon = 1e-12);
                approx::assert_abs_diff_eq!(d[i], slope, epsilon = 1e-10);
            }
        }
    }
}

#[test]
fn interpolation_at_the_collocation_points_reproduces_polynomials() {
    interpolates_polynomials::<1>();
    interpolates_polynomials::<3>();
    interpolates_polynomials::<4>();
    interpolates_polynomials::<6>();
}

/// A forced oscillator against a stop, four states: $\dot x_0 = x_1$,
/// $\dot x_1 = -p_0 \sin x_0 - p_1 x_1 + p_2 x_2$, and a forcing oscillator
/// $(x_2, x_3)$ at frequency $p_3$ on its unit circle; an impact at $x_0 = 0$.
struct ForcedStop;

impl HybridModel for ForcedStop {
    fn state_dim(&self) -> usize {
        4
    }
    fn parameter_names(&self) -> &[&'static str] {
        &["k", "c", "a", "w"]
    }
    fn mode_count(&self) -> usize {
        1
    }
    fn mode_name(&self, _: Mode) -> &'static str {
        "flight"
    }
    fn events(&self, _: Mode) -> &[EventId] {
        &[EventId(0)]
    }
    fn event_spec(&self, _: EventId) -> EventSpec {
        EventSpec {
            name: "impact",
            direction: Direction::Falling,
            action: EventAction::Jump { to: Mode(0) },
        }
    }
    fn vector_field<T: Scalar>(&self, _: Mode, x: &[T], p: &[T], f: &mut [T]) {
        let rho2 = x[2] * x[2] + x[3] * x[3];
        f[0] = x[1];
        f[1] = -p[0] * x[0].sin() - p[1] * x[1] + p[2] * x[2];
        f[2] = x[2] + p[3] * x[3] - x[2] * rho2;
        f[3] = x[3] - p[3] * x[2] - x[3] * rho2;
    }
    fn event<T: Scalar>(&self, _: EventId, x: &[T], _: &[T]) -> T {
        x[0]
    }
}

/// The collocation equations and their Jacobian as evaluated (inside
/// `linalg::dense::vectorized`: with AVX2 on a processor that has it) equal, to the bit, the
/// same code compiled for the baseline instruction set (called here directly), at any
/// unknowns on an uneven mesh: wider vectors change no number (no contraction into fused
/// multiply-adds, no reordering).
#[test]
fn vector_width_changes_no_collocation_number() {
    use crate::orbit::{SegmentEnd, SegmentSpec, Signature};
    use crate::problem::ZeroFunction;
    use crate::system::AutoDiff;
    let system = AutoDiff::new(ForcedStop);
    let segments = vec![SegmentSpec {
        mode: Mode(0),
        end: SegmentEnd::Event(EventId(0)),
    }];
    let signature = Signature::new(&system, segments).unwrap();
    let mesh = vec![0.0, 0.1, 0.35, 0.6, 0.8, 1.0];
    let mut coll = super::Collocation::new(&system, signature, vec![mesh], 4).unwrap();
    let u: Vec<f64> = (0..coll.unknowns())
        .map(|i| (i as f64 * 0.37).sin() + 0.1)
        .collect();
    let (m, len) = (coll.equations(), coll.jacobian_len());
    let (mut r_wide, mut j_wide) = (vec![0.0; m], vec![0.0; len]);
    coll.evaluate(&u, &mut r_wide, Some(&mut j_wide)).unwrap();
    let (mut r_base, mut j_base) = (vec![0.0; m], vec![0.0; len]);
    coll.evaluate_intervals(&u, &mut r_base, Some(&mut j_base))
        .unwrap();
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&r_wide), bits(&r_base));
    assert_eq!(bits(&j_wide), bits(&j_base));
    // The residual alone, too.
    coll.evaluate(&u, &mut r_wide, None).unwrap();
    assert_eq!(bits(&r_wide), bits(&r_base));
}
