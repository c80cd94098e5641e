//! Periodic orbits of a system whose modes have states of different dimensions (the shuttle of
//! `common/shuttle.rs`: a 1-D climb, a 2-D fall), against its closed form.
//!
//! Floquet multiplier: the monodromy lives in the climb's one-dimensional space,
//! $M = S_{\rm down} \Phi_B S_{\rm up} \Phi_A$ with $\Phi_A = 1$,
//! $S_{\rm up} = g_x + (f^+ - g_x f^-) h_x / (h_x f^-) = (1, 0)^T + ((-v_0, a) - (1, 0)) = (-v_0, a)^T$
//! (2 x 1; $h_x = -1$, $f^- = 1$), $\Phi_B = [[1, t_B], [0, 1]]$ and
//! $S_{\rm down} = (1, 0) + (1 + w)(1, 0)/(-w) = (-1/w, 0)$ (1 x 2; $f^- = (-w, a)$,
//! $w = \sqrt{v_0^2 - 2a}$, $f^+ = 1$): $M = (v_0 - a t_B)/w = 1$, since $a t_B = v_0 - w$.
//! The one multiplier is the flow direction's (trivial): the shuttle's orbit is isolated only
//! through its phase condition.

use crate::common;

use approx::assert_abs_diff_eq;
use common::shuttle::{A, B, DOWN, P, Shuttle, UP};
use hycont_core::orbit::{
    PeriodicOrbit, SegmentEnd, SegmentSpec, ShootingSettings, Signature, saltation_matrix,
    solve_shooting,
};
use hycont_core::problem::NewtonSettings;
use hycont_core::{
    AutoDiff, Direction, EventAction, EventId, EventSpec, HybridModel, Mode, Scalar,
    SimulationSettings, check_derivatives, check_derivatives_against,
};

/// `(t_B, w)` of the closed form.
fn closed_form() -> (f64, f64) {
    let [v0, a] = P;
    let w = (v0 * v0 - 2.0 * a).sqrt();
    ((v0 - w) / a, w)
}

/// The climb (A, to UP) and the fall (B, to DOWN).
fn climb_and_fall() -> Vec<SegmentSpec> {
    vec![
        SegmentSpec {
            mode: A,
            end: SegmentEnd::Event(UP),
        },
        SegmentSpec {
            mode: B,
            end: SegmentEnd::Event(DOWN),
        },
    ]
}

fn signature() -> Signature {
    Signature::new(&Shuttle::default(), climb_and_fall()).unwrap()
}

/// The shuttle as a [`HybridModel`]: its resets' rectangular Jacobians by dual numbers.
struct ShuttleModel;

impl HybridModel for ShuttleModel {
    fn state_dim(&self) -> usize {
        2
    }
    fn mode_dim(&self, mode: Mode) -> usize {
        if mode == A { 1 } else { 2 }
    }
    fn parameter_names(&self) -> &[&'static str] {
        &["v0", "a"]
    }
    fn mode_count(&self) -> usize {
        2
    }
    fn mode_name(&self, _: Mode) -> &'static str {
        "m"
    }
    fn events(&self, mode: Mode) -> &[EventId] {
        if mode == A { &[UP] } else { &[DOWN] }
    }
    fn event_spec(&self, e: EventId) -> EventSpec {
        EventSpec {
            name: "e",
            direction: Direction::Falling,
            action: EventAction::Jump {
                to: if e == UP { B } else { A },
            },
        }
    }
    fn vector_field<T: Scalar>(&self, mode: Mode, x: &[T], p: &[T], f: &mut [T]) {
        if mode == A {
            f[0] = T::from(1.0);
        } else {
            f[0] = x[1];
            f[1] = p[1];
        }
    }
    fn event<T: Scalar>(&self, e: EventId, x: &[T], _: &[T]) -> T {
        if e == UP { -x[0] + 1.0 } else { x[0] }
    }
    fn reset<T: Scalar>(&self, e: EventId, x: &[T], p: &[T], out: &mut [T]) {
        out[0] = x[0];
        if e == UP {
            out[1] = -p[0];
        }
    }
}

/// Rectangular reset Jacobians (2 x 1 and 1 x 2) agree with central differences (1e-7,
/// scaled) and with the dual-number twin's to rounding (1e-14).
#[test]
fn rectangular_reset_jacobians_are_checked() {
    let system = Shuttle::default();
    for (mode, x) in [(A, vec![0.7]), (B, vec![0.4, -0.3])] {
        let fd = check_derivatives(&system, mode, &x, &P).unwrap();
        assert!(fd.max_error() < 1e-7, "{mode}: {fd:?}");
        let ad =
            check_derivatives_against(&system, &AutoDiff::new(ShuttleModel), mode, &x, &P).unwrap();
        assert!(ad.max_error() < 1e-14, "{mode}: {ad:?}");
    }
    // A state of the system's largest dimension in the 1-D mode is refused.
    assert!(check_derivatives(&system, A, &[0.1, 0.2], &P).is_err());
}

/// Shooting from a guess 10 % off finds the closed form's durations and start states (1e-10)
/// and the 1 x 1 monodromy M = 1 (1e-9); the saltation matrices are 2 x 1 and 1 x 2 with the
/// closed form's entries.
#[test]
fn shooting_finds_the_shuttles_orbit() {
    let system = Shuttle::default();
    let (t_b, w) = closed_form();
    let guess = PeriodicOrbit::new(
        &system,
        signature(),
        vec![vec![0.05], vec![1.1, -0.9 * P[0]]],
        vec![0.9, 1.1 * t_b],
        P.to_vec(),
    )
    .unwrap();
    let sol = solve_shooting(
        &system,
        &guess,
        ShootingSettings::default(),
        &NewtonSettings::default(),
    )
    .unwrap();
    let o = &sol.orbit;
    assert_abs_diff_eq!(o.durations[0], 1.0, epsilon = 1e-10);
    assert_abs_diff_eq!(o.durations[1], t_b, epsilon = 1e-10);
    assert_abs_diff_eq!(o.starts[0][0], 0.0, epsilon = 1e-10);
    assert_abs_diff_eq!(o.starts[1][0], 1.0, epsilon = 1e-10);
    assert_abs_diff_eq!(o.starts[1][1], -P[0], epsilon = 1e-10);
    assert_eq!(sol.floquet.monodromy.len(), 1);
    assert_abs_diff_eq!(sol.floquet.monodromy[0], 1.0, epsilon = 1e-9);
    assert_eq!(sol.floquet.trivial, vec![true]);
    let s = o
        .saltation_matrices(&system, &SimulationSettings::default())
        .unwrap();
    assert_eq!((s[0].nrows(), s[0].ncols()), (2, 1));
    assert_eq!((s[1].nrows(), s[1].ncols()), (1, 2));
    assert_abs_diff_eq!(s[0][(0, 0)], -P[0], epsilon = 1e-9);
    assert_abs_diff_eq!(s[0][(1, 0)], P[1], epsilon = 1e-9);
    assert_abs_diff_eq!(s[1][(0, 0)], -1.0 / w, epsilon = 1e-9);
    assert_abs_diff_eq!(s[1][(0, 1)], 0.0, epsilon = 1e-12);
    let end = [0.0, -w];
    let direct = saltation_matrix(&system, o, 1, &end);
    assert_abs_diff_eq!(direct[(0, 0)], -1.0 / w, epsilon = 1e-12);
}

/// Bad input: a start of the wrong mode's dimension names the segment and both sizes.
#[test]
fn a_start_of_the_wrong_dimension_is_refused() {
    let system = Shuttle::default();
    let e = PeriodicOrbit::new(
        &system,
        signature(),
        vec![vec![0.0, 0.0], vec![1.0, -1.0]],
        vec![1.0, 1.0],
        P.to_vec(),
    )
    .unwrap_err();
    assert!(
        e.to_string().contains("segment 0") || e.to_string().contains("2 components"),
        "{e}"
    );
}

/// Collocation carries each segment's own dimension (a 1-D and a 2-D mesh of nodes): the
/// shuttle's flows are polynomials of degree at most 2, which collocation of degree 4
/// reproduces exactly, so the durations and starts match the closed form to 1e-11 and the 1 x 1
/// condensed monodromy is 1 (1e-9).
#[test]
fn collocation_finds_the_shuttles_orbit() {
    use hycont_core::orbit::{CollocationSettings, solve_collocation};
    let system = Shuttle::default();
    let (t_b, _) = closed_form();
    let guess = PeriodicOrbit::new(
        &system,
        signature(),
        vec![vec![0.0], vec![1.0, -P[0]]],
        vec![1.0, 1.05 * t_b],
        P.to_vec(),
    )
    .unwrap();
    let settings = CollocationSettings {
        ntst: 5,
        ..CollocationSettings::default()
    };
    let sol = solve_collocation(&system, &guess, settings, &NewtonSettings::default()).unwrap();
    let o = &sol.solution.orbit;
    assert_eq!(sol.nodes[0].len(), 21);
    assert_eq!(sol.nodes[1].len(), 42);
    assert_abs_diff_eq!(o.durations[0], 1.0, epsilon = 1e-11);
    assert_abs_diff_eq!(o.durations[1], t_b, epsilon = 1e-11);
    assert_abs_diff_eq!(o.starts[1][1], -P[0], epsilon = 1e-11);
    assert_eq!(sol.solution.floquet.monodromy.len(), 1);
    assert_abs_diff_eq!(sol.solution.floquet.monodromy[0], 1.0, epsilon = 1e-9);
    let again = sol.floquet(&system).unwrap();
    assert_abs_diff_eq!(again.monodromy[0], 1.0, epsilon = 1e-9);
}

/// Bad input: an event gradient that leaves an entry of its mode's state unwritten (written
/// as if the 2-state mode had one state) is a typed error naming the event function and the
/// entry, by both discretisations, not a stale value.
#[test]
fn a_gradient_of_the_wrong_length_is_an_error() {
    use hycont_core::Error;
    use hycont_core::orbit::{CollocationSettings, solve_collocation};
    let system = Shuttle {
        short_gradient: true,
        ..Shuttle::default()
    };
    let (t_b, _) = closed_form();
    let guess = PeriodicOrbit::new(
        &system,
        signature(),
        vec![vec![0.0], vec![1.0, -P[0]]],
        vec![1.0, 1.05 * t_b],
        P.to_vec(),
    )
    .unwrap();
    let newton = NewtonSettings::default();
    let by_shooting = solve_shooting(&system, &guess, ShootingSettings::default(), &newton);
    let by_collocation =
        solve_collocation(&system, &guess, CollocationSettings::default(), &newton);
    for e in [by_shooting.unwrap_err(), by_collocation.unwrap_err()] {
        assert!(
            matches!(&e, Error::NonFiniteDerivative { .. })
                && e.to_string().contains("event function event #1"),
            "{e}"
        );
    }
}

/// The shuttle made symmetric under x -> -x: A (x' = 1) climbs to 1, UP jumps into B
/// ((x) -> (x, -v0); x' = y, y' = a) which falls to 0, DOWN jumps into A' (x' = -1) which
/// descends to -1, UP' into B' ((x) -> (x, v0); y' = -a) back to 0, DOWN' into A. S = -I
/// maps A <-> A', B <-> B' (1 and 2 states) and the events likewise.
///
/// Closed form: the half orbit A, B (closed by S into A') lasts 1 + t_B. Half map multiplier:
/// as for the shuttle, but DOWN now leads into A' (f+ = -1), so
/// S_down = (1, 0) + (-1 + w)(1, 0)/(-w) = (1/w, 0) and the half flow's monodromy is
/// (1/w)(-v0 + a t_B) = -1; the half map S_1 M = (-1)(-1) = 1 (S's 1 x 1 block on A's state),
/// the flow direction's trivial multiplier.
struct SymmetricShuttle;

const A2: Mode = Mode(2);
const B2: Mode = Mode(3);
const UP2: EventId = EventId(2);
const DOWN2: EventId = EventId(3);

impl HybridModel for SymmetricShuttle {
    fn state_dim(&self) -> usize {
        2
    }
    fn mode_dim(&self, mode: Mode) -> usize {
        if mode == A || mode == A2 { 1 } else { 2 }
    }
    fn parameter_names(&self) -> &[&'static str] {
        &["v0", "a"]
    }
    fn mode_count(&self) -> usize {
        4
    }
    fn mode_name(&self, _: Mode) -> &'static str {
        "m"
    }
    fn events(&self, mode: Mode) -> &[EventId] {
        match mode.0 {
            0 => &[UP],
            1 => &[DOWN],
            2 => &[UP2],
            _ => &[DOWN2],
        }
    }
    fn event_spec(&self, e: EventId) -> EventSpec {
        let to = [B, A2, B2, A][e.0];
        EventSpec {
            name: "e",
            direction: Direction::Falling,
            action: EventAction::Jump { to },
        }
    }
    fn vector_field<T: Scalar>(&self, mode: Mode, x: &[T], p: &[T], f: &mut [T]) {
        match mode.0 {
            0 => f[0] = T::from(1.0),
            2 => f[0] = T::from(-1.0),
            1 => {
                f[0] = x[1];
                f[1] = p[1];
            }
            _ => {
                f[0] = x[1];
                f[1] = -p[1];
            }
        }
    }
    fn event<T: Scalar>(&self, e: EventId, x: &[T], _: &[T]) -> T {
        match e.0 {
            0 => -x[0] + 1.0,
            1 => x[0],
            2 => x[0] + 1.0,
            _ => -x[0],
        }
    }
    fn reset<T: Scalar>(&self, e: EventId, x: &[T], p: &[T], out: &mut [T]) {
        out[0] = x[0];
        match e.0 {
            0 => out[1] = -p[0],
            2 => out[1] = p[0],
            _ => {}
        }
    }
    fn symmetry(&self) -> Option<hycont_core::Z2Symmetry> {
        Some(hycont_core::Z2Symmetry {
            matrix: vec![-1.0, 0.0, 0.0, -1.0],
            modes: vec![A2, B2, A, B],
            events: vec![UP2, DOWN2, UP, DOWN],
        })
    }
}

/// A half orbit of the symmetric shuttle near its solution: the climb from 0.02, the fall
/// from 1.05 for `fall`.
fn half_orbit_guess(system: &AutoDiff<SymmetricShuttle>, fall: f64) -> PeriodicOrbit {
    let half = Signature::with_closure(
        system,
        climb_and_fall(),
        hycont_core::orbit::Closure::Symmetric,
    )
    .unwrap();
    PeriodicOrbit::new(
        system,
        half,
        vec![vec![0.02], vec![1.05, -0.95 * P[0]]],
        vec![0.95, fall],
        P.to_vec(),
    )
    .unwrap()
}

/// A half orbit across modes of 1 and 2 states (closed by S's 1 x 1 block into A'), by
/// shooting and by collocation: the half period 1 + t_B (1e-10), the half map's multiplier 1
/// (1e-9), the unfolded orbit's four segments of 1, 2, 1 and 2 states.
#[test]
fn symmetric_half_orbits_across_dimensions() {
    use hycont_core::orbit::{
        CollocationSettings, solve_symmetric_collocation, solve_symmetric_shooting,
    };
    let system = AutoDiff::new(SymmetricShuttle);
    let (t_b, _) = closed_form();
    let guess = half_orbit_guess(&system, 1.05 * t_b);
    let newton = NewtonSettings::default();
    let by_shooting =
        solve_symmetric_shooting(&system, &guess, ShootingSettings::default(), &newton).unwrap();
    let by_collocation =
        solve_symmetric_collocation(&system, &guess, CollocationSettings::default(), &newton)
            .unwrap();
    for (half, half_floquet, full) in [
        (
            &by_shooting.half,
            &by_shooting.half_floquet,
            &by_shooting.full.orbit,
        ),
        (
            &by_collocation.half,
            &by_collocation.half_floquet,
            &by_collocation.full.orbit,
        ),
    ] {
        assert_abs_diff_eq!(half.period(), 1.0 + t_b, epsilon = 1e-10);
        assert_abs_diff_eq!(half_floquet.monodromy[0], 1.0, epsilon = 1e-9);
        let dims: Vec<usize> = full.starts.iter().map(Vec::len).collect();
        assert_eq!(dims, vec![1, 2, 1, 2]);
        assert_abs_diff_eq!(full.starts[3][1], P[0], epsilon = 1e-10);
    }
}

/// A symmetry whose matrix mixes a 1-state mode's component with the second (a swap of the
/// two components) cannot map that mode's states among themselves: refused naming the mode.
#[test]
fn a_symmetry_that_mixes_a_modes_states_with_others_is_refused() {
    let swap = hycont_core::Z2Symmetry {
        matrix: vec![0.0, 1.0, 1.0, 0.0],
        modes: vec![A2, B2, A, B],
        events: vec![UP2, DOWN2, UP, DOWN],
    };
    let e = swap.validate(&AutoDiff::new(SymmetricShuttle)).unwrap_err();
    assert!(e.to_string().contains("mode #0's 1 states"), "{e}");
}

/// The unknowns of the unfolded orbit of a half orbit across modes of 1 and 2 states: the
/// segment values, then each state mapped by the symmetry's leading block of its mode's
/// dimension (as [`hycont_core::Z2Symmetry::apply`] maps it), the durations twice, then the
/// parameters; by shooting (the starts) and by collocation (every node). The symmetry is an
/// involution that is not a signed permutation ($S = [[-1, 0], [c, 1]]$, $S^2 = I$), so every
/// entry of its 2 x 2 block counts; and a diagonal one ($S = \mathrm{diag}(-1, 1)$, which maps
/// each component alone: the same numbers by a shorter path).
#[test]
fn repeated_unknowns_map_each_state_by_its_modes_block() {
    for matrix in [vec![-1.0, 0.7, 0.0, 1.0], vec![-1.0, 0.0, 0.0, 1.0]] {
        repeated_unknowns_by(hycont_core::Z2Symmetry {
            matrix,
            modes: vec![A2, B2, A, B],
            events: vec![UP2, DOWN2, UP, DOWN],
        });
    }
}

/// [`repeated_unknowns_map_each_state_by_its_modes_block`] for one symmetry.
fn repeated_unknowns_by(sym: hycont_core::Z2Symmetry) {
    use hycont_core::orbit::Discretisation;
    let system = AutoDiff::new(SymmetricShuttle);
    let like = half_orbit_guess(&system, 1.3);
    let collocation = Discretisation::Collocation {
        meshes: vec![vec![0.0, 0.5, 1.0], vec![0.0, 0.2, 0.6, 1.0]],
        ncol: 3,
    };
    for disc in [
        Discretisation::Shooting(ShootingSettings::default()),
        collocation,
    ] {
        // Per segment: its states' count and dimension.
        let states: Vec<(usize, usize)> = match &disc {
            Discretisation::Shooting(_) => vec![(1, 1), (1, 2)],
            Discretisation::Collocation { meshes, ncol } => meshes
                .iter()
                .zip([1, 2])
                .map(|(m, n)| ((m.len() - 1) * ncol + 1, n))
                .collect(),
        };
        let nv: usize = states.iter().map(|(k, n)| k * n).sum();
        let v: Vec<f64> = (0..nv + 2 + P.len())
            .map(|i| (i as f64 + 1.0) * 0.37 - 2.0)
            .collect();
        let mut expected = v[..nv].to_vec();
        let mut at = 0;
        for &(count, n) in &states {
            for _ in 0..count {
                let mut y = vec![0.0; n];
                sym.apply(&v[at..at + n], &mut y);
                expected.extend_from_slice(&y);
                at += n;
            }
        }
        expected.extend_from_slice(&v[nv..nv + 2]);
        expected.extend_from_slice(&v[nv..]);
        let got = disc.repeat_unknowns(&like, &v, Some(&sym));
        assert_eq!(got.len(), expected.len());
        for (g, e) in got.iter().zip(&expected) {
            assert_eq!(g.to_bits(), e.to_bits(), "{got:?} against {expected:?}");
        }
        let plain = disc.repeat_unknowns(&like, &v, None);
        assert_eq!(plain[nv..2 * nv], v[..nv]);
    }
}
