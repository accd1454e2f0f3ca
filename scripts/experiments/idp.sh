#!/usr/bin/env bash
# Issue 4's InvertedDoublePendulum experiment: LOGO (reference hyperparameters, the LOGO
# paper's demonstrations) on 5 seeds, and the TRPO baseline on 2, on sparse IDP.
# Prints, per run: the first iteration (and samples) with dense eval >= 9000, the final
# and best eval, the wall time. Usage: scripts/experiments/idp.sh [OUT_DIR]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
out="${1:-runs/idp}"
cargo build --release --bin logo
mkdir -p "$out"
run() { # algo seed
  ./target/release/logo train --config "configs/$1/inverted_double_pendulum.toml" --seed "$2" --out "$out/$1-seed$2" > "$out/$1-seed$2.log"
}
for seed in 0 1 2 3 4; do run logo "$seed"; done
for seed in 0 1; do run trpo "$seed"; done
summary() { # metrics.csv -> one line
  awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
    { e = $col["eval_dense_return"]; if (e > best) best = e
      if (first == "" && e >= 9000) { first = $col["iteration"] + 1; at = $col["samples"] }
      last = e; wall = $col["wall_s"] }
    END { printf "first >= 9000: %s (%s samples) | final %.1f | best %.1f | wall %.1f s\n",
          (first == "" ? "never" : "iteration " first), (at == "" ? "-" : at), last, best, wall }' "$1"
}
for run in "$out"/*/; do
  printf '%-14s %s\n' "$(basename "$run")" "$(summary "$run/metrics.csv")"
done | tee "$out/summary.txt"
