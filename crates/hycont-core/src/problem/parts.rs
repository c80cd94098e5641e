//! The pieces a [`super::Problem`] is made of: parts (blocks of equations) and monitor
//! functions, with the hints parts may use.

use crate::error::Result;

/// A block of equations over a list of the problem's unknowns.
pub trait ZeroFunction {
    /// Number of unknowns the part reads (the length of its local `u`).
    fn unknowns(&self) -> usize;
    /// Number of equations.
    fn equations(&self) -> usize;
    /// The Jacobian's non-zero entries as `(equation, local unknown)` pairs; fixed for the life
    /// of the part (a problem asks for them again whenever it builds its sparsity pattern,
    /// rather than keeping a copy).
    fn jacobian_pattern(&self) -> Vec<(usize, usize)>;
    /// The number of [`ZeroFunction::jacobian_pattern`]'s entries. The default builds the
    /// pattern to count it; a part with millions of entries says it directly (a problem checks
    /// the two agree when it builds its pattern).
    fn jacobian_len(&self) -> usize {
        self.jacobian_pattern().len()
    }
    /// Evaluates the residual (length [`ZeroFunction::equations`]) and, if asked, the Jacobian's
    /// values in the order of [`ZeroFunction::jacobian_pattern`].
    ///
    /// # Errors
    /// If the evaluation fails (e.g. an integration error in shooting).
    fn evaluate(
        &mut self,
        u: &[f64],
        residual: &mut [f64],
        jacobian: Option<&mut [f64]>,
    ) -> Result<()>;

    /// Like [`ZeroFunction::evaluate`] with hints on the Jacobian: which local unknowns the
    /// problem holds fixed, and what the Jacobian is for. Parts may use them to save work (see
    /// [`JacobianHints`]); the residual must be exact. The default evaluates everything.
    ///
    /// # Errors
    /// As [`ZeroFunction::evaluate`].
    fn evaluate_hinted(
        &mut self,
        u: &[f64],
        residual: &mut [f64],
        jacobian: Option<&mut [f64]>,
        hints: JacobianHints<'_>,
    ) -> Result<()> {
        let _ = hints;
        self.evaluate(u, residual, jacobian)
    }

    /// Whether [`ZeroFunction::evaluate`] (and [`ZeroFunction::evaluate_hinted`], under any
    /// hints) writes every Jacobian value of the pattern. The problem then hands the part its
    /// values as they are (from the last evaluation) instead of zeroing them first; the default,
    /// `false`, suits parts that leave some entries at zero (structural zeros of a particular
    /// evaluation, or entries skipped under hints).
    fn writes_every_entry(&self) -> bool {
        false
    }

    /// Groups of local unknowns that, among this part's equations, only one group of equations
    /// reads (see [`LocalBlock`]). The problem condenses them by small dense eliminations before
    /// its sparse factorisation; the default declares none.
    fn local_blocks(&self) -> Vec<LocalBlock> {
        Vec::new()
    }
}

/// Local unknowns of a part that, among the part's equations, only `equations` read, with
/// `equations.len() >= unknowns.len()` (e.g. collocation: the interior nodes of one mesh
/// interval and that interval's collocation equations). Other parts and monitors may read them
/// (an arclength or phase condition), at the cost of one dense row each; no other block's
/// equations may. Declaring them lets [`super::Problem::factorize`] and continuation eliminate
/// them block by block (static condensation, as AUTO and COCO do for collocation), so the sparse
/// LU only sees the much smaller coupled system.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LocalBlock {
    /// The block's equations (indices into the part's equations).
    pub equations: std::ops::Range<usize>,
    /// The block's unknowns (indices into the part's local unknowns).
    pub unknowns: std::ops::Range<usize>,
}

/// What a Jacobian evaluation is for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum JacobianUse {
    /// Everything: tangents, determinants, Floquet multipliers from the linearisation. As
    /// accurate as the residual.
    #[default]
    Exact,
    /// A Newton (chord) direction only. An approximate Jacobian changes the convergence rate,
    /// not the solution (the exact residual decides convergence), so a part may compute it more
    /// cheaply; shooting integrates the variational equations at a looser tolerance.
    NewtonDirection,
}

/// Hints passed to [`ZeroFunction::evaluate_hinted`].
#[derive(Debug, Clone, Copy)]
pub struct JacobianHints<'a> {
    /// `held[j]`: local unknown `j` is held fixed by the problem (an inactive monitor of that
    /// unknown alone, at its value). Newton steps, tangents and the determinant's sign do not
    /// depend on the Jacobian's entries in held columns (the monitor's row pins the unknown's
    /// change to zero), so they may be left zero where expensive (shooting: a parameter's
    /// sensitivities).
    pub held: &'a [bool],
    /// What the Jacobian is for.
    pub purpose: JacobianUse,
}

/// A scalar function $\psi(u)$ of some of the problem's unknowns.
pub trait MonitorFunction {
    /// Number of unknowns the monitor reads.
    fn unknowns(&self) -> usize;
    /// The value, and the gradient (length [`MonitorFunction::unknowns`]) if asked.
    ///
    /// # Errors
    /// If the evaluation fails.
    fn evaluate(&mut self, u: &[f64], gradient: Option<&mut [f64]>) -> Result<f64>;
}

/// A monitor of a single unknown: $\psi(u) = u_0$ (how parameters enter a problem).
#[derive(Debug, Clone, Copy, Default)]
pub struct UnknownMonitor;

impl MonitorFunction for UnknownMonitor {
    fn unknowns(&self) -> usize {
        1
    }
    fn evaluate(&mut self, u: &[f64], gradient: Option<&mut [f64]>) -> Result<f64> {
        if let Some(g) = gradient {
            g[0] = 1.0;
        }
        Ok(u[0])
    }
}
