#!/usr/bin/env bash
# Issue 15: LOGO and TRPO on sparse Hopper, Walker2d and HalfCheetah, 3 seeds each, 100
# iterations of 20,000 samples (2M), with the reference's hyperparameters; one figure per
# env. Usage: four_envs.sh [OUT] [JOBS] [ITERATIONS]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
out="${1:-runs/four-envs}"; jobs="${2:-2}"; iterations="${3:-100}"
logo="${LOGO:-./target/release/logo}"
for env in hopper walker2d halfcheetah; do
  "$logo" sweep "configs/logo/$env.toml" "configs/trpo/$env.toml" --seeds 0..3 \
    --jobs "$jobs" --threads 2 --iterations "$iterations" --out "$out/$env"
  "$logo" plot "$out/$env" --out "$out/$env.png" --paper-lines --smooth 5
done
