#!/usr/bin/env bash
# The suite's sparse Ant (ant-distance), why LOGO's final policy does not get to 5 m: the
# suite's LOGO config (runs/suite/ant-distance/configs/logo.toml, written by `suite.py run`)
# with one key changed per arm, 3 seeds x 2M each, LOGO only:
#   logo-held:  alpha = 1.0, δ_k held at δ_0 (the preset's decay on success shrank it on
#               rare, scattered successes of the sampled episodes);
#   logo-sigma: log_std_init = -1.0, σ starts at ≈ 0.37, the behaviour policy's start.
# A queue of (arm, seed) items that copies of this script share (queue.sh): start one copy
# per free vCPU.
# Usage: LOGO=path/to/logo scripts/experiments/suite_why_ant.sh [OUT]   (OUT: runs/suite-why)
set -uo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
out="${1:-runs/suite-why}/ant-distance"
logo="${LOGO:-./target/release/logo}"
source scripts/experiments/queue.sh
suite=runs/suite/ant-distance/configs/logo.toml
mkdir -p "$out/configs"
if [ ! -f "$out/configs/logo-held.toml" ] || [ ! -f "$out/configs/logo-sigma.toml" ]; then
  [ -f "$suite" ] || { echo "$suite: missing (run: suite.py run runs/suite ant-distance)" >&2; exit 1; }
fi
if [ ! -f "$out/configs/logo-held.toml" ]; then
  grep -qx 'alpha = 0.9' "$suite" || { echo "$suite: no line 'alpha = 0.9'" >&2; exit 1; }
  sed -e 's/^alpha = 0\.9$/alpha = 1.0/' \
    -e "1s|^.*\$|# The suite-why check on ant-distance: the suite's LOGO config ($suite) with alpha = 1.0, δ_k held at δ_0.|" \
    "$suite" > "$out/configs/logo-held.toml"
fi
if [ ! -f "$out/configs/logo-sigma.toml" ]; then
  grep -qx 'iterations = 400' "$suite" || { echo "$suite: no line 'iterations = 400'" >&2; exit 1; }
  sed -e 's/^iterations = 400$/iterations = 400\n# The suite-why check: σ starts at e^-1 ≈ 0.37 (the behaviour policy'"'"'s start, docs\/findings\/new-tasks.md) instead of 1.\nlog_std_init = -1.0/' \
    -e "1s|^.*\$|# The suite-why check on ant-distance: the suite's LOGO config ($suite) with log_std_init = -1.0.|" \
    "$suite" > "$out/configs/logo-sigma.toml"
fi
for arm in logo-held logo-sigma; do
  for seed in 0 1 2; do
    queue_item suite_why_ant "$out/runs/$arm/seed$seed/eval.json" "$arm seed$seed" \
      "$logo" sweep "$out/configs/$arm.toml" --seeds "$seed..$((seed + 1))" --jobs 1 --threads 1 \
      --out "$out/runs"
  done
done
