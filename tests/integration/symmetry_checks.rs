//! Symmetries are checked before they are used: a symmetry that is not one (a matrix of the
//! wrong size, $S^2 \ne I$, an event map that does not follow the event functions, a reset or
//! a vector field that does not commute with $S$) is a typed error naming what is wrong, from
//! the search, the half-orbit solves and continuation; never a panic or an "orbit" that is not
//! one. A half orbit given to `solve_orbit` is solved as one, with the full orbit's
//! multipliers; `solve_shooting` and `solve_collocation` refuse it.
//!
//! The system: the symmetric two-sided impact oscillator of `examples/symmetric_branch`, with
//! one flaw at a time.

use crate::model_symmetric_branch as pair;

use approx::assert_abs_diff_eq;
use hycont::hycont_continuation::{Error as RunError, OrbitRun, RunDirection};
use hycont::orbit::{
    Closure, CollocationSettings, OrbitMethod, PeriodicOrbit, SegmentEnd, SegmentSpec,
    ShootingSettings, Signature, SymmetricSearch, find_symmetric_orbit, solve_collocation,
    solve_orbit, solve_shooting,
};
use hycont::problem::NewtonSettings;
use hycont::{
    Error, EventId, EventSpec, FiniteDifferences, HybridSystem, Mode, Z2Symmetry, checked_symmetry,
};
use pair::{FREE, ImpactPair, LEFT, RIGHT};
use std::f64::consts::{PI, TAU};

#[derive(Debug, Clone, Copy, PartialEq)]
enum Flaw {
    /// A 3 x 3 matrix for the 4-dimensional state.
    SmallMatrix,
    /// A matrix with S^2 != I (one entry doubled).
    NotAnInvolution,
    /// The walls not swapped (the event map is the identity).
    EventsNotSwapped,
    /// The left wall restitutes less than the right one.
    ResetNotEquivariant,
    /// A constant force on the oscillator (not odd).
    FieldNotEquivariant,
}

const FLAWS: [Flaw; 5] = [
    Flaw::SmallMatrix,
    Flaw::NotAnInvolution,
    Flaw::EventsNotSwapped,
    Flaw::ResetNotEquivariant,
    Flaw::FieldNotEquivariant,
];

/// The impact pair with one flaw.
struct Flawed(Flaw);

impl HybridSystem for Flawed {
    fn state_dim(&self) -> usize {
        4
    }
    fn parameter_names(&self) -> &[&'static str] {
        ImpactPair.parameter_names()
    }
    fn mode_count(&self) -> usize {
        1
    }
    fn mode_name(&self, m: Mode) -> &'static str {
        ImpactPair.mode_name(m)
    }
    fn events(&self, m: Mode) -> &[EventId] {
        ImpactPair.events(m)
    }
    fn event_spec(&self, e: EventId) -> EventSpec {
        ImpactPair.event_spec(e)
    }
    fn vector_field(&self, m: Mode, x: &[f64], p: &[f64], f: &mut [f64]) {
        ImpactPair.vector_field(m, x, p, f);
        if self.0 == Flaw::FieldNotEquivariant {
            f[1] += 0.1;
        }
    }
    fn event(&self, e: EventId, x: &[f64], p: &[f64]) -> f64 {
        ImpactPair.event(e, x, p)
    }
    fn reset(&self, e: EventId, x: &[f64], p: &[f64], out: &mut [f64]) {
        ImpactPair.reset(e, x, p, out);
        if self.0 == Flaw::ResetNotEquivariant && e == LEFT {
            out[1] *= 0.9;
        }
    }
    fn symmetry(&self) -> Option<Z2Symmetry> {
        let mut sym = ImpactPair.symmetry()?;
        match self.0 {
            Flaw::SmallMatrix => {
                sym.matrix = vec![0.0; 9];
                for i in 0..3 {
                    sym.matrix[i + 3 * i] = -1.0;
                }
            }
            Flaw::NotAnInvolution => sym.matrix[0] = -2.0,
            Flaw::EventsNotSwapped => sym.events = vec![RIGHT, LEFT],
            _ => {}
        }
        Some(sym)
    }
    fn trivial_multipliers(&self, p: &[f64], period: f64) -> Vec<(f64, f64)> {
        ImpactPair.trivial_multipliers(p, period)
    }
}

fn half_signature<S: HybridSystem>(sys: &S) -> Result<Signature, Error> {
    Signature::with_closure(
        sys,
        vec![SegmentSpec {
            mode: FREE,
            end: SegmentEnd::Event(RIGHT),
        }],
        Closure::Symmetric,
    )
}

fn search() -> SymmetricSearch {
    let seeds = (0..12)
        .flat_map(|i| {
            (0..24).map(move |j| {
                let beta = TAU * f64::from(j) / 24.0;
                vec![-1.0, 0.1 + 0.25 * f64::from(i), beta.sin(), beta.cos()]
            })
        })
        .collect();
    SymmetricSearch::new(seeds).half_period(PI / 0.6)
}

const P: [f64; 6] = [1.0, 0.6, 1.0, 0.1, 1.0, 0.8];

fn symmetric_orbit() -> PeriodicOrbit {
    let half = half_signature(&ImpactPair).unwrap();
    find_symmetric_orbit(&ImpactPair, &half, &P, &search())
        .unwrap()
        .full
        .orbit
}

/// The reason of an `InvalidSymmetry`, or a panic naming what came instead.
fn reason<T>(r: Result<T, Error>, flaw: Flaw) -> String {
    match r {
        Err(Error::InvalidSymmetry { reason }) => reason,
        Err(other) => panic!("{flaw:?}: expected an invalid symmetry, got {other}"),
        Ok(_) => panic!("{flaw:?}: accepted"),
    }
}

fn expected_words(flaw: Flaw) -> &'static str {
    match flaw {
        Flaw::SmallMatrix => "9 entries",
        Flaw::NotAnInvolution => "S^2",
        Flaw::EventsNotSwapped => "does not map to its image",
        Flaw::ResetNotEquivariant => "reset",
        Flaw::FieldNotEquivariant => "vector field",
    }
}

/// The search refuses each flawed symmetry with a typed error naming the flaw (structural ones
/// already when the half orbit's signature is built).
#[test]
fn the_search_refuses_a_symmetry_that_is_not_one() {
    assert!(checked_symmetry(&ImpactPair).is_ok());
    for flaw in FLAWS {
        let sys = FiniteDifferences::new(Flawed(flaw));
        let why = match half_signature(&sys) {
            Err(e) => reason::<()>(Err(e), flaw),
            Ok(half) => reason(find_symmetric_orbit(&sys, &half, &P, &search()), flaw),
        };
        assert!(why.contains(expected_words(flaw)), "{flaw:?}: {why}");
    }
}

/// The half-orbit solves and continuation refuse them too: an orbit of the intact system,
/// handed to the flawed one, is not solved or continued on its half orbit through a symmetry
/// that does not hold.
#[test]
fn solves_and_runs_refuse_a_symmetry_that_is_not_one() {
    let orbit = symmetric_orbit();
    let newton = NewtonSettings::default();
    for flaw in FLAWS {
        let sys = FiniteDifferences::new(Flawed(flaw));
        for method in [
            OrbitMethod::Shooting(ShootingSettings::default()),
            OrbitMethod::Collocation(CollocationSettings::default()),
        ] {
            // Structural flaws and an event map that does not swap the walls: the orbit is not
            // recognised as symmetric (its second half is not the image of its first), and is
            // solved as the full orbit it is; the others are refused.
            let solved = solve_orbit(&sys, &orbit, &method, &newton, 1e-6);
            if matches!(
                flaw,
                Flaw::SmallMatrix | Flaw::NotAnInvolution | Flaw::EventsNotSwapped
            ) {
                assert!(solved.is_ok_and(|s| s.half_floquet.is_none()), "{flaw:?}");
            } else {
                let why = reason(solved, flaw);
                assert!(why.contains(expected_words(flaw)), "{flaw:?}: {why}");
                let mut run = OrbitRun::new(&sys, pair::A).unwrap();
                run.method(method).bounds(0.5, 1.5).max_points(5);
                match run.run("flawed", &orbit, RunDirection::Up) {
                    Err(RunError::Core(Error::InvalidSymmetry { .. })) => {}
                    other => panic!("{flaw:?}: expected the run refused, got {:?}", other.err()),
                }
            }
        }
    }
}

/// A half orbit given to `solve_orbit` is solved on its half orbit and reports the full
/// orbit with the full period's multipliers (those of the same orbit solved as a full orbit,
/// to 1e-8) and the half map's; `solve_shooting` and `solve_collocation`, which solve full
/// orbits, refuse it.
#[test]
fn a_half_orbit_is_solved_as_one_or_refused() {
    let full = symmetric_orbit();
    let half = full.half_of_symmetric(&ImpactPair, 1e-9).unwrap();
    let newton = NewtonSettings::default();
    let reference = solve_shooting(&ImpactPair, &full, ShootingSettings::default(), &newton)
        .unwrap()
        .floquet;
    let key = |m: &(f64, f64)| m.0.hypot(m.1);
    let mut expected: Vec<f64> = reference.multipliers.iter().map(key).collect();
    expected.sort_by(f64::total_cmp);
    for method in [
        OrbitMethod::Shooting(ShootingSettings::default()),
        OrbitMethod::Collocation(CollocationSettings::default()),
    ] {
        let solved = solve_orbit(&ImpactPair, &half, &method, &newton, 1e-6).unwrap();
        assert_eq!(solved.solution.orbit.segment_count(), 2);
        assert_eq!(solved.solution.orbit.signature.closure(), Closure::Periodic);
        let mut got: Vec<f64> = solved
            .solution
            .floquet
            .multipliers
            .iter()
            .map(key)
            .collect();
        got.sort_by(f64::total_cmp);
        for (a, b) in got.iter().zip(&expected) {
            assert_abs_diff_eq!(a, b, epsilon = 1e-8 * b.max(1.0));
        }
        // No non-trivial multiplier of this stable orbit is on the unit circle.
        let f = &solved.solution.floquet;
        assert!(
            f.multipliers
                .iter()
                .zip(&f.trivial)
                .all(|(m, t)| *t || key(m) < 0.99)
        );
        assert!(solved.half_floquet.is_some());
    }
    assert!(matches!(
        solve_shooting(&ImpactPair, &half, ShootingSettings::default(), &newton),
        Err(Error::InvalidSignature { .. })
    ));
    assert!(matches!(
        solve_collocation(&ImpactPair, &half, CollocationSettings::default(), &newton),
        Err(Error::InvalidSignature { .. })
    ));
}
