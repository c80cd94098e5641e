//! The unit sphere $x^2 + y^2 + z^2 = 1$ with $x$ and $y$ free (monitors of the first two
//! unknowns): the atlas tests' two-dimensional problem (`atlas_sphere.rs` derives what its
//! atlases are).
#![allow(dead_code)] // each test file uses part of it

use hycont_continuation::{ContinuationProblem, PointInfo};
use hycont_core::problem::{Activity, Problem, UnknownMonitor, ZeroFunction};

/// $x^2 + y^2 + z^2 - 1$.
pub struct Sphere;

impl ZeroFunction for Sphere {
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
        r[0] = u[0] * u[0] + u[1] * u[1] + u[2] * u[2] - 1.0;
        if let Some(j) = j {
            for k in 0..3 {
                j[k] = 2.0 * u[k];
            }
        }
        Ok(())
    }
}

pub struct Surface {
    pub problem: Problem<'static>,
}

impl ContinuationProblem<'static> for Surface {
    fn problem(&mut self) -> &mut Problem<'static> {
        &mut self.problem
    }
    fn parameter_index(&self) -> usize {
        3
    }
    fn parameter_position(&self) -> usize {
        0
    }
    fn parameter_name(&self) -> String {
        "x".into()
    }
    fn parameter_names(&self) -> Vec<String> {
        vec!["x".into(), "y".into()]
    }
    fn monitor_names(&self) -> Vec<String> {
        vec!["z".into()]
    }
    /// The parameters' unknowns repeat x and y: weighed (almost) nothing, the arclength is
    /// the sphere's own.
    fn unknown_weights(&self) -> Option<Vec<f64>> {
        Some(vec![1.0, 1.0, 1.0, 1e-12, 1e-12])
    }
    fn analyse(&mut self, u: &[f64]) -> hycont_core::Result<PointInfo> {
        Ok(PointInfo {
            params: vec![u[3], u[4]],
            monitors: vec![u[2]],
            ..PointInfo::default()
        })
    }
}

/// The sphere with `x` and `y` free, and the start near the north pole.
pub fn surface() -> (Surface, Vec<f64>) {
    let mut problem = Problem::new(3);
    problem.add_part(Box::new(Sphere), vec![0, 1, 2]).unwrap();
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
    let (x, y): (f64, f64) = (0.1, 0.05);
    let z = (1.0 - x * x - y * y).sqrt();
    // Unknowns: x, y, z, and the monitors' values x and y (the start is a little off).
    (Surface { problem }, vec![x, y, z + 1e-3, x, y])
}
