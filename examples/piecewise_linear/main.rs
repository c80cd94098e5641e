//! A forced oscillator whose stiffness grows at a switching surface `x = d` (a mode switch
//! without a jump) through hycont's public API: a two-mode orbit read off a simulation is
//! continued down in the forcing amplitude `f` until its stiff segment collapses (a grazing of
//! the switching surface); the soft orbit below is continued up until its maximum touches the
//! surface (an event on a grazing-margin measure); the grazing curve in `(f, omega)` follows.
//! Located points are printed next to the closed form `f = d D(omega)`,
//! `D = sqrt((1 - omega^2)^2 + (2 zeta omega)^2)` (derived in `tests/integration/piecewise_linear.rs`,
//! which also checks the orbits against matrix exponentials).
//!
//! User code: 99 lines (model.rs 55, this file 44; without comments and blank lines).
//!
//! Run with `cargo run --release --example piecewise_linear`.

mod model;

use hycont::hycont_continuation::{CurveSpec, OrbitRun, RunDirection, SpecialKind};
use hycont::orbit::{GrazingMargin, PeriodicOrbit, SegmentEnd, SegmentSpec, Signature};
use hycont::{FiniteDifferences, SimulationSettings, Simulator};
use model::{F, OMEGA, Oscillator, SOFT, UP};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (zeta, k, d, omega) = (0.05_f64, 1.0, 1.0, 0.8_f64);
    let graze = |w: f64| d * ((1.0 - w * w).powi(2) + (2.0 * zeta * w).powi(2)).sqrt();
    let show = |what: &str, f: f64, w: f64| {
        println!("{what} f = {f:.12} (closed form {:.12})", graze(w));
    };
    let osc = FiniteDifferences::new(Oscillator);
    let mut run = OrbitRun::new(&osc, F)?;
    run.bounds(0.1, 1.0);
    let margin = run.add_measure("margin", GrazingMargin::new([UP]))?;
    run.add_terminal_event(margin, 0.0, SpecialKind::Grazing)?;

    // A two-mode orbit at f = 0.5, read off a simulation, continued down to its grazing.
    let p = [0.5, omega, zeta, k, d];
    let mut sim = Simulator::new(SimulationSettings::default())?;
    let traj = sim.run(&osc, SOFT, 0.0, &[0.0, 0.0, 0.0, 1.0], &p, 500.0)?;
    let two = PeriodicOrbit::from_simulation(&osc, &traj, &p, 1e-9)?.starting_after(&osc, UP)?;
    let down = run.run("two-mode", &two, RunDirection::Down)?;
    let gr = down.first(SpecialKind::Grazing)?;
    show("two-mode: stiff segment collapses at", gr.point[F], omega);

    // A soft orbit at f = 0.3 (one segment from v = 0 to v = 0; a rough guess that the first
    // step solves), continued up to where its maximum reaches x = d.
    let end = SegmentEnd::Interior {
        component: 1,
        value: 0.0,
    };
    let sig = Signature::new(&osc, vec![SegmentSpec { mode: SOFT, end }])?;
    let (x0, period) = (vec![0.8, 0.0, 1.0, 0.0], 2.0 * std::f64::consts::PI / omega);
    let p = vec![0.3, omega, zeta, k, d];
    let soft = PeriodicOrbit::new(&osc, sig, vec![x0], vec![period], p)?;
    let up = run.run("soft", &soft, RunDirection::Up)?;
    let gr = up.first(SpecialKind::Grazing)?;
    show("soft: maximum reaches x = d at", gr.point[F], omega);

    // The grazing curve in (f, omega), with user points at omega = 0.7 and 0.9.
    let spec = CurveSpec::new(OMEGA)
        .bounds(0.6, 1.4)
        .user_points(OMEGA, [0.7, 0.9]);
    let curve = run.curve_at("GR", &up, gr.point.label, &spec)?;
    for s in curve.special(SpecialKind::UserPoint) {
        let w = s.point[OMEGA];
        show(&format!("grazing curve at omega = {w:.1}:"), s.point[F], w);
    }
    Ok(())
}
