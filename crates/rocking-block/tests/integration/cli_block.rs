//! Another block from the command line: the study's figures for it (`figure all --theta-b`),
//! dimensional inputs converted by the study's eq. (5), and the provenance every JSON carries.

use crate::common;

use approx::assert_relative_eq;
use common::{RunOk, bin, fails, json, scratch, without_provenance};
use serde_json::Value;

/// `figure all --theta-b 0.85` runs every figure for the other block: each JSON records the
/// block and the command line, each picture's title names the block (the study's do not), and
/// Figs. 3, 4 and 6 differ from the study's (its fold SN1 moves from omega 0.9096 to about
/// 0.99: a more slender block, another branch).
#[test]
fn figure_all_for_another_block() {
    let dir = scratch("block-all");
    let (other, study) = (dir.join("other"), dir.join("study"));
    bin()
        .args([
            "figure",
            "all",
            "--theta-b",
            "0.85",
            "--trials",
            "60",
            "--format",
            "both",
            "--out",
        ])
        .arg(&other)
        .run_ok();
    for n in [3, 4, 6] {
        bin()
            .args(["figure", &n.to_string(), "--out"])
            .arg(&study)
            .run_ok();
        let (a, b) = (
            json(&other.join(format!("fig{n}.json"))),
            json(&study.join(format!("fig{n}.json"))),
        );
        assert_ne!(without_provenance(&a), without_provenance(&b), "fig{n}");
        assert_eq!(b["provenance"]["block"]["theta_b"], 0.8795);
        let title = std::fs::read_to_string(study.join(format!("fig{n}.svg"))).unwrap();
        assert!(
            !title.contains("(block"),
            "fig{n} of the study names no block"
        );
    }
    // Every picture, SVG and PNG, and its title names the block.
    for name in [
        "fig2",
        "fig3",
        "fig4",
        "fig5",
        "fig6",
        "fig6_tests",
        "fig7",
        "fig8",
        "fig9",
        "fig10",
        "atlas",
    ] {
        let svg = std::fs::read_to_string(other.join(format!("{name}.svg"))).unwrap();
        assert!(
            svg.contains("(block theta_b = 0.85, xi = 0.00022)"),
            "{name}'s title names the block"
        );
        assert!(other.join(format!("{name}.png")).exists(), "{name}.png");
    }
    let names = (2..=10)
        .map(|n| format!("fig{n}"))
        .chain(["atlas".to_string()]);
    for (name, n) in names.zip(2..) {
        let v = json(&other.join(format!("{name}.json")));
        let p = &v["provenance"];
        assert_eq!(p["block"]["theta_b"], 0.85, "{name}");
        assert_eq!(p["hycont_version"], env!("CARGO_PKG_VERSION"));
        let line: Vec<&str> = p["command_line"]
            .as_array()
            .unwrap()
            .iter()
            .map(|a| a.as_str().unwrap())
            .collect();
        assert_eq!(&line[1..4], ["figure", "all", "--theta-b"], "{name}");
        if [7, 9, 10].contains(&n) {
            assert_eq!(
                (p["seed"].as_u64(), p["trials"].as_u64()),
                (Some(1), Some(60))
            );
        }
    }
    let sn1 = json(&other.join("fig3.json"))["labels"]
        .as_array()
        .unwrap()
        .iter()
        .find(|l| l["label"] == "SN1")
        .map(|l| l["omega"].as_f64().unwrap())
        .unwrap();
    assert!((sn1 - 0.9096).abs() > 0.05, "SN1 at {sn1}");
    std::fs::remove_dir_all(&dir).ok();
}

/// The orbit of a dimensional block and forcing is the orbit of the dimensionless values of
/// eq. (5), computed here independently: a 4 m x 5 m block of 15 t with damping 80 N m s has
/// $R = \tfrac12\sqrt{4^2+5^2}$, $\theta_b = \arctan(5/4)$, $\Omega_0 = \sqrt{9.81/R}$,
/// $\xi = 80/(15000 R^2 \Omega_0)$; ground motion of 2 m at 0.3 Hz gives
/// $\omega = 2\pi\,0.3/\Omega_0$, $\alpha = 2/R$.
#[test]
fn dimensional_inputs_are_the_dimensionless_values_of_eq_5() {
    let r = 0.5 * (16.0f64 + 25.0).sqrt();
    let omega0 = (9.81 / r).sqrt();
    let expected = [
        ("omega", std::f64::consts::TAU * 0.3 / omega0),
        ("alpha", 2.0 / r),
        ("xi", 80.0 / (15000.0 * r * r * omega0)),
        ("theta_b", (5.0f64 / 4.0).atan()),
    ];
    let out = bin()
        .args([
            "orbit",
            "--method",
            "shooting",
            "--width",
            "4",
            "--height",
            "5",
            "--mass",
            "15000",
            "--damping",
            "80",
            "--frequency-hz",
            "0.3",
            "--amplitude",
            "2",
            "--json",
        ])
        .run_ok();
    let told = String::from_utf8_lossy(&out.stderr);
    assert!(told.contains("dimensionless"), "{told}");
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    let p = &v["provenance"];
    for (name, value) in expected {
        assert_relative_eq!(
            p["parameters"][name].as_f64().unwrap(),
            value,
            max_relative = 1e-15
        );
    }
    assert_eq!(p["dimensional"]["size"], serde_json::json!([4.0, 5.0]));
    assert_relative_eq!(p["dimensional"]["omega0"].as_f64().unwrap(), omega0);
    // The same orbit from the dimensionless values.
    let mut args = vec!["orbit".to_string(), "--method".into(), "shooting".into()];
    for (name, value) in expected {
        args.push(format!("--{}={value}", name.replace('_', "-")));
    }
    args.push("--json".into());
    let w: Value = serde_json::from_slice(&bin().args(&args).run_ok().stdout).unwrap();
    assert_eq!(w["provenance"].get("dimensional"), None);
    assert_eq!(without_provenance(&v), without_provenance(&w));
}

/// Dimensional and dimensionless values of the same quantity, half a size, or values out of
/// range are refused as bad input (exit 2, one line naming the option).
#[test]
fn conflicting_or_bad_dimensional_inputs_are_refused() {
    for (args, needle) in [
        (&["--omega", "1.2", "--frequency", "2"][..], "--frequency"),
        (&["--alpha", "0.5", "--amplitude", "1"], "--amplitude"),
        (&["--width", "3"], "--height"),
        (
            &["--width", "3", "--height", "4", "--theta-b", "0.9"],
            "--theta-b",
        ),
        (&["--xi", "0.1", "--damping", "10"], "--damping"),
        (&["--frequency-hz", "-1"], "frequency"),
        (&["--radius", "0"], "radius"),
        (&["--width", "4", "--height", "1"], "theta_b"),
    ] {
        fails(&bin().arg("orbit").args(args).output().unwrap(), 2, needle);
    }
}

/// `continue --out` saves the run with its provenance; the restart reads it (provenance
/// ignored) and refuses block or forcing options (it keeps the saved run's).
#[test]
fn saved_runs_carry_provenance_and_restart() {
    let dir = scratch("block-saved");
    std::fs::create_dir_all(&dir).unwrap();
    let run = dir.join("run.json");
    bin()
        .args([
            "continue",
            "--free",
            "omega",
            "--theta-b",
            "0.85",
            "--max-points",
            "5",
        ])
        .arg("--out")
        .arg(&run)
        .run_ok();
    let v = json(&run);
    assert_eq!(v["provenance"]["parameters"]["theta_b"], 0.85);
    assert_eq!(v["provenance"]["command_line"][1], "continue");
    let again = bin()
        .args([
            "continue",
            "--free",
            "omega",
            "--label",
            "3",
            "--max-points",
            "3",
            "--json",
        ])
        .arg("--restart")
        .arg(&run)
        .run_ok();
    let w: Value = serde_json::from_slice(&again.stdout).unwrap();
    assert_eq!(w["provenance"]["block"]["theta_b"], 0.85);
    let refused = bin()
        .args([
            "continue",
            "--free",
            "omega",
            "--label",
            "3",
            "--amplitude",
            "1",
        ])
        .arg("--restart")
        .arg(&run)
        .output()
        .unwrap();
    assert_eq!(refused.status.code(), Some(2));
    std::fs::remove_dir_all(&dir).ok();
}
