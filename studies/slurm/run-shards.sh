#!/bin/bash
# Run a rockfrag study as a SLURM job array: task i runs shard i+1 of N into
# results/shard-<i>. From the repository root, after `cargo build --release`:
#
#   mkdir -p results
#   sbatch --array=0-15 studies/slurm/run-shards.sh studies/fragility.toml
#
# `mkdir -p results` first: SLURM opens this job's log, results/slurm-<job>_<i>.out,
# before the script starts, and a task whose log folder is missing fails with
# no log at all. The array 0..N-1 sets N. Each task asks for one CPU unless
# you ask for more: `sbatch --cpus-per-task=8 --array=0-15 ...` (the task
# then runs 8 threads, from SLURM_CPUS_PER_TASK).
#
# The binary: $ROCKFRAG if set, else `rockfrag` on PATH, else
# target/release/rockfrag in the folder you submitted from (or the nearest
# folder above it that has one). The log names the one used. When every task is done, merge (see studies/README.md):
#
#   target/release/rockfrag merge results/shard-* --out results/fragility
#
# A task that is killed (time limit, preemption) resumes where it stopped
# when it is run again with the same arguments. Resubmit the failed indices
# with N set to the original array's size, e.g. for tasks 3 and 7 of 16:
#
#   N=16 sbatch --array=3,7 studies/slurm/run-shards.sh studies/fragility.toml
#
#SBATCH --job-name=rockfrag
#SBATCH --time=02:00:00
#SBATCH --output=results/slurm-%A_%a.out

set -euo pipefail

STUDY=${1:?usage: mkdir -p results && sbatch --array=0-(N-1) studies/slurm/run-shards.sh STUDY.toml}
ID=${SLURM_ARRAY_TASK_ID:?run this as a job array: sbatch --array=0-15 studies/slurm/run-shards.sh $STUDY}
SCRIPT=studies/slurm/run-shards.sh

if [ -z "${N:-}" ]; then
    # Without N the array must be exactly 0..N-1. A resubmitted part of an
    # array (--array=3, --array=3,7) would otherwise run a wrong split: with
    # --array=3 alone, shard 1/1, the whole study, into results/shard-3.
    COUNT=${SLURM_ARRAY_TASK_COUNT:?run this as a job array, or set N}
    MIN=${SLURM_ARRAY_TASK_MIN:-0}
    MAX=${SLURM_ARRAY_TASK_MAX:-$((COUNT - 1))}
    if [ "$COUNT" -eq 1 ] || [ "$MIN" -ne 0 ] || [ "$MAX" -ne $((COUNT - 1)) ]; then
        if [ "$COUNT" -eq 1 ]; then
            echo "run-shards.sh: a one-element array (task $ID) does not say N, the number of shards." >&2
        else
            echo "run-shards.sh: the array (tasks $MIN..$MAX, $COUNT in all) is not 0..N-1, so it does not say N." >&2
        fi
        echo "To rerun task(s) of an N-task array, give N (the first array's size), e.g. for task $ID of 16:" >&2
        echo "  N=16 sbatch --array=$ID $SCRIPT $STUDY" >&2
        echo "(to run the whole study as one task: N=1 sbatch --array=0 $SCRIPT $STUDY)" >&2
        exit 2
    fi
    N=$COUNT
fi
if ! [[ $N =~ ^[1-9][0-9]*$ ]] || [ "$ID" -ge "$N" ]; then
    echo "run-shards.sh: task $ID does not fit N=$N shards (tasks are 0..N-1)" >&2
    exit 2
fi

# The binary: $ROCKFRAG, else rockfrag on PATH, else the target/release/rockfrag
# of the submit folder or the nearest folder above it (as cargo finds its
# workspace from a subfolder).
find_built() {
    local d=${SLURM_SUBMIT_DIR:-$PWD}
    while :; do
        [ -x "$d/target/release/rockfrag" ] && { echo "$d/target/release/rockfrag"; return 0; }
        [ "$d" = / ] || [ -z "$d" ] && return 1
        d=$(dirname "$d")
    done
}
if [ -n "${ROCKFRAG:-}" ]; then
    RF=$ROCKFRAG
    FROM="ROCKFRAG"
elif command -v rockfrag >/dev/null 2>&1; then
    RF=$(command -v rockfrag)
    FROM="PATH"
elif RF=$(find_built); then
    FROM="target/release of the submit folder or above"
else
    echo "run-shards.sh: no rockfrag binary: ROCKFRAG is not set, rockfrag is not on PATH, and there is" >&2
    echo "no target/release/rockfrag in ${SLURM_SUBMIT_DIR:-$PWD} or above (run 'cargo build --release' first)" >&2
    exit 127
fi
echo "run-shards.sh: task $ID: shard $((ID + 1))/$N of $STUDY with $RF (from $FROM), ${SLURM_CPUS_PER_TASK:-1} thread(s)"

mkdir -p results
exec "$RF" run "$STUDY" \
    --shard "$((ID + 1))/$N" \
    --threads "${SLURM_CPUS_PER_TASK:-1}" \
    --out "results/shard-$ID"
