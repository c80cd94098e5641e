//! Sampling studies that survive a cluster: count files written atomically, interrupted runs
//! kept and resumed, shards merged with full validation, and the trials split across the
//! ranks of an MPI job (cargo feature `mpi`), for any study a [`CountFile`] describes.
//!
//! A [`CountFile`] is what a study has counted so far over its shard of the trials (its
//! tables, which trials they hold, the seed they were drawn from): what [`sample`] fills and
//! writes, what [`merge`] joins. Three ways to have one:
//! - [`StudyFile`]: the file of a study of any [`crate::basin::Classifier`] (over trials, or
//!   cell by cell to a stopping rule), in this crate's documented layout;
//! - a [`TableFile`]: a driver's own file of one or more count tables ([`Table`]: over trials
//!   or cells) in its own layout (its fields, names and order), which says only what is its
//!   own (its study, how it counts, its checks) and gets the bookkeeping, checks and merging
//!   from its tables (the `rocking-block` command line's four files are);
//! - [`CountFile`] itself, for anything else.
//!
//! Results depend only on the study's seed, never on threads, shards or ranks: a trial's inputs are a function of its index ([`crate::basin::Study`]),
//! and counts merge exactly ([`crate::basin::Counts::merge`]).
//!
//! The contract a driver (a command line, a batch script) keeps:
//! - **Whole runs and shards.** Shard `i` of `n` counts the trials
//!   [`crate::basin::shard_range`] gives; its file names it (`(i, n)`). A complete whole run
//!   is the result; complete shards are merged ([`merge`]), which checks each file (shape,
//!   classes, ranges inside the shard, no trial counted twice, no overflow) before it is
//!   used.
//! - **Interrupts.** A run stopped through its [`crate::basin::Progress`] (a signal, a trial
//!   budget) keeps the exact trials it counted in its partial file, which is never written
//!   over a complete result nor over a partial file of the same run holding trials it lacks
//!   ([`sample`] writes beside it then); resuming the partial file runs the missing trials
//!   only, to the same result as an uninterrupted run.
//! - **Ranks.** Under `mpirun` every rank counts its share of the trials the file lacks
//!   ([`crate::basin::share`]), checkpoints it after each of [`ROUNDS`] rounds (a rank killed
//!   outright loses at most one round: merge the checkpoints to resume), and sends its counts
//!   to rank 0, which merges them and writes exactly what one process writes. A rank that
//!   fails reports to rank 0, which fails the job naming it ([`crate::Error::Rank`]).
//! - **Files** are JSON written by serde (their fields are the [`CountFile`]'s own); written
//!   atomically (a temporary file renamed over the target).
//! - **Slurm.** The workspace's `scripts/slurm/submit.sh N OUT COMMAND ARGS...` runs a study
//!   as a job array of `N` shards and a merge job, for any program (`$STUDY_BIN`, its files
//!   named `$STUDY_NAME`) that accepts `COMMAND ARGS --shard I/N --out OUT` (writing
//!   `OUT/NAME.shard-I-of-N.json`, or its `.partial.json` when stopped), `COMMAND --resume
//!   PARTIAL --out OUT` and `merge SHARDS --out OUT` (the rocking-block command line does;
//!   [`Invocation::parse`] and [`serve`] give any program that command line in one call).

mod checkpoint;
mod count_file;
mod files;
mod ranks;
mod request;
mod run;
mod study_file;
mod table_file;
mod tally;

pub use checkpoint::{ROUNDS, checkpoint_path, fill_in_rounds, remove_checkpoints, rounds};
pub use count_file::{CountFile, Todo, covers};
pub use files::{ensure_parent, is_special, read_checked, temp_path, write_atomic, write_with};
pub use ranks::Ranks;
#[cfg(feature = "mpi")]
pub use ranks::start_mpi;
pub use request::{Invocation, Request, parse_shard, serve, set_threads, use_up};
pub use run::{Outcome, merge, partial_path, sample};
pub use study_file::{FORMAT, MAX_TRIALS, Plan, StudyFile, VERSION};
pub use table_file::{TableFile, shard_paths};
pub use tally::{Table, fill_cells, fill_trials, runs};
