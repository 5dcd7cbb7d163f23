#!/usr/bin/python3
"""docs/reference-engines.md's joint-limit tables, measured: every engine's
own scheme and its own stops on the shipped stop scenes at dt 1e-3 and 1e-4,
judged by `eigenmass compare` against the in-house exact events (classical,
rk8pd 1e-10: each impact located to 1e-12 s, Newton's law through A). Per
route: the first impact's time error and rebound speed error, the largest
overshoot beyond a stop and the longest time beyond it, and impacts counted
against the reference's over the run. Usage:
  tools/limit_engines.py EIGENMASS OUT_DIR > tables.md  (a table per route)
Each row names the compare report it comes from (OUT_DIR/<scene>-<route>-<dt>.json)."""
import json, os, subprocess, sys

eigenmass, out = sys.argv[1], sys.argv[2]
os.makedirs(out, exist_ok=True)
# (scene file, horizon s, what it asks)
scenes = [("tests/scenes/limits/pendulum_stop.json", 2.0, "a rod released onto a stop, e = 1 (world hinge)"),
          ("tests/scenes/limits/slide_floor.json", 2.0, "a block dropped on a floor, e = 0.5 (world slider)"),
          ("tests/scenes/limits/double_hinge_stop.json", 2.0, "an elbow between two bodies with two stops, e = 1"),
          ("tests/scenes/limits/cart_slide_stop.json", 2.0, "a block on a slider carried by a cart, e = 1")]
routes = [("rk4 (in-house)", "classical", ["--integrator", "rk4"]), ("mujoco rk4", "mujoco", []), ("dart-euler", "dart", []),
          ("bullet-euler", "bullet", []), ("ode-step", "ode", []), ("ode-quickstep", "ode", ["--ode-integrator", "ode-quickstep"])]


def g(x, d=2):
    return "—" if x is None else "%.*g" % (d, x)


def compare(scene, t_end, methods, dt, extra, tag):
    path = os.path.join(out, "%s-%s.json" % (os.path.basename(scene)[:-5], tag))
    cmd = [eigenmass, "compare", scene, "--methods", methods, "--dt", repr(dt), "--t-end", repr(t_end), "--output-dt", "0.001",
           "--no-progress", "--out", path] + extra
    run = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if run.returncode == 2:  # refused before any run: the engine's one line
        return None, run.stderr.strip().splitlines()[-1]
    run.check_returncode()
    return json.load(open(path)), path


for label, methods, extra in routes:
    print("\n#### %s\n" % label)
    print("| scene | dt (s) | first impact: time error (s) | first rebound: speed error | overshoot max | beyond a stop max (s) | impacts (reference's) | report |")
    print("|---|---|---|---|---|---|---|---|")
    for scene, t_end, what in scenes:
        for dt in (1e-3, 1e-4):
            tag = "%s-%g" % (label.split()[0], dt)
            report, where = compare(scene, t_end, methods, dt, extra, tag)
            name = os.path.basename(scene)[:-5]
            if report is None:
                print("| %s | %g | refused: %s | | | | | |" % (name, dt, where))
                continue
            i = report["methods"][0].get("impacts") or {}
            print("| %s | %g | %s | %s | %s | %s | %s (%s) | %s |" % (
                name, dt, g(i.get("first_time_error_s")), g(i.get("first_rebound_error")), g(i.get("overshoot_max")),
                g(i.get("beyond_stop_max_s")), i.get("count", "—"), i.get("reference_count", "—"), os.path.basename(where)))
print("\nScenes: " + "; ".join("%s, %s" % (os.path.basename(s)[:-5], w) for s, _, w in scenes) + ".")
