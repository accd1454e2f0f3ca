#!/usr/bin/env bash
# The suite's degraded demonstrations (suite.py DEGRADED: the scripted demonstrators made
# worse, reaching the goal in 30-60% of their episodes): on each degraded task, 5 seeds
# of LOGO from the clone (bc-logo), held LOGO (the new-task preset), BC, GAIL and DAPG;
# TRPO's runs are the base task's. A queue of (task, method, seed) items that copies of
# this script share (queue.sh): start one copy per free vCPU. The cheap tasks go first; a
# Python env's run (mountain-car, maze) does not resume exactly, so one interrupted there
# is deleted before the queue is started again.
# Usage: LOGO=path/to/logo scripts/experiments/suite_degraded.sh [TASK...]
set -uo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
export LOGO="${LOGO:-$PWD/target/release/logo}"
# PYTHON: the interpreter whose logo_rl the runs use (a venv pinned for the study).
python="${PYTHON:-.venv/bin/python}"
source scripts/experiments/queue.sh
tasks="${*:-mountain-car-degraded reacher-goal-degraded maze-degraded}"
for task in $tasks; do
  for seed in 0 1 2 3 4; do
    for method in bc bc-logo logo gail dapg; do
      done_file="runs/suite/$task/runs/$method/seed$seed/eval.json"
      [ "$method" = bc ] && done_file="runs/suite/$task/runs/bc/seed$seed/policy.safetensors"
      queue_item suite_degraded "$done_file" "$method $task seed$seed" \
        "$python" scripts/experiments/suite.py run runs/suite "$task" \
        --seeds "$seed..$((seed + 1))" --arms "$method"
    done
  done
done
