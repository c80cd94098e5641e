//! The study's branches by collocation with meshes adapted along them, against shooting.

use hycont_continuation::observe::Silent;
use hycont_continuation::{OrbitContinuation, OrbitMethod, SpecialKind};
use hycont_core::orbit::CollocationSettings;
use rocking_block::RockingBlock;
use rocking_block::block::Block;
use rocking_block::continuation::{Free, Recipe, study_branches, study_branches_with};
use rocking_block::figures::branches::study_labels;

/// The branches of Figs. 3 and 4 by collocation on a coarse mesh (NTST 10 per segment, NCOL
/// 4, whose estimates of ~3e-8 make it move every 10 points), switched at branch points and
/// period doublings on the mesh of the point switched at, have the shooting branches' special
/// points: the same labels, at the same parameters to 1e-7, with estimates below the default
/// tolerance 1e-6. The asymmetric branch ends on its parent's located branch point where both
/// are on one mesh, else on its own located end: either way its end solves the problem on its
/// own mesh (a parent's point carried to another mesh would not: residual 1e-7, tried).
#[test]
fn study_branches_by_collocation_match_shooting() {
    let collocation = OrbitMethod::Collocation(CollocationSettings {
        ntst: 10,
        ..CollocationSettings::default()
    });
    for free in [Free::Omega, Free::Alpha] {
        let block = Block::default();
        let shooting = study_branches(free, &block, &mut Silent).unwrap();
        let coll =
            study_branches_with(free, &block, &Recipe::with_method(collocation), &mut Silent)
                .unwrap();
        let (a, b) = (
            study_labels(&shooting, free, &[]),
            study_labels(&coll, free, &[]),
        );
        let names = |l: &[(SpecialKind, f64, f64, String)]| -> Vec<String> {
            l.iter().map(|x| x.3.clone()).collect()
        };
        assert_eq!(names(&a), names(&b), "{free:?}");
        for (x, y) in a.iter().zip(&b) {
            assert!(
                (x.1 - y.1).abs() < 1e-7,
                "{free:?} {}: {} vs {}",
                x.3,
                x.1,
                y.1
            );
        }
        let adapted: usize = coll
            .iter()
            .map(|o| o.branch.statistics.rediscretisations)
            .sum();
        assert!(adapted > 0, "{free:?}: the meshes adapt");
        for o in &coll {
            for p in &o.branch.points {
                let e = p.discretisation_error.unwrap();
                assert!(e < 1e-6, "{} {}: {e:e}", o.branch.name, p.label);
                o.orbit_of(p).unwrap();
            }
        }
        // Fig. 3's asymmetric branch ends at BP2 (Fig. 4's at the bound).
        let asym = &coll[1];
        let end = asym.branch.special_points.last().unwrap();
        if free == Free::Alpha {
            assert_eq!(end.kind, SpecialKind::EndPoint);
            continue;
        }
        assert_eq!(end.kind, SpecialKind::BranchPoint);
        // Its unknowns solve the problem on its own mesh (the branch's layout: the full orbit
        // with the continued parameter's slot last).
        let disc = asym.discretisation_of(&end.point).unwrap().clone();
        let measures = std::rc::Rc::new(hycont_core::orbit::MeasureSet::new());
        let mut cp = OrbitContinuation::on_discretisation(
            &RockingBlock,
            asym.template.clone(),
            disc,
            free.id(),
            measures,
            Vec::new(),
        )
        .unwrap();
        let problem = cp.problem_mut();
        let mut r = vec![0.0; problem.equations()];
        problem.evaluate(&end.point.u, &mut r, None).unwrap();
        let res = r.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        assert!(res < 1e-8, "residual {res:e}");
    }
}
