//! The rocking block's solution classes (the study's basin-stability classes) from hycont's
//! stroboscopic classifier ([`hycont_sample::classify`]): the block compares $(\varphi, \psi)$
//! at the strobes $t = 2\pi k/\omega$, rest is absorbing where lift-off is impossible
//! ($\alpha\omega^2\tan\theta_b \le 1$), and the classes are
//! - **overturn_pos / overturn_neg**: the terminal overturn events ($|\varphi| = \pi/2$);
//! - **equilibrium**: absorbed at rest;
//! - **symmetric_p1**: period 1 with the half-period sample the $S$-image of the strobe
//!   sample; **asymmetric_p1_pos / _neg**: period 1 otherwise, by the sign of the mean of
//!   $\varphi$ over a period; **period2**;
//! - **other**: periods above 2 (recognised by repetition) and motions not decided within
//!   `max_periods` (chaos, long transients).
//!
//! Orbits that include rest (sticking) phases are classified by their periodicity and symmetry
//! like any other, and flagged `with_rest` (reported separately by the figures): at
//! $\alpha = 0.66$ true rest is absorbing only for $\omega < 1.1197$, so the study's
//! "equilibrium" at $\omega = 1.16$ is such rocking with rest phases.

use crate::error::Result;
use crate::model::{OVERTURN_POS, Parameters, REST, RockingBlock, initial_mode, initial_state};
use hycont_sample::classify::{
    Attractor, Decision as GenericDecision, PeriodicallyForced, StrobeSettings,
};
use serde::{Deserialize, Serialize};

/// The study's solution classes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Class {
    /// At rest for good.
    Equilibrium,
    /// Symmetric period-1 rocking.
    SymmetricP1,
    /// Asymmetric period-1 rocking leaning to $\varphi > 0$.
    AsymmetricP1Pos,
    /// Asymmetric period-1 rocking leaning to $\varphi < 0$.
    AsymmetricP1Neg,
    /// Period-2 rocking.
    Period2,
    /// Anything else (periods above 2, chaos, undecided).
    Other,
    /// Overturned to $\varphi = \pi/2$.
    OverturnPos,
    /// Overturned to $\varphi = -\pi/2$.
    OverturnNeg,
}

impl Class {
    /// All classes, in a fixed order (the index used in count tables).
    pub const ALL: [Class; 8] = [
        Class::Equilibrium,
        Class::SymmetricP1,
        Class::AsymmetricP1Pos,
        Class::AsymmetricP1Neg,
        Class::Period2,
        Class::Other,
        Class::OverturnPos,
        Class::OverturnNeg,
    ];

    /// The snake-case name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Class::Equilibrium => "equilibrium",
            Class::SymmetricP1 => "symmetric_p1",
            Class::AsymmetricP1Pos => "asymmetric_p1_pos",
            Class::AsymmetricP1Neg => "asymmetric_p1_neg",
            Class::Period2 => "period2",
            Class::Other => "other",
            Class::OverturnPos => "overturn_pos",
            Class::OverturnNeg => "overturn_neg",
        }
    }

    /// Index in [`Class::ALL`].
    #[must_use]
    pub fn index(self) -> usize {
        Class::ALL
            .iter()
            .position(|c| *c == self)
            .expect("every class is listed")
    }
}

/// Settings of the classifier: hycont's stroboscopic classifier's (defaults as documented
/// there).
pub type ClassifierSettings = StrobeSettings;

/// How a trial was decided.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Decision {
    /// A terminal event (overturn).
    Event,
    /// At rest with lift-off impossible.
    Rest,
    /// Strobe samples repeated to the tolerance.
    Converged,
    /// Geometric convergence extrapolated.
    Extrapolated,
    /// A Newton refinement of the stroboscopic map found the (stable) orbit.
    Newton,
    /// `max_periods` reached.
    Undecided,
}

/// The result of classifying one trial.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Classification {
    /// The class.
    pub class: Class,
    /// How it was decided.
    pub decision: Decision,
    /// Forcing periods simulated.
    pub periods: usize,
    /// Whether the final motion includes rest (sticking) phases.
    pub with_rest: bool,
}

/// The block as a periodically forced system: strobes compare $(\varphi, \psi)$; rest is
/// absorbing where lift-off is impossible.
impl PeriodicallyForced for RockingBlock {
    fn forcing_period(&self, p: &[f64]) -> f64 {
        Parameters::from_vec(p).forcing_period()
    }
    fn strobe_components(&self) -> &[usize] {
        &[0, 1]
    }
    fn mode_at(&self, x: &[f64], p: &[f64]) -> hycont_core::Mode {
        initial_mode(&[x[0], x[1], x[2], x[3]], &Parameters::from_vec(p))
    }
    fn absorbed(&self, mode: hycont_core::Mode, _: &[f64], p: &[f64]) -> bool {
        mode == REST && !Parameters::from_vec(p).lift_off_possible()
    }
}

/// Classifies the motion from $(\varphi_0, \psi_0)$ with forcing phase $\beta$ into the
/// study's classes.
///
/// # Errors
/// Invalid parameters, an initial condition refused by [`crate::simulation::check_start`], or an
/// integration failure.
pub fn classify(
    params: &Parameters,
    beta: f64,
    phi0: f64,
    psi0: f64,
    settings: &ClassifierSettings,
) -> Result<Classification> {
    params.validate()?;
    crate::simulation::check_start(phi0, psi0, beta)?;
    let x0 = initial_state(phi0, psi0, beta);
    let mode = initial_mode(&x0, params);
    let c = hycont_sample::classify::classify(&RockingBlock, &params.to_vec(), mode, &x0, settings)
        .map_err(|e| match e {
            hycont_sample::Error::Core(c) => crate::Error::Core(c),
            other => crate::Error::NoOrbit(other.to_string()),
        })?;
    let with_rest = c.modes.contains(&REST) || c.zeno;
    let class = match c.attractor {
        Attractor::Terminal { event } if event == OVERTURN_POS => Class::OverturnPos,
        Attractor::Terminal { .. } => Class::OverturnNeg,
        Attractor::Absorbed => Class::Equilibrium,
        Attractor::Periodic {
            period: 1,
            symmetric: true,
        } => Class::SymmetricP1,
        Attractor::Periodic { period: 1, .. } if c.mean[0] > 0.0 => Class::AsymmetricP1Pos,
        Attractor::Periodic { period: 1, .. } => Class::AsymmetricP1Neg,
        Attractor::Periodic { period: 2, .. } => Class::Period2,
        Attractor::Periodic { .. } => Class::Other,
        Attractor::Undecided => Class::Other,
    };
    let decision = match c.decision {
        GenericDecision::Event => Decision::Event,
        GenericDecision::Absorbed => Decision::Rest,
        GenericDecision::Converged => Decision::Converged,
        GenericDecision::Extrapolated => Decision::Extrapolated,
        GenericDecision::Newton => Decision::Newton,
        _ => Decision::Undecided,
    };
    Ok(Classification {
        class,
        decision,
        periods: c.periods,
        with_rest: with_rest && !matches!(c.attractor, Attractor::Terminal { .. }),
    })
}

/// The rocking block's classifier for [`hycont_sample::basin`] studies with variables
/// `[omega, alpha, beta, phi0, psi0]` (the study's default damping and slenderness).
///
/// Its classes are the eight of [`Class::ALL`], then the periodic and other classes again with
/// the suffix `_with_rest` for motions that include rest phases (so that the counts report
/// them separately); [`base_class`] maps an index back to the study's class.
#[derive(Debug, Clone, Copy, Default)]
pub struct RockingClassifier {
    /// Classifier settings.
    pub settings: ClassifierSettings,
    /// The block (the trials give the forcing).
    pub block: crate::block::Block,
}

/// Classes that can carry rest phases (counted separately with `_with_rest`).
const WITH_REST: [Class; 5] = [
    Class::SymmetricP1,
    Class::AsymmetricP1Pos,
    Class::AsymmetricP1Neg,
    Class::Period2,
    Class::Other,
];

/// The study class of a [`RockingClassifier`] class index, and whether it had rest phases.
#[must_use]
pub fn base_class(index: usize) -> (Class, bool) {
    if index < Class::ALL.len() {
        (Class::ALL[index], false)
    } else {
        (WITH_REST[index - Class::ALL.len()], true)
    }
}

impl hycont_sample::basin::Classifier for RockingClassifier {
    fn classes(&self) -> Vec<String> {
        Class::ALL
            .iter()
            .map(|c| c.name().to_string())
            .chain(WITH_REST.iter().map(|c| format!("{}_with_rest", c.name())))
            .collect()
    }
    fn classify(&self, v: &[f64]) -> std::result::Result<usize, String> {
        let c = classify(&self.block.at(v[0], v[1]), v[2], v[3], v[4], &self.settings)
            .map_err(|e| e.to_string())?;
        Ok(match WITH_REST.iter().position(|x| *x == c.class) {
            Some(i) if c.with_rest => Class::ALL.len() + i,
            _ => c.class.index(),
        })
    }
}

/// The CSV columns of a batch of trials, in the order [`parse_trials`] returns them.
pub const TRIAL_COLUMNS: [&str; 5] = ["omega", "alpha", "beta", "phi0", "psi0"];

/// Reads a CSV batch of trials: a header naming (at least) the columns of [`TRIAL_COLUMNS`] in
/// any order, then one trial per line (blank lines skipped); each row as
/// `[omega, alpha, beta, phi0, psi0]`.
///
/// # Errors
/// One line naming the problem: a missing column, a line with too few fields, a field that is
/// not a finite number (with its line number).
///
/// ```
/// use rocking_block::classes::parse_trials;
/// let rows = parse_trials("phi0,psi0,omega,alpha,beta\n0.01,0,1.3,0.66,0\n").unwrap();
/// assert_eq!(rows, vec![[1.3, 0.66, 0.0, 0.01, 0.0]]);
/// assert!(parse_trials("omega,alpha\n1,2\n").is_err());
/// assert!(parse_trials("omega,alpha,beta,phi0,psi0\n1,2,NaN,0,0\n").is_err());
/// ```
pub fn parse_trials(text: &str) -> std::result::Result<Vec<[f64; 5]>, String> {
    let mut lines = text.lines();
    let header: Vec<&str> = lines
        .next()
        .unwrap_or("")
        .split(',')
        .map(str::trim)
        .collect();
    let mut cols = [0usize; 5];
    for (c, name) in cols.iter_mut().zip(TRIAL_COLUMNS) {
        *c = header.iter().position(|h| *h == name).ok_or_else(|| {
            format!(
                "the header must name the columns {}; it has no {name}",
                TRIAL_COLUMNS.join(", ")
            )
        })?;
    }
    let mut rows = Vec::new();
    for (i, line) in lines.enumerate().filter(|(_, l)| !l.trim().is_empty()) {
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        let mut v = [0.0; 5];
        for ((x, &c), name) in v.iter_mut().zip(&cols).zip(TRIAL_COLUMNS) {
            *x = fields
                .get(c)
                .and_then(|f| f.parse::<f64>().ok())
                .filter(|x| x.is_finite())
                .ok_or_else(|| format!("line {}: {name} is not a finite number", i + 2))?;
        }
        rows.push(v);
    }
    Ok(rows)
}
