//! Whole diagrams of the rocking block in one call: every special point of Figs. 3 and 4 (as
//! the study's recipe of separate runs and switches computes them, to 1e-9, past grazing
//! too), the period-doubling cascade in alpha at omega = 1.3 beyond PD1 and PD2 and a second
//! one past GR2, and the `diagram`
//! command (output, saved diagrams extended deeper, bad input).

use crate::common;
use approx::assert_abs_diff_eq;

use common::{RunOk, bin, fails, scratch};
use hycont_continuation::observe::Silent;
use hycont_continuation::{DiagramSettings, SpecialKind};
use rocking_block::block::Block;
use rocking_block::continuation::{
    AMP, Free, Recipe, study_branches_from, study_diagram, study_start,
};

#[test]
fn one_call_holds_every_special_point_of_figures_3_and_4() {
    let block = Block::default();
    let start = study_start(&block).unwrap();
    let recipe = Recipe::default();
    for free in [Free::Omega, Free::Alpha] {
        let recipe_branches =
            study_branches_from(free, &block, &recipe, &start, &mut Silent).unwrap();
        let d = study_diagram(
            "symmetric",
            free,
            free.range(),
            &recipe,
            &start,
            &DiagramSettings::default(),
            &mut Silent,
        )
        .unwrap();
        let mut matched = 0;
        for s in recipe_branches
            .iter()
            .flat_map(|b| &b.branch.special_points)
        {
            if matches!(s.kind, SpecialKind::EndPoint | SpecialKind::UserPoint) {
                continue;
            }
            let (p, amp) = (s.point[free.id()], s.point[AMP]);
            let near = d.special_points().any(|(_, o)| {
                o.kind == s.kind
                    && (o.point[free.id()] - p).abs() <= 1e-9
                    && (o.point[AMP] - amp).abs() <= 1e-9
            });
            assert!(
                near,
                "{} {} = {p} (amp {amp}) is not in the diagram",
                s.kind.label(),
                free.name()
            );
            matched += 1;
        }
        // Fig. 3: GR, SN, BP1, BP2, SB1, SB2, BP2 again on the asymmetric branch; Fig. 4: GR,
        // SN, BP3, SB3, PD1, PD2; in both the branch past grazing's BP, SN and GR.
        assert!(matched >= 6, "{matched} special points in {}", free.name());
    }
}

/// Beyond the study's PD1 and PD2 (alpha ~ 0.7365, 0.7542): each doubled branch's own
/// doubling, located by continuation, the intervals shrinking by ratios that approach
/// Feigenbaum's delta = 4.6692, and the doublings accumulating below alpha ~ 0.759 where the
/// brute-force diagram (Fig. 5) turns chaotic. `diagram --free alpha --depth 7` with default
/// settings reaches PD6 on the period-32 branch, whose first step (from PD5, multiplier +1,
/// to alpha = 0.7588331, multiplier -1.18) holds it: a switched branch's first step is tested
/// like any other. PD1 to PD5 are the README's values (1e-9); PD6 is where a multiplier is -1
/// (to the critical tolerance 1e-6) and within 2e-8 of the Feigenbaum estimate
/// PD5 + (PD5 - PD4) / delta = 0.75883010 (the ratios' own distance from delta, 1e-3
/// relative, times the interval PD5 - PD6 = 3.6e-5).
#[test]
fn the_cascade_in_alpha_doubles_towards_chaos() {
    let out = bin()
        .args(["diagram", "--free", "alpha", "--depth", "7", "--json"])
        .run_ok();
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let cascades = v["cascades"].as_array().unwrap();
    let numbers = |c: &serde_json::Value, key: &str| -> Vec<f64> {
        c[key]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect()
    };
    // The study's cascade from PD1, and past grazing (alpha below GR2 = 0.5976, above its
    // family's fold at 0.5597) the cascades of the families with the dip's impacts: the one
    // from the BP of the first of them (below), and chains of doublings on the families
    // switched at their own grazings.
    let first = |c: &serde_json::Value| numbers(c, "doublings")[0];
    let study = cascades
        .iter()
        .find(|c| (first(c) - 0.7365).abs() < 1e-3)
        .unwrap_or_else(|| panic!("no study cascade in {cascades:?}"));
    let past = cascades
        .iter()
        .find(|c| (first(c) - 0.5609963).abs() < 1e-6)
        .unwrap_or_else(|| panic!("no cascade from 0.5609963 in {cascades:?}"));
    for c in cascades {
        if !std::ptr::eq(c, study) {
            let d = numbers(c, "doublings");
            assert!(d.iter().all(|a| (0.5597..0.5976).contains(a)), "{d:?}");
        }
    }
    let doublings = numbers(study, "doublings");
    assert!(doublings.len() >= 6, "{doublings:?}");
    let readme = [
        0.736_530_171_2,
        0.754_152_661_8,
        0.757_840_937_5,
        0.758_626_102_8,
        0.758_794_112_5,
    ];
    for (pd, expected) in doublings.iter().zip(readme) {
        assert_abs_diff_eq!(*pd, expected, epsilon = 1e-9);
    }
    const DELTA: f64 = 4.669_201_609_102_99;
    let estimate = doublings[4] + (doublings[4] - doublings[3]) / DELTA;
    assert_abs_diff_eq!(doublings[5], estimate, epsilon = 2e-8);
    assert!(doublings.windows(2).all(|w| w[1] > w[0]));
    assert!(*doublings.last().unwrap() < 0.759);
    let ratios = numbers(study, "ratios");
    assert!(ratios.iter().all(|r| (4.5..5.0).contains(r)), "{ratios:?}");
    // The ratios approach delta from above.
    assert!(ratios.windows(2).all(|w| w[1] < w[0]), "{ratios:?}");
    assert_abs_diff_eq!(*ratios.last().unwrap(), DELTA, epsilon = 0.01);
    // PD6 is a genuine doubling: its branch (period 32, depth 6, above PD1 where the study's
    // cascade lies; the cascade past grazing has depth-6 branches too) reports it with a
    // multiplier at -1.
    let branches = v["branches"].as_array().unwrap();
    let pd6 = branches
        .iter()
        .filter(|b| b["depth"] == 6)
        .flat_map(|b| b["special_points"].as_array().unwrap())
        .find(|s| s["kind"] == "PD" && s["alpha"].as_f64().unwrap() > readme[0])
        .unwrap_or_else(|| panic!("no PD on the period-32 branch"));
    assert_abs_diff_eq!(
        pd6["alpha"].as_f64().unwrap(),
        doublings[5],
        epsilon = 1e-12
    );
    let at_minus_one = pd6["multipliers"].as_array().unwrap().iter().any(|m| {
        let (re, im) = (m[0].as_f64().unwrap(), m[1].as_f64().unwrap());
        (re + 1.0).abs() <= 1e-6 && im.abs() <= 1e-8
    });
    assert!(at_minus_one, "{}", pd6["multipliers"]);
    // Past GR2 (alpha = 0.5976) the family with the dip's extra impacts has a branch point
    // (alpha = 0.5606); the branch switched there doubles in a cascade of its own, between the
    // two, its ratios approaching delta from below.
    let doublings = numbers(past, "doublings");
    assert!(doublings.len() >= 4, "{doublings:?}");
    assert!(
        doublings.iter().all(|a| (0.5606..0.5976).contains(a)),
        "{doublings:?}"
    );
    assert!(doublings.windows(2).all(|w| w[1] > w[0]));
    let ratios = numbers(past, "ratios");
    assert!(ratios.windows(2).all(|w| w[1] > w[0]), "{ratios:?}");
    assert!(
        ratios.iter().all(|r| (4.0..DELTA).contains(r)),
        "{ratios:?}"
    );
    assert_abs_diff_eq!(*ratios.last().unwrap(), DELTA, epsilon = 0.01);
}

#[test]
fn the_diagram_command_prints_extends_and_refuses_bad_input() {
    let dir = scratch("diagram");
    std::fs::create_dir_all(&dir).unwrap();
    let (saved, svg) = (dir.join("d.json"), dir.join("d.svg"));
    let out = bin()
        .args(["diagram", "--free", "alpha", "--depth", "2", "--out"])
        .arg(&saved)
        .arg("--svg")
        .arg(&svg)
        .run_ok();
    let picture = std::fs::read_to_string(&svg).unwrap();
    assert!(
        picture.contains("<svg") && picture.contains("PD1"),
        "{picture:.200}"
    );
    let text = String::from_utf8_lossy(&out.stdout);
    // The symmetric branch, the branches switched at its GR and BP, and at theirs (past GR2:
    // its BP and its own GR, where the dip's impacts grow another pair).
    assert!(text.starts_with("6 branches"), "{text}");
    assert!(text.contains("PD label"), "{text}");
    assert!(text.contains("period-doubling cascade"), "{text}");
    // A line per branch on stderr.
    assert_eq!(
        String::from_utf8_lossy(&out.stderr)
            .matches("branch ")
            .count(),
        6
    );
    // Extended one level deeper: the period-4 branch, and past GR2 four more (at the GR and
    // PD of the branch switched at its BP, and at the BP and GR of the one switched at its
    // GR); the study's cascade has three doublings.
    let out = bin()
        .args([
            "diagram",
            "--free",
            "alpha",
            "--depth",
            "3",
            "--json",
            "--restart",
        ])
        .arg(&saved)
        .run_ok();
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let branches = v["branches"].as_array().unwrap();
    assert_eq!(branches.len(), 11);
    assert_eq!(branches.iter().filter(|b| b["depth"] == 3).count(), 5);
    let study = v["cascades"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| (c["doublings"][0].as_f64().unwrap() - 0.736_530_171_2).abs() < 1e-9)
        .unwrap();
    assert_eq!(study["doublings"].as_array().unwrap().len(), 3);
    // --max-branches bounds a fresh diagram too: at depth 6 with 2 branches (the symmetric
    // one and the one past GR2) the switch at BP3 is left at the limit.
    let out = bin()
        .args([
            "diagram",
            "--free",
            "alpha",
            "--depth",
            "6",
            "--max-branches",
            "2",
        ])
        .run_ok();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.starts_with("2 branches"), "{text}");
    assert!(text.contains("not followed (--max-branches)"), "{text}");
    // Bad input: one line, exit 2.
    fails(
        &bin()
            .args(["diagram", "--free", "omega", "--restart"])
            .arg(&saved)
            .output()
            .unwrap(),
        2,
        "other parameter",
    );
    fails(
        &bin()
            .args([
                "diagram",
                "--free",
                "alpha",
                "--theta-b",
                "0.85",
                "--restart",
            ])
            .arg(&saved)
            .output()
            .unwrap(),
        2,
        "a restart continues the saved run's block",
    );
    // A saved diagram is checked before it is extended: edited, it is bad input.
    let text = std::fs::read_to_string(&saved).unwrap();
    let refused = |edit: &dyn Fn(&mut serde_json::Value), needle: &str| {
        let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
        edit(&mut v);
        std::fs::write(dir.join("edited.json"), v.to_string()).unwrap();
        let out = bin()
            .args(["diagram", "--free", "alpha", "--depth", "3", "--restart"])
            .arg(dir.join("edited.json"))
            .output()
            .unwrap();
        fails(&out, 2, needle);
    };
    refused(
        &|v| v["branches"][1]["origin"][0] = 42.into(),
        "origin on branch 42",
    );
    refused(
        &|v| {
            for p in v["branches"][2]["branch"]["branch"]["points"]
                .as_array_mut()
                .unwrap()
            {
                p["u"][0] = (p["u"][0].as_f64().unwrap() + 0.3).into();
            }
        },
        "orbit equations do not hold",
    );
    std::fs::write(dir.join("bad.json"), "{}").unwrap();
    fails(
        &bin()
            .args(["diagram", "--free", "alpha", "--restart"])
            .arg(dir.join("bad.json"))
            .output()
            .unwrap(),
        2,
        "not a diagram",
    );
    fails(
        &bin()
            .args(["diagram", "--free", "alpha", "--max-branches", "0"])
            .output()
            .unwrap(),
        2,
        "max_branches",
    );
    std::fs::remove_dir_all(&dir).ok();
}
