//! `basin`: basin stability of a block for user ranges, with shards, resuming and merging as
//! the sampling figures (see [`super::sampling`]).

use super::basin_cells::{BasinCellFile, basin_rule};
use super::block_args::{BlockArgs, figure_dimensional};
use super::sampling::{CountFile, Todo, parse_shard, sample, set_threads, stop_on_signals, use_up};
use super::shard_file::{MAX_TRIALS, count_paths, write_count_file};
use super::{print_written, read_err};
use crate::basin::{VARIABLES, classifier, folded, result_csv, result_json, validate};
use crate::block::Block;
use crate::error::{Error, Result};
use crate::output::{Format, OutDir};
use crate::provenance::Provenance;
use clap::Args;
use hycont_sample::basin::{Axis, Counts, Distribution, Progress, Study, run};
use std::io::Write;
use std::path::{Path, PathBuf};
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
    let bad = |reason| Error::InvalidArgument {
        name,
        value: text.to_string(),
        reason,
    };
    let number = |t: &str| {
        t.trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| bad("expected a finite number or LO:HI"))
    };
    match text.split_once(':') {
        None => Ok(Distribution::Fixed(number(text)?)),
        Some((lo, hi)) => {
            let (lo, hi) = (number(lo)?, number(hi)?);
            if lo < hi {
                Ok(Distribution::Uniform { lo, hi })
            } else {
                Err(bad("LO must be below HI"))
            }
        }
    }
}

/// The binning axis of `NAME:BINS` over the named uniform variable's range.
fn axis(text: &str, variables: &[Distribution]) -> Result<Axis> {
    let bad = |reason| Error::InvalidArgument {
        name: "bin",
        value: text.to_string(),
        reason,
    };
    let (name, bins) = text
        .split_once(':')
        .ok_or_else(|| bad("expected NAME:BINS, e.g. phi0:40"))?;
    let variable = VARIABLES
        .iter()
        .position(|v| *v == name.trim())
        .ok_or_else(|| bad("NAME must be omega, alpha, beta, phi0 or psi0"))?;
    let bins: usize = bins
        .trim()
        .parse()
        .ok()
        .filter(|b| (1..=10_000).contains(b))
        .ok_or_else(|| bad("BINS must be in 1..=10000"))?;
    match variables[variable] {
        Distribution::Uniform { lo, hi } => Ok(Axis {
            variable,
            lo,
            hi,
            bins,
        }),
        Distribution::Fixed(_) => Err(bad("bin a variable drawn from a range (LO:HI)")),
    }
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
            .map(|t| axis(t, &variables))
            .collect::<Result<Vec<_>>>()?;
        let study = Study {
            names: VARIABLES.iter().map(ToString::to_string).collect(),
            variables,
            axes,
            seed: self.seed,
        };
        validate(&study, block)?;
        Ok(study)
    }
}

/// The counts of a basin run over one shard of its trials, complete or not.
#[derive(Debug, serde::Serialize, serde::Deserialize)]
pub struct BasinFile {
    /// The study (variables, axes, seed).
    pub study: Study,
    /// The block.
    pub block: Block,
    /// Trials of the whole run.
    pub trials: u64,
    /// `(i, n)`: shard `i` of `n` (a whole run is `(0, 1)`).
    pub shard: (u64, u64),
    /// The counts (classes as [`crate::classes::RockingClassifier`]'s).
    pub counts: Counts,
    /// The invocation that started the run (for a merge: the merge).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub provenance: Option<Provenance>,
}

/// Whether `path` holds a basin file (rather than a sampling figure's shard).
pub(super) fn is_basin_file(path: &Path) -> bool {
    std::fs::read_to_string(path)
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .is_some_and(|v| v.get("study").is_some())
}

impl BasinFile {
    /// Reads and checks a file.
    ///
    /// # Errors
    /// [`Error::Read`], or [`Error::InvalidFile`] naming what is wrong.
    pub fn read(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(read_err(path))?;
        let invalid = |reason: String| Error::InvalidFile {
            path: path.to_path_buf(),
            reason,
        };
        let file: BasinFile = serde_json::from_str(&text)
            .map_err(|e| invalid(format!("not a basin file written by `basin` ({e})")))?;
        file.check().map_err(invalid)?;
        Ok(file)
    }

    fn check(&self) -> std::result::Result<(), String> {
        validate(&self.study, &self.block).map_err(|e| e.to_string())?;
        let (i, n) = self.shard;
        if self.trials == 0 || self.trials > MAX_TRIALS || n == 0 || i >= n {
            return Err(format!(
                "{} trials, shard {i}/{n}: need 1..=10^12 trials and 0 <= I < N",
                self.trials
            ));
        }
        let classes = hycont_sample::basin::Classifier::classes(&classifier(&self.block));
        if self.counts.classes != classes || self.counts.counts.len() != self.study.cells() {
            return Err(format!(
                "{} cells of classes {:?}; the study has {} cells of {:?}",
                self.counts.counts.len(),
                self.counts.classes,
                self.study.cells(),
                classes
            ));
        }
        self.counts.validate().map_err(|e| e.to_string())?;
        let range = self.range();
        if let Some(&(a, b)) = self
            .counts
            .ranges
            .iter()
            .find(|&&(a, b)| a < range.start || b > range.end)
        {
            return Err(format!(
                "counts trials {a}..{b}, outside the shard's trials {}..{}",
                range.start, range.end
            ));
        }
        Ok(())
    }

    fn range(&self) -> std::ops::Range<u64> {
        let (i, n) = self.shard;
        hycont_sample::basin::shard_range(self.trials, i, n).unwrap_or(0..0)
    }
}

impl CountFile for BasinFile {
    type Error = crate::error::Error;
    fn what(&self) -> String {
        "basin".into()
    }
    fn progress(&self) -> (u64, u64) {
        let range = self.range();
        let missing: u64 = self
            .counts
            .missing(range.clone())
            .iter()
            .map(|r| r.end - r.start)
            .sum();
        let per = range.end - range.start;
        (per - missing, per)
    }
    fn shard(&self) -> (u64, u64) {
        self.shard
    }
    fn paths(&self, dir: &Path) -> (PathBuf, PathBuf) {
        count_paths(dir, "basin", self.shard)
    }
    fn todo(&self, part: (u64, u64)) -> Result<Todo> {
        let missing = self.counts.missing(self.range());
        Ok(vec![
            hycont_sample::basin::share(&missing, part.0, part.1)
                .map_err(crate::figures::sampling::sample_err)?,
        ])
    }
    fn fill(&mut self, todo: &[Vec<std::ops::Range<u64>>], progress: &Progress) -> Result<()> {
        let c = classifier(&self.block);
        for r in todo.iter().flatten() {
            let counted = run(&self.study, &c, r.clone(), progress)
                .map_err(crate::figures::sampling::sample_err)?;
            self.counts
                .merge(&counted)
                .map_err(crate::figures::sampling::sample_err)?;
        }
        Ok(())
    }
    fn cleared(&self) -> Self {
        BasinFile {
            study: self.study.clone(),
            block: self.block,
            trials: self.trials,
            shard: self.shard,
            counts: Counts::new(self.counts.classes.clone(), self.counts.counts.len()),
            provenance: self.provenance.clone(),
        }
    }
    fn read(path: &Path) -> Result<Self> {
        BasinFile::read(path)
    }
    fn subsumes(&self, other: &Self) -> bool {
        (&self.study, self.block, self.trials, self.shard)
            == (&other.study, other.block, other.trials, other.shard)
            && super::shard_file::covers(&self.counts, &other.counts, &self.range())
    }
    fn write(&self, path: &Path) -> Result<()> {
        write_count_file(self, path)
    }
    fn merge(&mut self, other: &Self) -> std::result::Result<(), String> {
        if (&self.study, self.block, self.trials) != (&other.study, other.block, other.trials) {
            return Err("another study, block or trial count than the files before".into());
        }
        self.counts.merge(&other.counts).map_err(|e| e.to_string())
    }
    fn whole(self) -> Self {
        BasinFile {
            shard: (0, 1),
            ..self
        }
    }
}

/// The picture's title: the fixed variables and the block.
/// Writes a basin's files: `basin.json` (the result with `provenance`, completed with the
/// block and seed, and amended by `extra`), `basin.csv` and the picture.
pub(super) fn write_basin(
    out: &OutDir,
    study: &Study,
    block: &Block,
    counts: &Counts,
    provenance: Provenance,
    extra: impl FnOnce(&mut serde_json::Value),
) -> Result<Vec<PathBuf>> {
    let provenance = provenance.with_block(*block).with_seed(study.seed);
    let json_path = out.join("basin.json");
    let mut value = result_json(study, counts);
    extra(&mut value);
    crate::figures::write_json(&json_path, &provenance.insert_into(value))?;
    let csv_path = out.join("basin.csv");
    crate::output::write_atomic(&csv_path, result_csv(study, counts))?;
    let title = title(study, block, counts);
    let pictures = out.picture("basin", |p| {
        crate::plot::basin_svg(p, &title, study, &folded(counts))
    })?;
    Ok([vec![json_path, csv_path], pictures].concat())
}

fn title(study: &Study, block: &Block, counts: &Counts) -> String {
    let fixed: Vec<String> = study
        .names
        .iter()
        .zip(&study.variables)
        .filter_map(|(n, d)| match d {
            Distribution::Fixed(v) => Some(format!("{n} = {v}")),
            Distribution::Uniform { .. } => None,
        })
        .collect();
    let trials: u64 = (0..counts.counts.len()).map(|c| counts.trials(c)).sum();
    let at = if fixed.is_empty() {
        String::new()
    } else {
        format!(" at {}", fixed.join(", "))
    };
    format!(
        "basin stability{at}; theta_b = {}, xi = {} ({trials} trials)",
        block.theta_b, block.xi
    )
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
                let rule = basin_rule(h, args.max_per_cell)?;
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

impl super::sampling::Render for BasinFile {
    fn render(&self, out: &OutDir) -> Result<Vec<PathBuf>> {
        let provenance = self
            .provenance
            .clone()
            .unwrap_or_default()
            .with_trials(self.trials);
        write_basin(
            out,
            &self.study,
            &self.block,
            &self.counts,
            provenance,
            |_| {},
        )
    }
}
