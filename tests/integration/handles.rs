//! Handles are tied to what they name: a measure handle of another run (whose measure at that
//! index has another name) is a typed error in a run and is not read at a point, also after a
//! branch is saved and read back; handles of a run with the same measures work. A curve does
//! not start outside its own bounds, and a label that names a regular point where a special
//! one is needed says so.
//!
//! The system: COCO's impact oscillator (`examples/impact_oscillator/model.rs`).

use crate::model_impact_oscillator as impact;

use hycont::hycont_continuation::{
    CurveSpec, Error, OrbitBranch, OrbitRun, RunDirection, SpecialKind,
};
use hycont::orbit::SegmentValue;
use impact::{AMP, ImpactOscillator, W};

/// Run A records "x_end" and "v_end"; run B records "v_end" first, at A's "x_end" slot.
#[test]
fn a_measure_handle_of_another_run_is_refused_not_misread() {
    let mut a = OrbitRun::new(&ImpactOscillator, AMP).unwrap();
    a.bounds(0.5, 1.0).max_points(5);
    let x_end = a.add_measure("x_end", SegmentValue::end(0, 0)).unwrap();
    let v_end = a.add_measure("v_end", SegmentValue::end(0, 1)).unwrap();
    let mut b = OrbitRun::new(&ImpactOscillator, AMP).unwrap();
    let b_v_end = b.add_measure("v_end", SegmentValue::end(0, 1)).unwrap();
    assert_eq!(b_v_end.index(), x_end.index());

    // A run refuses the other run's handle where it names another measure.
    assert!(matches!(
        a.add_event(b_v_end, 0.0, SpecialKind::Grazing),
        Err(Error::ForeignHandle { .. })
    ));
    let branch = a
        .run(
            "impacting",
            &impact::impacting_orbit().unwrap(),
            RunDirection::Down,
        )
        .unwrap();
    let saved = OrbitBranch::from_json(&branch.to_json().unwrap()).unwrap();
    for br in [&branch, &saved] {
        let p = &br.branch.points[1];
        // Its own handles read their measures ...
        assert_eq!(p.get(x_end), Some(p.monitors[x_end.index()]));
        assert!(
            (p[x_end] - 1.0).abs() < 1e-9,
            "the impact is at the wall x = d = 1"
        );
        assert!(p[v_end] > 0.0);
        // ... the other run's is refused, not read as A's x_end.
        assert_eq!(p.get(b_v_end), None);
        assert!(matches!(p.value(b_v_end), Err(Error::ForeignHandle { .. })));
    }
    // A run with the same measures (a restart elsewhere, say) shares its handles.
    let mut same = OrbitRun::new(&ImpactOscillator, AMP).unwrap();
    let same_x = same.add_measure("x_end", SegmentValue::end(0, 0)).unwrap();
    assert_eq!(
        saved.branch.points[1].get(same_x),
        Some(saved.branch.points[1][x_end])
    );
}

/// From the GR point at w = 1, a curve asked for w in [1.2, 1.5] is refused (it would return
/// points outside its window); a label of a regular point is named as one.
#[test]
fn curves_refuse_starts_outside_their_bounds_and_regular_labels() {
    let mut run = OrbitRun::new(&ImpactOscillator, AMP).unwrap();
    run.bounds(0.01, 2.0);
    let branch = run
        .run(
            "impacting",
            &impact::impacting_orbit().unwrap(),
            RunDirection::Down,
        )
        .unwrap();
    let gr = branch.first(SpecialKind::Grazing).unwrap().point.label;
    let outside = CurveSpec::new(W).bounds(1.2, 1.5);
    match run.curve_at("GR", &branch, gr, &outside) {
        Err(Error::StartOutsideBounds {
            parameter, value, ..
        }) => {
            assert_eq!(parameter, "w");
            assert!((value - 1.0).abs() < 1e-9);
        }
        other => panic!("expected the start refused, got {:?}", other.err()),
    }
    match run.curve_at("GR", &branch, 1, &CurveSpec::new(W)) {
        Err(e @ Error::NotASpecialPoint { .. }) => {
            let text = e.to_string();
            assert!(
                text.contains("regular point") && text.contains("(GR)"),
                "{text}"
            );
        }
        other => panic!("expected a regular point named, got {:?}", other.err()),
    }
    // Inside its bounds the same curve runs, and stays inside them.
    let inside = CurveSpec::new(W).bounds(0.9, 1.1);
    let curve = run.curve_at("GR", &branch, gr, &inside).unwrap();
    assert!(
        curve
            .branch
            .points
            .iter()
            .all(|p| (0.9 - 1e-9..=1.1 + 1e-9).contains(&p[W]))
    );
}
