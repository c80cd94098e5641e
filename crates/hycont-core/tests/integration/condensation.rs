//! LU with condensation of local unknowns ([`EliminationBlock`]) against a dense reference:
//! solves, transposed solves and several right-hand sides have small residuals, and the
//! determinant's sign and $\ln|\det|$ equal the dense LU's, on seeded random block-structured
//! matrices (blocks with more rows than unknowns, kept columns shared between blocks, border
//! rows that read every block's unknowns, singleton rows whose columns other rows read, rows and
//! columns shuffled so that blocks are not contiguous). A block that is singular on its own falls back to the whole matrix's LU; badly
//! declared blocks are refused.

use crate::common;

use common::Rng;
use hycont_core::linalg::{EliminationBlock, SparsePattern};

/// A random square matrix with `nb` elimination blocks (`c` unknowns, `c + s` rows, reading
/// `links` random kept columns) and `borders` free rows that read every unknown of a few
/// blocks; every third other free row has a single entry (its column is pinned), the rest read
/// random kept columns. Rows and columns are shuffled.
struct Case {
    n: usize,
    entries: Vec<(usize, usize)>,
    values: Vec<f64>,
    blocks: Vec<EliminationBlock>,
}

fn random_case(rng: &mut Rng, nb: usize, c: usize, s: usize, extra_free: usize) -> Case {
    let kept = nb * s + extra_free;
    let n = nb * c + kept;
    let (rows, cols) = (rng.shuffle(n), rng.shuffle(n));
    let mut entries = Vec::new();
    let mut blocks = Vec::new();
    let mut next_row = 0;
    for b in 0..nb {
        let bc: Vec<usize> = (b * c..(b + 1) * c).map(|j| cols[j]).collect();
        let br: Vec<usize> = (next_row..next_row + c + s).map(|i| rows[i]).collect();
        next_row += c + s;
        // s kept columns of its own (so that the matrix is structurally regular), 3 shared.
        let own = (extra_free + b * s..extra_free + (b + 1) * s).map(|k| cols[nb * c + k]);
        let shared: Vec<usize> = (0..3).map(|_| cols[nb * c + rng.below(kept)]).collect();
        let links: Vec<usize> = own.chain(shared).collect();
        for &r in &br {
            entries.extend(bc.iter().map(|&j| (r, j)));
            entries.extend(links.iter().map(|&j| (r, j)));
        }
        blocks.push(EliminationBlock { rows: br, cols: bc });
    }
    for (f, i) in (next_row..n).enumerate() {
        let r = rows[i];
        if f % 3 == 2 {
            // A singleton row (a held parameter): its column is pinned; the entry is given
            // twice (summed).
            entries.extend([(r, cols[nb * c + f]); 2]);
            continue;
        }
        // Every other free row reads a few kept columns; the first two also read whole blocks.
        entries.extend((0..4).map(|_| (r, cols[nb * c + rng.below(kept)])));
        entries.push((r, cols[nb * c + f]));
        if f < 2 {
            for b in (f..nb).step_by(2) {
                entries.extend(blocks[b].cols.iter().map(|&j| (r, j)));
            }
        }
    }
    let values = entries.iter().map(|_| 2.0 * rng.next() - 1.0).collect();
    Case {
        n,
        entries,
        values,
        blocks,
    }
}

fn dense(case: &Case, values: &[f64]) -> faer::Mat<f64> {
    let mut a = faer::Mat::<f64>::zeros(case.n, case.n);
    for (&(i, j), v) in case.entries.iter().zip(values) {
        a[(i, j)] += v;
    }
    a
}

/// Largest |A x - b| relative to |A|_inf |x|_inf + |b|_inf (a backward-error measure that a
/// stable solve keeps at a modest multiple of the unit roundoff).
fn backward_error(a: &faer::Mat<f64>, x: &[f64], b: &[f64], transpose: bool) -> f64 {
    let n = b.len();
    let at = |i: usize, j: usize| if transpose { a[(j, i)] } else { a[(i, j)] };
    let norm_a = (0..n)
        .map(|i| (0..n).map(|j| at(i, j).abs()).sum::<f64>())
        .fold(0.0, f64::max);
    let norm_x = x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let norm_b = b.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let worst = (0..n)
        .map(|i| ((0..n).map(|j| at(i, j) * x[j]).sum::<f64>() - b[i]).abs())
        .fold(0.0, f64::max);
    worst / (norm_a * norm_x + norm_b)
}

#[test]
fn condensed_solves_and_determinants_match_the_dense_lu() {
    let mut rng = Rng(0x00c0_11de_5eed_0001);
    for (nb, c, s, extra) in [(1, 1, 0, 1), (3, 2, 1, 3), (10, 6, 2, 6), (40, 12, 4, 9)] {
        let case = random_case(&mut rng, nb, c, s, extra);
        let mut condensed =
            SparsePattern::with_blocks(case.n, case.n, &case.entries, &case.blocks).unwrap();
        for round in 0..3 {
            let vals: Vec<f64> = case
                .values
                .iter()
                .map(|v| v * (1.0 + 0.3 * round as f64) + 0.01 * round as f64)
                .collect();
            let a = dense(&case, &vals);
            condensed.factorize(&vals).unwrap();
            for transpose in [false, true] {
                let b: Vec<f64> = (0..case.n).map(|_| rng.next() - 0.5).collect();
                let mut x = b.clone();
                if transpose {
                    condensed.solve_transpose_in_place(&mut x).unwrap();
                } else {
                    condensed.solve_in_place(&mut x).unwrap();
                }
                let err = backward_error(&a, &x, &b, transpose);
                assert!(
                    err < 1e-13,
                    "n = {}, transpose {transpose}: {err:e}",
                    case.n
                );
            }
            let k = 3;
            let b: Vec<f64> = (0..case.n * k).map(|_| rng.next()).collect();
            let mut x = b.clone();
            condensed.solve_many_in_place(&mut x, k).unwrap();
            for col in 0..k {
                let r = col * case.n..(col + 1) * case.n;
                assert!(backward_error(&a, &x[r.clone()], &b[r], false) < 1e-13);
            }
            // ln|det| and sign from the dense LU's pivots.
            let lu = a.partial_piv_lu();
            let u = lu.U();
            let log_abs: f64 = (0..case.n).map(|i| u[(i, i)].abs().ln()).sum();
            let det = a.determinant();
            let (sign, log) = condensed.determinant().unwrap();
            assert_eq!(sign, det.signum(), "n = {}, det {det:e}", case.n);
            assert!(
                (log - log_abs).abs() < 1e-10 * (1.0 + log_abs.abs()),
                "n = {}: ln|det| {log} vs {log_abs}",
                case.n
            );
        }
    }
}

/// A chain like collocation's: `nb` intervals, each with `c` local unknowns and `c + s` rows
/// reading its two end nodes (`s` unknowns each), a shared "duration" and a "parameter"
/// pinned by a singleton row; `s` closure rows tie the last node to the first and one dense
/// row (a phase or arclength condition) reads everything. The reduced system pairs intervals
/// level by level (nested condensation).
fn chain_case(rng: &mut Rng, nb: usize, c: usize, s: usize) -> Case {
    let node = |j: usize| nb * c + j * s;
    let (dur, par) = (nb * c + (nb + 1) * s, nb * c + (nb + 1) * s + 1);
    let n = par + 1;
    let mut entries = Vec::new();
    let mut blocks = Vec::new();
    for b in 0..nb {
        let rows: Vec<usize> = (b * (c + s)..(b + 1) * (c + s)).collect();
        let cols: Vec<usize> = (b * c..(b + 1) * c).collect();
        for &r in &rows {
            entries.extend(cols.iter().map(|&j| (r, j)));
            entries.extend((node(b)..node(b + 2)).map(|j| (r, j)));
            entries.extend([(r, dur), (r, par)]);
        }
        blocks.push(EliminationBlock { rows, cols });
    }
    let mut r = nb * (c + s);
    for i in 0..s {
        entries.extend([(r, node(nb) + i), (r, node(0) + i)]);
        r += 1;
    }
    entries.extend((0..n).map(|j| (r, j)));
    entries.push((r + 1, par));
    assert_eq!(r + 2, n);
    let values = entries.iter().map(|_| 2.0 * rng.next() - 1.0).collect();
    Case {
        n,
        entries,
        values,
        blocks,
    }
}

#[test]
fn nested_condensation_of_a_chain_matches_the_dense_lu() {
    let mut rng = Rng(0xc4a1_0000_0000_0007);
    for nb in [1, 2, 3, 5, 16, 33] {
        let case = chain_case(&mut rng, nb, 6, 2);
        let mut a =
            SparsePattern::with_blocks(case.n, case.n, &case.entries, &case.blocks).unwrap();
        a.factorize(&case.values).unwrap();
        let dense_a = dense(&case, &case.values);
        for transpose in [false, true] {
            let b: Vec<f64> = (0..case.n).map(|_| rng.next() - 0.5).collect();
            let mut x = b.clone();
            if transpose {
                a.solve_transpose_in_place(&mut x).unwrap();
            } else {
                a.solve_in_place(&mut x).unwrap();
            }
            let err = backward_error(&dense_a, &x, &b, transpose);
            assert!(err < 1e-13, "nb = {nb}, transpose {transpose}: {err:e}");
        }
        let lu = dense_a.partial_piv_lu();
        let log_abs: f64 = (0..case.n).map(|i| lu.U()[(i, i)].abs().ln()).sum();
        let (sign, log) = a.determinant().unwrap();
        assert_eq!(sign, dense_a.determinant().signum(), "nb = {nb}");
        assert!(
            (log - log_abs).abs() < 1e-10 * (1.0 + log_abs.abs()),
            "nb = {nb}"
        );
    }
}

/// A right-hand side that vanishes on every block's rows (a tangent's $e_n$ on an arclength
/// row, or a closure row's unit vector) skips the forward elimination, whose result is zero
/// there: each unit vector of a free row of the chain (closure rows, the dense row) and of the
/// random case is solved to a backward error of roundoff, each after a solve with a full
/// right-hand side (so that nothing of that solve's elimination is read again).
#[test]
fn right_hand_sides_on_rows_outside_the_blocks_are_solved() {
    let mut rng = Rng(0x0f4e_e000_0000_0011);
    let chain = chain_case(&mut rng, 16, 6, 2);
    let random = random_case(&mut rng, 10, 6, 2, 6);
    for case in [chain, random] {
        let mut a =
            SparsePattern::with_blocks(case.n, case.n, &case.entries, &case.blocks).unwrap();
        a.factorize(&case.values).unwrap();
        let dense_a = dense(&case, &case.values);
        let in_block: Vec<usize> = case.blocks.iter().flat_map(|b| b.rows.clone()).collect();
        let outside: Vec<usize> = (0..case.n).filter(|i| !in_block.contains(i)).collect();
        assert!(
            outside.len() >= 3,
            "{} rows outside the blocks",
            outside.len()
        );
        for &row in &outside {
            let mut full: Vec<f64> = (0..case.n).map(|_| rng.next() - 0.5).collect();
            a.solve_in_place(&mut full).unwrap();
            let mut b = vec![0.0; case.n];
            b[row] = 1.0 + rng.next();
            let mut x = b.clone();
            a.solve_in_place(&mut x).unwrap();
            let err = backward_error(&dense_a, &x, &b, false);
            assert!(err < 1e-13, "n = {}, row {row}: {err:e}", case.n);
        }
    }
}

/// A block whose own equations are singular on its unknowns (here: two rows of the block are
/// equal on the block's columns and its other rows vanish there) while the matrix is not: the
/// pattern factorises the whole matrix instead and the solve is still exact.
#[test]
fn a_block_singular_on_its_own_falls_back_to_the_whole_matrix() {
    // Unknowns 0, 1 local to rows 0, 1; row 2 is a border row reading them.
    // [[1, 1, 1], [1, 1, 2], [1, 0, 1]]: the block [[1, 1], [1, 1]] is singular, det(A) = 1.
    let entries = [
        (0, 0),
        (0, 1),
        (0, 2),
        (1, 0),
        (1, 1),
        (1, 2),
        (2, 0),
        (2, 2),
    ];
    let values = [1.0, 1.0, 1.0, 1.0, 1.0, 2.0, 1.0, 1.0];
    let block = EliminationBlock {
        rows: vec![0, 1],
        cols: vec![0, 1],
    };
    let mut a = SparsePattern::with_blocks(3, 3, &entries, &[block]).unwrap();
    a.factorize(&values).unwrap();
    let mut x = vec![3.0, 4.0, 2.0]; // A (1, 1, 1)
    a.solve_in_place(&mut x).unwrap();
    for v in x {
        assert!((v - 1.0).abs() < 1e-14, "{v}");
    }
    let (sign, log) = a.determinant().unwrap();
    assert_eq!(sign, 1.0);
    assert!(log.abs() < 1e-14);
}

#[test]
fn badly_declared_blocks_are_refused() {
    let entries = [(0, 0), (0, 1), (1, 0), (1, 1), (2, 2), (1, 2), (2, 1)];
    let block = |rows: Vec<usize>, cols: Vec<usize>| EliminationBlock { rows, cols };
    let cases = [
        // More unknowns than equations.
        vec![block(vec![0], vec![0, 1])],
        // Overlapping blocks.
        vec![block(vec![0, 1], vec![0]), block(vec![1, 2], vec![1])],
        // Out of range.
        vec![block(vec![0, 5], vec![0])],
        // Unknown 1 is read by row 2, the equation of another block.
        vec![block(vec![0, 1], vec![0, 1]), block(vec![2], vec![2])],
        // Unknown 2 is not read by its own block's equation 0.
        vec![block(vec![0], vec![2])],
        // An empty block.
        vec![block(vec![0], vec![])],
    ];
    for blocks in cases {
        assert!(
            SparsePattern::with_blocks(3, 3, &entries, &blocks).is_err(),
            "{blocks:?} accepted"
        );
    }
    assert!(SparsePattern::with_blocks(3, 4, &entries, &[block(vec![0], vec![0])]).is_err());
    // An entry out of range.
    let outside = [(0, 0), (3, 1)];
    assert!(SparsePattern::with_blocks(3, 3, &outside, &[block(vec![0], vec![0])]).is_err());
}

/// Collocation declares each mesh interval's interior nodes as a local block: on a two-segment
/// orbit problem (its parameter held by a monitor, a pinned column) the condensed Newton step
/// and determinant equal those of the plain sparse LU of the same Jacobian, to rounding, and
/// the multipliers read off the condensation equal a fresh computation's.
#[test]
fn a_collocation_problem_condenses_to_the_plain_lu_steps() {
    use common::Relaxation;
    use hycont_core::orbit::{
        CollocationSettings, collocation_floquet, collocation_floquet_factorised,
        collocation_problem, solve_collocation,
    };
    use hycont_core::problem::NewtonSettings;
    use hycont_core::simulate::SimulationSettings;
    let a = 3.0;
    let guess = Relaxation::orbit([0.6, 1.0], 1.2 * Relaxation::period(a), a)
        .with_interior_points(&Relaxation, 1, 0.9, &SimulationSettings::default())
        .unwrap();
    let (ntst, ncol) = (8, 4);
    let settings = CollocationSettings {
        ntst,
        ncol,
        adapt: 0,
    };
    let sol = solve_collocation(&Relaxation, &guess, settings, &NewtonSettings::default()).unwrap();
    let mut problem =
        collocation_problem(&Relaxation, &sol.solution.orbit, sol.meshes.clone(), ncol).unwrap();
    assert_eq!(problem.elimination_blocks().len(), 2 * ntst);
    // Away from the solution, so that the step is not small.
    let mut u = problem.initial_unknowns(&sol.unknowns());
    for (i, x) in u.iter_mut().enumerate() {
        *x += 1e-2 * (0.37 * i as f64).sin();
    }
    let n = problem.unknowns();
    let (mut res, mut values) = (vec![0.0; n], Vec::new());
    problem.evaluate(&u, &mut res, Some(&mut values)).unwrap();
    let mut plain = SparsePattern::new(n, n, &problem.jacobian_entries()).unwrap();
    plain.factorize(&values).unwrap();
    problem.factorize(&u, &mut res).unwrap();
    let (mut condensed_step, mut plain_step) = (res.clone(), res.clone());
    problem.solve_in_place(&mut condensed_step).unwrap();
    plain.solve_in_place(&mut plain_step).unwrap();
    let scale = plain_step.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    for (c, p) in condensed_step.iter().zip(&plain_step) {
        assert!((c - p).abs() <= 1e-12 * scale, "{c} vs {p}");
    }
    let (sign, log) = problem.pattern().unwrap().determinant().unwrap();
    let (plain_sign, plain_log) = plain.determinant().unwrap();
    assert_eq!(sign, plain_sign);
    assert!((log - plain_log).abs() < 1e-10 * plain_log.abs().max(1.0));

    // At the solution, the multipliers read off the factorisation's condensed intervals equal
    // those of a fresh condensation; a factorisation that did not condense gives none.
    let u = problem.initial_unknowns(&sol.unknowns());
    problem.factorize(&u, &mut res).unwrap();
    let orbit = &sol.solution.orbit;
    let fresh = collocation_floquet(&Relaxation, orbit, &sol.meshes, &sol.nodes, ncol).unwrap();
    let jacobian = problem.pattern().unwrap();
    let read =
        collocation_floquet_factorised(&Relaxation, orbit, &sol.meshes, &sol.nodes, ncol, jacobian)
            .unwrap()
            .expect("a condensed factorisation");
    for (a, b) in read.multipliers.iter().zip(&fresh.multipliers) {
        assert!(
            (a.0 - b.0).abs() < 1e-12 && (a.1 - b.1).abs() < 1e-12,
            "{a:?} {b:?}"
        );
    }
    assert_eq!(read.trivial, fresh.trivial);
    let by_plain =
        collocation_floquet_factorised(&Relaxation, orbit, &sol.meshes, &sol.nodes, ncol, &plain);
    assert!(by_plain.unwrap().is_none());
}

/// Collocation writes every Jacobian value of its pattern (`ZeroFunction::writes_every_entry`),
/// so the problem hands it its value buffer without zeroing it: a buffer full of NaN from
/// "the last evaluation" gives exactly the values of a fresh, zeroed one. (A single entry the
/// part left unwritten would stay NaN.)
#[test]
fn collocation_writes_every_jacobian_value() {
    use common::Relaxation;
    use hycont_core::orbit::{CollocationSettings, collocation_problem, solve_collocation};
    use hycont_core::problem::NewtonSettings;
    use hycont_core::simulate::SimulationSettings;
    let a = 3.0;
    let guess = Relaxation::orbit([0.6, 1.0], 1.2 * Relaxation::period(a), a)
        .with_interior_points(&Relaxation, 1, 0.9, &SimulationSettings::default())
        .unwrap();
    for ncol in [1, 3, 4] {
        let settings = CollocationSettings {
            ntst: 5,
            ncol,
            adapt: 0,
        };
        let sol =
            solve_collocation(&Relaxation, &guess, settings, &NewtonSettings::default()).unwrap();
        let mut problem =
            collocation_problem(&Relaxation, &sol.solution.orbit, sol.meshes.clone(), ncol)
                .unwrap();
        let u = problem.initial_unknowns(&sol.unknowns());
        let mut res = vec![0.0; problem.equations()];
        let mut fresh = Vec::new();
        problem.evaluate(&u, &mut res, Some(&mut fresh)).unwrap();
        let mut stale = vec![f64::NAN; fresh.len()];
        problem.evaluate(&u, &mut res, Some(&mut stale)).unwrap();
        assert_eq!(fresh.len(), problem.jacobian_entries().len());
        assert!(stale.iter().all(|v| v.is_finite()), "ncol {ncol}");
        assert_eq!(stale, fresh);
    }
}
