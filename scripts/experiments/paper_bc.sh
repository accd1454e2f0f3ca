#!/usr/bin/env bash
# Behaviour cloning alone on the LOGO paper's four sparse tasks, 5 seeds each: the clone
# BC-TRPO and DAPG start from (`logo bc --config configs/bc-trpo/<task>.toml`, the same
# demonstrations, sizes and [init] settings), scored over 20 fresh episodes
# (policy.eval.json), for the README's task × method table beside the Figure 1 arms.
# Resumable: a seed with its policy.eval.json is skipped.
# Usage: LOGO=path/to/logo scripts/experiments/paper_bc.sh [OUT]   (OUT: runs/paper-bc)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
out="${1:-runs/paper-bc}"
logo="${LOGO:-./target/release/logo}"
export LD_LIBRARY_PATH="$PWD/third_party/mujoco/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
for task in inverted_double_pendulum hopper walker2d halfcheetah; do
  for seed in 0 1 2 3 4; do
    dir="$out/$task/bc/seed$seed"
    [ -f "$dir/policy.eval.json" ] && continue
    mkdir -p "$dir"
    echo "[paper_bc] $(date -u +%FT%TZ) $task seed$seed"
    "$logo" bc --config "configs/bc-trpo/$task.toml" --seed "$seed" \
      --out "$dir/policy.safetensors" > "$dir/bc.txt"
  done
done
