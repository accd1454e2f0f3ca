#!/usr/bin/env bash
# Copies what a study keeps in git from its run folders (docs/results/README.md): each
# run's metrics.csv, config.toml, eval.json, its `logo eval` outputs (eval-*.txt) where
# there are some, and its checkpoints as policies alone (`logo export`: a run is extended
# from the study's own runs/ folder, or from the commit that kept it, restore_run.sh),
# under the same layout; figures (*.png, *.csv) and tables (*.md) beside the runs too.
# Logs, locks and TensorBoard files stay behind.
# Usage: keep_runs.sh SRC DST   (e.g. runs/paper-scale docs/results/paper-scale)
set -euo pipefail
src="${1:?SRC}"; dst="${2:?DST}"
[ -d "$src" ] || { echo "keep_runs.sh: $src is not a folder" >&2; exit 1; }
find "$src" -name metrics.csv -print0 | while IFS= read -r -d '' metrics; do
  run="$(dirname "$metrics")"
  to="$dst/${run#"$src"/}"
  mkdir -p "$to"
  for file in metrics.csv config.toml eval.json "$run"/eval-*.txt; do
    file="$(basename "$file")"
    if [ -f "$run/$file" ]; then cp "$run/$file" "$to/$file"; fi
  done
  for file in checkpoint.safetensors best.safetensors; do
    if [ -f "$run/$file" ]; then
      "${LOGO:-./target/release/logo}" export --checkpoint "$run/$file" --out "$to/$file" >/dev/null
    fi
  done
done
find "$src" -maxdepth 2 -type f \( -name '*.png' -o -name '*.csv' -o -name '*.md' \) \
  ! -name metrics.csv -print0 | while IFS= read -r -d '' file; do
  mkdir -p "$dst/$(dirname "${file#"$src"/}")"
  cp "$file" "$dst/${file#"$src"/}"
done
