//! Grazing curves through the built-in admissibility events, on COCO's impact oscillator
//! (`examples/impact_oscillator/model.rs`, hand-coded Jacobians). Run with
//! `cargo bench --bench grazing_curves`.
//!
//! Benchmarked, on both discretisations: the grazing curve in `(A, w)` over `w` in
//! `[0.2, 1.58]` both ways from the default GR point that ends the impacting branch at
//! `w = 1` (the target: under a second, within `1e-9` of the closed form, which
//! `tests/integration/grazing_curves.rs` checks).

#[path = "../examples/impact_oscillator/model.rs"]
mod model;

use criterion::{Criterion, criterion_group, criterion_main};
use hycont::hycont_continuation::{CurveSpec, OrbitRun, RunDirection, SpecialKind};
use hycont::orbit::{CollocationSettings, OrbitMethod, ShootingSettings};
use model::{AMP, ImpactOscillator, W};
use std::hint::black_box;

fn grazing_curve(c: &mut Criterion) {
    // What users run: without the test suites' re-check of every branch.
    hycont::hycont_continuation::check_branches(false);
    let orbit = model::impacting_orbit().expect("the impacting orbit");
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
    let mut group = c.benchmark_group("impact_oscillator");
    group.sample_size(10);
    for (name, method) in methods {
        let mut run = OrbitRun::new(&ImpactOscillator, AMP).expect("a parameter");
        run.method(method).bounds(0.01, 2.0);
        let branch = run
            .run("impacting", &orbit, RunDirection::Down)
            .expect("the branch");
        let label = branch
            .first(SpecialKind::Grazing)
            .expect("a GR point")
            .point
            .label;
        let spec = CurveSpec::new(W).bounds(0.2, 1.58);
        group.bench_function(format!("grazing_curve_{name}"), |b| {
            b.iter(|| {
                let curve = run
                    .curve_at("grazing", &branch, label, &spec)
                    .expect("the grazing curve");
                black_box(curve.branch.points.len())
            });
        });
    }
    group.finish();
}

criterion_group!(benches, grazing_curve);
criterion_main!(benches);
