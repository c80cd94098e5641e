//! A ball bouncing on a vibrating table (Holmes 1982) through hycont's public API: simulate to
//! a period-1 orbit, continue it in the table's amplitude `a`, locate the existence fold (SN)
//! and the period doubling (PD), switch to the period-2 branch at PD, and continue the PD curve
//! in `(a, omega)`, then the branch again with exact derivatives by automatic
//! differentiation (`AutoDiff::new(TableModel)`), and the whole family of stable period-1
//! orbits over `(a, omega)` as an atlas of charts bounded by the fold and the period doubling;
//! located points are printed next to their
//! closed forms (derived in `tests/integration/vibrating_table.rs`): `a_SN omega^2 = pi g (1 - e) / (1 + e)` and
//! `a_PD omega^2 = g sqrt(4 (1 + e^2)^2 / (1 + e)^4 + pi^2 (1 - e)^2 / (1 + e)^2)`.
//!
//! User code: 166 lines (model.rs 92 with the model written twice, once for central differences
//! and once for automatic differentiation; this file 74; without comments and blank lines).
//! model.rs also holds hand-coded Jacobians and the closed-form start for the tests and benches
//! (79 more lines).
//!
//! Run with `cargo run --release --example vibrating_table`.

mod model;

use hycont::hycont_continuation::atlas::{AtlasChart, AtlasEdges, AtlasSettings};
use hycont::hycont_continuation::{CurveSpec, OrbitRun, RunDirection, SpecialKind};
use hycont::orbit::{PeriodicOrbit, SegmentValue};
use hycont::{AutoDiff, FiniteDifferences, SimulationSettings, Simulator};
use model::{A, FLIGHT, IMPACT, OMEGA, Table, TableModel};
use std::f64::consts::PI;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (e, g) = (0.5_f64, 1.0);
    let q = 4.0 * (1.0 + e * e).powi(2) / (1.0 + e).powi(4) + (PI * (1.0 - e) / (1.0 + e)).powi(2);
    let (a_sn, a_pd) = (PI * g * (1.0 - e) / (1.0 + e), g * q.sqrt()); // times 1 / omega^2
    let table = FiniteDifferences::new(Table);
    // Simulate at a = 1.3, omega = 1 and read the period-1 orbit off the tail, starting after
    // the impact: its segment 1 ends at the impact.
    let p = [1.3, 1.0, e, g];
    let mut sim = Simulator::new(SimulationSettings::default())?;
    let traj = sim.run(&table, FLIGHT, 0.0, &[0.0, 2.0, 0.0], &p, 300.0)?;
    let orbit = PeriodicOrbit::from_simulation(&table, &traj, &p, 1e-8)?;
    let orbit = orbit.starting_after(&table, IMPACT)?;
    // The branch in a, both ways from 1.3, recording the velocity just before the impact.
    let mut run = OrbitRun::new(&table, A)?;
    run.bounds(0.9, 1.8);
    let v = run.add_measure("impact_velocity", SegmentValue::end(1, 1))?;
    let branch = run.run("period-1", &orbit, RunDirection::Both)?;
    let show = |what: &str, value: f64, closed: f64| {
        println!("{what} {value:.12} (closed form {closed:.12})");
    };
    let v_impact = -2.0 * PI * g / (1.0 + e);
    show("impact velocity", branch.branch.points[0][v], v_impact);
    let sn = branch.first(SpecialKind::Fold)?;
    let pd = branch.first(SpecialKind::PeriodDoubling)?;
    show("SN at a =", sn.point[A], a_sn);
    show("PD at a =", pd.point[A], a_pd);
    // Period 2 from PD, and the PD curve with user points at omega = 0.95 and 1.05.
    let p2 = run.switch_at("period-2", &branch, pd.point.label, RunDirection::Up)?;
    let end = p2.branch.points.last().ok_or("no points")?;
    let (a_end, period) = (end[A], p2.orbit_of(end)?.period());
    println!("period 2: to a = {a_end:.3} with period {period:.10} (4 pi)");
    let spec = CurveSpec::new(OMEGA)
        .bounds(0.8, 1.25)
        .user_points(OMEGA, [0.95, 1.05]);
    let curve = run.curve_at("PD", &branch, pd.point.label, &spec)?;
    for s in curve.special(SpecialKind::UserPoint) {
        let (w, a) = (s.point[OMEGA], s.point[A]);
        let what = format!("PD curve at omega = {w:.2}: a =");
        show(&what, a, a_pd / (w * w));
    }
    // The same branch with exact derivatives, by automatic differentiation of `TableModel`.
    let exact = AutoDiff::new(TableModel);
    let mut run = OrbitRun::new(&exact, A)?;
    run.bounds(0.9, 1.8);
    let branch = run.run("period-1", &orbit, RunDirection::Both)?;
    let pd = branch.first(SpecialKind::PeriodDoubling)?;
    show("PD at a = (automatic differentiation)", pd.point[A], a_pd);
    // The whole family of stable period-1 orbits over (a, omega) by an atlas of charts: its
    // edges are the fold and the period doubling (and the bounds); every boundary chart on
    // them lies on its closed-form curve.
    let edges = AtlasEdges {
        period_doubling: true,
        ..AtlasEdges::default()
    };
    let settings = AtlasSettings::default()
        .radii(0.1, 1e-3, 0.2)
        .bound(OMEGA, 0.8, 1.25)
        .bound(A, 0.0, 1.8)
        .edges(edges);
    let atlas = run.atlas("period-1", &orbit, OMEGA, &settings)?.atlas;
    println!("atlas: {} charts ({:?})", atlas.charts.len(), atlas.end);
    for (kind, closed) in [
        (SpecialKind::Fold, a_sn),
        (SpecialKind::PeriodDoubling, a_pd),
    ] {
        let off = |c: &AtlasChart| (c.point[A] * c.point[OMEGA].powi(2) - closed).abs();
        let worst = atlas.edge_charts(kind).map(off).fold(0.0, f64::max);
        let n = atlas.edge_charts(kind).count();
        println!(
            "{n} {} charts, |a omega^2 - closed form| <= {worst:.1e}",
            kind.label()
        );
    }
    Ok(())
}
