//! Two-dimensional atlases: the vibrating table's stable period-one orbits over `(a, omega)`
//! (`examples/vibrating_table/model.rs`, exact derivatives by `AutoDiff`), covered up to the
//! fold and the period doubling and the bounds `omega` in [0.8, 1.25], `a <= 1.8`, by both
//! discretisations (the family of `tests/integration/atlas.rs`). Run with `cargo bench --bench atlas`.

#[path = "../examples/vibrating_table/model.rs"]
mod model;

use criterion::{Criterion, criterion_group, criterion_main};
use hycont::AutoDiff;
use hycont::hycont_continuation::OrbitRun;
use hycont::hycont_continuation::atlas::{AtlasEdges, AtlasSettings};
use hycont::orbit::{CollocationSettings, OrbitMethod, PeriodicOrbit, ShootingSettings};
use model::{A, OMEGA, TableModel};
use std::hint::black_box;

/// The stable period-one orbit at `a = 1.3`, `omega = 1` (`e = 1/2`, `g = 1`).
fn start(table: &AutoDiff<TableModel>) -> PeriodicOrbit {
    model::period_one(table, [1.3, 1.0, 0.5, 1.0]).expect("the orbit")
}

fn atlases(c: &mut Criterion) {
    hycont::hycont_continuation::check_branches(false);
    let table = AutoDiff::new(TableModel);
    let orbit = start(&table);
    let settings = AtlasSettings::default()
        .radii(0.1, 1e-3, 0.2)
        .bound(OMEGA, 0.8, 1.25)
        .bound(A, 0.0, 1.8)
        .edges(AtlasEdges {
            period_doubling: true,
            ..AtlasEdges::default()
        });
    let mut group = c.benchmark_group("atlas");
    group.sample_size(10);
    for (name, method) in [
        (
            "table_shooting",
            OrbitMethod::Shooting(ShootingSettings::default()),
        ),
        (
            "table_collocation",
            OrbitMethod::Collocation(CollocationSettings::default()),
        ),
    ] {
        let mut run = OrbitRun::new(&table, A).expect("a parameter");
        run.method(method);
        group.bench_function(name, |b| {
            b.iter(|| {
                let atlas = run
                    .atlas("period-1", &orbit, OMEGA, &settings)
                    .expect("the atlas");
                black_box(atlas.atlas.charts.len())
            });
        });
    }
    group.finish();
}

criterion_group!(benches, atlases);
criterion_main!(benches);
