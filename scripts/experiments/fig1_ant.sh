#!/usr/bin/env bash
# Figure 1 on sparse Ant (Ant-v4+distance(5), the new-task study's task and demonstrations):
# LOGO, TRPO, GAIL, POfD, BC-TRPO and DAPG, 3 seeds x 2M, each method made by `logo compare`
# from that study's LOGO config by its own keys. The study's own LOGO and TRPO runs
# (docs/results/new-task/ant/runs, binary f448712, 100 iterations with their checkpoints)
# are copied in first, so compare counts them as done and trains the four others.
# Usage: fig1_ant.sh [OUT]   (resumable: run it again after an interruption)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
out="${1:-runs/fig1-ant}"
logo="${LOGO:-./target/release/logo}"
# A pinned copy of the binary finds MuJoCo here, not by its relative runpath.
export LD_LIBRARY_PATH="$PWD/third_party/mujoco/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
kept=docs/results/new-task/ant
# docs/results keeps their policies alone: their learner checkpoints come back from the
# commit that holds them (restore_run.sh), so that compare counts the runs done.
scripts/experiments/restore_run.sh runs/kept "$kept"/runs/{logo,trpo}/seed{0,1,2} >/dev/null
for method in logo trpo; do
  for seed in 0 1 2; do
    if [ ! -e "$out/$method/seed$seed" ]; then
      mkdir -p "$out/$method"
      cp -r "runs/kept/$kept/runs/$method/seed$seed" "$out/$method/seed$seed"
    fi
  done
done
"$logo" compare --config "$kept/configs/logo.toml" \
  --algorithms logo,trpo,gail,pofd,bc-trpo,dapg --seeds 0..3 --samples 2M \
  --jobs 1 --threads 1 --out "$out"
