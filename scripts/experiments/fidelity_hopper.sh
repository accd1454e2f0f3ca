#!/usr/bin/env bash
# Issue 16: matched-seed arms on sparse Hopper against today's default, 3 seeds each,
# 100 iterations of 20,000 samples (2M). Arms: (a) the reference's F·v, (b) δ_k never
# decaying, (c) the strong-Wolfe L-BFGS, (d) the cross-episode bootstrap, (e) all of
# the reference's ways at once; and (f) the discriminator's output layer initialised
# uniformly, the default before edac686 (docs/results.md, issue 16). The default arm is four_envs.sh's LOGO Hopper sweep
# (the same config and seeds), run first. Usage: fidelity_hopper.sh [OUT] [JOBS] [ITERATIONS]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
out="${1:-runs/fidelity-hopper}"; jobs="${2:-2}"; iterations="${3:-100}"
logo="${LOGO:-./target/release/logo}"
default="${DEFAULT_ARM:-runs/four-envs/hopper/logo-hopper}"
"$logo" sweep configs/experiments/hopper_reference_fisher.toml \
  configs/experiments/hopper_no_decay.toml configs/experiments/hopper_strong_wolfe.toml \
  configs/experiments/hopper_cross_episode.toml configs/experiments/hopper_reference_exact.toml \
  configs/experiments/hopper_uniform_discriminator.toml \
  --seeds 0..3 --jobs "$jobs" --threads 2 --iterations "$iterations" --out "$out"
"$logo" plot "$out" "$default" --out "$out/figure.png" --paper-lines --smooth 5
