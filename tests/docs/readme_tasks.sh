#!/usr/bin/env bash
# The README's tasks run as written (ctest -L readme): in a fresh folder that
# sees the source's data/, docs/ and tools/ and the build's bin/ as the README
# does (build/bin/eigenmass), the main job's commands from ./run, then every
# ```sh block of "## Tasks" in order, each under bash -e. The Slurm block runs
# in the slurm test, which starts a cluster for it.
#   tests/docs/readme_tasks.sh SOURCE_DIR BINARY_DIR WORK_DIR
set -euo pipefail
src=$(cd "$1" && pwd) bin=$(cd "$2" && pwd) work=$3
rm -rf "$work"
"$src/tests/docs/readme_folder.sh" "$src" "$bin/bin" "$work"
cd "$work"
run_block() {  # HEADING, COMMANDS
  local start=$SECONDS
  if ! bash -euo pipefail -c "$2" >"$work/block.log" 2>&1; then
    echo "FAILED: README task '$1':"
    tail -20 "$work/block.log"
    exit 1
  fi
  echo "ok ($((SECONDS - start)) s): $1"
}
# ./run main's commands (its build aside): the main job's report is what the pandas task reads.
run_block "./run main" "$(sed -n '/^  main)/,/;;/p' "$src/run" | grep '^ *build/bin/eigenmass')"
n=0
while IFS= read -r heading; do
  case "$heading" in *Slurm*) echo "in ctest -L slurm: $heading"; continue ;; esac
  run_block "$heading" "$("$src/tests/docs/readme_block.sh" "$src/README.md" "$heading")"
  n=$((n + 1))
done < <("$src/tests/docs/readme_block.sh" "$src/README.md" --headings)
[ "$n" -ge 6 ] || { echo "FAILED: only $n task blocks found in README.md"; exit 1; }
echo "PASSED: the main job and $n README task blocks ran as written"
