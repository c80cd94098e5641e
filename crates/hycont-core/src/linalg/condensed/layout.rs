//! Where every entry of a condensed pattern goes: the dense blocks, the border rows, the
//! pinned columns (singleton rows), or the reduced system.

use super::{Block, Border, Condensed, Dest, Pin, Routes};
use crate::error::{Error, Result};
use crate::linalg::entries::Entries;
use crate::linalg::{EliminationBlock, SparsePattern, permutation_sign};

const NONE: usize = usize::MAX;

/// The most blocks of one level merged into one block of the next (see `next_level`): on a
/// chain of collocation intervals each level then reduces the chain fourfold, in fewer levels
/// (each with its own copies and fills) than pairs would need.
const GROUP: usize = 4;

fn bad(blocks: &[EliminationBlock], reason: &'static str) -> Error {
    Error::InvalidSetting {
        name: "elimination blocks",
        value: blocks.len() as f64,
        reason,
    }
}

/// Which block owns each row and column (`NONE` for none).
fn owners(n: usize, blocks: &[EliminationBlock]) -> Result<(Vec<usize>, Vec<usize>)> {
    let mut row = vec![NONE; n];
    let mut col = vec![NONE; n];
    for (b, blk) in blocks.iter().enumerate() {
        if blk.cols.is_empty() || blk.rows.len() < blk.cols.len() {
            return Err(bad(
                blocks,
                "each block needs unknowns and at least as many equations",
            ));
        }
        for (list, owner) in [(&blk.rows, &mut row), (&blk.cols, &mut col)] {
            for &i in list {
                match owner.get_mut(i) {
                    Some(slot) if *slot == NONE => *slot = b,
                    Some(_) => return Err(bad(blocks, "blocks overlap or repeat an index")),
                    None => return Err(bad(blocks, "an index is out of range")),
                }
            }
        }
    }
    Ok((row, col))
}

/// Rows outside the blocks with a single (structural) entry, in a column outside the blocks:
/// `pin_of_row[r]`/`pin_of_col[c]` give the pin's index. One pin per column.
fn pins(
    n: usize,
    entries: &Entries,
    row_owner: &[usize],
    col_owner: &[usize],
) -> (Vec<Pin>, Vec<usize>, Vec<usize>) {
    let (mut first, mut multi) = (vec![NONE; n], vec![false; n]);
    for (r, c) in entries.iter() {
        if first[r] == NONE {
            first[r] = c;
        } else if first[r] != c {
            multi[r] = true;
        }
    }
    let (mut pin_of_row, mut pin_of_col) = (vec![NONE; n], vec![NONE; n]);
    let mut pins = Vec::new();
    for r in 0..n {
        let c = first[r];
        let single = row_owner[r] == NONE && !multi[r] && c != NONE;
        if single && col_owner[c] == NONE && pin_of_col[c] == NONE {
            pin_of_row[r] = pins.len();
            pin_of_col[c] = pins.len();
            pins.push(Pin { row: r, col: c });
        }
    }
    (pins, pin_of_row, pin_of_col)
}

impl Condensed {
    /// The condensed layout of a square pattern.
    pub(in crate::linalg) fn new(
        n: usize,
        entries: &Entries,
        specs: &[EliminationBlock],
    ) -> Result<Self> {
        let (row_owner, col_owner) = owners(n, specs)?;
        let (pins, pin_of_row, pin_of_col) = pins(n, entries, &row_owner, &col_owner);
        // Reduced numbering: the rows left in each block (in block order), then the free rows;
        // the kept columns in order.
        let kept: Vec<usize> = (0..n)
            .filter(|&j| col_owner[j] == NONE && pin_of_col[j] == NONE)
            .collect();
        let mut red_col = vec![NONE; n];
        for (k, &j) in kept.iter().enumerate() {
            red_col[j] = k;
        }
        let mut blocks = Vec::with_capacity(specs.len());
        let (mut schur_row, mut top) = (0, 0);
        for s in specs {
            blocks.push(Block::new(s, schur_row, top));
            schur_row += s.rows.len() - s.cols.len();
            top += s.cols.len();
        }
        let free: Vec<usize> = (0..n)
            .filter(|&i| row_owner[i] == NONE && pin_of_row[i] == NONE)
            .collect();
        let mut red_row = vec![NONE; n];
        for (k, &i) in free.iter().enumerate() {
            red_row[i] = schur_row + k;
        }
        let mut borders = block_reads(
            entries,
            specs,
            (&row_owner, &col_owner),
            &red_col,
            &mut blocks,
        )?;
        let (mut red_entries, dense_len, border_len) =
            place_blocks(&mut blocks, &mut borders, &kept, &red_row);
        if u32::try_from(entries.len()).is_err() {
            return Err(bad(specs, "condensation handles at most 2^32 entries"));
        }
        let mut me = Self {
            entries: entries.len(),
            routes: Routes::default(),
            dense_covered_once: false,
            pin_entries: Vec::new(),
            pin_rows: Vec::new(),
            pin_starts: Vec::new(),
            pin_vals: Vec::new(),
            reduced: Box::new(SparsePattern::new(0, 0, &[])?),
            red_vals: Vec::new(),
            dense: vec![0.0; dense_len],
            border: vec![0.0; border_len],
            free_rows: free.iter().map(|&i| (i, red_row[i])).collect(),
            in_block: row_owner.iter().map(|&o| o != NONE).collect(),
            block_rows_left: schur_row,
            order_sign: 1.0,
            rhs: vec![0.0; n],
            red_rhs: vec![0.0; kept.len()],
            work: vec![0.0; super::sweep::RUN * blocks.iter().map(Block::m).max().unwrap_or(0)],
            top: vec![0.0; top],
            pivots: vec![0.0; top + pins.len()],
            inv_pivots: vec![0.0; top],
            pins,
            blocks,
            kept,
        };
        let ctx = Numbering {
            row_owner: &row_owner,
            col_owner: &col_owner,
            pin_of_row: &pin_of_row,
            pin_of_col: &pin_of_col,
            red_row: &red_row,
            red_col: &red_col,
        };
        // Routed straight into runs (no destination per entry is stored: a large system's
        // pattern has millions of entries); the other entries of pinned columns once their
        // places, grouped by pin, are known.
        let pinned = me.route(entries, &ctx, &mut red_entries, top);
        let new_index = me.group_pin_entries();
        for (e, i) in pinned {
            me.routes.push(e, Dest::PinColumn(new_index[i]), top);
        }
        let mut covered = vec![0u8; dense_len];
        for run in &me.routes.dense {
            for c in &mut covered[run.at..run.at + run.len as usize] {
                *c = c.saturating_add(1);
            }
        }
        me.dense_covered_once = covered.iter().all(|&c| c == 1);
        let nred = me.kept.len();
        let next = next_level(&me.blocks, nred, &red_entries);
        me.reduced = Box::new(SparsePattern::with_blocks(nred, nred, &red_entries, &next)?);
        me.red_vals = vec![0.0; red_entries.len()];
        let col_order: Vec<usize> = (me.pins.iter().map(|p| p.col))
            .chain(specs.iter().flat_map(|s| s.cols.iter().copied()))
            .chain(me.kept.iter().copied())
            .collect();
        // The blocks' pivoting orders are the identity until the first factorisation.
        me.order_sign = permutation_sign(&col_order) * permutation_sign(&me.row_order());
        Ok(me)
    }

    /// Orders the other entries of pinned columns by pin (stable: each pin's in entry order),
    /// with `pin_starts` delimiting each pin's; returns each entry's new place (by its place
    /// in `pin_entries`).
    fn group_pin_entries(&mut self) -> Vec<usize> {
        let mut order: Vec<usize> = (0..self.pin_entries.len()).collect();
        order.sort_by_key(|&i| self.pin_entries[i].0);
        let mut new_index = vec![0; order.len()];
        for (to, &from) in order.iter().enumerate() {
            new_index[from] = to;
        }
        self.pin_starts = vec![0; self.pins.len() + 1];
        for &(pin, _) in &self.pin_entries {
            self.pin_starts[pin + 1] += 1;
        }
        for k in 0..self.pins.len() {
            self.pin_starts[k + 1] += self.pin_starts[k];
        }
        self.pin_rows = order.iter().map(|&i| self.pin_entries[i].1).collect();
        self.pin_entries = Vec::new();
        new_index
    }

    /// Routes every entry into `routes` (pins' pivots after the blocks' `pin0`), but the other
    /// entries of pinned columns: returned as (entry, place in `pin_entries`).
    fn route(
        &mut self,
        entries: &Entries,
        ctx: &Numbering<'_>,
        red_entries: &mut Vec<(usize, usize)>,
        pin0: usize,
    ) -> Vec<(usize, usize)> {
        let mut pinned = Vec::new();
        // Position of each block column and block row within its block.
        let mut local = vec![NONE; ctx.row_owner.len()];
        let mut local_row = vec![NONE; ctx.row_owner.len()];
        // Position of each kept column among the current block's other columns (set while
        // that block's rows are routed).
        let mut other_at = vec![NONE; self.kept.len()];
        let mut current = NONE;
        for blk in &self.blocks {
            for (k, &j) in blk.cols.iter().enumerate() {
                local[j] = k;
            }
            for (i, &r) in blk.rows.iter().enumerate() {
                local_row[r] = i;
            }
        }
        for (e, (r, c)) in entries.iter().enumerate() {
            let (rb, cb) = (ctx.row_owner[r], ctx.col_owner[c]);
            let pin = ctx.pin_of_col[c];
            let dest = if pin != NONE && ctx.pin_of_row[r] == pin {
                Dest::Pivot(pin)
            } else if pin != NONE {
                pinned.push((e, self.pin_entries.len()));
                self.pin_entries.push((pin, r));
                continue;
            } else if rb != NONE {
                let blk = &self.blocks[rb];
                let i = local_row[r];
                if current != rb {
                    if current != NONE {
                        for &rc in &self.blocks[current].other {
                            other_at[rc] = NONE;
                        }
                    }
                    for (k, &rc) in blk.other.iter().enumerate() {
                        other_at[rc] = k;
                    }
                    current = rb;
                }
                let j = if cb == rb {
                    local[c]
                } else {
                    let k = other_at[ctx.red_col[c]];
                    assert_ne!(k, NONE, "the block's kept columns are listed");
                    blk.c() + k
                };
                Dest::Dense(blk.at + i + j * blk.m())
            } else if cb != NONE {
                let blk = &self.blocks[cb];
                let bd = blk.borders.iter().find(|bd| bd.row == r);
                Dest::Border(bd.expect("a border row of its block").at + local[c])
            } else {
                red_entries.push((ctx.red_row[r], ctx.red_col[c]));
                Dest::Reduced(red_entries.len() - 1)
            };
            self.routes.push(e, dest, pin0);
        }
        pinned
    }
}

/// The kept columns each block's rows read (into `blocks[b].other`) and, per block, the free
/// rows that read its columns (its border rows); checks that no block's columns appear in
/// another block's rows and that each block's rows read all its columns.
fn block_reads(
    entries: &Entries,
    specs: &[EliminationBlock],
    (row_owner, col_owner): (&[usize], &[usize]),
    red_col: &[usize],
    blocks: &mut [Block],
) -> Result<Vec<Vec<usize>>> {
    let mut borders: Vec<Vec<usize>> = vec![Vec::new(); specs.len()];
    let mut read = vec![false; col_owner.len()];
    // Consecutive repeats are not listed again (sorted and deduplicated later: a block's
    // entries come column by column, each kept column once per row).
    let push_new = |list: &mut Vec<usize>, x: usize| {
        if list.last() != Some(&x) {
            list.push(x);
        }
    };
    for (r, c) in entries.iter() {
        let (rb, cb) = (row_owner[r], col_owner[c]);
        if rb != NONE && cb == NONE && red_col[c] != NONE {
            push_new(&mut blocks[rb].other, red_col[c]);
        } else if rb != NONE && cb == rb {
            read[c] = true;
        } else if rb != NONE && cb != NONE {
            return Err(bad(
                specs,
                "a block's unknowns appear in another block's equations",
            ));
        } else if rb == NONE && cb != NONE {
            push_new(&mut borders[cb], r);
        }
    }
    if blocks.iter().any(|blk| blk.cols.iter().any(|&j| !read[j])) {
        return Err(bad(specs, "a block's unknown is not read by its equations"));
    }
    Ok(borders)
}

/// Places each block's dense storage, its remaining rows and its border rows in the reduced
/// system; returns the reduced entries so far and the dense and border storage sizes.
fn place_blocks(
    blocks: &mut [Block],
    borders: &mut [Vec<usize>],
    kept: &[usize],
    red_row: &[usize],
) -> (Vec<(usize, usize)>, usize, usize) {
    let mut red_entries: Vec<(usize, usize)> = Vec::new();
    let (mut dense_len, mut border_len) = (0, 0);
    for (blk, rows) in blocks.iter_mut().zip(borders) {
        blk.other.sort_unstable();
        blk.other.dedup();
        blk.other_cols = blk.other.iter().map(|&rc| kept[rc]).collect();
        blk.at = dense_len;
        dense_len += blk.m() * blk.w();
        blk.schur_entries = red_entries.len();
        // Column by column, as the block stores them (the next level copies them as runs).
        for &rc in &blk.other {
            red_entries.extend((0..blk.m() - blk.c()).map(|s| (blk.schur_row + s, rc)));
        }
        rows.sort_unstable();
        rows.dedup();
        for &r in rows.iter() {
            blk.borders.push(Border {
                row: r,
                red_row: red_row[r],
                at: border_len,
                entries: red_entries.len(),
            });
            border_len += blk.c();
            red_entries.extend(blk.other.iter().map(|&rc| (red_row[r], rc)));
        }
    }
    (red_entries, dense_len, border_len)
}

/// The numbering maps [`Condensed::route`] needs.
struct Numbering<'a> {
    row_owner: &'a [usize],
    col_owner: &'a [usize],
    pin_of_row: &'a [usize],
    pin_of_col: &'a [usize],
    red_row: &'a [usize],
    red_col: &'a [usize],
}

impl Block {
    fn new(s: &EliminationBlock, schur_row: usize, top: usize) -> Self {
        Self {
            rows: s.rows.clone(),
            cols: s.cols.clone(),
            other: Vec::new(),
            other_cols: Vec::new(),
            perm: (0..s.rows.len()).collect(),
            sign: 1.0,
            at: 0,
            schur_row,
            schur_entries: 0,
            top,
            borders: Vec::new(),
        }
    }
}

/// Blocks of this level merged into groups of at most [`GROUP`] whose remaining rows share
/// columns that no block outside the group reads (border rows may); each group eliminates
/// those columns. On a chain of intervals (collocation) a group is [`GROUP`] consecutive
/// intervals eliminating the nodes between them, and the levels that follow reduce the chain
/// again: AUTO's reduction, as nested condensation. Greedy in column order; columns that fit
/// no group stay for the next level.
///
/// No level (an empty list) when the groups would eliminate fewer than a quarter of the
/// `nred` unknowns: such a level (at the end of a chain, two groups merged into one that
/// eliminates a single shared column, every other row a border row) costs more in its copies,
/// fills and border solves than it saves the dense or sparse LU of the system it leaves.
fn next_level(
    blocks: &[Block],
    nred: usize,
    red_entries: &[(usize, usize)],
) -> Vec<EliminationBlock> {
    let left = |b: &Block| b.schur_row..b.schur_row + b.m() - b.c();
    let schur_rows = blocks.last().map_or(0, |b| left(b).end);
    let mut block_of_row = vec![NONE; schur_rows];
    for (b, blk) in blocks.iter().enumerate() {
        block_of_row[left(blk)].fill(b);
    }
    // Up to two blocks reading each column; more make it shared.
    let mut readers = vec![(NONE, NONE); nred];
    let mut shared = vec![false; nred];
    for &(r, c) in red_entries.iter().filter(|e| e.0 < schur_rows) {
        let b = block_of_row[r];
        match readers[c] {
            (x, _) if x == NONE => readers[c].0 = b,
            (x, y) if x == b || y == b => {}
            (_, y) if y == NONE => readers[c].1 = b,
            _ => shared[c] = true,
        }
    }
    // Groups: (member blocks, eliminated columns); `group_of` each block's group.
    let mut group_of = vec![NONE; blocks.len()];
    let mut groups: Vec<(Vec<usize>, Vec<usize>)> = Vec::new();
    for c in 0..nred {
        let (a, b) = readers[c];
        if shared[c] || a == NONE || b == NONE {
            continue;
        }
        match (group_of[a], group_of[b]) {
            (g, h) if g == NONE && h == NONE => {
                group_of[a] = groups.len();
                group_of[b] = groups.len();
                groups.push((vec![a, b], vec![c]));
            }
            (g, h) if g == h => groups[g].1.push(c),
            (g, h) if h == NONE && groups[g].0.len() < GROUP => {
                group_of[b] = g;
                groups[g].0.push(b);
                groups[g].1.push(c);
            }
            (g, h) if g == NONE && groups[h].0.len() < GROUP => {
                group_of[a] = h;
                groups[h].0.push(a);
                groups[h].1.push(c);
            }
            _ => {}
        }
    }
    let level: Vec<EliminationBlock> = groups
        .into_iter()
        .map(|(mut members, cols)| {
            members.sort_unstable();
            EliminationBlock {
                rows: members.iter().flat_map(|&b| left(&blocks[b])).collect(),
                cols,
            }
        })
        .filter(|g| g.rows.len() >= g.cols.len())
        .collect();
    let eliminated: usize = level.iter().map(|g| g.cols.len()).sum();
    if 4 * eliminated < nred {
        return Vec::new();
    }
    level
}
