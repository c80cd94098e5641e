//! The classifier and the sampling figures against the study's reference behaviour.

use crate::common;
use approx::assert_abs_diff_eq;

use common::{RunOk, bin};

use hycont_sample::basin::{Progress, run};
use rocking_block::block::Block;
use rocking_block::classes::{
    Class, ClassifierSettings, Decision, RockingClassifier, base_class, classify,
};
use rocking_block::figures::sampling::{SampleOptions, fig7_study, figure5, figure7};
use rocking_block::output::OutDir;
use rocking_block::provenance::Provenance;
use rocking_block::{Parameters, SimulationRequest, simulate};
use std::f64::consts::FRAC_PI_2;

fn settings() -> ClassifierSettings {
    ClassifierSettings::default()
}

/// A state on the attractor reached from (0.01, 0, beta = pi/2) at (1.3, alpha0), as
/// (phi, psi, beta) with beta the forcing phase of (r, s).
fn on_attractor(alpha0: f64) -> (f64, f64, f64) {
    // From the asymmetric orbit at alpha = 0.73 after its impact (`rocking-block orbit --kind
    // asymmetric-pos --alpha 0.73`): phi = 0, psi = 0.22926, forcing phase 1.44396.
    let req = SimulationRequest {
        params: Parameters::new(1.3, alpha0),
        phi0: 0.0,
        psi0: 0.229_263_630_265_526,
        beta: 1.443_957_489_041_63,
        periods: 200.0,
        ..SimulationRequest::default()
    };
    let (report, _) = simulate(&req).unwrap();
    assert_eq!(
        report.outcome,
        rocking_block::Outcome::Running,
        "alpha {alpha0}"
    );
    let x = report.final_state;
    (x[0], x[1], x[2].atan2(x[3]))
}

#[test]
fn classes_of_known_cases() {
    let p = |w, a| Parameters::new(w, a);
    let c = classify(&p(1.3, 0.66), FRAC_PI_2, 0.01, 0.0, &settings()).unwrap();
    assert!(
        matches!(c.class, Class::AsymmetricP1Pos | Class::AsymmetricP1Neg),
        "{c:?}"
    );
    assert_eq!(
        classify(&p(1.3, 0.66), 0.0, 0.01, 0.0, &settings())
            .unwrap()
            .class,
        Class::OverturnNeg
    );
    let c = classify(&p(1.3, 0.3), 0.0, 0.01, 0.0, &settings()).unwrap();
    assert_eq!((c.class, c.decision), (Class::Equilibrium, Decision::Rest));
    // The study's Fig. 3(d) initial condition comes to rest (not an overturn).
    let beta = (-0.7778f64).atan2(0.6284);
    assert_eq!(
        classify(&p(0.902, 0.66), beta, -0.2254, -0.1597, &settings())
            .unwrap()
            .class,
        Class::Equilibrium
    );
    // Near BP2 (a multiplier ~0.99 at omega = 4) the symmetric orbit is found by Newton
    // refinement instead of waiting.
    let c = classify(&p(4.0, 0.66), 0.0, -0.3, -0.5, &settings()).unwrap();
    assert_eq!(c.class, Class::SymmetricP1, "{c:?}");
    assert!(c.periods < 600);
}

#[test]
fn period_two_and_chaos_on_the_cascade() {
    let (phi, psi, beta) = on_attractor(0.73);
    let c = classify(&Parameters::new(1.3, 0.745), beta, phi, psi, &settings()).unwrap();
    assert_eq!(c.class, Class::Period2, "{c:?}");
    let (phi, psi, beta) = on_attractor(0.77);
    let c = classify(&Parameters::new(1.3, 0.779), beta, phi, psi, &settings()).unwrap();
    assert!(
        matches!(
            c.class,
            Class::Other | Class::OverturnNeg | Class::OverturnPos
        ),
        "{c:?}"
    );
}

#[test]
fn classified_asymmetric_orbits_are_the_orbit_solvers() {
    // The simulation that the classifier calls asymmetric settles on the orbit computed by
    // `rocking-block orbit`: same flight durations.
    use rocking_block::orbits::{OrbitKind, orbit};
    let params = Parameters::new(1.3, 0.66);
    let c = classify(&params, FRAC_PI_2, 0.01, 0.0, &settings()).unwrap();
    let kind = if c.class == Class::AsymmetricP1Pos {
        OrbitKind::AsymmetricPos
    } else {
        OrbitKind::AsymmetricNeg
    };
    let o = orbit(&params, kind, None).unwrap().report("x").unwrap();
    let req = SimulationRequest {
        beta: FRAC_PI_2,
        periods: 300.0,
        ..SimulationRequest::default()
    };
    let (_, traj) = simulate(&req).unwrap();
    let ev = &traj.events;
    let last = ev[ev.len() - 1].t - ev[ev.len() - 2].t;
    let mode_of_last = rocking_block::RockingBlock;
    let _ = mode_of_last;
    let flight_mode = if ev[ev.len() - 2].mode_after == Some(rocking_block::PLUS) {
        "+"
    } else {
        "-"
    };
    let expected = o
        .segments
        .iter()
        .find(|s| s.mode == flight_mode)
        .unwrap()
        .duration;
    assert_abs_diff_eq!(last, expected, epsilon = 1e-6);
}

#[test]
fn basin_counts_do_not_depend_on_threads() {
    let study = fig7_study(1.5, 11, &Block::default());
    let classifier = RockingClassifier::default();
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let two = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let a = one.install(|| run(&study, &classifier, 0..300, &Progress::default()).unwrap());
    let b = two.install(|| run(&study, &classifier, 0..300, &Progress::default()).unwrap());
    assert_eq!(a, b);
    let (class, with_rest) = base_class(9);
    assert_eq!((class, with_rest), (Class::AsymmetricP1Pos, true));
}

/// The texts of an SVG written by plotters (each text element's content is a line of its own).
fn svg_texts(path: &std::path::Path) -> Vec<String> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .map(|l| l.trim().to_string())
        .filter(|l| !l.starts_with('<'))
        .collect()
}

/// Every class named in a key: some text ends with `(name)`.
fn key_names(texts: &[String], classes: &[&str]) {
    for class in classes {
        let tag = format!("({class})");
        assert!(
            texts.iter().any(|t| t.ends_with(&tag)),
            "no key entry for {class}"
        );
    }
}

#[test]
fn figure_7_reference_behaviour() {
    let dir = std::env::temp_dir().join(format!("rocking-block-fig7-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    figure7(
        &OutDir::new(&dir),
        SampleOptions {
            trials: 1500,
            seed: 3,
            block: Block::default(),
        },
        &Provenance::default(),
        &Progress::default(),
    )
    .unwrap();
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("fig7.json")).unwrap()).unwrap();
    let basin = |w: f64| {
        v["basins"]
            .as_array()
            .unwrap()
            .iter()
            .find(|b| b["omega"].as_f64().unwrap() == w)
            .unwrap()
            .clone()
    };
    let f = |b: &serde_json::Value, c: &str| b["fractions"][c].as_f64().unwrap();
    // The key names every class a cell is coloured with (the dominant ones).
    let texts = svg_texts(&dir.join("fig7.svg"));
    assert!(texts.iter().any(|t| t == "dominant class"));
    key_names(
        &texts,
        &[
            "symmetric_p1",
            "equilibrium",
            "overturn_pos",
            "overturn_neg",
        ],
    );
    // omega = 1.0: symmetric period 1, equilibrium and both overturns coexist.
    let b = basin(1.0);
    for c in [
        "symmetric_p1",
        "equilibrium",
        "overturn_pos",
        "overturn_neg",
    ] {
        assert!(f(&b, c) > 0.02, "omega 1.0: {c} = {}", f(&b, c));
    }
    // omega = 1.16: the two asymmetric orbits, with overlapping 95 % intervals.
    let b = basin(1.16);
    let (lo_p, hi_p) = (
        b["intervals_95"]["asymmetric_p1_pos"][0].as_f64().unwrap(),
        b["intervals_95"]["asymmetric_p1_pos"][1].as_f64().unwrap(),
    );
    let (lo_n, hi_n) = (
        b["intervals_95"]["asymmetric_p1_neg"][0].as_f64().unwrap(),
        b["intervals_95"]["asymmetric_p1_neg"][1].as_f64().unwrap(),
    );
    assert!(f(&b, "asymmetric_p1_pos") > 0.1 && f(&b, "asymmetric_p1_neg") > 0.1);
    assert!(
        lo_p <= hi_n && lo_n <= hi_p,
        "asymmetric fractions differ: {lo_p}..{hi_p} vs {lo_n}..{hi_n}"
    );
    // omega = 1.5: no equilibrium; omega = 4.0: the symmetric orbit again, nothing undecided.
    assert_eq!(f(&basin(1.5), "equilibrium"), 0.0);
    let b = basin(4.0);
    assert!(f(&b, "symmetric_p1") > 0.1);
    assert_eq!(f(&b, "other"), 0.0);
    assert_eq!(b["trials"].as_u64().unwrap(), 1500);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn figure_5_shows_the_period_doubling_cascade() {
    let dir = std::env::temp_dir().join(format!("rocking-block-fig5-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    figure5(
        &OutDir::new(&dir),
        &Provenance::default(),
        &Progress::default(),
    )
    .unwrap();
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("fig5.json")).unwrap()).unwrap();
    // The picture marks the study's special points and says what every mark is.
    let texts = svg_texts(&dir.join("fig5.svg"));
    for needle in [
        "BP3",
        "PD1",
        "PD2",
        "sweep up (alpha increasing)",
        "sweep down (alpha decreasing)",
        "sweep down overturned (no samples;",
        "PD (period doubling)",
    ] {
        assert!(
            texts.iter().any(|t| t == needle),
            "fig5.svg lacks {needle:?}"
        );
    }
    let distinct = |alpha: f64| {
        let p = v["diagram"]
            .as_array()
            .unwrap()
            .iter()
            .min_by(|a, b| {
                (a["alpha"].as_f64().unwrap() - alpha)
                    .abs()
                    .total_cmp(&(b["alpha"].as_f64().unwrap() - alpha).abs())
            })
            .unwrap();
        let mut psi: Vec<f64> = p["psi"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| (x.as_f64().unwrap() * 1e6).round())
            .collect();
        psi.sort_by(f64::total_cmp);
        psi.dedup();
        (psi.len(), p["outcome"].as_str().unwrap().to_string())
    };
    assert_eq!(distinct(0.70).0, 1, "period 1 below PD1");
    assert_eq!(distinct(0.745).0, 2, "period 2 between PD1 and PD2");
    assert_eq!(distinct(0.757).0, 4, "period 4 after PD2");
    assert!(distinct(0.779).0 > 20, "chaotic at 0.779");
    assert!(distinct(0.8).1.starts_with("overturn"));
    // The cascade by continuation sits where the brute-force diagram splits: between the
    // k-th and (k+1)-th doublings (15 % of the interval off each, where the transients have
    // died out), the sampled values of alpha show period 2^k; at least through PD4.
    let doublings: Vec<f64> = v["continuation"]["period_doublings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    assert!(doublings.len() >= 4, "{doublings:?}");
    let mut checked = 0;
    for (k, w) in doublings.windows(2).enumerate() {
        let margin = 0.15 * (w[1] - w[0]);
        for p in v["diagram"].as_array().unwrap() {
            let alpha = p["alpha"].as_f64().unwrap();
            if alpha > w[0] + margin && alpha < w[1] - margin {
                assert_eq!(
                    distinct(alpha).0,
                    2 << k,
                    "period 2^{} at alpha {alpha}",
                    k + 1
                );
                checked += 1;
            }
        }
    }
    assert!(checked >= 10, "{checked} values between doublings");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn classify_cli_batch_and_errors() {
    let dir = std::env::temp_dir().join(format!("rocking-block-cls-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (input, output) = (dir.join("in.csv"), dir.join("out.csv"));
    std::fs::write(
        &input,
        "omega,alpha,beta,phi0,psi0\n1.3,0.3,0,0.01,0\n1.3,0.66,0,0.01,0\n",
    )
    .unwrap();
    bin()
        .args(["classify", "--input"])
        .arg(&input)
        .arg("--output")
        .arg(&output)
        .run_ok();
    let text = std::fs::read_to_string(&output).unwrap();
    let classes: Vec<&str> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(5).unwrap())
        .collect();
    assert_eq!(classes, ["equilibrium", "overturn_neg"]);
    std::fs::write(&input, "omega,alpha\n1,2\n").unwrap();
    let out = bin()
        .args(["classify", "--input"])
        .arg(&input)
        .arg("--output")
        .arg(&output)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr)
            .trim_end()
            .lines()
            .count(),
        1
    );
    let out = bin()
        .args(["classify", "--omega", "1.3", "--alpha", "0.3", "--json"])
        .output()
        .unwrap();
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["class"], "equilibrium");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn figures_8_to_10_write_their_json() {
    use rocking_block::figures::sampling::{figure9, figure10};
    let dir = std::env::temp_dir().join(format!("rocking-block-fig910-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let opts = SampleOptions {
        trials: 600,
        seed: 5,
        block: Block::default(),
    };
    figure9(
        &OutDir::new(&dir),
        opts,
        &Provenance::default(),
        &Progress::default(),
    )
    .unwrap();
    figure10(
        &OutDir::new(&dir),
        opts,
        &Provenance::default(),
        &Progress::default(),
    )
    .unwrap();
    let v9: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("fig9.json")).unwrap()).unwrap();
    assert_eq!(v9["basins"].as_array().unwrap().len(), 2);
    for b in v9["basins"].as_array().unwrap() {
        assert_eq!(b["trials"].as_u64().unwrap(), 600);
        assert_eq!(
            b["probabilities"]["overturn"].as_array().unwrap().len(),
            900
        );
    }
    // Fig. 9 reads on its own: axes, a probability scale with ticks, the curves named, every
    // group's panel at both betas.
    let svg9 = std::fs::read_to_string(dir.join("fig9.svg")).unwrap();
    for needle in [
        "omega (forcing frequency / Omega0, dimensionless)",
        "alpha (forcing amplitude / R, dimensionless)",
        "probability",
        "0.00",
        "1.00",
        "SN (fold, saddle-node) curve",
        "BP (branch point) curve",
        "PD (period doubling) curve",
        "symmetric_p1, beta = 0.0000",
        "other, beta = 1.5708",
    ] {
        // Each text element's content is a line of its own in the SVG.
        assert!(
            svg9.lines().any(|l| l.trim() == needle),
            "fig9.svg lacks the text {needle:?}"
        );
    }
    let v10: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("fig10.json")).unwrap()).unwrap();
    for m in ["phi0", "psi0", "beta"] {
        let per_bin: u64 = v10["marginals"][m]["trials_per_bin"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_u64().unwrap())
            .sum();
        assert_eq!(per_bin, 600, "{m}");
        // Probabilities of the groups add up to 1 in every bin with trials.
        let probs = &v10["marginals"][m]["probabilities"];
        for bin in 0..50 {
            let total: f64 = [
                "symmetric_p1",
                "asymmetric_p1",
                "overturn",
                "equilibrium",
                "other",
            ]
            .iter()
            .map(|g| probs[g][bin].as_f64().unwrap_or(0.0))
            .sum();
            assert!(
                (total - 1.0).abs() < 1e-12 || total == 0.0,
                "{m} bin {bin}: {total}"
            );
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn figure_8_grid_matches_the_studys_description() {
    use rocking_block::figures::sampling::{FIG8_GRID, figure8};
    let dir = std::env::temp_dir().join(format!("rocking-block-fig8-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    figure8(&OutDir::new(&dir), &Provenance::default()).unwrap();
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("fig8.json")).unwrap()).unwrap();
    let grids = v["grids"].as_array().unwrap();
    assert_eq!(grids.len(), 2);
    let count = |g: &serde_json::Value, class: &str| {
        g["classes"]
            .as_array()
            .unwrap()
            .iter()
            .flat_map(|c| c.as_array().unwrap())
            .filter(|x| *x == class)
            .count()
    };
    let total = FIG8_GRID.0 * FIG8_GRID.1;
    for g in grids {
        assert_eq!(g["classes"].as_array().unwrap().len(), FIG8_GRID.0);
        assert_eq!(count(g, "error"), 0);
        // Equilibrium at low forcing, symmetric period 1 above it, in both panels.
        assert!(count(g, "equilibrium") > total / 10);
        assert!(count(g, "symmetric_p1") > total / 10);
    }
    // The equilibrium region does not depend on beta (the study's observation).
    let (e0, e1) = (
        count(&grids[0], "equilibrium"),
        count(&grids[1], "equilibrium"),
    );
    assert_abs_diff_eq!(e0 as f64, e1 as f64, epsilon = 0.05 * e0 as f64);
    // beta = pi/2 has far more asymmetric orbits than beta = 0 (between the BP and PD lines).
    let asym = |g| count(g, "asymmetric_p1_pos") + count(g, "asymmetric_p1_neg");
    assert!(asym(&grids[1]) > 3 * asym(&grids[0]));
    assert_eq!(v["curves"].as_array().unwrap().len(), 5);
    // The key names every class drawn and the three curves.
    let drawn: Vec<String> = grids
        .iter()
        .flat_map(|g| g["classes"].as_array().unwrap().iter())
        .flat_map(|c| c.as_array().unwrap().iter())
        .map(|x| x.as_str().unwrap().to_string())
        .collect();
    let mut drawn: Vec<&str> = drawn.iter().map(String::as_str).collect();
    drawn.sort_unstable();
    drawn.dedup();
    let texts = svg_texts(&dir.join("fig8.svg"));
    key_names(&texts, &drawn);
    for curve in [
        "SN (fold, saddle-node) curve",
        "BP (branch point) curve",
        "PD (period doubling) curve",
        "final class",
    ] {
        assert!(texts.iter().any(|t| t == curve), "{curve}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// An interrupt during a figure that is not sampled stops its computation where it is (the
/// sweeps of Fig. 5 between values, the continuations of Figs. 3-6 and the atlas between
/// points and charts), and the figure is not written: an `Interrupted` error, no file. (With
/// the stop flag set before it starts, each figure must stop at its first check: before, the
/// flag was only read between figures.)
#[test]
fn an_interrupt_stops_a_figure_inside_it() {
    let dir = std::env::temp_dir().join(format!("rocking-block-stop-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    let progress = Progress::default();
    progress
        .stop
        .store(true, std::sync::atomic::Ordering::Relaxed);
    let options = SampleOptions {
        trials: 100,
        seed: 1,
        block: Block::default(),
    };
    for n in [3, 4, 5, 6, rocking_block::figures::ATLAS] {
        let e = rocking_block::figures::figure_with(
            n,
            &OutDir::new(&dir),
            options,
            &Provenance::default(),
            &progress,
        )
        .unwrap_err();
        assert!(
            matches!(e, rocking_block::error::Error::Interrupted { .. }),
            "figure {n}: {e}"
        );
        let files = std::fs::read_dir(&dir).map_or(0, |d| d.count());
        assert_eq!(files, 0, "figure {n} wrote files");
    }
    std::fs::remove_dir_all(&dir).ok();
}
