#!/usr/bin/env bash
# Issue 40, item 4: the headline comparison at five seeds and equal settings.
#   - LOGO and LOGO+PPO+CDQ, seeds 3 and 4, on sparse Hopper, Walker2d and HalfCheetah to
#     ITERATIONS x 20,000 samples (500: 10M), the configs of paper_scale.sh, whose seeds
#     0-2 are in docs/results/paper-scale (same configs, same training code);
#   - on Hopper, LOGO with `skip_improvement_without_reward = true`
#     (configs/experiments/hopper_skip_rewardless.toml), seeds 0-4: the setting the
#     Hopper LOGO+PPO+CDQ arm runs with, so that both arms can be compared at it.
# Each final policy is then evaluated over 20 episodes of the dense env, as paper_scale.sh
# does (eval-20.txt, eval-20-clipped.txt). Resumable: run it again and every run goes on
# from its checkpoint; finished runs are skipped. ENGINE_ARGS (e.g. "--dtype f32") go to
# every `logo train`. LOGO names the binary (a pinned copy, so that builds during the
# study do not change it).
# Usage: [LOGO=runs/bin/logo-<commit>] five_seeds.sh [OUT] [JOBS] [ITERATIONS] [ENGINE_ARGS...]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."

# Each final policy over 20 episodes of the dense env, mean action, as sent and clipped.
evaluate() {
  local logo="$1" dir="$2" dense="$3" run
  for run in "$dir"/*/seed*; do
    [ -f "$run/checkpoint.safetensors" ] || continue
    [ "$run/eval-20-clipped.txt" -nt "$run/checkpoint.safetensors" ] && continue
    "$logo" eval --checkpoint "$run/checkpoint.safetensors" --episodes 20 \
      --env "$dense" > "$run/eval-20.txt"
    "$logo" eval --checkpoint "$run/checkpoint.safetensors" --episodes 20 \
      --env "$dense" --clip-actions > "$run/eval-20-clipped.txt"
  done
}

main() {
  # Beside builds and tests: under the kernel's autogroups `nice` alone does not yield
  # the CPU to another session's processes; the group's own nice value does.
  { echo 19 > /proc/self/autogroup; } 2>/dev/null || true
  local out="${1:-runs/five-seeds}" jobs="${2:-2}" iterations="${3:-500}"
  shift $(( $# < 3 ? $# : 3 ))
  local logo="${LOGO:-./target/release/logo}" failed=0 env variant dense
  local sweep=("$logo" sweep --jobs "$jobs" --threads "$(nproc)" --iterations "$iterations")
  mkdir -p "$out"
  for env in hopper hopper-skip walker2d halfcheetah; do
    local ok=1
    case "$env" in
      hopper)
        "${sweep[@]}" configs/logo/hopper.toml \
          configs/experiments/hopper_ppo_cdq_skip_rewardless.toml --seeds 3..5 \
          --out "$out/hopper" "$@" || ok=0
        dense=Hopper-v4 ;;
      hopper-skip)
        "${sweep[@]}" configs/experiments/hopper_skip_rewardless.toml --seeds 0..5 \
          --out "$out/hopper-skip" "$@" || ok=0
        dense=Hopper-v4 ;;
      walker2d | halfcheetah)
        variant="configs/logo-ppo-cdq/$env.toml"
        "${sweep[@]}" "configs/logo/$env.toml" "$variant" --seeds 3..5 \
          --out "$out/$env" "$@" || ok=0
        [ "$env" = walker2d ] && dense=Walker2d-v4 || dense=HalfCheetah-v4 ;;
    esac
    # Only whole sweeps are evaluated: a failed run (the sweep named its log) is retried
    # by the next call, and the evaluations with it.
    if [ "$ok" = 1 ]; then evaluate "$logo" "$out/$env" "$dense"; else failed=1; fi
  done
  return "$failed"
}

# Read whole before it runs: editing this file while a sweep runs cannot change it.
main "$@"
exit
