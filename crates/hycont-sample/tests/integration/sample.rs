//! Basin-stability machinery and brute-force sweeps against exact answers.

use approx::assert_abs_diff_eq;
use hycont_core::{
    Direction, EventAction, EventId, EventSpec, HybridSystem, Mode, SimulationSettings,
};
use hycont_sample::basin::{
    Axis, Classifier, Distribution, Progress, Study, run, shard_range, share,
};
use hycont_sample::sweep::{Sweep, brute_force};
use std::sync::atomic::Ordering;

/// Class = which quarter of [0, 1) the first variable falls in.
struct Quarters;
impl Classifier for Quarters {
    fn classes(&self) -> Vec<String> {
        (0..4).map(|i| format!("q{i}")).collect()
    }
    fn classify(&self, v: &[f64]) -> Result<usize, String> {
        Ok(((v[0] * 4.0) as usize).min(3))
    }
}

fn study() -> Study {
    Study {
        names: vec!["x".into(), "y".into()],
        variables: vec![
            Distribution::Uniform { lo: 0.0, hi: 1.0 },
            Distribution::Uniform { lo: -2.0, hi: 2.0 },
        ],
        axes: vec![Axis {
            variable: 1,
            lo: -2.0,
            hi: 2.0,
            bins: 5,
        }],
        seed: 2026,
    }
}

#[test]
fn results_do_not_depend_on_the_number_of_threads() {
    let s = study();
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let two = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let a = one.install(|| run(&s, &Quarters, 0..5000, &Progress::default()).unwrap());
    let b = two.install(|| run(&s, &Quarters, 0..5000, &Progress::default()).unwrap());
    assert_eq!(a, b);
    assert_eq!(a.ranges, vec![(0, 5000)]);
    // A different seed gives different draws.
    let c = run(
        &Study { seed: 1, ..s },
        &Quarters,
        0..5000,
        &Progress::default(),
    )
    .unwrap();
    assert_ne!(a.counts, c.counts);
}

#[test]
fn shards_merge_to_the_whole_and_double_counting_is_refused() {
    let s = study();
    let whole = run(&s, &Quarters, 0..3000, &Progress::default()).unwrap();
    let mut merged = run(
        &s,
        &Quarters,
        shard_range(3000, 0, 3).unwrap(),
        &Progress::default(),
    )
    .unwrap();
    for i in 1..3 {
        let part = run(
            &s,
            &Quarters,
            shard_range(3000, i, 3).unwrap(),
            &Progress::default(),
        )
        .unwrap();
        merged.merge(&part).unwrap();
    }
    assert_eq!(merged.counts, whole.counts);
    let again = run(&s, &Quarters, 0..10, &Progress::default()).unwrap();
    assert!(merged.merge(&again).is_err());
    assert!(shard_range(10, 3, 3).is_err());
}

/// An interrupted run's missing trials split among processes (as MPI ranks do): the shares
/// are disjoint, cover exactly the missing trials, differ in size by at most one, and the counts
/// merged are the whole run's.
#[test]
fn the_missing_trials_share_out_among_processes() {
    let s = study();
    let whole = run(&s, &Quarters, 0..3000, &Progress::default()).unwrap();
    // A run that counted two stretches, then stopped.
    let mut resumed = run(&s, &Quarters, 100..700, &Progress::default()).unwrap();
    resumed
        .merge(&run(&s, &Quarters, 1500..1800, &Progress::default()).unwrap())
        .unwrap();
    let missing = resumed.missing(0..3000);
    for n in [1u64, 2, 3, 7, 4000] {
        let shares: Vec<_> = (0..n).map(|i| share(&missing, i, n).unwrap()).collect();
        let sizes: Vec<u64> = shares
            .iter()
            .map(|s| s.iter().map(|r| r.end - r.start).sum())
            .collect();
        assert_eq!(sizes.iter().sum::<u64>(), 2100, "n = {n}");
        assert!(sizes.iter().max().unwrap() - sizes.iter().min().unwrap() <= 1);
        let mut all = resumed.clone();
        for ranges in &shares {
            for r in ranges {
                all.merge(&run(&s, &Quarters, r.clone(), &Progress::default()).unwrap())
                    .unwrap();
            }
        }
        assert_eq!(all.counts, whole.counts, "n = {n}");
        assert!(all.missing(0..3000).is_empty());
    }
    assert!(share(&missing, 0, 0).is_err());
    assert_eq!(
        share(&[], 0, 3).unwrap(),
        Vec::<std::ops::Range<u64>>::new()
    );
}

#[test]
fn fractions_have_covering_wilson_intervals() {
    // Each quarter has probability 1/4 in every cell; the 95 % interval must contain it in
    // (nearly) all cells and be narrow.
    let s = study();
    let counts = run(&s, &Quarters, 0..40_000, &Progress::default()).unwrap();
    let mut covered = 0;
    for cell in 0..5 {
        assert!(counts.trials(cell) > 7000);
        for class in 0..4 {
            let (p, lo, hi) = counts.fraction(cell, class);
            assert!(lo <= p && p <= hi && hi - lo < 0.03);
            if lo <= 0.25 && 0.25 <= hi {
                covered += 1;
            }
        }
    }
    assert!(covered >= 18, "only {covered} of 20 intervals cover 0.25");
}

#[test]
fn an_interrupted_run_reports_exactly_what_it_counted() {
    let s = study();
    let progress = Progress::default();
    progress.stop.store(true, Ordering::Relaxed);
    let none = run(&s, &Quarters, 0..1000, &progress).unwrap();
    assert!(none.ranges.is_empty());
    assert_eq!((0..5).map(|c| none.trials(c)).sum::<u64>(), 0);
}

#[test]
fn invalid_studies_are_rejected() {
    let mut s = study();
    s.variables[0] = Distribution::Uniform { lo: 1.0, hi: 1.0 };
    assert!(run(&s, &Quarters, 0..10, &Progress::default()).is_err());
}

/// x'' + c x' + x = cos(omega t), made autonomous with (r, s) = (sin, cos) of omega t.
/// Steady state: amplitude 1 / sqrt((1 - omega^2)^2 + (c omega)^2).
struct Forced;
impl HybridSystem for Forced {
    fn state_dim(&self) -> usize {
        4
    }
    fn parameter_names(&self) -> &[&'static str] {
        &["omega", "c"]
    }
    fn mode_count(&self) -> usize {
        1
    }
    fn mode_name(&self, _: Mode) -> &'static str {
        "linear"
    }
    fn events(&self, _: Mode) -> &[EventId] {
        &[]
    }
    fn event_spec(&self, _: EventId) -> EventSpec {
        EventSpec {
            name: "none",
            direction: Direction::Either,
            action: EventAction::Terminal,
        }
    }
    fn vector_field(&self, _: Mode, x: &[f64], p: &[f64], out: &mut [f64]) {
        let (w, c) = (p[0], p[1]);
        let rho = x[2] * x[2] + x[3] * x[3];
        out[0] = x[1];
        out[1] = -c * x[1] - x[0] + x[3];
        out[2] = x[2] + w * x[3] - x[2] * rho;
        out[3] = x[3] - w * x[2] - x[3] * rho;
    }
    fn event(&self, _: EventId, _: &[f64], _: &[f64]) -> f64 {
        1.0
    }
}

#[test]
fn brute_force_sweep_reaches_the_closed_form_steady_state() {
    let omega: f64 = 0.8;
    let sweep = Sweep {
        values: vec![0.5, 1.0],
        parameter: 1,
        period: 2.0 * std::f64::consts::PI / omega,
        transient: 60,
        recorded: 5,
    };
    let pts = brute_force(
        &Forced,
        Mode(0),
        &[0.0, 0.0, 0.0, 1.0],
        &[omega, 0.5],
        &sweep,
        &SimulationSettings::default(),
        &hycont_sample::basin::Progress::default(),
    )
    .unwrap();
    assert_eq!(pts.len(), 2);
    for p in &pts {
        let c = p.value;
        let amp = 1.0 / ((1.0 - omega * omega).powi(2) + (c * omega).powi(2)).sqrt();
        let phase = (c * omega).atan2(1.0 - omega * omega);
        // At t = 2 pi k / omega the forcing phase is 0: x = amp cos(-phase).
        assert_eq!(p.samples.len(), 5);
        for s in &p.samples {
            assert_abs_diff_eq!(s[0], amp * phase.cos(), epsilon = 1e-7);
        }
    }
}
