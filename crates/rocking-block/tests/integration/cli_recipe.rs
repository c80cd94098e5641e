//! `figure` takes the continuation recipe of `continue` for the branch figures 3 to 5.

use crate::common;

use approx::assert_abs_diff_eq;
use common::{RunOk, bin, fails, json, scratch};

/// The labelled special points of a branch figure, `(label, parameter)`.
fn labels(v: &serde_json::Value, free: &str) -> Vec<(String, f64)> {
    v["labels"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| {
            (
                l["label"].as_str().unwrap().to_string(),
                l[free].as_f64().unwrap(),
            )
        })
        .collect()
}

fn points(v: &serde_json::Value) -> usize {
    v["branches"]
        .as_array()
        .unwrap()
        .iter()
        .map(|b| b["points"].as_array().unwrap().len())
        .sum()
}

/// A denser Fig. 3 (`--h-max 0.02`) has several times the points of the study's, the same
/// labelled special points (located: to 1e-8, the location's accuracy with room), and records
/// its recipe in the provenance, which the study's run does not; Fig. 4 by collocation on a
/// coarse mesh has the same labels, at the same parameters to 1e-7 (the mesh's error).
#[test]
fn branch_figures_take_steps_and_meshes() {
    let dir = scratch("recipe");
    let run = |n: &str, sub: &str, extra: &[&str]| {
        let out = dir.join(sub);
        bin()
            .args(["figure", n, "--out"])
            .arg(&out)
            .args(extra)
            .run_ok();
        json(&out.join(format!("fig{n}.json")))
    };
    let study = run("3", "study", &[]);
    let dense = run("3", "dense", &["--h-max", "0.02"]);
    assert!(study["provenance"].get("recipe").is_none());
    assert_eq!(dense["provenance"]["recipe"]["h_max"], 0.02);
    assert!(
        points(&dense) > 3 * points(&study),
        "{} vs {}",
        points(&dense),
        points(&study)
    );
    let (a, b) = (labels(&study, "omega"), labels(&dense, "omega"));
    assert_eq!(a.len(), b.len());
    for ((la, wa), (lb, wb)) in a.iter().zip(&b) {
        assert_eq!(la, lb);
        assert_abs_diff_eq!(wa, wb, epsilon = 1e-8);
    }
    let study4 = run("4", "study", &[]);
    let coll4 = run(
        "4",
        "collocation",
        &["--method", "collocation", "--ntst", "10"],
    );
    assert_eq!(
        coll4["provenance"]["recipe"]["method"]["Collocation"]["ntst"],
        10
    );
    let (a, b) = (labels(&study4, "alpha"), labels(&coll4, "alpha"));
    assert_eq!(a.len(), b.len());
    for ((la, xa), (lb, xb)) in a.iter().zip(&b) {
        assert_eq!(la, lb);
        assert_abs_diff_eq!(xa, xb, epsilon = 1e-7);
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// Bad recipes, and recipes for figures that do not continue branches, exit 2 with one line.
#[test]
fn bad_recipes_exit_2() {
    let dir = scratch("recipe-bad");
    for (args, needle) in [
        (
            &["7", "--h-max", "0.02"][..],
            "apply to the branch figures 3, 4 and 5",
        ),
        (&["3", "--ntst", "10"][..], "--method collocation"),
        (
            &["3", "--h-min", "0.5"][..],
            "h_max = 0.1: must be >= h_min",
        ),
        (
            &["4", "--method", "collocation", "--ncol", "9"][..],
            "collocation.ncol = 9",
        ),
    ] {
        let out = bin()
            .arg("figure")
            .args(args)
            .arg("--out")
            .arg(&dir)
            .output()
            .unwrap();
        fails(&out, 2, needle);
    }
    assert!(!dir.exists(), "nothing written");
}
