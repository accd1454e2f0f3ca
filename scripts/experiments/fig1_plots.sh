#!/usr/bin/env bash
# Figure 1 on sparse Hopper, Walker2d and HalfCheetah: one figure per task from the kept
# runs (docs/results/fig1/<task>/<method>/ and the five-seed LOGO arm), read up to 2M: the
# IQM over seeds with its 95% band, the LOGO paper's behaviour and expert lines, and the
# expert measured here where its run is kept (dense-reward TRPO, configs/expert/: the mean
# of its last 10% of evaluations, as `logo summary`'s "mean of last 10%").
# Usage: scripts/experiments/fig1_plots.sh   (LOGO=path/to/logo to use another binary)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
logo="${LOGO:-./target/release/logo}"
for t in hopper:Hopper walker2d:Walker2d halfcheetah:HalfCheetah; do
  n=${t%%:*}; N=${t##*:}
  args=(docs/results/five-seeds-view/$n/LOGO)
  for m in trpo:TRPO bc-trpo:BC-TRPO dapg:DAPG gail:GAIL pofd:POfD; do
    if [ -d docs/results/fig1/$n/${m%%:*} ]; then
      args+=(docs/results/fig1/$n/${m%%:*} --label "${m%%:*}=${m##*:}")
    fi
  done
  expert=docs/results/fig1/$n/expert/seed0/metrics.csv
  if [ -f "$expert" ]; then
    level=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "eval_dense_return") c = i; next }
                     $c != "NaN" { v[++n] = $c }
                     END { k = int((n + 9) / 10); for (i = n - k + 1; i <= n; i++) s += v[i]; printf "%.0f", s / k }' "$expert")
    args+=(--hline "expert here (dense TRPO, 5M)=$level")
  fi
  "$logo" plot "${args[@]}" --max-samples 2M --stat iqm --band ci --smooth 5 \
    --paper-lines --title "Sparse $N, 5 seeds each: IQM with 95% bands" \
    --out docs/results/fig1/$n.png
done
