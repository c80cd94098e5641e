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

    /// The Jacobian's entries in order, collected: each part's pattern, asked of it and mapped
    /// to the problem's rows and unknowns in place (one part's is the collection's storage),
    /// then the monitors' rows.
    pub(super) fn global_pattern(&self) -> Vec<(usize, usize)> {
        let total = self.pattern_len();
        let mut entries: Vec<(usize, usize)> = Vec::new();
        for part in &self.parts {
            let mut local = part.function.jacobian_pattern();
            for e in &mut local {
                *e = (part.row + e.0, part.unknowns[e.1]);
            }
            if entries.is_empty() {
                entries = local;
                entries.reserve_exact(total.saturating_sub(entries.len()));
            } else {
                entries.extend_from_slice(&local);
            }
        }
        entries.extend(self.monitor_entries());
        entries
    }

    /// The number of the Jacobian's entries.
    pub(super) fn pattern_len(&self) -> usize {
        self.parts.iter().map(|p| p.entries).sum::<usize>()
            + self
                .monitors
                .iter()
                .map(|m| m.unknowns.len() + usize::from(matches!(m.activity, Activity::Active(_))))
                .sum::<usize>()
    }

    /// The Jacobian's entries in order, without collecting them all (a large system's pattern
    /// has millions; each part's is asked of it in turn).
    pub(super) fn global_entries(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        let parts = self.parts.iter().flat_map(|part| {
            part.function
                .jacobian_pattern()
                .into_iter()
                .map(move |(r, c)| (part.row + r, part.unknowns[c]))
        });
        parts.chain(self.monitor_entries())
    }

    /// The monitors' rows' entries, after the parts'.
    fn monitor_entries(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        let row0 = self.equations() - self.monitors.len();
        let slots = self.active_slots();
        self.monitors.iter().enumerate().flat_map(move |(k, m)| {
            m.unknowns
                .iter()
                .map(move |&c| (row0 + k, c))
                .chain(slots[k].map(|slot| (row0 + k, slot)))
        })
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
    /// If the pattern is invalid, a part's pattern has another length than its
    /// [`ZeroFunction::jacobian_len`](crate::problem::ZeroFunction::jacobian_len), or a part's
    /// local blocks are invalid (out of range, overlapping, read by another block's equations).
    pub fn pattern(&mut self) -> Result<&mut SparsePattern> {
        if self.pattern.is_none() {
            let entries = self.global_pattern();
            if entries.len() != self.pattern_len() {
                return Err(crate::Error::InvalidSetting {
                    name: "jacobian_len",
                    value: entries.len() as f64,
                    reason: "a part's pattern has another length than it says",
                });
            }
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
    ///
    /// `self` is spent: its Jacobian's values (as large as its entries) are released first,
    /// before the comparison asks `other`'s parts for their entries.
    pub(crate) fn hand_pattern_to(&mut self, other: &mut Problem<'_>) -> bool {
        self.values = Vec::new();
        let Some(pattern) = self.pattern.as_ref() else {
            return false;
        };
        // Against the entries the pattern kept where it did (one of the two problems' patterns
        // is then asked of its parts, not both).
        let same = other.pattern.is_none()
            && (self.equations(), self.unknowns()) == (other.equations(), other.unknowns())
            && self.pattern_len() == other.pattern_len()
            && pattern
                .has_entries(other.global_entries())
                .unwrap_or_else(|| self.global_entries().eq(other.global_entries()))
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

    /// $F(u) = A u - b$ for a fixed matrix with the entries `pattern` (of which it may claim
    /// another number, `claimed`).
    struct Linear {
        pattern: Vec<(usize, usize)>,
        values: Vec<f64>,
        claimed: Option<usize>,
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
        fn jacobian_len(&self) -> usize {
            self.claimed.unwrap_or(self.pattern.len())
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
            claimed: None,
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

    /// A part that counts its entries wrongly is refused when the pattern is built (its values
    /// would be read against other entries), naming the setting; the problem and its pattern
    /// read each part's entries in order (two parts, the second's rows and unknowns shifted).
    #[test]
    fn parts_entries_are_counted_and_mapped_in_order() {
        let mut p = Problem::new(3);
        let lying = Linear {
            pattern: vec![(0, 0), (1, 1)],
            values: vec![1.0, 1.0],
            claimed: Some(3),
        };
        p.add_part(Box::new(lying), vec![0, 1]).unwrap();
        let err = p.pattern().unwrap_err();
        assert!(err.to_string().contains("jacobian_len"), "{err}");

        let mut p = problem(&[(0, 0), (1, 0), (1, 1)], &[1.0, 2.0, 3.0]);
        let second = Linear {
            pattern: vec![(0, 1), (0, 0)],
            values: vec![1.0, 1.0],
            claimed: None,
        };
        p.add_part(Box::new(second), vec![1, 0]).unwrap();
        let expected = vec![(0, 0), (1, 0), (1, 1), (2, 0), (2, 1)];
        assert_eq!(p.jacobian_entries(), expected);
        assert!(p.global_entries().eq(expected.iter().copied()));
        assert_eq!(p.pattern_len(), 5);
    }
}
