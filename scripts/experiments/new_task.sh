#!/usr/bin/env bash
# A new task end to end (docs/new-task.md): from a dense task id to LOGO against TRPO on
# its sparse version, with demonstrations made here as the LOGO authors made theirs.
#   1. behaviour policy: TRPO on the dense reward, stopped when the sampled episodes'
#      mean return reaches TARGET (a sub-optimal policy, as the paper's);
#   2. demonstrations: EPISODES episodes of it (sampled actions) on the sparse task, as a
#      Minari dataset (its stored rewards the sparse ones, the dense in its metadata);
#   3. LOGO (guided by them) and TRPO (not) on the sparse task, SEEDS seeds each; then
#      `logo summary` (summary.md) and `logo plot` (curves.png).
# Resumable: run it again and the training and recording go on from where they stopped
# (finished ones are skipped). Every `logo` command is printed before it runs.
#
# Usage: new_task.sh TASK SPARSE TARGET
#   TASK    a dense id of `logo envs`, e.g. Hopper-v4
#   SPARSE  how its reward is made sparse: distance(<metres>), delayed, or goal(<metres>)
#           (Reacher and Pusher)
#   TARGET  the behaviour policy's stopping return (dense)
# Settings, as environment variables (defaults in brackets):
#   OUT [runs/new-task/<task>-<rule>, lower-cased]  LOGO [./target/release/logo]
#   BEHAVIOUR_ITERATIONS [500]  BEHAVIOUR_SAMPLES [5000]  EPISODES [20]
#   BEHAVIOUR_LOG_STD [the config default]: the behaviour policy's initial log sigma
#   ITERATIONS [100]  SAMPLES [20000]  SEEDS [0..3]  JOBS [1]
#   LOG_STD [the config default]: LOGO's and TRPO's initial log sigma on the sparse task
#   DELTA0 [0.01]  ALPHA [0.95]  WARMUP [50]  (LOGO's guidance: the paper's Hopper values;
#   it chose δ_0 per task, 0.01 to 0.2; docs/new-task.md says how to choose them)
set -euo pipefail

usage() {
  sed -n '/^# Usage/,/^set -euo/p' "${BASH_SOURCE[0]}" | sed '$d; s/^# \{0,1\}//' >&2
  exit 2
}

# `distance(2)`, `delayed` or `goal(0.02)` as the TOML inline table of a config's [env] sparse.
sparse_table() {
  case "$1" in
    distance\(*\) | goal\(*\))
      local kind="${1%%(*}" metres="${1#*(}" key=threshold
      metres="${metres%)}"
      [ "$kind" = goal ] && key=radius
      [[ "$metres" =~ ^(0|[1-9][0-9]*)(\.[0-9]+)?$ ]] || {
        echo "new_task.sh: SPARSE $1: the $key must be a positive number of metres" >&2
        exit 2
      }
      echo "{ kind = \"$kind\", $key = $metres }" ;;
    delayed) echo '{ kind = "delayed" }' ;;
    *)
      echo "new_task.sh: SPARSE $1: expected distance(<metres>), delayed or goal(<metres>)" >&2
      exit 2 ;;
  esac
}

# Prints a command, then runs it.
run() {
  echo "+ $*" >&2
  "$@"
}

main() {
  [ $# -eq 3 ] || usage
  local task="$1" rule="$2" sparse target="$3"
  sparse="$(sparse_table "$rule")"
  [[ "$target" =~ ^-?[0-9]+(\.[0-9]+)?$ ]] || {
    echo "new_task.sh: TARGET $target: expected a number" >&2
    exit 2
  }
  case "$task" in
    Sparse* | *+*)
      echo "new_task.sh: TASK $task: give the dense id (e.g. Hopper-v4); SPARSE makes it sparse" >&2
      exit 2 ;;
  esac
  local logo="${LOGO:-./target/release/logo}"
  local name
  name="$(echo "$task-$rule" | tr '[:upper:]' '[:lower:]' | tr -c 'a-z0-9.\n' '-')"
  local out="${OUT:-runs/new-task/${name%-}}"
  local configs="$out/configs"
  [ -x "$logo" ] || {
    echo "new_task.sh: $logo is not built (cargo build --release -p logo-cli, or set LOGO)" >&2
    exit 2
  }
  mkdir -p "$configs"
  # A folder holds one task, rule and target: going on in it with others would mix
  # their demonstrations and runs.
  local params="task $task, sparse $rule, target $target"
  if [ -f "$out/params" ] && [ "$(cat "$out/params")" != "$params" ]; then
    echo "new_task.sh: $out holds $(cat "$out/params"); give another OUT for $params" >&2
    exit 2
  fi
  echo "$params" > "$out/params"

  # 1. The behaviour policy.
  cat > "$configs/behaviour.toml" <<EOF
# TRPO on the dense $task reward, stopped at a return of $target (new_task.sh, step 1).
env = "$task"
iterations = ${BEHAVIOUR_ITERATIONS:-500}
samples_per_iter = ${BEHAVIOUR_SAMPLES:-5000}
eval_steps = ${BEHAVIOUR_SAMPLES:-5000}
max_kl = 0.01
EOF
  if [ -n "${BEHAVIOUR_LOG_STD:-}" ]; then
    echo "log_std_init = $BEHAVIOUR_LOG_STD" >> "$configs/behaviour.toml"
  fi
  local behaviour="$out/behaviour"
  # Stopped at the target, then killed before `done` was written: that policy stands.
  if grep -qs "reached --stop-at-return" "$out/behaviour.log"; then touch "$behaviour/done"; fi
  if [ ! -f "$behaviour/done" ]; then
    local stop=(--stop-at-return="$target" --stop-metric train)  # `=`: a negative target is not a flag
    if [ -f "$behaviour/checkpoint.safetensors" ]; then
      run "$logo" train --resume "$behaviour" "${stop[@]}" --no-tensorboard | tee -a "$out/behaviour.log"
    else
      run "$logo" train --config "$configs/behaviour.toml" --out "$behaviour" "${stop[@]}" \
        --no-tensorboard | tee -a "$out/behaviour.log"
    fi
    if ! grep -q "reached --stop-at-return" "$out/behaviour.log"; then
      echo "new_task.sh: the behaviour policy did not reach $target in" \
        "${BEHAVIOUR_ITERATIONS:-500} iterations; its last policy is recorded" >&2
    fi
    touch "$behaviour/done"
  fi

  # 2. The demonstrations.
  local demos="$out/demos"
  if [ ! -f "$demos/data/metadata.json" ]; then
    run "$logo" data record --policy "$behaviour/checkpoint.safetensors" --env "$task+$rule" \
      --episodes "${EPISODES:-20}" --seed 0 --out "$demos"
  fi
  run "$logo" data inspect "$demos"

  # 3. LOGO and TRPO on the sparse task.
  local common
  common="$(cat <<EOF
iterations = ${ITERATIONS:-100}
samples_per_iter = ${SAMPLES:-20000}
max_kl = 0.01${LOG_STD:+
log_std_init = $LOG_STD}

[env]
id = "$task"
sparse = $sparse
EOF
)"
  printf '# LOGO on %s made sparse (new_task.sh, step 3).\n%s\n\n[guidance]\ndemos = "../demos"\ndelta0 = %s\nalpha = %s\nwarmup = %s\n' \
    "$task" "$common" "${DELTA0:-0.01}" "${ALPHA:-0.95}" "${WARMUP:-50}" > "$configs/logo.toml"
  printf '# TRPO on %s made sparse, without guidance (new_task.sh, step 3).\n%s\n' \
    "$task" "$common" > "$configs/trpo.toml"
  run "$logo" sweep "$configs/logo.toml" "$configs/trpo.toml" --seeds "${SEEDS:-0..3}" \
    --jobs "${JOBS:-1}" --out "$out/runs"
  run "$logo" summary "$out/runs" > "$out/summary.md"
  run "$logo" plot "$out/runs" --out "$out/curves.png"
  cat "$out/summary.md"
  echo "new_task.sh: behaviour $behaviour, demonstrations $demos, runs $out/runs," \
    "summary $out/summary.md, curves $out/curves.png"
}

main "$@"
