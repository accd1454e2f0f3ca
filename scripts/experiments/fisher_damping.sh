#!/usr/bin/env bash
# Issue 24: is damping of the natural-gradient step what keeps the reference code's runs
# rising? Matched seeds 0-2, 100 iterations of 20,000 samples (2M), float64, beside the
# default runs of the same seeds (docs/results/four-envs, docs/results/halfcheetah-fall)
# and the reference F·v (J^T M J / N + 2·I on the mean network) runs:
#   - the exact F·v damped by 0.5·I (default 0.01) on sparse HalfCheetah, Hopper, Walker2d;
#   - the reference F·v on sparse Walker2d (HalfCheetah's and Hopper's exist).
# Resumable: run it again and it continues where it stopped.
# Usage: fisher_damping.sh [OUT] [JOBS] [ITERATIONS]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
out="${1:-runs/fisher-damping}"; jobs="${2:-2}"; iterations="${3:-100}"
logo="${LOGO:-./target/release/logo}"
"$logo" sweep configs/experiments/halfcheetah_damped_fisher.toml \
  configs/experiments/hopper_damped_fisher.toml \
  configs/experiments/walker2d_reference_fisher.toml \
  configs/experiments/walker2d_damped_fisher.toml \
  --seeds 0..3 --jobs "$jobs" --threads "$(nproc)" --iterations "$iterations" --out "$out"
