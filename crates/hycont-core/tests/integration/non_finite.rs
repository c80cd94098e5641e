//! Non-finite values a system returns are typed errors naming what returned them, never a
//! crossing silently missed, a cryptic linear-algebra failure or a panic: an event function
//! that is NaN past its surface (a NaN is never crossed: without the check the mass passes
//! through its wall), a NaN reset, NaN Jacobian entries (in the variational equations of
//! shooting and at collocation points), and misuse of the derivative checks and second
//! derivatives; a system without a state is refused.

use hycont_core::orbit::{
    CollocationSettings, PeriodicOrbit, SegmentEnd, SegmentSpec, ShootingSettings, Signature,
    solve_collocation, solve_shooting,
};
use hycont_core::problem::NewtonSettings;
use hycont_core::{
    AutoDiff, Direction, Error, EventAction, EventId, EventSpec, HybridJacobians, HybridModel,
    HybridSystem, Mode, Scalar, SimulationSettings, Simulator, Variation, check_derivatives,
    check_derivatives_against,
};
use std::f64::consts::PI;

const WALL: EventId = EventId(0);

/// A mass falling onto a wall at x = 0 (`x' = v`, `v' = -1`), bouncing back elastically; its
/// wall's event function is `x` above the wall and, by `nan_below`, NaN below it; its reset
/// is NaN by `nan_reset`.
struct Wall {
    nan_below: bool,
    nan_reset: bool,
}

impl HybridSystem for Wall {
    fn state_dim(&self) -> usize {
        2
    }
    fn parameter_names(&self) -> &[&'static str] {
        &[]
    }
    fn mode_count(&self) -> usize {
        1
    }
    fn mode_name(&self, _: Mode) -> &'static str {
        "free"
    }
    fn events(&self, _: Mode) -> &[EventId] {
        &[WALL]
    }
    fn event_spec(&self, _: EventId) -> EventSpec {
        EventSpec {
            name: "wall",
            direction: Direction::Falling,
            action: EventAction::Jump { to: Mode(0) },
        }
    }
    fn vector_field(&self, _: Mode, x: &[f64], _: &[f64], f: &mut [f64]) {
        f[0] = x[1];
        f[1] = -1.0;
    }
    fn event(&self, _: EventId, x: &[f64], _: &[f64]) -> f64 {
        if self.nan_below && x[0] < 0.0 {
            f64::NAN
        } else {
            x[0]
        }
    }
    fn reset(&self, _: EventId, x: &[f64], _: &[f64], out: &mut [f64]) {
        out[0] = x[0];
        out[1] = if self.nan_reset { f64::NAN } else { -x[1] };
    }
}

fn sim() -> Simulator {
    Simulator::new(SimulationSettings::default()).unwrap()
}

/// From x = 1 at rest the mass reaches the wall at t = sqrt(2). An event function that is NaN
/// below the wall is an error at the step that passes it (the mass would otherwise go
/// through: NaN compares false with zero), naming the event and a time past sqrt(2); a NaN
/// reset is an error naming the event and the component.
#[test]
fn a_nan_event_or_reset_is_an_error_not_a_missed_crossing() {
    let well = Wall {
        nan_below: false,
        nan_reset: false,
    };
    let traj = sim()
        .run(&well, Mode(0), 0.0, &[1.0, 0.0], &[], 2.0)
        .unwrap();
    assert_eq!(traj.events.len(), 1);
    let nan = Wall {
        nan_below: true,
        nan_reset: false,
    };
    match sim().run(&nan, Mode(0), 0.0, &[1.0, 0.0], &[], 2.0) {
        Err(Error::NonFiniteEvent {
            event, t, state, ..
        }) => {
            assert_eq!(event, WALL);
            assert!(t > 2f64.sqrt() && state[0] < 0.0, "{t} {state:?}");
        }
        other => panic!("{other:?}"),
    }
    // Below the wall from the start: at t = 0.
    let e = sim()
        .run(&nan, Mode(0), 0.0, &[-1.0, 0.0], &[], 2.0)
        .unwrap_err();
    assert!(
        matches!(e, Error::NonFiniteEvent { t, .. } if t == 0.0),
        "{e}"
    );
    let bad_reset = Wall {
        nan_below: false,
        nan_reset: true,
    };
    match sim().run(&bad_reset, Mode(0), 0.0, &[1.0, 0.0], &[], 2.0) {
        Err(Error::NonFiniteReset { event, index, .. }) => {
            assert_eq!((event, index), (WALL, 1));
        }
        other => panic!("{other:?}"),
    }
}

/// The circle `x' = y + x (1 - r^2)`, `y' = -x + y (1 - r^2)` with hand-coded Jacobians that
/// are NaN where `x < -0.5` (in the entry `d f_1 / d x`).
struct NanJacobian;

impl HybridSystem for NanJacobian {
    fn state_dim(&self) -> usize {
        2
    }
    fn parameter_names(&self) -> &[&'static str] {
        &["a"]
    }
    fn mode_count(&self) -> usize {
        1
    }
    fn mode_name(&self, _: Mode) -> &'static str {
        "circle"
    }
    fn events(&self, _: Mode) -> &[EventId] {
        &[]
    }
    fn event_spec(&self, _: EventId) -> EventSpec {
        unreachable!("no events")
    }
    fn vector_field(&self, _: Mode, x: &[f64], p: &[f64], f: &mut [f64]) {
        let r = p[0] - x[0] * x[0] - x[1] * x[1];
        f[0] = x[1] + x[0] * r;
        f[1] = -x[0] + x[1] * r;
    }
    fn event(&self, _: EventId, _: &[f64], _: &[f64]) -> f64 {
        unreachable!("no events")
    }
}

impl HybridJacobians for NanJacobian {
    fn vector_field_jacobian(
        &self,
        _: Mode,
        x: &[f64],
        p: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        let r = p[0] - x[0] * x[0] - x[1] * x[1];
        dx[0] = r - 2.0 * x[0] * x[0];
        dx[1] = if x[0] < -0.5 {
            f64::NAN
        } else {
            -1.0 - 2.0 * x[0] * x[1]
        };
        dx[2] = 1.0 - 2.0 * x[0] * x[1];
        dx[3] = r - 2.0 * x[1] * x[1];
        if let Some(dp) = dp {
            dp[0] = x[0];
            dp[1] = x[1];
        }
    }
    fn event_gradient(
        &self,
        _: EventId,
        _: &[f64],
        _: &[f64],
        _: &mut [f64],
        _: Option<&mut [f64]>,
    ) {
        unreachable!("no events")
    }
}

/// The unit circle (`a = 1`) from (1, 0), one turn back to `y = 0`.
fn circle() -> PeriodicOrbit {
    let sig = Signature::new(
        &NanJacobian,
        vec![SegmentSpec {
            mode: Mode(0),
            end: SegmentEnd::Interior {
                component: 1,
                value: 0.0,
            },
        }],
    )
    .unwrap();
    PeriodicOrbit::new(
        &NanJacobian,
        sig,
        vec![vec![1.0, 0.0]],
        vec![2.0 * PI],
        vec![1.0],
    )
    .unwrap()
}

/// A NaN Jacobian entry met along the orbit is an error naming the mode and the entry, by
/// shooting (in the variational equations) and by collocation (at a collocation point: row 1,
/// column 0, `d f_1 / d x`), not a Newton failure on a singular system.
#[test]
fn a_nan_jacobian_is_an_error_naming_the_mode_and_the_entry() {
    let newton = NewtonSettings::default();
    match solve_shooting(
        &NanJacobian,
        &circle(),
        ShootingSettings::default(),
        &newton,
    ) {
        Err(Error::NonFiniteDerivative { of, columns, .. }) => {
            assert!(of.contains("mode #0") && of.contains("variational"), "{of}");
            assert_eq!(columns, "sensitivity");
        }
        other => panic!("{other:?}"),
    }
    let e = solve_collocation(
        &NanJacobian,
        &circle(),
        CollocationSettings::default(),
        &newton,
    )
    .unwrap_err();
    match e {
        Error::NonFiniteDerivative {
            of,
            row,
            column,
            columns,
            state,
            ..
        } => {
            assert!(of.contains("vector field of mode #0"), "{of}");
            assert_eq!((row, column, columns), (1, 0, "state"));
            assert!(state[0] < -0.5);
        }
        other => panic!("{other:?}"),
    }
}

/// `x' = sqrt(x^2) - x` written once for dual numbers: finite everywhere, but its derivative
/// at `x = 0` is `0 / 0` for dual numbers (NaN), as the docs of `HybridModel` say.
struct Kink;

impl HybridModel for Kink {
    fn state_dim(&self) -> usize {
        1
    }
    fn parameter_names(&self) -> &[&'static str] {
        &["c"]
    }
    fn mode_count(&self) -> usize {
        1
    }
    fn mode_name(&self, _: Mode) -> &'static str {
        "kink"
    }
    fn events(&self, _: Mode) -> &[EventId] {
        &[]
    }
    fn event_spec(&self, _: EventId) -> EventSpec {
        unreachable!("no events")
    }
    fn vector_field<T: Scalar>(&self, _: Mode, x: &[T], p: &[T], f: &mut [T]) {
        f[0] = (x[0] * x[0]).sqrt() - x[0] * p[0];
    }
    fn event<T: Scalar>(&self, _: EventId, x: &[T], _: &[T]) -> T {
        x[0]
    }
}

/// AD's NaN at a point where the model is not differentiable is reported, not hidden; the
/// derivative checks and second derivatives refuse arguments of the wrong size with typed
/// errors; a system without a state is refused by the simulator.
#[test]
fn misuse_is_a_typed_error() {
    let ad = AutoDiff::new(Kink);
    let mut dx = [0.0];
    ad.vector_field_jacobian(Mode(0), &[0.0], &[1.0], &mut dx, None);
    assert!(dx[0].is_nan());
    let check = check_derivatives(&ad, Mode(0), &[0.5], &[1.0]).unwrap();
    assert!(check.max_error() < 1e-7);
    // Sizes and modes.
    assert!(matches!(
        check_derivatives(&ad, Mode(0), &[0.5, 1.0], &[1.0]),
        Err(Error::DimensionMismatch { .. })
    ));
    assert!(matches!(
        check_derivatives(&ad, Mode(3), &[0.5], &[1.0]),
        Err(Error::InvalidMode { .. })
    ));
    let e = check_derivatives_against(&ad, &NanJacobian, Mode(0), &[0.5], &[1.0]).unwrap_err();
    assert!(matches!(e, Error::InvalidSystem { .. }), "{e}");
    // Second derivatives: variations and outputs of the state's and parameters' sizes.
    let (x, p) = ([0.5], [1.0]);
    let one = Variation { x: &[1.0], p: &[] };
    let mut out = [0.0];
    ad.vector_field_second_derivative(Mode(0), &x, &p, one, one, &mut out)
        .unwrap();
    let long = Variation {
        x: &[1.0, 2.0],
        p: &[],
    };
    let e = ad
        .vector_field_second_derivative(Mode(0), &x, &p, one, long, &mut out)
        .unwrap_err();
    assert!(
        matches!(
            e,
            Error::DimensionMismatch {
                what: "variation b",
                ..
            }
        ),
        "{e}"
    );
    let params = Variation {
        x: &[1.0],
        p: &[1.0, 0.0],
    };
    assert!(
        ad.vector_field_second_derivative(Mode(0), &x, &p, params, one, &mut out)
            .is_err()
    );
    assert!(
        ad.vector_field_second_derivative(Mode(0), &x, &p, one, one, &mut [0.0; 2])
            .is_err()
    );
    assert!(
        ad.event_second_derivative(EventId(0), &x, &p, one, one)
            .is_err()
    );
    // No state at all.
    struct Empty;
    impl HybridSystem for Empty {
        fn state_dim(&self) -> usize {
            0
        }
        fn parameter_names(&self) -> &[&'static str] {
            &[]
        }
        fn mode_count(&self) -> usize {
            1
        }
        fn mode_name(&self, _: Mode) -> &'static str {
            "none"
        }
        fn events(&self, _: Mode) -> &[EventId] {
            &[]
        }
        fn event_spec(&self, _: EventId) -> EventSpec {
            unreachable!("no events")
        }
        fn vector_field(&self, _: Mode, _: &[f64], _: &[f64], _: &mut [f64]) {}
        fn event(&self, _: EventId, _: &[f64], _: &[f64]) -> f64 {
            unreachable!("no events")
        }
    }
    let e = sim().run(&Empty, Mode(0), 0.0, &[], &[], 1.0).unwrap_err();
    assert!(matches!(e, Error::InvalidSystem { .. }), "{e}");
}
