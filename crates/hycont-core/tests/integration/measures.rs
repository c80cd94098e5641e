//! Measures of orbits against closed forms.
//!
//! Test model: the oscillator $x' = v$, $v' = -(x - c)$ in one mode, with two walls
//! $h_\mathrm{low} = x + d$ (falling: the flow lives in $x > -d$) and
//! $h_\mathrm{high} = x - d$ (rising: $x < d$). Its orbits are the circles
//! $x = c + R\cos t$, $v = -R \sin t$ (period $2\pi$), so over an orbit:
//! $\max x = c + R$, $\min x = c - R$, $\max|x| = |c| + R$, the time average of $x$ is $c$,
//! and the flow turns back towards the low wall at $x = c - R$ (margin $c - R + d$) and towards
//! the high wall at $x = c + R$ (margin $d - c - R$). For $c = 0$, $S = -I$ is a symmetry
//! swapping the walls.

use approx::assert_abs_diff_eq;
use hycont_core::orbit::{
    Closure, Extremum, GrazingMargin, Measure, MeasureSet, PeriodicOrbit, ScanNeeds, SegmentEnd,
    SegmentSpec, SegmentValue, Signature, TimeAverage, Turn, Watch, scan,
};
use hycont_core::{
    DerivativeKind, Direction, Error, EventAction, EventId, EventSpec, HybridJacobians,
    HybridSystem, Mode, SimulationSettings, Z2Symmetry, check_derivatives,
};
use std::f64::consts::PI;

const LOW: EventId = EventId(0);
const HIGH: EventId = EventId(1);

/// Parameters (c, d).
struct Walls;

impl HybridSystem for Walls {
    fn state_dim(&self) -> usize {
        2
    }
    fn parameter_names(&self) -> &[&'static str] {
        &["c", "d"]
    }
    fn mode_count(&self) -> usize {
        1
    }
    fn mode_name(&self, _: Mode) -> &'static str {
        "free"
    }
    fn events(&self, _: Mode) -> &[EventId] {
        &[LOW, HIGH]
    }
    fn event_spec(&self, e: EventId) -> EventSpec {
        EventSpec {
            name: if e == LOW { "low" } else { "high" },
            direction: if e == LOW {
                Direction::Falling
            } else {
                Direction::Rising
            },
            action: EventAction::Jump { to: Mode(0) },
        }
    }
    fn vector_field(&self, _: Mode, x: &[f64], p: &[f64], out: &mut [f64]) {
        out[0] = x[1];
        out[1] = -(x[0] - p[0]);
    }
    fn event(&self, e: EventId, x: &[f64], p: &[f64]) -> f64 {
        if e == LOW { x[0] + p[1] } else { x[0] - p[1] }
    }
    fn symmetry(&self) -> Option<Z2Symmetry> {
        Some(Z2Symmetry {
            matrix: vec![-1.0, 0.0, 0.0, -1.0],
            modes: vec![Mode(0)],
            events: vec![HIGH, LOW],
        })
    }
}

impl HybridJacobians for Walls {
    fn vector_field_jacobian(
        &self,
        _: Mode,
        _: &[f64],
        _: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        dx.copy_from_slice(&[0.0, -1.0, 1.0, 0.0]);
        if let Some(dp) = dp {
            dp.copy_from_slice(&[0.0, 1.0, 0.0, 0.0]);
        }
    }
    fn event_gradient(
        &self,
        e: EventId,
        _: &[f64],
        _: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        dx.copy_from_slice(&[1.0, 0.0]);
        if let Some(dp) = dp {
            dp.copy_from_slice(&[0.0, if e == LOW { 1.0 } else { -1.0 }]);
        }
    }
}

const V_ZERO: SegmentEnd = SegmentEnd::Interior {
    component: 1,
    value: 0.0,
};

/// The circle of radius `r` about `c` from its maximum, as one segment of a full turn.
fn circle(c: f64, r: f64, d: f64) -> PeriodicOrbit {
    let sig = Signature::new(
        &Walls,
        vec![SegmentSpec {
            mode: Mode(0),
            end: V_ZERO,
        }],
    )
    .unwrap();
    PeriodicOrbit::new(
        &Walls,
        sig,
        vec![vec![c + r, 0.0]],
        vec![2.0 * PI],
        vec![c, d],
    )
    .unwrap()
}

/// The same circle split at its minimum (two half turns, boundaries at v = 0).
fn split_circle(c: f64, r: f64, d: f64) -> PeriodicOrbit {
    let seg = SegmentSpec {
        mode: Mode(0),
        end: V_ZERO,
    };
    let sig = Signature::new(&Walls, vec![seg, seg]).unwrap();
    PeriodicOrbit::new(
        &Walls,
        sig,
        vec![vec![c + r, 0.0], vec![c - r, 0.0]],
        vec![PI, PI],
        vec![c, d],
    )
    .unwrap()
}

#[test]
fn extrema_averages_and_margins_of_a_circle() {
    let (c, r, d) = (0.3, 1.2, 1.0);
    for orbit in [circle(c, r, d), split_circle(c, r, d)] {
        let mut set = MeasureSet::new();
        let max = set.add("max", Extremum::max(0)).unwrap();
        let min = set.add("min", Extremum::min(0)).unwrap();
        let max_abs = set.add("max_abs", Extremum::max_abs(1)).unwrap();
        let mean = set.add("mean", TimeAverage::new(0)).unwrap();
        let mean_v = set.add("mean_v", TimeAverage::new(1)).unwrap();
        let low = set.add("low", GrazingMargin::new([LOW])).unwrap();
        let high = set.add("high", GrazingMargin::new([HIGH])).unwrap();
        let v = set.evaluate(&Walls, &orbit).unwrap();
        let tol = 1e-9;
        assert_abs_diff_eq!(v[max], c + r, epsilon = tol);
        assert_abs_diff_eq!(v[min], c - r, epsilon = tol);
        assert_abs_diff_eq!(v[max_abs], r, epsilon = tol);
        assert_abs_diff_eq!(v[mean], c, epsilon = tol);
        assert_abs_diff_eq!(v[mean_v], 0.0, epsilon = tol);
        assert_abs_diff_eq!(v[low], c - r + d, epsilon = tol);
        assert_abs_diff_eq!(v[high], d - c - r, epsilon = tol);
    }
}

/// A set keeps its scans' simulator from one evaluation to the next: what it measures after
/// other orbits (of other segment counts, a larger and a smaller one) is what a new set
/// measures, to the bit.
#[test]
fn a_set_measures_each_orbit_as_a_new_set_does() {
    let set_of = || {
        let mut set = MeasureSet::new();
        set.add("max", Extremum::max(0)).unwrap();
        set.add("max_abs", Extremum::max_abs(1)).unwrap();
        set.add("mean", TimeAverage::new(0)).unwrap();
        set.add("low", GrazingMargin::new([LOW])).unwrap();
        set
    };
    let orbits = [
        circle(0.3, 1.2, 1.0),
        split_circle(-0.2, 0.4, 1.0),
        circle(0.1, 0.05, 1.0),
        split_circle(0.3, 1.2, 1.0),
    ];
    let kept = set_of();
    for orbit in &orbits {
        let again = kept.evaluate(&Walls, orbit).unwrap();
        let fresh = set_of().evaluate(&Walls, orbit).unwrap();
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&again), bits(&fresh));
    }
}

#[test]
fn critical_points_inside_segments_and_at_interior_boundaries() {
    let settings = SimulationSettings::default();
    let needs = ScanNeeds {
        watches: vec![Watch::Component(0), Watch::Event(LOW)],
        ..ScanNeeds::default()
    };
    // One segment from the maximum (its own boundary: it ends at v = 0) round to it: the
    // minimum at t = pi is found by integration, for x and for the wall's function x + d
    // (the same rate v: simultaneous zeros are both reported).
    let s = scan(&Walls, &circle(0.0, 1.0, 2.0), &needs, &settings).unwrap();
    for w in [Watch::Component(0), Watch::Event(LOW)] {
        let found: Vec<_> = s.critical_of(w).map(|p| (p.t, p.turn)).collect();
        assert_eq!(found.len(), 2, "{w:?}: {found:?}");
        assert_eq!(found[0], (0.0, Turn::Max));
        assert_eq!(found[1].1, Turn::Min);
        assert_abs_diff_eq!(found[1].0, PI, epsilon = 1e-10);
    }
    // Split at the minimum: both boundaries are critical points of x, with exact states.
    let s = scan(&Walls, &split_circle(0.0, 1.0, 2.0), &needs, &settings).unwrap();
    let found: Vec<_> = s
        .critical_of(Watch::Component(0))
        .map(|p| (p.segment, p.t, p.turn, p.value))
        .collect();
    assert_eq!(
        found,
        vec![(0, 0.0, Turn::Max, 1.0), (1, 0.0, Turn::Min, -1.0)]
    );
    // The wall's function x + d turns at the same places.
    assert_eq!(s.critical_of(Watch::Event(LOW)).count(), 2);
}

#[test]
fn the_margin_is_negative_past_grazing() {
    // The circle reaches below the low wall: the margin is the (negative) depth.
    let orbit = circle(0.0, 1.5, 1.0);
    let m = GrazingMargin::new([LOW]);
    let mut set = MeasureSet::new();
    set.add("margin", m).unwrap();
    assert_abs_diff_eq!(
        set.evaluate(&Walls, &orbit).unwrap()[0],
        -0.5,
        epsilon = 1e-9
    );
}

#[test]
fn segment_end_values_are_the_flow_at_the_end() {
    // A quarter turn from (R, 0): ends at (c, -R) = (0, -R).
    let sig = Signature::new(
        &Walls,
        vec![SegmentSpec {
            mode: Mode(0),
            end: V_ZERO,
        }],
    )
    .unwrap();
    let orbit = PeriodicOrbit::new(
        &Walls,
        sig,
        vec![vec![0.7, 0.0]],
        vec![0.5 * PI],
        vec![0.0, 1.0],
    )
    .unwrap();
    let mut set = MeasureSet::new();
    set.add("v_end", SegmentValue::end(0, 1)).unwrap();
    set.add("x_start", SegmentValue::start(0, 0)).unwrap();
    let v = set.evaluate(&Walls, &orbit).unwrap();
    assert_abs_diff_eq!(v[0], -0.7, epsilon = 1e-9);
    assert_eq!(v[1], 0.7);
}

#[test]
fn half_orbits_are_measured_as_their_full_orbits() {
    let (r, d) = (0.8, 1.0);
    let full = split_circle(0.0, r, d);
    let sig = Signature::with_closure(
        &Walls,
        vec![SegmentSpec {
            mode: Mode(0),
            end: V_ZERO,
        }],
        Closure::Symmetric,
    )
    .unwrap();
    let half = PeriodicOrbit::new(&Walls, sig, vec![vec![r, 0.0]], vec![PI], vec![0.0, d]).unwrap();
    let sym = Walls.symmetry().unwrap();
    // Which measures can be evaluated on the half orbit: max |x| and the two-wall margin.
    assert!(Measure::<Walls>::invariant_under(
        &Extremum::max_abs(0),
        &Walls,
        &sym
    ));
    assert!(!Measure::<Walls>::invariant_under(
        &Extremum::max(0),
        &Walls,
        &sym
    ));
    assert!(!Measure::<Walls>::invariant_under(
        &TimeAverage::new(0),
        &Walls,
        &sym
    ));
    assert!(Measure::<Walls>::invariant_under(
        &GrazingMargin::new([LOW, HIGH]),
        &Walls,
        &sym
    ));
    assert!(!Measure::<Walls>::invariant_under(
        &GrazingMargin::new([LOW]),
        &Walls,
        &sym
    ));
    let build = || {
        let mut set = MeasureSet::new();
        set.add("max_abs", Extremum::max_abs(0)).unwrap();
        set.add("margin", GrazingMargin::new([LOW, HIGH])).unwrap();
        set.add("min", Extremum::min(0)).unwrap();
        set.add("mean", TimeAverage::new(0)).unwrap();
        set
    };
    let on_half = build().evaluate(&Walls, &half).unwrap();
    let on_full = build().evaluate(&Walls, &full).unwrap();
    for (a, b) in on_half.iter().zip(&on_full) {
        assert_abs_diff_eq!(a, b, epsilon = 1e-9);
    }
    assert_abs_diff_eq!(on_half[0], r, epsilon = 1e-12);
    assert_abs_diff_eq!(on_half[1], d - r, epsilon = 1e-9);
    assert_abs_diff_eq!(on_half[2], -r, epsilon = 1e-9);
    // The invariant measures alone on the half orbit (no unfolding needed).
    let mut set = MeasureSet::new();
    set.add("max_abs", Extremum::max_abs(0)).unwrap();
    set.add("margin", GrazingMargin::new([LOW, HIGH])).unwrap();
    let v = set.evaluate(&Walls, &half).unwrap();
    assert_abs_diff_eq!(v[1], d - r, epsilon = 1e-9);
}

#[test]
fn bad_measures_are_errors_naming_the_value() {
    let orbit = circle(0.0, 1.0, 2.0);
    let mut set = MeasureSet::new();
    set.add("x9", Extremum::max(9)).unwrap();
    let err = set.evaluate(&Walls, &orbit).unwrap_err();
    assert!(
        matches!(err, Error::InvalidMeasure { ref reason } if reason.contains('9')),
        "{err}"
    );
    let mut set = MeasureSet::new();
    set.add("seg", SegmentValue::start(3, 0)).unwrap();
    let err = set.evaluate(&Walls, &orbit).unwrap_err();
    assert!(err.to_string().contains("segment 3"), "{err}");
    let mut set = MeasureSet::new();
    set.add("wall", GrazingMargin::new([EventId(7)])).unwrap();
    assert!(
        set.evaluate(&Walls, &orbit)
            .unwrap_err()
            .to_string()
            .contains("#7")
    );
    assert!(set.add("wall", SegmentValue::start(0, 0)).is_err());
    assert!(set.add("", SegmentValue::start(0, 0)).is_err());
    assert!(set.evaluate_one(&Walls, &orbit, 5).is_err());
}

#[test]
fn closures_are_measures() {
    let orbit = circle(0.0, 1.0, 2.0);
    let mut set = MeasureSet::new();
    set.add("period", |_: &Walls, o: &PeriodicOrbit| o.period())
        .unwrap();
    assert_abs_diff_eq!(set.evaluate(&Walls, &orbit).unwrap()[0], 2.0 * PI);
}

/// [`Walls`] with its structural hints declared: $\dot x = v$ (the rate of component 0 is
/// component 1) and both walls are surfaces of $x$. `wrong` declares false hints instead,
/// which [`check_derivatives`] must catch.
struct Hinted {
    wrong: bool,
}

impl HybridSystem for Hinted {
    fn state_dim(&self) -> usize {
        Walls.state_dim()
    }
    fn parameter_names(&self) -> &[&'static str] {
        Walls.parameter_names()
    }
    fn mode_count(&self) -> usize {
        1
    }
    fn mode_name(&self, m: Mode) -> &'static str {
        Walls.mode_name(m)
    }
    fn events(&self, m: Mode) -> &[EventId] {
        Walls.events(m)
    }
    fn event_spec(&self, e: EventId) -> EventSpec {
        Walls.event_spec(e)
    }
    fn vector_field(&self, m: Mode, x: &[f64], p: &[f64], out: &mut [f64]) {
        Walls.vector_field(m, x, p, out);
    }
    fn event(&self, e: EventId, x: &[f64], p: &[f64]) -> f64 {
        Walls.event(e, x, p)
    }
    fn rate_component(&self, _: Mode, c: usize) -> Option<usize> {
        (c == 0).then_some(if self.wrong { 0 } else { 1 })
    }
    fn event_component(&self, _: EventId) -> Option<usize> {
        Some(usize::from(self.wrong))
    }
}

impl HybridJacobians for Hinted {
    fn vector_field_jacobian(
        &self,
        m: Mode,
        x: &[f64],
        p: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        Walls.vector_field_jacobian(m, x, p, dx, dp);
    }
    fn event_gradient(
        &self,
        e: EventId,
        x: &[f64],
        p: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        Walls.event_gradient(e, x, p, dx, dp);
    }
}

fn walls_orbit<S: HybridSystem>(system: &S, split: bool, c: f64, r: f64) -> PeriodicOrbit {
    let seg = SegmentSpec {
        mode: Mode(0),
        end: V_ZERO,
    };
    let (specs, starts, durations) = if split {
        (
            vec![seg, seg],
            vec![vec![c + r, 0.0], vec![c - r, 0.0]],
            vec![PI, PI],
        )
    } else {
        (vec![seg], vec![vec![c + r, 0.0]], vec![2.0 * PI])
    };
    let sig = Signature::new(system, specs).unwrap();
    PeriodicOrbit::new(system, sig, starts, durations, vec![c, 1.5]).unwrap()
}

#[test]
fn hinted_scans_find_the_same_critical_points() {
    // The hints group x, x + d and x - d into one watched rate v: the scan must still report
    // each function's own extrema, exactly as without hints. The orbit starts a quarter turn
    // off its maximum so that both extrema lie inside the segment.
    let settings = SimulationSettings::default();
    let needs = ScanNeeds {
        watches: vec![
            Watch::Component(0),
            Watch::Event(LOW),
            Watch::Component(1),
            Watch::Event(HIGH),
        ],
        integrals: vec![0],
        ..ScanNeeds::default()
    };
    let (c, r) = (0.2, 0.9);
    let quarter = |s: &dyn Fn(bool) -> PeriodicOrbit| {
        let mut o = s(false);
        o.starts[0] = vec![c, -r];
        o
    };
    let plain_orbits = [
        walls_orbit(&Walls, false, c, r),
        walls_orbit(&Walls, true, c, r),
        quarter(&|s| walls_orbit(&Walls, s, c, r)),
    ];
    let hinted = Hinted { wrong: false };
    for plain_orbit in &plain_orbits {
        let mut hinted_orbit = walls_orbit(&hinted, plain_orbit.starts.len() == 2, c, r);
        hinted_orbit.starts.clone_from(&plain_orbit.starts);
        let a = scan(&Walls, plain_orbit, &needs, &settings).unwrap();
        let b = scan(&hinted, &hinted_orbit, &needs, &settings).unwrap();
        assert_eq!(a.critical.len(), b.critical.len(), "{a:?}\n{b:?}");
        // Each function has one maximum and one minimum per turn (v: at x = c, -r and +r).
        for w in &needs.watches {
            assert_eq!(b.critical_of(*w).count(), 2, "{w:?}: {b:?}");
        }
        for (p, q) in a.critical.iter().zip(&b.critical) {
            assert_eq!((p.watch, p.turn, p.segment), (q.watch, q.turn, q.segment));
            assert_abs_diff_eq!(p.t, q.t, epsilon = 1e-12);
            assert_abs_diff_eq!(p.value, q.value, epsilon = 1e-12);
        }
        assert_abs_diff_eq!(a.integrals[0][0], b.integrals[0][0], epsilon = 1e-12);
    }
}

#[test]
fn derivative_checks_verify_the_hints() {
    let (x, p) = ([0.4, -0.7], [0.1, 1.0]);
    let good = check_derivatives(&Hinted { wrong: false }, Mode(0), &x, &p).unwrap();
    assert!(good.max_error() < 1e-8, "{good:?}");
    for kind in [
        DerivativeKind::RateComponent,
        DerivativeKind::EventComponent(LOW),
        DerivativeKind::EventComponent(HIGH),
    ] {
        assert!(
            good.worst.iter().any(|m| m.kind == kind),
            "{kind:?} not checked"
        );
    }
    // x' = v, not x; the walls are surfaces of x, not of v: errors of order one.
    let bad = check_derivatives(&Hinted { wrong: true }, Mode(0), &x, &p).unwrap();
    for kind in [
        DerivativeKind::RateComponent,
        DerivativeKind::EventComponent(LOW),
    ] {
        let m = bad.worst.iter().find(|m| m.kind == kind).unwrap();
        assert!(m.error > 0.3, "{m:?}");
    }
}
