// The impact chain's study settings (shared by the example, the tests and the bench): the
// sizes, the parameters of each size and its exact impacting orbit as a `PeriodicOrbit`.

use super::model::{FREE, IMPACT, ImpactChain};
use super::reference;
use hycont::orbit::{PeriodicOrbit, SegmentEnd, SegmentSpec, Signature};

/// The chain lengths studied (state dimension 4 to 102).
pub const SIZES: [usize; 6] = [1, 2, 5, 10, 25, 50];

/// The stop's distance as a fraction of the free response's amplitude at the last mass.
pub const GAP_RATIO: f64 = 0.9;

/// The parameters `(k, c, A, w, d, e)` of the chain of `n` masses: `k = 1`, `c = 0.1`,
/// `A = 1`, `w = 1.3`, `e = 0.8` and the stop at [`GAP_RATIO`] of the free response's
/// amplitude `|Z_{x_N}|` at the last mass (so that the chain impacts once a period).
pub fn parameters(n: usize) -> Vec<f64> {
    let mut p = vec![1.0, 0.1, 1.0, 1.3, 0.0, 0.8];
    p[4] = GAP_RATIO * reference::response(n, &p)[n - 1].norm();
    p
}

/// The impacting orbit's one segment: a flight ended by the impact.
pub fn signature(chain: &ImpactChain) -> Result<Signature, hycont::Error> {
    let segment = SegmentSpec {
        mode: FREE,
        end: SegmentEnd::Event(IMPACT),
    };
    Signature::new(chain, vec![segment])
}

/// The exact physical impacting orbit of the chain of `n` masses at [`parameters`] (the
/// first, where both are).
pub fn exact_orbit(n: usize) -> Result<PeriodicOrbit, hycont::Error> {
    let p = parameters(n);
    let chain = ImpactChain { masses: n };
    let exact = reference::exact_orbits(n, &p)
        .into_iter()
        .find(|o| reference::is_physical(n, &p, o))
        .expect("a physical impacting orbit at the chain's parameters");
    PeriodicOrbit::new(
        &chain,
        signature(&chain)?,
        vec![exact.start],
        vec![exact.period],
        p,
    )
}
