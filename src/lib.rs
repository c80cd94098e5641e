//! # hycont
//!
//! Numerical continuation of periodic orbits of hybrid (impacting, switching,
//! piecewise-smooth) dynamical systems: simulate a system, solve its periodic orbits by
//! shooting or collocation with their Floquet multipliers, continue them with located
//! bifurcations, switch branches (at branch points, period doublings and grazing), follow
//! special points in two parameters, compute whole diagrams and atlases, and estimate basins
//! of attraction. This crate is the facade: it re-exports [`hycont_core`] (at the top level
//! too), [`hycont_continuation`] and [`hycont_sample`]. The workflow step by step, with a
//! runnable example per step, is `docs/guide.md` in the repository; `docs/clusters.md` runs
//! sampling studies on clusters.
//!
//! ## Walk-through: a ball on a vibrating table
//!
//! The system of `examples/vibrating_table/model.rs`, `Table`, is a ball over a table that
//! moves as $s(t) = a \sin\omega t$, in table coordinates: state $(z, w, \theta)$ (height and
//! velocity above the table, forcing phase), one mode with $\dot z = w$,
//! $\dot w = -g + a\omega^2\sin\theta$, $\dot\theta = \omega$, and two events: the impact
//! ($z$ falls through 0, $w \mapsto -e w$) and the phase wrap ($\theta$ from $\pi$ to $-\pi$).
//! Implementing [`HybridSystem`] is all a user writes; [`FiniteDifferences`] supplies the
//! derivatives (or implement [`HybridJacobians`]).
//!
//! 1. **Simulate** with the event-driven [`Simulator`] and read a periodic orbit off the tail
//!    ([`orbit::PeriodicOrbit::from_simulation`]), rotated to start after the impact
//!    ([`orbit::PeriodicOrbit::starting_after`]): its signature is the sequence of modes and
//!    the events that end them.
//! 2. **Solve** it by shooting or collocation ([`orbit::solve_orbit`]; symmetric orbits on their
//!    half orbit) and read its Floquet multipliers, monodromy and Floquet vectors
//!    ([`orbit::Floquet`], nalgebra matrices), saltation matrices included: an orbit is stable
//!    when its multipliers other than the flow direction's $1$ lie inside the unit circle.
//! 3. **Continue** it in a parameter with an [`hycont_continuation::OrbitRun`]: measures with
//!    typed handles ([`orbit::Extremum`], [`orbit::GrazingMargin`], [`orbit::SegmentValue`],
//!    [`orbit::TimeAverage`], closures), events on them with labels, user points (UZ), bounds.
//!    Pseudo-arclength continuation locates folds (SN), branch points (BP), period doublings
//!    (PD: a multiplier through $-1$), tori and the events, to $10^{-10}$ in arclength.
//! 4. **Switch** branches at a BP or PD in one call
//!    ([`hycont_continuation::OrbitRun::switch_at`]).
//! 5. **Follow** a special point in two parameters
//!    ([`hycont_continuation::OrbitRun::curve_at`]): a fold or period doubling as the
//!    singularity of the boundary-value problem's Jacobian with its closure scaled by $\pm 1$
//!    (a minimally augmented system, exact for either discretisation), an event as its measure
//!    held at its level.
//! 6. **Save and restart**: an [`hycont_continuation::OrbitBranch`] is JSON with everything a
//!    restart at any label needs ([`hycont_continuation::OrbitRun::restart`]).
//!
//! For $e = 1/2$, $g = 1$, $\omega = 1$ the fold is at $a = \pi g(1-e)/((1+e)\omega^2) =
//! \pi/3$ and the period doubling at
//! $a\omega^2 = g\sqrt{4(1+e^2)^2/(1+e)^4 + \pi^2(1-e)^2/(1+e)^2}$ (derived in
//! `tests/integration/vibrating_table.rs`):
//!
//! ```
//! include!("../examples/vibrating_table/model.rs"); // `Table`, `A`, `OMEGA`, `IMPACT`, ...
//! use hycont::hycont_continuation::{Label, OrbitBranch, OrbitRun, RunDirection, SpecialKind};
//! use hycont::orbit::{solve_orbit, OrbitMethod, PeriodicOrbit, SegmentValue};
//! use hycont::problem::NewtonSettings;
//! use hycont::{FiniteDifferences, SimulationSettings, Simulator};
//!
//! fn main() -> Result<(), Box<dyn std::error::Error>> {
//!     let table = FiniteDifferences::new(Table);
//!     // 1. Simulate, read the orbit off the tail.
//!     let p = [1.3, 1.0, 0.5, 1.0]; // a, omega, e, g
//!     let traj = Simulator::new(SimulationSettings::default())?
//!         .run(&table, FLIGHT, 0.0, &[0.0, 2.0, 0.0], &p, 300.0)?;
//!     let guess = PeriodicOrbit::from_simulation(&table, &traj, &p, 1e-8)?
//!         .starting_after(&table, IMPACT)?;
//!     // 2. Solve it; multipliers, monodromy and Floquet vectors as nalgebra types.
//!     let solved = solve_orbit(&table, &guess, &OrbitMethod::default(),
//!                              &NewtonSettings::default(), 1e-6)?;
//!     let floquet = &solved.solution.floquet;
//!     assert!(floquet.stable());
//!     let (m, v) = (floquet.monodromy_matrix(), floquet.vectors()?);
//!     assert_eq!((m.nrows(), v.ncols()), (3, 3));
//!     // 3. Continue in a: the impact velocity as a measure, an event labelled "PH" where
//!     //    the impact phase is 0.5, a user point at a = 1.2.
//!     let mut run = OrbitRun::new(&table, A)?;
//!     run.bounds(0.9, 1.8);
//!     let phase = run.add_measure("impact_phase", SegmentValue::start(0, 2))?;
//!     run.add_event(phase, 0.5, SpecialKind::Custom(Label::new("PH")?))?
//!         .add_user_points(A, [1.2])?;
//!     let branch = run.run("period-1", &solved.solution.orbit, RunDirection::Both)?;
//!     let sn = branch.first(SpecialKind::Fold)?;
//!     assert!((sn.point[A] - std::f64::consts::PI / 3.0).abs() < 1e-8);
//!     let ph = branch.first(SpecialKind::Custom(Label::new("PH")?))?;
//!     assert!((ph.point[phase] - 0.5).abs() < 1e-9);
//!     // 4. Switch to period 2 at the period doubling.
//!     let pd = branch.first(SpecialKind::PeriodDoubling)?;
//!     let period2 = run.switch_at("period-2", &branch, pd.point.label, RunDirection::Up)?;
//!     let last = period2.branch.points.last().ok_or("empty")?;
//!     assert!((period2.orbit_of(last)?.period() - 4.0 * std::f64::consts::PI).abs() < 1e-8);
//!     // 5. run.curve_at(...) follows PD or SN in (a, omega) (the guide, step 5).
//!     // 6. Save, load and restart at the user point on the stable sheet (impact phase > 0;
//!     //    the other one is on the unstable sheet past the fold), upwards.
//!     let saved = OrbitBranch::from_json(&branch.to_json()?)?;
//!     let uz = saved.special(SpecialKind::UserPoint).find(|s| s.point[phase] > 0.0);
//!     let uz = uz.ok_or("no UZ")?.point.label;
//!     let again = run.restart("again", &saved, uz, Some(RunDirection::Up))?;
//!     assert!(again.first(SpecialKind::PeriodDoubling).is_ok());
//!     Ok(())
//! }
//! ```
//!
//! ## Crates
//!
//! This facade re-exports the library crates:
//!
//! - [`hycont_core`] (also re-exported at the top level): hybrid systems, event-driven
//!   simulation with variational equations, periodic-orbit problems (shooting, collocation),
//!   measures, symmetric orbits, Floquet multipliers;
//! - [`hycont_continuation`]: pseudo-arclength continuation of periodic orbits ([`OrbitRun`]),
//!   special points, events, branch switching, two-parameter curves, saved branches;
//! - [`hycont_sample`]: brute-force bifurcation diagrams, attractor classification of
//!   periodically forced systems, basin stability.
//!
//! [`OrbitRun`]: hycont_continuation::OrbitRun
#![deny(missing_docs)]

pub use hycont_continuation;
pub use hycont_core;
// The core's items under `hycont::`, documented once, in `hycont_core` (with nalgebra and
// num_dual linked, not copied).
#[doc(no_inline)]
pub use hycont_core::*;
pub use hycont_sample;

/// The README's example, compiled and run as a doctest.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
