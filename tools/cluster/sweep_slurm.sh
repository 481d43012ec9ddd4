#!/usr/bin/env bash
# A bridgetwin sweep as a Slurm array job: each array task runs one shard of the plan.
#
#   sbatch --array=0-31 tools/cluster/sweep_slurm.sh plan.toml /shared/sweep-out
#
# Every task expands the same plan into the same numbered runs and takes those with
# index mod SLURM_ARRAY_TASK_COUNT == task index (bridgetwin reads SLURM_ARRAY_TASK_ID,
# SLURM_ARRAY_TASK_MIN and SLURM_ARRAY_TASK_COUNT itself). Resubmitting the same array
# resumes: finished runs (runs/<id>.json present) are skipped. The output directory must
# be on a file system every node sees. runs.csv is rebuilt by each task at its end; the
# last task to finish lists every run (or run `bridgetwin sweep PLAN --out DIR` once
# more afterwards: it skips everything and rewrites the manifest).
#SBATCH --job-name=bridgetwin-sweep
#SBATCH --cpus-per-task=4
#SBATCH --mem-per-cpu=1G
#SBATCH --time=04:00:00
#SBATCH --output=bridgetwin-sweep-%A_%a.log
set -euo pipefail
plan=${1:?usage: sbatch --array=0-N tools/cluster/sweep_slurm.sh PLAN.toml OUT_DIR}
out=${2:?usage: sbatch --array=0-N tools/cluster/sweep_slurm.sh PLAN.toml OUT_DIR}
bridgetwin=${BRIDGETWIN:-bridgetwin}
exec "$bridgetwin" sweep "$plan" --out "$out" --jobs "${SLURM_CPUS_PER_TASK:-1}"
