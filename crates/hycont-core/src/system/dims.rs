//! The state dimensions of a system's modes ([`HybridSystem::mode_dim`]): checked once, and
//! asked by the parts of the library that need one dimension for every mode.

use super::{EventAction, EventId, HybridSystem, Mode};
use crate::error::{Error, Result};

/// Checks the modes' state dimensions: each at least one and at most
/// [`HybridSystem::state_dim`], which one of them attains, and every mode that monitors an
/// event of the same dimension (the event function and its gradient take that state).
///
/// # Errors
/// [`Error::InvalidSystem`] naming the mode or the event and the dimensions.
///
/// ```
/// # use hycont_core::{EventId, EventSpec, HybridSystem, Mode, check_mode_dims};
/// /// A 1-D mode and a 2-D mode that both watch event 0: refused.
/// struct Mixed;
/// impl HybridSystem for Mixed {
///     fn state_dim(&self) -> usize { 2 }
///     fn mode_dim(&self, m: Mode) -> usize { m.0 + 1 }
///     fn parameter_names(&self) -> &[&'static str] { &[] }
///     fn mode_count(&self) -> usize { 2 }
///     fn mode_name(&self, _: Mode) -> &'static str { "m" }
///     fn events(&self, _: Mode) -> &[EventId] { &[EventId(0)] }
///     fn event_spec(&self, _: EventId) -> EventSpec { unreachable!() }
///     fn vector_field(&self, _: Mode, _: &[f64], _: &[f64], f: &mut [f64]) { f.fill(0.0) }
///     fn event(&self, _: EventId, x: &[f64], _: &[f64]) -> f64 { x[0] }
/// }
/// let e = check_mode_dims(&Mixed).unwrap_err();
/// assert!(e.to_string().contains("event #0"), "{e}");
/// ```
pub fn check_mode_dims<S: HybridSystem + ?Sized>(system: &S) -> Result<()> {
    let n = system.state_dim();
    let invalid = |reason: String| Err(Error::InvalidSystem { reason });
    let mut largest = 0;
    let mut watched: Vec<(EventId, Mode, usize)> = Vec::new();
    for m in (0..system.mode_count()).map(Mode) {
        let nm = system.mode_dim(m);
        if nm == 0 || nm > n {
            return invalid(format!(
                "mode {m} has {nm} states: a mode has between 1 and state_dim() = {n}"
            ));
        }
        largest = largest.max(nm);
        for &e in system.events(m) {
            match watched.iter().find(|(f, ..)| *f == e) {
                Some(&(_, other, no)) if no != nm => {
                    return invalid(format!(
                        "{e} is watched in mode {other} ({no} states) and in mode {m} ({nm} states): the modes that watch an event share its state's dimension"
                    ));
                }
                Some(_) => {}
                None => watched.push((e, m, nm)),
            }
        }
    }
    if largest != n && system.mode_count() > 0 {
        return invalid(format!(
            "state_dim() = {n}, but the largest mode has {largest} states"
        ));
    }
    Ok(())
}

/// The dimension of the state `event`'s reset writes: that of the mode the event leads to
/// ([`EventAction::Jump`]), or `n_from` (the state's before it) for a terminal event.
///
/// ```
/// # use hycont_core::{Direction, EventAction, EventId, EventSpec, HybridSystem, Mode, reset_dim};
/// /// Mode 0 (2 states) jumps into mode 1 (3 states) through event 0.
/// struct Grow;
/// impl HybridSystem for Grow {
///     fn state_dim(&self) -> usize { 3 }
///     fn mode_dim(&self, m: Mode) -> usize { 2 + m.0 }
///     fn parameter_names(&self) -> &[&'static str] { &[] }
///     fn mode_count(&self) -> usize { 2 }
///     fn mode_name(&self, _: Mode) -> &'static str { "m" }
///     fn events(&self, m: Mode) -> &[EventId] { if m.0 == 0 { &[EventId(0)] } else { &[] } }
///     fn event_spec(&self, _: EventId) -> EventSpec {
///         EventSpec { name: "grow", direction: Direction::Either,
///                     action: EventAction::Jump { to: Mode(1) } }
///     }
///     fn vector_field(&self, _: Mode, _: &[f64], _: &[f64], f: &mut [f64]) { f.fill(0.0) }
///     fn event(&self, _: EventId, x: &[f64], _: &[f64]) -> f64 { x[0] }
/// }
/// assert_eq!(reset_dim(&Grow, EventId(0), 2), 3);
/// ```
#[must_use]
pub fn reset_dim<S: HybridSystem + ?Sized>(system: &S, event: EventId, n_from: usize) -> usize {
    match system.event_spec(event).action {
        EventAction::Jump { to } if to.0 < system.mode_count() => system.mode_dim(to),
        _ => n_from,
    }
}

/// Whether every mode of `system` has [`HybridSystem::state_dim`] states.
#[must_use]
pub fn uniform_dims<S: HybridSystem + ?Sized>(system: &S) -> bool {
    let n = system.state_dim();
    (0..system.mode_count()).all(|m| system.mode_dim(Mode(m)) == n)
}

/// Refuses a system whose modes have states of different dimensions in `what`, which does
/// not support them yet.
pub(crate) fn require_uniform_dims<S: HybridSystem + ?Sized>(system: &S, what: &str) -> Result<()> {
    if uniform_dims(system) {
        return Ok(());
    }
    let dims: Vec<String> = (0..system.mode_count())
        .map(|m| format!("mode {}: {}", Mode(m), system.mode_dim(Mode(m))))
        .collect();
    Err(Error::InvalidSystem {
        reason: format!(
            "its modes have states of different dimensions ({}): {what} supports one dimension for every mode",
            dims.join(", ")
        ),
    })
}
