//! Basin stability of the ball on a vibrating table with sticking (`examples/table_basins`)
//! through hycont's sampling API, against the closed forms of `tests/integration/vibrating_table.rs`.
//!
//! With $\omega = g = 1$, $e = 1/2$: the period-1 orbit has one impact per period at phase
//! $\theta_0$ with $a\omega^2\cos\theta_0 = \pi g(1-e)/(1+e)$ and post-impact velocity
//! $w^+ = e g T/(1+e)$; it exists for $a \ge a_\mathrm{SN} = \pi/3 = 1.0472$ and is stable (the
//! branch with $\sin\theta_0 > 0$) up to $a_\mathrm{PD} = 1.5268$, where a multiplier of the
//! impact map (trace $1 + e^2 - \kappa(1+e)$, determinant $e^2$,
//! $\kappa = a\omega^2\sin\theta_0(1+e)/g$) passes $-1$. Below $a\omega^2 = g$ the table
//! cannot lift a ball at rest, and no bouncing orbit exists (the period-1 fold is above it).

#[path = "../../examples/table_basins/model.rs"]
mod model;

use hycont::hycont_sample::adaptive::{Adaptive, CellCounts, run_cells};
use hycont::hycont_sample::basin::{Classifier, Progress};
use hycont::hycont_sample::classify::StrobeSettings;
use hycont::{SimulationSettings, Simulator};
use model::TableClassifier;
use std::f64::consts::PI;

const E: f64 = 0.5;

fn classifier() -> TableClassifier {
    TableClassifier {
        omega: 1.0,
        e: E,
        g: 1.0,
        settings: StrobeSettings::default(),
    }
}

/// The state just after the period-1 orbit's impact at amplitude `a` (stable branch).
fn on_orbit(a: f64) -> [f64; 3] {
    let t = 2.0 * PI;
    let theta0 = (PI * (1.0 - E) / (1.0 + E) / a).acos();
    [0.0, E * t / (1.0 + E), theta0]
}

/// The orbit's state a quarter period after its impact (the classifier's strobes then fall
/// between impacts, not on one: at the impact the strobe map jumps between the velocities
/// before and after it).
fn quarter_after_impact(a: f64) -> Vec<f64> {
    let p = [a, 1.0, E, 1.0];
    let mut sim = Simulator::new(SimulationSettings::default()).unwrap();
    let table = hycont::FiniteDifferences::new(model::StickyTable);
    let traj = sim
        .run(&table, model::FLIGHT, 0.0, &on_orbit(a), &p, 0.5 * PI)
        .unwrap();
    traj.state_final
}

/// Multipliers of the impact map at `a`: (trace, determinant).
fn impact_map(a: f64) -> (f64, f64) {
    let theta0 = on_orbit(a)[2];
    let kappa = a * theta0.sin() * (1.0 + E);
    (1.0 + E * E - kappa * (1.0 + E), E * E)
}

#[test]
fn the_closed_form_orbit_attracts_exactly_where_it_is_stable() {
    let c = classifier();
    let a_pd = (4.0 * (1.0 + E * E).powi(2) / (1.0 + E).powi(4)
        + (PI * (1.0 - E) / (1.0 + E)).powi(2))
    .sqrt();
    for a in [1.1, 1.3, 1.45, 1.6, 1.7] {
        // The largest multiplier's modulus from the trace and determinant.
        let (tr, det) = impact_map(a);
        let disc = tr * tr - 4.0 * det;
        let rho = if disc >= 0.0 {
            0.5 * (tr.abs() + disc.sqrt())
        } else {
            det.sqrt()
        };
        assert_eq!(rho < 1.0, a < a_pd, "a = {a}: rho = {rho}");
        // Started 1e-3 off the orbit: back onto it where stable, away where not.
        let mut x = quarter_after_impact(a);
        x[0] += 1e-3;
        let class = c.classify(&[a, x[0], x[1], x[2]]).unwrap();
        if rho < 1.0 {
            assert_eq!(class, 2, "a = {a}: {}", model::CLASSES[class]);
        } else {
            assert_ne!(class, 2, "a = {a}");
        }
    }
}

#[test]
fn basins_follow_the_closed_forms() {
    let study = model::amplitude_study(1);
    let c = classifier();
    let rule = Adaptive::default();
    let mut counts = CellCounts::new(c.classes(), study.cells());
    let cells: Vec<usize> = (0..study.cells()).collect();
    run_cells(&study, &c, &rule, &mut counts, &cells, &Progress::default()).unwrap();
    for cell in 0..study.cells() {
        let (lo, hi) = (0.5 + 0.1 * cell as f64, 0.6 + 0.1 * cell as f64);
        assert!(counts.settled[cell], "cell {cell}");
        assert!(counts.halfwidth(cell) <= rule.halfwidth || counts.trials[cell] >= rule.max_trials);
        let stuck = counts.counts[cell][0];
        if hi <= 1.0 + 1e-12 {
            // a omega^2 < g: every ball comes to rest for good.
            assert_eq!(stuck, counts.trials[cell], "cell [{lo}, {hi})");
        } else {
            // The table lifts a resting ball: never stuck for good.
            assert_eq!(stuck, 0, "cell [{lo}, {hi})");
        }
        if hi <= PI / 3.0 {
            // Below the period-1 fold: no bouncing period-1 orbit.
            assert_eq!(counts.counts[cell][2], 0, "cell [{lo}, {hi})");
        }
    }
}

/// The example's study through hycont-sample's runner: stopped after a budget of trials, its
/// partial file holds the exact cells counted; resumed from it, the counts equal an
/// uninterrupted run's (every cell's record); three shards of its cells merge to the same.
#[test]
fn the_study_resumes_and_merges_to_an_uninterrupted_run() {
    use hycont::hycont_sample::study::{self, CountFile, Outcome, Ranks, StudyFile};
    let dir = std::env::temp_dir().join(format!("hycont-tb-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let rule = Adaptive {
        halfwidth: 0.1,
        ..Adaptive::default()
    };
    let make = |shard| {
        StudyFile::cells("tb", model::amplitude_study(1), classifier(), rule, shard).unwrap()
    };
    let run = |file, progress: &Progress| study::sample(file, &dir, progress, Ranks::current());
    let Outcome::Complete { file: whole, .. } = run(make((0, 1)), &Progress::default()).unwrap()
    else {
        panic!("not complete")
    };
    let Outcome::Partial { path, file } = run(make((0, 1)), &Progress::with_budget(200)).unwrap()
    else {
        panic!("not stopped")
    };
    assert!(file.progress().0 < file.progress().1);
    let resumed = StudyFile::<TableClassifier>::read(&path).unwrap();
    let Outcome::Complete { file: done, .. } = run(resumed, &Progress::default()).unwrap() else {
        panic!("not complete")
    };
    assert_eq!(done.plan, whole.plan);
    let shards: Vec<_> = (0..3)
        .map(|i| {
            let Outcome::Complete {
                written: Some(p), ..
            } = run(make((i, 3)), &Progress::default()).unwrap()
            else {
                panic!("shard {i}")
            };
            (p.clone(), StudyFile::<TableClassifier>::read(&p).unwrap())
        })
        .collect();
    assert_eq!(study::merge(shards).unwrap().plan, whole.plan);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The bouncing orbit's own neighbourhood (the example's second table): started near the
/// closed-form orbit (`model::NearOrbit`, take-off velocity within 2 % and phase within
/// 0.02 rad), every trial is period 1 in the cells where the closed form's multipliers are
/// inside the unit circle, and none is beyond the period doubling, where the orbit is unstable
/// (a trial lands on an unstable orbit with probability 0). The drops of the main study, with
/// less energy than the orbit, all end on the sticking orbit in `[1.1, 1.5)` instead.
#[test]
fn trials_near_the_bouncing_orbit_stay_exactly_where_it_is_stable() {
    let near = model::NearOrbit {
        table: classifier(),
        spread: 0.02,
    };
    let (lo, bins) = (1.1, 6);
    let study = model::near_orbit_study(lo, lo + 0.1 * bins as f64, bins, 3);
    let rule = Adaptive::default();
    let mut counts = CellCounts::new(near.classes(), bins);
    let cells: Vec<usize> = (0..bins).collect();
    run_cells(
        &study,
        &near,
        &rule,
        &mut counts,
        &cells,
        &Progress::default(),
    )
    .unwrap();
    for cell in 0..bins {
        let (a_lo, a_hi) = (lo + 0.1 * cell as f64, lo + 0.1 * (cell + 1) as f64);
        let mu = |a| model::orbit_multiplier(a, 1.0, E, 1.0).unwrap();
        let period_one = counts.counts[cell][2];
        assert!(counts.trials[cell] > 0 && counts.failures[cell] == 0);
        if mu(a_lo) < 1.0 && mu(a_hi) < 1.0 {
            assert_eq!(period_one, counts.trials[cell], "[{a_lo}, {a_hi})");
        } else if mu(a_lo) > 1.0 {
            assert_eq!(period_one, 0, "[{a_lo}, {a_hi})");
        }
    }
    // The main study's drops in [1.1, 1.5): the sticking orbit, not the bouncing one.
    let drops = model::amplitude_study(1);
    let mut main = CellCounts::new(classifier().classes(), drops.cells());
    run_cells(
        &drops,
        &classifier(),
        &rule,
        &mut main,
        &[6, 7],
        &Progress::default(),
    )
    .unwrap();
    for cell in [6, 7] {
        assert_eq!(main.counts[cell][1], main.trials[cell], "cell {cell}");
    }
}
