#!/usr/bin/env bash
# The README quotes the benchmark page's summary (label `docs`): the table under
# README.md's "### Which engine for my mechanism" must hold exactly the rows of
# docs/benchmark.md's "## Summary" table, header included, in the page's order
# (a regenerated page that the README does not follow, or a README row edited
# by hand, fails here).
#   tests/docs/summary_quote_test.sh SOURCE_DIR
set -euo pipefail
cd "$1"
table() {  # FILE START_REGEX: the first markdown table after the line matching START_REGEX
  awk -v start="$2" '
    $0 ~ start { on = 1; next }
    on && /^\|/ { print; seen = 1; next }
    on && seen { exit }
    on && /^#/ { exit }
  ' "$1"
}
readme=$(table README.md '^### Which engine for my mechanism$')
page=$(table docs/benchmark.md '^## Summary$')
[ -n "$page" ] || { echo "docs/benchmark.md: no table under '## Summary'" >&2; exit 1; }
[ -n "$readme" ] || { echo "README.md: no table under '### Which engine for my mechanism'" >&2; exit 1; }
if [ "$readme" != "$page" ]; then
  echo "README.md's mechanism table is not docs/benchmark.md's summary (README <, page >):" >&2
  diff <(echo "$readme") <(echo "$page") >&2 || true
  exit 1
fi
echo "README.md quotes docs/benchmark.md's summary: $(($(grep -c . <<<"$page") - 2)) rows"
