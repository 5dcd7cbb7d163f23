#!/usr/bin/env bash
# The (plan, merged-results folder) pairs of the sigma table, in sigma order:
# the three data/plans/sigma/ plans and the 100-member paper-ensemble (sigma
# 1e-3), all read from RESULTS (results/<plan> for each plan when RESULTS is
# "results", else one folder holding every merged file: docs/results).
#   tools/sigma_pairs.sh docs/results | xargs python3 tools/ensemble_summary.py --sigma
set -euo pipefail
dir=$1
for plan in data/plans/sigma/paper-sigma-1e-6.json data/plans/sigma/paper-sigma-1e-4.json \
            data/plans/paper-ensemble.json data/plans/sigma/paper-sigma-1e-2.json; do
  name=$(basename "$plan" .json)
  if [ "$dir" = results ]; then echo "$plan results/$name"; else echo "$plan $dir"; fi
done
