# Sourced by the experiment scripts whose copies share a queue of runs (fig1_paper.sh,
# suite_why_ant.sh, suite_preset.sh): start one copy per free vCPU; each item is a run
# that a finished copy skips, that another copy's lock keeps (logo's run.lock: the command
# fails at once and the item is passed over), or that an interrupted copy left (the
# command resumes it exactly).

# A pinned copy of the binary finds MuJoCo here, not by its relative runpath.
export LD_LIBRARY_PATH="$PWD/third_party/mujoco/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"

# queue_item TAG DONE LABEL COMMAND...: COMMAND, unless the file DONE says the run has
# finished; a COMMAND that fails is said, with the run's LABEL, and passed over.
queue_item() {
  local tag=$1 done=$2 label=$3
  shift 3
  [ -f "$done" ] && return 0
  echo "[$tag] $(date -u +%FT%TZ) $label"
  "$@" || echo "[$tag] $label: not finished here (held by another copy, or failed: see its train.log)"
}

# queue_suite TAG "ARM ..." TASK...: suite.py's runs as queue items, task by task, seed by
# seed (0-4), arm by arm; an item is done once its run's eval.json is there. The caller
# sets $python, the interpreter whose logo_rl the runs use.
queue_suite() {
  local tag=$1 arms=$2 task seed arm
  shift 2
  for task in "$@"; do
    for seed in 0 1 2 3 4; do
      for arm in $arms; do
        queue_item "$tag" "runs/suite/$task/runs/$arm/seed$seed/eval.json" \
          "$arm $task seed$seed" "$python" scripts/experiments/suite.py run runs/suite "$task" \
          --seeds "$seed..$((seed + 1))" --arms "$arm"
      done
    done
  done
}
