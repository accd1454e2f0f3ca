#!/usr/bin/env bash
# Issue 13: LOGO+PPO, LOGO+CDQ, LOGO+PPO+CDQ and LOGO+PPO-Penalty on sparse Hopper,
# Walker2d and HalfCheetah, 3 seeds each, 50 iterations of 20,000 samples (1M), plotted
# with four_envs.sh's LOGO runs of the same seeds (run first), every curve cut at the
# variants' budget. One figure per env.
# Usage: variants_mujoco.sh [OUT] [JOBS] [ITERATIONS]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
out="${1:-runs/variants-mujoco}"; jobs="${2:-2}"; iterations="${3:-50}"
logo="${LOGO:-./target/release/logo}"
plot="${LOGO_PLOT:-$logo}" # a sweep may train with a pinned older binary; plots need --max-samples
# Each iteration overshoots its 20,000 samples by less than one episode (≤ 1000 steps):
# cutting at 21,000 per iteration keeps every variant iteration and LOGO's up to it.
cut=$((iterations * 21000))
for env in hopper walker2d halfcheetah; do
  configs=()
  for algo in logo-ppo logo-cdq logo-ppo-cdq logo-ppo-penalty; do
    configs+=("configs/$algo/$env.toml")
  done
  "$logo" sweep "${configs[@]}" --seeds 0..3 --jobs "$jobs" --threads 2 \
    --iterations "$iterations" --out "$out/$env"
  "$plot" plot "$out/$env" "${LOGO_RUNS:-runs/four-envs}/$env/logo-$env" \
    --out "$out/$env.png" --paper-lines --smooth 5 --max-samples "$cut"
done
