//! Two-parameter curves (Fig. 6): each passes through the one-parameter special points it
//! started from, and its user points (UZ) where it crosses alpha = 0.66 and omega = 1.3 are the
//! special points of Figs. 3 and 4 there, to 1e-9; a curve meets a separate one-parameter run.

use crate::common;
use approx::assert_abs_diff_eq;
use hycont_continuation::observe::Silent;
use hycont_continuation::{CurveSpec, MeasureId, OrbitMethod, RunDirection, SpecialKind};
use hycont_core::orbit::CollocationSettings;
use rocking_block::block::Block;
use rocking_block::continuation::{Free, default_method, study_branches, study_curves, study_run};
use rocking_block::orbits::{OrbitKind, orbit};
use rocking_block::{ALPHA, OMEGA, Parameters};
use std::f64::consts::PI;

#[test]
fn the_curves_meet_the_special_points_of_figures_3_and_4() {
    let fig3 = study_branches(Free::Omega, &Block::default(), &mut Silent).unwrap();
    let fig4 = study_branches(Free::Alpha, &Block::default(), &mut Silent).unwrap();
    let specials = |branches: &[hycont_continuation::OrbitBranch], k: SpecialKind, q| {
        branches
            .iter()
            .flat_map(|b| b.special(k))
            .map(|s| s.point[q])
            .collect::<Vec<f64>>()
    };
    let curves = study_curves(&Block::default(), &mut Silent).unwrap();
    let kinds: Vec<SpecialKind> = curves.iter().map(|c| c.kind).collect();
    use SpecialKind::{BoundaryTouch as SB, BranchPoint as BP, Fold as SN, Grazing as GR};
    assert_eq!(kinds, [SN, BP, SB, GR, SpecialKind::PeriodDoubling]);
    // How many special points of its kind each curve meets on alpha = 0.66 and omega = 1.3:
    // SN1 | SN2; BP1, BP2 | BP3; SB1, SB2 | SB3; GR1 | GR2; PD1.
    let expected = [(1, 1), (2, 1), (2, 1), (1, 1), (0, 1)];
    for (c, (n_alpha, n_omega)) in curves.iter().zip(expected) {
        let uz: Vec<_> = c.branch.special(SpecialKind::UserPoint).collect();
        let on_alpha: Vec<f64> = uz
            .iter()
            .filter(|s| (s.point[ALPHA] - 0.66).abs() < 1e-9)
            .map(|s| s.point[OMEGA])
            .collect();
        let on_omega: Vec<f64> = uz
            .iter()
            .filter(|s| (s.point[OMEGA] - 1.3).abs() < 1e-9)
            .map(|s| s.point[ALPHA])
            .collect();
        assert_eq!(
            (on_alpha.len(), on_omega.len()),
            (n_alpha, n_omega),
            "{}",
            c.kind
        );
        for (values, fig, q) in [(on_alpha, &fig3, OMEGA), (on_omega, &fig4, ALPHA)] {
            let reference = specials(fig, c.kind, q);
            for v in values {
                let nearest = reference
                    .iter()
                    .map(|r| (r - v).abs())
                    .fold(f64::INFINITY, f64::min);
                assert!(
                    nearest < 1e-9,
                    "{} UZ at {v}: {nearest:e} from Fig. 3/4",
                    c.kind
                );
            }
        }
        // Every point is a period-1 orbit of the forcing (half-orbit curves report the full
        // period), and the curve lies in the study's window.
        for p in &c.branch.branch.points {
            let forcing = 2.0 * PI / p[OMEGA];
            assert_abs_diff_eq!(p[MeasureId::PERIOD], forcing, epsilon = 1e-8 * forcing);
            assert!(p[OMEGA] >= 0.5 - 1e-9 && p[OMEGA] <= 4.0 + 1e-9);
        }
    }
}

#[test]
fn the_period_doubling_curve_meets_a_separate_alpha_continuation() {
    // The PD curve from PD1 (omega = 1.3), with a user point at omega = 2, against the PD
    // found by an alpha continuation of the asymmetric orbit at omega = 2.
    let params = Parameters::new(1.3, 0.66);
    let fig4 = study_branches(Free::Alpha, &Block::default(), &mut Silent).unwrap();
    let pd1 = fig4[1].special(SpecialKind::PeriodDoubling).next().unwrap();
    let mut run = study_run(Free::Alpha, &params, Free::Alpha.range(), default_method()).unwrap();
    let spec = CurveSpec::new(OMEGA)
        .bounds(0.5, 4.0)
        .user_points(OMEGA, [2.0]);
    let c = run
        .curve_at("PD", &fig4[1], pd1.point.label, &spec)
        .unwrap();
    let uz = c.special(SpecialKind::UserPoint).next().unwrap();
    let alpha_curve = uz.point[ALPHA];
    let asym = orbit(&Parameters::new(2.0, 0.7), OrbitKind::AsymmetricPos, None)
        .unwrap()
        .solution
        .orbit;
    let mut run = study_run(Free::Alpha, &params, (0.5, 1.06), default_method()).unwrap();
    let b = run.run("asym", &asym, RunDirection::Up).unwrap();
    let pd = b.special(SpecialKind::PeriodDoubling).next().unwrap().point[ALPHA];
    assert_abs_diff_eq!(pd, alpha_curve, epsilon = 1e-9);
}

/// The symmetry-breaking curve by collocation (its own branch and curve on NTST 20, NCOL 4)
/// meets the shooting branch point BP3 at omega = 1.3 to the discretisation's accuracy.
#[test]
fn a_collocation_curve_agrees_with_shooting() {
    let params = Parameters::new(1.3, 0.66);
    let start = orbit(&params, OrbitKind::Symmetric, None)
        .unwrap()
        .solution
        .orbit;
    let method = OrbitMethod::Collocation(CollocationSettings::default());
    let mut run = study_run(Free::Omega, &params, (1.0, 1.35), method).unwrap();
    let b = run.run("symmetric", &start, RunDirection::Down).unwrap();
    let bp1 = b.special(SpecialKind::BranchPoint).next().unwrap();
    assert_abs_diff_eq!(bp1.point[OMEGA], 1.142_793_27, epsilon = 1e-7);
    let spec = CurveSpec::new(ALPHA)
        .bounds(0.01, 1.06)
        .user_points(OMEGA, [1.3])
        .direction(RunDirection::Up);
    let c = run.curve_at("BP", &b, bp1.point.label, &spec).unwrap();
    let bp3 = c.special(SpecialKind::UserPoint).next().unwrap().point[ALPHA];
    let fig4 = study_branches(Free::Alpha, &Block::default(), &mut Silent).unwrap();
    let shooting = fig4[0]
        .special(SpecialKind::BranchPoint)
        .next()
        .unwrap()
        .point[ALPHA];
    assert_abs_diff_eq!(bp3, shooting, epsilon = 1e-7);
}

/// `rocking-block curve` from PD1 of a saved asymmetric run in alpha (omega = 1.3): the PD curve
/// of Fig. 6. Every point has a multiplier at -1 (to 1e-6), the user point at omega = 1.3 is
/// PD1, alpha = 0.73653017 (to 1e-6), the curve file and its picture are written; a start
/// that is not a special point of a curve's kind, or the saved run's own parameter as second,
/// exit 2.
#[test]
fn the_curve_command_continues_pd1_in_omega() {
    use common::{RunOk, bin};
    let dir = std::env::temp_dir().join(format!("rocking-block-curve-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let run = dir.join("run.json");
    let out = bin()
        .args([
            "continue",
            "--free",
            "alpha",
            "--omega",
            "1.3",
            "--kind",
            "asymmetric-pos",
        ])
        .args(["--json", "--out"])
        .arg(&run)
        .run_ok();
    let branch: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let label_of = |kind: &str| {
        branch["special_points"]
            .as_array()
            .unwrap()
            .iter()
            .find(|s| s["kind"] == kind)
            .unwrap()["label"]
            .as_u64()
            .unwrap()
            .to_string()
    };
    let (pd, end) = (label_of("PD"), label_of("EP"));
    let (file, svg) = (dir.join("pd.json"), dir.join("pd.svg"));
    let curve = |label: &str, second: &str| {
        let mut cmd = bin();
        cmd.arg("curve").arg("--restart").arg(&run).args([
            "--label",
            label,
            "--second",
            second,
            "--uz-omega",
            "1.3",
            "--json",
        ]);
        cmd
    };
    let out = curve(&pd, "omega")
        .arg("--out")
        .arg(&file)
        .arg("--svg")
        .arg(&svg)
        .run_ok();
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["kind"], "PD");
    assert_eq!(v["free"], serde_json::json!(["alpha", "omega"]));
    let points = v["points"].as_array().unwrap();
    assert!(points.len() > 20);
    for p in points {
        let closest = p["multipliers"]
            .as_array()
            .unwrap()
            .iter()
            .map(|m| (m[0].as_f64().unwrap() + 1.0).hypot(m[1].as_f64().unwrap()))
            .fold(f64::INFINITY, f64::min);
        assert!(closest < 1e-6, "label {}: {closest:e}", p["label"]);
    }
    let uz = v["special_points"]
        .as_array()
        .unwrap()
        .iter()
        .find(|s| s["kind"] == "UZ" && (s["omega"].as_f64().unwrap() - 1.3).abs() < 1e-9)
        .expect("a user point at omega = 1.3");
    assert_abs_diff_eq!(uz["alpha"].as_f64().unwrap(), 0.736_530_17, epsilon = 1e-6);
    assert!(
        std::fs::read_to_string(&file)
            .unwrap()
            .contains("\"second\"")
    );
    assert!(std::fs::read_to_string(&svg).unwrap().contains("PD curve"));
    // A saved curve continues from its end: bounded at omega = 2, then on to omega = 4.
    let short = dir.join("short.json");
    let out = curve(&pd, "omega")
        .args(["--max", "2", "--out"])
        .arg(&short)
        .run_ok();
    let saved: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let top = saved["special_points"]
        .as_array()
        .unwrap()
        .iter()
        .find(|s| s["kind"] == "EP" && (s["omega"].as_f64().unwrap() - 2.0).abs() < 1e-9)
        .map(|s| s["label"].as_u64().unwrap().to_string())
        .expect("the end at omega = 2");
    let out = bin()
        .arg("curve")
        .arg("--restart")
        .arg(&short)
        .args([
            "--label",
            &top,
            "--second",
            "omega",
            "--uz-omega",
            "3",
            "--json",
        ])
        .run_ok();
    let longer: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let uz3 = longer["special_points"]
        .as_array()
        .unwrap()
        .iter()
        .find(|s| s["kind"] == "UZ")
        .expect("the user point at omega = 3 beyond the saved curve's end");
    assert_abs_diff_eq!(uz3["omega"].as_f64().unwrap(), 3.0, epsilon = 1e-9);
    let mu = uz3["multipliers"].as_array().unwrap();
    assert!(
        mu.iter()
            .any(|m| (m[0].as_f64().unwrap() + 1.0).abs() < 1e-6)
    );
    for (label, second, needle) in [
        (end.as_str(), "omega", "cannot continue a curve at label"),
        (pd.as_str(), "alpha", "must differ from the saved run's"),
    ] {
        let out = curve(label, second).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{err}");
        assert!(err.contains(needle), "{err}");
    }
    std::fs::remove_dir_all(&dir).ok();
}
