#!/usr/bin/env bash
# Runs an `atmosh sweep` on a Slurm cluster: one shard per array task, then a merge job
# that starts when every task has succeeded (docs/sweeps.md, "On a Slurm cluster").
#
#   scripts/slurm-sweep.sh [--shards N] [--atmosh PATH] [--sweep-args "ARGS"] [--dry-run]
#                          SWEEP.toml OUTDIR [sbatch options...]
#   scripts/slurm-sweep.sh --resume [SWEEP.toml] OUTDIR [sbatch options...]
#
# Writes OUTDIR/slurm/{shard.sbatch,merge.sbatch,state}, submits
#   sbatch --array=0-(N-1) shard.sbatch        (task i runs --shard (i+1)/N --resume)
#   sbatch --dependency=afterok:<array> merge.sbatch   (-> OUTDIR/sweep.csv)
# and prints "array job: ID" and "merge job: ID". Options after OUTDIR go to both
# sbatch calls (e.g. --partition=..., --time=..., --cpus-per-task=8, --account=...).
# --sweep-args: quality options of `atmosh sweep` for every shard, split on blanks
# (e.g. "--scattering single --shells 64"). Each task passes --threads from its
# allocation: SLURM_CPUS_PER_TASK (1 unless --cpus-per-task is given), else the CPUs
# allocated on its node.
#
# --resume: submits again only the shards whose CSV is missing (a task that failed,
# was cancelled or timed out; each resumes from its journal, losing no finished point)
# and a new merge job; a merge job of an earlier submission still pending is cancelled.
# N, the atmosh binary and the sweep arguments come from OUTDIR/slurm/state unless given.
# --dry-run: writes the job scripts and prints the sbatch commands without running them.
# Exit codes: 0 submitted (or nothing to do), 2 bad arguments, other: sbatch failed.
set -euo pipefail

die() { echo "slurm-sweep.sh: $*" >&2; exit 2; }

shards="" atmosh="" resume=0 dry=0 sweep_args="" have_sweep_args=0
while [ $# -gt 0 ]; do
  case "$1" in
    --shards) [ $# -ge 2 ] || die "--shards needs a value"; shards=$2; shift 2 ;;
    --shards=*) shards=${1#--shards=}; shift ;;
    --atmosh) [ $# -ge 2 ] || die "--atmosh needs a value"; atmosh=$2; shift 2 ;;
    --atmosh=*) atmosh=${1#--atmosh=}; shift ;;
    --sweep-args) [ $# -ge 2 ] || die "--sweep-args needs a value"; sweep_args=$2; have_sweep_args=1; shift 2 ;;
    --sweep-args=*) sweep_args=${1#--sweep-args=}; have_sweep_args=1; shift ;;
    --resume) resume=1; shift ;;
    --dry-run) dry=1; shift ;;
    -h|--help) sed -n '2,/^set -e/p' "$0" | grep '^#' | sed 's/^# \{0,1\}//'; exit 0 ;;
    --) shift; break ;;
    -*) die "unknown option '$1' (sbatch options go after SWEEP.toml OUTDIR)" ;;
    *) break ;;
  esac
done
usage="usage: slurm-sweep.sh [--shards N] [--atmosh PATH] [--sweep-args ARGS] [--dry-run] SWEEP.toml OUTDIR [sbatch options...]
       slurm-sweep.sh --resume [SWEEP.toml] OUTDIR [sbatch options...]"
if [ "$resume" = 1 ] && [ $# -ge 1 ] && { [ $# -eq 1 ] || [[ "$2" == -* ]]; }; then
  # --resume OUTDIR: the sweep file of the earlier submission.
  [ -f "$1/slurm/state" ] || die "--resume: no earlier submission in '$1' ($1/slurm/state missing)"
  sweep=$(sed -n 's/^sweep=//p' "$1/slurm/state") outdir=$1
  shift 1
else
  [ $# -ge 2 ] || die "$usage"
  sweep=$1 outdir=$2
  shift 2
fi
sbatch_opts=("$@")

[ -f "$sweep" ] || die "sweep file '$sweep' not found"
sweep=$(cd "$(dirname "$sweep")" && pwd)/$(basename "$sweep")
mkdir -p "$outdir/slurm"
outdir=$(cd "$outdir" && pwd)
state=$outdir/slurm/state

old_merge=""
if [ -f "$state" ]; then
  prev_shards=$(sed -n 's/^shards=//p' "$state")
  prev_atmosh=$(sed -n 's/^atmosh=//p' "$state")
  prev_args=$(sed -n 's/^sweep_args=//p' "$state")
  old_merge=$(sed -n 's/^merge_job=//p' "$state")
  if [ "$resume" = 1 ]; then
    [ "$have_sweep_args" = 1 ] || sweep_args=$prev_args
    [ -n "$shards" ] || shards=$prev_shards
    [ -n "$atmosh" ] || atmosh=$prev_atmosh
    [ "$shards" = "$prev_shards" ] ||
      die "--shards $shards differs from the $prev_shards shards of the earlier submission in $outdir"
  fi
elif [ "$resume" = 1 ]; then
  die "--resume: no earlier submission in '$outdir' ($state missing)"
fi
[ -n "$shards" ] || shards=8
[[ "$shards" =~ ^[1-9][0-9]*$ ]] || die "--shards '$shards' is not a positive integer"
if [ -z "$atmosh" ]; then
  atmosh=$(command -v atmosh || true)
  [ -n "$atmosh" ] || die "no atmosh on PATH; give --atmosh PATH"
fi
[ -x "$atmosh" ] || die "--atmosh '$atmosh' is not an executable"
atmosh=$(cd "$(dirname "$atmosh")" && pwd)/$(basename "$atmosh")

shard_csv() { echo "$outdir/sweep.shard-$1-of-$shards.csv"; }

# The array tasks still to run: all of them, or (resume) those without a shard CSV.
tasks=()
for ((i = 0; i < shards; i++)); do
  if [ "$resume" = 0 ] || [ ! -f "$(shard_csv $((i + 1)))" ]; then tasks+=("$i"); fi
done

cat > "$outdir/slurm/shard.sbatch" <<EOF
#!/bin/bash
#SBATCH --job-name=atmosh-sweep
#SBATCH --output=$outdir/slurm/shard-%a.out
#SBATCH --cpus-per-task=1
set -euo pipefail
threads=\${SLURM_CPUS_PER_TASK:-}
if [ -z "\$threads" ]; then threads=\${SLURM_JOB_CPUS_PER_NODE%%(*}; threads=\${threads%%,*}; fi
shard=\$((SLURM_ARRAY_TASK_ID + 1))
exec "$atmosh" sweep "$sweep" -o "$outdir" --shard "\$shard/$shards" --resume --threads "\${threads:-0}" $sweep_args
EOF
inputs=""
for ((k = 1; k <= shards; k++)); do inputs+=" \"$(shard_csv "$k")\""; done
cat > "$outdir/slurm/merge.sbatch" <<EOF
#!/bin/bash
#SBATCH --job-name=atmosh-sweep-merge
#SBATCH --output=$outdir/slurm/merge.out
#SBATCH --cpus-per-task=1
set -euo pipefail
exec "$atmosh" sweep merge$inputs -o "$outdir/sweep.csv"
EOF

run() {
  if [ "$dry" = 1 ]; then echo "$*" >&2; echo "DRYRUN"; else "$@"; fi
}

if [ "$resume" = 1 ] && [ -n "$old_merge" ] && [ "$dry" = 0 ]; then
  # The earlier merge waits on a dependency that can no longer be met.
  if squeue -h -j "$old_merge" -o %T 2>/dev/null | grep -q PENDING; then scancel "$old_merge" || true; fi
fi

dep=()
if [ ${#tasks[@]} -gt 0 ]; then
  array=$(IFS=,; echo "${tasks[*]}")
  if [ "$resume" = 0 ]; then array="0-$((shards - 1))"; fi
  array_job=$(run sbatch --parsable --array="$array" "${sbatch_opts[@]}" "$outdir/slurm/shard.sbatch")
  array_job=${array_job%%;*}
  echo "array job: $array_job (tasks $array of $shards shards)"
  dep=(--dependency="afterok:$array_job")
else
  array_job=""
  echo "array job: none (all $shards shard CSVs present)"
fi
merge_job=$(run sbatch --parsable "${dep[@]}" "${sbatch_opts[@]}" "$outdir/slurm/merge.sbatch")
merge_job=${merge_job%%;*}
echo "merge job: $merge_job (writes $outdir/sweep.csv)"

if [ "$dry" = 0 ]; then
  printf 'sweep=%s\nshards=%s\natmosh=%s\nsweep_args=%s\narray_job=%s\nmerge_job=%s\n' \
    "$sweep" "$shards" "$atmosh" "$sweep_args" "$array_job" "$merge_job" > "$state.tmp"
  mv "$state.tmp" "$state"
fi
