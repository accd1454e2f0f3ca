#!/usr/bin/env bash
# Clone-started LOGO arms (suite.py CLONE_STARTED) on the suite's tasks, 5 seeds each, to
# set beside the kept runs of every other arm of those tasks (suite.md's tables):
#   bc-logo             the new-task preset from the clone, δ_k held;
#   bc-logo-letting-go  the same, δ_k held until an evaluation's share at the goal reaches
#                       the demonstrations' own, then shrinking by 0.9 after each such one.
# A queue of (arm, task, seed) items that copies of this script share (queue.sh): start
# one copy per free vCPU. A Python env's run (mountain-car, maze) does not resume exactly,
# so one interrupted there is deleted before the queue is started again.
# Usage: PYTHON=<venv>/bin/python LOGO=path/to/logo \
#          scripts/experiments/suite_clone_started.sh ARM[,ARM] TASK...
set -uo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
export LOGO="${LOGO:-$PWD/target/release/logo}"
python="${PYTHON:-.venv/bin/python}"
source scripts/experiments/queue.sh
[ $# -ge 2 ] || { echo "usage: $0 ARM[,ARM] TASK..." >&2; exit 2; }
arms=${1//,/ }
shift
queue_suite suite_clone_started "$arms" "$@"
