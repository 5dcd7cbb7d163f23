#!/usr/bin/env bash
# Make DIR a folder that sees what the README's reader sees from the top of the
# project: the source's data/, docs/, tools/ and examples/, and the build's
# binaries as build/bin/, plugins as build/lib/ and the Python module as
# build/python/ (the README's commands run
# there as written).
#   tests/docs/readme_folder.sh SOURCE_DIR BIN_DIR DIR
set -euo pipefail
src=$(cd "$1" && pwd) bin=$(cd "$2" && pwd) dir=$3
mkdir -p "$dir/build" "$dir/out"
for d in data docs tools examples; do ln -s "$src/$d" "$dir/$d"; done
ln -s "$bin" "$dir/build/bin"
ln -s "$bin/../lib" "$dir/build/lib"
ln -s "$bin/../python" "$dir/build/python"
