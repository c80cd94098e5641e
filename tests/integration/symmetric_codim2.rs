//! Codimension-two points of the full orbit on curves continued on half orbits, against closed
//! forms.
//!
//! # The system
//! State $(r, s, z, w, u, v)$, parameters $(p_1, p_2)$, one mode:
//! $$\dot r = r + s - r\rho,\quad \dot s = s - r - s\rho\quad (\rho = r^2 + s^2),$$
//! $$\dot z = p_1 + \tfrac12 p_2 - z^2,\quad \dot w = (p_1 + p_2 - 0.2)\,w,$$
//! $$\dot u = \sigma u - 0.7 v,\quad \dot v = 0.7 u + \sigma v\quad (\sigma = p_2 + 0.3),$$
//! symmetric under $S = \mathrm{diag}(-1, -1, 1, -1, 1, 1)$ (the oscillator $(r, s)$ half a
//! turn on, $w$ odd, the rest even). Its symmetric orbits are the unit circle (period
//! $T = 2\pi$) with $z = z^* = \pm\sqrt{p_1 + p_2/2}$ and $w = u = v = 0$, continued on the
//! half orbit (from $r = 0$ to $r = 0$, $T/2 = \pi$).
//!
//! # The multipliers
//! The blocks are decoupled and constant along the orbit, so the half map $S \circ
//! \phi_{T/2}$ has the multipliers $e^{\pi a}$ times the sign $S$ gives each block, $a$ the
//! block's rate: $\mu_z = e^{-2\pi z^*}$, $\mu_w = -e^{\pi(p_1 + p_2 - 0.2)}$,
//! $\mu_{uv} = e^{\pi(\sigma \pm 0.7 i)}$, and the oscillator's trivial $1$ and $e^{-2\pi}$.
//! The full orbit's are $\lambda = \mu^2$.
//!
//! # The curves and their points
//! - Symmetric folds ($\mu_z = +1$, $z^* = 0$): the line $p_1 = -p_2/2$. Another full
//!   multiplier reaches $+1$ (R1) where $\mu_w = -1$: $p_1 + p_2 = 0.2$, at
//!   $(p_1, p_2) = (-0.2, 0.4)$; the complex pair $\lambda_{uv} = e^{2\pi(\sigma \pm 0.7i)}$
//!   crosses the unit circle (LPNS) at $\sigma = 0$: $(0.15, -0.3)$.
//! - Symmetry breaking ($\mu_w = -1$): the line $p_1 = 0.2 - p_2$, with
//!   $z^* = \pm\sqrt{0.2 - p_2/2}$. R1 where $\mu_z = +1$ ($z^* = 0$, where the curve turns
//!   in $p_2$): $(-0.2, 0.4)$; LPNS at $p_2 = -0.3$: $(0.5, -0.3)$.
//!
//! Every other full multiplier is real and positive ($\mu^2$ of a real $\mu$) or the complex
//! pair: no full multiplier crosses $-1$ (LPPD, and R2 and PDNS, which need one held at
//! $-1$, are not reported).

use approx::assert_abs_diff_eq;
use hycont::hycont_continuation::{CurveSpec, OrbitBranch, OrbitRun, RunDirection, SpecialKind};
use hycont::orbit::{
    CollocationSettings, OrbitMethod, PeriodicOrbit, SegmentEnd, SegmentSpec, ShootingSettings,
    Signature,
};
use hycont::{
    EventId, EventSpec, HybridJacobians, HybridSystem, Mode, ParamId, Z2Symmetry, check_derivatives,
};
use std::f64::consts::PI;

const P1: ParamId = ParamId(0);
const P2: ParamId = ParamId(1);
const M: Mode = Mode(0);
const OMEGA_UV: f64 = 0.7;

struct Blocks;

impl HybridSystem for Blocks {
    fn state_dim(&self) -> usize {
        6
    }
    fn parameter_names(&self) -> &[&'static str] {
        &["p1", "p2"]
    }
    fn mode_count(&self) -> usize {
        1
    }
    fn mode_name(&self, _: Mode) -> &'static str {
        "blocks"
    }
    fn events(&self, _: Mode) -> &[EventId] {
        &[]
    }
    fn event_spec(&self, _: EventId) -> EventSpec {
        unreachable!("no events")
    }
    fn vector_field(&self, _: Mode, x: &[f64], p: &[f64], f: &mut [f64]) {
        let (r, s) = (x[0], x[1]);
        let rho = r * r + s * s;
        let sigma = p[1] + 0.3;
        f[0] = r + s - r * rho;
        f[1] = s - r - s * rho;
        f[2] = p[0] + 0.5 * p[1] - x[2] * x[2];
        f[3] = (p[0] + p[1] - 0.2) * x[3];
        f[4] = sigma * x[4] - OMEGA_UV * x[5];
        f[5] = OMEGA_UV * x[4] + sigma * x[5];
    }
    fn event(&self, _: EventId, _: &[f64], _: &[f64]) -> f64 {
        unreachable!("no events")
    }
    fn symmetry(&self) -> Option<Z2Symmetry> {
        let diagonal = [-1.0, -1.0, 1.0, -1.0, 1.0, 1.0];
        let mut matrix = vec![0.0; 36];
        for (i, d) in diagonal.iter().enumerate() {
            matrix[i + 6 * i] = *d;
        }
        Some(Z2Symmetry {
            matrix,
            modes: vec![M],
            events: vec![],
        })
    }
    /// The oscillator's multipliers: 1 (its phase) and `exp(-2 T)` (its radius).
    fn trivial_multipliers(&self, _: &[f64], period: f64) -> Vec<(f64, f64)> {
        vec![(1.0, 0.0), ((-2.0 * period).exp(), 0.0)]
    }
}

impl HybridJacobians for Blocks {
    fn vector_field_jacobian(
        &self,
        _: Mode,
        x: &[f64],
        p: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        let (r, s) = (x[0], x[1]);
        let rho = r * r + s * s;
        let sigma = p[1] + 0.3;
        // Column-major 6 x 6: dx[i + 6 j] = d f_i / d x_j.
        dx.fill(0.0);
        dx[0] = 1.0 - rho - 2.0 * r * r;
        dx[1] = -1.0 - 2.0 * r * s;
        dx[6] = 1.0 - 2.0 * r * s;
        dx[7] = 1.0 - rho - 2.0 * s * s;
        dx[2 + 12] = -2.0 * x[2];
        dx[3 + 18] = p[0] + p[1] - 0.2;
        dx[4 + 24] = sigma;
        dx[5 + 24] = OMEGA_UV;
        dx[4 + 30] = -OMEGA_UV;
        dx[5 + 30] = sigma;
        if let Some(dp) = dp {
            // Column-major 6 x 2: p1, p2.
            dp.fill(0.0);
            dp[2] = 1.0;
            dp[3] = x[3];
            dp[6 + 2] = 0.5;
            dp[6 + 3] = x[3];
            dp[6 + 4] = x[4];
            dp[6 + 5] = x[5];
        }
    }
    fn event_gradient(
        &self,
        _: EventId,
        _: &[f64],
        _: &[f64],
        _: &mut [f64],
        _: Option<&mut [f64]>,
    ) {
        unreachable!("no events")
    }
}

/// The symmetric orbit at `(p1, p2)` with `z* = +sqrt(p1 + p2 / 2)`: two halves from `r = 0`
/// to `r = 0`.
fn symmetric_orbit(p1: f64, p2: f64) -> PeriodicOrbit {
    let half = SegmentSpec {
        mode: M,
        end: SegmentEnd::Interior {
            component: 0,
            value: 0.0,
        },
    };
    let sig = Signature::new(&Blocks, vec![half, half]).unwrap();
    let z = (p1 + 0.5 * p2).sqrt();
    PeriodicOrbit::new(
        &Blocks,
        sig,
        vec![
            vec![0.0, 1.0, z, 0.0, 0.0, 0.0],
            vec![0.0, -1.0, z, 0.0, 0.0, 0.0],
        ],
        vec![PI, PI],
        vec![p1, p2],
    )
    .unwrap()
}

fn methods() -> [OrbitMethod; 2] {
    [
        OrbitMethod::Shooting(ShootingSettings::default()),
        OrbitMethod::Collocation(CollocationSettings::default()),
    ]
}

/// The codimension-two points of `curve` as (kind, p1, p2), with their critical multipliers
/// checked: R1 a full multiplier at +1 besides the held one, LPNS a non-real one on the unit
/// circle (1e-6, the critical tolerance).
fn points(curve: &OrbitBranch) -> Vec<(SpecialKind, f64, f64)> {
    let codim2 = [
        SpecialKind::Resonance1,
        SpecialKind::FoldFlip,
        SpecialKind::Resonance2,
        SpecialKind::FoldTorus,
        SpecialKind::FlipTorus,
    ];
    curve
        .branch
        .special_points
        .iter()
        .filter(|s| codim2.contains(&s.kind))
        .map(|s| {
            assert!(s.located, "{s:?}");
            let (re, im) = s
                .critical
                .expect("a codimension-two point carries its multiplier");
            match s.kind {
                SpecialKind::Resonance1 => {
                    assert!((re - 1.0).hypot(im) <= 1e-6, "{re} {im}");
                }
                SpecialKind::FoldTorus => {
                    assert!(
                        im.abs() > 0.1 && (re.hypot(im) - 1.0).abs() <= 1e-6,
                        "{re} {im}"
                    );
                }
                _ => {}
            }
            (s.kind, s.point[P1], s.point[P2])
        })
        .collect()
}

#[test]
fn the_jacobians_match_differences() {
    let x = [0.3, -0.8, 0.4, 0.2, -0.1, 0.5];
    let check = check_derivatives(&Blocks, M, &x, &[0.1, -0.2]).unwrap();
    assert!(check.max_error() < 1e-7, "{check:?}");
}

/// The symmetric fold curve $p_1 = -p_2/2$ and the symmetry-breaking curve $p_1 = 0.2 - p_2$,
/// each continued on half orbits from its point on the branch in $p_1$ at $p_2 = 0$, report
/// the full orbit's R1 and LPNS at their closed forms (1e-7), and nothing else of
/// codimension two, by both discretisations.
#[test]
fn half_orbit_curves_report_the_full_orbits_codimension_two_points() {
    for method in methods() {
        let mut run = OrbitRun::new(&Blocks, P1).unwrap();
        run.method(method).bounds(-1.0, 1.0);
        let branch = run
            .run("symmetric", &symmetric_orbit(0.1, 0.0), RunDirection::Both)
            .unwrap();
        let fold = branch.first(SpecialKind::Fold).unwrap();
        assert_abs_diff_eq!(fold.point[P1], 0.0, epsilon = 1e-8);
        let bp = branch.first(SpecialKind::BranchPoint).unwrap();
        assert_abs_diff_eq!(bp.point[P1], 0.2, epsilon = 1e-8);
        let spec = CurveSpec::new(P2).bounds(-1.0, 1.0);

        let sn = run
            .curve_at("SN", &branch, fold.point.label, &spec)
            .unwrap();
        for p in &sn.branch.points {
            assert_abs_diff_eq!(p[P1], -0.5 * p[P2], epsilon = 1e-8);
        }
        let mut found = points(&sn);
        found.sort_by(|a, b| a.2.total_cmp(&b.2));
        assert_eq!(found.len(), 2, "{method:?}: {found:?}");
        assert_eq!(found[0].0, SpecialKind::FoldTorus);
        assert_abs_diff_eq!(found[0].1, 0.15, epsilon = 1e-7);
        assert_abs_diff_eq!(found[0].2, -0.3, epsilon = 1e-7);
        assert_eq!(found[1].0, SpecialKind::Resonance1);
        assert_abs_diff_eq!(found[1].1, -0.2, epsilon = 1e-7);
        assert_abs_diff_eq!(found[1].2, 0.4, epsilon = 1e-7);

        let sb = run.curve_at("SB", &branch, bp.point.label, &spec).unwrap();
        for p in &sb.branch.points {
            assert_abs_diff_eq!(p[P1], 0.2 - p[P2], epsilon = 1e-8);
        }
        let found = points(&sb);
        let r1: Vec<_> = found
            .iter()
            .filter(|f| f.0 == SpecialKind::Resonance1)
            .collect();
        let lpns: Vec<_> = found
            .iter()
            .filter(|f| f.0 == SpecialKind::FoldTorus)
            .collect();
        assert_eq!(r1.len() + lpns.len(), found.len(), "{method:?}: {found:?}");
        assert!(!r1.is_empty() && !lpns.is_empty(), "{method:?}: {found:?}");
        for f in r1 {
            assert_abs_diff_eq!(f.1, -0.2, epsilon = 1e-7);
            assert_abs_diff_eq!(f.2, 0.4, epsilon = 1e-7);
        }
        for f in lpns {
            assert_abs_diff_eq!(f.1, 0.5, epsilon = 1e-7);
            assert_abs_diff_eq!(f.2, -0.3, epsilon = 1e-7);
        }
    }
}
