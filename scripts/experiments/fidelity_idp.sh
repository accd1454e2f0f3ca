#!/usr/bin/env bash
# Issue 16 on sparse InvertedDoublePendulum: the fidelity arms (a)-(e) of
# fidelity_hopper.sh, 5 seeds each, the full 200k budget (40 iterations of 5,000),
# beside the LOGO runs of variants_idp.sh (same config and seeds, run first), which are
# the default arm. Usage: fidelity_idp.sh [OUT] [JOBS]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
out="${1:-runs/fidelity-idp}"; jobs="${2:-2}"
logo="${LOGO:-./target/release/logo}"
default="${DEFAULT_ARM:-runs/variants-idp/logo-inverted_double_pendulum}"
configs=()
for arm in reference_fisher no_decay strong_wolfe cross_episode reference_exact; do
  configs+=("configs/experiments/idp_$arm.toml")
done
"$logo" sweep "${configs[@]}" --seeds 0..5 --jobs "$jobs" --threads 2 --out "$out"
"$logo" plot "$out" "$default" --out "$out/figure.png" --paper-lines --smooth 3
