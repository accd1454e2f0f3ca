#!/usr/bin/env bash
# Issue 15: the incomplete-observation ("censored") setting: sparse IDP (5 seeds, 40
# iterations) and sparse Hopper (3 seeds, 100 iterations of 20,000 samples), plotted
# beside the full-observation LOGO runs. Usage: censored.sh [OUT] [JOBS] [ITERATIONS]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
out="${1:-runs/censored}"; jobs="${2:-2}"; iterations="${3:-100}"
logo="${LOGO:-./target/release/logo}"
"$logo" sweep configs/experiments/idp_censored.toml --seeds 0..5 --jobs "$jobs" --threads 2 --out "$out"
"$logo" sweep configs/experiments/hopper_censored.toml --seeds 0..3 --jobs "$jobs" --threads 2 \
  --iterations "$iterations" --out "$out"
"$logo" plot "$out/idp_censored" "${VARIANTS_IDP:-runs/variants-idp}/logo-inverted_double_pendulum" \
  --out "$out/idp.png" --paper-lines
"$logo" plot "$out/hopper_censored" "${LOGO_RUNS:-runs/four-envs}/hopper/logo-hopper" \
  --out "$out/hopper.png" --paper-lines --smooth 5
