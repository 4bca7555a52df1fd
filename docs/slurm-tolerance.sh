#!/bin/bash
# A tolerance study of the Table 4 springs as a Slurm job array: task I of N runs shard
# I/N of `coil-tune tolerance` and writes parts/part-IIII-of-NNNN.csv; a dependent job
# merges the parts into the table a single run writes (docs/scale-out.md).
#
#   coil-tune calibrate cases/160ect --out out/cal           # once, before the split
#   sbatch --array=1-32 docs/slurm-tolerance.sh               # 32 shards
#   sbatch --dependency=afterok:<jobid> --wrap \
#       "coil-tune merge out/tolerance/parts --out out/tolerance"
#
# Every shard must see the same inputs (case, variants, calibration.json) and write to a
# shared folder; a failed shard is rerun alone (`sbatch --array=7 ...`), and merge
# refuses to run while any shard is missing or given twice.
#SBATCH --job-name=coil-tolerance
#SBATCH --cpus-per-task=1
#SBATCH --mem=1G
#SBATCH --time=02:00:00
#SBATCH --output=out/tolerance/logs/%A_%a.log
set -euo pipefail
N=${SLURM_ARRAY_TASK_COUNT:?run as a job array: sbatch --array=1-N}
I=${SLURM_ARRAY_TASK_ID:?}
# One core per task: the shard's tasks run in coil's thread pool of this size.
export RAYON_NUM_THREADS=${SLURM_CPUS_PER_TASK:-1}
coil-tune tolerance cases/160ect --variants cases/160ect/table4.json \
    --calibration out/cal/calibration.json \
    --samples 10000 --seed 2026 \
    --shard "$I/$N" --out out/tolerance/parts -q
