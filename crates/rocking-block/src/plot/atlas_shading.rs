//! The atlas's shading: Amp interpolated linearly between the chart centres over the Delaunay
//! triangles of the centres, where the charts' polygons cover the plane. Flat-shaded polygons
//! (a colour per chart) show a saw-tooth mosaic where Amp changes across a chart; the
//! interpolation is exact for a field linear in (omega, alpha) and continuous across charts.

use delaunator::{Point, triangulate};

/// A sheet's shading: the centres (in coordinates scaled to the window), their values, the
/// triangles kept, the charts' polygons, and a bucket grid of both for lookups.
pub(super) struct Shading {
    centres: Vec<(f64, f64)>,
    values: Vec<f64>,
    triangles: Vec<[usize; 3]>,
    polygons: Vec<Vec<(f64, f64)>>,
    /// Which triangles and polygons touch each bucket (`BUCKETS` x `BUCKETS` over [0, 1]^2).
    tri_in: Vec<Vec<usize>>,
    poly_in: Vec<Vec<usize>>,
    /// The window `[(x0, x1), (y0, y1)]` scaled to [0, 1]^2.
    window: [(f64, f64); 2],
}

const BUCKETS: usize = 64;

/// Triangles with an edge longer than this many times the median edge are not interpolated
/// over (they would join charts across a gap of the sheet); their points keep their chart's
/// value.
const LONGEST: f64 = 4.0;

impl Shading {
    /// The shading of charts with centres `centres`, values `values` and polygons `polygons`
    /// (in the plane's coordinates) over `window`.
    pub(super) fn new(
        centres: &[(f64, f64)],
        values: &[f64],
        polygons: &[Vec<(f64, f64)>],
        window: [(f64, f64); 2],
    ) -> Self {
        let scale = |(x, y): (f64, f64)| {
            let [(x0, x1), (y0, y1)] = window;
            ((x - x0) / (x1 - x0), (y - y0) / (y1 - y0))
        };
        let centres: Vec<(f64, f64)> = centres.iter().map(|&c| scale(c)).collect();
        let polygons: Vec<Vec<(f64, f64)>> = (polygons.iter())
            .map(|p| p.iter().map(|&v| scale(v)).collect())
            .collect();
        let points: Vec<Point> = centres.iter().map(|&(x, y)| Point { x, y }).collect();
        let all: Vec<[usize; 3]> = triangulate(&points)
            .triangles
            .chunks_exact(3)
            .map(|t| [t[0], t[1], t[2]])
            .collect();
        let longest = |t: &[usize; 3]| {
            (0..3)
                .map(|k| dist(centres[t[k]], centres[t[(k + 1) % 3]]))
                .fold(0.0, f64::max)
        };
        let mut edges: Vec<f64> = all.iter().map(longest).collect();
        edges.sort_by(f64::total_cmp);
        let median = edges.get(edges.len() / 2).copied().unwrap_or(0.0);
        let triangles: Vec<[usize; 3]> = (all.into_iter())
            .filter(|t| longest(t) <= LONGEST * median)
            .collect();
        let tri_in = buckets(triangles.iter().map(|t| t.map(|k| centres[k]).to_vec()));
        let poly_in = buckets(polygons.iter().cloned());
        Shading {
            centres,
            values: values.to_vec(),
            triangles,
            polygons,
            tri_in,
            poly_in,
            window,
        }
    }

    /// The value at `(x, y)` (the plane's coordinates): interpolated in the kept Delaunay
    /// triangle around it (between the centres of neighbouring charts: inside the sheet, also
    /// over the hairline gaps the charts' polygons leave between them), else its chart's
    /// value (the rim of the sheet beyond the outer centres); `None` where neither covers it.
    pub(super) fn value_at(&self, x: f64, y: f64) -> Option<f64> {
        let [(x0, x1), (y0, y1)] = self.window;
        let p = ((x - x0) / (x1 - x0), (y - y0) / (y1 - y0));
        let bucket = bucket_of(p)?;
        for &t in &self.tri_in[bucket] {
            let [a, b, c] = self.triangles[t].map(|k| self.centres[k]);
            if let Some(w) = barycentric(p, a, b, c) {
                let v = self.triangles[t].map(|k| self.values[k]);
                return Some(w[0] * v[0] + w[1] * v[1] + w[2] * v[2]);
            }
        }
        let chart = (self.poly_in[bucket].iter()).find(|&&k| inside(&self.polygons[k], p))?;
        Some(self.values[*chart])
    }
}

fn dist(a: (f64, f64), b: (f64, f64)) -> f64 {
    (a.0 - b.0).hypot(a.1 - b.1)
}

fn bucket_of((x, y): (f64, f64)) -> Option<usize> {
    let at = |v: f64| ((v * BUCKETS as f64).floor() as i64).clamp(-1, BUCKETS as i64);
    let (i, j) = (at(x), at(y));
    let ok = |k: i64| (0..BUCKETS as i64).contains(&k);
    (ok(i) && ok(j)).then(|| (i as usize) * BUCKETS + j as usize)
}

/// For each bucket, the shapes (by index) whose bounding box meets it.
fn buckets(shapes: impl Iterator<Item = Vec<(f64, f64)>>) -> Vec<Vec<usize>> {
    let mut out = vec![Vec::new(); BUCKETS * BUCKETS];
    let cell = |v: f64| ((v * BUCKETS as f64).floor().max(0.0) as usize).min(BUCKETS - 1);
    for (k, shape) in shapes.enumerate() {
        let (lo, hi) = shape.iter().fold(
            (
                (f64::INFINITY, f64::INFINITY),
                (f64::NEG_INFINITY, f64::NEG_INFINITY),
            ),
            |(lo, hi), &(x, y)| ((lo.0.min(x), lo.1.min(y)), (hi.0.max(x), hi.1.max(y))),
        );
        if !(lo.0.is_finite() && hi.0.is_finite() && lo.1.is_finite() && hi.1.is_finite()) {
            continue;
        }
        for i in cell(lo.0)..=cell(hi.0) {
            for j in cell(lo.1)..=cell(hi.1) {
                out[i * BUCKETS + j].push(k);
            }
        }
    }
    out
}

/// Whether `p` is inside the convex polygon `poly` (either orientation; edges included).
fn inside(poly: &[(f64, f64)], p: (f64, f64)) -> bool {
    if poly.len() < 3 {
        return false;
    }
    let cross =
        |a: (f64, f64), b: (f64, f64)| (b.0 - a.0) * (p.1 - a.1) - (b.1 - a.1) * (p.0 - a.0);
    let signs = (0..poly.len()).map(|k| cross(poly[k], poly[(k + 1) % poly.len()]));
    let (mut pos, mut neg) = (false, false);
    for s in signs {
        pos |= s > 0.0;
        neg |= s < 0.0;
    }
    !(pos && neg)
}

/// The barycentric weights of `p` in the triangle `(a, b, c)`, if it lies inside (edges
/// included) and the triangle is not degenerate.
fn barycentric(p: (f64, f64), a: (f64, f64), b: (f64, f64), c: (f64, f64)) -> Option<[f64; 3]> {
    let det = (b.1 - c.1) * (a.0 - c.0) + (c.0 - b.0) * (a.1 - c.1);
    if det.abs() < 1e-300 {
        return None;
    }
    let wa = ((b.1 - c.1) * (p.0 - c.0) + (c.0 - b.0) * (p.1 - c.1)) / det;
    let wb = ((c.1 - a.1) * (p.0 - c.0) + (a.0 - c.0) * (p.1 - c.1)) / det;
    let wc = 1.0 - wa - wb;
    let tol = -1e-12;
    (wa >= tol && wb >= tol && wc >= tol).then_some([wa, wb, wc])
}

#[cfg(test)]
mod tests {
    use super::Shading;

    /// Charts: squares of side 0.1 centred on a grid over [0, 1]^2 (every point covered),
    /// values of the linear field `f = 2 + 3x - y`. Barycentric interpolation reproduces a
    /// linear field exactly inside the hull of the centres; beyond it (a rim of half a square)
    /// a point keeps its chart's value, within `|grad f| * 0.05 * sqrt(2)` of the field.
    #[test]
    fn a_linear_field_is_reproduced_and_uncovered_points_are_blank() {
        let f = |x: f64, y: f64| 2.0 + 3.0 * x - y;
        let (mut centres, mut values, mut polygons) = (vec![], vec![], vec![]);
        for i in 0..10 {
            for j in 0..10 {
                let (x, y) = (0.05 + 0.1 * f64::from(i), 0.05 + 0.1 * f64::from(j));
                centres.push((x, y));
                values.push(f(x, y));
                let h = 0.05;
                polygons.push(vec![
                    (x - h, y - h),
                    (x + h, y - h),
                    (x + h, y + h),
                    (x - h, y + h),
                ]);
            }
        }
        // Only the bottom-left three quarters are charted: the rest is blank.
        let keep: Vec<usize> = (0..100).filter(|k| !(k / 10 >= 5 && k % 10 >= 5)).collect();
        let kept_centres: Vec<(f64, f64)> = keep.iter().map(|&k| centres[k]).collect();
        let kept_values: Vec<f64> = keep.iter().map(|&k| values[k]).collect();
        let polys: Vec<_> = keep.iter().map(|&k| polygons[k].clone()).collect();
        let s = Shading::new(
            &kept_centres,
            &kept_values,
            &polys,
            [(0.0, 1.0), (0.0, 1.0)],
        );
        for (x, y) in [(0.3, 0.3), (0.123, 0.456), (0.44, 0.9), (0.9, 0.2)] {
            let v = s.value_at(x, y).expect("covered");
            approx::assert_abs_diff_eq!(v, f(x, y), epsilon = 1e-12);
        }
        for (x, y) in [(0.02, 0.5), (0.5, 0.99)] {
            let v = s.value_at(x, y).expect("covered");
            assert!((v - f(x, y)).abs() <= 10f64.sqrt() * 0.05 * 2f64.sqrt() + 1e-12);
        }
        assert_eq!(s.value_at(0.8, 0.8), None);
        assert_eq!(s.value_at(1.5, 0.5), None);
    }
}
