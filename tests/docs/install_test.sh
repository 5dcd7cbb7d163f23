#!/usr/bin/env bash
# An installed tree works without the source tree (ctest -L install):
# cmake --install into a fresh prefix, then, from a folder outside both, the
# README's first task with the installed binary and data, its figures with the
# installed plotter, and the module imported from the prefix.
#   tests/docs/install_test.sh BUILD_DIR WORK_DIR
set -euo pipefail
build=$(cd "$1" && pwd) work=$2
rm -rf "$work" && mkdir -p "$work/run"
cmake --install "$build" --prefix "$work/prefix" >/dev/null
P=$work/prefix
cd "$work/run"
"$P/bin/eigenmass" --version | grep -q "shipped files: $P/share/eigenmass" ||
  { echo "FAILED: the installed eigenmass does not read its own share/eigenmass"; "$P/bin/eigenmass" --version; exit 1; }
"$P/bin/eigenmass" crosscheck "$P/share/eigenmass/data/robots/ur5.urdf" --states 2 >/dev/null
"$P/bin/eigenmass" compare "$P/share/eigenmass/data/robots/ur5.urdf" --t-end 1 --methods classical --out ur5.report.json --no-progress >/dev/null
"$P/bin/eigenmass" plot ur5.report.json --out figures >/dev/null
ls figures/*.png >/dev/null
"$P/bin/eigenmass_bench" 5 >/dev/null
PYTHONPATH="$P/lib/python3/dist-packages" /usr/bin/python3 -c "
import eigenmass as em
s = em.load('$P/share/eigenmass/data/scenes/pendulum5.json')
assert em.equations(s)['A'].shape == (7, 7)
print('module ok', s)"
test -f "$P/include/eigenmass/eigenmass_plugin.h"
echo "PASSED: the installed tree ran compare, plot, crosscheck, the bench and the module from $work/run"
