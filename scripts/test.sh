#!/usr/bin/env bash
# The test command: set up (idempotent), check the Gymnasium oracle has not drifted from
# the committed parity fixtures, then run every Rust test in release mode (MuJoCo and
# burn are too slow unoptimised, and the main job shares this build).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

./scripts/setup.sh
# Binaries find libmujoco by an rpath relative to ./target; this also covers a
# CARGO_TARGET_DIR outside the checkout.
# Tests that use the Python oracle fail instead of skipping when it is missing.
export LOGO_REQUIRE_PYTHON=1
# On CI the Slurm integration test must run (it installs and starts a single-node
# cluster through scripts/slurm-cluster.sh, as root, and stops it at the end).
if [ "${CI:-}" = true ]; then
  export LOGO_REQUIRE_SLURM=1
fi
export LD_LIBRARY_PATH="$root/third_party/mujoco/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"

echo "== parity fixtures vs the Gymnasium 1.4.0 oracle"
.venv/bin/python -W ignore tests/parity/generate.py --check tests/parity/fixtures

echo "== cargo test --release --workspace"
cargo test --release --workspace "$@"
