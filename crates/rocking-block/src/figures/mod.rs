//! The study's figures: each writes `figN.json` and `figN.svg` into an output directory.

pub mod atlas;
pub mod branches;
pub mod cells;
mod fig2;
mod fig5;
pub mod fig6;
mod fig7;
mod fig9_files;
pub mod sampling;
pub mod tables;

pub use atlas::{ATLAS, figure_atlas};
pub use branches::branches_figure;
pub use fig2::figure2;
pub use fig6::figure6;

use crate::block::Block;
use crate::error::{Error, Result};
use crate::output::OutDir;
use crate::provenance::Provenance;
use std::path::{Path, PathBuf};

/// Figures `rocking-block figure` knows: the study's 2 to 10, and the atlas ([`ATLAS`],
/// `figure atlas`).
pub const AVAILABLE: &[u32] = &[2, 3, 4, 5, 6, 7, 8, 9, 10, ATLAS];

/// What a figure run wrote.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FigureFiles {
    /// The figure's number.
    pub figure: u32,
    /// Files written.
    pub files: Vec<PathBuf>,
}

/// Writes figure `n` of the study's block into `out` (sampling figures with their default
/// trial counts, [`sampling::default_trials`], and seed 1).
///
/// # Errors
/// [`Error::InvalidArgument`] for a figure that does not exist or is not available yet; numerical
/// or I/O failures.
pub fn figure(n: u32, out: &Path) -> Result<FigureFiles> {
    figure_with(
        n,
        &OutDir::new(out),
        sampling::SampleOptions {
            trials: sampling::default_trials(n),
            seed: 1,
            block: Block::default(),
        },
        &Provenance::default(),
        &hycont_sample::basin::Progress::default(),
    )
}

/// Writes figure `n` into `out` for `options.block` with the given sampling options (used by
/// the sampling figures) and progress; every JSON records `provenance` (with the block, and
/// the seed and trials of a sampling figure).
///
/// # Errors
/// As [`figure`]; an invalid block.
pub fn figure_with(
    n: u32,
    out: &OutDir,
    options: sampling::SampleOptions,
    provenance: &Provenance,
    progress: &hycont_sample::basin::Progress,
) -> Result<FigureFiles> {
    options.block.validate()?;
    std::fs::create_dir_all(&out.dir).map_err(|source| Error::Io {
        path: out.dir.clone(),
        source,
    })?;
    let record = provenance.clone().with_block(options.block);
    // The computations stop where they are when the run is interrupted, and write nothing.
    let stop = &mut hycont_continuation::observe::StopFlag(&progress.stop);
    let files = match n {
        2 => figure2(out, &record),
        3 => branches_figure(crate::continuation::Free::Omega, out, &record, stop),
        4 => branches_figure(crate::continuation::Free::Alpha, out, &record, stop),
        5 => sampling::figure5(out, &record, progress),
        6 => figure6(out, &record, stop),
        7 => sampling::figure7(out, options, &record, progress),
        8 => sampling::figure8(out, &record),
        9 => sampling::figure9(out, options, &record, progress),
        10 => sampling::figure10(out, options, &record, progress),
        ATLAS => figure_atlas(out, &record, stop),
        _ => Err(Error::InvalidArgument {
            name: "figure",
            value: n.to_string(),
            reason: "the study has figures 2 to 10 (and `atlas`)",
        }),
    };
    // However the computation was stopped, say which figure was not written.
    files.map_err(|e| match e {
        Error::Interrupted { .. } => Error::Interrupted {
            detail: format!("during figure {}: none of it was written", names(&[n])),
        },
        e => e,
    })
}

/// [`Error::Interrupted`] where `observer` asked the computation of figure `n` to stop (it
/// ended early: it is not the figure).
///
/// # Errors
/// That.
pub(crate) fn stopped_by(observer: &mut dyn hycont_continuation::Observer, n: u32) -> Result<()> {
    if observer.stop() {
        Err(Error::Interrupted {
            detail: format!("during figure {}: none of it was written", names(&[n])),
        })
    } else {
        Ok(())
    }
}

/// [`Error::Interrupted`] once `progress` was asked to stop during figure `n`.
///
/// # Errors
/// That.
pub(crate) fn stopped(progress: &hycont_sample::basin::Progress, n: u32) -> Result<()> {
    if progress.stop.load(std::sync::atomic::Ordering::Relaxed) {
        Err(Error::Interrupted {
            detail: format!("during figure {}: none of it was written", names(&[n])),
        })
    } else {
        Ok(())
    }
}

/// The figures a name on the command line asks for: a number (2 to 10), `atlas` or `all`.
///
/// # Errors
/// [`Error::InvalidArgument`] for any other name.
pub fn parse(which: &str) -> Result<Vec<u32>> {
    if which == "all" {
        return Ok(AVAILABLE.to_vec());
    }
    if which == "atlas" {
        return Ok(vec![ATLAS]);
    }
    let n: u32 = which.parse().map_err(|_| Error::InvalidArgument {
        name: "figure",
        value: which.to_string(),
        reason: "expected a figure number (2 to 10), `atlas` or `all`",
    })?;
    if !AVAILABLE.contains(&n) || n == ATLAS {
        return Err(Error::InvalidArgument {
            name: "figure",
            value: which.to_string(),
            reason: "the study has figures 2 to 10 (and `atlas`)",
        });
    }
    Ok(vec![n])
}

/// The figures named as the command line names them (`3, 4, atlas`).
#[must_use]
pub fn names(which: &[u32]) -> String {
    let name = |n: &u32| {
        if *n == ATLAS {
            "atlas".to_string()
        } else {
            n.to_string()
        }
    };
    which.iter().map(name).collect::<Vec<_>>().join(", ")
}

pub(crate) fn write_json(path: &Path, value: &serde_json::Value) -> Result<()> {
    let text = serde_json::to_string_pretty(value).expect("figure JSON serialises");
    crate::output::write_atomic(path, text)
}
