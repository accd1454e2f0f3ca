#!/usr/bin/env bash
# The candidate presets that let δ_k decay only once the agent reaches the goal (suite.py
# CANDIDATES), on the suite's four tasks with a goal, 5 seeds each, beside the kept runs of
# the held preset (logo) and of LOGO's own decay (logo-decayed):
#   logo-waiting       δ_k shrinks by α = 0.9 at iterations where at least 0.9 of the
#                      batch's sampled episodes reached the goal;
#   logo-eval-waiting  δ_k shrinks by α = 0.9 after each evaluation (the mean action, at
#                      least 10 whole episodes) with at least 0.9 of them at the goal.
# The delayed Hopper reports no success, so there both hold δ_k as the preset does: not run.
# A queue of (arm, task, seed) items that copies of this script share (queue.sh): start one
# copy per free vCPU. A Python env's run (maze, mountain-car) does not resume exactly, so
# those go before the long sparse-Ant tail, whose runs do.
# Usage: LOGO=path/to/logo scripts/experiments/suite_waiting.sh [ARM]   (default: both)
set -uo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
export LOGO="${LOGO:-$PWD/target/release/logo}"
python=.venv/bin/python
source scripts/experiments/queue.sh
arms="${1:-logo-waiting logo-eval-waiting}"
items=(mountain-car:0 mountain-car:1 mountain-car:2 mountain-car:3 mountain-car:4
  ant-distance:0 ant-distance:1 maze:0 maze:1 maze:2 maze:3 maze:4
  reacher-goal:0 reacher-goal:1 reacher-goal:2 reacher-goal:3 reacher-goal:4
  ant-distance:2 ant-distance:3 ant-distance:4)
for arm in $arms; do
  for item in "${items[@]}"; do
    task=${item%%:*}; seed=${item##*:}
    queue_item suite_waiting "runs/suite/$task/runs/$arm/seed$seed/eval.json" \
      "$arm $task seed$seed" "$python" scripts/experiments/suite.py run runs/suite "$task" \
      --seeds "$seed..$((seed + 1))" --arms "$arm"
  done
done
