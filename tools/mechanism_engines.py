#!/usr/bin/python3
"""docs/reference-engines.md's mechanism tables, measured: every engine's own
scheme on the shipped mechanisms at dt 1e-3 and 1e-4, judged by `eigenmass
compare` against its IDA reference (largest loop violation by eigenmass's g(q),
energy balance, pose error, CPU); and MuJoCo's soft closures against solref's
time constant and dt. Usage:
  tools/mechanism_engines.py EIGENMASS OUT_DIR > table.md
Each row names the compare report it comes from (OUT_DIR/<scene>-<route>-<dt>.json)."""
import json, os, subprocess, sys

eigenmass, out = sys.argv[1], sys.argv[2]
os.makedirs(out, exist_ok=True)
# (scene file, horizon s): Andrews over the IVP test set's 0.03 s, the others over 1 s of their specification's
scenes = [("data/scenes/mechanisms/andrews.json", 0.03), ("data/scenes/mechanisms/iftomm_a01.json", 1.0),
          ("data/scenes/mechanisms/iftomm_a02_n2.json", 1.0), ("data/scenes/mechanisms/iftomm_a04.json", 1.0),
          ("data/scenes/mechanisms/iftomm_a05.json", 1.0), ("tests/scenes/mechanisms/door_and_plate.json", 1.0)]
# A route: (label, --methods, extra options); every engine's own fixed-step scheme.
routes = [("mujoco rk4", "mujoco", []), ("dart-euler", "dart", []), ("bullet-euler", "bullet", []),
          ("bullet-rk4", "bullet", ["--bullet-integrator", "bullet-rk4"]), ("ode-step", "ode", []),
          ("ode-quickstep", "ode", ["--ode-integrator", "ode-quickstep"])]


def compare(scene, t_end, methods, dt, extra, tag):
    path = os.path.join(out, "%s-%s.json" % (os.path.basename(scene)[:-5], tag))
    cmd = [eigenmass, "compare", scene, "--methods", methods, "--dt", repr(dt), "--t-end", repr(t_end), "--no-progress",
           "--out", path] + extra
    run = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if run.returncode == 2:  # refused before any run: the engine's one line
        return None, run.stderr.strip().splitlines()[-1]
    run.check_returncode()
    report = json.load(open(path))
    return report, [m for m in report["methods"] if m["name"] == methods][0]


def g(x):
    return "–" if x is None else "%.2g" % x


print("| scene | route | dt (s) | outcome | loops open (m, rad) | dE / E_scale | max pose error (rad) | CPU (s) |")
print("|---|---|---|---|---|---|---|---|")
for scene, t_end in scenes:
    for label, methods, extra in routes:
        for dt in (1e-3, 1e-4):
            report, m = compare(scene, t_end, methods, dt, extra, "%s-%g" % (label.replace(" ", "-"), dt))
            if report is None:
                print("| %s | %s | %g | refused: %s | | | | |" % (os.path.basename(scene)[:-5], label, dt, m.replace("|", "/")))
                continue
            loops = m.get("loops") or {}
            outcome = m["outcome"]
            if m["failure"]:
                outcome += " (%s at %.3g s)" % (m["failure"]["kind"], m["failure"]["t"])
            opened = "–" if not loops else "%s, %s" % (g(loops["max_position_violation_m"]), g(loops["max_position_violation_rad"]))
            print("| %s | %s | %g | %s | %s | %s | %s | %.3g |" % (
                report["scene"]["name"], label, dt, outcome, opened, g(m["energy_error_max"]), g(m["max_pose_error_rad"]),
                m["run_time_s"]))

print()
print("MuJoCo's soft closures on A04 (Bricard) over 1 s, rk4: the largest violation (m) against solref's time constant and dt")
print()
taus = [0.02, 0.005, 0.002]
print("| dt (s) | " + " | ".join("τ = %g s" % t for t in taus) + " |")
print("|---|" + "---|" * len(taus))
for dt in (1e-3, 1e-4):
    cells = []
    for tau in taus:
        _, m = compare("data/scenes/mechanisms/iftomm_a04.json", 1.0, "mujoco", dt, ["--mujoco-solref-time", repr(tau)],
                       "solref-%g-%g" % (tau, dt))
        cells.append("%s (%s)" % (g(m["loops"]["max_position_violation_m"]), m["outcome"]))
    print("| %g | %s |" % (dt, " | ".join(cells)))
