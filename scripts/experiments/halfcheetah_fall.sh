#!/usr/bin/env bash
# Issue 24: why sparse HalfCheetah's dense evaluation falls after its peak here while the
# reference code's keeps rising. Matched seeds 0-2, 100 iterations of 20,000 samples (2M),
# float64: the default; every way the reference code computes differently at once (the
# like-for-like partner of the reference rerun); then each of those ways alone. Resumable:
# run it again and it continues where it stopped.
# Usage: halfcheetah_fall.sh [OUT] [JOBS] [ITERATIONS]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
out="${1:-runs/halfcheetah-fall}"; jobs="${2:-2}"; iterations="${3:-100}"
logo="${LOGO:-./target/release/logo}"
"$logo" sweep configs/logo/halfcheetah.toml configs/experiments/halfcheetah_reference_exact.toml \
  configs/experiments/halfcheetah_reference_fisher.toml \
  configs/experiments/halfcheetah_cross_episode.toml \
  configs/experiments/halfcheetah_strong_wolfe.toml \
  --seeds 0..3 --jobs "$jobs" --threads "$(nproc)" --iterations "$iterations" --out "$out"
reference=docs/results/reference-curves/v4/halfcheetah/seed0.csv
"$logo" plot "$out" --out "$out/figure.png" --paper-lines --smooth 5 \
  --external "$reference,samples,eval_dense_return,reference code (seed 0)"
for metric in eval_action_rms eval_moved delta_k guidance_kl step_norm mean_log_std; do
  "$logo" plot "$out" --out "$out/$metric.png" --metric "$metric" --smooth 5
done
