#!/usr/bin/python3
"""CPU time to Andrews' published solution (the IVP test set's angles at t = 0.03 s)
within 1e-9 relative, by IDA and by the in-house formulations under rk8pd, each
tolerance run five times (`eigenmass simulate`; its sidecar's run_time_s, the
integration alone). Usage: tools/andrews_published.py [EIGENMASS]  (docs/results.md)."""
import csv
import json
import os
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
E = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build", "bin", "eigenmass")
SCENE = os.path.join(ROOT, "data", "scenes", "mechanisms", "andrews.json")
# beta, Theta, gamma, Phi, delta, Omega, epsilon (the scene's body order): PSIDE at 1e-14 (the scene's x-reference).
PUBLISHED = [15.81077119629904, -15.75637105984298, 0.04082224013073101, -0.5347301163226948,
             0.5244099658805304, 0.5347301163226948, 1.048080741042263]
ROUTES = [("ida", None), ("rk8pd", "projection"), ("rk8pd", "udwadia-kalaba"), ("rk8pd", "coordinate-partitioning")]

print("| route | tolerance | largest relative error | CPU s (median of 5) |\n|---|---|---|---|")
with tempfile.TemporaryDirectory() as tmp:
    out = os.path.join(tmp, "andrews.csv")
    for integrator, formulation in ROUTES:
        for tol in (1e-8, 1e-9, 1e-10, 1e-11, 1e-12):
            args = [E, "simulate", SCENE, "--method", "classical", "--integrator", integrator, "--tol", str(tol),
                    "--t-end", "0.03", "--output-dt", "0.03", "--out", out]
            if formulation:
                args += ["--formulation", formulation]
            cpu = []
            for _ in range(5):
                subprocess.run(args, capture_output=True, check=True)
                cpu.append(json.load(open(out + ".json"))["run_time_s"])
                last = list(csv.reader(open(out)))[-1]
                os.remove(out)
                os.remove(out + ".json")
            rel = max(abs(float(last[1 + k]) - p) / abs(p) for k, p in enumerate(PUBLISHED))
            print("| classical %s%s | %g | %.2e | %.2e |" % ((formulation + " ") if formulation else "", integrator, tol, rel, statistics.median(cpu)))
