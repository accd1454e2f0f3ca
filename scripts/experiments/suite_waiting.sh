#!/usr/bin/env bash
# The candidate preset `logo-waiting` (suite.py CANDIDATES: δ_k shrinks by α = 0.9 only at
# iterations where at least 0.9 of the batch's episodes reached the goal) on the suite's
# four tasks with a goal, 5 seeds each, beside the kept runs of the held preset (logo) and
# of LOGO's own decay (logo-decayed). The delayed Hopper reports no success, so there the
# candidate holds δ_k as the preset does: not run.
# Order: the quick MountainCar, two sparse-Ant seeds (the task the preset's choice turns
# on), the Python maze (a Python env's run does not resume exactly, so it goes before the
# long tail), Reacher, then the other Ant seeds (they resume exactly).
# A queue of (task, seed) items that copies of this script share (queue.sh): start one copy
# per free vCPU.
# Usage: LOGO=path/to/logo scripts/experiments/suite_waiting.sh
set -uo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
export LOGO="${LOGO:-$PWD/target/release/logo}"
python=.venv/bin/python
source scripts/experiments/queue.sh
for item in mountain-car:0 mountain-car:1 mountain-car:2 mountain-car:3 mountain-car:4 \
  ant-distance:0 ant-distance:1 maze:0 maze:1 maze:2 maze:3 maze:4 \
  reacher-goal:0 reacher-goal:1 reacher-goal:2 reacher-goal:3 reacher-goal:4 \
  ant-distance:2 ant-distance:3 ant-distance:4; do
  task=${item%%:*}; seed=${item##*:}
  queue_item suite_waiting "runs/suite/$task/runs/logo-waiting/seed$seed/eval.json" \
    "$task seed$seed" "$python" scripts/experiments/suite.py run runs/suite "$task" \
    --seeds "$seed..$((seed + 1))" --arms logo-waiting
done
