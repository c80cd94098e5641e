//! Modes of their own state dimension cost no more than one dimension for every mode: the
//! stick-slip family of COCO's stick-slip oscillator (`examples/stick_slip/model.rs`, STICK 3
//! states, SLIP 4; three segments STICK-STICK-SLIP) against its twin with 4 states in every
//! mode (STICK carrying a fourth, passive state that REST sets to zero), the same orbits and
//! segments. Run with `cargo bench --bench stick_slip`.
//!
//! Benchmarked, on both discretisations: the family continued from its orbit at `V = 0.6` up
//! to `V = 0.7` with a fixed step (the same points for both systems); throughput in points
//! (the target: the mixed system's time per point at most 1.5 times the twin's).

#[path = "../examples/stick_slip/model.rs"]
mod model;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use hycont::hycont_continuation::{OrbitMethod, OrbitRun, RunDirection, SpecialKind};
use hycont::orbit::{CollocationSettings, PeriodicOrbit, ShootingSettings};
use hycont::{AutoDiff, EventId, EventSpec, HybridModel, HybridSystem, Mode, Scalar};
use model::{COLLISION, Model, REST, STICK, StickSlip, V};
use std::hint::black_box;

/// The stick-slip oscillator with 4 states in STICK too (the fourth passive, zeroed at REST).
#[derive(Clone, Copy)]
struct Uniform;

impl HybridModel for Uniform {
    fn state_dim(&self) -> usize {
        4
    }
    fn parameter_names(&self) -> &[&'static str] {
        Model.parameter_names()
    }
    fn mode_count(&self) -> usize {
        2
    }
    fn mode_name(&self, mode: Mode) -> &'static str {
        Model.mode_name(mode)
    }
    fn events(&self, mode: Mode) -> &[EventId] {
        Model.events(mode)
    }
    fn event_spec(&self, e: EventId) -> EventSpec {
        Model.event_spec(e)
    }
    fn vector_field<T: Scalar>(&self, mode: Mode, x: &[T], p: &[T], f: &mut [T]) {
        if mode == STICK {
            Model.vector_field(mode, &x[..3], p, &mut f[..3]);
            f[3] = T::from(0.0);
        } else {
            Model.vector_field(mode, x, p, f);
        }
    }
    fn event<T: Scalar>(&self, e: EventId, x: &[T], p: &[T]) -> T {
        Model.event(e, x, p)
    }
    fn reset<T: Scalar>(&self, e: EventId, x: &[T], p: &[T], out: &mut [T]) {
        match e {
            COLLISION => Model.reset(e, &x[..3], p, out),
            REST => {
                Model.reset(e, x, p, &mut out[..3]);
                out[3] = T::from(0.0);
            }
            _ => Model.reset(e, x, p, out),
        }
    }
}

/// The stick-slip orbit at `V = 0.6`, switched from the sustained-stick family's grazing.
fn stick_slip_orbit() -> PeriodicOrbit {
    let system = StickSlip::default();
    let orbit = model::sustained_stick_orbit().expect("the sustained-stick orbit");
    let mut run = OrbitRun::new(&system, V).expect("a parameter");
    run.bounds(0.5, 0.6);
    let two = run
        .run("sustained", &orbit, RunDirection::Up)
        .expect("the family");
    let db = two
        .first(SpecialKind::DOMAIN_BOUNDARY)
        .expect("the grazing");
    let three = run
        .switch_at("stick-slip", &two, db.point.label, RunDirection::Up)
        .expect("the stick-slip family");
    three
        .orbit_of(three.branch.points.last().expect("points"))
        .expect("its orbit")
}

/// The same orbit with STICK's starts given the fourth, zero, state.
fn padded(orbit: &PeriodicOrbit) -> PeriodicOrbit {
    let mut o = orbit.clone();
    for x in &mut o.starts {
        x.resize(4, 0.0);
    }
    o
}

fn per_point(c: &mut Criterion) {
    hycont::hycont_continuation::check_branches(false);
    let mixed = stick_slip_orbit();
    let uniform = padded(&mixed);
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
    let mut group = c.benchmark_group("stick_slip");
    group.sample_size(10);
    for (name, method) in methods {
        let twin = AutoDiff::new(Uniform);
        let system = StickSlip::default();
        let runs: [(&str, &dyn Fn() -> usize); 2] = [
            ("mixed_3_4", &|| family(&system, &mixed, &method)),
            ("uniform_4", &|| family(&twin, &uniform, &method)),
        ];
        for (dims, f) in runs {
            let points = f();
            group.throughput(Throughput::Elements(points as u64));
            group.bench_function(format!("{name}_{dims}"), |b| b.iter(|| black_box(f())));
        }
    }
    group.finish();
}

/// The family from `orbit` up to `V = 0.7` with a fixed step; its number of points.
fn family<S: hycont::HybridJacobians + HybridSystem>(
    system: &S,
    orbit: &PeriodicOrbit,
    method: &OrbitMethod,
) -> usize {
    let mut run = OrbitRun::new(system, V).expect("a parameter");
    run.method(*method).bounds(0.59, 0.7);
    run.steps(0.005, 0.005, 0.005);
    run.run("stick-slip", orbit, RunDirection::Up)
        .expect("the family")
        .branch
        .points
        .len()
}

criterion_group!(benches, per_point);
criterion_main!(benches);
