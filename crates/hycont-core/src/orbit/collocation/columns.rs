//! One interval's collocation block: the order of its column groups (interior nodes first, the
//! unknowns condensation eliminates) and the kernels of one collocation point (the polynomial
//! and its derivative there, the nodes' columns of its rows), with the state dimension known at
//! compile time where it is small.

/// The nodes' columns of one collocation point's rows in its interval's block.
pub(super) struct NodeColumns<'b> {
    pub(super) block: &'b mut [f64],
    /// The block's rows (`ncol * n`) and the point's first row.
    pub(super) rows: usize,
    pub(super) at: usize,
    /// $A = f_x$ at the point (column-major), $L_i(z_c)$, $L_i'(z_c)$, $-h T$.
    pub(super) a: &'b [f64],
    pub(super) l: &'b [f64],
    pub(super) dl: &'b [f64],
    pub(super) ht: f64,
}

impl NodeColumns<'_> {
    /// Column (node, comp) on the point's rows: $L_i'(z_c) e_{comp} - h T L_i(z_c) A_{:, comp}$,
    /// with the state dimension `N` known at compile time (whole columns of `A` at once).
    #[inline(always)]
    pub(super) fn write<const N: usize>(self) {
        let ncol = self.l.len() - 1;
        let mut a = [[0.0; N]; N];
        for (col, src) in a.iter_mut().zip(self.a.chunks_exact(N)) {
            col.copy_from_slice(src);
        }
        for (node, (&lv, &dv)) in self.l.iter().zip(self.dl).enumerate() {
            let s = self.ht * lv;
            let g = group_of_node(node, ncol);
            for (comp, a_col) in a.iter().enumerate() {
                let start = (g * N + comp) * self.rows + self.at;
                let col: &mut [f64; N] = (&mut self.block[start..start + N])
                    .try_into()
                    .expect("N rows");
                for (o, x) in col.iter_mut().zip(a_col) {
                    *o = s * x;
                }
                col[comp] += dv;
            }
        }
    }

    /// [`NodeColumns::write`] for any state dimension.
    pub(super) fn write_any(self, n: usize) {
        let ncol = self.l.len() - 1;
        for (node, (&lv, &dv)) in self.l.iter().zip(self.dl).enumerate() {
            let s = self.ht * lv;
            let g = group_of_node(node, ncol);
            for comp in 0..n {
                let col = &mut self.block[(g * n + comp) * self.rows + self.at..][..n];
                for (o, x) in col.iter_mut().zip(&self.a[comp * n..(comp + 1) * n]) {
                    *o = s * x;
                }
                col[comp] += dv;
            }
        }
    }
}

/// $\xi = \sum_i L_i(z_c)\, x_i$ and $d = \sum_i L_i'(z_c)\, x_i$ over the nodes `x_i` (`N`
/// values each, consecutive in `nodes`), with the state dimension known at compile time: the
/// sums stay in registers.
#[inline(always)]
pub(super) fn interpolate<const N: usize>(
    nodes: &[f64],
    (l, dl): (&[f64], &[f64]),
    xi: &mut [f64],
    dx: &mut [f64],
) {
    let (mut s, mut d) = ([0.0; N], [0.0; N]);
    for ((x, &lv), &dv) in nodes.chunks_exact(N).zip(l).zip(dl) {
        for i in 0..N {
            s[i] += lv * x[i];
            d[i] += dv * x[i];
        }
    }
    xi.copy_from_slice(&s);
    dx.copy_from_slice(&d);
}

/// [`interpolate`] for any state dimension.
pub(super) fn interpolate_any(
    nodes: &[f64],
    (l, dl): (&[f64], &[f64]),
    xi: &mut [f64],
    dx: &mut [f64],
) {
    xi.fill(0.0);
    dx.fill(0.0);
    for ((x, &lv), &dv) in nodes.chunks_exact(xi.len()).zip(l).zip(dl) {
        for ((s, d), xv) in xi.iter_mut().zip(dx.iter_mut()).zip(x) {
            *s += lv * xv;
            *d += dv * xv;
        }
    }
}

/// The node whose `n` columns come `g`-th in an interval's block: the interior nodes
/// `1..ncol` first (the unknowns condensation eliminates), then node `0`, then node `ncol`.
pub(super) fn node_of_group(g: usize, ncol: usize) -> usize {
    match (g + 1).cmp(&ncol) {
        std::cmp::Ordering::Less => g + 1,
        std::cmp::Ordering::Equal => 0,
        std::cmp::Ordering::Greater => ncol,
    }
}

/// The inverse of [`node_of_group`].
pub(super) fn group_of_node(node: usize, ncol: usize) -> usize {
    if node == 0 {
        ncol - 1
    } else if node == ncol {
        ncol
    } else {
        node - 1
    }
}
