#!/usr/bin/python3
"""Rows of N four-bars for docs/performance.md's cost against size: A02's
topology (tools/make_mechanisms.py's a02(n)) over 1 s, sampled every 0.01 s,
without A02's benchmark block. Usage: tools/fourbar_rows.py OUT_DIR [N ...]
(default N = 10 20 40 80 160); writes OUT_DIR/fbN.json, never over a file."""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import make_mechanisms  # noqa: E402


def main():
    if len(sys.argv) < 2:
        sys.exit("usage: fourbar_rows.py OUT_DIR [N ...]")
    out = sys.argv[1]
    sizes = [int(a) for a in sys.argv[2:]] or [10, 20, 40, 80, 160]
    make_mechanisms.a02_solution = lambda n, **kw: []  # the rows are judged against the closed form, not A02's file
    for n in sizes:
        if not 1 <= n <= 1000:
            sys.exit("fourbar_rows.py: N must be in [1, 1000], got %d" % n)
        doc = make_mechanisms.a02(n, t_end=1.0, output_dt=0.01)
        doc.pop("benchmark")
        doc["name"] = "fourbar_row_%d" % n
        path = os.path.join(out, "fb%d.json" % n)
        with open(path, "x") as f:  # "x": never over an existing file
            json.dump(doc, f, indent=1)
        print(path)


if __name__ == "__main__":
    main()
