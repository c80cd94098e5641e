//! Sampling runs split across the processes of an MPI job (cargo feature `mpi`, which turns on
//! `hycont-sample`'s): under `mpirun -n N rocking-block figure 7|9|10 ...` (or `basin`) every
//! rank counts its share of the trials the run lacks and rank 0 writes exactly what one
//! process writes ([`hycont_sample::study`]). Outside an MPI launcher, or without the
//! feature, the run is one rank of one.

use crate::error::{Error, Result};
pub(crate) use hycont_sample::study::Ranks;
#[cfg(feature = "mpi")]
pub use hycont_sample::study::start_mpi;

/// Refuses to run as one rank of several without MPI support: every rank would run the whole
/// job and write the same files.
///
/// # Errors
/// [`Error::InvalidArgument`] naming the job's size.
pub(crate) fn check_launcher() -> Result<()> {
    if let Some(n) = Ranks::unjoinable_job() {
        return Err(Error::InvalidArgument {
            name: "mpirun",
            value: format!("{n} ranks"),
            reason: "this rocking-block is built without MPI: build it with `--features mpi` (each rank would otherwise run the whole job and write the same files)",
        });
    }
    Ok(())
}

/// Refuses commands other than the sampling ones in a job of several ranks (they would all
/// write the same files).
///
/// # Errors
/// [`Error::InvalidArgument`] naming the job's size.
pub(crate) fn only_sampling(ranks: Ranks, command: &str) -> Result<()> {
    if ranks.part().1 > 1 {
        return Err(Error::InvalidArgument {
            name: "mpirun",
            value: format!("{command} on {} ranks", ranks.part().1),
            reason: "only `figure` and `basin` split across MPI ranks; run the other commands as one process",
        });
    }
    Ok(())
}
