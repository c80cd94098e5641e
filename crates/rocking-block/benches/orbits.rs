//! Periodic-orbit benchmarks (issue: orbits). Run with `cargo bench -p rocking-block --bench orbits`.
//!
//! One Newton solve of the symmetric orbit at (omega, alpha) = (1.3, 0.66) from the converged
//! orbit at omega = 1.31, on a problem built once (pattern and symbolic LU reused, as along a
//! branch): collocation with NTST 40 in all (20 per flight, two flights) and NCOL 4, and multiple
//! shooting on the two flights. Reference: AUTO-07p spends ~1.5 ms per continuation point on this
//! orbit (NTST 40, NCOL 4). Also the cost of the multipliers.

use criterion::{Criterion, criterion_group, criterion_main};
use hycont_core::orbit::{
    CollocationSettings, ShootingSettings, collocation_problem, monodromy_by_shooting, pack,
    shooting_problem, solve_collocation,
};
use hycont_core::problem::{Activity, NewtonSettings, newton};
use rocking_block::orbits::{OrbitKind, orbit};
use rocking_block::{Parameters, RockingBlock};
use std::hint::black_box;

fn symmetric_orbit_solves(c: &mut Criterion) {
    // What users run: without the test suites' re-check of every branch.
    hycont_continuation::check_branches(false);
    let params = Parameters::new(1.3, 0.66);
    let flights = orbit(&params, OrbitKind::Symmetric, None)
        .unwrap()
        .solution
        .orbit
        .without_interior_points(&RockingBlock)
        .unwrap();
    let newton_settings = NewtonSettings::default();

    // Collocation: converge at omega = 1.31, then time the solve back to 1.30.
    let settings = CollocationSettings {
        ntst: 20,
        ncol: 4,
        adapt: 0,
    };
    let coll = solve_collocation(&RockingBlock, &flights, settings, &newton_settings).unwrap();
    let mut problem =
        collocation_problem(&RockingBlock, &coll.solution.orbit, coll.meshes.clone(), 4).unwrap();
    let omega = problem.monitor_id("omega").unwrap();
    problem
        .set_activity(omega, Activity::Inactive(1.31))
        .unwrap();
    let near = newton(&mut problem, &coll.unknowns(), &newton_settings)
        .unwrap()
        .u;
    problem
        .set_activity(omega, Activity::Inactive(1.30))
        .unwrap();
    let probe = newton(&mut problem, &near, &newton_settings).unwrap();
    eprintln!(
        "collocation: {} unknowns, {} iterations ({} factorisations)",
        problem.unknowns(),
        probe.history.len(),
        probe.factorizations()
    );
    c.bench_function("symmetric_orbit/newton_collocation_ntst40_ncol4", |b| {
        b.iter(|| black_box(newton(&mut problem, black_box(&near), &newton_settings).unwrap()));
    });

    // Shooting on the two flights.
    let mut shoot = shooting_problem(&RockingBlock, &flights, ShootingSettings::default()).unwrap();
    let omega = shoot.monitor_id("omega").unwrap();
    shoot.set_activity(omega, Activity::Inactive(1.31)).unwrap();
    let near = newton(&mut shoot, &pack(&flights), &newton_settings)
        .unwrap()
        .u;
    shoot.set_activity(omega, Activity::Inactive(1.30)).unwrap();
    let probe = newton(&mut shoot, &near, &newton_settings).unwrap();
    eprintln!(
        "shooting: {} unknowns, {} iterations ({} factorisations)",
        shoot.unknowns(),
        probe.history.len(),
        probe.factorizations()
    );
    c.bench_function("symmetric_orbit/newton_shooting", |b| {
        b.iter(|| black_box(newton(&mut shoot, black_box(&near), &newton_settings).unwrap()));
    });

    // Multipliers.
    c.bench_function("symmetric_orbit/multipliers_shooting", |b| {
        b.iter(|| {
            black_box(
                monodromy_by_shooting(
                    &RockingBlock,
                    black_box(&flights),
                    ShootingSettings::default(),
                )
                .unwrap(),
            )
        });
    });
    c.bench_function("symmetric_orbit/multipliers_collocation_condensed", |b| {
        b.iter(|| black_box(coll.floquet(&RockingBlock).unwrap()));
    });
}

criterion_group!(benches, symmetric_orbit_solves);
criterion_main!(benches);
