//! Saved diagrams are re-checked before they are extended (`OrbitRun::check_diagram`): edits
//! of their points, of their tree and of their records are refused with a typed error, and so
//! is a diagram of another system or run; random edits of any value of the saved JSON are
//! refused or give the diagram the unedited file gives, never a panic or another diagram.
//! The model is `common`'s Hopf circle times a pitchfork loop (its diagram: the symmetric
//! branch with two symmetry-breaking points, and the loop between them, `diagram.rs`).

use hycont_continuation::{
    Diagram, DiagramBranchId, DiagramSettings, Error, OrbitRun, SpecialKind, SwitchOutcome,
};
use hycont_core::orbit::Extremum;
use hycont_core::{EventId, EventSpec, HybridJacobians, HybridSystem, Mode, Z2Symmetry};
use proptest::prelude::*;
use serde_json::Value;

use crate::common;
use crate::common::edits;
use common::{HopfLoop, MU, circle, run};
use edits::{EDITS, edit, leaf_paths};

/// The diagram to `depth` levels.
fn diagram(depth: usize) -> Diagram {
    let settings = DiagramSettings {
        depth,
        ..DiagramSettings::default()
    };
    run()
        .diagram("symmetric", &circle(-0.3, 0.0), &settings)
        .unwrap()
}

/// `text` read and extended to depth 2.
fn extended(text: &str) -> Result<Diagram, String> {
    let mut d = Diagram::from_json(text).map_err(|e| e.to_string())?;
    run()
        .extend_diagram(&mut d, &DiagramSettings::default())
        .map_err(|e| e.to_string())?;
    Ok(d)
}

/// Whether `a` and `b` are the same diagram to the tolerance saved points are checked to
/// (1e-6): the same tree, the same switch records, the same points switched at (BP, PD) and,
/// on the branches the extension computed (`from` on), the same special points. (What a
/// diagram carries as saved and no extension reads, e.g. the labels of its end points and
/// user points, or its step sizes, is not compared.)
fn same_diagram(a: &Diagram, b: &Diagram, from: usize) -> bool {
    let close = |x: f64, y: f64| (x - y).abs() <= 1e-6 * (1.0 + x.abs());
    let switched =
        |k: SpecialKind| matches!(k, SpecialKind::BranchPoint | SpecialKind::PeriodDoubling);
    a.branches.len() == b.branches.len()
        && a.switches.len() == b.switches.len()
        && a.branches
            .iter()
            .zip(&b.branches)
            .enumerate()
            .all(|(i, (p, q))| {
                let pick = |s: &&hycont_continuation::SpecialPoint| i >= from || switched(s.kind);
                let s: Vec<_> = p.branch.branch.special_points.iter().filter(pick).collect();
                let t: Vec<_> = q.branch.branch.special_points.iter().filter(pick).collect();
                p.origin == q.origin
                    && p.depth == q.depth
                    && s.len() == t.len()
                    && s.iter().zip(&t).all(|(x, y)| {
                        x.kind == y.kind
                            && x.located == y.located
                            && close(x.point[MU], y.point[MU])
                    })
            })
        && a.switches.iter().zip(&b.switches).all(|(r, s)| {
            r.branch == s.branch
                && r.label == s.label
                && r.kind == s.kind
                && close(r.parameter, s.parameter)
                && std::mem::discriminant(&r.outcome) == std::mem::discriminant(&s.outcome)
        })
}

/// The JSON of `d` edited by `edit`.
fn edited(d: &Diagram, edit: impl FnOnce(&mut Value)) -> String {
    let mut v: Value = serde_json::from_str(&d.to_json().unwrap()).unwrap();
    edit(&mut v);
    v.to_string()
}

fn refused(text: &str, why: &str) {
    let mut d = Diagram::from_json(text).expect("still a diagram");
    let e = run()
        .extend_diagram(&mut d, &DiagramSettings::default())
        .expect_err(why);
    assert!(
        matches!(e, Error::InvalidSaved { .. } | Error::InvalidPoint { .. }),
        "{why}: {e}"
    );
    assert!(
        e.to_string().contains(why),
        "expected '{why}' in the error: {e}"
    );
}

/// The edits of the issue that found the readers trusting: points moved off their orbits, an
/// origin on a branch or label that does not exist, a branch reversed, a record naming a
/// branch the diagram does not have, a branch in the other parameter; each refused, naming
/// what is wrong.
#[test]
fn edited_diagrams_are_refused() {
    let d = diagram(2);
    assert_eq!(d.branches.len(), 2);
    let shifted = edited(&d, |v| {
        for p in v["branches"][1]["branch"]["branch"]["points"]
            .as_array_mut()
            .unwrap()
        {
            for x in p["u"].as_array_mut().unwrap() {
                *x = Value::from(x.as_f64().unwrap() + 0.3);
            }
        }
    });
    refused(&shifted, "orbit equations do not hold");
    refused(
        &edited(&d, |v| v["branches"][1]["origin"][0] = 42.into()),
        "origin on branch 42",
    );
    refused(
        &edited(&d, |v| v["branches"][1]["origin"][1] = 9999.into()),
        "label 9999",
    );
    refused(
        &edited(&d, |v| {
            v["branches"][1]["branch"]["branch"]["points"]
                .as_array_mut()
                .unwrap()
                .reverse();
        }),
        "labels are not in order",
    );
    refused(
        &edited(&d, |v| {
            v["switches"][0]["outcome"] = serde_json::json!({"followed": 7})
        }),
        "branch 7",
    );
    refused(
        &edited(&d, |v| v["branches"][1]["branch"]["free"] = 0.into()),
        "not continued in the root's parameter",
    );
    refused(
        &edited(&d, |v| {
            let p = &mut v["branches"][0]["branch"]["branch"]["points"][3];
            p["params"][1] = Value::from(p["params"][1].as_f64().unwrap() + 1e-3);
        }),
        "parameters",
    );
    refused(
        &edited(&d, |v| {
            let p = &mut v["branches"][0]["branch"]["branch"]["points"][3];
            p["multipliers"][0][0] = Value::from(p["multipliers"][0][0].as_f64().unwrap() + 0.01);
        }),
        "multipliers",
    );
    // Unedited, it extends (to the same diagram: nothing is pending).
    let mut same = Diagram::from_json(&d.to_json().unwrap()).unwrap();
    run()
        .extend_diagram(&mut same, &DiagramSettings::default())
        .unwrap();
    assert_eq!(same, d);
}

/// The model with another pitchfork, $y' = y(g(\mu) - 2y^2)$: the same names, sizes and
/// symmetric branch, other loop orbits ($y^{*2} = g/2$).
struct Twin;

impl HybridSystem for Twin {
    fn state_dim(&self) -> usize {
        3
    }
    fn parameter_names(&self) -> &[&'static str] {
        HopfLoop.parameter_names()
    }
    fn mode_count(&self) -> usize {
        1
    }
    fn mode_name(&self, m: Mode) -> &'static str {
        HopfLoop.mode_name(m)
    }
    fn events(&self, _: Mode) -> &[EventId] {
        &[]
    }
    fn event_spec(&self, _: EventId) -> EventSpec {
        unreachable!("no events")
    }
    fn vector_field(&self, m: Mode, x: &[f64], p: &[f64], f: &mut [f64]) {
        HopfLoop.vector_field(m, x, p, f);
        f[2] -= x[2].powi(3);
    }
    fn event(&self, _: EventId, _: &[f64], _: &[f64]) -> f64 {
        unreachable!("no events")
    }
    fn symmetry(&self) -> Option<Z2Symmetry> {
        HopfLoop.symmetry()
    }
}

impl HybridJacobians for Twin {
    fn vector_field_jacobian(
        &self,
        m: Mode,
        x: &[f64],
        p: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        HopfLoop.vector_field_jacobian(m, x, p, dx, dp);
        dx[8] -= 3.0 * x[2] * x[2];
    }
    fn event_gradient(
        &self,
        _: EventId,
        _: &[f64],
        _: &[f64],
        _: &mut [f64],
        _: Option<&mut [f64]>,
    ) {
    }
}

/// A diagram of another system with the same names and sizes is refused at its first point
/// that is not that system's orbit (on the loop); one saved with other measures is refused
/// by name; the checks are public (`check_diagram`, `check_tree`).
#[test]
fn another_systems_or_runs_diagram_is_refused() {
    let d = diagram(2);
    let mut twin = OrbitRun::new(&Twin, MU).unwrap();
    twin.bounds(-0.5, 1.5);
    let e = twin.check_diagram(&d).unwrap_err();
    assert!(matches!(e, Error::InvalidPoint { .. }), "{e}");
    let mut measured = run();
    measured.add_measure("height", Extremum::max(2)).unwrap();
    let e = measured.check_diagram(&d).unwrap_err();
    assert!(e.to_string().contains("measures"), "{e}");
    d.check_tree().unwrap();
    run().check_diagram(&d).unwrap();
}

/// Every value of the saved JSON (numbers, flags, labels, list entries), edited at random:
/// the diagram is refused (a typed error, or not a diagram at all), or extended to the
/// diagram the unedited file gives, never a panic or another diagram.
#[test]
fn random_edits_are_refused_or_change_nothing() {
    let shallow = diagram(0);
    let text = shallow.to_json().unwrap();
    let reference = extended(&text).unwrap();
    assert!(same_diagram(&reference, &diagram(2), 0));
    let leaves = leaf_paths(&serde_json::from_str(&text).unwrap());
    let config = ProptestConfig {
        cases: std::env::var("PROPTEST_CASES")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(1000),
        failure_persistence: None,
        ..ProptestConfig::default()
    };
    proptest!(config, |(leaf in 0..leaves.len(), op in 0..EDITS)| {
        let mut v: Value = serde_json::from_str(&text).unwrap();
        let path = &leaves[leaf];
        edit(&mut v, path, op);
        if let Ok(d) = extended(&v.to_string()) {
            prop_assert!(
                same_diagram(&d, &reference, shallow.branches.len()),
                "edit {op} of {path:?} gave another diagram: {:?}",
                d.switches
            );
        }
    });
}

/// A branch point saved exactly at the singular point (a symmetry breaking at mu = 0 to the
/// last bit, where the augmented Jacobian is singular) switches as one a hair away.
#[test]
fn a_branch_point_exactly_at_its_singularity_switches() {
    let shallow = diagram(0);
    let reference = extended(&shallow.to_json().unwrap()).unwrap();
    let text = edited(&shallow, |v| {
        let specials = v["branches"][0]["branch"]["branch"]["special_points"]
            .as_array_mut()
            .unwrap();
        let bp = specials.iter_mut().find(|s| s["kind"] == "BP").unwrap();
        let point = &mut bp["point"];
        let n = point["u"].as_array().unwrap().len();
        // mu is the second parameter: the layout's (n - 4)-th unknown, and the last.
        point["u"][n - 3] = 0.0.into();
        point["u"][n - 1] = 0.0.into();
        point["params"][1] = 0.0.into();
        let label = point["label"].clone();
        for r in v["switches"].as_array_mut().unwrap() {
            if r["label"] == label {
                r["parameter"] = 0.0.into();
            }
        }
    });
    let d = extended(&text).unwrap();
    assert!(same_diagram(&d, &reference, 1), "{:?}", d.switches);
}

#[test]
fn cascades_of_an_unchecked_diagram_never_panic() {
    let mut d = diagram(2);
    d.switches[0].outcome = SwitchOutcome::Followed(DiagramBranchId(42));
    d.branches[1].origin = Some((DiagramBranchId(42), 1));
    d.switches[0].kind = SpecialKind::PeriodDoubling;
    let _ = d.cascades();
    assert!(d.check_tree().is_err());
}

/// Stops after `after` answers of `stop` (points, switches), and hears nothing else.
struct StopAfter(usize);

impl hycont_continuation::Observer for StopAfter {
    fn stop(&mut self) -> bool {
        if self.0 == 0 {
            return true;
        }
        self.0 -= 1;
        false
    }
}

/// A diagram whose observer asks it to stop ends cleanly where it is: the branch it was
/// continuing ends `Stopped` with its points so far, and the diagram is a consistent one (it
/// passes the re-check an extension makes), smaller than the whole.
#[test]
fn a_stopped_diagram_ends_cleanly() {
    let whole = diagram(2);
    for after in [10, 30, 60] {
        let mut run = run();
        run.observer(Box::new(StopAfter(after)));
        let stopped = run
            .diagram("symmetric", &circle(-0.3, 0.0), &DiagramSettings::default())
            .unwrap();
        let ended = |b: &hycont_continuation::DiagramBranch| {
            b.branch.branch.end == hycont_continuation::EndReason::Stopped
        };
        assert!(stopped.branches.iter().any(ended), "after {after}");
        assert!(!same_diagram(&stopped, &whole, 0));
        self::run().check_diagram(&stopped).unwrap();
    }
}
