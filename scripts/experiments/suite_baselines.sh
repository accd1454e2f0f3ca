#!/usr/bin/env bash
# The seed's Figure 1 baselines on the suite (suite.py BASELINES: GAIL, POfD, BC-TRPO and
# DAPG, each the task's LOGO config made into it as `logo compare` makes it), 5 seeds on
# each of its five tasks, beside the kept LOGO, TRPO and BC runs. A queue of (method,
# task, seed) items that copies of this script share (queue.sh): start one copy per free
# vCPU. The cheap tasks go first; a Python env's run (mountain-car, maze) does not resume
# exactly, so one interrupted there is deleted before the queue is started again.
# Usage: LOGO=path/to/logo scripts/experiments/suite_baselines.sh [TASK...]
set -uo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
export LOGO="${LOGO:-$PWD/target/release/logo}"
python=.venv/bin/python
source scripts/experiments/queue.sh
tasks="${*:-mountain-car reacher-goal maze hopper-delayed ant-distance}"
# shellcheck disable=SC2086 # the tasks are words
queue_suite suite_baselines "gail pofd bc-trpo dapg" $tasks
