#!/bin/bash
# Run a rockfrag study as a SLURM job array: task i runs shard i+1 of N into
# results/shard-<i>. Submit from the repository root:
#
#   sbatch --array=0-15 studies/slurm/run-shards.sh studies/fragility.toml
#
# Create results/ first (SLURM opens the log there). The array size sets N (SLURM_ARRAY_TASK_COUNT). Then merge (see studies/README.md):
#
#   rockfrag merge results/shard-* --out results/fragility
#
# A task that is killed (time limit, preemption) resumes where it stopped
# when it is run again with the same arguments: resubmit the failed indices,
# e.g. sbatch --array=3,7 ... (keep N the same: pass N=16 in the environment).
#
#SBATCH --job-name=rockfrag
#SBATCH --cpus-per-task=8
#SBATCH --time=02:00:00
#SBATCH --output=results/slurm-%A_%a.out

set -euo pipefail

STUDY=${1:?usage: sbatch --array=0-(N-1) run-shards.sh STUDY.toml}
N=${N:-${SLURM_ARRAY_TASK_COUNT:?run this as a job array (sbatch --array=0-15), or set N}}
ID=${SLURM_ARRAY_TASK_ID:?run this as a job array}
ROCKFRAG=${ROCKFRAG:-rockfrag}

mkdir -p results
exec "$ROCKFRAG" run "$STUDY" \
    --shard "$((ID + 1))/$N" \
    --threads "${SLURM_CPUS_PER_TASK:-1}" \
    --out "results/shard-$ID"
