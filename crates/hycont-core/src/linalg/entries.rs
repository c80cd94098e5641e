//! A pattern's `(row, col)` entries kept compactly, for the factorisations built from them
//! later (the fallback sparse LU of a condensed pattern, [`super::SparsePattern::matrix`]).

use crate::error::{Error, Result};

/// `(row, col)` entries in their order, as 32-bit indices: half the memory of `usize` pairs
/// (a large system's collocation pattern has millions of entries).
#[derive(Debug, Default)]
pub(super) struct Entries(Vec<(u32, u32)>);

impl Entries {
    /// The entries of an `nrows x ncols` pattern, checked to lie inside it.
    ///
    /// # Errors
    /// [`Error::InvalidSetting`] if an entry is out of range, or the matrix has more than
    /// $2^{32}$ rows or columns.
    pub(super) fn new(nrows: usize, ncols: usize, entries: &[(usize, usize)]) -> Result<Self> {
        let fits = |r: usize, c: usize| r < nrows && c < ncols;
        let (Ok(_), Ok(_)) = (
            u32::try_from(nrows.saturating_sub(1)),
            u32::try_from(ncols.saturating_sub(1)),
        ) else {
            return Err(Error::InvalidSetting {
                name: "sparse pattern",
                value: nrows.max(ncols) as f64,
                reason: "more than 2^32 rows or columns",
            });
        };
        if !entries.iter().all(|&(r, c)| fits(r, c)) {
            return Err(Error::InvalidSetting {
                name: "sparse pattern",
                value: entries.len() as f64,
                reason: "an entry is out of range",
            });
        }
        // In range of an index that fits: the casts are exact.
        Ok(Self(
            entries.iter().map(|&(r, c)| (r as u32, c as u32)).collect(),
        ))
    }

    /// The number of entries.
    pub(super) fn len(&self) -> usize {
        self.0.len()
    }

    /// The entries in order, as `usize` pairs.
    pub(super) fn iter(&self) -> impl ExactSizeIterator<Item = (usize, usize)> + '_ {
        self.0.iter().map(|&(r, c)| (r as usize, c as usize))
    }

    /// Whether `other` lists the same entries in the same order.
    pub(super) fn eq_pairs(&self, other: impl Iterator<Item = (usize, usize)>) -> bool {
        self.iter().eq(other)
    }

    /// The entries as `usize` pairs.
    pub(super) fn pairs(&self) -> Vec<(usize, usize)> {
        self.iter().collect()
    }
}

#[cfg(test)]
mod tests {
    use super::Entries;

    /// The entries come back as given, in order (duplicates too); out-of-range ones are
    /// refused, naming the pattern.
    #[test]
    fn entries_round_trip_and_are_checked() {
        let given = [(2, 0), (0, 1), (2, 0), (1, 2)];
        let e = Entries::new(3, 3, &given).unwrap();
        assert_eq!(e.len(), 4);
        assert_eq!(e.pairs(), given.to_vec());
        assert!(e.eq_pairs(given.iter().copied()));
        assert!(!e.eq_pairs(given[..3].iter().copied()));
        assert!(!e.eq_pairs(given.iter().copied().chain([(0, 0)])));
        assert!(!e.eq_pairs([(2, 0), (0, 1), (2, 0), (2, 1)].into_iter()));
        assert!(Entries::new(3, 3, &[(0, 3)]).is_err());
        assert!(Entries::new(3, 3, &[(3, 0)]).is_err());
        assert_eq!(Entries::new(0, 0, &[]).unwrap().len(), 0);
    }
}
