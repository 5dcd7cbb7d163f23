#!/usr/bin/python3
"""Figures of a sweep, from its merged CSV and case files only (docs/sweep.md).

    /usr/bin/python3 tools/plot_sweep.py PLAN.json RESULTS_DIR [--out docs/figures]

Draws what the plan's tables ask for:
  work-precision  work-precision-<scene>.png: CPU time against max pose error,
                  log-log, one line per method x integrator, failed runs as x
  cost-vs-size    cost-vs-size.png: time per right-hand-side evaluation and per
                  simulated second against the number of links
  trajectories    fig3-<scene>.png (one joint angle of every method and the
                  reference, 0.1-rad divergence marked) and fig5-<scene>.png
                  (total energy and its relative error)
and, for a plan with an ensemble:
  <plan>-cdf.png          per scene, the fraction of members whose joint angles
                          have left the reference by 0.1 rad against time, one
                          colour per method, one line style per step
  <plan>-prediction.png   measured against predicted 0.1-rad divergence times
                          (t0 + ln(0.1 / e(t0)) / chi), per scene
Needs Debian's python3-matplotlib (./run figures installs it); never needed
by the build or the tests.
"""
import argparse, csv, json, math, os, sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

MARKERS = {"rk4": "o", "rkf45": "s", "rk8pd": "^", "bsimp": "D", "rkmerson": "v", "rk3": "<", "cpodes": ">",
           "euler": "P", "implicit": "X"}
STYLES = {"rk4": "-", "rkf45": "--", "rk8pd": "-.", "bsimp": ":", "rkmerson": "-", "rk3": "--", "cpodes": "-.",
          "euler": ":", "implicit": "--"}
COLORS = {"classical": "tab:blue", "articulated": "tab:cyan", "eigen": "tab:orange", "eigen-jacobi": "tab:green", "eigen-jacobi-orth": "tab:olive",
          "eigen-block": "tab:purple", "eigen-block-jacobi": "tab:brown", "simbody": "tab:gray", "mujoco": "tab:red"}


def read_merged(results, plan_name):
    path = os.path.join(results, plan_name + ".csv")
    if not os.path.exists(path):
        sys.exit("%s: no merged CSV (run `eigenmass sweep PLAN --merge %s` first)" % (path, results))
    with open(path) as f:
        return list(csv.DictReader(f))


def num(x):
    return float(x) if x not in ("", None) else math.nan


def work_precision(rows, out):
    for scene in dict.fromkeys(r["scene"] for r in rows if r["role"] == "run"):
        fig, ax = plt.subplots(figsize=(9, 6.5))
        lines = {}
        for r in rows:
            if r["scene"] == scene and r["role"] == "run":
                lines.setdefault((r["method"], r["integrator"]), []).append(r)
        for (method, integ), pts in lines.items():
            pts.sort(key=lambda r: -num(r["setting"]))
            ok = [p for p in pts if p["status"] == "ok"]
            bad = [p for p in pts if p["status"] != "ok"]
            line, = ax.loglog([num(p["cpu_median_s"]) for p in ok], [num(p["max_pose_error_rad"]) for p in ok],
                              marker=MARKERS.get(integ, "."), ls=STYLES.get(integ, "-"), color=COLORS.get(method),
                              ms=4, lw=1, label="%s %s" % (method, integ))
            if bad:
                ax.loglog([num(p["cpu_median_s"]) for p in bad], [max(num(p["max_pose_error_rad"]), 1e-16) for p in bad],
                          "x", color=line.get_color(), ms=7)
        check = [r for r in rows if r["scene"] == scene and r["role"] == "check"]
        if check:
            ax.axhline(num(check[0]["max_pose_error_rad"]), color="k", ls=":", lw=0.8)
            ax.annotate("floor: reference vs its check (%s)" % check[0]["method"], (ax.get_xlim()[0], num(check[0]["max_pose_error_rad"])),
                        fontsize=7, va="bottom")
        ax.set_xlabel("CPU time of the integration, s (median of the repeats)")
        ax.set_ylabel("max pose error against the reference, rad")
        ax.set_title("Work-precision: %s (x: run failed; its error up to the failure)" % scene)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=6, ncol=2)
        save(fig, out, "work-precision-%s.png" % scene)


def cost_vs_size(rows, out):
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(12, 5))
    lines = {}
    for r in rows:
        if r["role"] == "run":
            lines.setdefault("%s %s" % (r["method"], r["integrator"]), []).append(r)
    for label, pts in lines.items():
        pts.sort(key=lambda r: int(r["nu"]))
        n = [int(p["nu"]) for p in pts]
        per_s = [num(p["cpu_median_s"]) / (num(p["failure_time_s"]) if p["status"] != "ok" else T_END[0]) for p in pts]
        method = label.split(" ")[0]
        line, = a1.loglog(n, [num(p["cpu_per_rhs_s"]) * 1e6 for p in pts], marker="o", ms=3, label=label,
                          color=COLORS.get(method))
        a2.loglog(n, per_s, marker="o", ms=3, color=line.get_color(), label=label)
        for p, y in zip(pts, per_s):
            if p["status"] != "ok":
                a2.plot(int(p["nu"]), y, "x", color=line.get_color(), ms=8)
    a1.set_xlabel("degrees of freedom n")
    a1.set_ylabel("µs per right-hand-side evaluation")
    a2.set_xlabel("degrees of freedom n")
    a2.set_ylabel("CPU s per simulated second (x: failed, up to the failure)")
    for a in (a1, a2):
        a.grid(True, which="both", alpha=0.3)
    a1.legend(fontsize=7)
    fig.suptitle("Cost against size (chains; the paper's Fig. 4)")
    save(fig, out, "cost-vs-size.png")


def read_traj_csv(path):
    with open(path) as f:
        rd = csv.reader(f)
        head = next(rd)
        cols = {h: [] for h in head}
        for row in rd:
            for h, v in zip(head, row):
                cols[h].append(float(v))
    return cols


def reference_traj(results, scene):
    with open(os.path.join(results, scene + ".reference.json")) as f:
        tr = json.load(f)["trajectory"]
    cols = {"t": tr["t"], "energy": tr["energy"], "kinetic": tr["kinetic"]}
    for i, name in enumerate(tr["q_names"]):
        cols[name] = [q[i] for q in tr["q"]]
    return cols


def trajectories(rows, results, out):
    for scene in dict.fromkeys(r["scene"] for r in rows if r["role"] == "run"):
        ref = reference_traj(results, scene)
        runs = {}
        for r in rows:
            if r["scene"] == scene and r["role"] == "run":
                name = "%s.%s.%s.%s" % (scene, r["method"], r["integrator"], shortest(r["setting"]))
                runs[r["method"]] = (r, read_traj_csv(os.path.join(results, name + ".csv")))
        fig3(scene, ref, runs, out)
        fig5(scene, ref, runs, out)


def shortest(setting):
    return "%g" % float(setting)


def first_joint_to_leave(ref, runs):
    """The coordinate some run leaves the reference by 0.1 rad on first (the figure's angle)."""
    best = (math.inf, None)
    qnames = [k for k in ref if k.endswith((".q0", ".q1", ".q2"))]
    for _, (_, tr) in runs.items():
        for q in qnames:
            for k, (a, b) in enumerate(zip(tr[q], ref[q])):
                if abs(a - b) > 0.1:
                    best = min(best, (tr["t"][k], q))
                    break
    return best[1] or qnames[-1]


def fig3(scene, ref, runs, out):
    q = first_joint_to_leave(ref, runs)
    fig, ax = plt.subplots(figsize=(9, 5))
    ax.plot(ref["t"], ref[q], "k-", lw=2.5, alpha=0.35, label="reference")
    for method, (row, tr) in runs.items():
        line, = ax.plot(tr["t"], tr[q], lw=1, label=method)
        if row["coord_beyond_1e-1_s"]:
            t = float(row["coord_beyond_1e-1_s"])
            ax.axvline(t, color=line.get_color(), ls="--", lw=0.8)
            ax.annotate("%s: 0.1 rad off at %.2f s" % (method, t), (t, ax.get_ylim()[1]), fontsize=7, rotation=90,
                        va="top", ha="right", color=line.get_color())
    ax.set_xlabel("t, s")
    ax.set_ylabel("%s, rad" % q)
    ax.set_title("Fig. 3: %s of %s (dashed: the first joint coordinate 0.1 rad off the reference)" % (q, scene),
                 fontsize=9)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    save(fig, out, "fig3-%s.png" % scene)


def fig5(scene, ref, runs, out):
    scale = max(ref["kinetic"]) or 1.0
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(9, 7), sharex=True)
    for method, (_, tr) in runs.items():
        e0 = tr["energy"][0]
        a1.plot(tr["t"], tr["energy"], lw=1, label=method)
        a2.semilogy(tr["t"], [max(abs(e - e0) / scale, 1e-17) for e in tr["energy"]], lw=1, label=method)
    a1.set_ylabel("total energy E, J")
    a2.set_ylabel("|E(t) - E(0)| / max kinetic energy")
    a2.set_xlabel("t, s")
    a1.set_title("Fig. 5: total energy of %s and its relative error" % scene, fontsize=9)
    for a in (a1, a2):
        a.grid(alpha=0.3, which="both")
        a.legend(fontsize=8)
    save(fig, out, "fig5-%s.png" % scene)


def save(fig, out, name):
    os.makedirs(out, exist_ok=True)
    path = os.path.join(out, name)
    fig.tight_layout()
    fig.savefig(path, dpi=110, metadata={"Software": None})
    plt.close(fig)
    print(path)


T_END = [1.0]
DT_STYLES = ["-", "--", "-.", ":"]


def ensemble_cdf(plan, rows, out):
    # Small multiples: a row per method (its colour), a column per scene, a line style per step.
    runs = [r for r in rows if r["role"] == "run"]
    scenes = sorted({r["scene"] for r in runs})
    methods = list(dict.fromkeys(r["method"] for r in runs))
    fig, axes = plt.subplots(len(methods), len(scenes), figsize=(4.6 * len(scenes), 2.6 * len(methods)),
                             sharex=True, sharey=True, squeeze=False)
    for i, method in enumerate(methods):
        for j, scene in enumerate(scenes):
            ax = axes[i][j]
            mine = [r for r in runs if r["scene"] == scene and r["method"] == method]
            settings = sorted({float(r["setting"]) for r in mine}, reverse=True)
            for k, dt in enumerate(settings):
                t = [num(r["coord_beyond_1e-1_s"]) for r in mine if float(r["setting"]) == dt]
                crossed = sorted(x for x in t if not math.isnan(x))
                xs = [0.0] + [x for x in crossed for _ in (0, 1)] + [T_END[0]]
                ys = [0.0] + [y for n in range(len(crossed)) for y in (n / len(t), (n + 1) / len(t))] + [len(crossed) / len(t)]
                ax.plot(xs, ys, DT_STYLES[k % len(DT_STYLES)], color=COLORS.get(method, "k"), lw=1.4, label="dt %g" % dt)
            ax.axvline(7.2, color="k", lw=0.8, ls=":")
            ax.set_title("%s, %s (%d members)" % (method, scene, len(t)), fontsize=9)
            ax.set_xlim(0, T_END[0])
            ax.set_ylim(0, 1.02)
            ax.grid(alpha=0.3)
            if i == len(methods) - 1:
                ax.set_xlabel("time (s); dotted: the paper's 7.2 s")
            if j == 0:
                ax.set_ylabel("fraction beyond 0.1 rad")
            if i == 0 and j == 0:
                ax.legend(fontsize=7, loc="upper left")
    save(fig, out, plan["name"] + "-cdf.png")


def ensemble_prediction(plan, results, out):
    path = os.path.join(results, plan["name"] + "-prediction.csv")
    if not os.path.exists(path):
        return
    with open(path) as f:
        pred = [p for p in csv.DictReader(f) if float(p["threshold"]) == 0.1 and p["predicted_s"] and p["measured_s"]]
    scenes = sorted({p["scene"] for p in pred})
    fig, axes = plt.subplots(1, len(scenes), figsize=(4.8 * len(scenes), 4.4), sharey=True, squeeze=False)
    for ax, scene in zip(axes[0], scenes):
        for method in dict.fromkeys(p["method"] for p in pred):
            mine = [p for p in pred if p["scene"] == scene and p["method"] == method]
            ax.scatter([float(p["predicted_s"]) for p in mine], [float(p["measured_s"]) for p in mine], s=6,
                       color=COLORS.get(method, "k"), alpha=0.5, label=method)
        ax.plot([0, T_END[0] * 1.5], [0, T_END[0] * 1.5], "k:", lw=0.8)
        ax.set_xlim(0, T_END[0] * 1.5)
        ax.set_ylim(0, T_END[0])
        ax.set_title(scene + ": every member and step")
        ax.set_xlabel("predicted from e(t0) and chi (s)")
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel("measured: pose beyond 0.1 rad (s)")
    axes[0][0].legend(fontsize=8)
    save(fig, out, plan["name"] + "-prediction.png")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("plan")
    ap.add_argument("results")
    ap.add_argument("--out", default="docs/figures")
    a = ap.parse_args()
    with open(a.plan) as f:
        plan = json.load(f)
    T_END[0] = plan["t_end"]
    rows = read_merged(a.results, plan["name"])
    tables = plan.get("tables", [])
    if "work-precision" in tables:
        work_precision(rows, a.out)
    if "cost-vs-size" in tables:
        cost_vs_size(rows, a.out)
    if "trajectories" in tables:
        trajectories(rows, a.results, a.out)
    if "ensemble" in plan:
        ensemble_cdf(plan, rows, a.out)
        ensemble_prediction(plan, a.results, a.out)


if __name__ == "__main__":
    main()
