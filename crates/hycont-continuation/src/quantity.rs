//! What a branch point reports, by typed handle: parameters ([`ParamId`]) and measures
//! ([`MeasureId`]) in one index space ([`Quantity`]), and free labels for user events
//! ([`Label`]).

use crate::error::{Error, Result};
use hycont_core::ParamId;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// Handle of a measure (monitor) recorded at every point of a branch: an index into
/// [`crate::BranchPoint::monitors`] and [`crate::Branch::monitor_names`], tied to the measure's
/// name.
///
/// Orbit branches record [`MeasureId::PERIOD`], [`MeasureId::SHORTEST_SEGMENT`],
/// [`MeasureId::ADMISSIBLE_GRAZING`] and [`MeasureId::ADMISSIBLE_DOMAIN`] first, then the
/// measures added to the run ([`crate::OrbitRun::add_measure`] returns their handles).
///
/// A handle carries a key of its measure's name, so that one from another run (whose measure
/// at that index has another name) is caught where it is used: a run refuses it
/// ([`crate::Error::ForeignHandle`]) and a point does not read it ([`crate::BranchPoint::get`]
/// gives `None`, [`crate::BranchPoint::value`] the error). Handles of runs with the same
/// measures (a run restarted in another process, say) are interchangeable. Handles are equal
/// when their indices are; [`MeasureId::new`] and handles read from files are unchecked.
///
/// ```
/// use hycont_continuation::MeasureId;
/// let amp = MeasureId::named(4, "amp");
/// assert_eq!(amp.index(), 4);
/// assert_eq!(amp, MeasureId::new(4)); // the same slot, one of them unchecked
/// ```
#[derive(Debug, Clone, Copy)]
pub struct MeasureId {
    index: usize,
    /// [`name_key`] of the measure's name; 0: unchecked.
    key: u64,
}

/// A key of a measure's name (FNV-1a, never 0).
#[must_use]
pub(crate) const fn name_key(name: &str) -> u64 {
    let bytes = name.as_bytes();
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut i = 0;
    while i < bytes.len() {
        h ^= bytes[i] as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
        i += 1;
    }
    if h == 0 { 1 } else { h }
}

impl PartialEq for MeasureId {
    fn eq(&self, other: &Self) -> bool {
        self.index == other.index
    }
}

impl Eq for MeasureId {}

impl std::hash::Hash for MeasureId {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        self.index.hash(state);
    }
}

impl PartialOrd for MeasureId {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for MeasureId {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.index.cmp(&other.index)
    }
}

impl Serialize for MeasureId {
    fn serialize<Z: Serializer>(&self, s: Z) -> std::result::Result<Z::Ok, Z::Error> {
        self.index.serialize(s)
    }
}

impl<'de> Deserialize<'de> for MeasureId {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        Ok(MeasureId::new(usize::deserialize(d)?))
    }
}

impl MeasureId {
    /// The orbit's period (of the full orbit, also on half-orbit problems).
    pub const PERIOD: MeasureId = MeasureId::named(0, "period");
    /// The shortest segment's duration (zero where a segment collapses: a grazing).
    pub const SHORTEST_SEGMENT: MeasureId = MeasureId::named(1, "shortest_segment");
    /// The grazing margin of [`crate::OrbitRun::admissibility`] (zero at an interior touch of
    /// an event surface or a tangential impact).
    pub const ADMISSIBLE_GRAZING: MeasureId = MeasureId::named(2, "admissible_grazing");
    /// The domain margin of [`crate::OrbitRun::admissibility`] (zero where a segment ends on
    /// another event's surface).
    pub const ADMISSIBLE_DOMAIN: MeasureId = MeasureId::named(3, "admissible_domain");

    /// The handle of monitor `index` of a problem, unchecked (for problems built by hand).
    #[must_use]
    pub const fn new(index: usize) -> Self {
        Self { index, key: 0 }
    }

    /// The handle of monitor `index` named `name` (checked against the names of the runs and
    /// branches it is used with), e.g. an application's constant for a measure it always adds
    /// in the same place.
    #[must_use]
    pub const fn named(index: usize, name: &str) -> Self {
        Self {
            index,
            key: name_key(name),
        }
    }

    /// Index in the monitors.
    #[must_use]
    pub fn index(self) -> usize {
        self.index
    }

    /// Whether the handle fits a measure named `name` (unchecked handles fit any).
    #[must_use]
    pub fn fits(self, name: &str) -> bool {
        self.key == 0 || self.key == name_key(name)
    }

    /// Whether the handle fits the measure whose name has key `key` (0: unknown).
    pub(crate) fn fits_key(self, key: u64) -> bool {
        self.key == 0 || key == 0 || self.key == key
    }
}

/// A quantity reported at every point: a parameter or a measure.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Quantity {
    /// A parameter of the system.
    Parameter(ParamId),
    /// A measure recorded by the problem.
    Measure(MeasureId),
}

impl From<ParamId> for Quantity {
    fn from(p: ParamId) -> Self {
        Quantity::Parameter(p)
    }
}

impl From<MeasureId> for Quantity {
    fn from(m: MeasureId) -> Self {
        Quantity::Measure(m)
    }
}

impl std::fmt::Display for Quantity {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Quantity::Parameter(p) => write!(f, "parameter #{}", p.index()),
            Quantity::Measure(m) => write!(f, "measure #{}", m.index()),
        }
    }
}

/// Labels of the built-in special points, which user labels may not take.
pub(crate) const BUILT_IN: [&str; 14] = [
    "SN", "BP", "PD", "TR", "SB", "GR", "EP", "UZ", "CP", "R1", "LPPD", "R2", "LPNS", "PDNS",
];

/// A free label for user events (COCO's event labels, e.g. `"VZ"` for a vanishing impact
/// velocity): 1 to 8 ASCII letters, digits, `_` or `-`, not one of the built-in labels
/// (SN, BP, PD, TR, SB, GR, EP, UZ). Copyable and stored inline.
///
/// ```
/// use hycont_continuation::Label;
/// let vz = Label::new("VZ").unwrap();
/// assert_eq!(vz.as_str(), "VZ");
/// assert!(Label::new("SN").is_err());          // built in
/// assert!(Label::new("too_long_1").is_err());  // more than 8 characters
/// ```
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct Label {
    bytes: [u8; 8],
    len: u8,
}

impl Label {
    /// `DB`: the label of the points where an orbit reaches a domain boundary of its signature
    /// (a segment collapsing or ending on another event's surface; see
    /// [`crate::OrbitRun::admissibility`] and [`crate::SpecialKind::DOMAIN_BOUNDARY`]).
    pub const DB: Label = Label {
        bytes: *b"DB\0\0\0\0\0\0",
        len: 2,
    };

    /// A label from its text.
    ///
    /// # Errors
    /// [`Error::InvalidLabel`] naming the text if it is empty, too long, has other characters
    /// or is a built-in label.
    pub fn new(text: &str) -> Result<Self> {
        let bad = |reason: &'static str| {
            Err(Error::InvalidLabel {
                label: text.to_string(),
                reason,
            })
        };
        if text.is_empty() || text.len() > 8 {
            return bad("must have 1 to 8 characters");
        }
        if !text
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || b == b'_' || b == b'-')
        {
            return bad("may only hold ASCII letters, digits, '_' and '-'");
        }
        if BUILT_IN.contains(&text) {
            return bad("is a built-in label");
        }
        let mut bytes = [0u8; 8];
        bytes[..text.len()].copy_from_slice(text.as_bytes());
        Ok(Self {
            bytes,
            len: text.len() as u8,
        })
    }

    /// The text.
    #[must_use]
    pub fn as_str(&self) -> &str {
        // Validated ASCII on construction.
        std::str::from_utf8(&self.bytes[..usize::from(self.len)]).unwrap_or("?")
    }
}

impl std::fmt::Debug for Label {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Label({:?})", self.as_str())
    }
}

impl std::fmt::Display for Label {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

impl Serialize for Label {
    fn serialize<Z: Serializer>(&self, s: Z) -> std::result::Result<Z::Ok, Z::Error> {
        s.serialize_str(self.as_str())
    }
}

impl<'de> Deserialize<'de> for Label {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        let text = String::deserialize(d)?;
        Label::new(&text).map_err(serde::de::Error::custom)
    }
}
