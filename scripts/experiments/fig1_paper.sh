#!/usr/bin/env bash
# Figure 1 on sparse Walker2d and HalfCheetah: the baselines' runs still to make, 5 seeds x
# 2M each (100 iterations of 20,000 samples), float64 kernels, one thread per run, as the
# sparse Hopper's (docs/findings/baselines.md). A queue of (method, task, seed) items that
# any number of copies of this script share: an item whose run has finished is skipped,
# one whose run another copy holds (its run.lock) is left to that copy, an interrupted one
# resumes exactly. Start one copy per free vCPU.
# Usage: LOGO=path/to/logo scripts/experiments/fig1_paper.sh [OUT]   (OUT: runs/fig1)
set -uo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
out="${1:-runs/fig1}"
logo="${LOGO:-./target/release/logo}"
# A pinned copy of the binary finds MuJoCo here, not by its relative runpath.
export LD_LIBRARY_PATH="$PWD/third_party/mujoco/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
for item in gail:walker2d pofd:walker2d dapg:halfcheetah gail:halfcheetah pofd:halfcheetah; do
  method=${item%%:*}; task=${item##*:}
  for seed in 0 1 2 3 4; do
    run="$out/$method/$task/$task/seed$seed"
    [ -f "$run/eval.json" ] && continue
    echo "[fig1_paper] $(date -u +%FT%TZ) $method $task seed$seed"
    "$logo" sweep "configs/$method/$task.toml" --seeds "$seed..$((seed + 1))" --jobs 1 \
      --threads 1 --iterations 100 --out "$out/$method/$task" \
      || echo "[fig1_paper] $method $task seed$seed: not finished here (held by another copy, or failed: see $run/train.log)"
  done
done
