//! `basin`: basin stability of a block for user ranges, with shards, resuming and merging as
//! the sampling figures (see [`super::sampling`]).

use super::basin_cells::BasinCellFile;
use super::basin_file::BasinFile;
use super::block_args::{BlockArgs, figure_dimensional};
use super::driver::CountFile;
use super::driver::{
    cell_rule, parse_shard, sample, set_threads, spec_err, stop_on_signals, use_up,
};
use super::print_written;
use super::shard_file::MAX_TRIALS;
use crate::basin::{VARIABLES, classifier, validate};
use crate::block::Block;
use crate::error::{Error, Result};
use crate::output::{Format, OutDir};
use crate::provenance::Provenance;
use clap::Args;
use hycont_sample::basin::{Axis, Counts, Distribution, Progress, Study};
use std::io::Write;
use std::path::PathBuf;
use std::sync::Arc;

/// Arguments of `rocking-block basin`.
#[derive(Debug, Args)]
pub struct BasinArgs {
    /// Forcing frequency: a value, or LO:HI for uniform draws.
    #[arg(long, default_value = "1.3", allow_hyphen_values = true)]
    pub omega: String,
    /// Forcing amplitude: a value or LO:HI.
    #[arg(long, default_value = "0.66", allow_hyphen_values = true)]
    pub alpha: String,
    /// Forcing phase: a value or LO:HI.
    #[arg(long, default_value = "0", allow_hyphen_values = true)]
    pub beta: String,
    /// Initial angle: a value or LO:HI [default: uniform within the static boundary,
    /// -(pi/2 - theta_b):(pi/2 - theta_b), as Fig. 7].
    #[arg(long, allow_hyphen_values = true)]
    pub phi0: Option<String>,
    /// Initial angular velocity: a value or LO:HI [default: -1:1, as Fig. 7].
    #[arg(long, default_value = "-1:1", allow_hyphen_values = true)]
    pub psi0: String,
    /// Bin the trials on a uniform variable, NAME:BINS (repeat for a 2-D map; at most two).
    #[arg(long)]
    pub bin: Vec<String>,
    /// Trials.
    #[arg(long, default_value_t = 2000, allow_hyphen_values = true)]
    pub trials: u64,
    /// Instead of --trials: draw trials cell by cell (binned variables uniform inside each
    /// cell) until every class's 95 % Wilson half-width in every cell is at most this, or the
    /// cell has --max-per-cell trials.
    #[arg(long, conflicts_with = "trials", allow_hyphen_values = true)]
    pub halfwidth: Option<f64>,
    /// With --halfwidth: most trials per cell.
    #[arg(long, default_value_t = 4096, allow_hyphen_values = true)]
    pub max_per_cell: u64,
    /// Seed (results are identical for a seed whatever the threads).
    #[arg(long, default_value_t = 1, allow_hyphen_values = true)]
    pub seed: u64,
    /// Worker threads (default: all cores).
    #[arg(long, allow_hyphen_values = true)]
    pub threads: Option<usize>,
    /// Run only shard I of N (0-based, `I/N`) and write DIR/basin.shard-I-of-N.json, for
    /// `rocking-block merge`.
    #[arg(long)]
    pub shard: Option<String>,
    /// Complete an interrupted run or shard from its `*.partial.json` file.
    #[arg(long, conflicts_with_all = ["omega", "alpha", "beta", "phi0", "psi0", "bin", "trials", "seed", "shard", "halfwidth"])]
    pub resume: Option<PathBuf>,
    /// Stop once this many trials of the run are counted (those of a resumed file included;
    /// whole chunks of 256 per thread), as an interrupt would: the counts go to the partial
    /// file, to be completed with --resume.
    #[arg(long, allow_hyphen_values = true)]
    pub stop_after: Option<u64>,
    /// An interrupted run also writes the result of the trials counted so far.
    #[arg(long)]
    pub force: bool,
    /// Output directory: basin.json, basin.csv and basin.svg.
    #[arg(long, default_value = "results")]
    pub out: PathBuf,
    /// Picture format: basin.svg, basin.png or both.
    #[arg(long, value_enum, default_value_t = Format::Svg)]
    pub format: Format,
    /// Print the files written as JSON (`{"files": [...]}`).
    #[arg(long)]
    pub json: bool,
    /// The block.
    #[command(flatten)]
    pub block: BlockArgs,
}

/// A variable's distribution from `VALUE` or `LO:HI`.
fn distribution(name: &'static str, text: &str) -> Result<Distribution> {
    text.parse().map_err(spec_err(name))
}

impl BasinArgs {
    /// The study the arguments describe, for `block`.
    fn study(&self, block: &Block) -> Result<Study> {
        let b = block.static_boundary();
        let phi0 = self.phi0.clone().unwrap_or_else(|| format!("{}:{b}", -b));
        let variables = vec![
            distribution("omega", &self.omega)?,
            distribution("alpha", &self.alpha)?,
            distribution("beta", &self.beta)?,
            distribution("phi0", &phi0)?,
            distribution("psi0", &self.psi0)?,
        ];
        let names: Vec<String> = VARIABLES.iter().map(ToString::to_string).collect();
        if self.bin.len() > 2 {
            return Err(Error::InvalidArgument {
                name: "bin",
                value: self.bin.join(" "),
                reason: "bin on at most two variables",
            });
        }
        let axes = self
            .bin
            .iter()
            .map(|t| Axis::parse(t, &names, &variables).map_err(spec_err("bin")))
            .collect::<Result<Vec<_>>>()?;
        let study = Study {
            names,
            variables,
            axes,
            seed: self.seed,
        };
        validate(&study, block)?;
        Ok(study)
    }
}

pub(super) fn run_basin(
    args: &BasinArgs,
    invocation: &Provenance,
    out: &mut dyn Write,
) -> Result<()> {
    if args.resume.is_some() && args.block.given() {
        return Err(Error::InvalidArgument {
            name: "block options",
            value: "given with --resume".into(),
            reason: "a resumed run keeps the block it was started for",
        });
    }
    set_threads(args.threads)?;
    crate::output::check_dir(&args.out)?;
    let progress = Arc::new(Progress {
        budget: args.stop_after,
        ..Progress::default()
    });
    stop_on_signals(&progress);
    let dir = OutDir::new(&args.out).with_format(args.format);
    let cells = match &args.resume {
        Some(path) if super::cell_file::is_cell_file(path) => Some(BasinCellFile::read(path)?),
        Some(_) => None,
        None => match args.halfwidth {
            Some(h) => {
                let rule = cell_rule(h, args.max_per_cell)?;
                let block = args.block.block()?;
                let shard = args.shard.as_deref().map(parse_shard).transpose()?;
                let mut file =
                    BasinCellFile::new(args.study(&block)?, rule, shard.unwrap_or((0, 1)), block);
                file.provenance = Some(
                    invocation
                        .clone()
                        .with_dimensional(figure_dimensional(&args.block)?),
                );
                Some(file)
            }
            None => None,
        },
    };
    if let Some(file) = cells {
        let files = sample(file, &dir, args.force, &progress)?;
        if let Some(from) = &args.resume {
            use_up(from, &files);
        }
        return print_written(out, &files, args.json);
    }
    let file = match &args.resume {
        Some(path) => BasinFile::read(path)?,
        None => {
            if !(1..=MAX_TRIALS).contains(&args.trials) {
                return Err(Error::InvalidArgument {
                    name: "trials",
                    value: args.trials.to_string(),
                    reason: "must be in 1..=10^12 (shard larger studies into separate runs)",
                });
            }
            let block = args.block.block()?;
            let study = args.study(&block)?;
            let classes = hycont_sample::basin::Classifier::classes(&classifier(&block));
            BasinFile {
                counts: Counts::new(classes, study.cells()),
                study,
                block,
                trials: args.trials,
                shard: args
                    .shard
                    .as_deref()
                    .map(parse_shard)
                    .transpose()?
                    .unwrap_or((0, 1)),
                provenance: Some(
                    invocation
                        .clone()
                        .with_dimensional(figure_dimensional(&args.block)?),
                ),
            }
        }
    };
    let files = sample(file, &dir, args.force, &progress)?;
    if let Some(from) = &args.resume {
        use_up(from, &files);
    }
    print_written(out, &files, args.json)
}
