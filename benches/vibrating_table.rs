//! The library's workflow on a system that is not the rocking block: the bouncing ball on a
//! vibrating table (`examples/vibrating_table/model.rs`, derivatives by central differences as
//! in the example). Run with `cargo bench --bench vibrating_table`.
//!
//! Benchmarked, on both discretisations: the period-1 branch in the table amplitude `a` over
//! `[0.9, 1.8]` both ways from `a = 1.3` (its SN and PD located), the switch to period 2 at PD,
//! the PD curve in `(a, omega)` over `omega` in `[0.8, 1.25]` with two user points, and the
//! whole diagram to depth 3 (the period-doubling cascade to period 8).

#[path = "../examples/vibrating_table/model.rs"]
mod model;

use criterion::{Criterion, criterion_group, criterion_main};
use hycont::FiniteDifferences;
use hycont::hycont_continuation::{
    CurveSpec, DiagramSettings, OrbitBranch, OrbitRun, RunDirection, SpecialKind,
};
use hycont::orbit::{CollocationSettings, OrbitMethod, PeriodicOrbit, ShootingSettings};
use model::{A, OMEGA, Table};
use std::hint::black_box;

const E: f64 = 0.5;
const G: f64 = 1.0;

/// The stable period-1 orbit at `a = 1.3`, `omega = 1` from its closed-form post-impact state
/// (see `tests/integration/vibrating_table.rs`).
fn start(table: &FiniteDifferences<Table>) -> PeriodicOrbit {
    model::period_one(table, [1.3, 1.0, E, G]).expect("the start orbit")
}

fn amplitude_run(
    table: &FiniteDifferences<Table>,
    method: OrbitMethod,
) -> OrbitRun<'_, FiniteDifferences<Table>> {
    let mut run = OrbitRun::new(table, A).expect("a parameter of the table");
    run.method(method).bounds(0.9, 1.8);
    run
}

fn pd_label(branch: &OrbitBranch) -> usize {
    branch
        .special(SpecialKind::PeriodDoubling)
        .next()
        .expect("a PD on the branch")
        .point
        .label
}

fn workflow(c: &mut Criterion) {
    // What users run: without the test suites' re-check of every branch.
    hycont::hycont_continuation::check_branches(false);
    let table = FiniteDifferences::new(Table);
    let orbit = start(&table);
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
    for (name, method) in methods {
        let mut run = amplitude_run(&table, method);
        let branch = run
            .run("period-1", &orbit, RunDirection::Both)
            .expect("the branch");
        eprintln!(
            "{name}: {} points, {} special points",
            branch.branch.points.len(),
            branch.branch.special_points.len()
        );
        c.bench_function(&format!("vibrating_table/{name}/branch"), |b| {
            b.iter(|| black_box(run.run("period-1", &orbit, RunDirection::Both).unwrap()));
        });
        let pd = pd_label(&branch);
        c.bench_function(&format!("vibrating_table/{name}/switch_at_pd"), |b| {
            b.iter(|| {
                black_box(
                    run.switch_at("period-2", &branch, pd, RunDirection::Up)
                        .unwrap(),
                )
            });
        });
        let spec = CurveSpec::new(OMEGA)
            .bounds(0.8, 1.25)
            .user_points(OMEGA, [0.95, 1.05]);
        c.bench_function(&format!("vibrating_table/{name}/pd_curve"), |b| {
            b.iter(|| black_box(run.curve_at("PD", &branch, pd, &spec).unwrap()));
        });
        // The whole diagram: the period-1 branch and the cascade to period 8 (four branches).
        let settings = DiagramSettings {
            depth: 3,
            ..DiagramSettings::default()
        };
        c.bench_function(&format!("vibrating_table/{name}/diagram_depth_3"), |b| {
            b.iter(|| black_box(run.diagram("period-1", &orbit, &settings).unwrap()));
        });
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = workflow
}
criterion_main!(benches);
