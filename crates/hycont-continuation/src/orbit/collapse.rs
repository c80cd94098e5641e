//! Collapsing segments: where a continuation meets a segment of zero duration, whether the
//! collapse is a grazing (the flow meets the segment's end surface tangentially: two events
//! merging at zero speed, GR) or a crossing of another event's surface (DB).

use hycont_core::HybridJacobians;

/// A duration this close to zero (absolute) is a collapsed segment at a located collapse.
pub(super) const COLLAPSED: f64 = 1e-8;

/// The collapsed segment of `orbit` (its shortest, within [`COLLAPSED`] of zero), if any.
pub(super) fn collapsed_segment(orbit: &hycont_core::orbit::PeriodicOrbit) -> Option<usize> {
    (orbit.durations.iter().enumerate())
        .min_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
        .filter(|(_, d)| d.abs() <= COLLAPSED)
        .map(|(k, _)| k)
}

/// Whether the collapsed segment `k` of `orbit` ends at an event whose surface the flow of its
/// mode touches tangentially at the segment's start ($|\nabla h \cdot f| \le 10^{-6}
/// |\nabla h| |f|$): a grazing, where the segment's duration behaves like a square root of the
/// parameter distance and holding it at zero is singular.
pub(super) fn collapses_tangentially<S: HybridJacobians + ?Sized>(
    system: &S,
    orbit: &hycont_core::orbit::PeriodicOrbit,
    k: usize,
) -> bool {
    let seg = orbit.signature.segments()[k];
    let hycont_core::orbit::SegmentEnd::Event(e) = seg.end else {
        return false;
    };
    let x = &orbit.starts[k];
    let n = x.len();
    let (mut f, mut g) = (vec![0.0; n], vec![0.0; n]);
    system.vector_field(seg.mode, x, &orbit.params, &mut f);
    system.event_gradient(e, x, &orbit.params, &mut g, None);
    let rate: f64 = f.iter().zip(&g).map(|(a, b)| a * b).sum();
    let norm = |v: &[f64]| v.iter().map(|a| a * a).sum::<f64>().sqrt();
    rate.abs() <= 1e-6 * norm(&f) * norm(&g)
}
