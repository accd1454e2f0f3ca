#!/usr/bin/env bash
# When each run first met the sparse reward, read from its metrics.csv: the samples at
# the first iteration whose training sparse return is above 0 ("first"), and at the
# first of 5 such iterations in a row ("sustained"). Usage: sparse_discovery.sh DIR...
# (every metrics.csv under each DIR).
set -euo pipefail
find "$@" -name metrics.csv | sort | while read -r csv; do
  awk -F, -v run="$(dirname "$csv")" '
    NR == 1 { for (i = 1; i <= NF; i++) column[$i] = i
              if (!("train_sparse_return" in column)) { print run ": no train_sparse_return column" > "/dev/stderr"; exit 1 }
              next }
    { n++; samples[n] = $2; found[n] = ($column["train_sparse_return"] > 0)
      if (!first && found[n]) first = $2 }
    END { for (i = 1; i + 4 <= n && !sustained; i++)
            if (found[i] && found[i+1] && found[i+2] && found[i+3] && found[i+4]) sustained = samples[i]
          printf "%s\tfirst %s\tsustained %s\n", run, first ? first : "never", sustained ? sustained : "never" }' "$csv"
done
