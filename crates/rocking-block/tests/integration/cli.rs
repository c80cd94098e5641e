//! The `rocking-block` command line: output contract and error behaviour.

use crate::common;
use approx::assert_abs_diff_eq;

use common::{RunOk, bin};

#[test]
fn simulate_json_has_the_documented_fields() {
    let out = bin()
        .args([
            "simulate", "--omega", "1.3", "--alpha", "0.66", "--phi0", "0.01", "--psi0", "0",
        ])
        .args(["--beta", "1.5707963267948966", "--periods", "10", "--json"])
        .run_ok();
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["outcome"], "running");
    // Each outcome says what it means.
    assert!(
        v["outcome_description"]
            .as_str()
            .unwrap()
            .contains("still moving at the end time")
    );
    assert!(v["t_end"].as_f64().unwrap() > 48.0);
    assert!(v["impacts"].as_u64().unwrap() > 5);
    assert_eq!(v["final_state"].as_array().unwrap().len(), 4);
    let strobe = v["strobe"].as_array().unwrap();
    assert_eq!(strobe.len(), 11); // t = 0, T, ..., 10 T
    assert_eq!(strobe[0][0], 0.01);
    for key in ["steps", "rejected_steps", "rhs_evaluations", "events"] {
        assert!(v["stats"][key].is_u64(), "stats.{key}");
    }
}

#[test]
fn simulate_writes_csv_and_svg() {
    let dir = std::env::temp_dir().join(format!("rocking-block-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (csv, svg) = (dir.join("run.csv"), dir.join("run.svg"));
    bin()
        .args(["simulate", "--periods", "3", "--beta", "1.57", "--csv"])
        .arg(&csv)
        .arg("--svg")
        .arg(&svg)
        .run_ok();
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(text.starts_with("t,mode,phi,psi,r,s\n"));
    assert!(text.lines().count() > 500);
    let svg_text = std::fs::read_to_string(&svg).unwrap();
    assert!(svg_text.contains("<svg") && svg_text.contains("polyline"));
    // The run rocks from one corner to the other (impacts): the key says what the phase
    // portrait's jumps are, and names both modes.
    let modes: Vec<&str> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(1).unwrap())
        .collect();
    assert!(modes.windows(2).any(|w| w == ["+", "-"]));
    for needle in [
        "impact at phi = 0: psi jumps",
        "mode + (rocking",
        "mode - (rocking",
    ] {
        assert!(svg_text.contains(needle), "{needle}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

fn assert_one_line_usage_error(args: &[&str], needle: &str) {
    let out = bin().args(args).output().unwrap();
    assert_eq!(out.status.code(), Some(2), "{args:?}");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
    assert!(err.contains(needle), "{args:?}: {err}");
    assert!(!err.contains("panicked") && !err.contains("backtrace"));
}

/// Omega of the first SN of a branch printed by `continue --json`.
fn sn_omega(v: &serde_json::Value) -> f64 {
    v["special_points"]
        .as_array()
        .unwrap()
        .iter()
        .find(|s| s["kind"] == "SN")
        .unwrap()["omega"]
        .as_f64()
        .unwrap()
}

#[test]
fn bad_arguments_give_one_line_and_exit_code_2() {
    assert_one_line_usage_error(&["simulate", "--omega", "abc"], "--omega");
    assert_one_line_usage_error(&["simulate", "--omega", "-1"], "omega = -1");
    assert_one_line_usage_error(&["simulate", "--theta-b", "2"], "theta_b");
    assert_one_line_usage_error(&["simulate", "--rtol", "0"], "rtol");
    assert_one_line_usage_error(&["simulate", "--periods", "nan"], "periods");
    assert_one_line_usage_error(&["simulate", "--r0", "1"], "--s0");
    assert_one_line_usage_error(&["frobnicate"], "frobnicate");
    // Negative numbers are values of every numeric option (checked, not taken for flags).
    assert_one_line_usage_error(&["simulate", "--xi", "-1"], "xi = -1");
    assert_one_line_usage_error(&["simulate", "--theta-b", "-0.2"], "theta_b = -0.2");
    assert_one_line_usage_error(&["simulate", "--periods", "-3"], "periods = -3");
    assert_one_line_usage_error(&["simulate", "--rtol", "-1e-10"], "rtol = -1e-10");
    assert_one_line_usage_error(&["figure", "7", "--trials", "-5"], "invalid value '-5'");
    // Inputs that cannot be read say so (exit 2), naming the file.
    let missing = "/nonexistent/run.json";
    for args in [
        &[
            "continue",
            "--free",
            "omega",
            "--restart",
            missing,
            "--label",
            "1",
        ][..],
        &["merge", missing],
        &["figure", "--resume", missing],
        &[
            "classify",
            "--input",
            missing,
            "--output",
            "/tmp/rocking-block-out.csv",
        ],
    ] {
        assert_one_line_usage_error(args, &format!("cannot read {missing}"));
    }
}

#[test]
fn orbit_json_reports_the_symmetric_orbit() {
    for method in ["collocation", "shooting"] {
        let out = bin()
            .args([
                "orbit",
                "--omega",
                "1.3",
                "--alpha",
                "0.66",
                "--kind",
                "symmetric",
            ])
            .args(["--method", method, "--json"])
            .run_ok();
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_abs_diff_eq!(v["amp"].as_f64().unwrap(), 0.43843, epsilon = 5e-6);
        assert_eq!(v["stable"], false);
        assert_eq!(v["multipliers"].as_array().unwrap().len(), 4);
        let segs = v["segments"].as_array().unwrap();
        assert_eq!(segs.len(), 2);
        for s in segs {
            assert_abs_diff_eq!(
                s["duration"].as_f64().unwrap(),
                std::f64::consts::PI / 1.3,
                epsilon = 1e-8
            );
            assert_eq!(s["start"].as_array().unwrap().len(), 4);
        }
        assert!(v["period"].as_f64().is_some());
    }
}

#[test]
fn figure_2_writes_json_and_svg() {
    let dir = std::env::temp_dir().join(format!("rocking-block-fig2-{}", std::process::id()));
    bin().args(["figure", "2", "--out"]).arg(&dir).run_ok();
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("fig2.json")).unwrap()).unwrap();
    assert_eq!(v["figure"], 2);
    let orbits = v["orbits"].as_array().unwrap();
    let names: Vec<&str> = orbits.iter().map(|o| o["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["symmetric", "asymmetric-pos", "asymmetric-neg"]);
    for o in orbits {
        for key in [
            "omega",
            "alpha",
            "amp",
            "period",
            "stable",
            "multipliers",
            "segments",
        ] {
            assert!(o.get(key).is_some(), "{key}");
        }
        for s in o["segments"].as_array().unwrap() {
            assert!(s["mode"] == "+" || s["mode"] == "-");
            assert!(s["duration"].as_f64().unwrap() > 0.0);
        }
    }
    let svg = std::fs::read_to_string(dir.join("fig2.svg")).unwrap();
    assert!(svg.contains("<svg") && svg.contains("polyline"));
    std::fs::remove_dir_all(&dir).ok();
}

/// A start that has no orbit fails with exit code 1 and one line saying what happened to the
/// block: it comes to rest, or it overturns (with the time), from the given initial state.
#[test]
fn starts_without_an_orbit_say_what_the_block_does() {
    for (args, needle) in [
        (
            &[
                "continue", "--free", "omega", "--omega", "1.0", "--kind", "simulate",
            ][..],
            "comes to rest from phi0 = 0.01",
        ),
        (
            &["orbit", "--kind", "simulate", "--beta", "0"][..],
            "overturns at t = 8.5702",
        ),
    ] {
        let out = bin().args(args).output().unwrap();
        assert_eq!(out.status.code(), Some(1), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
}

#[test]
fn unknown_figures_and_bad_settings_fail_cleanly() {
    assert_one_line_usage_error(&["figure", "11"], "figures 2 to 10");
    assert_one_line_usage_error(&["figure", "seven"], "figure number");
    assert_one_line_usage_error(&["figure", "7", "--trials", "0"], "trials");
    assert_one_line_usage_error(&["figure", "7", "--threads", "0"], "threads");
    assert_one_line_usage_error(&["orbit", "--ncol", "9"], "ncol");
    assert_one_line_usage_error(&["orbit", "--kind", "sideways"], "sideways");
    assert_one_line_usage_error(&["orbit", "--omega", "0"], "omega");
    assert_one_line_usage_error(
        &["orbit", "--kind", "asymmetric-pos", "--alpha", "-1"],
        "alpha",
    );
}

#[test]
fn figures_3_and_4_write_branches_in_the_study_format() {
    let dir = std::env::temp_dir().join(format!("rocking-block-fig34-{}", std::process::id()));
    for n in ["3", "4"] {
        bin().args(["figure", n, "--out"]).arg(&dir).run_ok();
        let v: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(dir.join(format!("fig{n}.json"))).unwrap(),
        )
        .unwrap();
        assert_eq!(v["figure"].as_u64().unwrap().to_string(), n);
        for key in ["omega", "alpha", "xi", "theta_b"] {
            assert!(v["parameters"][key].is_f64(), "{key}");
        }
        let branches = v["branches"].as_array().unwrap();
        assert!(branches.len() >= 2);
        for b in branches {
            assert!(b["name"].is_string() && b["free"].is_array());
            for p in b["points"].as_array().unwrap() {
                for key in ["omega", "alpha", "amp", "period", "stable", "multipliers"] {
                    assert!(p.get(key).is_some(), "{key}");
                }
            }
            for s in b["special_points"].as_array().unwrap() {
                let kind = s["kind"].as_str().unwrap();
                assert!(
                    ["SN", "BP", "PD", "TR", "SB", "GR", "EP"].contains(&kind),
                    "{kind}"
                );
                for key in ["omega", "alpha", "amp", "multipliers"] {
                    assert!(s.get(key).is_some(), "{key}");
                }
            }
        }
        let svg = std::fs::read_to_string(dir.join(format!("fig{n}.svg"))).unwrap();
        assert!(svg.contains("<svg"));
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn figure_6_writes_curves_and_test_points() {
    let dir = std::env::temp_dir().join(format!("rocking-block-fig6-{}", std::process::id()));
    bin().args(["figure", "6", "--out"]).arg(&dir).run_ok();
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("fig6.json")).unwrap()).unwrap();
    assert_eq!(v["figure"], 6);
    let kinds: Vec<&str> = v["curves"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["kind"].as_str().unwrap())
        .collect();
    for k in ["SN", "PD", "BP", "SB"] {
        assert!(kinds.contains(&k), "{k} curve missing: {kinds:?}");
    }
    for c in v["curves"].as_array().unwrap() {
        let pts = c["points"].as_array().unwrap();
        assert!(pts.len() > 10);
        assert!(
            pts.iter()
                .all(|p| p["omega"].is_f64() && p["alpha"].is_f64())
        );
    }
    let tests = v["test_points"].as_array().unwrap();
    assert_eq!(tests.len(), 6);
    for t in tests {
        // Below the fold curve a block that comes to rest cannot lift off: it stays at rest.
        assert!(t["outcome"] == "rest" || t["outcome"].as_str().unwrap().starts_with("overturn"));
    }
    for f in ["fig6.svg", "fig6_tests.svg"] {
        assert!(
            std::fs::read_to_string(dir.join(f))
                .unwrap()
                .contains("<svg")
        );
    }
    // The key (beside the plot) names the regions, every curve (its acronym spelled out), the
    // lines of Figs. 3 and 4, the test points and the curves' user points.
    let svg = std::fs::read_to_string(dir.join("fig6.svg")).unwrap();
    let texts: Vec<&str> = svg.lines().map(str::trim).collect();
    for needle in [
        "stable symmetric period 1",
        "stable asymmetric period 1",
        "SN (fold, saddle-node) curve",
        "BP (branch point) curve",
        "PD (period doubling) curve",
        "SB (Amp at the boundary) curve",
        "line alpha = 0.66",
        "line omega = 1.3",
        "test point (its outcome)",
        "UZ (user point): on a dashed line",
    ] {
        assert!(texts.contains(&needle), "fig6.svg lacks {needle:?}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn shards_merge_into_the_same_figure_as_one_run() {
    let dir = std::env::temp_dir().join(format!("rocking-block-shards-{}", std::process::id()));
    for i in 0..2 {
        bin()
            .args([
                "figure",
                "10",
                "--trials",
                "200",
                "--seed",
                "4",
                "--shard",
                &format!("{i}/2"),
                "--out",
            ])
            .arg(&dir)
            .run_ok();
    }
    let merged = dir.join("merged");
    bin()
        .arg("merge")
        .arg(dir.join("fig10.shard-0-of-2.json"))
        .arg(dir.join("fig10.shard-1-of-2.json"))
        .arg("--out")
        .arg(&merged)
        .run_ok();
    let whole = dir.join("whole");
    let out = bin()
        .args(["figure", "10", "--trials", "200", "--seed", "4", "--out"])
        .arg(&whole)
        .output()
        .unwrap();
    assert!(out.status.success());
    let read = |p: std::path::PathBuf| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
    };
    assert_eq!(
        read(merged.join("fig10.json"))["marginals"],
        read(whole.join("fig10.json"))["marginals"]
    );
    assert_one_line_usage_error(&["figure", "7", "--shard", "2/2"], "shard");
    std::fs::remove_dir_all(&dir).ok();
}

/// `continue` takes the step sizes, point count, mesh and tolerance: a smaller largest step
/// gives a denser branch with the same special points; a finer mesh the same fold; settings
/// the library refuses exit 2 naming them.
#[test]
fn continue_takes_steps_meshes_and_tolerances() {
    let run = |extra: &[&str]| -> serde_json::Value {
        let out = bin()
            .args(["continue", "--free", "omega", "--json"])
            .args(extra)
            .run_ok();
        serde_json::from_slice(&out.stdout).unwrap()
    };
    let points = |v: &serde_json::Value| v["points"].as_array().unwrap().len();
    let fold = sn_omega;
    let default = run(&[]);
    let dense = run(&["--h-max", "0.02", "--tol", "1e-11"]);
    assert!(
        points(&dense) > 3 * points(&default),
        "{} vs {}",
        points(&dense),
        points(&default)
    );
    assert_abs_diff_eq!(fold(&dense), fold(&default), epsilon = 1e-9);
    let coarse = run(&[
        "--method",
        "collocation",
        "--ntst",
        "8",
        "--ncol",
        "3",
        "--max-points",
        "60",
    ]);
    let fine = run(&["--method", "collocation", "--ntst", "30", "--ncol", "4"]);
    assert!(points(&coarse) <= 2 * 60);
    assert_abs_diff_eq!(fold(&fine), fold(&default), epsilon = 1e-8);
    for (args, needle) in [
        (&["--h0", "-1"][..], "h0 = -1"),
        (&["--h-min", "0.5"][..], "h_max = 0.1: must be >= h_min"),
        (&["--tol", "0"][..], "newton.tol = 0"),
        (&["--max-points", "1"][..], "max_points = 1"),
        (&["--ntst", "5"][..], "--method collocation"),
        (
            &["--method", "collocation", "--ncol", "9"][..],
            "collocation.ncol = 9",
        ),
    ] {
        let mut all = vec!["continue", "--free", "omega"];
        all.extend_from_slice(args);
        assert_one_line_usage_error(&all, needle);
    }
}

/// Collocation runs adapt their mesh along the branch and report every point's error
/// estimate: started on 4 intervals per segment the mesh is refined where the estimate exceeds
/// 1e-6; on 8 it moves every 10 points (its estimate, ~1e-7, is above a hundredth of the
/// tolerance); a tolerance the start mesh is far from (1e-12) is reported with a hint;
/// without adaptation (`--adapt-every 0 --mesh-tol inf`) there are none; the fold agrees with
/// shooting's to 1e-8 on the default mesh; bad settings exit 2.
#[test]
fn collocation_meshes_adapt_along_the_branch() {
    let text = |extra: &[&str]| -> String {
        let out = bin()
            .args(["continue", "--free", "omega", "--method", "collocation"])
            .args(extra)
            .run_ok();
        String::from_utf8(out.stdout).unwrap()
    };
    let coarse = text(&["--ntst", "4"]);
    assert!(
        coarse.contains("4 intervals per segment at the start"),
        "{coarse}"
    );
    assert!(!coarse.contains("4 intervals per segment at the start, 4 at the most"));
    assert!(!coarse.contains("raise --ntst"), "{coarse}");
    let strict = text(&["--ntst", "4", "--mesh-tol", "1e-12"]);
    assert!(strict.contains("raise --ntst"), "{strict}");
    let fixed = text(&["--adapt-every", "0", "--mesh-tol", "inf"]);
    assert!(fixed.contains("collocation mesh: 0 adaptations"), "{fixed}");
    let adapted = text(&["--ntst", "8"]);
    let count: usize = adapted
        .split("collocation mesh: ")
        .nth(1)
        .and_then(|r| r.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap();
    assert!(count > 0, "{adapted}");
    let json = |extra: &[&str]| -> serde_json::Value {
        let out = bin()
            .args(["continue", "--free", "omega", "--json"])
            .args(extra)
            .run_ok();
        serde_json::from_slice(&out.stdout).unwrap()
    };
    let coll = json(&["--method", "collocation"]);
    for p in coll["points"].as_array().unwrap() {
        let e = p["discretisation_error"].as_f64().unwrap();
        assert!(e > 0.0 && e < 1e-6, "{e}");
    }
    let shooting = json(&[]);
    assert!(shooting["points"][0].get("discretisation_error").is_none());
    assert_abs_diff_eq!(sn_omega(&coll), sn_omega(&shooting), epsilon = 1e-8);
    assert_one_line_usage_error(
        &["continue", "--free", "omega", "--mesh-tol", "0"],
        "discretisation_tolerance = 0",
    );
}

/// `--xi` and `--theta-b` reach `continue`, `orbit` and `classify` (as `simulate`): another
/// block has other special points and orbits; bad values exit 2 naming the parameter; a restart
/// keeps the saved run's block and refuses them.
#[test]
fn another_block_on_every_command() {
    let json = |args: &[&str]| -> serde_json::Value {
        serde_json::from_slice(&bin().args(args).run_ok().stdout).unwrap()
    };
    let fold = sn_omega;
    let study = json(&["continue", "--free", "omega", "--json"]);
    let other = json(&["continue", "--free", "omega", "--theta-b", "0.85", "--json"]);
    assert!(
        (fold(&study) - fold(&other)).abs() > 0.05,
        "{} vs {}",
        fold(&study),
        fold(&other)
    );
    let amp = |extra: &[&str]| {
        let mut args = vec!["orbit", "--json"];
        args.extend_from_slice(extra);
        json(&args)["amp"].as_f64().unwrap()
    };
    assert!((amp(&[]) - amp(&["--theta-b", "0.85"])).abs() > 1e-3);
    let trial = json(&["classify", "--xi", "0.001", "--theta-b", "0.9", "--json"]);
    assert_eq!(trial["xi"], 0.001);
    assert_eq!(trial["theta_b"], 0.9);
    assert_one_line_usage_error(
        &["continue", "--free", "omega", "--xi", "-0.1"],
        "xi = -0.1",
    );
    assert_one_line_usage_error(&["orbit", "--theta-b", "1.7"], "theta_b = 1.7");
    assert_one_line_usage_error(
        &[
            "continue",
            "--free",
            "omega",
            "--restart",
            "run.json",
            "--label",
            "2",
            "--xi",
            "0.1",
        ],
        "a restart continues the saved run's block",
    );
}
