#!/usr/bin/env bash
# Puts back the learner checkpoints of runs kept under docs/results/, for a study that
# extends them (paper_scale.sh, fig1_ant.sh use it): since the docs keep a
# policy alone (scripts/slim_results.py), the last commit that holds each run's
# checkpoint.safetensors and best.safetensors as the learner wrote them is HELD below.
# Each RUN folder (e.g. docs/results/paper-scale/hopper/hopper/seed0) is copied to OUT/RUN
# (its metrics.csv, eval.json and config.toml too), from which `logo train --resume`
# continues it to the numbers of an unbroken run.
# Usage: scripts/experiments/restore_run.sh OUT RUN...
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
held=13235261fb72f5194834f1ea26159d3dccffc917
[ $# -ge 2 ] || { echo "usage: $0 OUT RUN..." >&2; exit 2; }
out=$1
shift
git cat-file -e "$held^{commit}" 2>/dev/null \
  || { echo "restore_run: commit $held is not in this clone (a shallow clone? git fetch --unshallow)" >&2; exit 1; }
for run in "$@"; do
  run=${run%/}
  # docs/results/suite-why was runs/suite-why, a study's folder, at that commit.
  at=${run/#docs\/results\/suite-why/runs\/suite-why}
  files=$(git ls-tree --name-only "$held" "$at/") \
    || { echo "restore_run: $run is not a run kept at $held" >&2; exit 1; }
  [ -n "$files" ] || { echo "restore_run: $run is not a run kept at $held" >&2; exit 1; }
  mkdir -p "$out/$run"
  for file in $files; do
    case "$file" in
      *.safetensors|*/metrics.csv|*/eval.json|*/config.toml)
        git show "$held:$file" > "$out/$run/${file##*/}" ;;
    esac
  done
  echo "restore_run: $out/$run (from $held)"
done
