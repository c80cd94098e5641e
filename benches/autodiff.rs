//! Derivatives by hand, by automatic differentiation and by central differences: their
//! accuracy against the hand-coded ones (printed); one vector-field Jacobian with its
//! parameter columns and the field's derivatives along a branch's six directions (what the
//! variational equations integrate; AD seeds its duals with them) on two balls on vibrating
//! tables (`examples/two_balls/model.rs`: `TwoBalls` hand-coded, `TwoBallsModel` written once
//! for `AutoDiff`, `FiniteDifferences<TwoBalls>`); and a continuation run (the period-1 branch
//! in `a`, both ways, by shooting and by collocation; the same points each way) of the two
//! balls and of one ball on a vibrating table (`examples/vibrating_table/model.rs`: `Table`,
//! `TableModel`). Run with `cargo bench --bench autodiff`.

#[path = "../examples/two_balls/model.rs"]
mod model;
#[path = "../examples/vibrating_table/model.rs"]
#[allow(dead_code)] // the table's model file serves examples and tests too
mod table;

use criterion::{Criterion, criterion_group, criterion_main};
use hycont::hycont_continuation::{OrbitRun, RunDirection};
use hycont::orbit::{CollocationSettings, OrbitMethod, PeriodicOrbit, ShootingSettings};
use hycont::{
    AutoDiff, FiniteDifferences, HybridJacobians, Mode, ParamId, Tangents,
    check_derivatives_against,
};
use model::{A, E1, FLIGHT, G1, TwoBalls, TwoBallsModel, a_sn, orbit};
use std::hint::black_box;
use table::{Table, TableModel};

fn jacobian<S: HybridJacobians>(c: &mut Criterion, name: &str, sys: &S) {
    let (x, p) = (
        [0.3, -0.7, 1.1, 0.4, 0.9],
        [1.2, 1.0, 0.5, 0.7, 1.0, 1.2, -1.5],
    );
    let (mut f, mut dx, mut dp) = ([0.0; 5], [0.0; 25], [0.0; 35]);
    c.bench_function(&format!("autodiff/field_with_jacobian/{name}"), |b| {
        b.iter(|| {
            sys.vector_field_with_jacobian(
                FLIGHT,
                black_box(&x),
                &p,
                &mut f,
                &mut dx,
                Some(&mut dp),
            );
            black_box(&dp);
        });
    });
}

/// The field's derivatives along the 6 directions a branch's variational equations carry at
/// every stage (5 state sensitivities and one parameter's).
fn tangents<S: HybridJacobians>(c: &mut Criterion, name: &str, sys: &S) {
    let (x, p) = (
        [0.3, -0.7, 1.1, 0.4, 0.9],
        [1.2, 1.0, 0.5, 0.7, 1.0, 1.2, -1.5],
    );
    let dirs: Vec<f64> = (0..30).map(|i| (0.37 * f64::from(i)).sin()).collect();
    let (mut f, mut out, mut work) = ([0.0; 5], [0.0; 30], [0.0; 60]);
    c.bench_function(&format!("autodiff/field_with_tangents/{name}"), |b| {
        b.iter(|| {
            let t = Tangents {
                x: black_box(&dirs),
                params: &[ParamId(0)],
                out: &mut out,
                work: &mut work,
            };
            sys.vector_field_with_tangents(FLIGHT, black_box(&x), &p, &mut f, t);
            black_box(&out);
        });
    });
}

/// The largest scaled error |d - d_hand| / (1 + |d_hand|) of `sys`'s derivatives (vector field
/// with parameter columns, event gradients, reset Jacobians) against the hand-coded
/// `reference`'s in `mode` over 200 spread points with `n` states and `np` parameters
/// (printed, not timed).
fn accuracy<S: HybridJacobians, R: HybridJacobians>(
    name: &str,
    (sys, reference): (&S, &R),
    mode: Mode,
    (n, np): (usize, usize),
) {
    let worst = (0..200)
        .map(|k| {
            let k = f64::from(k);
            let x: Vec<f64> = (0..n)
                .map(|i| 2.0 * (1.3 * k + 0.7 * i as f64).sin())
                .collect();
            let p: Vec<f64> = (0..np)
                .map(|j| 1.0 + 0.5 * (2.1 * k + 1.1 * j as f64).sin())
                .collect();
            check_derivatives_against(sys, reference, mode, &x, &p)
                .unwrap()
                .max_error()
        })
        .fold(0.0, f64::max);
    eprintln!("accuracy {name} against hand-coded: {worst:.1e}");
}

/// The branch of `family` in parameter `param` over `bounds` through `start`, both ways, by
/// shooting and by collocation, with `sys`'s derivatives (`name`).
fn branch<S: HybridJacobians>(
    c: &mut Criterion,
    (family, name): (&str, &str),
    sys: &S,
    (param, bounds): (ParamId, (f64, f64)),
    start: &PeriodicOrbit,
) {
    for (method_name, method) in [
        (
            "shooting",
            OrbitMethod::Shooting(ShootingSettings::default()),
        ),
        (
            "collocation",
            OrbitMethod::Collocation(CollocationSettings::default()),
        ),
    ] {
        let mut run = OrbitRun::new(sys, param).expect("a parameter");
        run.method(method).bounds(bounds.0, bounds.1);
        let b = run
            .run("period-1", start, RunDirection::Both)
            .expect("the branch");
        eprintln!(
            "{family} {name} {method_name}: {} points",
            b.branch.points.len()
        );
        let id = format!("autodiff/{family}/{method_name}/{name}");
        c.bench_function(&id, |bch| {
            bch.iter(|| black_box(run.run("period-1", start, RunDirection::Both).unwrap()));
        });
    }
}

fn derivatives(c: &mut Criterion) {
    hycont::hycont_continuation::check_branches(false);
    let (ad, fd) = (
        AutoDiff::new(TwoBallsModel),
        FiniteDifferences::new(TwoBalls),
    );
    accuracy("two_balls ad", (&ad, &TwoBalls), FLIGHT, (5, 7));
    accuracy("two_balls fd", (&fd, &TwoBalls), FLIGHT, (5, 7));
    jacobian(c, "hand", &TwoBalls);
    jacobian(c, "ad", &ad);
    jacobian(c, "fd", &fd);
    tangents(c, "hand", &TwoBalls);
    tangents(c, "ad", &ad);
    tangents(c, "fd", &fd);
    let start = orbit(1.1 * a_sn(E1, G1), 0.65, 1.0);
    let on = (A, (0.9, 1.5));
    branch(c, ("two_balls", "hand"), &TwoBalls, on, &start);
    branch(c, ("two_balls", "ad"), &ad, on, &start);
    branch(c, ("two_balls", "fd"), &fd, on, &start);
    // One ball: the vibrating table's period-1 branch in a over [0.9, 1.8] from a = 1.3.
    let start = table::period_one(&Table, [1.3, 1.0, 0.5, 1.0]).expect("the table's orbit");
    let on = (table::A, (0.9, 1.8));
    let (ad, fd) = (AutoDiff::new(TableModel), FiniteDifferences::new(Table));
    accuracy("table ad", (&ad, &Table), table::FLIGHT, (3, 4));
    accuracy("table fd", (&fd, &Table), table::FLIGHT, (3, 4));
    branch(c, ("table", "hand"), &Table, on, &start);
    branch(c, ("table", "ad"), &ad, on, &start);
    branch(c, ("table", "fd"), &fd, on, &start);
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = derivatives
}
criterion_main!(benches);
