#!/usr/bin/python3
"""One line saying what ran a sweep's cases, from their own provenance: commits,
libraries, compiler, machine, dates. Usage: tools/provenance.py RESULTS_DIR..."""
import glob
import json
import sys

p = []
for d in sys.argv[1:]:
    for f in glob.glob(d + "/*.json"):
        with open(f) as fh:
            x = json.load(fh).get("provenance", {})
        if x:
            p.append(x)
if not p:
    sys.exit("provenance: no case file with provenance in " + " ".join(sys.argv[1:]))
commits = sorted({x["git_commit"] for x in p})
libs = ", ".join("%s %s" % kv for kv in sorted(p[0]["libraries"].items()))
dates = sorted(x["date_utc"] for x in p)
print("eigenmass %s (commit %s; %s; g++ %s,%s) on %d cores of %s, %s to %s" % (
    p[0]["eigenmass_version"], " and ".join(commits), libs, p[0]["compiler"], p[0]["flags"], p[0]["cores"], p[0]["cpu"],
    dates[0], dates[-1]))
