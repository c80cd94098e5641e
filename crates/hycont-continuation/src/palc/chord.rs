//! Chord steps from the factorisation a stepping chart left behind.
//!
//! A chart at $u_a$ is corrected on the hyperplane of the previous tangent, so the corrector
//! leaves $A = [J(u_a); r_p^\top]$ factorised, $r_p = W t_p$, and the chart's tangent is
//! $t_a \propto z = A^{-1} e_n$. The next step corrects on $r_a = W t_a$, that is with
//! $\tilde A = A + e_n v^\top$, $v = r_a - r_p$. Sherman and Morrison give its solves from $A$'s:
//! $$\tilde A^{-1} b = y - z\,\frac{v^\top y}{1 + v^\top z}, \qquad y = A^{-1} b,$$
//! exact for the new row, with the Jacobian of $u_a$: chord steps. With the predictor on the
//! hyperplane, a step's first residual is small and the chord contraction (the Jacobian's
//! change over the step) brings it to the tolerance in about two steps, where Newton needs a
//! fresh factorisation at the predictor; the corrector falls back to that when the
//! contraction is slow, and the chart at the solution is factorised exactly either way.

use super::predict::dot;

/// What a stepping chart's factorisation leaves for chord steps from it.
#[derive(Debug)]
pub(super) struct Held {
    /// The corrector's factorisation count when it was left (any later factorisation
    /// replaces it).
    pub(super) generation: u64,
    /// The factorised matrix's last row, $r_p$.
    pub(super) row: Vec<f64>,
    /// $z = A^{-1} e_n$, the chart's tangent before normalisation.
    pub(super) z: Vec<f64>,
}

/// Chord steps in progress: solves with the held factorisation, corrected for the new row.
#[derive(Debug)]
pub(super) struct Chord {
    v: Vec<f64>,
    z: Vec<f64>,
    denom: f64,
}

impl Chord {
    /// Chord steps on the hyperplane of `row` from `held`; `None` where the correction is
    /// ill-conditioned ($|1 + v^\top z| < 1/2$: the new row nearly in the old system's range;
    /// the tangents of neighbouring charts give about 1).
    pub(super) fn new(held: Held, row: &[f64]) -> Option<Self> {
        if held.row.len() != row.len() || held.z.len() != row.len() {
            return None;
        }
        let v: Vec<f64> = row.iter().zip(&held.row).map(|(a, b)| a - b).collect();
        let denom = 1.0 + dot(&v, &held.z);
        (denom.abs() >= 0.5 && denom.is_finite()).then_some(Self {
            v,
            z: held.z,
            denom,
        })
    }

    /// Turns $y = A^{-1} b$ into $\tilde A^{-1} b$ in place.
    pub(super) fn correct(&self, y: &mut [f64]) {
        let c = dot(&self.v, y) / self.denom;
        for (x, z) in y.iter_mut().zip(&self.z) {
            *x -= c * z;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{Chord, Held};

    /// On a 3 x 3 system: the corrected solve with $A$ solves $\tilde A x = b$, $\tilde A$ =
    /// $A$ with its last row replaced (checked by multiplying out), and a replacement that makes
    /// $\tilde A$ nearly singular is refused.
    #[test]
    fn corrected_solves_use_the_new_last_row() {
        // A = [[2, 1, 0], [0, 3, 1], [1, 0, 1]] (row-major), det = 7.
        let a = [[2.0, 1.0, 0.0], [0.0, 3.0, 1.0], [1.0, 0.0, 1.0]];
        let solve = |b: [f64; 3]| {
            // Cramer's rule for A.
            let det = |m: [[f64; 3]; 3]| {
                m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
                    - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
                    + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
            };
            let d = det(a);
            let mut x = [0.0; 3];
            for (j, xj) in x.iter_mut().enumerate() {
                let mut m = a;
                for i in 0..3 {
                    m[i][j] = b[i];
                }
                *xj = det(m) / d;
            }
            x
        };
        let z = solve([0.0, 0.0, 1.0]);
        let held = Held {
            generation: 0,
            row: a[2].to_vec(),
            z: z.to_vec(),
        };
        let new_row = [0.5, -1.0, 2.0];
        let chord = Chord::new(held, &new_row).expect("well conditioned");
        let b = [1.0, -2.0, 0.5];
        let mut x = solve(b).to_vec();
        chord.correct(&mut x);
        let rows = [a[0], a[1], new_row];
        for (row, bi) in rows.iter().zip(b) {
            let ax: f64 = row.iter().zip(&x).map(|(r, x)| r * x).sum();
            approx::assert_abs_diff_eq!(ax, bi, epsilon = 1e-13);
        }
        // A last row that makes the new matrix singular: [2, 4, 1] = row 0 + row 1.
        let held = Held {
            generation: 0,
            row: a[2].to_vec(),
            z: z.to_vec(),
        };
        assert!(Chord::new(held, &[2.0, 4.0, 1.0]).is_none());
    }
}
