//! The public API under random misuse: random handles (modes, events, parameters, measures,
//! monitors, segments, labels, cells), random lengths, NaN and infinities, degenerate
//! signatures, random symmetries, random simulations read as orbits, measure handles of other
//! runs. Every call returns `Ok` or a typed error; none panics; and no `Ok` carries a wrong
//! result: a symmetric solution is an orbit, an orbit read off a simulation closes to its
//! tolerance, a measure handle reads only the measure it names, and every branch a run returns
//! with admissibility on holds physical orbits only (`OrbitBranch::check_points`; the test
//! suites' `invariants` feature also re-checks every branch computed here). 10,000 cases per
//! entry point (`PROPTEST_CASES` overrides), on the bouncing ball on a vibrating table
//! (`examples/vibrating_table/model.rs`). Work that succeeds is kept small (short horizons, few
//! Newton iterations, few points) so that the cases stay cheap.

use crate::model_vibrating_table as model;

use hycont::hycont_continuation::{
    ContinuationSettings, CurveSpec, Label, MeasureId, OrbitBranch, OrbitRun, Quantity,
    RunDirection, SpecialKind,
};
use hycont::hycont_sample::basin::{Axis, Counts, Distribution, Study, shard_range};
use hycont::orbit::{
    Closure, CollocationSettings, Discretisation, Measure, OrbitMethod, PeriodicOrbit, SegmentEnd,
    SegmentSpec, SegmentValue, ShootingSettings, Signature, SymmetricSearch, find_symmetric_orbit,
    solve_collocation, solve_orbit, solve_shooting,
};
use hycont::problem::{Activity, MonitorId, NewtonSettings, Problem, UnknownMonitor};
use hycont::{
    EventId, EventSpec, FiniteDifferences, HybridJacobians, HybridSystem, Mode, ParamId,
    SimulationSettings, Simulator, Z2Symmetry, checked_symmetry,
};
use model::{A, FLIGHT, IMPACT, Table, WRAP};
// The model names both parameters; the runs here vary the amplitude.
const _: ParamId = model::OMEGA;
use proptest::prelude::*;
use std::sync::OnceLock;

const CASES: u32 = 10_000;

fn config() -> ProptestConfig {
    ProptestConfig {
        cases: std::env::var("PROPTEST_CASES")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(CASES),
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

/// Finite values, zero, NaN, infinities and extremes.
fn value() -> impl Strategy<Value = f64> {
    prop_oneof![
        6 => -5.0f64..5.0,
        1 => Just(0.0),
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(f64::NEG_INFINITY),
        1 => Just(1e308),
        1 => Just(-1e-300),
    ]
}

fn values(len: std::ops::Range<usize>) -> impl Strategy<Value = Vec<f64>> {
    prop::collection::vec(value(), len)
}

const P: [f64; 4] = [1.3, 1.0, 0.5, 1.0];

/// Measure names for named handles: the built-in ones and others.
const NAMES: [&str; 6] = [
    "period",
    "shortest_segment",
    "admissible_grazing",
    "admissible_domain",
    "amp",
    "x",
];

fn table() -> &'static FiniteDifferences<Table> {
    static FD: OnceLock<FiniteDifferences<Table>> = OnceLock::new();
    FD.get_or_init(|| FiniteDifferences::new(Table))
}

/// The stable period-1 orbit at `a = 1.3`, `omega = 1` (e = 0.5, g = 1).
fn good_orbit() -> &'static PeriodicOrbit {
    static ORBIT: OnceLock<PeriodicOrbit> = OnceLock::new();
    ORBIT.get_or_init(|| {
        let a_fold = std::f64::consts::PI * 0.5 / 1.5;
        let x0 = [
            0.0,
            0.5 * 2.0 * std::f64::consts::PI / 1.5,
            (a_fold / 1.3).acos(),
        ];
        let sig = Signature::new(
            &Table,
            [WRAP, IMPACT]
                .map(|e| SegmentSpec {
                    mode: FLIGHT,
                    end: SegmentEnd::Event(e),
                })
                .to_vec(),
        )
        .unwrap();
        let guess = PeriodicOrbit::from_initial_state(
            &Table,
            sig,
            &x0,
            &P,
            20.0,
            &SimulationSettings::default(),
        )
        .unwrap();
        solve_shooting(
            table(),
            &guess,
            ShootingSettings::default(),
            &NewtonSettings::default(),
        )
        .unwrap()
        .orbit
    })
}

/// A short amplitude branch with its SN-free stretch and the PD (both ways over [1.2, 1.7]).
fn good_branch() -> &'static OrbitBranch {
    static BRANCH: OnceLock<OrbitBranch> = OnceLock::new();
    BRANCH.get_or_init(|| {
        let mut run = OrbitRun::new(table(), A).unwrap();
        run.bounds(1.2, 1.7);
        run.run("b", good_orbit(), RunDirection::Both).unwrap()
    })
}

fn segment_end() -> impl Strategy<Value = SegmentEnd> {
    prop_oneof![
        (0usize..4).prop_map(|e| SegmentEnd::Event(EventId(e))),
        (0usize..5, value())
            .prop_map(|(component, value)| SegmentEnd::Interior { component, value }),
    ]
}

fn segments() -> impl Strategy<Value = Vec<SegmentSpec>> {
    prop::collection::vec(
        (0usize..3, segment_end()).prop_map(|(m, end)| SegmentSpec { mode: Mode(m), end }),
        0..4,
    )
}

fn kind() -> impl Strategy<Value = SpecialKind> {
    prop_oneof![
        Just(SpecialKind::Fold),
        Just(SpecialKind::BranchPoint),
        Just(SpecialKind::PeriodDoubling),
        Just(SpecialKind::Torus),
        Just(SpecialKind::BoundaryTouch),
        Just(SpecialKind::Grazing),
        Just(SpecialKind::EndPoint),
        Just(SpecialKind::UserPoint),
        Just(SpecialKind::Custom(Label::new("XY").unwrap())),
    ]
}

fn quantity() -> impl Strategy<Value = Quantity> {
    prop_oneof![
        (0usize..7).prop_map(|p| Quantity::Parameter(ParamId(p))),
        (0usize..9).prop_map(|m| Quantity::Measure(MeasureId::new(m))),
    ]
}

/// The table with a symmetry of the fuzzer's choice (the identity is the only valid one).
struct Symmetric(Z2Symmetry);

impl HybridSystem for Symmetric {
    fn state_dim(&self) -> usize {
        Table.state_dim()
    }
    fn parameter_names(&self) -> &[&'static str] {
        Table.parameter_names()
    }
    fn mode_count(&self) -> usize {
        Table.mode_count()
    }
    fn mode_name(&self, m: Mode) -> &'static str {
        Table.mode_name(m)
    }
    fn events(&self, m: Mode) -> &[EventId] {
        Table.events(m)
    }
    fn event_spec(&self, e: EventId) -> EventSpec {
        Table.event_spec(e)
    }
    fn vector_field(&self, m: Mode, x: &[f64], p: &[f64], out: &mut [f64]) {
        Table.vector_field(m, x, p, out);
    }
    fn event(&self, e: EventId, x: &[f64], p: &[f64]) -> f64 {
        Table.event(e, x, p)
    }
    fn reset(&self, e: EventId, x: &[f64], p: &[f64], out: &mut [f64]) {
        Table.reset(e, x, p, out);
    }
    fn symmetry(&self) -> Option<Z2Symmetry> {
        Some(self.0.clone())
    }
}

fn symmetry() -> impl Strategy<Value = Z2Symmetry> {
    let entry = prop_oneof![
        3 => prop::sample::select(vec![-1.0, 0.0, 1.0, 2.0]),
        1 => value(),
    ];
    let identity = Z2Symmetry {
        matrix: vec![1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
        modes: vec![FLIGHT],
        events: vec![IMPACT, WRAP],
    };
    prop_oneof![
        1 => Just(identity),
        4 => (
            prop::sample::select(vec![0usize, 4, 9, 16]).prop_flat_map(move |len| {
                prop::collection::vec(entry.clone(), len..=len)
            }),
            prop::collection::vec((0usize..2).prop_map(Mode), 0..3),
            prop::collection::vec((0usize..3).prop_map(EventId), 0..4),
        )
            .prop_map(|(matrix, modes, events)| Z2Symmetry { matrix, modes, events }),
    ]
}

/// The largest residual of `orbit`'s (periodic) shooting equations, relative to its size.
fn closure_residual<S: HybridJacobians + ?Sized>(system: &S, orbit: &PeriodicOrbit) -> f64 {
    let disc = Discretisation::Shooting(ShootingSettings::default());
    let Ok(mut eq) = disc.equations(system, orbit, None) else {
        return f64::INFINITY;
    };
    let Ok(u) = disc.pack(system, orbit) else {
        return f64::INFINITY;
    };
    let mut r = vec![0.0; eq.equations()];
    if eq.evaluate(&u, &mut r, None).is_err() {
        return f64::INFINITY;
    }
    let scale = 1.0 + u.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    r.iter().fold(0.0f64, |m, v| m.max(v.abs())) / scale
}

proptest! {
    #![proptest_config(config())]

    /// Symmetries: random matrices (of any size, S^2 = I or not, NaN), mode and event maps.
    /// Checks, half-orbit signatures, the search, solves of half orbits and runs never panic;
    /// a symmetric orbit found or solved is an orbit (its full shooting equations hold).
    #[test]
    fn symmetries(sym in symmetry(), segs in segments(), seeds in prop::collection::vec(values(3..4), 0..3),
                  half_period in value(), method in 0u8..2, go in 0u8..20) {
        let sys = FiniteDifferences::new(Symmetric(sym));
        let _ = checked_symmetry(&sys);
        let _ = good_orbit().is_symmetric(&sys, 1e-6);
        let _ = good_orbit().doubled().half_of_symmetric(&sys, 1e-6);
        let newton = NewtonSettings { max_iterations: 4, ..NewtonSettings::default() };
        if let Ok(half) = Signature::with_closure(&sys, segs, Closure::Symmetric) {
            let mut search = SymmetricSearch::new(seeds);
            search.half_period = Some(half_period);
            search.max_duration = 5.0;
            // As the simulations below: a seed that chatters stops at a step limit.
            search.scan = search.scan.max_steps(20_000);
            search.candidates = 1;
            search.newton = newton;
            if let Ok(sol) = find_symmetric_orbit(&sys, &half, &P, &search) {
                prop_assert!(closure_residual(&sys, &sol.full.orbit) < 1e-6);
            }
        }
        let method = if method == 0 {
            OrbitMethod::Shooting(ShootingSettings::default())
        } else {
            OrbitMethod::Collocation(CollocationSettings { ntst: 4, ncol: 2, adapt: 0 })
        };
        let doubled = good_orbit().doubled();
        for guess in [Some(doubled.clone()), doubled.half_of_symmetric(&sys, 1e-6).ok()].into_iter().flatten() {
            if let Ok(solved) = solve_orbit(&sys, &guess, &method, &newton, 1e-6) {
                prop_assert!(solved.solution.orbit.signature.closure() == Closure::Periodic);
                if matches!(method, OrbitMethod::Shooting(_)) {
                    prop_assert!(closure_residual(&sys, &solved.solution.orbit) < 1e-6);
                }
            }
        }
        if go == 0 {
            let mut run = OrbitRun::new(&sys, A).unwrap();
            run.bounds(1.2, 1.7).max_points(3);
            if let Ok(b) = run.run("s", &doubled, RunDirection::Up) {
                prop_assert!(b.check_points(&sys, true).is_ok());
            }
        }
    }

    /// Simulations read as orbits: random (table) parameters, starts, horizons and
    /// tolerances, so that tails chatter to rest (Zeno), stop at the step limit, repeat or not.
    /// An orbit read off one has positive durations and closes to the tolerance asked for.
    #[test]
    fn orbits_from_simulations(a in 0.0f64..2.5, omega in 0.5f64..1.5, e in 0.0f64..1.0,
                               x0 in values(3..4), horizon in 0.0f64..60.0, tol in 1e-12f64..1e-2,
                               wild in 0u8..10) {
        let p = [a, omega, e, 1.0];
        let x0: Vec<f64> = if wild == 0 {
            x0
        } else {
            x0.iter().map(|v| if v.is_finite() { v.abs().min(3.0) } else { 0.5 }).collect()
        };
        let mut sim = Simulator::new(SimulationSettings::default().max_steps(20_000)).unwrap();
        let Ok(traj) = sim.run(&Table, FLIGHT, 0.0, &x0, &p, horizon) else { return Ok(()) };
        if let Ok(orbit) = PeriodicOrbit::from_simulation(&Table, &traj, &p, tol) {
            prop_assert!(orbit.durations.iter().all(|d| d.is_finite() && *d > 0.0));
            let residual = closure_residual(table(), &orbit);
            prop_assert!(residual <= 10.0 * tol + 1e-6, "residual {residual:e} for tol {tol:e}");
        }
    }

    /// `Simulator::run`: random modes, lengths, non-finite states and parameters, reversed or
    /// non-finite time spans.
    #[test]
    fn simulator_runs(mode in 0usize..3, x0 in values(0..5), p in values(2..6),
                      t0 in value(), span in value()) {
        let mut sim = Simulator::new(SimulationSettings::default().max_steps(2000)).unwrap();
        let t_end = t0 + span.clamp(-1e300, 2.0);
        let _ = sim.run(&Table, Mode(mode), t0, &x0, &p, t_end);
    }

    /// Signatures and orbits: random modes and ends, start and duration lengths, NaN; then
    /// queries, rotation and a few Newton iterations of either method.
    #[test]
    fn orbits_and_solves(segs in segments(), starts in prop::collection::vec(values(2..5), 0..4),
                         durations in values(0..4), p in values(3..6), event in 0usize..4,
                         k in 0usize..5, solve in 0u8..20) {
        let Ok(sig) = Signature::new(&Table, segs) else { return Ok(()) };
        let Ok(orbit) = PeriodicOrbit::new(&Table, sig, starts, durations, p) else {
            return Ok(())
        };
        let _ = orbit.start(k);
        let _ = orbit.validate(&Table);
        let _ = orbit.starting_after(&Table, EventId(event));
        let _ = SegmentValue::end(k, k).evaluate(table(), &orbit);
        let newton = NewtonSettings { max_iterations: 3, ..NewtonSettings::default() };
        match solve {
            0 => { let _ = solve_shooting(table(), &orbit, ShootingSettings::default(), &newton); }
            1 => {
                let c = CollocationSettings { ntst: 3, ncol: 2, adapt: 0 };
                let _ = solve_collocation(table(), &orbit, c, &newton);
            }
            _ => {}
        }
    }

    /// Zero problems with monitors: random monitor handles, unknown indices and lengths.
    #[test]
    fn problems_and_monitors(n in 0usize..4, idx in prop::collection::vec(0usize..6, 0..3),
                             id in 0usize..4, u in values(0..6), activity in value()) {
        let mut problem = Problem::new(n);
        let _ = problem.add_monitor("m", Box::new(UnknownMonitor), idx, Activity::Inactive(0.0));
        let _ = problem.set_activity(MonitorId(id), Activity::Active(activity));
        let _ = problem.activity(MonitorId(id));
        let _ = problem.monitor_value(MonitorId(id), &u);
        let mut residual = vec![0.0; u.len()];
        let _ = problem.evaluate(&u, &mut residual, None);
    }

    /// Runs: random free parameters, bounds, steps, events on random quantities and levels,
    /// user points; a few points when everything is valid.
    #[test]
    fn orbit_runs(free in 0usize..6, lo in value(), hi in value(), h in values(3..4),
                  on in quantity(), level in value(), kind in kind(), user in 0usize..6,
                  at in value(), go in 0u8..50) {
        let Ok(mut run) = OrbitRun::new(table(), ParamId(free)) else { return Ok(()) };
        let _ = run.bounds(lo, hi);
        let _ = run.steps(h[0], h[1], h[2]);
        let _ = run.add_event(on, level, kind);
        let _ = run.add_terminal_event(on, level, SpecialKind::Custom(Label::new("T").unwrap()));
        let _ = run.add_user_points(ParamId(user), [at]);
        run.max_points(3);
        if go == 0 {
            // Sane steps: tiny random ones are valid but slow (many halvings).
            run.steps(0.02, 1e-4, 0.1);
            let _ = run.run("r", good_orbit(), RunDirection::Both);
        }
    }

    /// Runs from perturbed starts (some solve to orbits that are not physical): with
    /// admissibility on, a run refuses the start or returns physical orbits only.
    #[test]
    fn runs_are_physical(scale in values(4..5), shift in 0.0f64..3.0, go in 0u8..10) {
        if go != 0 {
            return Ok(());
        }
        let mut start = good_orbit().clone();
        for (x, s) in start.starts.iter_mut().flatten().zip(scale.iter().cycle()) {
            *x *= 1.0 + 0.5 * s.clamp(-1.0, 1.0);
        }
        start.params[0] += shift - 1.5;
        let mut run = OrbitRun::new(table(), A).unwrap();
        run.bounds(0.5, 3.0).max_points(4).steps(0.02, 1e-4, 0.1);
        if let Ok(b) = run.run("p", &start, RunDirection::Both) {
            prop_assert!(b.check_points(table(), true).is_ok());
        }
    }

    /// Saved branches: random labels and kinds for queries, restarts, switches and curves (a
    /// few points where the label is a special point).
    #[test]
    fn branch_queries(label in 0usize..80, kind in kind(), q in quantity(), second in 0usize..6,
                      lo in value(), hi in value(), go in 0u8..100, name in 0usize..6,
                      slot in 0usize..6) {
        let b = good_branch();
        let _ = b.point(label);
        let _ = b.special_at(label);
        let _ = b.first(kind);
        let _ = b.orbit_at(label);
        let _ = b.direction_at(label);
        if let Ok(p) = b.point(label) {
            let _ = p.get(q);
            // A named handle reads only the measure of its name.
            let named = MeasureId::named(slot, NAMES[name]);
            if let Ok(v) = p.value(named) {
                prop_assert_eq!(&b.branch.monitor_names[slot], NAMES[name]);
                prop_assert_eq!(v.to_bits(), p.monitors[named.index()].to_bits());
            }
        }
        let mut run = OrbitRun::new(table(), A).unwrap();
        run.max_points(3)
            .curve_settings(ContinuationSettings::default().max_points(3));
        let _ = run.restart("r", b, label, None);
        if go == 0 {
            let _ = run.switch_at("s", b, label, RunDirection::Up);
            let spec = CurveSpec::new(ParamId(second)).bounds(lo, hi);
            let _ = run.curve_at("c", b, label, &spec);
        }
    }

    /// Saved branches read back from mutated JSON: wrong shapes, NaN, wrong lengths.
    #[test]
    fn restart_files(cut in 0usize..20_000, byte in any::<u8>(), at in 0usize..20_000,
                     label in 0usize..40) {
        let text = good_branch().to_json().unwrap();
        let mut bytes = text.into_bytes();
        if at < bytes.len() {
            bytes[at] = byte;
        }
        bytes.truncate(cut.max(bytes.len() / 2));
        let Ok(text) = String::from_utf8(bytes) else { return Ok(()) };
        if let Ok(saved) = OrbitBranch::from_json(&text) {
            let _ = saved.orbit_at(label);
            let mut run = OrbitRun::new(table(), A).unwrap();
            run.max_points(2);
            let _ = run.restart("r", &saved, label, Some(RunDirection::Up));
        }
    }

    /// Basin studies and count tables: random axes, cells, ranges, shard indices.
    #[test]
    fn sampling(trials in any::<u64>(), i in any::<u64>(), n in any::<u64>(),
                var in 0usize..4, bins in 0usize..4, lo in value(), hi in value(),
                cell in 0usize..20, class in 0usize..4, counts in prop::collection::vec(any::<u64>(), 0..6),
                ranges in prop::collection::vec((any::<u64>(), any::<u64>()), 0..3)) {
        let _ = shard_range(trials, i, n);
        let study = Study {
            names: vec!["x".into(), "y".into()],
            variables: vec![Distribution::Uniform { lo, hi }, Distribution::Fixed(hi)],
            axes: vec![Axis { variable: var, lo, hi, bins }],
            seed: trials,
        };
        if study.validate().is_ok() {
            let _ = study.cell(&study.trial(i));
            let _ = study.cells();
        }
        let table = Counts {
            classes: vec!["a".into(), "b".into()],
            counts: counts.chunks(2).map(<[u64]>::to_vec).collect(),
            failures: counts.clone(),
            ranges,
        };
        let _ = table.validate();
        let _ = table.trials(cell);
        let _ = table.fraction(cell, class);
        let mut other = table.clone();
        let _ = other.merge(&table);
    }
}
