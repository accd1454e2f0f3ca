#!/usr/bin/env bash
# Issue 13: every algorithm on sparse InvertedDoublePendulum, 5 seeds, the full budget
# (40 iterations of 5,000 samples), then the figure. Usage: variants_idp.sh [OUT] [JOBS]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
out="${1:-runs/variants-idp}"; jobs="${2:-2}"
logo="${LOGO:-./target/release/logo}"
configs=()
for algo in logo logo-ppo logo-cdq logo-ppo-cdq logo-ppo-penalty logo-clip-in-trpo ppo trpo; do
  configs+=("configs/$algo/inverted_double_pendulum.toml")
done
"$logo" sweep "${configs[@]}" --seeds 0..5 --jobs "$jobs" --threads 2 --out "$out"
"$logo" plot "$out" --out "$out/figure.png" --paper-lines
