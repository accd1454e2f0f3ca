#!/usr/bin/env bash
# Issue 24: what the final sparse-HalfCheetah policies of each arm do before and after
# the sparse reward's 20 m threshold, acting with the mean action (as the evaluation
# does) and with sampled actions (as training does): 20 episodes each, `logo eval
# --split-at 20`. Usage: halfcheetah_gait.sh RUNS_FOLDER... > gait.txt
# (each folder holds seed*/checkpoint.safetensors).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
logo="${LOGO:-./target/release/logo}"
for arm in "$@"; do
  for checkpoint in "$arm"/seed*/checkpoint.safetensors; do
    for mode in mean sample; do
      flag=(); [ "$mode" = sample ] && flag=(--sample)
      echo "== $(dirname "$checkpoint") $mode"
      "$logo" eval --checkpoint "$checkpoint" --episodes 20 --env HalfCheetah-v4 \
        --split-at 20 "${flag[@]}" | tail -n 2
    done
  done
done
