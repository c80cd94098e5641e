//! Studies from text, as a command line gives them: a variable's distribution as `VALUE` or
//! `LO:HI` ([`Distribution`]'s `FromStr`), a binning axis as `NAME:BINS` ([`Axis::parse`]).

use crate::basin::{Axis, Distribution};
use crate::error::{Error, Result};
use std::str::FromStr;

/// Most bins an axis parsed from text may have.
const MAX_BINS: usize = 10_000;

impl FromStr for Distribution {
    type Err = Error;

    /// `VALUE` (fixed) or `LO:HI` (uniform on `[LO, HI)`, `LO < HI`), finite numbers.
    ///
    /// ```
    /// use hycont_sample::basin::Distribution;
    /// assert_eq!("1.5".parse::<Distribution>().unwrap(), Distribution::Fixed(1.5));
    /// assert_eq!(
    ///     "-1:2".parse::<Distribution>().unwrap(),
    ///     Distribution::Uniform { lo: -1.0, hi: 2.0 }
    /// );
    /// assert!("2:1".parse::<Distribution>().is_err() && "inf".parse::<Distribution>().is_err());
    /// ```
    ///
    /// # Errors
    /// [`Error::InvalidSpec`]: not a finite number or `LO:HI`, or `LO >= HI`.
    fn from_str(text: &str) -> Result<Self> {
        let bad = |reason| Error::InvalidSpec {
            spec: text.to_string(),
            reason,
        };
        let number = |t: &str| {
            t.trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| bad("expected a finite number or LO:HI"))
        };
        match text.split_once(':') {
            None => Ok(Distribution::Fixed(number(text)?)),
            Some((lo, hi)) => {
                let (lo, hi) = (number(lo)?, number(hi)?);
                if lo < hi {
                    Ok(Distribution::Uniform { lo, hi })
                } else {
                    Err(bad("LO must be below HI"))
                }
            }
        }
    }
}

impl Axis {
    /// The axis of `NAME:BINS`: `BINS` (1 to 10,000) bins over the range of the uniform
    /// variable `NAME` (one of `names`, drawn from `variables`).
    ///
    /// ```
    /// use hycont_sample::basin::{Axis, Distribution};
    /// let names = ["x".to_string(), "y".to_string()];
    /// let vars = [Distribution::Fixed(1.0), Distribution::Uniform { lo: 0.0, hi: 2.0 }];
    /// let axis = Axis::parse("y:8", &names, &vars).unwrap();
    /// assert_eq!(axis, Axis { variable: 1, lo: 0.0, hi: 2.0, bins: 8 });
    /// assert!(Axis::parse("x:8", &names, &vars).is_err()); // fixed: nothing to bin
    /// ```
    ///
    /// # Errors
    /// [`Error::InvalidSpec`]: not `NAME:BINS`, an unknown name, bins out of range, or a
    /// fixed variable.
    pub fn parse(spec: &str, names: &[String], variables: &[Distribution]) -> Result<Self> {
        let bad = |reason| Error::InvalidSpec {
            spec: spec.to_string(),
            reason,
        };
        let (name, bins) = spec
            .split_once(':')
            .ok_or_else(|| bad("expected NAME:BINS"))?;
        let variable = (names.iter().position(|v| v == name.trim()))
            .filter(|&v| v < variables.len())
            .ok_or_else(|| bad("NAME must be one of the study's variables"))?;
        let bins: usize = (bins.trim().parse().ok())
            .filter(|b| (1..=MAX_BINS).contains(b))
            .ok_or_else(|| bad("BINS must be in 1..=10000"))?;
        match variables[variable] {
            Distribution::Uniform { lo, hi } => Ok(Axis {
                variable,
                lo,
                hi,
                bins,
            }),
            Distribution::Fixed(_) => Err(bad("bin a variable drawn from a range (LO:HI)")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reason(e: Error) -> &'static str {
        match e {
            Error::InvalidSpec { reason, .. } => reason,
            other => panic!("{other}"),
        }
    }

    #[test]
    fn bad_distributions_name_what_is_wrong() {
        for (text, why) in [
            ("abc", "finite number"),
            ("1:nan", "finite number"),
            ("1e999", "finite number"),
            ("1:1", "below"),
            ("", "finite number"),
        ] {
            let e = text.parse::<Distribution>().unwrap_err();
            assert!(reason(e).contains(why), "{text}");
        }
    }

    #[test]
    fn bad_axes_name_what_is_wrong() {
        let names = ["a".to_string(), "b".to_string()];
        let vars = [
            Distribution::Uniform { lo: 0.0, hi: 1.0 },
            Distribution::Fixed(0.0),
        ];
        for (spec, why) in [
            ("a", "NAME:BINS"),
            ("c:3", "NAME must be"),
            ("a:0", "BINS"),
            ("a:10001", "BINS"),
            ("a:x", "BINS"),
            ("b:3", "range"),
        ] {
            let e = Axis::parse(spec, &names, &vars).unwrap_err();
            assert!(reason(e).contains(why), "{spec}");
        }
        let ok = Axis::parse(" a : 10000", &names, &vars).unwrap();
        assert_eq!(ok.bins, 10_000);
    }
}
