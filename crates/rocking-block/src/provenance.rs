//! Where a result file came from: every JSON the command line writes carries a `provenance`
//! object (hycont's version, the command line, the block and its dimensional inputs, the
//! parameters, the seed and trials) so that the file says how to reproduce it.

use crate::block::{Block, DimensionalInputs};
use crate::continuation::Recipe;
use crate::model::Parameters;
use serde::{Deserialize, Serialize};
use serde_json::Value;

/// hycont's version (the workspace's, which this crate shares).
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

/// How a result was asked for: the invocation, and what it was run on.
///
/// ```
/// use rocking_block::provenance::Provenance;
/// let p = Provenance::from_command_line(["rocking-block", "figure", "3"]).with_seed(7);
/// let v = p.insert_into(serde_json::json!({"figure": 3}));
/// assert_eq!(v["provenance"]["command_line"][1], "figure");
/// assert_eq!(v["provenance"]["seed"], 7);
/// assert_eq!(v["provenance"]["block"]["theta_b"], 0.8795);
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Provenance {
    /// hycont's version that wrote the file.
    pub hycont_version: String,
    /// The command line (program and arguments), when the result came from one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub command_line: Option<Vec<String>>,
    /// The block, dimensionless.
    #[serde(default)]
    pub block: Block,
    /// The dimensional inputs the block and forcing came from, when given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dimensional: Option<DimensionalInputs>,
    /// The parameters of a result at one parameter point (an orbit, a simulation, a
    /// continuation's start).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub parameters: Option<Parameters>,
    /// The seed of a sampled result.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seed: Option<u64>,
    /// The trials asked for of a sampled result (per study; see the file for those counted).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub trials: Option<u64>,
    /// How the branches were continued, when not by the study's [`Recipe`] (the branch
    /// figures 3 to 5 compute by it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub recipe: Option<Recipe>,
}

impl Default for Provenance {
    /// This version, the study's block, no command line (a library call).
    fn default() -> Self {
        Self {
            hycont_version: VERSION.to_string(),
            command_line: None,
            block: Block::default(),
            dimensional: None,
            parameters: None,
            seed: None,
            trials: None,
            recipe: None,
        }
    }
}

impl Provenance {
    /// The provenance of a command line (program first).
    #[must_use]
    pub fn from_command_line<I: IntoIterator<Item = S>, S: Into<String>>(args: I) -> Self {
        Self {
            command_line: Some(args.into_iter().map(Into::into).collect()),
            ..Self::default()
        }
    }

    /// With the block.
    #[must_use]
    pub fn with_block(self, block: Block) -> Self {
        Self { block, ..self }
    }

    /// With the parameters of a one-point result (and their block).
    #[must_use]
    pub fn with_parameters(self, params: Parameters) -> Self {
        Self {
            block: params.block(),
            parameters: Some(params),
            ..self
        }
    }

    /// With dimensional inputs (or none).
    #[must_use]
    pub fn with_dimensional(self, dimensional: Option<DimensionalInputs>) -> Self {
        Self {
            dimensional,
            ..self
        }
    }

    /// With a seed.
    #[must_use]
    pub fn with_seed(self, seed: u64) -> Self {
        Self {
            seed: Some(seed),
            ..self
        }
    }

    /// With the trials asked for.
    #[must_use]
    pub fn with_trials(self, trials: u64) -> Self {
        Self {
            trials: Some(trials),
            ..self
        }
    }

    /// With the continuation recipe (recorded only when it is not the study's).
    #[must_use]
    pub fn with_recipe(self, recipe: Recipe) -> Self {
        Self {
            recipe: (!recipe.is_study()).then_some(recipe),
            ..self
        }
    }

    /// The continuation recipe of the branch figures (the study's unless one was given).
    #[must_use]
    pub fn recipe(&self) -> Recipe {
        self.recipe.unwrap_or_default()
    }

    /// `value` (a JSON object) with a `provenance` entry; other values are wrapped as
    /// `{"result": value, "provenance": ...}`.
    #[must_use]
    pub fn insert_into(&self, value: Value) -> Value {
        let me = serde_json::to_value(self).expect("provenance serialises");
        match value {
            Value::Object(mut map) => {
                map.insert("provenance".into(), me);
                Value::Object(map)
            }
            other => serde_json::json!({"result": other, "provenance": me}),
        }
    }
}
