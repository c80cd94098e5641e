//! How the cost of a branch point grows with the state dimension: the impacting period-1
//! orbits of a chain of `N` masses against a stop (`examples/impact_chain/model.rs`, state
//! dimension `n = 2N + 2`), continued in the forcing frequency `w` from the exact orbit
//! (`reference.rs`) with a fixed step, for N = 1, 2, 5, 10, 25, 50, by multiple shooting and
//! by collocation (NTST 20, NCOL 4). Throughput in points: criterion's time per element is
//! the time per branch point; `.../two` times a run of two points (set-up, the start, one
//! step), so that `(T_branch - T_two) / (points - 2)` is the cost of a step. Run with `cargo bench --bench impact_chain` (one size:
//! `cargo bench --bench impact_chain -- /50`).
//!
//! Targets (issue 39): at N = 50 a point in at most 50 ms by shooting and 200 ms by
//! collocation on a 2-core machine; from N = 10 to 50 no steeper than n^2 by shooting.

#[path = "../examples/impact_chain/model.rs"]
mod model;
#[path = "../examples/impact_chain/reference.rs"]
#[allow(dead_code)]
mod reference;
#[path = "../examples/impact_chain/setup.rs"]
mod setup;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use hycont::hycont_continuation::{OrbitMethod, OrbitRun, RunDirection};
use hycont::orbit::{CollocationSettings, PeriodicOrbit, ShootingSettings};
use model::{ImpactChain, W};
use std::hint::black_box;

/// Points of each benchmarked branch.
const POINTS: usize = 6;

/// The branch from `orbit` up in `w` with a fixed step, of at most `points` points; its
/// number of points.
fn branch(chain: &ImpactChain, orbit: &PeriodicOrbit, method: OrbitMethod, points: usize) -> usize {
    let mut run = OrbitRun::new(chain, W).expect("a parameter");
    run.method(method).max_points(points);
    run.steps(1e-3, 1e-3, 1e-3);
    run.run("impacting", orbit, RunDirection::Up)
        .expect("the branch")
        .branch
        .points
        .len()
}

fn growth(c: &mut Criterion) {
    hycont::hycont_continuation::check_branches(false);
    let methods = [
        (
            "shooting",
            OrbitMethod::Shooting(ShootingSettings::default()),
        ),
        (
            "collocation",
            OrbitMethod::Collocation(CollocationSettings::default()),
        ),
    ];
    let mut group = c.benchmark_group("impact_chain");
    group.sample_size(10);
    for n in setup::SIZES {
        let chain = ImpactChain { masses: n };
        let orbit = setup::exact_orbit(n).expect("an impacting orbit");
        for (name, method) in methods {
            let points = branch(&chain, &orbit, method, POINTS);
            group.throughput(Throughput::Elements(points as u64));
            group.bench_function(format!("{name}/{n}"), |b| {
                b.iter(|| black_box(branch(&chain, &orbit, method, POINTS)));
            });
            // The start and one step (the run's set-up, the start's correction and analysis):
            // the branch's time less this, over its other points, is the cost of a step.
            group.throughput(Throughput::Elements(2));
            group.bench_function(format!("{name}/{n}/two"), |b| {
                b.iter(|| black_box(branch(&chain, &orbit, method, 2)));
            });
        }
    }
    group.finish();
}

criterion_group!(benches, growth);
criterion_main!(benches);
