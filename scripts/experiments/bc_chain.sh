#!/usr/bin/env bash
# `logo bc` -> `logo eval` -> a TRPO run that starts from the clone, on one of the LOGO
# paper's tasks and its demonstrations: the user's path from a dataset to BC-TRPO, with
# the commands a user types. (A `configs/bc-trpo/` config does the same in one run:
# `[init] kind = "bc"` clones before its first iteration.)
# Usage: scripts/experiments/bc_chain.sh [TASK] [OUT]   (TASK: hopper; OUT: runs/bc-chain)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
task="${1:-hopper}"
out="${2:-runs/bc-chain}/$task"
logo="${LOGO:-./target/release/logo}"
export LD_LIBRARY_PATH="$PWD/third_party/mujoco/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
mkdir -p "$out"
# 1. Clone the demonstrations (the BC-TRPO config's env, demonstrations, sizes and seed).
"$logo" bc --config "configs/bc-trpo/$task.toml" --out "$out/bc.safetensors"
# 2. Score the clone again from its checkpoint, as any policy.
"$logo" eval --checkpoint "$out/bc.safetensors" --episodes 20
# 3. TRPO from the clone: the TRPO config with `init_policy` (first, so that it stays a
# top-level key; paths in a config are relative to its folder), one iteration.
{ echo 'init_policy = "bc.safetensors"'; cat "configs/trpo/$task.toml"; } > "$out/trpo-from-bc.toml"
"$logo" train --config "$out/trpo-from-bc.toml" --out "$out/trpo-from-bc" --threads 1 \
  --iterations 1
