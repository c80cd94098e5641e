//! Saved atlases are re-checked before they grow (`atlas::check`, run by `atlas::extend`):
//! charts moved off the solutions, tangent planes, radii, neighbours and parameters edited,
//! and atlases of another problem with the same names and sizes are refused with a typed
//! error; random edits of any value of the saved JSON are refused or grow the atlas the
//! unedited file grows, never a panic or another atlas. The problem is the unit sphere with
//! the fold over the (x, y) plane and a bound x <= 0.35 as edges (`atlas_sphere.rs`: the upper
//! hemisphere up to the bound).

use hycont_continuation::Error;
use hycont_continuation::atlas::{self, Atlas, AtlasEnd, AtlasSettings};
use hycont_continuation::observe::Silent;
use hycont_core::problem::{Activity, Problem, UnknownMonitor, ZeroFunction};
use proptest::prelude::*;
use serde_json::Value;

use crate::common::edits;
use crate::common::sphere;
use edits::{EDITS, Step, edit, leaf_paths};
use sphere::surface;

/// Radii up to 0.2, and a bound x <= 0.35 near the start (x = 0.1), so that boundary charts
/// (with their cuts) come early.
fn settings() -> AtlasSettings {
    AtlasSettings::default()
        .radii(0.2, 1e-3, 0.2)
        .bound(hycont_core::ParamId(0), -2.0, 0.35)
}

/// The hemisphere's atlas stopped at `charts` charts (all of it for `None`).
fn hemisphere(charts: Option<usize>) -> Atlas {
    let (mut s, u0) = surface();
    let settings = charts.map_or(settings(), |n| settings().max_charts(n));
    atlas::cover(&mut s, "cap", &u0, [3, 4], &settings, &mut Silent).unwrap()
}

/// `text` read and grown to the end.
fn grown(text: &str) -> Result<Atlas, String> {
    let mut a = Atlas::from_json(text).map_err(|e| e.to_string())?;
    let (mut s, _) = surface();
    atlas::extend(&mut s, &mut a, 10_000, &mut Silent).map_err(|e| e.to_string())?;
    Ok(a)
}

/// The same atlas to the tolerance saved charts are checked to (1e-6): the same charts, at
/// the same points, on the same edges.
fn same_atlas(a: &Atlas, b: &Atlas) -> bool {
    a.end == b.end
        && a.charts.len() == b.charts.len()
        && a.charts.iter().zip(&b.charts).all(|(p, q)| {
            p.edge == q.edge
                && p.point.u.len() == q.point.u.len()
                && p.point
                    .u
                    .iter()
                    .zip(&q.point.u)
                    .all(|(x, y)| (x - y).abs() <= 1e-6)
        })
}

fn edited(a: &Atlas, edit: impl FnOnce(&mut Value)) -> String {
    let mut v: Value = serde_json::from_str(&a.to_json().unwrap()).unwrap();
    edit(&mut v);
    v.to_string()
}

fn refused(text: &str, why: &str) {
    let e = grown(text).unwrap_err();
    assert!(e.contains(why), "expected '{why}' in: {e}");
}

/// Grown from where it stopped, an atlas is the atlas grown in one go; each edit of the
/// issue's kind is refused, naming what is wrong.
#[test]
fn edited_atlases_are_refused() {
    let part = hemisphere(Some(20));
    assert_eq!(part.end, AtlasEnd::ChartLimit);
    let whole = hemisphere(None);
    let read = grown(&part.to_json().unwrap()).unwrap();
    assert!(same_atlas(&read, &whole));
    refused(
        &edited(&part, |v| {
            let u = &mut v["charts"][5]["point"]["u"][2];
            *u = (u.as_f64().unwrap() + 0.3).into();
        }),
        "not a solution",
    );
    refused(
        &edited(&part, |v| v["unknown_params"] = serde_json::json!([4, 3])),
        "test values",
    );
    refused(
        &edited(&part, |v| {
            let t = &mut v["charts"][7]["tangent2"];
            let (a, b) = (t[0].clone(), t[1].clone());
            t[0] = b;
            t[1] = a;
        }),
        "tangent",
    );
    refused(
        &edited(&part, |v| v["charts"][3]["radius"] = 5.0.into()),
        "radius",
    );
    refused(
        &edited(&part, |v| {
            v["charts"][3]["neighbours"]
                .as_array_mut()
                .unwrap()
                .push(19.into());
        }),
        "neighbours",
    );
    refused(
        &edited(&part, |v| v["charts"][4]["parent"] = 12.into()),
        "parent",
    );
    refused(
        &edited(&part, |v| v["monitor_names"][0] = "w".into()),
        "monitors",
    );
    // The checks alone, on the problem: the unedited atlas passes.
    let (mut s, _) = surface();
    atlas::check(&mut s, &part).unwrap();
}

/// $x^2 + y^2 + 2 z^2 - 1$: an ellipsoid, with the sphere's names and sizes.
struct Ellipsoid;

impl ZeroFunction for Ellipsoid {
    fn unknowns(&self) -> usize {
        3
    }
    fn equations(&self) -> usize {
        1
    }
    fn jacobian_pattern(&self) -> Vec<(usize, usize)> {
        vec![(0, 0), (0, 1), (0, 2)]
    }
    fn evaluate(
        &mut self,
        u: &[f64],
        r: &mut [f64],
        j: Option<&mut [f64]>,
    ) -> hycont_core::Result<()> {
        r[0] = u[0] * u[0] + u[1] * u[1] + 2.0 * u[2] * u[2] - 1.0;
        if let Some(j) = j {
            j.copy_from_slice(&[2.0 * u[0], 2.0 * u[1], 4.0 * u[2]]);
        }
        Ok(())
    }
}

/// The sphere's atlas is not the ellipsoid's: growing it there is refused at its first chart
/// off the ellipsoid.
#[test]
fn another_problems_atlas_is_refused() {
    let part = hemisphere(Some(20));
    let (mut s, _) = surface();
    let mut problem = Problem::new(3);
    problem
        .add_part(Box::new(Ellipsoid), vec![0, 1, 2])
        .unwrap();
    for (name, k) in [("x", 0), ("y", 1)] {
        problem
            .add_monitor(
                name,
                Box::new(UnknownMonitor),
                vec![k],
                Activity::Active(0.0),
            )
            .unwrap();
    }
    s.problem = problem;
    let e = atlas::extend(&mut s, &mut part.clone(), 100, &mut Silent).unwrap_err();
    assert!(matches!(e, Error::InvalidSaved { .. }), "{e}");
    assert!(e.to_string().contains("chart 0"), "{e}");
}

/// Every value of the saved JSON of an atlas stopped at 60 charts (boundary charts on the
/// bound among them), but the settings (the recipe the atlas grows by: an edit there asks
/// for another atlas), edited at random: refused, or grown to the atlas the unedited file
/// grows to.
#[test]
fn random_edits_are_refused_or_change_nothing() {
    let part = hemisphere(Some(60));
    // Far enough to hold boundary charts on the equator, with their cuts.
    assert!(
        part.charts
            .iter()
            .any(|c| c.edge.is_some() && !c.cuts.is_empty())
    );
    let text = part.to_json().unwrap();
    let reference = grown(&text).unwrap();
    let value: Value = serde_json::from_str(&text).unwrap();
    let leaves: Vec<Vec<Step>> = leaf_paths(&value)
        .into_iter()
        .filter(|p| !matches!(p.first(), Some(Step::Key(k)) if k == "settings"))
        .collect();
    let config = ProptestConfig {
        cases: std::env::var("PROPTEST_CASES")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(500),
        failure_persistence: None,
        ..ProptestConfig::default()
    };
    proptest!(config, |(leaf in 0..leaves.len(), op in 0..EDITS)| {
        let mut v = value.clone();
        let path = &leaves[leaf];
        edit(&mut v, path, op);
        if let Ok(a) = grown(&v.to_string()) {
            prop_assert!(same_atlas(&a, &reference), "edit {op} of {path:?} grew another atlas");
        }
    });
}

/// Asks to stop once it has heard `charts` charts.
struct StopAt(usize);

impl hycont_continuation::Observer for StopAt {
    fn chart(&mut self, _: &atlas::AtlasChart, count: usize) {
        self.0 = self.0.saturating_sub(usize::from(count > 0));
    }
    fn stop(&mut self) -> bool {
        self.0 == 0
    }
}

/// An atlas whose observer asks it to stop ends `Stopped` with the charts it has, and grows
/// from there to the atlas grown in one go.
#[test]
fn a_stopped_atlas_grows_to_the_whole_one() {
    let (mut s, u0) = surface();
    let stopped = atlas::cover(&mut s, "cap", &u0, [3, 4], &settings(), &mut StopAt(25)).unwrap();
    assert_eq!(stopped.end, AtlasEnd::Stopped);
    assert_eq!(stopped.charts.len(), 25);
    let whole = hemisphere(None);
    let grown = grown(&stopped.to_json().unwrap()).unwrap();
    assert!(same_atlas(&grown, &whole));
}
