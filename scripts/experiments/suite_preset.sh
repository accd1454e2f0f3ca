#!/usr/bin/env bash
# The suite's LOGO arm again, after a change of the new-task preset (configs/templates/
# new_task.toml): TRPO and BC do not read the preset's guidance, so only LOGO is run, on
# the suite's four tasks with a goal, 5 seeds each (the delayed Hopper already held δ_k).
#   - runs/suite/<task>/runs/trpo and bc: the kept runs of docs/results/suite/<task>, where
#     absent (their eval.json is all `suite.py report` reads);
#   - runs/suite/<task>/runs/logo-decayed: the LOGO runs made with the earlier preset;
#   - ant-distance seeds 0-2: the held arm of suite_why_ant.sh (the suite's LOGO config with
#     alpha = 1.0: the same numbers as the new preset's), copied where finished.
# A queue of (task, seed) items that copies of this script share (queue.sh): start one copy
# per free vCPU.
# Usage: LOGO=path/to/logo scripts/experiments/suite_preset.sh
set -uo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
export LOGO="${LOGO:-$PWD/target/release/logo}"
python=.venv/bin/python
source scripts/experiments/queue.sh
mkdir -p runs/suite
# Put in place, by one copy at a time; each folder arrives whole (copied beside, then moved).
place() { [ -e "$2" ] || { rm -rf "$2.partial" && cp -r "$1" "$2.partial" && mv "$2.partial" "$2"; }; }
(
  flock 9
  for task in ant-distance reacher-goal mountain-car maze; do
    runs=runs/suite/$task/runs
    mkdir -p "$runs"
    for arm in trpo bc; do place "docs/results/suite/$task/$arm" "$runs/$arm"; done
    if [ ! -e "$runs/logo-decayed" ]; then
      if [ -d "$runs/logo" ]; then mv "$runs/logo" "$runs/logo-decayed"
      else place "docs/results/suite/$task/logo" "$runs/logo-decayed"; fi
    fi
  done
  held=docs/results/suite-why/ant-distance/runs/logo-held
  mkdir -p runs/suite/ant-distance/runs/logo
  for seed in 0 1 2; do
    [ -f "$held/seed$seed/eval.json" ] || continue
    place "$held/seed$seed" "runs/suite/ant-distance/runs/logo/seed$seed"
    rm -f "runs/suite/ant-distance/runs/logo/seed$seed/run.lock"
  done
) 9> runs/suite/.suite_preset.lock
for item in ant-distance:3 ant-distance:4 maze:0 maze:1 maze:2 maze:3 maze:4 \
  reacher-goal:0 reacher-goal:1 reacher-goal:2 reacher-goal:3 reacher-goal:4 \
  mountain-car:0 mountain-car:1 mountain-car:2 mountain-car:3 mountain-car:4 \
  ant-distance:0 ant-distance:1 ant-distance:2; do
  task=${item%%:*}; seed=${item##*:}
  queue_item suite_preset "runs/suite/$task/runs/logo/seed$seed/eval.json" "$task seed$seed" \
    "$python" scripts/experiments/suite.py run runs/suite "$task" --seeds "$seed..$((seed + 1))" \
    --arms logo
done
