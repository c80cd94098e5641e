// The model of the `impact_chain` example (shared with `tests/integration/impact_chain.rs` and
// `benches/impact_chain.rs`): a chain of `N` unit masses, each joined to the next (the first
// to a fixed base) by a spring `k` and a dashpot `c`, the first forced by `A sin(w t)`, the
// last striking a rigid stop at `x_N = d` with restitution `e` (`v_N -> -e v_N`). A linear
// flight and one impact: the scalable test system with an exact reference
// (`reference.rs`).
//
// State `(x_1..x_N, v_1..v_N, r, s)`, `n = 2N + 2`: displacements, velocities and the forcing
// oscillator `r' = r + w s - r (r^2 + s^2)`, `s' = s - w r - s (r^2 + s^2)` (limit cycle
// `(r, s) = (sin(w t + beta), cos(w t + beta))`). Flight: `x' = v`,
// `v' = -k L x - c L v + A r e_1`, with `L` the chain's stiffness pattern (tridiagonal,
// 2 on the diagonal but 1 at the free end, -1 beside it). One mode; the event IMPACT
// (`d - x_N` falls through 0). Parameters `(k, c, A, w, d, e)`.

use hycont::{
    Direction, EventAction, EventId, EventSpec, HybridJacobians, HybridSystem, Mode, ParamId,
};

/// The forcing frequency `w`.
pub const W: ParamId = ParamId(3);
pub const FREE: Mode = Mode(0);
pub const IMPACT: EventId = EventId(0);

/// A chain of `masses` masses.
#[derive(Debug, Clone, Copy)]
pub struct ImpactChain {
    pub masses: usize,
}

impl ImpactChain {
    /// `(L x)_i`: the stiffness pattern applied to `x`.
    pub fn stiffness(&self, x: &[f64], i: usize) -> f64 {
        let n = self.masses;
        let mut y = x[i];
        if i + 1 < n {
            y += x[i] - x[i + 1];
        }
        if i > 0 {
            y -= x[i - 1];
        }
        y
    }

    /// `L[i][j]` (nonzero for `|i - j| <= 1`).
    pub fn pattern(&self, i: usize, j: usize) -> f64 {
        let n = self.masses;
        match i.abs_diff(j) {
            0 if i + 1 < n => 2.0,
            0 => 1.0,
            1 => -1.0,
            _ => 0.0,
        }
    }

    /// The state's dimension `2N + 2`.
    pub fn dim(&self) -> usize {
        2 * self.masses + 2
    }
}

impl HybridSystem for ImpactChain {
    fn state_dim(&self) -> usize {
        self.dim()
    }
    fn parameter_names(&self) -> &[&'static str] {
        &["k", "c", "A", "w", "d", "e"]
    }
    fn mode_count(&self) -> usize {
        1
    }
    fn mode_name(&self, _: Mode) -> &'static str {
        "flight"
    }
    fn events(&self, _: Mode) -> &[EventId] {
        &[IMPACT]
    }
    fn event_spec(&self, _: EventId) -> EventSpec {
        EventSpec {
            name: "impact",
            direction: Direction::Falling,
            action: EventAction::Jump { to: FREE },
        }
    }
    fn vector_field(&self, _: Mode, x: &[f64], p: &[f64], f: &mut [f64]) {
        let n = self.masses;
        let (pos, vel) = x[..2 * n].split_at(n);
        let (r, s) = (x[2 * n], x[2 * n + 1]);
        for i in 0..n {
            f[i] = vel[i];
            f[n + i] = -p[0] * self.stiffness(pos, i) - p[1] * self.stiffness(vel, i);
        }
        f[n] += p[2] * r;
        let rho = r * r + s * s;
        f[2 * n] = r + p[3] * s - r * rho;
        f[2 * n + 1] = s - p[3] * r - s * rho;
    }
    fn event(&self, _: EventId, x: &[f64], p: &[f64]) -> f64 {
        p[4] - x[self.masses - 1]
    }
    fn reset(&self, _: EventId, x: &[f64], p: &[f64], out: &mut [f64]) {
        out.copy_from_slice(x);
        out[2 * self.masses - 1] = -p[5] * x[2 * self.masses - 1];
    }
    /// The forcing oscillator's multipliers: 1 (its phase) and `exp(-2 T)` (its radius).
    fn trivial_multipliers(&self, _: &[f64], period: f64) -> Vec<(f64, f64)> {
        vec![(1.0, 0.0), ((-2.0 * period).exp(), 0.0)]
    }
}

impl HybridJacobians for ImpactChain {
    fn vector_field_jacobian(
        &self,
        _: Mode,
        x: &[f64],
        p: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        let (n, dim) = (self.masses, self.dim());
        let (r, s) = (x[2 * n], x[2 * n + 1]);
        let rho = r * r + s * s;
        // Column-major dim x dim: entry (i, j) at i + dim * j.
        dx.fill(0.0);
        for i in 0..n {
            dx[i + dim * (n + i)] = 1.0;
            for j in i.saturating_sub(1)..(i + 2).min(n) {
                let l = self.pattern(i, j);
                dx[n + i + dim * j] = -p[0] * l;
                dx[n + i + dim * (n + j)] = -p[1] * l;
            }
        }
        dx[n + dim * (2 * n)] = p[2];
        let (ir, is) = (2 * n, 2 * n + 1);
        dx[ir + dim * ir] = 1.0 - rho - 2.0 * r * r;
        dx[is + dim * ir] = -p[3] - 2.0 * r * s;
        dx[ir + dim * is] = p[3] - 2.0 * r * s;
        dx[is + dim * is] = 1.0 - rho - 2.0 * s * s;
        if let Some(dp) = dp {
            // Column-major dim x 6: k, c, A, w, d, e.
            dp.fill(0.0);
            let (pos, vel) = x[..2 * n].split_at(n);
            for i in 0..n {
                dp[n + i] = -self.stiffness(pos, i);
                dp[n + i + dim] = -self.stiffness(vel, i);
            }
            dp[n + 2 * dim] = r;
            dp[ir + 3 * dim] = s;
            dp[is + 3 * dim] = -r;
        }
    }
    fn event_gradient(
        &self,
        _: EventId,
        _: &[f64],
        _: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        dx.fill(0.0);
        dx[self.masses - 1] = -1.0;
        if let Some(dp) = dp {
            dp.fill(0.0);
            dp[4] = 1.0;
        }
    }
    fn reset_jacobian(
        &self,
        _: EventId,
        x: &[f64],
        p: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        let (dim, v) = (self.dim(), 2 * self.masses - 1);
        dx.fill(0.0);
        for i in 0..dim {
            dx[i + dim * i] = 1.0;
        }
        dx[v + dim * v] = -p[5];
        if let Some(dp) = dp {
            dp.fill(0.0);
            dp[v + dim * 5] = -x[v];
        }
    }
}
