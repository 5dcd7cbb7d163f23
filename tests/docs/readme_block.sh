#!/usr/bin/env bash
# Print the ```sh block under "### HEADING" of README.md's "## Tasks" section,
# as written (the tests run the README's task commands verbatim).
#   tests/docs/readme_block.sh README.md "Run a sweep on a Slurm cluster"
#   tests/docs/readme_block.sh README.md --headings     # every task heading with a block
set -euo pipefail
awk -v want="${2}" '
  /^## / { tasks = ($0 == "## Tasks") }
  tasks && /^### / { heading = substr($0, 5); inblock = 0; next }
  tasks && /^```sh$/ { inblock = 1; if (want == "--headings") print heading; next }
  tasks && /^```$/ { inblock = 0; next }
  tasks && inblock && heading == want { print }
' "$1"
