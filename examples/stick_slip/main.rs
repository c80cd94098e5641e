//! COCO's stick-slip oscillator ("Recipes for Continuation", Examples 9.3-9.4) through hycont's
//! public API: a system whose STICK mode has 3 states and whose SLIP mode has 4 (its model,
//! user code, in `model.rs`).
//!
//! 1. The sustained-stick orbit (two segments in STICK, ended by PHASE and MINSEP) is read
//!    off a simulation at `V = 0.5` and continued up in `V` over `[0.5, 0.7]`. The family
//!    folds (SN) and, just beyond the fold on its way back, its position's maximum reaches
//!    the stop at `x1 = 0.5`: the grazing orbit, where the MINSEP end of a segment lies on
//!    COLLISION's surface (a `DB` point: a segment ending on another event's surface).
//! 2. `switch_at` there replaces that end by COLLISION, whose bounce leads into SLIP, with a
//!    zero-length SLIP segment ended by REST back into STICK (COCO's one-point slip segment),
//!    and continues the three-segment stick-slip family on the side where it is physical
//!    (the slip segment's duration grows from zero), up to `V = 0.7`.
//!
//! Both discretisations (shooting; collocation with 40 intervals of degree 4 per segment) do
//! all of it. Printed next to each located number: the other discretisation's (they agree to
//! 1e-8), and for orbits of the new family away from the grazing (where the return is
//! ill-conditioned) the gap of the orbit's own simulation after one period, by the
//! simulator's event detection (1e-8 or less) and the number of events it met (3: PHASE,
//! COLLISION, REST).
//!
//! Run with `cargo run --release --example stick_slip`.

mod model;

use hycont::SimulationSettings;
use hycont::hycont_continuation::{OrbitBranch, OrbitMethod, OrbitRun, RunDirection, SpecialKind};
use hycont::orbit::{CollocationSettings, ShootingSettings};
use model::{StickSlip, V};

/// The located numbers of one discretisation.
struct Found {
    fold: f64,
    grazing: f64,
    /// The three-segment family at the user points: `(V, slip duration, period)`.
    stick_slip: Vec<(f64, f64, f64)>,
    /// Its largest simulated-return gap and the events per period, at the user points.
    gap: f64,
    events: Vec<usize>,
    points: (usize, usize),
}

/// The user points on the stick-slip family (away from the grazing at `V ~ 0.5875`).
const USER: [f64; 2] = [0.62, 0.68];

fn trace(method: OrbitMethod) -> Result<Found, Box<dyn std::error::Error>> {
    let system = StickSlip::default();
    let orbit = model::sustained_stick_orbit()?;
    let mut run = OrbitRun::new(&system, V)?;
    run.method(method).bounds(0.5, 0.7);
    run.add_user_points(V, USER)?;
    let two = run.run("sustained stick", &orbit, RunDirection::Up)?;
    let fold = two.first(SpecialKind::Fold)?.point.params[V.index()];
    let db = two.first(SpecialKind::DOMAIN_BOUNDARY)?;
    let three: OrbitBranch = run.switch_at("stick-slip", &two, db.point.label, RunDirection::Up)?;
    let settings = SimulationSettings::default().rtol(1e-12).atol(1e-13);
    let (mut stick_slip, mut gap, mut events) = (Vec::new(), 0.0f64, Vec::new());
    for uz in three.special(SpecialKind::UserPoint) {
        let o = three.orbit_of(&uz.point)?;
        let back = o.simulated_return(&system, &settings)?;
        gap = gap.max(back.gap);
        events.push(back.events);
        // The slip segment is the one in SLIP.
        let slip = (o.signature.segments().iter())
            .position(|s| s.mode == model::SLIP)
            .map_or(f64::NAN, |k| o.durations[k]);
        stick_slip.push((uz.point.params[V.index()], slip, o.period()));
    }
    Ok(Found {
        fold,
        grazing: db.point.params[V.index()],
        stick_slip,
        gap,
        events,
        points: (two.branch.points.len(), three.branch.points.len()),
    })
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let shooting = trace(OrbitMethod::Shooting(ShootingSettings::default()))?;
    let collocation = trace(OrbitMethod::Collocation(CollocationSettings {
        ntst: 40,
        ..CollocationSettings::default()
    }))?;
    let (s, c) = (&shooting, &collocation);
    println!("sustained stick (2 segments, STICK only), up in V from 0.5:");
    println!("  SN: V = {:.10} (collocation {:.10})", s.fold, c.fold);
    println!(
        "  grazing (DB, max x1 = 0.5): V = {:.10} (collocation {:.10})",
        s.grazing, c.grazing
    );
    println!("stick-slip (3 segments, STICK-STICK-SLIP) from the grazing, up to V = 0.7:");
    for (a, b) in s.stick_slip.iter().zip(&c.stick_slip) {
        println!(
            "  UZ V = {:.2}: slip lasts {:.10} (collocation {:.10}), period {:.10} (pi/w = {:.10})",
            a.0,
            a.1,
            b.1,
            a.2,
            std::f64::consts::PI / model::P0[3]
        );
    }
    println!(
        "  simulated return of those orbits: gap {:.1e} by shooting, {:.1e} by collocation; events per period {:?}",
        s.gap, c.gap, s.events
    );
    println!(
        "points: shooting {:?}, collocation {:?} (sustained stick, stick-slip)",
        s.points, c.points
    );
    Ok(())
}
