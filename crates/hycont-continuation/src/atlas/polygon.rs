//! Convex polygons in a chart's tangent coordinates: Henderson's trimmed chart domains.

use serde::{Deserialize, Serialize};

/// A halfplane $\{ s : n \cdot s \le b \}$ of a chart's tangent coordinates.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct HalfPlane {
    /// The outward normal (need not be a unit vector).
    pub normal: [f64; 2],
    /// The offset.
    pub offset: f64,
}

impl HalfPlane {
    /// Henderson's halfplane of a chart of radius `r` against a neighbour whose centre projects
    /// to `c` with radius `rc`: the side of the radical line of the two discs that holds the
    /// chart's centre, $c \cdot s \le (|c|^2 + r^2 - r_c^2)/2$.
    #[must_use]
    pub fn against(c: [f64; 2], r: f64, rc: f64) -> Self {
        Self {
            normal: c,
            offset: 0.5 * (c[0] * c[0] + c[1] * c[1] + r * r - rc * rc),
        }
    }

    fn value(&self, v: [f64; 2]) -> f64 {
        self.normal[0] * v[0] + self.normal[1] * v[1] - self.offset
    }
}

/// The regular polygon with `sides` vertices circumscribing the circle of radius `r`,
/// counter-clockwise.
#[must_use]
pub fn circumscribed(r: f64, sides: usize) -> Vec<[f64; 2]> {
    let step = std::f64::consts::TAU / sides as f64;
    let reach = r / (0.5 * step).cos();
    (0..sides)
        .map(|k| {
            let a = step * k as f64;
            [reach * a.cos(), reach * a.sin()]
        })
        .collect()
}

/// Clips a convex polygon by a halfplane (Sutherland and Hodgman's step): the part of `poly`
/// with `h.value <= 0`.
#[must_use]
pub fn clip(poly: &[[f64; 2]], h: &HalfPlane) -> Vec<[f64; 2]> {
    let mut out = Vec::with_capacity(poly.len() + 1);
    for (i, &a) in poly.iter().enumerate() {
        let b = poly[(i + 1) % poly.len()];
        let (fa, fb) = (h.value(a), h.value(b));
        if fa <= 0.0 {
            out.push(a);
        }
        if (fa < 0.0 && fb > 0.0) || (fa > 0.0 && fb < 0.0) {
            let t = fa / (fa - fb);
            out.push([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]);
        }
    }
    out
}

/// The vertex of `poly` farthest outside the circle of radius `r` (by more than `slack`
/// relative), if any: where a chart's domain is not yet covered.
#[must_use]
pub fn outside_vertex(poly: &[[f64; 2]], r: f64, slack: f64) -> Option<[f64; 2]> {
    poly.iter()
        .copied()
        .map(|v| (v, v[0].hypot(v[1])))
        .filter(|&(_, d)| d > r * (1.0 + slack))
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(v, _)| v)
}

/// Area of a polygon (shoelace formula; positive counter-clockwise).
#[cfg(test)]
fn area(poly: &[[f64; 2]]) -> f64 {
    let n = poly.len();
    0.5 * (0..n)
        .map(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            a[0] * b[1] - a[1] * b[0]
        })
        .sum::<f64>()
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_abs_diff_eq;

    /// The circumscribed octagon of the unit circle has area $8 \tan(\pi/8)$; cut by the
    /// bisector of a neighbour at distance 1 on the x axis it keeps the part $x \le 1/2$,
    /// whose only vertices outside the unit circle are on the far side.
    #[test]
    fn clipping_an_octagon_by_a_neighbour() {
        let p = circumscribed(1.0, 8);
        let tan = (std::f64::consts::PI / 8.0).tan();
        assert_abs_diff_eq!(area(&p), 8.0 * tan, epsilon = 1e-12);
        let q = clip(&p, &HalfPlane::against([1.0, 0.0], 1.0, 1.0));
        assert!(q.iter().all(|v| v[0] <= 0.5 + 1e-12));
        // The square [-1, 1]^2 cut at x = 1/2 keeps [-1, 1/2] x [-1, 1]: area 3.
        let square = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];
        let cut = clip(&square, &HalfPlane::against([1.0, 0.0], 1.0, 1.0));
        assert_abs_diff_eq!(area(&cut), 3.0, epsilon = 1e-12);
        // Unequal radii move the line: r = 1, rc = 0.5 at distance 1: x <= (1 + 1 - 0.25)/2.
        let cut = clip(&square, &HalfPlane::against([1.0, 0.0], 1.0, 0.5));
        assert_abs_diff_eq!(area(&cut), 2.0 * (1.0 + 0.875), epsilon = 1e-12);
        let far = outside_vertex(&q, 1.0, 1e-9).expect("the far side is open");
        assert!(far[0] < 0.0);
        // A full ring of six neighbours at distance 1 closes the chart (the hexagon of
        // bisectors lies inside the unit circle).
        let mut r = circumscribed(1.0, 8);
        for k in 0..6 {
            let a = std::f64::consts::TAU * k as f64 / 6.0;
            r = clip(&r, &HalfPlane::against([a.cos(), a.sin()], 1.0, 1.0));
        }
        assert!(outside_vertex(&r, 1.0, 1e-9).is_none());
        // The hexagon with inradius 1/2: area 6 (1/2)^2 tan(30 deg) ... = sqrt(3)/2.
        assert_abs_diff_eq!(area(&r), 3f64.sqrt() / 2.0, epsilon = 1e-12);
    }
}
