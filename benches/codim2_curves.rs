//! Two-parameter curves with their codimension-two points detected, on two balls on vibrating
//! tables (`examples/two_balls/model.rs`): ball 1's fold curve in `(a, e2)` (its fold-flip
//! point located) and period-doubling curve (R2 located), by both discretisations. Run with
//! `cargo bench --bench codim2_curves`.

#[path = "../examples/two_balls/model.rs"]
mod model;

use criterion::{Criterion, criterion_group, criterion_main};
use hycont::hycont_continuation::{CurveSpec, OrbitRun, RunDirection, SpecialKind};
use hycont::orbit::{CollocationSettings, OrbitMethod, ShootingSettings};
use model::{A, E1, E2, G1, TwoBalls, a_pd, a_sn, orbit};
use std::hint::black_box;

fn curves(c: &mut Criterion) {
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
    let cases = [
        (
            "fold_curve_lppd",
            SpecialKind::Fold,
            a_sn(E1, G1),
            (1.1, 0.65, 1.0),
            (0.56, 0.95),
        ),
        (
            "pd_curve_r2",
            SpecialKind::PeriodDoubling,
            a_pd(E1, G1),
            (0.95, 0.75, 1.2),
            (0.58, 0.9),
        ),
    ];
    for (name, method) in methods {
        for (case, kind, a_ref, (f, e2, g2), (lo, hi)) in cases {
            let mut run = OrbitRun::new(&TwoBalls, A).expect("a parameter");
            run.method(method).bounds(0.3, 3.0);
            let branch = run
                .run("period-1", &orbit(f * a_ref, e2, g2), RunDirection::Both)
                .expect("the branch");
            let label = branch
                .special(kind)
                .find(|s| (s.point[A] - a_ref).abs() < 1e-6)
                .expect("ball 1's point")
                .point
                .label;
            let spec = CurveSpec::new(E2).bounds(lo, hi);
            c.bench_function(&format!("codim2_curves/{name}/{case}"), |b| {
                b.iter(|| black_box(run.curve_at(kind.label(), &branch, label, &spec).unwrap()));
            });
        }
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = curves
}
criterion_main!(benches);
