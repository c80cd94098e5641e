//! The command line of a study program, as the workspace's Slurm scripts drive it: `NAME
//! COMMAND [--shard I/N] [--out DIR] [--threads T]` runs a study (or one shard of it),
//! `NAME COMMAND --resume PARTIAL [--out DIR]` completes a partial file, `NAME merge FILES...
//! [--out DIR]` merges shards. [`Request::parse`] reads it and [`serve`] carries it out for
//! any [`CountFile`], so that a user's study is ready for a cluster in one call.

use super::count_file::CountFile;
use super::ranks::Ranks;
use super::run::{Outcome, merge, sample};
use crate::Error;
use crate::basin::Progress;
use std::path::{Path, PathBuf};

/// What a study program is asked to do.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum Request {
    /// Count shard `shard` of a new study (`(0, 1)`: all of it).
    Run {
        /// `(i, n)`.
        shard: (u64, u64),
    },
    /// Complete the partial file `partial`.
    Resume {
        /// The file.
        partial: PathBuf,
    },
    /// Merge these count files.
    Merge {
        /// The files.
        files: Vec<PathBuf>,
    },
}

/// A [`Request`] with where its files go and how many threads count.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Invocation {
    /// What to do.
    pub request: Request,
    /// The output directory (default `results`).
    pub out: PathBuf,
    /// Worker threads (default: all cores).
    pub threads: Option<usize>,
}

fn usage(reason: String) -> Error {
    Error::InvalidStudy {
        reason: format!(
            "{reason} (usage: COMMAND [--shard I/N] [--out DIR] [--threads T] | COMMAND --resume PARTIAL [--out DIR] | merge FILES... [--out DIR])"
        ),
    }
}

impl Invocation {
    /// Parses a study program's arguments (without the program's name).
    ///
    /// ```
    /// use hycont_sample::study::{Invocation, Request};
    /// let args = ["run", "--shard", "2/5", "--out", "o"].map(String::from);
    /// let i = Invocation::parse(args).unwrap();
    /// assert_eq!(i.request, Request::Run { shard: (2, 5) });
    /// assert_eq!(i.out, std::path::Path::new("o"));
    /// let args = ["merge", "a.json", "b.json"].map(String::from);
    /// assert!(matches!(Invocation::parse(args).unwrap().request, Request::Merge { .. }));
    /// assert!(Invocation::parse(["run", "--shard", "5/5"].map(String::from)).is_err());
    /// ```
    ///
    /// # Errors
    /// [`Error::InvalidStudy`] naming the argument that does not fit, with the usage.
    pub fn parse(args: impl IntoIterator<Item = String>) -> Result<Self, Error> {
        let mut args = args.into_iter();
        let command = args.next().ok_or_else(|| usage("no command".into()))?;
        let (mut shard, mut resume, mut out, mut threads) = (None, None, None, None);
        let mut files = Vec::new();
        while let Some(a) = args.next() {
            let mut value = |name: &str| {
                args.next()
                    .ok_or_else(|| usage(format!("{name} needs a value")))
            };
            match a.as_str() {
                "--shard" => {
                    let text = value("--shard")?;
                    let bad = |_| usage(format!("--shard {text}: I/N with 0 <= I < N"));
                    shard = Some(parse_shard(&text).map_err(bad)?);
                }
                "--resume" => resume = Some(PathBuf::from(value("--resume")?)),
                "--out" => out = Some(PathBuf::from(value("--out")?)),
                "--threads" => {
                    let t = value("--threads")?;
                    threads = Some(
                        t.parse::<usize>()
                            .ok()
                            .filter(|&n| n > 0)
                            .ok_or_else(|| usage(format!("--threads {t}: a positive number")))?,
                    );
                }
                other if command == "merge" && !other.starts_with("--") => {
                    files.push(PathBuf::from(other));
                }
                other => return Err(usage(format!("unexpected argument {other:?}"))),
            }
        }
        let request = match (command.as_str(), shard, resume) {
            ("merge", None, None) if !files.is_empty() => Request::Merge { files },
            ("merge", ..) => return Err(usage("merge takes files only".into())),
            (_, Some(_), Some(_)) => {
                return Err(usage("--shard and --resume exclude each other".into()));
            }
            (_, _, Some(partial)) => Request::Resume { partial },
            (_, shard, None) => Request::Run {
                shard: shard.unwrap_or((0, 1)),
            },
        };
        Ok(Self {
            request,
            out: out.unwrap_or_else(|| PathBuf::from("results")),
            threads,
        })
    }
}

/// Shard `I/N` of a study (0-based, `0 <= I < N`), as `--shard` gives it.
///
/// ```
/// use hycont_sample::study::parse_shard;
/// assert_eq!(parse_shard("2/5").unwrap(), (2, 5));
/// assert!(parse_shard("5/5").is_err() && parse_shard("1/0").is_err() && parse_shard("3").is_err());
/// ```
///
/// # Errors
/// [`Error::InvalidSpec`] for anything else.
pub fn parse_shard(text: &str) -> Result<(u64, u64), Error> {
    let bad = || Error::InvalidSpec {
        spec: text.to_string(),
        reason: "expected I/N with 0 <= I < N",
    };
    let (i, n) = text.split_once('/').ok_or_else(bad)?;
    let (i, n): (u64, u64) = (
        i.trim().parse().map_err(|_| bad())?,
        n.trim().parse().map_err(|_| bad())?,
    );
    if n == 0 || i >= n {
        return Err(bad());
    }
    Ok((i, n))
}

/// Sizes rayon's global pool to `threads` (`None`: all cores). Only the first call of a
/// process takes effect; results never depend on it.
///
/// # Errors
/// [`Error::InvalidSpec`] for zero threads.
pub fn set_threads(threads: Option<usize>) -> Result<(), Error> {
    match threads {
        Some(0) => Err(Error::InvalidSpec {
            spec: "0".into(),
            reason: "must be at least 1",
        }),
        Some(n) => {
            let _ = rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build_global();
            Ok(())
        }
        None => Ok(()),
    }
}

/// Removes the partial file `partial` that a resumed run completed, unless the run wrote it
/// again (one of `written`) or it is not a partial file (`*.partial.json`).
pub fn use_up(partial: &Path, written: &[PathBuf]) {
    if partial.to_string_lossy().ends_with(".partial.json") && !written.iter().any(|w| w == partial)
    {
        let _ = std::fs::remove_file(partial);
    }
}

/// Carries out `invocation` for studies of type `F`: a new study from `new(shard)`, or the
/// partial file to resume ([`CountFile::read`]), counted by [`sample`] into the output
/// directory (threads sized first, once per process), a complete whole run written to its
/// complete path too; or a [`merge`] of the files, written
/// to the whole run's complete path when it holds every trial and to its partial path
/// otherwise. Returns the [`Outcome`] (a merge's as a run's: complete or partial).
///
/// # Errors
/// As [`sample`], [`merge`] and [`CountFile::read`]; what `new` returns.
pub fn serve<F: CountFile>(
    invocation: &Invocation,
    new: impl FnOnce((u64, u64)) -> Result<F, F::Error>,
    progress: &Progress,
    ranks: Ranks,
) -> Result<Outcome<F>, F::Error>
where
    F::Error: std::fmt::Display,
{
    set_threads(invocation.threads)?;
    let out = &invocation.out;
    let file = match &invocation.request {
        Request::Run { shard } => new(*shard)?,
        Request::Resume { partial } => F::read(partial)?,
        Request::Merge { files } => {
            let read = files
                .iter()
                .map(|p| F::read(p).map(|f| (p.clone(), f)))
                .collect::<Result<Vec<_>, _>>()?;
            let merged = merge(read)?;
            let (complete, partial) = merged.paths(out);
            let path = if merged.is_complete() {
                complete
            } else {
                partial
            };
            merged.write(&path)?;
            return Ok(if merged.is_complete() {
                Outcome::Complete {
                    file: merged,
                    written: Some(path),
                }
            } else {
                Outcome::Partial { file: merged, path }
            });
        }
    };
    let outcome = match sample(file, out, progress, ranks)? {
        // A whole run's counts are its result: written as a shard's would be.
        Outcome::Complete {
            file,
            written: None,
        } => {
            let path = file.paths(out).0;
            file.write(&path)?;
            Outcome::Complete {
                file,
                written: Some(path),
            }
        }
        other => other,
    };
    // A resumed run has used its partial file up (unless it wrote the same path again).
    if let (Request::Resume { partial }, Outcome::Complete { written, .. }) =
        (&invocation.request, &outcome)
    {
        use_up(partial, written.as_slice());
    }
    Ok(outcome)
}
