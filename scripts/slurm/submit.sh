#!/usr/bin/env bash
# Submits a rocking-block sampling run as a Slurm job array of N shards and a merge job that
# runs once every shard has succeeded:
#
#   scripts/slurm/submit.sh N OUT COMMAND [ARGS...]
#   e.g. scripts/slurm/submit.sh 50 results figure 10 --trials 2000000 --seed 1
#
# COMMAND is `figure 7|9|10` or `basin` (the commands that shard; others are refused before
# anything is submitted). With N = 1 the one task runs the whole study and writes the result
# (figK.json) itself; the merge job then checks it is there. Options for sbatch (partition,
# account, time, CPUs) go in $SBATCH_OPTIONS; both jobs run `rocking-block` from
# $ROCKING_BLOCK or PATH. Prints the two job ids.
#
# Any other program built on hycont-sample's study runner runs the same way: set $STUDY_BIN
# to it and $STUDY_NAME to the stem of its study's files. The contract it keeps:
#   $STUDY_BIN COMMAND [ARGS...] --shard I/N --out OUT [--threads T]
#       counts shard I of N, writing OUT/NAME.shard-I-of-N.json when complete (N = 1:
#       OUT/NAME.json) or OUT/NAME[.shard-I-of-N].partial.json when stopped;
#   $STUDY_BIN COMMAND --resume PARTIAL --out OUT [--threads T]
#       completes a partial file (a task that is run again resumes its own);
#   $STUDY_BIN merge SHARD... --out OUT
#       checks and merges the shards (hycont_sample::study::merge) and writes the result.
set -euo pipefail
if [[ $# -lt 3 ]]; then
  echo "usage: submit.sh N OUT COMMAND [ARGS...]" >&2
  exit 2
fi
n=$1
if ! [[ $n =~ ^[0-9]+$ ]] || ((n < 1)); then
  echo "submit.sh: N must be a positive integer, not '$n'" >&2
  exit 2
fi
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=common.sh
source "$here/common.sh"
# Refuse a command that cannot be sharded before anything is submitted.
if ! result_name "${@:3}" > /dev/null; then
  exit 2
fi
# The jobs run copies of their scripts (from Slurm's spool): they find common.sh here.
export RB_SLURM_SCRIPTS="$here"
# shellcheck disable=SC2086 # SBATCH_OPTIONS holds separate options
array=$(sbatch --parsable ${SBATCH_OPTIONS:-} --array="0-$((n - 1))" "$here/shard.sbatch" "$@")
array=${array%%;*}
# shellcheck disable=SC2086
merge=$(sbatch --parsable ${SBATCH_OPTIONS:-} --dependency="afterok:$array" "$here/merge.sbatch" "$@")
echo "shards: job $array (array 0-$((n - 1))), merge: job ${merge%%;*}"
