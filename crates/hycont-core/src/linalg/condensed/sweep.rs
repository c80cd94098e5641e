//! The sweeps over the blocks, two blocks of the same shape at a time: the solves' forward
//! elimination and back substitution, and the factorisation's Schur updates.
//!
//! A block's forward elimination, back substitution and border rows' triangular solves are
//! chains of short dependent loops: each step waits for the one before, and one block's chain
//! is longer than the processor looks ahead. Blocks are independent of each other in all of
//! them, so two of them advanced step by step together keep two chains in flight. Each block
//! sees exactly the operations of a sweep over it alone, in the same order: the numbers do not
//! depend on the pairing.

use super::Block;
use crate::linalg::dense::{dot, solve_upper_transpose, vectorized};

/// Whether blocks `a` and `b` can be swept together (the same rows, eliminated columns and
/// kept columns read).
fn same_shape(a: &Block, b: &Block) -> bool {
    a.m() == b.m() && a.c() == b.c() && a.other.len() == b.other.len()
}

/// Calls `sweep` on the blocks in runs of up to [`RUN`] of the same shape.
#[inline(always)]
pub(super) fn in_runs(blocks: &[Block], mut sweep: impl FnMut(&[Block])) {
    let mut b = 0;
    while b < blocks.len() {
        let mut len = 1;
        while len < RUN && b + len < blocks.len() && same_shape(&blocks[b], &blocks[b + len]) {
            len += 1;
        }
        sweep(&blocks[b..b + len]);
        b += len;
    }
}

/// [`in_runs`] compiled for the widest vectors the processor has (AVX2 on x86-64 where
/// present, see `dense::vectorized`): the factorisation and the solves sweep so. `sweep` must
/// be inlined (`#[inline(always)]` on the closure) to be compiled so; the numbers are the same.
#[inline(always)]
pub(super) fn in_runs_vectorized(blocks: &[Block], sweep: impl FnMut(&[Block])) {
    vectorized(
        #[inline(always)]
        || in_runs(blocks, sweep),
    );
}

/// The most blocks swept together (runs of 4 measured no faster than single blocks on the
/// rocking block's collocation systems, runs of 2 about 1 % of a branch faster).
pub(super) const RUN: usize = 2;

/// The work slices of `B` blocks with `m` rows (`work` holds at least `B m` values).
#[inline(always)]
fn work_of<const B: usize>(work: &mut [f64], m: usize) -> [&mut [f64]; B] {
    let mut parts = work.chunks_mut(m.max(1));
    std::array::from_fn(|_| parts.next().unwrap_or_default())
}

/// The blocks' factors: column-major `m x w` each.
#[inline(always)]
fn factors<'a, const B: usize>(blks: &[Block], dense: &'a [f64]) -> [&'a [f64]; B] {
    std::array::from_fn(|i| &dense[blks[i].at..blks[i].at + blks[i].m() * blks[i].w()])
}

/// Forward elimination of `B` blocks of one shape: each block's right-hand side (gathered from
/// `rhs` in pivot order) by its unit lower factor; the pivot rows' values go to the blocks'
/// places in `top`, the rows left to their reduced rows in `red_rhs`.
#[inline(always)]
pub(super) fn forward<const B: usize>(
    blks: &[Block],
    dense: &[f64],
    rhs: &[f64],
    work: &mut [f64],
    (top, red_rhs): (&mut [f64], &mut [f64]),
) {
    let (m, c) = (blks[0].m(), blks[0].c());
    let a = factors::<B>(blks, dense);
    let mut v = work_of::<B>(work, m);
    for (vi, blk) in v.iter_mut().zip(blks) {
        for (x, &p) in vi.iter_mut().zip(&blk.perm) {
            *x = rhs[blk.rows[p]];
        }
    }
    match m {
        16 => lower_rows::<B, 16>(&mut v, &a, c),
        _ => lower_any(&mut v, &a, m, c),
    }
    for (vi, blk) in v.iter().zip(blks) {
        top[blk.top..blk.top + c].copy_from_slice(&vi[..c]);
        red_rhs[blk.schur_row..blk.schur_row + m - c].copy_from_slice(&vi[c..m]);
    }
}

/// The forward elimination's steps: $v \leftarrow L^{-1} v$ for each block's right-hand side
/// `v` and unit lower factor (the multipliers below the diagonal of `a`'s first `c` columns,
/// `m` rows).
#[inline(always)]
fn lower_any<const B: usize>(v: &mut [&mut [f64]; B], a: &[&[f64]; B], m: usize, c: usize) {
    for k in 0..c {
        for (vi, ai) in v.iter_mut().zip(a) {
            let vk = vi[k];
            if vk != 0.0 {
                let l = &ai[k * m + k + 1..(k + 1) * m];
                for (x, l) in vi[k + 1..m].iter_mut().zip(l) {
                    *x -= l * vk;
                }
            }
        }
    }
}

/// [`lower_any`] for blocks of `M` rows (a multiple of 4) known at compile
/// time: each step updates the 4-row chunks from the one holding row `k + 1` down, whole, the
/// rows at and above `k` kept as they are. A step that writes from row `k + 1` and the next
/// that reads from row `k + 2` each straddle the other's chunks, and such reads wait for the
/// writes to reach the cache. The same numbers as the general loop.
#[inline(always)]
fn lower_rows<const B: usize, const M: usize>(v: &mut [&mut [f64]; B], a: &[&[f64]; B], c: usize) {
    for k in 0..c {
        match (k + 1) / 4 {
            0 => lower_step::<B, M, 0>(v, a, k),
            1 => lower_step::<B, M, 4>(v, a, k),
            2 => lower_step::<B, M, 8>(v, a, k),
            3 => lower_step::<B, M, 12>(v, a, k),
            4 => lower_step::<B, M, 16>(v, a, k),
            5 => lower_step::<B, M, 20>(v, a, k),
            _ => {} // k + 1 >= 24 >= M: no rows below the pivot.
        }
    }
}

/// Step `k` of [`lower_rows`] on rows `S..M`.
#[inline(always)]
fn lower_step<const B: usize, const M: usize, const S: usize>(
    v: &mut [&mut [f64]; B],
    a: &[&[f64]; B],
    k: usize,
) {
    if S >= M {
        return;
    }
    for (vi, ai) in v.iter_mut().zip(a) {
        let vk = vi[k];
        if vk != 0.0 {
            let col = &ai[k * M + S..(k + 1) * M];
            for ((x, l), i) in vi[S..M].iter_mut().zip(col).zip(S..) {
                let below = *x - l * vk;
                *x = if i > k { below } else { *x };
            }
        }
    }
}

/// Back substitution of `B` blocks of one shape: with the kept unknowns `red_x` solved,
/// $U x_C = t - W' x_O$ for each block's `t` (its places in `top`); `x_C` goes to the block's
/// columns of `b`.
#[inline(always)]
pub(super) fn back<const B: usize>(
    blks: &[Block],
    dense: &[f64],
    (top, inv_pivots): (&[f64], &[f64]),
    red_x: &[f64],
    work: &mut [f64],
    b: &mut [f64],
) {
    let (m, c) = (blks[0].m(), blks[0].c());
    let a = factors::<B>(blks, dense);
    let mut t = work_of::<B>(work, m);
    for (ti, blk) in t.iter_mut().zip(blks) {
        ti[..c].copy_from_slice(&top[blk.top..blk.top + c]);
    }
    for k in 0..blks[0].other.len() {
        for ((ti, ai), blk) in t.iter_mut().zip(&a).zip(blks) {
            let xo = red_x[blk.other[k]];
            if xo != 0.0 {
                for (x, wi) in ti[..c].iter_mut().zip(&ai[(c + k) * m..(c + k) * m + c]) {
                    *x -= wi * xo;
                }
            }
        }
    }
    // U x = t, as `dense::solve_upper` on each block, step by step together.
    for k in (0..c).rev() {
        for ((ti, ai), blk) in t.iter_mut().zip(&a).zip(blks) {
            let xk = ti[k] * inv_pivots[blk.top + k];
            ti[k] = xk;
            if xk != 0.0 {
                for (x, ui) in ti[..k].iter_mut().zip(&ai[k * m..k * m + k]) {
                    *x -= ui * xk;
                }
            }
        }
    }
    for (ti, blk) in t.iter().zip(blks) {
        for (&j, &x) in blk.cols.iter().zip(&ti[..c]) {
            b[j] = x;
        }
    }
}

/// The contributions of `B` blocks of one shape to the reduced system (see the module docs of
/// `condensed`): each block's rows left after elimination, and its border rows' updates
/// $-y^\top W'$ with $U^\top y = g$ (`y` kept in `border` for the solves). The border rows'
/// triangular solves of the blocks advance step by step together where the blocks have as
/// many border rows; each gets the numbers of a solve alone.
#[inline(always)]
pub(super) fn schur<const B: usize>(
    blks: &[Block],
    dense: &[f64],
    inv_pivots: &[f64],
    border: &mut [f64],
    red: &mut [f64],
) {
    let (m, c, o) = (blks[0].m(), blks[0].c(), blks[0].other.len());
    let a = factors::<B>(blks, dense);
    for (blk, ai) in blks.iter().zip(&a) {
        // The rows left, column by column (`m - c` entries each, as the reduced system lists
        // them).
        let left = &mut red[blk.schur_entries..blk.schur_entries + o * (m - c)];
        for (k, col) in left.chunks_exact_mut((m - c).max(1)).enumerate() {
            for (x, v) in col.iter_mut().zip(&ai[(c + k) * m + c..(c + k + 1) * m]) {
                *x += v;
            }
        }
    }
    let inv: [&[f64]; B] = std::array::from_fn(|i| &inv_pivots[blks[i].top..blks[i].top + c]);
    let rows = blks.iter().map(|b| b.borders.len()).max().unwrap_or(0);
    let together = blks.iter().all(|b| b.borders.len() == rows);
    for r in 0..rows {
        let places: [std::ops::Range<usize>; B] =
            std::array::from_fn(|i| blks[i].borders.get(r).map_or(0..0, |bd| bd.at..bd.at + c));
        match border.get_disjoint_mut(places.clone()) {
            Ok(mut ys) if together => upper_transpose(&a, m, &inv, &mut ys),
            _ => {
                for (i, place) in places
                    .into_iter()
                    .enumerate()
                    .filter(|(_, p)| !p.is_empty())
                {
                    solve_upper_transpose(a[i], m, inv[i], &mut border[place]);
                }
            }
        }
    }
    for (blk, ai) in blks.iter().zip(&a) {
        for bd in &blk.borders {
            let y = &border[bd.at..bd.at + c];
            let row = &mut red[bd.entries..bd.entries + o];
            for (k, x) in row.iter_mut().enumerate() {
                *x -= dot(&ai[(c + k) * m..(c + k) * m + c], y);
            }
        }
    }
}

/// `dense::solve_upper_transpose` on `B` blocks' right-hand sides (the factors `a` with `m`
/// rows, the pivots' reciprocals `inv`), step by step together.
#[inline(always)]
fn upper_transpose<const B: usize>(
    a: &[&[f64]; B],
    m: usize,
    inv: &[&[f64]; B],
    ys: &mut [&mut [f64]; B],
) {
    let c = ys[0].len();
    for k in 0..c {
        for ((y, ai), inv) in ys.iter_mut().zip(a).zip(inv) {
            y[k] = (y[k] - dot(&ai[k * m..k * m + k], &y[..k])) * inv[k];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{back, forward, in_runs, lower_any, lower_rows, schur};
    use crate::linalg::{EliminationBlock, SparsePattern};
    use proptest::prelude::*;

    /// A chain like a collocation system's: block `b` has `c` unknowns of its own and `c + r`
    /// rows that also read the kept columns `K_b` and `K_{b+1}` (`r` each) and a parameter
    /// (the last column); `r` closing rows read `K_0` and `K_nb`; a last row (as an
    /// arclength row: every block's border row) reads every column. Returns the size, the
    /// entries and the blocks.
    fn chain(nb: usize, c: usize, r: usize) -> (usize, Vec<(usize, usize)>, Vec<EliminationBlock>) {
        let kept0 = nb * c;
        let n = kept0 + (nb + 1) * r + 1;
        let kept = |k: usize| kept0 + k * r..kept0 + (k + 1) * r;
        let (mut entries, mut blocks) = (Vec::new(), Vec::new());
        for b in 0..nb {
            let rows: Vec<usize> = (b * (c + r)..(b + 1) * (c + r)).collect();
            let cols: Vec<usize> = (b * c..(b + 1) * c).collect();
            for &i in &rows {
                entries.extend(
                    cols.iter()
                        .chain(kept(b).collect::<Vec<_>>().iter())
                        .map(|&j| (i, j)),
                );
                entries.extend(kept(b + 1).map(|j| (i, j)));
                entries.push((i, n - 1));
            }
            blocks.push(EliminationBlock { rows, cols });
        }
        for i in nb * (c + r)..n - 1 {
            entries.extend(kept(0).chain(kept(nb)).map(|j| (i, j)));
        }
        entries.extend((0..n).map(|j| (n - 1, j)));
        (n, entries, blocks)
    }

    /// [`chain`] factorised, its values from `vals` (repeated) with dominant diagonal entries
    /// on the blocks' own columns (nonsingular blocks); returns its size and pattern.
    fn factorised_chain(vals: &[f64], nb: usize, c: usize, r: usize) -> (usize, SparsePattern) {
        let (n, entries, blocks) = chain(nb, c, r);
        let mut a = SparsePattern::with_blocks(n, n, &entries, &blocks).unwrap();
        let values: Vec<f64> = (entries.iter().enumerate())
            .map(|(k, &(i, j))| {
                let dominant = i % (c + r) == j % c && j < nb * c;
                vals[k % vals.len()] + if dominant { 4.0 } else { 0.0 }
            })
            .collect();
        a.factorize(&values).unwrap();
        (n, a)
    }

    /// The right-hand sides and the factorisation's starting values [`all_sweeps`] uses.
    struct SweepInputs<'a> {
        rhs: &'a [f64],
        red_x: &'a [f64],
        border: &'a [f64],
        red_vals: &'a [f64],
    }

    /// The forward, back and Schur sweeps over every block of `cd`, as the solves and the
    /// factorisation run them: the bits of (top, reduced right-hand side, x, border, reduced
    /// values). Inlined where it is called, so that it is compiled for that context's vectors.
    #[inline(always)]
    fn all_sweeps(cd: &super::super::Condensed, input: &SweepInputs<'_>) -> [Vec<u64>; 5] {
        let m = cd.blocks.iter().map(super::Block::m).max().unwrap_or(0);
        let mut work = vec![0.0; 2 * m];
        let (mut top, mut red) = (vec![0.0; cd.top.len()], vec![0.0; cd.red_rhs.len()]);
        let mut x = vec![0.0; cd.rhs.len()];
        let (mut border, mut red_vals) = (input.border.to_vec(), input.red_vals.to_vec());
        let (dense, inv) = (&cd.dense, &cd.inv_pivots);
        in_runs(
            &cd.blocks,
            #[inline(always)]
            |blks| match blks.len() {
                2 => forward::<2>(blks, dense, input.rhs, &mut work, (&mut top, &mut red)),
                _ => forward::<1>(blks, dense, input.rhs, &mut work, (&mut top, &mut red)),
            },
        );
        in_runs(
            &cd.blocks,
            #[inline(always)]
            |blks| match blks.len() {
                2 => back::<2>(blks, dense, (&top, inv), input.red_x, &mut work, &mut x),
                _ => back::<1>(blks, dense, (&top, inv), input.red_x, &mut work, &mut x),
            },
        );
        in_runs(
            &cd.blocks,
            #[inline(always)]
            |blks| match blks.len() {
                2 => schur::<2>(blks, dense, inv, &mut border, &mut red_vals),
                _ => schur::<1>(blks, dense, inv, &mut border, &mut red_vals),
            },
        );
        [top, red, x, border, red_vals].map(|v| v.iter().map(|x| x.to_bits()).collect())
    }

    proptest! {
        /// The kernel for 16 rows gives the general loops' numbers to the bit (zeros of
        /// both signs among the entries, which the loops skip), for every count of eliminated
        /// columns.
        #[test]
        fn sixteen_row_kernel_is_the_general_loop(
            a in prop::collection::vec(
                prop_oneof![-1.0..1.0f64, Just(0.0), Just(-0.0)], 16 * 16),
            v in prop::collection::vec(prop_oneof![-1.0..1.0f64, Just(0.0), Just(-0.0)], 16),
            c in 1usize..=16,
        ) {
            let (mut fixed, mut any) = (v.clone(), v);
            lower_rows::<1, 16>(&mut [&mut fixed[..]], &[&a[..]], c);
            lower_any::<1>(&mut [&mut any[..]], &[&a[..]], 16, c);
            let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            prop_assert_eq!(bits(&fixed), bits(&any));
        }

        /// Blocks swept two at a time get the numbers a sweep over each alone gets, to the bit
        /// (the same operations in the same order per block), in both sweeps and in the Schur
        /// updates of the factorisation (each block has one border row, the last).
        /// Blocks of 5 rows take the general loops, blocks of 16 (4 states, 4 collocation
        /// points) the kernel for a row count known at compile time.
        #[test]
        fn pairs_sweep_as_single_blocks(
            vals in prop::collection::vec(-1.0..1.0f64, 400),
            rhs in prop::collection::vec(-1.0..1.0f64, 40),
            nb in 2usize..5,
            (c, r) in prop_oneof![Just((3usize, 2usize)), Just((12, 4))],
        ) {
            let (n, mut a) = factorised_chain(&vals, nb, c, r);
            let cd = a.condensed.as_mut().unwrap();
            let rhs: Vec<f64> = (0..n).map(|i| rhs[i % rhs.len()]).collect();
            let (len_top, len_red) = (cd.top.len(), cd.red_rhs.len());
            let mut work = vec![0.0; 2 * (c + r)];
            let (mut top2, mut red2) = (vec![0.0; len_top], vec![0.0; len_red]);
            let (mut top1, mut red1) = (vec![0.0; len_top], vec![0.0; len_red]);
            let mut runs = 0;
            in_runs(&cd.blocks, |blks| {
                runs += 1;
                match blks.len() {
                    2 => forward::<2>(blks, &cd.dense, &rhs, &mut work, (&mut top2, &mut red2)),
                    _ => forward::<1>(blks, &cd.dense, &rhs, &mut work, (&mut top2, &mut red2)),
                }
            });
            prop_assert_eq!(runs, nb.div_ceil(2));
            for k in 0..nb {
                let blk = &cd.blocks[k..=k];
                forward::<1>(blk, &cd.dense, &rhs, &mut work, (&mut top1, &mut red1));
            }
            prop_assert_eq!(top1.iter().map(|x| x.to_bits()).collect::<Vec<_>>(), top2.iter().map(|x| x.to_bits()).collect::<Vec<_>>());
            prop_assert_eq!(red1.iter().map(|x| x.to_bits()).collect::<Vec<_>>(), red2.iter().map(|x| x.to_bits()).collect::<Vec<_>>());
            let red_x: Vec<f64> = (0..len_red).map(|k| rhs[(3 * k + 1) % n]).collect();
            let (mut x1, mut x2) = (vec![0.0; n], vec![0.0; n]);
            in_runs(&cd.blocks, |blks| match blks.len() {
                2 => back::<2>(blks, &cd.dense, (&top1, &cd.inv_pivots), &red_x, &mut work, &mut x2),
                _ => back::<1>(blks, &cd.dense, (&top1, &cd.inv_pivots), &red_x, &mut work, &mut x2),
            });
            for k in 0..nb {
                let blk = &cd.blocks[k..=k];
                back::<1>(blk, &cd.dense, (&top1, &cd.inv_pivots), &red_x, &mut work, &mut x1);
            }
            prop_assert_eq!(x1.iter().map(|x| x.to_bits()).collect::<Vec<_>>(), x2.iter().map(|x| x.to_bits()).collect::<Vec<_>>());
            // The Schur updates, on any border values and reduced entries.
            let border0: Vec<f64> = (0..cd.border.len()).map(|k| rhs[(5 * k + 2) % n]).collect();
            let red0: Vec<f64> = (0..cd.red_vals.len()).map(|k| vals[(7 * k + 3) % vals.len()]).collect();
            let (mut border1, mut red1) = (border0.clone(), red0.clone());
            let (mut border2, mut red2) = (border0, red0);
            in_runs(&cd.blocks, |blks| match blks.len() {
                2 => schur::<2>(blks, &cd.dense, &cd.inv_pivots, &mut border2, &mut red2),
                _ => schur::<1>(blks, &cd.dense, &cd.inv_pivots, &mut border2, &mut red2),
            });
            for k in 0..nb {
                schur::<1>(&cd.blocks[k..=k], &cd.dense, &cd.inv_pivots, &mut border1, &mut red1);
            }
            prop_assert_eq!(border1.iter().map(|x| x.to_bits()).collect::<Vec<_>>(), border2.iter().map(|x| x.to_bits()).collect::<Vec<_>>());
            prop_assert_eq!(red1.iter().map(|x| x.to_bits()).collect::<Vec<_>>(), red2.iter().map(|x| x.to_bits()).collect::<Vec<_>>());
            prop_assert!(cd.blocks.iter().all(|b| b.borders.len() == 1));
        }

        /// The sweeps as the factorisation and the solves run them (inside
        /// `dense::vectorized`: with AVX2 on a processor that has it) and compiled for the
        /// baseline instruction set (called here directly) give the same numbers to the bit:
        /// wider vectors change no number (no contraction into fused multiply-adds, no
        /// reordering).
        #[test]
        fn vector_width_changes_no_sweep_number(
            vals in prop::collection::vec(-1.0..1.0f64, 400),
            rhs in prop::collection::vec(-1.0..1.0f64, 40),
            nb in 2usize..5,
            (c, r) in prop_oneof![Just((3usize, 2usize)), Just((12, 4))],
        ) {
            let (n, mut a) = factorised_chain(&vals, nb, c, r);
            let cd = a.condensed.as_mut().unwrap();
            let rhs: Vec<f64> = (0..n).map(|i| rhs[i % rhs.len()]).collect();
            let red_x: Vec<f64> = (0..cd.red_rhs.len()).map(|k| rhs[(3 * k + 1) % n]).collect();
            let border0: Vec<f64> = (0..cd.border.len()).map(|k| rhs[(5 * k + 2) % n]).collect();
            let red0: Vec<f64> = (0..cd.red_vals.len()).map(|k| vals[(7 * k + 3) % vals.len()]).collect();
            let cd = &*cd;
            // Forward, back and Schur sweeps over every block: (top, reduced rhs, x, border,
            // reduced values).
            let inputs = SweepInputs { rhs: &rhs, red_x: &red_x, border: &border0, red_vals: &red0 };
            let wide = crate::linalg::dense::vectorized(
                #[inline(always)]
                || all_sweeps(cd, &inputs),
            );
            prop_assert_eq!(wide, all_sweeps(cd, &inputs));
        }
    }
}
