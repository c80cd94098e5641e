//! $\mathbb{Z}_2$-symmetric orbits: recognition, images, and the half-orbit problem.
//!
//! An orbit is symmetric when $S$ maps it to itself shifted by half a period: with $2K$
//! segments, segment $k + K$ is the $S$-image of segment $k$. Then the period map is the square of
//! the half map $P_{1/2} = S \circ \phi_{T/2}$, whose multipliers $\mu$ satisfy $\mu^2 = \lambda$:
//! $\mu = -1$ marks a symmetry-breaking branch point, $\mu = +1$ a fold.

use super::signature::{Closure, SegmentEnd, SegmentSpec, Signature};
use super::{
    Floquet, OrbitSolution, PeriodicOrbit, ShootingSettings, floquet, monodromy_by_shooting,
};
use crate::error::{Error, Result, check_finite, check_len};
use crate::problem::NewtonSettings;
use crate::simulate::{SimulationSettings, Simulator};
use crate::system::{HybridJacobians, HybridSystem, Z2Symmetry, checked_symmetry};
use serde::{Deserialize, Serialize};

fn symmetry_of<S: HybridSystem + ?Sized>(system: &S) -> Result<Z2Symmetry> {
    checked_symmetry(system)
}

fn image_segment(sym: &Z2Symmetry, n: usize, seg: &SegmentSpec) -> SegmentSpec {
    SegmentSpec {
        mode: sym.modes[seg.mode.0],
        end: match seg.end {
            SegmentEnd::Event(e) => SegmentEnd::Event(sym.events[e.0]),
            // x_c = v maps to (S x)_c = S_cc v for the signed-permutation symmetries supported.
            SegmentEnd::Interior { component, value } => SegmentEnd::Interior {
                component,
                value: sym.matrix[component + component * n] * value,
            },
        },
    }
}

impl PeriodicOrbit {
    /// The system's symmetry, checked ([`Z2Symmetry::validate`]) and checked to commute with
    /// the system at the orbit's segment starts, each in its mode ([`Z2Symmetry::check_at`]):
    /// what the half-orbit solves and continuation do before using it.
    ///
    /// # Errors
    /// [`Error::InvalidSymmetry`] naming what is wrong or does not commute.
    pub fn symmetry_at_starts<S: HybridSystem + ?Sized>(&self, system: &S) -> Result<Z2Symmetry> {
        let sym = checked_symmetry(system)?;
        for (seg, x) in self.signature.segments().iter().zip(&self.starts) {
            sym.check_at(system, seg.mode, &[x], &self.params)?;
        }
        Ok(sym)
    }

    /// The $S$-image of the orbit: modes and events mapped, start states $S x_k$, same durations.
    ///
    /// # Errors
    /// If the system has no symmetry.
    pub fn symmetric_image<S: HybridSystem + ?Sized>(&self, system: &S) -> Result<Self> {
        let sym = symmetry_of(system)?;
        let n = system.state_dim();
        let segments = self
            .signature
            .segments()
            .iter()
            .map(|s| image_segment(&sym, n, s))
            .collect();
        let starts = self
            .starts
            .iter()
            .map(|x| {
                let mut y = vec![0.0; x.len()];
                sym.apply(x, &mut y);
                y
            })
            .collect();
        let signature = Signature::with_closure(system, segments, self.signature.closure())?;
        Self::new(
            system,
            signature,
            starts,
            self.durations.clone(),
            self.params.clone(),
        )
    }

    /// Whether the orbit is $\mathbb{Z}_2$-symmetric to `tol` (relative): $2K$ segments with
    /// segment $k + K$ the image of segment $k$.
    #[must_use]
    pub fn is_symmetric<S: HybridSystem + ?Sized>(&self, system: &S, tol: f64) -> bool {
        let Ok(sym) = checked_symmetry(system) else {
            return false;
        };
        let kk = self.segment_count();
        if !kk.is_multiple_of(2) || self.signature.closure() != Closure::Periodic {
            return false;
        }
        let h = kk / 2;
        let n = system.state_dim();
        (0..h).all(|k| {
            let a = &self.signature.segments()[k];
            let b = &self.signature.segments()[k + h];
            let mut y = vec![0.0; self.starts[k].len()];
            sym.apply(&self.starts[k], &mut y);
            let scale = 1.0 + y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            image_segment(&sym, n, a) == *b
                && (self.durations[k] - self.durations[k + h]).abs()
                    <= tol * self.durations[k].max(1.0)
                && y.iter()
                    .zip(&self.starts[k + h])
                    .all(|(u, v)| (u - v).abs() <= tol * scale)
        })
    }

    /// The first half of a symmetric orbit, as a half orbit with [`Closure::Symmetric`].
    ///
    /// # Errors
    /// If the orbit is not symmetric to `tol`.
    pub fn half_of_symmetric<S: HybridSystem + ?Sized>(
        &self,
        system: &S,
        tol: f64,
    ) -> Result<Self> {
        if !self.is_symmetric(system, tol) {
            return Err(Error::InvalidSignature {
                segment: 0,
                reason: format!("the orbit is not symmetric to {tol:e}"),
            });
        }
        let h = self.segment_count() / 2;
        let signature = Signature::with_closure(
            system,
            self.signature.segments()[..h].to_vec(),
            Closure::Symmetric,
        )?;
        Self::new(
            system,
            signature,
            self.starts[..h].to_vec(),
            self.durations[..h].to_vec(),
            self.params.clone(),
        )
    }

    /// The full orbit of a half orbit ([`Closure::Symmetric`]): the half followed by its image.
    ///
    /// # Errors
    /// If the orbit is not a half orbit or the system has no symmetry.
    pub fn unfold_symmetric<S: HybridSystem + ?Sized>(&self, system: &S) -> Result<Self> {
        if self.signature.closure() != Closure::Symmetric {
            return Err(Error::InvalidSignature {
                segment: 0,
                reason: "not a half orbit (closure is periodic)".into(),
            });
        }
        let image = self.symmetric_image(system)?;
        let mut segments = self.signature.segments().to_vec();
        segments.extend_from_slice(image.signature.segments());
        let mut starts = self.starts.clone();
        starts.extend(image.starts);
        let mut durations = self.durations.clone();
        durations.extend(image.durations);
        let signature = Signature::new(system, segments)?;
        Self::new(system, signature, starts, durations, self.params.clone())
    }
}

/// The multipliers of a half orbit ([`Closure::Symmetric`]) from its half monodromy
/// $M_{1/2}$ (the Jacobian of $x_0 \mapsto x_K$, saltations included, where the closure is
/// $x_K = S x_0$): the half map $P_{1/2} = S \circ \phi_{T/2}$ has Jacobian $S M_{1/2}$ and
/// multipliers $\mu$; the full period map has Jacobian $(S M_{1/2})^2$ and multipliers
/// $\lambda = \mu^2$. Returns `(half, full)`, each with its trivial multipliers flagged (the
/// half map's for the period $T/2$, the full map's for $T$).
///
/// # Errors
/// If the system has no symmetry, the orbit is not a half orbit, `half_monodromy` is not
/// $n \times n$, or the eigenvalue computation fails.
pub fn symmetric_floquet<S: HybridSystem + ?Sized>(
    system: &S,
    half: &PeriodicOrbit,
    half_monodromy: &[f64],
) -> Result<(Floquet, Floquet)> {
    // The monodromy lives in the first segment's space.
    let n = half.starts.first().map_or(0, Vec::len);
    if half.signature.closure() != Closure::Symmetric {
        return Err(Error::InvalidSignature {
            segment: 0,
            reason: "not a half orbit (closure is periodic)".into(),
        });
    }
    if half_monodromy.len() != n * n {
        return Err(Error::DimensionMismatch {
            what: "half monodromy",
            expected: n * n,
            found: half_monodromy.len(),
        });
    }
    let sym = symmetry_of(system)?;
    let half_map = floquet::matmul(n, &sym.block_ref(n), half_monodromy);
    let full_map = floquet::matmul(n, &half_map, &half_map);
    let half_period = half.period();
    let half_floquet = Floquet::from_monodromy(system, &half.params, half_period, half_map)?;
    let full = Floquet::from_monodromy(system, &half.params, 2.0 * half_period, full_map)?;
    Ok((half_floquet, full))
}

/// A solved symmetric orbit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SymmetricSolution {
    /// The full orbit, with the full period's multipliers ($\lambda = \mu^2$).
    pub full: OrbitSolution,
    /// The half orbit.
    pub half: PeriodicOrbit,
    /// Multipliers $\mu$ of the half map $S \circ \phi_{T/2}$, with the trivial ones flagged
    /// ($\mu = -1$: symmetry-breaking branch point; $\mu = +1$: fold).
    pub half_floquet: Floquet,
}

/// Solves the half-orbit problem of a symmetric orbit by shooting (half the unknowns of the full
/// problem), and returns the full orbit with both the half-map and the full multipliers.
///
/// # Errors
/// As [`super::solve_shooting`]; the guess must have a [`Closure::Symmetric`] signature.
pub fn solve_symmetric_shooting<S: HybridJacobians + ?Sized>(
    system: &S,
    half_guess: &PeriodicOrbit,
    settings: ShootingSettings,
    newton_settings: &NewtonSettings,
) -> Result<SymmetricSolution> {
    if half_guess.signature.closure() != Closure::Symmetric {
        return Err(Error::InvalidSignature {
            segment: 0,
            reason: "the half-orbit guess needs a symmetric closure".into(),
        });
    }
    half_guess.validate(system)?;
    half_guess.symmetry_at_starts(system)?;
    let mut problem = super::shooting_problem(system, half_guess, settings)?;
    let sol = crate::problem::newton(&mut problem, &super::pack(half_guess), newton_settings)?;
    let half = super::solved_orbit(half_guess, &sol.u, newton_settings);
    super::check_admissible(system, &half)?;
    // The wrap saltation of M_half already maps into sigma(m_0).
    let m_half = monodromy_by_shooting(system, &half, settings)?.monodromy;
    let (half_floquet, floquet) = symmetric_floquet(system, &half, &m_half)?;
    let full_orbit = half.unfold_symmetric(system)?;
    Ok(SymmetricSolution {
        full: OrbitSolution {
            orbit: full_orbit,
            floquet,
            newton: sol.history,
            residual: sol.residual,
        },
        half,
        half_floquet,
    })
}

/// Like [`solve_symmetric_shooting`], by collocation: the half orbit is solved by collocation
/// and the half-map multipliers come from its condensed Jacobian.
///
/// # Errors
/// As [`super::solve_collocation`]; the guess must have a [`Closure::Symmetric`] signature.
pub fn solve_symmetric_collocation<S: HybridJacobians + ?Sized>(
    system: &S,
    half_guess: &PeriodicOrbit,
    settings: super::CollocationSettings,
    newton_settings: &NewtonSettings,
) -> Result<SymmetricSolution> {
    if half_guess.signature.closure() != Closure::Symmetric {
        return Err(Error::InvalidSignature {
            segment: 0,
            reason: "the half-orbit guess needs a symmetric closure".into(),
        });
    }
    half_guess.validate(system)?;
    half_guess.symmetry_at_starts(system)?;
    let sol = super::collocation::solve_collocation_admissible(
        system,
        half_guess,
        settings,
        newton_settings,
    )?;
    let half = sol.solution.orbit.clone();
    let (half_floquet, floquet) =
        symmetric_floquet(system, &half, &sol.solution.floquet.monodromy)?;
    let full_orbit = half.unfold_symmetric(system)?;
    Ok(SymmetricSolution {
        full: OrbitSolution {
            orbit: full_orbit,
            floquet,
            newton: sol.solution.newton,
            residual: sol.solution.residual,
        },
        half,
        half_floquet,
    })
}

/// How [`find_symmetric_orbit`] looks for a symmetric orbit.
#[derive(Debug, Clone, PartialEq)]
pub struct SymmetricSearch {
    /// Start states of the half orbit's first segment to try (e.g. a grid of velocities and
    /// forcing phases on an impact surface).
    pub seeds: Vec<Vec<f64>>,
    /// The half orbit's duration, if it is known (half a forcing period for a forced system):
    /// guesses are ranked by it too, and only solutions with it (to `1e-6` relative) count.
    pub half_period: Option<f64>,
    /// The longest a segment may last when a seed is followed (default 100).
    pub max_duration: f64,
    /// How many of the best-ranked guesses Newton's method tries (default 12).
    pub candidates: usize,
    /// Integration settings for following the seeds (default `rtol = 1e-6`, `atol = 1e-8`: the
    /// guesses are only ranked).
    pub scan: SimulationSettings,
    /// Shooting settings of the Newton solves (default [`ShootingSettings::default`]).
    pub shooting: ShootingSettings,
    /// Newton settings (default [`NewtonSettings::default`]).
    pub newton: NewtonSettings,
}

impl SymmetricSearch {
    /// A search from `seeds` with the defaults above.
    #[must_use]
    pub fn new(seeds: Vec<Vec<f64>>) -> Self {
        Self {
            seeds,
            half_period: None,
            max_duration: 100.0,
            candidates: 12,
            scan: SimulationSettings::default().rtol(1e-6).atol(1e-8),
            shooting: ShootingSettings::default(),
            newton: NewtonSettings::default(),
        }
    }

    /// Sets the expected half-orbit duration.
    #[must_use]
    pub fn half_period(mut self, t: f64) -> Self {
        self.half_period = Some(t);
        self
    }
}

/// A $\mathbb{Z}_2$-symmetric periodic orbit whose half orbit has the signature `half`
/// ([`Closure::Symmetric`]): every seed is followed along the signature (each segment to its
/// end condition; a seed whose flow meets another event of the segment's mode first leaves
/// the signature and is dropped) and ranked by how nearly it closes, $\|x_K - S x_0\|_1$
/// (plus the relative miss of the half period, when given); Newton's method on the half-orbit
/// problem ([`solve_symmetric_shooting`]) is tried from the best-ranked guesses.
///
/// # Errors
/// A signature that is not a half orbit's, seeds or parameters of the wrong length or not
/// finite; [`Error::NotPeriodic`] if no seed reaches the end of the signature;
/// [`Error::NewtonFailed`] (the last failure) if no guess converges to an orbit with the
/// half period.
pub fn find_symmetric_orbit<S: HybridJacobians + ?Sized>(
    system: &S,
    half: &Signature,
    params: &[f64],
    search: &SymmetricSearch,
) -> Result<SymmetricSolution> {
    if half.closure() != Closure::Symmetric {
        return Err(Error::InvalidSignature {
            segment: 0,
            reason: "the search needs a half orbit's signature (symmetric closure)".into(),
        });
    }
    let sym = symmetry_of(system)?;
    check_len("parameters", params, system.parameter_count())?;
    check_finite("parameters", params)?;
    let first = half.segments()[0].mode;
    let n = system.mode_dim(first);
    for x0 in &search.seeds {
        check_len("seed", x0, n)?;
        check_finite("seed", x0)?;
        sym.check_at(system, first, &[x0], params)?;
    }
    let mut candidates = Vec::new();
    let mut image = vec![0.0; n];
    let mut sim = Simulator::new(search.scan.clone())?;
    for x0 in &search.seeds {
        check_len("seed", x0, n)?;
        check_finite("seed", x0)?;
        let Ok((guess, end)) = super::periodic_orbit::follow(
            &mut sim,
            system,
            half.clone(),
            x0,
            params,
            search.max_duration,
        ) else {
            continue;
        };
        sym.apply(x0, &mut image);
        let mut miss: f64 = end.iter().zip(&image).map(|(a, b)| (a - b).abs()).sum();
        if let Some(t) = search.half_period {
            miss += (guess.period() - t).abs() / t;
        }
        candidates.push((miss, guess));
    }
    if candidates.is_empty() {
        return Err(Error::NotPeriodic {
            reason: format!(
                "none of {} seeds reaches the end of the half orbit's signature",
                search.seeds.len()
            ),
        });
    }
    candidates.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut last_err = None;
    for (_, guess) in candidates.into_iter().take(search.candidates.max(1)) {
        match solve_symmetric_shooting(system, &guess, search.shooting, &search.newton) {
            Ok(sol)
                if search
                    .half_period
                    .is_none_or(|t| (sol.half.period() - t).abs() < 1e-6 * t) =>
            {
                return Ok(sol);
            }
            Ok(_) => {}
            Err(e) => last_err = Some(e),
        }
    }
    Err(last_err.unwrap_or_else(|| Error::NotPeriodic {
        reason: "no guess converged to an orbit with the expected half period".into(),
    }))
}

/// An orbit solved by [`solve_orbit`]: the solution (the full orbit, its multipliers) and, for
/// a symmetric orbit solved on its half orbit, the half map's multipliers.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SolvedOrbit {
    /// The full orbit with its multipliers.
    pub solution: OrbitSolution,
    /// The half map's multipliers $\mu$ ($\mu^2 = \lambda$) of a symmetric orbit.
    pub half_floquet: Option<Floquet>,
}

/// Solves the orbit near `guess` by `method`; a guess that is symmetric to `symmetric_tol`
/// ([`PeriodicOrbit::is_symmetric`]) is solved on its half orbit, with half the unknowns, and
/// reports the half map's multipliers too; so is a half orbit ([`Closure::Symmetric`]) given
/// as the guess. The solution is always the full orbit with the full period's multipliers.
///
/// # Errors
/// As [`super::solve_shooting`] and [`super::solve_collocation`].
pub fn solve_orbit<S: HybridJacobians + ?Sized>(
    system: &S,
    guess: &PeriodicOrbit,
    method: &super::OrbitMethod,
    newton: &NewtonSettings,
    symmetric_tol: f64,
) -> Result<SolvedOrbit> {
    use super::OrbitMethod;
    let half_given = guess.signature.closure() == Closure::Symmetric;
    if half_given || guess.is_symmetric(system, symmetric_tol) {
        let half = if half_given {
            guess.clone()
        } else {
            guess.half_of_symmetric(system, symmetric_tol)?
        };
        let sol = match *method {
            OrbitMethod::Shooting(s) => solve_symmetric_shooting(system, &half, s, newton)?,
            OrbitMethod::Collocation(c) => solve_symmetric_collocation(system, &half, c, newton)?,
        };
        return Ok(SolvedOrbit {
            solution: sol.full,
            half_floquet: Some(sol.half_floquet),
        });
    }
    let solution = match *method {
        OrbitMethod::Shooting(s) => super::solve_shooting(system, guess, s, newton)?,
        OrbitMethod::Collocation(c) => super::solve_collocation(system, guess, c, newton)?.solution,
    };
    Ok(SolvedOrbit {
        solution,
        half_floquet: None,
    })
}
