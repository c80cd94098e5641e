//! Henderson's covering ([`atlas::cover`]) on the unit sphere $x^2 + y^2 + z^2 = 1$ with $x$
//! and $y$ as the free parameters (monitors of the first two unknowns): a closed surface of
//! area $4\pi$, whose projection onto the $(x, y)$ plane folds on the equator, where
//! $\det [J; e_x^\top; e_y^\top] = 2z$ vanishes.
//! - Without edges the atlas closes on itself: every chart's polygon is cut by its neighbours
//!   inside its disc, and the polygons' areas add up to the sphere's (each polygon is flat, in
//!   its tangent plane: the sum converges to $4\pi$ from below as the radii shrink).
//! - With the fold as an edge, from the north pole, it covers the upper hemisphere: its
//!   boundary charts lie on the equator ($|z|$ below the location tolerance) and every chart
//!   has $z \ge 0$; with a bound $x \le 1/2$ as well, the bound's charts have $x = 1/2$.

use hycont_continuation::SpecialKind;
use hycont_continuation::atlas::{self, AtlasEdges, AtlasEnd, AtlasSettings, Edge};
use hycont_continuation::observe::Silent;
use hycont_core::ParamId;
use hycont_core::problem::{Activity, Problem, UnknownMonitor};

use crate::common::sphere;
use sphere::{Sphere, Surface, surface};

/// The area of a convex polygon (shoelace).
fn area(poly: &[[f64; 2]]) -> f64 {
    let n = poly.len();
    0.5 * (0..n)
        .map(|i| poly[i][0] * poly[(i + 1) % n][1] - poly[(i + 1) % n][0] * poly[i][1])
        .sum::<f64>()
}

fn no_edges() -> AtlasEdges {
    AtlasEdges {
        fold: false,
        ..AtlasEdges::default()
    }
}

#[test]
fn the_whole_sphere_is_covered_and_closes() {
    let (mut s, u0) = surface();
    let settings = AtlasSettings::default()
        .radii(0.1, 1e-3, 0.1)
        .edges(no_edges());
    let a = atlas::cover(&mut s, "sphere", &u0, [3, 4], &settings, &mut Silent).unwrap();
    assert_eq!(a.end, AtlasEnd::Covered);
    for c in &a.charts {
        let u = &c.point.u;
        let r = (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt();
        assert!((r - 1.0).abs() < 1e-10, "a chart off the sphere: |u| = {r}");
        assert!(c.edge.is_none() && !c.gave_up);
        // Every polygon lies inside its disc: nothing left uncovered.
        assert!(
            c.polygon
                .iter()
                .all(|v| v[0].hypot(v[1]) <= c.radius * (1.0 + 1e-6))
        );
    }
    // Flat polygons of radius R on a unit sphere: the area falls short by O(R^2).
    let total: f64 = a.charts.iter().map(|c| area(&c.polygon)).sum();
    let sphere = 4.0 * std::f64::consts::PI;
    assert!(
        total > 0.99 * sphere && total < 1.005 * sphere,
        "area {total} of {sphere}"
    );
    // Points everywhere on the sphere: both poles and the equator are reached.
    let z: Vec<f64> = a.charts.iter().map(|c| c.point.u[2]).collect();
    assert!(z.iter().any(|&z| z > 0.99) && z.iter().any(|&z| z < -0.99));
    // Charts meet symmetrically.
    for (i, c) in a.charts.iter().enumerate() {
        assert!(
            c.neighbours
                .iter()
                .all(|&j| a.charts[j].neighbours.contains(&i))
        );
    }
    // The triangles of mutual neighbours mesh the surface (at least two per chart on a closed
    // surface: V - E + F = 2 with E = 3F/2 for a triangulation, more where they overlap).
    let triangles = a.triangles();
    assert!(
        triangles.len() >= 2 * a.charts.len() - 4,
        "{}",
        triangles.len()
    );
    for [i, j, k] in triangles {
        assert!(i < j && j < k && a.charts[i].neighbours.contains(&k));
    }
}

#[test]
fn with_the_fold_as_an_edge_the_upper_hemisphere_is_covered() {
    let (mut s, u0) = surface();
    let settings = AtlasSettings::default().radii(0.1, 1e-3, 0.1);
    let a = atlas::cover(&mut s, "hemisphere", &u0, [3, 4], &settings, &mut Silent).unwrap();
    assert_eq!(a.end, AtlasEnd::Covered);
    let fold = Edge::Special {
        kind: SpecialKind::Fold,
    };
    let mut on_equator = 0;
    for c in &a.charts {
        let z = c.point.u[2];
        // Located to 1e-6 of a radius in arclength on the inside: 0 <= z <= 1e-7.
        assert!(z >= 0.0, "a chart below the equator: z = {z}");
        if c.edge == Some(fold) {
            on_equator += 1;
            assert!(z < 1e-6, "a fold chart at z = {z}");
        }
    }
    // The equator (length 2 pi) is lined with boundary charts about a radius apart.
    assert!(on_equator >= 40, "{on_equator} charts on the equator");
    let total: f64 = a.charts.iter().map(|c| area(&c.polygon)).sum();
    let half = 2.0 * std::f64::consts::PI;
    assert!(
        total > 0.99 * half && total < 1.005 * half,
        "area {total} of {half}"
    );
}

#[test]
fn a_bound_cuts_the_hemisphere_at_its_level() {
    let (mut s, u0) = surface();
    let settings = AtlasSettings::default()
        .radii(0.1, 1e-3, 0.1)
        .bound(ParamId(0), -2.0, 0.5);
    let a = atlas::cover(&mut s, "cut", &u0, [3, 4], &settings, &mut Silent).unwrap();
    assert_eq!(a.end, AtlasEnd::Covered);
    let mut on_bound = 0;
    for c in &a.charts {
        assert!(c.point.u[0] <= 0.5 && c.point.u[2] >= 0.0);
        if let Some(Edge::Bound { level, .. }) = c.edge {
            on_bound += 1;
            assert!((c.point.u[0] - level).abs() < 1e-6);
        }
    }
    // The cut x = 1/2 across the upper hemisphere is an arc of length
    // 2 asin... = pi sqrt(3)/2 ~ 2.72: about 27 radii.
    assert!(on_bound >= 15, "{on_bound}");
    // A start outside the bounds is refused.
    let (mut s, u0) = surface();
    let outside = AtlasSettings::default().bound(ParamId(0), 0.5, 0.9);
    assert!(atlas::cover(&mut s, "outside", &u0, [3, 4], &outside, &mut Silent).is_err());
}

/// The observer hears every chart once, in order; bad settings, a start of the wrong length
/// and a problem that is not two-dimensional are typed errors naming the bad value.
#[test]
fn observers_and_misuse() {
    struct Count(usize);
    impl hycont_continuation::Observer for Count {
        fn chart(&mut self, _: &atlas::AtlasChart, count: usize) {
            self.0 += 1;
            assert_eq!(count, self.0);
        }
    }
    let (mut s, u0) = surface();
    let mut count = Count(0);
    let settings = AtlasSettings::default().radii(0.2, 1e-3, 0.2);
    let a = atlas::cover(&mut s, "cap", &u0, [3, 4], &settings, &mut count).unwrap();
    assert_eq!(count.0, a.charts.len());
    let bad = [
        AtlasSettings::default().radii(0.5, 1e-3, 0.2),
        AtlasSettings::default().radii(0.1, 0.0, 0.2),
        AtlasSettings {
            growth: 0.5,
            ..AtlasSettings::default()
        },
        AtlasSettings::default().max_charts(0),
        AtlasSettings::default().bound(ParamId(0), 1.0, f64::NAN),
        AtlasSettings {
            max_angle: 2.0,
            ..AtlasSettings::default()
        },
    ];
    for settings in bad {
        let (mut s, u0) = surface();
        let e = atlas::cover(&mut s, "bad", &u0, [3, 4], &settings, &mut Silent).unwrap_err();
        assert!(
            matches!(e, hycont_continuation::Error::InvalidSetting { .. }),
            "{e}"
        );
    }
    let (mut s, u0) = surface();
    assert!(atlas::cover(&mut s, "short", &u0[..4], [3, 4], &settings, &mut Silent).is_err());
    assert!(atlas::cover(&mut s, "same", &u0, [3, 3], &settings, &mut Silent).is_err());
    // One active monitor only: a one-dimensional problem.
    let mut problem = Problem::new(3);
    problem.add_part(Box::new(Sphere), vec![0, 1, 2]).unwrap();
    problem
        .add_monitor(
            "x",
            Box::new(UnknownMonitor),
            vec![0],
            Activity::Active(0.0),
        )
        .unwrap();
    let mut line = Surface { problem };
    let e = atlas::cover(
        &mut line,
        "1d",
        &[0.0, 0.0, 1.0, 0.0],
        [3, 2],
        &settings,
        &mut Silent,
    );
    assert!(e.is_err());
}
