//! LU by condensation of local unknowns (AUTO's and COCO's treatment of collocation systems),
//! then a sparse LU of the small reduced system.
//!
//! Each [`EliminationBlock`] is a set $C_b$ of columns that no row of another block touches and a
//! set $R_b$ of rows with $|R_b| \ge |C_b|$. Rows outside the blocks with a single entry
//! (parameters held by a monitor) *pin* their column $D$. Order rows as $[E; P; Q]$ and columns as
//! $[D; C; K]$, where $E$ are the pinned rows, $P_b \subset R_b$ the rows chosen as pivots by
//! Gaussian elimination with partial pivoting of the dense block $A[R_b, C_b]$, $C$ all block
//! columns and $K$ the kept ones:
//! $$\Pi_r A \Pi_c = \begin{pmatrix} \Delta & 0 & 0 \\ \ast & X & Y \\ \ast & Z & W
//! \end{pmatrix}, \quad \Delta \text{ diagonal}, \quad X = \operatorname{diag}(X_b),\
//! X_b = L_b U_b,$$
//! $$\det A = \operatorname{sgn}\Pi_r \operatorname{sgn}\Pi_c \det\Delta \prod_b \det U_b\,
//! \det S, \qquad S = W - Z X^{-1} Y.$$
//! The Schur complement $S$ (over $Q \times K$) touches only the rows that remain of each block
//! and the *border rows* (rows outside every block that touch a block's columns, e.g. an
//! arclength row): each gets $-\,g^\top X_b^{-1} Y_b$ on the kept columns $O_b$ its block reads.
//! Each block is a small dense matrix $|R_b| \times (|C_b| + |O_b|)$ factorised in place; $S$ is
//! factorised by [`super::sparse_lu::SparseLu`] (symbolic analysis once). Solves fix the pinned
//! unknowns, forward-eliminate block by block (two blocks of one shape at a time, see `sweep`,
//! as the factorisation's Schur updates), solve with $S$ and back-substitute.

mod layout;
mod sweep;

use super::LogProduct;
use super::SparsePattern;
use super::dense::{dot, eliminate, reciprocals, solve_upper_transpose};
use crate::error::Result;

/// Where an entry's value goes.
#[derive(Debug, Clone, Copy)]
enum Dest {
    /// Into a dense block (absolute position in `dense`).
    Dense(usize),
    /// Into a border row's block columns (position in `border`).
    Border(usize),
    /// Into the reduced system (its entry index).
    Reduced(usize),
    /// A pinned row's only entry (the pin's index).
    Pivot(usize),
    /// Another entry of a pinned column (index into `pin_entries`).
    PinColumn(usize),
}

/// `len` consecutive entries from `entry` whose values go to consecutive positions from `at`.
#[derive(Debug, Clone, Copy)]
struct Run {
    entry: u32,
    len: u32,
    at: usize,
}

/// The entries by destination, as runs (an interval's collocation block listed in storage
/// order is a few runs; scattered entries are runs of one); pivots of pins are stored after the
/// blocks' pivots.
#[derive(Debug, Default)]
struct Routes {
    dense: Vec<Run>,
    border: Vec<Run>,
    reduced: Vec<Run>,
    pivot: Vec<Run>,
    pin_column: Vec<Run>,
}

impl Routes {
    /// Adds entry `e`'s destination (entries in increasing order per destination list; pivots
    /// of pins go after the blocks' `pin0` pivots).
    fn push(&mut self, e: usize, d: Dest, pin0: usize) {
        let e = u32::try_from(e).expect("at most 2^32 entries");
        let (list, at) = match d {
            Dest::Dense(p) => (&mut self.dense, p),
            Dest::Border(p) => (&mut self.border, p),
            Dest::Reduced(p) => (&mut self.reduced, p),
            Dest::Pivot(p) => (&mut self.pivot, pin0 + p),
            Dest::PinColumn(p) => (&mut self.pin_column, p),
        };
        match list.last_mut() {
            Some(run) if run.entry + run.len == e && run.at + run.len as usize == at => {
                run.len += 1;
            }
            _ => list.push(Run {
                entry: e,
                len: 1,
                at,
            }),
        }
    }
}

/// A row outside the blocks with one entry, and its column.
#[derive(Debug, Clone, Copy)]
struct Pin {
    row: usize,
    col: usize,
}

/// A border row of one block.
#[derive(Debug)]
struct Border {
    row: usize,
    /// Its index in the reduced system.
    red_row: usize,
    /// Start of its `|C_b|` values in `border` ($g$, then $y = U_b^{-\top} g$).
    at: usize,
    /// First of its `|O_b|` entries in the reduced system.
    entries: usize,
}

#[derive(Debug)]
struct Block {
    rows: Vec<usize>,
    cols: Vec<usize>,
    /// Reduced columns of the kept columns the block's rows read.
    other: Vec<usize>,
    /// The same columns' original indices.
    other_cols: Vec<usize>,
    /// Row order after pivoting (local indices into `rows`), and its sign.
    perm: Vec<usize>,
    sign: f64,
    /// Start of the column-major `rows.len() x (cols.len() + other.len())` storage in `dense`.
    at: usize,
    /// First reduced row of the rows left after elimination.
    schur_row: usize,
    /// First reduced entry of those rows (column-major: `m - c` per kept column).
    schur_entries: usize,
    /// Start of the block's `cols.len()` values in `top` (and its pivots in `pivots`).
    top: usize,
    borders: Vec<Border>,
}

impl Block {
    fn m(&self) -> usize {
        self.rows.len()
    }
    fn c(&self) -> usize {
        self.cols.len()
    }
    fn w(&self) -> usize {
        self.cols.len() + self.other.len()
    }
}

/// The condensed factorisation of one pattern.
#[derive(Debug)]
pub(super) struct Condensed {
    blocks: Vec<Block>,
    pins: Vec<Pin>,
    entries: usize,
    routes: Routes,
    /// Whether the entries cover every place of the blocks' storage exactly once (then they
    /// are copied in, without clearing the storage first).
    dense_covered_once: bool,
    dense: Vec<f64>,
    border: Vec<f64>,
    /// `(pin, row)` of the other entries of pinned columns while routing; then grouped by pin:
    /// the rows (`pin_rows[pin_starts[k]..pin_starts[k + 1]]` for pin `k`) and their values
    /// (`pin_vals`).
    pin_entries: Vec<(usize, usize)>,
    pin_rows: Vec<usize>,
    pin_starts: Vec<usize>,
    pin_vals: Vec<f64>,
    /// The reduced system: itself condensed where groups of blocks' remaining rows share
    /// columns no other block reads (see `layout::next_level`), else a plain sparse LU.
    reduced: Box<SparsePattern>,
    red_vals: Vec<f64>,
    /// `(row, reduced row)` of the rows outside every block.
    free_rows: Vec<(usize, usize)>,
    /// Whether each row belongs to a block.
    in_block: Vec<bool>,
    /// The reduced rows the blocks leave (they come first in the reduced numbering).
    block_rows_left: usize,
    /// Original column of each reduced column.
    kept: Vec<usize>,
    /// Sign of the row and column orders $\Pi_r, \Pi_c$ with every block's pivoting order the
    /// identity; a factorisation's row order adds its blocks' pivoting permutations.
    order_sign: f64,
    /// Work space: right-hand sides.
    rhs: Vec<f64>,
    red_rhs: Vec<f64>,
    /// Two blocks' right-hand sides (twice as many places as the tallest block has rows).
    work: Vec<f64>,
    top: Vec<f64>,
    /// The blocks' pivots (at each block's `top`), then the pins'.
    pivots: Vec<f64>,
    /// The blocks' pivots' reciprocals.
    inv_pivots: Vec<f64>,
}

/// Outcome of a condensed factorisation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Condensation {
    /// Factorised.
    Done,
    /// A block or pin is numerically singular on its own: factorise the whole matrix instead.
    SingularBlock,
}

/// The rows a block leaves after its local unknowns are eliminated (see
/// [`crate::linalg::SparsePattern::reduced_rows`]).
#[derive(Debug, Clone, Copy)]
pub struct ReducedRows<'a> {
    columns: &'a [usize],
    data: &'a [f64],
    m: usize,
    c: usize,
}

impl<'a> ReducedRows<'a> {
    /// Number of rows left (the block's equations minus its local unknowns).
    #[must_use]
    pub fn rows(&self) -> usize {
        self.m - self.c
    }

    /// The columns (in increasing order) the rows are over: every column the block's equations
    /// read apart from its own unknowns and pinned columns.
    #[must_use]
    pub fn columns(&self) -> &[usize] {
        self.columns
    }

    /// Column `k` (indexing [`ReducedRows::columns`]) over the rows; `None` out of range.
    #[must_use]
    pub fn column(&self, k: usize) -> Option<&'a [f64]> {
        (k < self.columns.len()).then(|| {
            let at = self.c + (self.c + k) * self.m;
            &self.data[at..at + self.rows()]
        })
    }

    /// Entry `(row, k)`, `k` indexing [`ReducedRows::columns`]; `None` out of range.
    #[must_use]
    pub fn value(&self, row: usize, k: usize) -> Option<f64> {
        (row < self.rows() && k < self.columns.len())
            .then(|| self.data[self.c + row + (self.c + k) * self.m])
    }
}

impl Condensed {
    /// Block `b`'s rows left after elimination in the last factorisation.
    pub(super) fn reduced_rows(&self, b: usize) -> Option<ReducedRows<'_>> {
        let blk = self.blocks.get(b)?;
        Some(ReducedRows {
            columns: &blk.other_cols,
            data: &self.dense[blk.at..blk.at + blk.m() * blk.w()],
            m: blk.m(),
            c: blk.c(),
        })
    }

    /// Condenses the blocks and factorises the reduced system.
    pub(super) fn factorize(&mut self, values: &[f64]) -> Result<Condensation> {
        crate::error::check_len("sparse values", values, self.entries)?;
        if !self.dense_covered_once {
            self.dense.fill(0.0);
        }
        self.border.fill(0.0);
        self.red_vals.fill(0.0);
        self.pin_vals.resize(self.pin_rows.len(), 0.0);
        self.pin_vals.fill(0.0);
        let pin0 = self.top.len();
        self.pivots[pin0..].fill(0.0);
        let r = &self.routes;
        if self.dense_covered_once {
            for run in &r.dense {
                let (e, len) = (run.entry as usize, run.len as usize);
                self.dense[run.at..run.at + len].copy_from_slice(&values[e..e + len]);
            }
        }
        let dense: &[Run] = if self.dense_covered_once {
            &[]
        } else {
            &r.dense
        };
        for (to, list) in [
            (&mut self.dense, dense),
            (&mut self.border, &r.border[..]),
            (&mut self.red_vals, &r.reduced[..]),
            (&mut self.pivots, &r.pivot[..]),
            (&mut self.pin_vals, &r.pin_column[..]),
        ] {
            for run in list {
                let (e, len) = (run.entry as usize, run.len as usize);
                for (x, v) in to[run.at..run.at + len].iter_mut().zip(&values[e..e + len]) {
                    *x += v;
                }
            }
        }
        if self.pivots[pin0..].iter().any(|p| !(p.abs() > 0.0)) {
            return Ok(Condensation::SingularBlock);
        }
        for blk in &mut self.blocks {
            let a = &mut self.dense[blk.at..blk.at + blk.m() * blk.w()];
            let pivots = &mut self.pivots[blk.top..blk.top + blk.c()];
            let Some(sign) = eliminate(a, (blk.m(), blk.c(), blk.w()), &mut blk.perm, pivots)
            else {
                return Ok(Condensation::SingularBlock);
            };
            blk.sign = sign;
            let inv = &mut self.inv_pivots[blk.top..blk.top + blk.c()];
            reciprocals(pivots, inv);
        }
        // Each block's contributions to the reduced system, two blocks at a time (their
        // border rows' triangular solves are chains of dependent dot products).
        let (dense, inv) = (&self.dense, &self.inv_pivots);
        let (border, red) = (&mut self.border, &mut self.red_vals);
        sweep::in_runs_vectorized(
            &self.blocks,
            #[inline(always)]
            |blks| match blks.len() {
                2 => sweep::schur::<2>(blks, dense, inv, border, red),
                _ => sweep::schur::<1>(blks, dense, inv, border, red),
            },
        );
        self.reduced.factorize(&self.red_vals)?;
        Ok(Condensation::Done)
    }

    /// Row order `[E, P_1 .. P_B, rows left in each block, free rows]` of the factorisation.
    /// Its sign is that of the order with identity pivoting (fixed by the layout) times the
    /// blocks' pivoting permutations' (each acts on its block's own places in the order).
    fn row_order(&self) -> Vec<usize> {
        let order = self
            .pins
            .iter()
            .map(|p| p.row)
            .chain(
                self.blocks
                    .iter()
                    .flat_map(|b| b.perm[..b.c()].iter().map(|&i| b.rows[i])),
            )
            .chain(
                self.blocks
                    .iter()
                    .flat_map(|b| b.perm[b.c()..].iter().map(|&i| b.rows[i])),
            )
            .chain(self.free_rows.iter().map(|&(i, _)| i));
        order.collect()
    }

    /// Sign and $\ln|\det|$ of the factorised matrix.
    pub(super) fn determinant(&self) -> Result<(f64, f64)> {
        let (sign, log) = self.reduced.determinant()?;
        let (pivot_sign, pivot_log) = LogProduct::of(&self.pivots).finish();
        let order_sign = self.blocks.iter().fold(self.order_sign, |s, b| s * b.sign);
        Ok((sign * pivot_sign * order_sign, log + pivot_log))
    }

    /// Solves $A x = b$ in place.
    pub(super) fn solve(&mut self, b: &mut [f64]) -> Result<()> {
        self.rhs.copy_from_slice(b);
        let pin0 = self.top.len();
        for (k, p) in self.pins.iter().enumerate() {
            b[p.col] = self.rhs[p.row] / self.pivots[pin0 + k];
        }
        for (k, p) in self.pins.iter().enumerate() {
            // Held parameters: usually no change to carry into the other rows.
            let x = b[p.col];
            if x != 0.0 {
                let at = self.pin_starts[k]..self.pin_starts[k + 1];
                for (&r, a) in self.pin_rows[at.clone()].iter().zip(&self.pin_vals[at]) {
                    self.rhs[r] -= a * x;
                }
            }
        }
        // Forward elimination of each block's rows in pivot order (one loop per step over the
        // rows below it), two blocks at a time (see `sweep`); the pivot rows go into `top`, the
        // rows left into the reduced right-hand side. A right-hand side that vanishes on every
        // block row (a tangent's $e_n$ on an arclength row) stays zero: nothing to eliminate.
        let on_blocks =
            (self.rhs.iter().zip(&self.in_block)).any(|(&x, &in_block)| in_block && x != 0.0);
        if on_blocks {
            let (dense, rhs, work) = (&self.dense, &self.rhs, &mut self.work);
            let out = (&mut self.top[..], &mut self.red_rhs[..]);
            sweep::in_runs_vectorized(
                &self.blocks,
                #[inline(always)]
                |blks| match blks.len() {
                    2 => sweep::forward::<2>(blks, dense, rhs, work, (&mut *out.0, &mut *out.1)),
                    _ => sweep::forward::<1>(blks, dense, rhs, work, (&mut *out.0, &mut *out.1)),
                },
            );
        } else {
            self.top.fill(0.0);
            self.red_rhs[..self.block_rows_left].fill(0.0);
        }
        for &(i, r) in &self.free_rows {
            self.red_rhs[r] = self.rhs[i];
        }
        for blk in &self.blocks {
            let t = &self.top[blk.top..blk.top + blk.c()];
            for bd in &blk.borders {
                self.red_rhs[bd.red_row] -= dot(&self.border[bd.at..bd.at + blk.c()], t);
            }
        }
        self.reduced.solve_in_place(&mut self.red_rhs)?;
        for (k, &j) in self.kept.iter().enumerate() {
            b[j] = self.red_rhs[k];
        }
        // t <- t - W' x_O, then U x_C = t; two blocks at a time.
        let (dense, red_x, work) = (&self.dense, &self.red_rhs, &mut self.work);
        let factors = (&self.top[..], &self.inv_pivots[..]);
        sweep::in_runs_vectorized(
            &self.blocks,
            #[inline(always)]
            |blks| match blks.len() {
                2 => sweep::back::<2>(blks, dense, factors, red_x, work, b),
                _ => sweep::back::<1>(blks, dense, factors, red_x, work, b),
            },
        );
        Ok(())
    }

    /// Solves $A^\top z = d$ in place.
    pub(super) fn solve_transpose(&mut self, d: &mut [f64]) -> Result<()> {
        self.rhs.copy_from_slice(d);
        for (k, &j) in self.kept.iter().enumerate() {
            self.red_rhs[k] = self.rhs[j];
        }
        for blk in &self.blocks {
            let (m, c) = (blk.m(), blk.c());
            let a = &self.dense[blk.at..blk.at + m * blk.w()];
            let v = &mut self.top[blk.top..blk.top + c];
            // U^T v = d_C, then d_K[O] -= W'^T v.
            for (vk, &j) in v.iter_mut().zip(&blk.cols) {
                *vk = self.rhs[j];
            }
            solve_upper_transpose(a, m, &self.inv_pivots[blk.top..blk.top + c], v);
            for (k, &rc) in blk.other.iter().enumerate() {
                self.red_rhs[rc] -= dot(&a[(c + k) * m..(c + k) * m + c], v);
            }
        }
        self.reduced.solve_transpose_in_place(&mut self.red_rhs)?;
        for &(i, r) in &self.free_rows {
            d[i] = self.red_rhs[r];
        }
        for blk in &self.blocks {
            let (m, c) = (blk.m(), blk.c());
            let a = &self.dense[blk.at..blk.at + m * blk.w()];
            let v = &mut self.top[blk.top..blk.top + c];
            for bd in &blk.borders {
                let zr = self.red_rhs[bd.red_row];
                for (vk, y) in v.iter_mut().zip(&self.border[bd.at..bd.at + c]) {
                    *vk -= y * zr;
                }
            }
            // z = [z_P; z_S] with L^T z = v on the pivot rows: z_k = v_k - sum_{i > k} L_ik z_i.
            let rest = &self.red_rhs[blk.schur_row..blk.schur_row + m - c];
            for k in (0..c).rev() {
                let col = &a[k * m..(k + 1) * m];
                v[k] -= dot(&col[k + 1..c], &v[k + 1..c]) + dot(&col[c..m], rest);
            }
            for (i, &p) in blk.perm.iter().enumerate() {
                d[blk.rows[p]] = if i < c { v[i] } else { rest[i - c] };
            }
        }
        // Pinned rows last: Delta z_E = d_D - (other entries of the pinned columns)^T z.
        let pin0 = self.top.len();
        for p in &self.pins {
            d[p.row] = self.rhs[p.col];
        }
        for (k, p) in self.pins.iter().enumerate() {
            let at = self.pin_starts[k]..self.pin_starts[k + 1];
            for (&r, a) in self.pin_rows[at.clone()].iter().zip(&self.pin_vals[at]) {
                d[p.row] -= a * d[r];
            }
        }
        for (k, p) in self.pins.iter().enumerate() {
            d[p.row] /= self.pivots[pin0 + k];
        }
        Ok(())
    }
}
