//! Small vector helpers and the predictors of PALC: the generic direction, orientation, and the
//! Hermite interpolant of charts as a graph over a tangent line (stepping and location).

pub(super) use hycont_core::linalg::max_norm as max_abs;

/// $\sum_i a_i b_i$ in four interleaved partial sums (independent additions: the vectors
/// have as many entries as the problem has unknowns).
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut s = [0.0f64; 4];
    let (ca, cb) = (a.chunks_exact(4), b.chunks_exact(4));
    let tail: f64 = ca
        .remainder()
        .iter()
        .zip(cb.remainder())
        .map(|(x, y)| x * y)
        .sum();
    for (x, y) in ca.zip(cb) {
        for l in 0..4 {
            s[l] += x[l] * y[l];
        }
    }
    (s[0] + s[1]) + (s[2] + s[3]) + tail
}

/// `u += du`, returning the new `max_abs(u)` (the same value, from the same pass).
pub(super) fn add_with_max(u: &mut [f64], du: &[f64]) -> f64 {
    let mut lanes = [0.0_f64; 4];
    let more = |l: &mut f64, x: f64| {
        let y = x.abs();
        *l = if y > *l { y } else { *l };
    };
    let mut cu = u.chunks_exact_mut(4);
    let mut cd = du.chunks_exact(4);
    for (x, d) in (&mut cu).zip(&mut cd) {
        for ((l, xi), di) in lanes.iter_mut().zip(x).zip(d) {
            *xi += di;
            more(l, *xi);
        }
    }
    for (xi, di) in cu.into_remainder().iter_mut().zip(cd.remainder()) {
        *xi += di;
        more(&mut lanes[0], *xi);
    }
    lanes
        .into_iter()
        .fold(0.0, |s, l| if l > s { l } else { s })
}

/// `max_abs(x - y)` over the common length, without forming the difference (the same value: the
/// maximum is exact, in any order).
pub(super) fn max_abs_diff(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len().min(y.len());
    let (cx, cy) = (x[..n].chunks_exact(4), y[..n].chunks_exact(4));
    let (tx, ty) = (cx.remainder(), cy.remainder());
    let more = |m: &mut f64, d: f64| *m = if d > *m { d } else { *m };
    let mut lanes = [0.0f64; 4];
    for (a, b) in cx.zip(cy) {
        for l in 0..4 {
            more(&mut lanes[l], (a[l] - b[l]).abs());
        }
    }
    for (a, b) in tx.iter().zip(ty) {
        more(&mut lanes[0], (a - b).abs());
    }
    lanes
        .into_iter()
        .fold(0.0, |s, l| if l > s { l } else { s })
}

/// A fixed, generic unit vector of length `n`.
pub(super) fn generic(n: usize) -> Vec<f64> {
    let mut v: Vec<f64> = (0..n)
        .map(|i| ((i as f64 + 1.0) * 0.618_033_988_7).fract() - 0.5)
        .collect();
    let norm = dot(&v, &v).sqrt();
    v.iter_mut().for_each(|x| *x /= norm);
    v
}

/// The sign that says which way a tangent `t` goes: its parameter component, or, where that
/// vanishes (to `1e-9`), its component along a fixed generic vector, so that the two ways from
/// a start are always opposite.
pub(super) fn orientation(t: &[f64], pi: usize) -> f64 {
    if t[pi].abs() > 1e-9 {
        t[pi]
    } else {
        dot(t, &generic(t.len()))
    }
}

/// A chart seen from the tangent line of the current chart $(u_a, t_a)$: its coordinate
/// $\sigma = \langle t_a, u - u_a \rangle_W$ along the line, its point $u$ and tangent $t$, and
/// $\langle t_a, t \rangle_W$: the branch's slope there as a graph over the line is
/// $du/d\sigma = t / \langle t_a, t \rangle_W$.
pub(super) struct GraphNode<'c> {
    pub(super) sigma: f64,
    pub(super) u: &'c [f64],
    pub(super) t: &'c [f64],
    pub(super) along: f64,
}

/// The Hermite interpolant of the branch as a graph over a chart's tangent line, through
/// `nodes` (values and slopes at distinct coordinates), at coordinate `x`: the predictor on the
/// corrector's hyperplane $\sigma = x$ of that chart.
///
/// In this coordinate the data are exact (every chart's $\sigma$ and slope are computed, not
/// estimated from step lengths), so $k$ charts give an error $O(h^{2k})$ in their spacing $h$:
/// a step from the current chart with the two charts before it, $O(h^6)$, against the $O(h^2)$
/// of the tangent predictor; a location between two charts, $O(w^4)$ in the bracket's width.
/// The interpolant's $\sigma$-component is the line itself (every slope has $\sigma$-component
/// 1), so the predictor lies on the hyperplane.
///
/// A component with the same value and zero slope at every node (an unknown held by a
/// monitor) is that value exactly: the interpolant of constant data is the constant, which the
/// weights' rounding would move by an ulp (and the corrector would then correct it back,
/// through every equation that reads it).
pub(super) fn hermite_graph(nodes: &[GraphNode<'_>], x: f64) -> Vec<f64> {
    let weights = hermite_weights(&nodes.iter().map(|nd| nd.sigma).collect::<Vec<_>>(), x);
    let mut p = vec![0.0; nodes.first().map_or(0, |nd| nd.u.len())];
    for (nd, (wv, ws)) in nodes.iter().zip(&weights) {
        let ws = ws / nd.along;
        for ((pi, u), t) in p.iter_mut().zip(nd.u).zip(nd.t) {
            *pi += wv * u + ws * t;
        }
    }
    if let Some((first, rest)) = nodes.split_first() {
        for (i, pi) in p.iter_mut().enumerate() {
            let v = first.u[i];
            if first.t[i] == 0.0 && rest.iter().all(|nd| nd.u[i] == v && nd.t[i] == 0.0) {
                *pi = v;
            }
        }
    }
    p
}

/// The Hermite basis at `x` for nodes `z` (distinct): per node, the weights of its value and
/// of its slope in the interpolant of degree `2 z.len() - 1`. Each is the interpolant of unit
/// data, by Newton's divided differences on the doubled nodes.
fn hermite_weights(z: &[f64], x: f64) -> Vec<(f64, f64)> {
    let m = 2 * z.len();
    let at = |j: usize| z[j / 2];
    // The divided differences' work space, for every unit datum in turn.
    let (mut level, mut coef) = (vec![0.0; m], Vec::with_capacity(m));
    // The interpolant of unit data: value (`slope == false`) or slope 1 at `node`, 0 elsewhere.
    let mut unit = |node: usize, slope: bool| {
        let one =
            |j: usize, of_slope: bool| f64::from(u8::from(j / 2 == node && slope == of_slope));
        for (j, v) in level.iter_mut().enumerate() {
            *v = one(j, false);
        }
        coef.clear();
        coef.push(level[0]);
        for l in 1..m {
            for j in 0..m - l {
                // At l = 1 an even j pairs a node with itself: the slope datum.
                level[j] = if l == 1 && j.is_multiple_of(2) {
                    one(j, true)
                } else {
                    (level[j + 1] - level[j]) / (at(j + l) - at(j))
                };
            }
            coef.push(level[0]);
        }
        (0..m).rev().fold(0.0, |p, l| coef[l] + (x - at(l)) * p)
    };
    (0..z.len())
        .map(|i| (unit(i, false), unit(i, true)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::{GraphNode, hermite_graph, hermite_weights};

    /// `add_with_max` adds as a loop does and returns `max_abs` of the sum, for every length
    /// and remainder, NaNs among the entries (ignored by the maximum, as by `max_abs`); and
    /// `max_abs_diff` is `max_abs` of the difference.
    #[test]
    fn add_with_max_is_the_sum_and_its_max_abs() {
        for len in 0..11 {
            let u: Vec<f64> = (0..len).map(|i| (i as f64 * 0.37).sin() * 3.0).collect();
            let mut du: Vec<f64> = (0..len).map(|i| (i as f64 * 1.3).cos()).collect();
            if len > 5 {
                du[len / 2] = f64::NAN;
            }
            let difference: Vec<f64> = u.iter().zip(&du).map(|(x, d)| x - d).collect();
            let max_diff = super::max_abs_diff(&u, &du);
            assert_eq!(max_diff.to_bits(), super::max_abs(&difference).to_bits());
            let mut fused = u.clone();
            let max = super::add_with_max(&mut fused, &du);
            let sum: Vec<f64> = u.iter().zip(&du).map(|(x, d)| x + d).collect();
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&fused), bits(&sum));
            assert_eq!(max.to_bits(), super::max_abs(&sum).to_bits());
        }
    }

    /// $p(\sigma) = \sum_{j \le d} c_j \sigma^j$ and $p'(\sigma)$.
    fn poly(c: &[f64], x: f64) -> (f64, f64) {
        let value = c.iter().rev().fold(0.0, |p, cj| cj + x * p);
        let slope = (1..c.len()).rev().fold(0.0, |p, j| j as f64 * c[j] + x * p);
        (value, slope)
    }

    /// Hermite interpolation on $k$ nodes is exact for polynomials of degree $2k - 1$ (the
    /// interpolant is unique in that space) and not for degree $2k$: at $x$ the error of
    /// $\sigma^{2k}$ is $\prod_i (x - z_i)^2$ (the interpolant of $\sigma^{2k}$ is $\sigma^{2k}$
    /// minus the monic polynomial with the doubled nodes as roots).
    #[test]
    fn weights_reproduce_polynomials_of_degree_two_k_minus_one() {
        let z = [0.0, -0.7, -1.5];
        let x = 0.4;
        let w = hermite_weights(&z, x);
        let interpolate = |c: &[f64]| -> f64 {
            z.iter()
                .zip(&w)
                .map(|(&zi, &(wv, ws))| {
                    let (v, s) = poly(c, zi);
                    wv * v + ws * s
                })
                .sum()
        };
        let c5 = [0.3, -1.2, 0.8, 2.0, -0.5, 0.25];
        approx::assert_abs_diff_eq!(interpolate(&c5), poly(&c5, x).0, epsilon = 1e-12);
        let mut c6 = [0.0; 7];
        c6[6] = 1.0;
        let want: f64 = z.iter().map(|zi| (x - zi) * (x - zi)).product();
        approx::assert_relative_eq!(
            poly(&c6, x).0 - interpolate(&c6),
            want,
            max_relative = 1e-10
        );
        assert!(want > 1e-3, "the degree-6 error is not zero: {want}");
    }

    /// Extrapolation one spacing beyond three nodes converges as $h^6$: on
    /// $u(\sigma) = (\sigma, e^\sigma, \cos(\sigma + 1/2))$ (a graph over its first coordinate:
    /// tangent line $e_1$, slopes $u'$ with $\sigma$-component 1) from nodes $0, -h, -2h$ to
    /// $\sigma = h$ the error is $u^{(6)}(\xi) / 6! \cdot h^2 (2h)^2 (3h)^2$, both sixth
    /// derivatives nonzero near 0, so halving $h$ divides it by about $2^6 = 64$; the
    /// predictor's first component is $h$ (on the hyperplane).
    #[test]
    fn step_predictor_converges_to_sixth_order() {
        let curve = |s: f64| [s, s.exp(), (s + 0.5).cos()];
        let slope = |s: f64| [1.0, s.exp(), -(s + 0.5).sin()];
        let error = |h: f64| {
            let (us, ts): (Vec<_>, Vec<_>) = [0.0, -h, -2.0 * h]
                .iter()
                .map(|&s| (curve(s), slope(s)))
                .unzip();
            let nodes: Vec<GraphNode<'_>> = (0..3)
                .map(|i| GraphNode {
                    sigma: -(i as f64) * h,
                    u: &us[i],
                    t: &ts[i],
                    along: 1.0,
                })
                .collect();
            let p = hermite_graph(&nodes, h);
            approx::assert_abs_diff_eq!(p[0], h, epsilon = 1e-15);
            let want = curve(h);
            (1..3).map(|i| (p[i] - want[i]).abs()).fold(0.0, f64::max)
        };
        let (e1, e2) = (error(0.1), error(0.05));
        let order = (e1 / e2).log2();
        assert!(
            (5.7..6.3).contains(&order),
            "order {order} ({e1:e}, {e2:e})"
        );
    }

    /// Slopes are tangents over $\langle t_a, t \rangle_W$: on the unit circle seen from the
    /// tangent line at angle 0 (coordinate $\sigma = \sin\theta$, graph
    /// $y = \sqrt{1 - \sigma^2}$, whose sixth derivative is $-45$ at 0), nodes at
    /// $\theta = 0, -0.05, -0.1$ with unit tangents $(\cos\theta, -\sin\theta)$ interpolate the graph
    /// to its error bound $|y^{(6)}| / 6! \prod_i (x - \sigma_i)^2$ (taken with a factor 2 for
    /// $\xi \ne 0$); unit tangents used as slopes (without the scaling) miss it by far. With one
    /// node the predictor is the tangent step itself.
    #[test]
    fn unit_tangents_are_scaled_to_graph_slopes() {
        let point = |th: f64| [th.sin(), th.cos()];
        let tangent = |th: f64| [th.cos(), -th.sin()];
        let angles = [0.0, -0.05, -0.1];
        let (us, ts): (Vec<_>, Vec<_>) = angles.iter().map(|&a| (point(a), tangent(a))).unzip();
        let x = 0.05;
        let bound =
            2.0 * 45.0 / 720.0 * us.iter().map(|u| (x - u[0]) * (x - u[0])).product::<f64>();
        let error = |scaled: bool| {
            let nodes: Vec<GraphNode<'_>> = (0..3)
                .map(|i| GraphNode {
                    sigma: us[i][0],
                    u: &us[i],
                    t: &ts[i],
                    along: if scaled { ts[i][0] } else { 1.0 },
                })
                .collect();
            let p = hermite_graph(&nodes, x);
            if scaled {
                approx::assert_abs_diff_eq!(p[0], x, epsilon = 1e-15);
            }
            (p[1] - (1.0 - x * x).sqrt()).abs()
        };
        assert!(error(true) <= bound, "{} > {bound}", error(true));
        assert!(
            error(false) > 10.0 * bound,
            "{} <= 10 x {bound}",
            error(false)
        );
        let one = GraphNode {
            sigma: 0.0,
            u: &us[0],
            t: &ts[0],
            along: 1.0,
        };
        assert_eq!(hermite_graph(&[one], x), vec![x, 1.0]);
    }

    /// A component with one value and zero slopes at every node (an unknown a monitor holds) is
    /// predicted as that value to the bit, on uneven nodes and at points inside and outside
    /// them, where the weights' sum is 1 only to rounding; the other components interpolate.
    #[test]
    fn held_components_are_predicted_exactly() {
        let sigmas = [0.0, -0.093, -0.2117];
        let held = [0.8795, 2.2e-4, -3.7];
        let us: Vec<Vec<f64>> = sigmas
            .iter()
            .map(|&s| [vec![s, s * s], held.to_vec()].concat())
            .collect();
        let ts: Vec<Vec<f64>> = sigmas
            .iter()
            .map(|&s| vec![1.0, 2.0 * s, 0.0, 0.0, 0.0])
            .collect();
        let nodes: Vec<GraphNode<'_>> = (0..3)
            .map(|i| GraphNode {
                sigma: sigmas[i],
                u: &us[i],
                t: &ts[i],
                along: 1.0,
            })
            .collect();
        let mut moved = 0;
        for k in 1..40 {
            let x = 0.0123 * f64::from(k) - 0.25;
            let p = hermite_graph(&nodes, x);
            approx::assert_abs_diff_eq!(p[1], x * x, epsilon = 1e-14);
            for (i, v) in held.iter().enumerate() {
                assert_eq!(
                    p[2 + i].to_bits(),
                    v.to_bits(),
                    "x = {x}: {} for {v}",
                    p[2 + i]
                );
            }
            // The same sums without the held components' rule.
            let weights = hermite_weights(&sigmas, x);
            let sum: f64 = weights.iter().map(|(wv, _)| wv * held[0]).sum();
            moved += usize::from(sum != held[0]);
        }
        assert!(
            moved > 0,
            "the weights sum to 1 exactly at every x: nothing tested"
        );
    }
}
