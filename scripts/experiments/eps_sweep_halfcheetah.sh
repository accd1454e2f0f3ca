#!/usr/bin/env bash
# Issue 13: the seed paper's Figure 3, the clip ε of modified LOGO (LOGO+PPO+CDQ,
# Algorithm 2) on sparse HalfCheetah at 0.1, 0.2, 0.3, 0.4, 3 seeds each, 50 iterations of
# 20,000 samples (1M). ε = 0.2 is the default, so when variants_mujoco.sh has run
# LOGO+PPO+CDQ on HalfCheetah (the same config and seeds) those runs are linked in as
# eps0.2 instead of being run again. Usage: eps_sweep_halfcheetah.sh [OUT] [JOBS] [ITERATIONS]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
out="${1:-runs/eps-halfcheetah}"; jobs="${2:-2}"; iterations="${3:-50}"
logo="${LOGO:-./target/release/logo}"
default_runs="${DEFAULT_EPS_RUNS:-runs/variants-mujoco/halfcheetah/logo-ppo-cdq-halfcheetah}"
mkdir -p "$out/configs"
configs=()
for eps in 0.1 0.2 0.3 0.4; do
  if [[ $eps == 0.2 && -d $default_runs && ! -e $out/eps0.2 ]]; then
    ln -s "$(realpath "$default_runs")" "$out/eps0.2"
  fi
  [[ -L $out/eps$eps ]] && continue
  config="$out/configs/eps$eps.toml"
  sed -e "s|\.\./\.\./data/|$PWD/data/|" \
      -e "s|^kind = \"ppo-clip\"|kind = \"ppo-clip\"\nclip_epsilon = $eps|" \
      configs/logo-ppo-cdq/halfcheetah.toml > "$config"
  configs+=("$config")
done
"$logo" sweep "${configs[@]}" --seeds 0..3 --jobs "$jobs" --threads 2 \
  --iterations "$iterations" --out "$out"
"$logo" plot "$out" --out "$out/figure.png" --paper-lines --smooth 5
