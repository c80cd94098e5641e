//! Zeno detection: the times between consecutive jumps, and when they accumulate.

use super::{ZenoRecord, ZenoSettings};

/// A run's Zeno bookkeeping: the jumps watched since the last transition, and the transitions.
#[derive(Debug, Default)]
pub(super) struct Zeno {
    pub(super) watch: ZenoWatch,
    pub(super) log: Vec<ZenoRecord>,
}

/// The jumps of a run so far, for Zeno detection ([`ZenoSettings`]).
#[derive(Debug, Default, Clone, Copy)]
pub(super) struct ZenoWatch {
    last_jump: Option<f64>,
    last_interval: Option<f64>,
    /// Consecutive intervals that contracted by at most [`ZenoSettings::max_ratio`].
    contracting: usize,
}

impl ZenoWatch {
    /// Records a jump at `te`; returns the predicted accumulation time when the jumps
    /// accumulate: [`ZenoSettings::min_contracting`] contracting intervals in a row with the
    /// geometric remainder $\Delta t\, r / (1 - r)$ within [`ZenoSettings::horizon`], or an
    /// interval below [`ZenoSettings::min_interval`] (relative). The time is `te` itself where
    /// the remainder is not a finite, non-negative number.
    pub(super) fn jump_at(&mut self, te: f64, zeno: &ZenoSettings) -> Option<f64> {
        let previous = self.last_jump.replace(te)?;
        let interval = te - previous;
        let mut ratio = f64::NAN;
        if let Some(prev_interval) = self.last_interval {
            ratio = interval / prev_interval;
            if ratio <= zeno.max_ratio {
                self.contracting += 1;
            } else {
                self.contracting = 0;
            }
        }
        self.last_interval = Some(interval);
        let remaining = interval * ratio / (1.0 - ratio);
        let accumulates = (self.contracting >= zeno.min_contracting && remaining <= zeno.horizon)
            || interval <= zeno.min_interval * te.abs().max(1.0);
        accumulates.then(|| {
            if remaining.is_finite() && remaining >= 0.0 {
                te + remaining
            } else {
                te
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Jumps at $t_k = 1 - r^k$ (intervals $r^{k-1}(1 - r)$, ratio $r$) accumulate at 1: after
    /// [`ZenoSettings::min_contracting`] contracting ratios the prediction is
    /// $t_k + r^k = 1$ once the remainder $r^k$ is within the horizon.
    #[test]
    fn geometric_jumps_accumulate_at_their_limit() {
        let zeno = ZenoSettings {
            horizon: 1e-3,
            ..ZenoSettings::default()
        };
        let r: f64 = 0.5;
        let mut watch = ZenoWatch::default();
        let mut found = None;
        for k in 0..40 {
            let t = 1.0 - r.powi(k);
            if let Some(t_acc) = watch.jump_at(t, &zeno) {
                found = Some((k, t_acc));
                break;
            }
        }
        let (k, t_acc) = found.expect("accumulation detected");
        // Remainder r^k <= 1e-3 first at k = 10; contracting ratios from the third jump on.
        assert_eq!(k, 10);
        assert!((t_acc - 1.0).abs() < 1e-12, "{t_acc}");
    }

    /// Jumps at a constant interval never accumulate; the relative floor on the interval
    /// catches a repeated jump time at once.
    #[test]
    fn periodic_jumps_do_not_accumulate_and_a_repeat_does() {
        let zeno = ZenoSettings::default();
        let mut watch = ZenoWatch::default();
        for k in 0..100 {
            assert_eq!(watch.jump_at(0.1 * f64::from(k), &zeno), None);
        }
        let last = 0.1 * f64::from(99);
        assert_eq!(watch.jump_at(last, &zeno), Some(last));
    }
}
