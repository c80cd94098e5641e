//! The Jacobian's structure: its entries, the parts' elimination blocks, and the sparse
//! pattern built from them once (and handed to a problem of the same structure).

use super::{Activity, Problem};
use crate::error::Result;
use crate::linalg::{EliminationBlock, SparsePattern};

impl Problem<'_> {
    /// The Jacobian's `(row, col)` entries, in the order [`Problem::evaluate`] produces values.
    #[must_use]
    pub fn jacobian_entries(&self) -> Vec<(usize, usize)> {
        self.global_pattern()
    }

    pub(super) fn global_pattern(&self) -> Vec<(usize, usize)> {
        let mut entries = Vec::with_capacity(self.pattern_len());
        entries.extend(self.global_entries());
        entries
    }

    /// The number of the Jacobian's entries.
    pub(super) fn pattern_len(&self) -> usize {
        self.parts.iter().map(|p| p.pattern.len()).sum::<usize>()
            + self
                .monitors
                .iter()
                .map(|m| m.unknowns.len() + usize::from(matches!(m.activity, Activity::Active(_))))
                .sum::<usize>()
    }

    /// The Jacobian's entries in order, without collecting them (a large system's pattern has
    /// millions).
    pub(super) fn global_entries(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        let parts = self.parts.iter().flat_map(|part| {
            part.pattern
                .iter()
                .map(move |&(r, c)| (part.row + r, part.unknowns[c]))
        });
        let row0 = self.equations() - self.monitors.len();
        let slots = self.active_slots();
        let monitors = self.monitors.iter().enumerate().flat_map(move |(k, m)| {
            m.unknowns
                .iter()
                .map(move |&c| (row0 + k, c))
                .chain(slots[k].map(|slot| (row0 + k, slot)))
        });
        parts.chain(monitors)
    }

    /// The parts' [`LocalBlock`](crate::problem::LocalBlock)s in the problem's rows and unknowns.
    #[must_use]
    pub fn elimination_blocks(&self) -> Vec<EliminationBlock> {
        self.parts
            .iter()
            .flat_map(|part| {
                // Indices outside the part become out of range (refused by the pattern).
                let rows = part.function.equations();
                part.function
                    .local_blocks()
                    .into_iter()
                    .map(move |b| EliminationBlock {
                        rows: b
                            .equations
                            .map(|r| if r < rows { part.row + r } else { usize::MAX })
                            .collect(),
                        cols: b
                            .unknowns
                            .map(|c| part.unknowns.get(c).copied().unwrap_or(usize::MAX))
                            .collect(),
                    })
            })
            .collect()
    }

    /// The sparse pattern of the Jacobian (built, with its symbolic analysis, on first use);
    /// a square problem condenses its parts' [`LocalBlock`](crate::problem::LocalBlock)s.
    ///
    /// # Errors
    /// If the pattern is invalid, or a part's local blocks are (out of range, overlapping, read
    /// by another block's equations).
    pub fn pattern(&mut self) -> Result<&mut SparsePattern> {
        if self.pattern.is_none() {
            let entries = self.global_pattern();
            let (m, n) = (self.equations(), self.unknowns());
            let blocks = if m == n {
                self.elimination_blocks()
            } else {
                Vec::new()
            };
            self.pattern = Some(SparsePattern::with_blocks_owned(m, n, entries, &blocks)?);
        }
        Ok(self.pattern.as_mut().expect("pattern built above"))
    }

    /// Moves this problem's sparsity pattern (with its symbolic analysis and condensed layout)
    /// to `other` if `other` has the same Jacobian structure (entries and elimination blocks),
    /// e.g. the same collocation problem on another mesh with as many intervals: `other` is
    /// then spared the build. Returns whether it moved.
    pub(crate) fn hand_pattern_to(&mut self, other: &mut Problem<'_>) -> bool {
        let same = self.pattern.is_some()
            && other.pattern.is_none()
            && (self.equations(), self.unknowns()) == (other.equations(), other.unknowns())
            && self.pattern_len() == other.pattern_len()
            && self.global_entries().eq(other.global_entries())
            && self.elimination_blocks() == other.elimination_blocks();
        if same {
            other.pattern = self.pattern.take();
        }
        same
    }
}

#[cfg(test)]
mod tests {
    use super::Problem;
    use crate::problem::ZeroFunction;

    /// $F(u) = A u - b$ for a fixed matrix with the entries `pattern`.
    struct Linear {
        pattern: Vec<(usize, usize)>,
        values: Vec<f64>,
    }

    impl ZeroFunction for Linear {
        fn unknowns(&self) -> usize {
            2
        }
        fn equations(&self) -> usize {
            2
        }
        fn jacobian_pattern(&self) -> Vec<(usize, usize)> {
            self.pattern.clone()
        }
        fn evaluate(
            &mut self,
            u: &[f64],
            r: &mut [f64],
            j: Option<&mut [f64]>,
        ) -> crate::Result<()> {
            r.copy_from_slice(&[-1.0, -2.0]);
            for (&(i, k), v) in self.pattern.iter().zip(&self.values) {
                r[i] += v * u[k];
            }
            if let Some(j) = j {
                j.copy_from_slice(&self.values);
            }
            Ok(())
        }
    }

    fn problem<'a>(pattern: &[(usize, usize)], values: &[f64]) -> Problem<'a> {
        let mut p = Problem::new(2);
        let part = Linear {
            pattern: pattern.to_vec(),
            values: values.to_vec(),
        };
        p.add_part(Box::new(part), vec![0, 1]).unwrap();
        p
    }

    /// The pattern moves only between problems of the same structure, and the receiving
    /// problem factorises and solves with it: $A = \mathrm{diag}(2, 4)$, $b = (1, 2)$ gives
    /// the Newton step from 0 to $(1/2, 1/2)$.
    #[test]
    fn a_pattern_moves_to_a_problem_of_the_same_structure_only() {
        let diag = [(0, 0), (1, 1)];
        let mut first = problem(&diag, &[1.0, 1.0]);
        first.pattern().unwrap();
        let mut other = problem(&[(0, 0), (1, 1), (0, 1)], &[2.0, 4.0, 0.0]);
        assert!(!first.hand_pattern_to(&mut other));
        let mut same = problem(&diag, &[2.0, 4.0]);
        assert!(first.hand_pattern_to(&mut same));
        assert!(first.pattern.is_none() && same.pattern.is_some());
        let mut r = vec![0.0; 2];
        same.factorize(&[0.0, 0.0], &mut r).unwrap();
        same.solve_in_place(&mut r).unwrap();
        assert_eq!(r, vec![-0.5, -0.5]);
        // Nothing to hand on any more.
        assert!(!first.hand_pattern_to(&mut problem(&diag, &[1.0, 1.0])));
    }
}
