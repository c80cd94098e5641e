//! Newton's method on small problems: a Jacobian check that catches a wrong derivative, and
//! failures that report their history and say why.

use hycont_core::Error;
use hycont_core::problem::{NewtonFailure, NewtonSettings, Problem, ZeroFunction, newton};

/// A scalar equation f(x) = 0 with the derivative it claims.
struct Scalar {
    f: fn(f64) -> f64,
    df: fn(f64) -> f64,
}

impl ZeroFunction for Scalar {
    fn unknowns(&self) -> usize {
        1
    }
    fn equations(&self) -> usize {
        1
    }
    fn jacobian_pattern(&self) -> Vec<(usize, usize)> {
        vec![(0, 0)]
    }
    fn evaluate(
        &mut self,
        u: &[f64],
        r: &mut [f64],
        j: Option<&mut [f64]>,
    ) -> hycont_core::Result<()> {
        r[0] = (self.f)(u[0]);
        if let Some(j) = j {
            j[0] = (self.df)(u[0]);
        }
        Ok(())
    }
}

fn scalar_problem(f: fn(f64) -> f64, df: fn(f64) -> f64) -> Problem<'static> {
    let mut problem = Problem::new(1);
    problem
        .add_part(Box::new(Scalar { f, df }), vec![0])
        .unwrap();
    problem
}

#[test]
fn a_wrong_jacobian_is_caught_by_the_problem_check() {
    // sin with a derivative 1 % off.
    let mut problem = scalar_problem(f64::sin, |x| x.cos() * 1.01);
    let (err, _, _) = problem.check_jacobian(&[0.3], 1e-6).unwrap();
    assert!(err > 1e-3);
}

#[test]
fn newton_failure_reports_its_history() {
    // x^2 + 1 = 0 has no real root.
    let mut problem = scalar_problem(|x| x * x + 1.0, |x| 2.0 * x);
    match newton(&mut problem, &[0.7], &NewtonSettings::default()).unwrap_err() {
        Error::NewtonFailed {
            history,
            reason,
            failure,
        } => {
            assert!(!history.is_empty(), "{reason}");
            assert!(history.iter().all(|h| h.residual >= 1.0));
            // x^2 + 1 >= 1: no step can bring the residual down for long.
            assert!(
                matches!(
                    failure,
                    NewtonFailure::NoDescent | NewtonFailure::IterationLimit
                ),
                "{failure:?}: {reason}"
            );
        }
        other => panic!("{other}"),
    }
}

/// Newton's failures say why. $x^2 = 0$ has a double root, where the Jacobian $2x$ vanishes:
/// Newton halves $x$ each step, so after 20 steps the residual $x^2 \approx 10^{-12}$ is below
/// its tolerance while the step $x/2 \approx 5 \cdot 10^{-7}$ is not: a solution that is not
/// isolated. $x - 1 = 0$ with a Jacobian ten times too large moves a tenth of the way each
/// step: the residual falls by 0.9 per step, slowly.
#[test]
fn newton_failures_say_why() {
    let mut double = scalar_problem(|x| x * x, |x| 2.0 * x);
    match newton(&mut double, &[1.0], &NewtonSettings::default()).unwrap_err() {
        Error::NewtonFailed {
            failure, reason, ..
        } => {
            assert_eq!(failure, NewtonFailure::StepsNotConverging, "{reason}");
            assert!(reason.contains("not isolated"), "{reason}");
        }
        other => panic!("{other}"),
    }
    let mut wrong = scalar_problem(|x| x - 1.0, |_| 10.0);
    let settings = NewtonSettings {
        chord_contraction: 0.0,
        ..NewtonSettings::default()
    };
    match newton(&mut wrong, &[0.0], &settings).unwrap_err() {
        Error::NewtonFailed {
            failure, reason, ..
        } => {
            assert_eq!(failure, NewtonFailure::SlowContraction, "{reason}");
            assert!(reason.contains("0.900"), "{reason}");
        }
        other => panic!("{other}"),
    }
}

/// $r = x_0 - 2 x_1$ over a part's two unknowns, with its gradient.
struct Difference;

impl ZeroFunction for Difference {
    fn unknowns(&self) -> usize {
        2
    }
    fn equations(&self) -> usize {
        1
    }
    fn jacobian_pattern(&self) -> Vec<(usize, usize)> {
        vec![(0, 0), (0, 1)]
    }
    fn evaluate(
        &mut self,
        u: &[f64],
        r: &mut [f64],
        j: Option<&mut [f64]>,
    ) -> hycont_core::Result<()> {
        r[0] = u[0] - 2.0 * u[1];
        if let Some(j) = j {
            j.copy_from_slice(&[1.0, -2.0]);
        }
        Ok(())
    }
}

/// Each part reads its unknowns in its own order, whether they are consecutive global ones
/// (read in place: from the start, at an offset) or not (gathered: out of order, apart).
#[test]
fn parts_read_their_unknowns_in_their_own_order() {
    let mut problem = Problem::new(4);
    for unknowns in [vec![0, 1], vec![2, 3], vec![3, 0], vec![1, 3]] {
        problem.add_part(Box::new(Difference), unknowns).unwrap();
    }
    let u = [1.0, 10.0, 100.0, 1000.0];
    let (mut r, mut j) = (vec![0.0; 4], Vec::new());
    problem.evaluate(&u, &mut r, Some(&mut j)).unwrap();
    assert_eq!(r, [1.0 - 20.0, 100.0 - 2000.0, 1000.0 - 2.0, 10.0 - 2000.0]);
    assert_eq!(j, [1.0, -2.0].repeat(4));
    problem.evaluate(&u, &mut r, None).unwrap();
    assert_eq!(r, [1.0 - 20.0, 100.0 - 2000.0, 1000.0 - 2.0, 10.0 - 2000.0]);
}
