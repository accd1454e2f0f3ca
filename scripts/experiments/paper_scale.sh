#!/usr/bin/env bash
# Issue 24, items 2-5: LOGO and LOGO+PPO+CDQ (the seed paper's Algorithm 2) on sparse
# Hopper, Walker2d and HalfCheetah, 3 seeds each, to ITERATIONS x 20,000 samples (500:
# 10M; 1500: 30M), beside the reference code's own learning curve of each env. Resumable:
# run it again (with a larger ITERATIONS to extend) and every run continues from its
# checkpoint. ENGINE_ARGS (e.g. "--dtype f32") go to every `logo train`.
# Item 4, LOGO alone toward 30M in a folder of its own, so that the 10M runs, their
# checkpoints and evaluations stay as the 10M tables cite them: CONFIGS=logo runs LOGO
# only, and FROM=DIR first copies into OUT the LOGO runs of DIR that OUT lacks, e.g.
#   FROM=docs/results/paper-scale CONFIGS=logo paper_scale.sh runs/paper-scale-30m 2 1500
# docs/results keeps policies alone now: DIR is a folder of learner checkpoints, e.g. the
# one restore_run.sh makes (restore_run.sh runs/kept docs/results/paper-scale/<env>/...,
# then FROM=runs/kept/docs/results/paper-scale).
# Usage: [CONFIGS=logo] [FROM=DIR] paper_scale.sh [OUT] [JOBS] [ITERATIONS] [ENGINE_ARGS...]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."

main() {
  local out="${1:-runs/paper-scale}" jobs="${2:-2}" iterations="${3:-500}"
  shift $(( $# < 3 ? $# : 3 ))
  local logo="${LOGO:-./target/release/logo}" curves=docs/results/reference-curves
  local configs="${CONFIGS:-logo logo-ppo-cdq}" from="${FROM:-}"
  case "$configs" in
    logo | "logo logo-ppo-cdq") ;;
    *) echo "paper_scale.sh: CONFIGS must be \"logo\" or \"logo logo-ppo-cdq\"" >&2; return 2 ;;
  esac
  # The copies are named as a LOGO-only sweep names its runs (below); beside
  # LOGO+PPO+CDQ the sweep would not find them and would start LOGO over.
  if [ -n "$from" ] && [ "$configs" != logo ]; then
    echo "paper_scale.sh: FROM=$from needs CONFIGS=logo" >&2; return 2
  fi
  mkdir -p "$out"
  local env variant curve reference run failed=0
  for env in hopper walker2d halfcheetah; do
    # A sweep names a run folder after its config's stem, `<parent>-<stem>` where two
    # stems collide: the LOGO runs are `logo-<env>` beside LOGO+PPO+CDQ, `<env>` alone.
    if [ -n "$from" ] && [ ! -d "$out/$env/$env" ]; then
      run="$from/$env/logo-$env"
      [ -d "$run" ] || run="$from/$env/$env"
      [ -d "$run" ] || { echo "paper_scale.sh: $from/$env has no LOGO runs" >&2; return 2; }
      mkdir -p "$out/$env"
      cp -r "$run" "$out/$env/$env"
      rm -f "$out/$env/$env"/seed*/eval-*.txt # evaluations of the old checkpoints
    fi
    # Twin-min critics need the rewardless improvement step skipped on Hopper (issue 13).
    variant="configs/logo-ppo-cdq/$env.toml"
    [ "$env" = hopper ] && variant=configs/experiments/hopper_ppo_cdq_skip_rewardless.toml
    [ "$configs" = logo ] && variant=
    "$logo" sweep "configs/logo/$env.toml" ${variant:+"$variant"} --seeds 0..3 --jobs "$jobs" \
      --threads "$(nproc)" --iterations "$iterations" --out "$out/$env" "$@" || failed=1
    if [ "$env" = halfcheetah ] && [ -n "$variant" ]; then
      # The fall study's like-for-like arm (the reference code's F·v), extended from its
      # committed 2M checkpoints in float64, as it trained: does it fall after its peak
      # as the reference rerun did, or rise as the reference's own curve does?
      local arm="$out/halfcheetah/halfcheetah_reference_fisher"
      if [ ! -d "$arm" ]; then
        local kept=docs/results/halfcheetah-fall/halfcheetah_reference_fisher
        scripts/experiments/restore_run.sh runs/kept "$kept"/seed{0,1,2}
        cp -r "runs/kept/$kept" "$arm"
      fi
      "$logo" sweep configs/experiments/halfcheetah_reference_fisher.toml --seeds 0..3 \
        --jobs "$jobs" --threads "$(nproc)" --iterations "$iterations" --out "$out/$env" \
        --dtype f64 || failed=1
    fi
    case "$env" in
      hopper) curve=Hopper ;;
      walker2d) curve=Walker2d ;;
      halfcheetah) curve=HalfCheetah ;;
    esac
    # Each final policy over 20 episodes of the dense env, mean action, on the engine
    # it trained on (the per-iteration evaluation has 3).
    # A failed run (the sweep named its log) is left out here and retried by the next
    # call; the other envs go on.
    for run in "$out/$env"/*/seed*; do
      [ -f "$run/checkpoint.safetensors" ] || continue
      "$logo" eval --checkpoint "$run/checkpoint.safetensors" --episodes 20 \
        --env "${curve}-v4" > "$run/eval-20.txt"
      # The same episodes with each action clipped to the actuator range: the motion is
      # the same (MuJoCo clamps), the control cost is that of the actions MuJoCo applies.
      "$logo" eval --checkpoint "$run/checkpoint.safetensors" --episodes 20 \
        --env "${curve}-v4" --clip-actions > "$run/eval-20-clipped.txt"
    done
    reference="$curves/${curve}_LOGO_ref.csv,samples,rewards/eval_R_avg,reference code"
    # The reference curve runs to 30-50M: draw it to the runs' budget (an iteration is a
    # little over 20,000 samples: episodes end whole).
    "$logo" plot "$out/$env" --out "$out/$env.png" --paper-lines --smooth 5 --external "$reference" \
      --max-samples "$(( iterations * 20600 ))"
    # At equal samples, every run read as the reference curve is quoted: the mean of the
    # 10 evaluations nearest each budget.
    "$logo" summary "$out/$env" --external "$reference" --window 10 \
      --at 1M --at 2M --at 5M --at 10M --at 20M --at 30M > "$out/$env.md"
  done
  return "$failed"
}

# Read whole before it runs: editing this file while a sweep runs cannot change it.
main "$@"
exit
