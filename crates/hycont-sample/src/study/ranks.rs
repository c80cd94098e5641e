//! Runs split across the processes of an MPI job (cargo feature `mpi`): under `mpirun -n N`
//! every rank counts its share of the trials the run lacks ([`crate::basin::share`]), sends
//! its counts to rank 0, and rank 0 merges them and writes exactly what one process writes.
//! An interrupt stops the rank it reaches (each keeps its counts so far); rank 0 then writes
//! the partial file of every trial counted, as one process would. Outside an MPI launcher, or
//! without the feature, the run is one rank of one.

use super::count_file::CountFile;
#[cfg(feature = "mpi")]
use crate::Error;

/// This process's place in the job: rank `rank` of `size`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Ranks {
    rank: u64,
    size: u64,
}

/// Whether an MPI launcher started this process (the variables Open MPI, MPICH's Hydra,
/// PMI-2 and PMIx set), so that MPI is initialised only then.
#[cfg(feature = "mpi")]
fn launched_by_mpi() -> bool {
    [
        "OMPI_COMM_WORLD_SIZE",
        "PMI_SIZE",
        "PMIX_RANK",
        "MPI_LOCALNRANKS",
    ]
    .iter()
    .any(|v| std::env::var_os(v).is_some())
}

/// The size of the job an MPI launcher says this process belongs to (Open MPI's and PMI's
/// variables), if any.
#[cfg(not(feature = "mpi"))]
fn launcher_size() -> Option<u64> {
    ["OMPI_COMM_WORLD_SIZE", "PMI_SIZE"]
        .iter()
        .find_map(|v| std::env::var(v).ok()?.trim().parse().ok())
}

impl Ranks {
    /// The size of the job an MPI launcher started this process in, where this build cannot
    /// join it (without the `mpi` feature; `None` with it or outside a launcher): a driver
    /// refuses to run then, as every rank would run the whole job and write the same files.
    #[must_use]
    pub fn unjoinable_job() -> Option<u64> {
        #[cfg(not(feature = "mpi"))]
        if let Some(n) = launcher_size().filter(|n| *n > 1) {
            return Some(n);
        }
        None
    }
}

/// Initialises MPI when an MPI launcher started this process (call it first thing in
/// `main`); keep the value until the process ends (dropping it finalises MPI).
#[cfg(feature = "mpi")]
#[must_use]
pub fn start_mpi() -> Option<mpi::environment::Universe> {
    if launched_by_mpi() {
        mpi::initialize()
    } else {
        None
    }
}

impl Ranks {
    /// This process's rank and the job's size (0 of 1 without MPI).
    #[must_use]
    pub fn current() -> Self {
        #[cfg(feature = "mpi")]
        if mpi::environment::is_initialized() && !mpi::environment::is_finalized() {
            use mpi::topology::Communicator;
            let world = mpi::topology::SimpleCommunicator::world();
            return Ranks {
                rank: u64::try_from(world.rank()).unwrap_or(0),
                size: u64::try_from(world.size()).unwrap_or(1),
            };
        }
        Ranks { rank: 0, size: 1 }
    }

    /// `(rank, size)`: the share of the trials this process counts.
    #[must_use]
    pub fn part(self) -> (u64, u64) {
        (self.rank, self.size)
    }

    /// Whether `flag` holds on any rank (a collective: every rank of the job must call it,
    /// as often as the others; one rank of one: `flag`).
    #[must_use]
    pub fn any(self, flag: bool) -> bool {
        if self.size == 1 {
            return flag;
        }
        self.any_of_job(flag)
    }

    #[cfg(not(feature = "mpi"))]
    #[allow(clippy::unused_self)]
    fn any_of_job(self, flag: bool) -> bool {
        flag
    }

    #[cfg(feature = "mpi")]
    fn any_of_job(self, flag: bool) -> bool {
        use mpi::collective::{CommunicatorCollectives, SystemOperation};
        let world = mpi::topology::SimpleCommunicator::world();
        let mut any = 0u8;
        world.all_reduce_into(&u8::from(flag), &mut any, SystemOperation::max());
        any == 1
    }

    /// Whether this process writes the results (rank 0).
    #[must_use]
    pub fn is_root(self) -> bool {
        self.rank == 0
    }

    /// Collects every rank's counts at rank 0: there, `Some` of all of them merged (or the
    /// first rank's error); elsewhere `None` once sent (or this rank's own error). Every rank
    /// sends, even after an error, so that rank 0 never waits for a rank that gave up.
    ///
    /// # Errors
    /// A rank's error, counts that do not merge, a message that is not a count file
    /// ([`crate::Error::Rank`] naming the rank).
    pub fn gather<F: CountFile>(self, mine: Result<F, F::Error>) -> Result<Option<F>, F::Error>
    where
        F::Error: std::fmt::Display,
    {
        if self.size == 1 {
            return mine.map(Some);
        }
        self.exchange(mine)
    }

    #[cfg(not(feature = "mpi"))]
    #[allow(clippy::unused_self)]
    fn exchange<F: CountFile>(self, mine: Result<F, F::Error>) -> Result<Option<F>, F::Error> {
        mine.map(Some)
    }

    #[cfg(feature = "mpi")]
    fn exchange<F: CountFile>(self, mine: Result<F, F::Error>) -> Result<Option<F>, F::Error>
    where
        F::Error: std::fmt::Display,
    {
        use mpi::point_to_point::{Destination, Source};
        use mpi::topology::Communicator;
        let world = mpi::topology::SimpleCommunicator::world();
        if !self.is_root() {
            // One byte of status (0: counts, 1: an error's message), then the payload.
            // (Always sent: rank 0 waits for every rank.)
            let message = match mine.as_ref().map(serde_json::to_vec) {
                Ok(Ok(json)) => [&[0u8][..], &json].concat(),
                Ok(Err(e)) => [&[1u8][..], e.to_string().as_bytes()].concat(),
                Err(e) => [&[1u8][..], e.to_string().as_bytes()].concat(),
            };
            world.process_at_rank(0).send(&message[..]);
            return mine.map(|_| None);
        }
        let mut merged = mine;
        for r in 1..world.size() {
            let (message, _) = world.process_at_rank(r).receive_vec::<u8>();
            let rank = u64::try_from(r).unwrap_or(0);
            let other: Result<F, F::Error> = match message.split_first() {
                Some((0, json)) => {
                    serde_json::from_slice(json).map_err(|e| rank_err(rank, &e).into())
                }
                Some((_, text)) => Err(rank_err(rank, &String::from_utf8_lossy(text)).into()),
                None => Err(rank_err(rank, &"an empty message").into()),
            };
            merged = match (merged, other) {
                (Ok(mut m), Ok(o)) => m
                    .merge(&o)
                    .map(|()| m)
                    .map_err(|e| rank_err(rank, &e).into()),
                (Err(e), _) | (Ok(_), Err(e)) => Err(e),
            };
        }
        merged.map(Some)
    }
}

/// A failure of rank `rank`'s share.
#[cfg(feature = "mpi")]
fn rank_err(rank: u64, reason: &dyn std::fmt::Display) -> Error {
    Error::Rank {
        rank,
        reason: reason.to_string(),
    }
}
