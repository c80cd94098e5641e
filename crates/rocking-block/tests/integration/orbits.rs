//! Periodic orbits of the rocking block against the study's reference values (issue: orbits),
//! both discretisations, and Floquet multipliers against finite differences of the period map.

use approx::assert_abs_diff_eq;
use hycont_core::orbit::{
    CollocationSettings, ShootingSettings, monodromy_by_shooting, solve_collocation,
};
use hycont_core::orbit::{Extremum, GrazingMargin, Measure, PeriodicOrbit};
use hycont_core::problem::NewtonSettings;
use hycont_core::{HybridSystem, SimulationSettings, Simulator};
use rocking_block::orbits::{OrbitKind, orbit};
use rocking_block::{IMPACT_MINUS, IMPACT_PLUS, Parameters, RockingBlock};
use std::f64::consts::PI;

/// Amp: the true maximum of |phi|.
fn amplitude(o: &PeriodicOrbit) -> f64 {
    Extremum::max_abs(0).evaluate(&RockingBlock, o).unwrap()
}

/// The signed grazing margin of the flights' turning points to phi = 0.
fn grazing_margin(o: &PeriodicOrbit) -> f64 {
    GrazingMargin::new([IMPACT_PLUS, IMPACT_MINUS])
        .cap(std::f64::consts::FRAC_PI_2)
        .evaluate(&RockingBlock, o)
        .unwrap()
}

fn nontrivial(report: &rocking_block::report::OrbitReport) -> Vec<f64> {
    let mut m: Vec<f64> = report
        .multipliers
        .iter()
        .zip(&report.trivial)
        .filter(|(_, t)| !**t)
        .map(|(z, _)| z[0])
        .collect();
    m.sort_by(|a, b| b.total_cmp(a));
    m
}

#[test]
fn symmetric_orbit_reference_values() {
    let params = Parameters::new(1.3, 0.66);
    let o = orbit(&params, OrbitKind::Symmetric, None).unwrap();
    let r = o.report("symmetric").unwrap();
    assert!(r.symmetric);
    assert_eq!(r.segments.len(), 2);
    for s in &r.segments {
        assert_abs_diff_eq!(s.duration, PI / 1.3, epsilon = 1e-9);
        assert_abs_diff_eq!(s.start[1].abs(), 0.37347, epsilon = 5e-6);
    }
    // Pre-impact |psi| = post-impact / e.
    let pre = r.segments[0].start[1].abs() / params.restitution();
    assert_abs_diff_eq!(pre, 0.95683, epsilon = 5e-6);
    assert_abs_diff_eq!(r.amp, 0.43843, epsilon = 5e-6);
    let m = nontrivial(&r);
    assert!(
        (m[0] - 1.2292).abs() < 5e-5 && (m[1] - 0.018868).abs() < 5e-7,
        "{m:?}"
    );
    assert!(!r.stable);
    // Trivial multipliers: 1 and exp(-2T).
    let trivial: Vec<f64> = r
        .multipliers
        .iter()
        .zip(&r.trivial)
        .filter(|(_, t)| **t)
        .map(|(z, _)| z[0])
        .collect();
    assert!(trivial.iter().any(|v| (v - 1.0).abs() < 1e-8));
    assert!(
        trivial
            .iter()
            .any(|v| (v - (-2.0 * r.period).exp()).abs() < 1e-10)
    );
    // Half-map multipliers: mu^2 = lambda; the unstable one is negative (past a BP).
    let half = r.half_multipliers.unwrap();
    assert!(
        half.iter()
            .any(|z| (z[0] * z[0] - m[0]).abs() < 1e-8 && z[0] < -1.0),
        "{half:?}"
    );
}

#[test]
fn asymmetric_orbits_reference_values() {
    let params = Parameters::new(1.3, 0.66);
    let pos = orbit(&params, OrbitKind::AsymmetricPos, None)
        .unwrap()
        .report("asymmetric-pos")
        .unwrap();
    let neg = orbit(&params, OrbitKind::AsymmetricNeg, None)
        .unwrap()
        .report("asymmetric-neg")
        .unwrap();
    for r in [&pos, &neg] {
        assert!(!r.symmetric && r.stable);
        assert_abs_diff_eq!(r.amp, 0.62605, epsilon = 5e-6);
        let m = nontrivial(r);
        assert!(
            (m[0] - 0.48968).abs() < 5e-6 && (m[1] - 0.047362).abs() < 5e-7,
            "{m:?}"
        );
    }
    let plus = pos
        .segments
        .iter()
        .find(|s| s.mode == "+")
        .unwrap()
        .duration;
    let minus = pos
        .segments
        .iter()
        .find(|s| s.mode == "-")
        .unwrap()
        .duration;
    assert!(
        (plus - 3.14569).abs() < 5e-6 && (minus - 1.68753).abs() < 5e-6,
        "{plus} {minus}"
    );
    let plus_neg = neg
        .segments
        .iter()
        .find(|s| s.mode == "+")
        .unwrap()
        .duration;
    assert_abs_diff_eq!(plus_neg, 1.68753, epsilon = 5e-6);
}

#[test]
fn collocation_and_shooting_agree_to_1e_8() {
    let params = Parameters::new(1.3, 0.66);
    for kind in [OrbitKind::Symmetric, OrbitKind::AsymmetricPos] {
        let sh = orbit(&params, kind, None).unwrap().solution;
        let co = solve_collocation(
            &RockingBlock,
            &sh.orbit,
            CollocationSettings::default(),
            &NewtonSettings::default(),
        )
        .unwrap()
        .solution;
        for (a, b) in sh.orbit.durations.iter().zip(&co.orbit.durations) {
            assert_abs_diff_eq!(a, b, epsilon = 1e-8);
        }
        for (x, y) in sh
            .orbit
            .starts
            .iter()
            .flatten()
            .zip(co.orbit.starts.iter().flatten())
        {
            assert_abs_diff_eq!(x, y, epsilon = 1e-8);
        }
        for (a, b) in sh.floquet.multipliers.iter().zip(&co.floquet.multipliers) {
            assert!(
                (a.0 - b.0).abs() + (a.1 - b.1).abs() < 1e-8,
                "{kind:?} multipliers {a:?} vs {b:?}"
            );
        }
        assert_abs_diff_eq!(amplitude(&sh.orbit), amplitude(&co.orbit), epsilon = 1e-8);
    }
}

/// Jacobian of the full hybrid period map (simulation with events over one period) by central
/// differences, from a point inside a flight (an extremum, away from the impact surface).
fn period_map_jacobian(x0: &[f64], mode: hycont_core::Mode, p: &[f64], period: f64) -> Vec<f64> {
    let mut sim = Simulator::new(SimulationSettings::default().rtol(1e-13).atol(1e-15)).unwrap();
    let mut flow = |x: &[f64]| {
        sim.run(&RockingBlock, mode, 0.0, x, p, period)
            .unwrap()
            .state_final
    };
    let h = 1e-6;
    let mut jac = vec![0.0; 16];
    for j in 0..4 {
        let (mut xp, mut xm) = (x0.to_vec(), x0.to_vec());
        xp[j] += h;
        xm[j] -= h;
        let (fp, fm) = (flow(&xp), flow(&xm));
        for i in 0..4 {
            jac[i + 4 * j] = (fp[i] - fm[i]) / (2.0 * h);
        }
    }
    jac
}

#[test]
fn multipliers_match_finite_differences_of_the_period_map() {
    let params = Parameters::new(1.3, 0.66);
    for kind in [OrbitKind::Symmetric, OrbitKind::AsymmetricPos] {
        let sol = orbit(&params, kind, None).unwrap().solution;
        // Start at the first interior extremum (psi = 0).
        let k = sol
            .orbit
            .starts
            .iter()
            .position(|x| x[0].abs() > 0.1)
            .expect("an interior extremum");
        let x0 = &sol.orbit.starts[k];
        let mode = sol.orbit.signature.segments()[k].mode;
        let fd = period_map_jacobian(x0, mode, &sol.orbit.params, sol.orbit.period());
        let fd_eigs = hycont_core::linalg::eigenvalues(4, &fd).unwrap();
        for (a, b) in sol.floquet.multipliers.iter().zip(&fd_eigs) {
            assert!(
                (a.0 - b.0).abs() + (a.1 - b.1).abs() < 1e-6,
                "{kind:?}: {a:?} vs finite differences {b:?}"
            );
        }
        // And the monodromy from shooting at that segment start agrees with the FD matrix.
        let rotated = {
            let mut o = sol.orbit.clone();
            let kk = o.segment_count();
            let segs: Vec<_> = (0..kk)
                .map(|i| o.signature.segments()[(i + k) % kk])
                .collect();
            o.signature = hycont_core::orbit::Signature::new(&RockingBlock, segs).unwrap();
            o.starts.rotate_left(k);
            o.durations.rotate_left(k);
            o
        };
        let m =
            monodromy_by_shooting(&RockingBlock, &rotated, ShootingSettings::default()).unwrap();
        for (a, b) in m.monodromy.iter().zip(&fd) {
            assert_abs_diff_eq!(a, b, epsilon = 1e-6 * (1.0 + b.abs()));
        }
    }
    let _ = RockingBlock.state_dim();
}

#[test]
fn orbit_kinds_report_their_symmetry_and_simulation_finds_the_attractor() {
    let params = Parameters::new(1.3, 0.66);
    let sim = orbit(&params, OrbitKind::Simulate, None)
        .unwrap()
        .report("simulate")
        .unwrap();
    assert!(!sim.symmetric && sim.stable);
    assert_abs_diff_eq!(sim.amp, 0.62605, epsilon = 5e-6);
}

#[test]
fn mesh_adaptation_reduces_the_error_at_fixed_ntst() {
    let params = Parameters::new(1.3, 0.66);
    let sh = orbit(&params, OrbitKind::AsymmetricPos, None)
        .unwrap()
        .solution;
    let flights = sh.orbit.without_interior_points(&RockingBlock).unwrap();
    let err = |adapt| {
        let co = solve_collocation(
            &RockingBlock,
            &flights,
            CollocationSettings {
                ntst: 6,
                ncol: 2,
                adapt,
            },
            &NewtonSettings::default(),
        )
        .unwrap()
        .solution;
        let reference = sh.orbit.without_interior_points(&RockingBlock).unwrap();
        co.orbit
            .durations
            .iter()
            .zip(&reference.durations)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max)
    };
    let (uniform, adapted) = (err(0), err(3));
    eprintln!("uniform {uniform:e}, adapted {adapted:e}");
    assert!(
        adapted < 0.75 * uniform,
        "uniform {uniform:e}, adapted {adapted:e}"
    );
}

#[test]
fn orbit_from_an_explicit_initial_state_and_signature() {
    use hycont_core::orbit::{PeriodicOrbit, SegmentEnd, SegmentSpec, Signature, solve_shooting};
    use rocking_block::{IMPACT_MINUS, IMPACT_PLUS, MINUS, PLUS};
    // A rough point of the asymmetric orbit (just after the impact into mode +) and its
    // signature: + until impact+, - until impact-.
    let params = Parameters::new(1.3, 0.66);
    let sig = Signature::new(
        &RockingBlock,
        vec![
            SegmentSpec {
                mode: PLUS,
                end: SegmentEnd::Event(IMPACT_PLUS),
            },
            SegmentSpec {
                mode: MINUS,
                end: SegmentEnd::Event(IMPACT_MINUS),
            },
        ],
    )
    .unwrap();
    let x0 = [0.0, 0.29, 0.99, -0.07];
    let guess = PeriodicOrbit::from_initial_state(
        &RockingBlock,
        sig,
        &x0,
        &params.to_vec(),
        20.0,
        &SimulationSettings::default(),
    )
    .unwrap();
    let sol = solve_shooting(
        &RockingBlock,
        &guess,
        ShootingSettings::default(),
        &NewtonSettings::default(),
    )
    .unwrap();
    assert_abs_diff_eq!(sol.orbit.durations[0], 3.14569, epsilon = 5e-6);
    assert_abs_diff_eq!(sol.orbit.durations[1], 1.68753, epsilon = 5e-6);
}

#[test]
fn grazing_margin_finds_turning_points_at_segment_boundaries() {
    use hycont_core::orbit::{SegmentEnd, SegmentSpec, Signature};
    use rocking_block::PLUS;
    // A mode + flight with an interior extremum where |phi| has a local minimum (phi > 0 and
    // psi' > 0: the forcing pushes the block back up before it reaches the ground).
    let params = Parameters::new(1.3, 0.66);
    let p = params.to_vec();
    let sig = Signature::new(
        &RockingBlock,
        vec![
            SegmentSpec {
                mode: PLUS,
                end: SegmentEnd::Interior {
                    component: 1,
                    value: 0.0,
                },
            },
            SegmentSpec {
                mode: PLUS,
                end: SegmentEnd::Interior {
                    component: 1,
                    value: 0.0,
                },
            },
            SegmentSpec {
                mode: PLUS,
                end: SegmentEnd::Event(IMPACT_PLUS),
            },
        ],
    );
    // IMPACT_PLUS leads to mode -, so a single-mode cycle is inconsistent: the signature is
    // rejected, and the measure is computed on a hand-built orbit value instead.
    assert!(sig.is_err());
    let sig = Signature::new(
        &RockingBlock,
        vec![
            SegmentSpec {
                mode: PLUS,
                end: SegmentEnd::Interior {
                    component: 1,
                    value: 0.0,
                },
            },
            SegmentSpec {
                mode: PLUS,
                end: SegmentEnd::Interior {
                    component: 1,
                    value: 0.0,
                },
            },
        ],
    )
    .unwrap();
    // r = 1 at the turning point makes psi' = 3/4 (alpha omega^2 sin(theta_b + phi) - cos(...)) > 0.
    let orbit = PeriodicOrbit::new(
        &RockingBlock,
        sig,
        vec![vec![0.05, 0.0, 1.0, 0.0], vec![0.3, 0.0, -1.0, 0.0]],
        vec![1.0, 1.0],
        p,
    )
    .unwrap();
    assert_eq!(grazing_margin(&orbit), 0.05);
    assert_abs_diff_eq!(amplitude(&orbit), 0.3, epsilon = 1e-15);
}

#[test]
fn splitting_half_of_a_symmetric_orbit_keeps_its_closure() {
    use hycont_core::orbit::Closure;
    let full = orbit(&Parameters::new(1.3, 0.66), OrbitKind::Symmetric, None)
        .unwrap()
        .solution
        .orbit;
    let half = full.half_of_symmetric(&RockingBlock, 1e-5).unwrap();
    assert_eq!(half.signature.closure(), Closure::Symmetric);
    // Its psi = 0 points are already segment ends: nothing new to split, same orbit back, still
    // closing through the symmetry (as a periodic cycle its modes would not close).
    let split = half
        .with_interior_points(&RockingBlock, 1, 0.0, &SimulationSettings::default())
        .unwrap();
    assert_eq!(split.signature.closure(), Closure::Symmetric);
    assert_eq!(split.segment_count(), half.segment_count());
    // Its grazing margin: no flight turns back (capped at pi/2); the full orbit agrees.
    let m = grazing_margin(&half);
    assert_eq!(m, grazing_margin(&full));
    assert!(m > 0.0);
}
