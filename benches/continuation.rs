//! Continuation benchmarks (issue: continuation). Run with `cargo bench --bench continuation`.
//!
//! All branches of Figs. 3 and 4 with every special point located (the target: both together in
//! under 0.5 s), and all curves of Fig. 6 (target: under 2 s). Reference: AUTO-07p continues the symmetric omega branch (223 points, NTST 40,
//! NCOL 4) in 0.32-0.39 s on the project machine, ~1.5 ms a point.

use criterion::{Criterion, criterion_group, criterion_main};
use hycont::rocking_block::continuation::{Free, study_branches, study_curves};
use hycont_continuation::RunStatistics;
use hycont_continuation::observe::Silent;
use std::hint::black_box;

fn figures_3_and_4(c: &mut Criterion) {
    for free in [Free::Omega, Free::Alpha] {
        let t = std::time::Instant::now();
        let branches = study_branches(free, &mut Silent).unwrap();
        let elapsed = t.elapsed();
        let points: usize = branches
            .iter()
            .map(|b| b.points.len() + b.special_points.len())
            .sum();
        let iterations: usize = branches
            .iter()
            .flat_map(|b| b.points.iter().map(|p| p.newton_iterations))
            .sum();
        let work = branches
            .iter()
            .fold(RunStatistics::default(), |acc, b| acc + b.statistics);
        eprintln!(
            "{}: {} branches, {points} points (incl. special), {iterations} corrector iterations, \
             {:.3} ms per point (one run {elapsed:?}); {work:?}",
            free.name(),
            branches.len(),
            1e3 * elapsed.as_secs_f64() / points as f64
        );
    }
    c.bench_function("continuation/figure_3_and_4_branches", |b| {
        b.iter(|| {
            black_box(study_branches(Free::Omega, &mut Silent).unwrap());
            black_box(study_branches(Free::Alpha, &mut Silent).unwrap());
        });
    });
}

fn figure_6_curves(c: &mut Criterion) {
    let t = std::time::Instant::now();
    let curves = study_curves(&mut Silent).unwrap();
    let elapsed = t.elapsed();
    for cv in &curves {
        eprintln!(
            "{} curve: {} points",
            cv.kind.label(),
            cv.branch.points.len()
        );
    }
    let points: usize = curves.iter().map(|c| c.branch.points.len()).sum();
    eprintln!(
        "all curves (with the Fig. 3/4 branches they start from): {points} points in {elapsed:?}"
    );
    c.bench_function("continuation/figure_6_curves", |b| {
        b.iter(|| black_box(study_curves(&mut Silent).unwrap()));
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = figures_3_and_4, figure_6_curves
}
criterion_main!(benches);
