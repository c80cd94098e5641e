//! `figure` and `merge`: the study's figures, sampling shards, interrupts and merging.

use super::{FigureArgs, MergeArgs, io_err, print_written};
use crate::error::{Error, Result};
use std::io::Write;
use std::path::PathBuf;

/// A shard of a sampling figure on disk.
#[derive(Debug, serde::Serialize, serde::Deserialize)]
struct ShardFile {
    figure: u32,
    trials: u64,
    seed: u64,
    shard: (u64, u64),
    counts: Vec<hycont_sample::basin::Counts>,
}

fn parse_shard(text: &str) -> Result<(u64, u64)> {
    let bad = || Error::InvalidArgument {
        name: "shard",
        value: text.to_string(),
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

pub(super) fn run_merge(args: &MergeArgs, out: &mut dyn Write) -> Result<()> {
    let mut merged: Option<ShardFile> = None;
    for path in &args.shards {
        let text = std::fs::read_to_string(path).map_err(io_err(path))?;
        let shard: ShardFile = serde_json::from_str(&text).map_err(|_| Error::InvalidArgument {
            name: "shard",
            value: path.display().to_string(),
            reason: "not a shard file written by `figure N --shard I/N`",
        })?;
        match merged.as_mut() {
            None => merged = Some(shard),
            Some(m) => {
                if (m.figure, m.trials, m.seed) != (shard.figure, shard.trials, shard.seed)
                    || m.counts.len() != shard.counts.len()
                {
                    return Err(Error::InvalidArgument {
                        name: "shard",
                        value: path.display().to_string(),
                        reason: "belongs to another figure, trial count or seed",
                    });
                }
                for (a, b) in m.counts.iter_mut().zip(&shard.counts) {
                    a.merge(b).map_err(|e| Error::InvalidArgument {
                        name: "shard",
                        value: format!("{}: {e}", path.display()),
                        reason: "overlaps a shard merged before",
                    })?;
                }
            }
        }
    }
    let m = merged.expect("clap requires at least one shard");
    let complete: u64 = m.counts[0].ranges.iter().map(|(a, b)| b - a).sum();
    if complete != m.trials {
        eprintln!(
            "rocking-block: the shards hold {complete} of {} trials; writing what they hold",
            m.trials
        );
    }
    std::fs::create_dir_all(&args.out).map_err(io_err(&args.out))?;
    let options = crate::figures::sampling::SampleOptions {
        trials: m.trials,
        seed: m.seed,
    };
    let files = crate::figures::sampling::render(m.figure, &args.out, options, &m.counts)?;
    print_written(out, &files.files, args.json)
}

pub(super) fn run_figure(args: &FigureArgs, out: &mut dyn Write) -> Result<()> {
    use hycont_sample::basin::Progress;
    use std::sync::Arc;
    use std::sync::atomic::{AtomicBool, Ordering};
    let which: Vec<u32> = if args.which == "all" {
        crate::figures::AVAILABLE.to_vec()
    } else {
        vec![args.which.parse().map_err(|_| Error::InvalidArgument {
            name: "figure",
            value: args.which.clone(),
            reason: "expected a figure number (2 to 10) or `all`",
        })?]
    };
    if args.trials == 0 {
        return Err(Error::InvalidArgument {
            name: "trials",
            value: "0".into(),
            reason: "must be at least 1",
        });
    }
    if let Some(n) = args.threads {
        if n == 0 {
            return Err(Error::InvalidArgument {
                name: "threads",
                value: "0".into(),
                reason: "must be at least 1",
            });
        }
        // Only the first call configures the global pool; results do not depend on it.
        let _ = rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build_global();
    }
    let options = crate::figures::sampling::SampleOptions {
        trials: args.trials,
        seed: args.seed,
    };
    let progress = Arc::new(Progress::default());
    if let Some(shard) = &args.shard {
        let (i, n) = parse_shard(shard)?;
        let [fig] = which.as_slice() else {
            return Err(Error::InvalidArgument {
                name: "shard",
                value: args.which.clone(),
                reason: "shard one sampling figure (7, 9 or 10) at a time",
            });
        };
        let range = hycont_sample::basin::shard_range(args.trials, i, n).map_err(|e| {
            Error::InvalidArgument {
                name: "shard",
                value: e.to_string(),
                reason: "invalid shard",
            }
        })?;
        let counts = crate::figures::sampling::counts_for(*fig, options, range, &progress)?;
        std::fs::create_dir_all(&args.out).map_err(io_err(&args.out))?;
        let path = args.out.join(format!("fig{fig}.shard-{i}-of-{n}.json"));
        let file = ShardFile {
            figure: *fig,
            trials: args.trials,
            seed: args.seed,
            shard: (i, n),
            counts,
        };
        std::fs::write(&path, serde_json::to_string(&file).expect("serialises"))
            .map_err(io_err(&path))?;
        return print_written(out, &[path], args.json);
    }
    // Ctrl-C stops sampling studies early; what was counted is written, with its trial ranges.
    {
        let p = Arc::clone(&progress);
        let _ = ctrlc::set_handler(move || p.stop.store(true, Ordering::Relaxed));
    }
    let mut written: Vec<PathBuf> = Vec::new();
    for n in which {
        let total = match n {
            7 => options.trials * crate::figures::sampling::FIG7_OMEGAS.len() as u64,
            9 => 2 * options.trials,
            10 => options.trials,
            _ => 0,
        };
        progress.done.store(0, Ordering::Relaxed);
        // A progress bar for the sampling figures, on stderr (hidden when not a terminal).
        let bar = (total > 0).then(|| {
            let bar = indicatif::ProgressBar::new(total);
            bar.set_style(
                indicatif::ProgressStyle::with_template(
                    "figure {msg} [{bar:40}] {pos}/{len} trials ({per_sec}, eta {eta})",
                )
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
            );
            bar.set_message(n.to_string());
            bar
        });
        let done = AtomicBool::new(false);
        let files = std::thread::scope(|scope| {
            if let Some(bar) = &bar {
                let (p, done) = (&progress, &done);
                scope.spawn(move || {
                    while !done.load(Ordering::Relaxed) {
                        bar.set_position(p.done.load(Ordering::Relaxed));
                        std::thread::sleep(std::time::Duration::from_millis(100));
                    }
                });
            }
            let r = crate::figures::figure_with(n, &args.out, options, &progress);
            done.store(true, Ordering::Relaxed);
            r
        })?;
        if let Some(bar) = bar {
            bar.finish_and_clear();
        }
        written.extend(files.files);
        if progress.stop.load(Ordering::Relaxed) {
            eprintln!(
                "rocking-block: interrupted: figure {n} holds the trials counted so far (see trial_ranges)"
            );
            break;
        }
    }
    print_written(out, &written, args.json)
}

