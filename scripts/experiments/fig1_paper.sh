#!/usr/bin/env bash
# Figure 1 on sparse Walker2d and HalfCheetah: the baselines' runs still to make, 5 seeds x
# 2M each (100 iterations of 20,000 samples), float64 kernels, one thread per run, as the
# sparse Hopper's (docs/findings/baselines.md). A queue of (method, task, seed) items that
# copies of this script share (queue.sh): start one copy per free vCPU.
# Usage: LOGO=path/to/logo scripts/experiments/fig1_paper.sh [OUT]   (OUT: runs/fig1)
set -uo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
out="${1:-runs/fig1}"
logo="${LOGO:-./target/release/logo}"
source scripts/experiments/queue.sh
for item in gail:walker2d pofd:walker2d dapg:halfcheetah gail:halfcheetah pofd:halfcheetah; do
  method=${item%%:*}; task=${item##*:}
  for seed in 0 1 2 3 4; do
    queue_item fig1_paper "$out/$method/$task/$task/seed$seed/eval.json" "$method $task seed$seed" \
      "$logo" sweep "configs/$method/$task.toml" --seeds "$seed..$((seed + 1))" --jobs 1 \
      --threads 1 --iterations 100 --out "$out/$method/$task"
  done
done
