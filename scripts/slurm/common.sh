# Shared by the Slurm scripts (sourced): which commands shard, and the files a run writes.
#
# result_name COMMAND [ARGS...]: prints the stem of the files a sampling run writes (`figK`
# for `figure K`, K in 7, 9, 10; `basin` for `basin`; $STUDY_NAME for another program), or
# says why the command cannot be sharded and returns 2.
result_name() {
  # Another program built on hycont-sample's runner names its study's files itself.
  if [[ -n "${STUDY_NAME:-}" ]]; then
    if ! [[ $STUDY_NAME =~ ^[A-Za-z0-9._-]+$ ]]; then
      echo "STUDY_NAME must be letters, digits, '.', '_' and '-', not '$STUDY_NAME'" >&2
      return 2
    fi
    echo "$STUDY_NAME"
    return 0
  fi
  case "${1:-}" in
    figure)
      case "${2:-}" in
        7 | 9 | 10) echo "fig$2" ;;
        *)
          echo "only the sampling figures (7, 9, 10) and basin shard, not 'figure ${2:-}'" >&2
          return 2
          ;;
      esac
      ;;
    basin) echo basin ;;
    *)
      echo "COMMAND must be 'figure 7|9|10' or 'basin', not '${1:-}' (it cannot be sharded)" >&2
      return 2
      ;;
  esac
}

# shard_file OUT NAME I N [partial]: the file task I of N writes (with `partial`, the partial
# file an interrupt leaves). One task is the whole run: its files are the whole run's
# (`figK.json`), as `--shard 0/1` writes them.
shard_file() {
  local out=$1 name=$2 i=$3 n=$4 kind=${5:-}
  local stem
  if ((n == 1)); then
    stem="$out/$name"
  else
    stem="$out/$name.shard-$i-of-$n"
  fi
  if [[ $kind == partial ]]; then
    echo "$stem.partial.json"
  else
    echo "$stem.json"
  fi
}
