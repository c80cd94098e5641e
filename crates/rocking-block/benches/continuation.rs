//! Continuation benchmarks (issue: continuation). Run with `cargo bench -p rocking-block --bench continuation`.
//!
//! All branches of Figs. 3 and 4 with every special point located, from their common start (the
//! Fig. 2 orbit, found once; issue 13's target: both together under 0.05 s), and all curves of
//! Fig. 6 (target: under 2 s). Reference: AUTO-07p continues the symmetric omega branch (223 points, NTST 40,
//! NCOL 4) in 0.32-0.39 s on the project machine, ~1.5 ms a point.

use criterion::{Criterion, criterion_group, criterion_main};
use hycont_continuation::observe::Silent;
use hycont_continuation::{DiagramSettings, RunStatistics};
use rocking_block::block::Block;
use rocking_block::continuation::{
    Free, Recipe, study_branches, study_branches_from, study_curves, study_diagram, study_start,
};
use std::hint::black_box;

fn figures_3_and_4(c: &mut Criterion) {
    // What users run: without the test suites' re-check of every branch.
    hycont_continuation::check_branches(false);
    for free in [Free::Omega, Free::Alpha] {
        let t = std::time::Instant::now();
        let branches = study_branches(free, &Block::default(), &mut Silent).unwrap();
        let elapsed = t.elapsed();
        let branches: Vec<_> = branches.into_iter().map(|b| b.branch).collect();
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
    // Both figures from their common start, the Fig. 2 orbit, found once (its search over 432
    // seeds is about a tenth of the time); as `study_curves` does.
    c.bench_function("continuation/figure_3_and_4_branches", |b| {
        b.iter(|| {
            let block = Block::default();
            let (start, recipe) = (study_start(&block).unwrap(), Recipe::default());
            for free in [Free::Omega, Free::Alpha] {
                black_box(study_branches_from(free, &block, &recipe, &start, &mut Silent).unwrap());
            }
        });
    });
}

/// The branch AUTO-07p was timed on: the symmetric orbit continued in omega over [0.5, 4.0] at
/// alpha = 0.66 from the Fig. 2 orbit, both directions, every detector on; at our default step
/// control (~100 points) and with the largest step set to 0.04, which gives AUTO's ~223 points.
/// As every symmetric start in the rocking block, it is continued on its half orbit (the same
/// points, special points to 1e-10 and multipliers to 1e-8 of the full orbit's problem, which is
/// benchmarked too).
/// Accuracy is equal: AUTO's discretisation (collocation with 40 mesh intervals over the orbit,
/// NCOL 4; hycont's collocation with NTST 10 on each of the orbit's 4 segments) puts SN1, BP1
/// and GR1 within 5e-11 and BP2 within 1.3e-8 of a rtol 1e-13 shooting run, the multipliers
/// within 3e-10 (relative); our default shooting (rtol 1e-10) puts every special point within
/// 2.4e-10 and the multipliers within 1e-10 (half orbit: 3e-10). (hycont's collocation on that
/// mesh takes 1.5 ms/point, as AUTO.)
fn symmetric_omega_branch(c: &mut Criterion) {
    // What users run: without the test suites' re-check of every branch.
    hycont_continuation::check_branches(false);
    use hycont_continuation::RunDirection;
    use rocking_block::continuation::{default_method, study_run};
    use rocking_block::model::Parameters;
    use rocking_block::orbits::{OrbitKind, orbit};
    let params = Parameters::new(1.3, 0.66);
    let start = orbit(&params, OrbitKind::Symmetric, None)
        .unwrap()
        .solution
        .orbit;
    let branch = |h_max: f64, half: bool| {
        let mut run = study_run(Free::Omega, &params, (0.5, 4.0), default_method()).unwrap();
        run.steps(0.02, 1e-8, h_max).half_orbits(half);
        run.run("symmetric", &start, RunDirection::Both)
            .unwrap()
            .branch
    };
    let run = |h_max: f64| branch(h_max, true);
    let run_full = || branch(0.1, false);
    let runs: [(&str, &dyn Fn() -> hycont_continuation::Branch); 3] = [
        ("default steps", &|| run(0.1)),
        ("AUTO's point count", &|| run(0.04)),
        ("default steps, full orbit", &run_full),
    ];
    for (name, go) in runs {
        let t = std::time::Instant::now();
        let b = go();
        let elapsed = t.elapsed();
        // Solutions computed: the points and the special points (the branch's end points are
        // both; count them once).
        let ends = b
            .special_points
            .iter()
            .filter(|s| b.points.iter().any(|p| p.u == s.point.u))
            .count();
        let points = b.points.len() + b.special_points.len() - ends;
        eprintln!(
            "symmetric omega branch, {name}: {points} points (incl. special), {:.3} ms per point \
             (one run {elapsed:?}); {:?}",
            1e3 * elapsed.as_secs_f64() / points as f64,
            b.statistics
        );
    }
    c.bench_function("continuation/symmetric_omega_branch", |b| {
        b.iter(|| black_box(run(0.1)));
    });
    c.bench_function(
        "continuation/symmetric_omega_branch_auto_point_count",
        |b| {
            b.iter(|| black_box(run(0.04)));
        },
    );
    c.bench_function("continuation/symmetric_omega_branch_full_orbit", |b| {
        b.iter(|| black_box(run_full()));
    });
}

/// Per point, both discretisations, on the symmetric omega branch at alpha = 0.66 (issue 13's
/// targets: collocation with NTST 20 per segment and NCOL 4 at <= 0.25 ms/point, shooting at
/// <= 0.1 ms/point; issue 39's: <= 0.12 and <= 0.08 ms/point on the developers' machine, the
/// criterion median of a branch divided by its 103 points). AUTO-07p on the same model and branch (2-segment stacked BVP, analytic
/// Jacobians, this machine, one thread, medians of 11 runs): 0.75 ms/point at NTST 20,
/// 1.34 ms/point at NTST 40, fixed cost of a run (start and 2 points) 10 ms. Prints ms/point and
/// corrector iterations per point; the criterion medians are of whole branches.
fn per_point(c: &mut Criterion) {
    // What users run: without the test suites' re-check of every branch.
    hycont_continuation::check_branches(false);
    use hycont_continuation::{OrbitMethod, RunDirection};
    use hycont_core::orbit::CollocationSettings;
    use rocking_block::continuation::{default_method, study_run};
    use rocking_block::model::Parameters;
    use rocking_block::orbits::{OrbitKind, orbit};
    let params = Parameters::new(1.3, 0.66);
    let start = orbit(&params, OrbitKind::Symmetric, None)
        .unwrap()
        .solution
        .orbit;
    let methods = [
        ("shooting", default_method()),
        (
            "collocation",
            OrbitMethod::Collocation(CollocationSettings {
                ntst: 20,
                ncol: 4,
                adapt: 1,
            }),
        ),
    ];
    for (name, method) in methods {
        let branch = || {
            let mut run = study_run(Free::Omega, &params, (0.5, 4.0), method).unwrap();
            run.run("symmetric", &start, RunDirection::Both)
                .unwrap()
                .branch
        };
        let t = std::time::Instant::now();
        let b = branch();
        let elapsed = t.elapsed().as_secs_f64();
        let points = b.points.len() + b.special_points.len();
        let iterations: usize = b.points.iter().map(|p| p.newton_iterations).sum();
        eprintln!(
            "per point, {name}: {points} points (incl. special), {:.3} ms/point, {:.2} corrector \
             iterations/point",
            1e3 * elapsed / points as f64,
            iterations as f64 / b.points.len() as f64
        );
        c.bench_function(&format!("continuation/per_point_{name}"), |bch| {
            bch.iter(|| black_box(branch()));
        });
    }
}

fn figure_6_curves(c: &mut Criterion) {
    // What users run: without the test suites' re-check of every branch.
    hycont_continuation::check_branches(false);
    let t = std::time::Instant::now();
    let curves = study_curves(&Block::default(), &mut Silent).unwrap();
    let elapsed = t.elapsed();
    for cv in &curves {
        eprintln!(
            "{} curve: {} points",
            cv.kind.label(),
            cv.branch.branch.points.len()
        );
    }
    let points: usize = curves.iter().map(|c| c.branch.branch.points.len()).sum();
    eprintln!(
        "all curves (with the Fig. 3/4 branches they start from): {points} points in {elapsed:?}"
    );
    c.bench_function("continuation/figure_6_curves", |b| {
        b.iter(|| black_box(study_curves(&Block::default(), &mut Silent).unwrap()));
    });
}

/// Whole diagrams in one call from the Fig. 2 orbit (found once): in omega at depth 2 (Fig. 3's
/// branches, the asymmetric one as a closed loop through both branch points, and the branch
/// past GR1 with the one switched at its branch point) and in alpha at depth 6 (Fig. 4's
/// branches, the cascade to period 32: PD1 to PD5, and past GR2 a second cascade). The
/// branch count is printed, for the time per branch.
fn diagrams(c: &mut Criterion) {
    hycont_continuation::check_branches(false);
    let block = Block::default();
    let (start, recipe) = (study_start(&block).unwrap(), Recipe::default());
    for (free, depth) in [(Free::Omega, 2), (Free::Alpha, 6)] {
        let settings = DiagramSettings {
            depth,
            ..Default::default()
        };
        let d = study_diagram(
            "symmetric",
            free,
            free.range(),
            &recipe,
            &start,
            &settings,
            &mut Silent,
        )
        .unwrap();
        eprintln!(
            "diagram in {} at depth {depth}: {} branches",
            free.name(),
            d.branches.len()
        );
        let name = format!("continuation/diagram_{}_depth_{depth}", free.name());
        c.bench_function(&name, |b| {
            b.iter(|| {
                black_box(
                    study_diagram(
                        "symmetric",
                        free,
                        free.range(),
                        &recipe,
                        &start,
                        &DiagramSettings {
                            depth,
                            ..Default::default()
                        },
                        &mut Silent,
                    )
                    .unwrap(),
                )
            });
        });
    }
}

/// The symmetric branch in alpha from the Fig. 2 orbit (both ways; by the study's shooting and
/// by collocation) with the block's hand-coded Jacobians, by automatic differentiation
/// (`AutoDiff<RockingBlockModel>`) and by central differences: the cost of each per point, and
/// (printed) the accuracy of the latter two against the hand-coded Jacobians.
fn derivatives(c: &mut Criterion) {
    use hycont_continuation::{OrbitMethod, OrbitRun, RunDirection};
    use hycont_core::orbit::CollocationSettings;
    use hycont_core::{AutoDiff, FiniteDifferences, HybridJacobians, check_derivatives_against};
    use rocking_block::model_ad::RockingBlockModel;
    use rocking_block::{ALPHA, MINUS, PLUS, REST, RockingBlock};
    fn bench<S: HybridJacobians>(c: &mut Criterion, name: &str, sys: &S) {
        let start = study_start(&Block::default()).unwrap();
        let methods = [
            ("shooting", rocking_block::continuation::default_method()),
            (
                "collocation",
                OrbitMethod::Collocation(CollocationSettings::default()),
            ),
        ];
        for (method_name, method) in methods {
            let mut run = OrbitRun::new(sys, ALPHA).unwrap();
            run.method(method).bounds(0.01, 1.06);
            let branch = run.run("symmetric", &start, RunDirection::Both).unwrap();
            let points = branch.branch.points.len();
            eprintln!("{name} {method_name}: {points} points");
            let id = format!("continuation/derivatives/{method_name}/{name}");
            c.bench_function(&id, |b| {
                b.iter(|| black_box(run.run("symmetric", &start, RunDirection::Both).unwrap()));
            });
        }
    }
    /// The largest scaled error |d - d_hand| / (1 + |d_hand|) of `sys`'s derivatives against
    /// the hand-coded ones in every mode over 200 spread points of the proptests' ranges.
    fn accuracy<S: HybridJacobians>(name: &str, sys: &S) {
        let worst = (0..200)
            .flat_map(|k| [PLUS, MINUS, REST].map(|m| (f64::from(k), m)))
            .map(|(k, mode)| {
                let w = |a: f64, b: f64| (a * k + b).sin();
                let x = [
                    1.5 * w(1.3, 0.0),
                    2.0 * w(0.7, 1.0),
                    0.99 * w(1.9, 2.0),
                    w(2.3, 3.0),
                ];
                let p = [
                    2.15 + 1.85 * w(2.1, 0.5),
                    0.6 + 0.6 * w(1.7, 1.5),
                    0.05 + 0.05 * w(1.1, 2.5),
                    1.075 + 0.425 * w(0.9, 3.5),
                ];
                check_derivatives_against(sys, &RockingBlock, mode, &x, &p)
                    .unwrap()
                    .max_error()
            })
            .fold(0.0, f64::max);
        eprintln!("accuracy {name} against hand-coded: {worst:.1e}");
    }
    hycont_continuation::check_branches(false);
    accuracy("autodiff", &AutoDiff::new(RockingBlockModel));
    accuracy("differences", &FiniteDifferences::new(RockingBlock));
    bench(c, "hand", &RockingBlock);
    bench(c, "autodiff", &AutoDiff::new(RockingBlockModel));
    bench(c, "differences", &FiniteDifferences::new(RockingBlock));
}

/// The atlas of the symmetric period-one orbits through the Fig. 2 orbit over the study's
/// window (`figure atlas`'s first sheet), by shooting and by collocation.
fn atlas(c: &mut Criterion) {
    use hycont_continuation::OrbitMethod;
    use hycont_core::orbit::CollocationSettings;
    use rocking_block::continuation::{atlas_settings, default_method, study_atlas};
    hycont_continuation::check_branches(false);
    let start = study_start(&Block::default()).unwrap();
    let settings = atlas_settings();
    for (name, method) in [
        ("shooting", default_method()),
        (
            "collocation",
            OrbitMethod::Collocation(CollocationSettings::default()),
        ),
    ] {
        let sheet = study_atlas("sheet", &start, method, &settings, &mut Silent).unwrap();
        eprintln!("atlas by {name}: {} charts", sheet.atlas.charts.len());
        c.bench_function(&format!("continuation/atlas_{name}"), |b| {
            b.iter(|| black_box(study_atlas("sheet", &start, method, &settings, &mut Silent)));
        });
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = figures_3_and_4, symmetric_omega_branch, per_point, figure_6_curves, diagrams,
        derivatives, atlas
}
criterion_main!(benches);
