//! Collocation meshes adapted along a branch, against the closed-form orbits of the relaxation
//! oscillator.
//!
//! # The reference
//! `Relaxation` (hycont-core's test models): $\dot x = a - x$, $\dot y = -2y$, fired at
//! $x = 1.5$ and reset to $(x/3, y + 1)$. Its orbit starts at $x = 0.5$,
//! $y_0 = 1/(1 - e^{-2T})$ and lasts $T(a) = \ln\frac{a - 0.5}{a - 1.5}$; at time $t$ of the
//! segment $x = a - (a - 0.5)e^{-t}$, $y = y_0 e^{-2t}$. As $a \to 1.5$ the period grows
//! ($T = 3.9$ at $a = 1.52$ against $0.51$ at $a = 3$) and the orbit's fast start and slow tail
//! differ more and more: a mesh fixed at the start loses accuracy along the branch, and one
//! that equidistributes the error keeps it. The true error of a point is the largest
//! difference between its polynomial (read on a fine mesh through the transfer, which
//! evaluates it) and the closed form.

#[path = "../../../hycont-core/tests/integration/common/mod.rs"]
mod common;

use common::Relaxation;
use hycont_continuation::{BranchPoint, OrbitBranch, OrbitRun, RunDirection};
use hycont_core::ParamId;
use hycont_core::orbit::{CollocationSettings, OrbitMethod, PeriodicOrbit};

fn start(a: f64) -> PeriodicOrbit {
    Relaxation::orbit([0.5, Relaxation::y0(a)], Relaxation::period(a), a)
}

/// The run from a = 3 down to a = 1.52 starting on 8 intervals of degree 3, adapting its mesh
/// (the defaults: every 10 points, and refined above an estimate of 1e-6) or not.
fn run(adapt: bool) -> OrbitBranch {
    let mut run = OrbitRun::new(&Relaxation, ParamId(0)).unwrap();
    run.method(OrbitMethod::Collocation(CollocationSettings {
        ntst: 8,
        ncol: 3,
        adapt: 1,
    }))
    .bounds(1.52, 3.5);
    if !adapt {
        *run.settings_mut() = run.settings_mut().clone().adaptation(0, f64::INFINITY);
    }
    run.run("relaxation", &start(3.0), RunDirection::Down)
        .unwrap()
}

/// The true largest error of a point of `branch`, on the point's own discretisation (see
/// `Relaxation::collocation_error`).
fn true_error(branch: &OrbitBranch, p: &BranchPoint) -> f64 {
    let disc = branch.discretisation_of(p).unwrap();
    Relaxation::collocation_error(disc, &branch.template, &p.u, p.params[0])
}

/// Along the branch the adapted run re-meshes, and refines its mesh where the estimate exceeds
/// the default tolerance 1e-6 (8 intervals at the start, 20 at the end), so that its estimates
/// stay within half the tolerance above it (a point above it is the last on its mesh) and its
/// true error at the end, where the orbit is most uneven, is below 1.5e-6: a hundredth of the
/// fixed mesh's (2.2e-4 there). Every point of either run reports an estimate within a factor
/// 2 of its true error (asymptotically exact; within 25 % on uniform meshes, see hycont-core's
/// `collocation_error`). The periods agree with $T(a)$ to 1e-5 on either mesh: the event
/// $x = 1.5$ is reached with $\dot x = a - 1.5 = 0.02$ at $a = 1.52$, so the period magnifies
/// the error at the segment's end fifty-fold, and equidistributing the largest error leaves
/// the slow tail relatively fewer intervals.
#[test]
fn an_adapted_mesh_keeps_the_error_down_along_the_branch() {
    let (adapted, fixed) = (run(true), run(false));
    assert!(adapted.branch.statistics.rediscretisations >= 1);
    assert_eq!(fixed.branch.statistics.rediscretisations, 0);
    assert!(adapted.branch.points.iter().any(|p| p.discretisation > 0));
    assert!(!adapted.rediscretised.is_empty());
    for b in [&adapted, &fixed] {
        for p in &b.branch.points {
            let truth = true_error(b, p);
            let estimate = p.discretisation_error.unwrap();
            assert!(
                (0.5..=2.0).contains(&(estimate / truth)),
                "a = {}: estimate {estimate:e}, true {truth:e}",
                p.params[0]
            );
            let period = b.orbit_of(p).unwrap().durations[0];
            assert!((period - Relaxation::period(p.params[0])).abs() < 1e-5);
        }
    }
    let end = |b: &OrbitBranch| {
        let p = b.branch.points.last().unwrap();
        assert!((p.params[0] - 1.52).abs() < 1e-9, "ends on the bound");
        true_error(b, p)
    };
    let sizes: Vec<usize> = std::iter::once(&adapted.discretisation)
        .chain(&adapted.rediscretised)
        .map(|d| match d {
            hycont_core::orbit::Discretisation::Collocation { meshes, .. } => meshes[0].len() - 1,
            _ => unreachable!(),
        })
        .collect();
    let largest = adapted
        .branch
        .points
        .iter()
        .map(|p| p.discretisation_error.unwrap())
        .fold(0.0, f64::max);
    // The mesh grows as the orbit gets more uneven (8 intervals at the start).
    assert!(sizes.windows(2).all(|w| w[1] >= w[0]), "{sizes:?}");
    assert!(*sizes.last().unwrap() > 8, "{sizes:?}");
    // A point above the tolerance is the last one on its mesh: the estimate grows by a few
    // per cent per step, so none exceeds it by half.
    assert!(largest < 1.5e-6, "largest estimate {largest:e}");
    let (e_adapted, e_fixed) = (end(&adapted), end(&fixed));
    assert!(
        e_adapted < 1.5e-6 && e_adapted <= 0.01 * e_fixed,
        "adapted {e_adapted:e}, fixed {e_fixed:e}"
    );
}

/// A branch with adapted meshes saves every discretisation: it reads back equal and valid,
/// a restart from its last point (on a later mesh) continues on that mesh, and a point naming
/// a discretisation the branch lacks is refused.
#[test]
fn adapted_branches_save_and_restart_on_their_meshes() {
    let branch = run(true);
    let text = branch.to_json().unwrap();
    let back = OrbitBranch::from_json(&text).unwrap();
    assert_eq!(back, branch);
    back.validate(&Relaxation).unwrap();
    let last = branch.branch.points.last().unwrap();
    assert!(last.discretisation > 0);
    let mut run = OrbitRun::new(&Relaxation, ParamId(0)).unwrap();
    run.method(OrbitMethod::Collocation(CollocationSettings {
        ntst: 8,
        ncol: 3,
        adapt: 1,
    }))
    .bounds(1.51, 3.5)
    .max_points(5);
    let again = run
        .restart("again", &branch, last.label, Some(RunDirection::Up))
        .unwrap();
    let first = &again.branch.points[0];
    assert_eq!(first.discretisation, 0);
    assert_eq!(
        again.discretisation,
        *branch.discretisation_of(last).unwrap()
    );
    assert!((first.params[0] - last.params[0]).abs() < 1e-9);
    assert!(true_error(&again, first) < 1.5 * true_error(&branch, last));
    let mut broken = branch.clone();
    broken.branch.points[0].discretisation = branch.rediscretised.len() + 1;
    assert!(broken.validate(&Relaxation).is_err());
}
