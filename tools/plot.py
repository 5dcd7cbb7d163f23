#!/usr/bin/python3
"""The figures of any report or results folder eigenmass writes; run by
`eigenmass plot` (docs/figures.md), which checks the input and the output
folder first and moves the figures written into OUT to their place.

    /usr/bin/python3 tools/plot.py report|sweep|extreme|precision|trajectory INPUT OUT png|svg|pdf [--csv-dir DIR]

report   a compare report (eigenmass-report/1):
         <scene>-divergence   each method's pose error against time, log scale,
                              thresholds and the reference horizon marked,
                              failures as x, the reference check as the floor
         <scene>-energy       the energy balance error against time
         <scene>-coordinate   the first angle against time (the paper's Fig. 3)
sweep    a results folder (its merged <plan>.csv and case files):
         work-precision-<scene>  small multiples, a panel per method
         cost-vs-size            time per evaluation and per simulated second
         fig3-<scene>, fig5-<scene>  trajectories, when the plan kept them
         <plan>-cdf, <plan>-prediction  an ensemble's distributions
extreme  an extreme summary (eigenmass-extreme/1):
         extreme-outcomes     cases x methods coloured by outcome, a panel per setting
precision  a precision file (eigenmass-precision/1):
         <scene>-work-precision  error against CPU time and against the step or tolerance
trajectory  a trajectory CSV (simulate --out) with its sidecar <csv>.json:
         <stem>-state, <stem>-energy  coordinates and speeds, the energy balance error
         <stem>-loops         a mechanism's constraint violation against time

One colour per method and one marker per integrator in every figure. Prints
each file written, one per line. An input of the right format but not of its
shape exits 2 with its one-line reason in OUT/error.txt. Needs Debian's
python3-matplotlib.
"""
import argparse, csv, glob, json, math, os, re, shutil, signal, sys

import warnings

import matplotlib
matplotlib.use("Agg")
# plot prints the figures it wrote, one path per line: matplotlib's layout warnings
# (tight layout, an empty legend) are about the drawing, not the numbers, and do not
# go between those lines (docs/figures.md).
warnings.filterwarnings("ignore", category=UserWarning, module="matplotlib")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402
from matplotlib.ticker import NullFormatter  # noqa: E402

# Deterministic files: no dates, fixed SVG ids, text kept as text (editable, searchable).
matplotlib.rcParams.update({"svg.hashsalt": "eigenmass", "svg.fonttype": "none", "pdf.fonttype": 42})

# One colour per method and one marker per integrator: the registry's, given by
# `eigenmass plot` as --style (solver/registry.cpp, reference/table.cpp); so are
# whose route each method is (an engine's name, the in-house owner's, else its
# own) and the integrators that own their routes in the benchmark (IDA): no
# engine or owner is named here (sweep/engine_study.cpp's routeOwner,
# sweep/benchmark_tables.cpp's benchmarkOwner).
MARKERS = {}
COLORS = {}
OWNERS = {}
INTEGRATOR_OWNERS = {}
IN_HOUSE_OWNER = [None]
OUTCOME_COLORS = {"ok": "#4daf4a", "wrong": "#ff7f00", "failed": "#e41a1c"}
FLOOR = 1e-17  # zero errors drawn here on log axes
FORMAT = ["png"]
KINDS = {"report": "a compare report", "sweep": "a sweep's merged results", "extreme": "an extreme summary",
         "precision": "a precision file", "trajectory": "a trajectory"}
WRITTEN = []


class Refused(Exception):
    """An input of the right shape that this tool will not draw: its message is the whole line."""


def color(method):
    return COLORS.get(method, "k")


def marker(integrator):
    return MARKERS.get(integrator, ".")


def tuned(r):
    """A line's tuning set (sweep plans' "tuning"), bracketed, or "" (none; CSVs from before it)."""
    return "[%s]" % r["tuning"] if r.get("tuning") else ""


def num(x):
    if x in ("", None):
        return math.nan
    return float(x)


def positive(values):
    return [max(num(v), FLOOR) if not math.isnan(num(v)) else math.nan for v in values]


# What a name read from a file may be before it becomes part of a figure's
# file name: what scene names may be (io/scene_json.hpp's isSceneName).
SAFE_NAME = re.compile(r"[A-Za-z0-9_-]{1,64}\Z")


def checked_name(value, where):
    """`value`, read from `where` (a file and its key), if it can name a file; else Refused."""
    if isinstance(value, str) and SAFE_NAME.match(value):
        return value
    shown = json.dumps(value)[:60] if not isinstance(value, str) else json.dumps(value[:60])
    raise Refused("%s is %s: a name read from a file must be letters, digits, '_' and '-' (1 to 64), since it names "
                  "the figures; nothing drawn" % (where, shown))


def save(fig, out, stem):
    path = os.path.join(out, "%s.%s" % (stem, FORMAT[0]))
    # Every figure lands in OUT itself, whatever a name read from a file said.
    if os.path.dirname(os.path.realpath(path)) != os.path.realpath(out) or stem.startswith("."):
        raise Refused("the figure name %s would leave the output folder; nothing drawn" % json.dumps(stem[:80]))
    fig.tight_layout()
    meta = {"png": {"Software": None}, "svg": {"Date": None}, "pdf": {"CreationDate": None}}[FORMAT[0]]
    fig.savefig(path, dpi=110, metadata=meta)
    plt.close(fig)
    WRITTEN.append(os.path.basename(path))


def label_pair(a1, a2, labels1, labels2):
    """Two log-log panels side by side: (x, y) labels each (None: shared), grids, the legend on the first."""
    for ax, (x, y) in ((a1, labels1), (a2, labels2)):
        ax.set_xlabel(x)
        if y:
            ax.set_ylabel(y)
        ax.grid(True, which="both", alpha=0.3)
    a1.legend(fontsize=7)


def mark_failure(ax, method, t, y, label=None):
    """An x where a run stopped; its gid names the method (tests read it in the SVG)."""
    (pt,) = ax.plot([t], [y], "x", color=color(method), ms=9, mew=2, label=label)
    pt.set_gid("failed-" + method)


def last_finite(ts, ys, t_stop):
    pts = [(t, y) for t, y in zip(ts, ys) if not math.isnan(y) and t <= t_stop + 1e-12]
    return pts[-1] if pts else (t_stop, FLOOR)


# ----------------------------------------------------------------------------------------- report


def report_figures(rep, out, csv_dir, source):
    scene = checked_name(rep["scene"]["name"], "%s: key scene.name" % source)
    s = rep["series"]
    t = s["t"]
    methods = {m["name"]: m for m in rep["methods"]}
    inhouse = rep["options"]["inhouse"]
    subtitle = "%s, in-house %s %s; reference %s %s %s; %s" % (
        scene, inhouse["integrator"], " ".join("%s %g" % (k, v) for k, v in inhouse.items() if k != "integrator"),
        rep["reference"]["engine"], rep["reference"]["integrator"], reference_setting(rep["reference"]),
        rep["provenance"].get("date_utc", ""))
    divergence(rep, t, s, methods, subtitle, out, scene)
    energy(t, s, methods, subtitle, out, scene)
    coordinate_figure(rep, t, s, methods, csv_dir, subtitle, out, scene)


def reference_setting(ref, twin=False):
    """The reference's (or its twin's) step or tolerance: a fixed-step reference
    (a mechanism's replacement) has a dt and no tolerance."""
    dt = ref.get("horizon_dt" if twin else "dt")
    return "dt %g" % dt if dt is not None else "tol %g" % ref["horizon_tolerance" if twin else "tolerance"]


def method_label(m):
    extra = m["outcome"] if m["outcome"] != "ok" else ""
    if m["failure"]:
        extra = "failed at %g s: %s" % (m["failure"]["t"], m["failure"]["kind"])
    dt = m.get("dt", m.get("step"))  # "step" in reports before one vocabulary
    setting = "dt %g" % dt if dt is not None else "tol %g" % m["tolerance"]
    return "%s %s %s%s" % (m["name"], m["integrator"], setting, " (%s)" % extra if extra else "")


def divergence(rep, t, s, methods, subtitle, out, scene):
    fig, ax = plt.subplots(figsize=(9, 5.5))
    check = s.get("reference_check")
    if check:
        ax.semilogy(t[: len(check["pose_error_rad"])], positive(check["pose_error_rad"]), color="k", lw=2.5,
                    alpha=0.25, label="floor: reference vs its twin at %s" % reference_setting(rep["reference"], True))
    for name, m in methods.items():
        y = positive(s["methods"][name]["pose_error_rad"])
        ax.semilogy(t[: len(y)], y, color=color(name), lw=1.2, label=method_label(m))
        if m["failure"]:
            mark_failure(ax, name, *last_finite(t, y, m["failure"]["t"] or t[len(y) - 1]))
    for th in rep["options"]["thresholds_rad"]:
        ax.axhline(th, color="k", ls="--", lw=0.8)
        ax.annotate("%g rad" % th, (t[0], th), fontsize=8, va="bottom")
    notes = []
    for key, h in rep["reference"]["horizon_s"].items():
        if h is None:
            notes.append("reference within %g rad of its check to t_end" % float(key.replace("p", ".")))
        else:
            ax.axvline(h, color="k", ls=":", lw=1)
            ax.annotate("reference horizon %g rad: %g s" % (float(key.replace("p", ".")), h), (h, 0.98),
                        xycoords=ax.get_xaxis_transform(), rotation=90, fontsize=7, ha="right", va="top")
    ax.set_xlabel("time t, s")
    ax.set_ylabel("max pose error against the reference, rad")
    ax.set_title("Divergence from the reference: %s\n%s%s" % (scene, subtitle, ("\n" + "; ".join(notes)) if notes else ""),
                 fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, loc="best")
    save(fig, out, scene + "-divergence")


def energy(t, s, methods, subtitle, out, scene):
    fig, ax = plt.subplots(figsize=(9, 5))
    for name, m in methods.items():
        y = positive(s["methods"][name]["energy_error"])
        ax.semilogy(t[: len(y)], y, color=color(name), lw=1.2, label=method_label(m))
        if m["failure"]:
            mark_failure(ax, name, *last_finite(t, y, m["failure"]["t"] or t[len(y) - 1]))
    ax.set_xlabel("time t, s")
    ax.set_ylabel("|E(t) + W_diss(t) - E(0)| / max kinetic energy of the reference")
    ax.set_title("Energy balance error: %s\n%s" % (scene, subtitle), fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, loc="lower right")
    save(fig, out, scene + "-energy")


def coordinate_figure(rep, t, s, methods, csv_dir, subtitle, out, scene):
    """The paper's Fig. 3: from the report's `coordinate` series, else --csv-dir's trajectories."""
    c = s.get("coordinate")
    if c:
        name, ref = c["name"], (t, c["reference"])
        runs = {m: (t[: len(c["methods"][m])], c["methods"][m]) for m in methods if m in c["methods"]}
    elif csv_dir:
        ref_cols = read_traj_csv(os.path.join(csv_dir, "reference.csv"))
        name = first_angle(ref_cols)
        ref = (ref_cols["t"], ref_cols[name])
        runs = {}
        for m in methods:
            path = os.path.join(csv_dir, m + ".csv")
            if os.path.exists(path):
                cols = read_traj_csv(path)
                runs[m] = (cols["t"], cols[name])
    else:
        print("note: the report keeps no coordinate series (an older report): give --csv-dir to draw the "
              "coordinate figure", file=sys.stderr)
        return
    fig, ax = plt.subplots(figsize=(9, 5))
    ax.plot(ref[0], ref[1], "k-", lw=3, alpha=0.3, label="reference (%s)" % rep["reference"]["engine"])
    for m, (tm, v) in runs.items():
        ax.plot(tm, v, color=color(m), lw=1, label=method_label(methods[m]))
        f = methods[m]["failure"]
        if f and v:
            mark_failure(ax, m, tm[len(v) - 1], v[-1])
        d = methods[m]["coordinate_divergence_time_s"].get("1e-1")
        if d is not None:
            ax.axvline(d, color=color(m), ls="--", lw=0.7)
    ax.set_xlabel("time t, s")
    ax.set_ylabel("%s, rad" % name)
    ax.set_title("%s against time (the paper's Fig. 3; dashed: joint angles 0.1 rad off the reference)\n%s"
                 % (name, subtitle), fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    save(fig, out, scene + "-coordinate")


# ------------------------------------------------------------------------------------------ sweep


def read_traj_csv(path):
    with open(path) as f:
        rd = csv.reader(f)
        head = next(rd)
        cols = {h: [] for h in head}
        for row in rd:
            for h, v in zip(head, row):
                cols[h].append(num(v))
    return cols


def first_angle(cols):
    names = [k for k in cols if ".q" in k]
    return names[0]


def read_json(path):
    """A JSON file, or Refused naming it (a corrupt case file once gave "RESULTS: JSONDecodeError")."""
    try:
        with open(path) as f:
            return json.load(f)
    except ValueError as e:
        raise Refused("%s: not JSON (%s)" % (path, str(e)[:120]))


def sweep_figures(results, out):
    cases = [read_json(p) for p in sorted(glob.glob(os.path.join(results, "*.json")))]
    cases = [c for c in cases if c.get("format") == "eigenmass-sweep-case/1"]
    plan, t_end = checked_name(cases[0]["plan"], "%s: a case file's key plan" % results), cases[0]["key"]["t_end"]
    with open(os.path.join(results, plan + ".csv")) as f:
        rows = list(csv.DictReader(f))
    for r in rows:  # names that build figure and trajectory file names
        for column in ("scene", "method", "integrator"):
            checked_name(r[column], "%s: column %s of %s.csv" % (results, column, plan))
    runs = [r for r in rows if r["role"] == "run"]
    drawn = len(WRITTEN)
    # The plan's tables say which figures its results are for (a case file names them).
    tables = cases[0].get("tables")
    if tables is None:
        raise Refused("%s: its case files name no plan tables (an older eigenmass made them): plot them with the "
                 "version that ran them, or rerun the plan into a fresh folder" % results)
    if "work-precision" in tables or "engine-study" in tables:
        work_precision(rows, out)
    if "cost-vs-size" in tables:
        cost_vs_size(runs, t_end, out)
    if "benchmark" in tables:
        benchmark(rows, results, out)
    trajectories(rows, results, out)
    if os.path.exists(os.path.join(results, plan + "-ensemble.csv")):
        ensemble_cdf(plan, runs, t_end, cases[0].get("claim"), out)
        ensemble_prediction(plan, results, t_end, out)
    if len(WRITTEN) == drawn:
        raise Refused("%s: nothing to draw: the plan's tables (%s) have no figure, no trajectory was kept and there is no "
                 "ensemble" % (results, ", ".join(tables) or "none"))


def small_multiples(rows, scene, error, key, panel, label, ylabel, mark, title, out, stem):
    """Error (column `error`) against CPU time on one scene: a panel per `panel` (the first item of each line's
    `key`), its lines in colour, every other line grey behind it, x a failed run; `mark(ax)` adds the panel's
    reference lines. A line is the runs of one key, coarse to fine; `label(key)` names it in its panel."""
    lines = {}
    for r in rows:
        if r["scene"] == scene and r["role"] == "run" and r[error]:
            lines.setdefault(key(r), []).append(r)
    for pts in lines.values():
        pts.sort(key=lambda r: -num(r["setting"]))
    panels = list(dict.fromkeys(k[0] for k in lines))
    if not panels:
        return
    cols = min(3, len(panels))
    nrows = (len(panels) + cols - 1) // cols
    fig, axes = plt.subplots(nrows, cols, figsize=(4.4 * cols, 3.6 * nrows), sharex=True, sharey=True, squeeze=False)
    for k, name in enumerate(panels):
        ax = axes[k // cols][k % cols]
        for line, pts in lines.items():
            xs = [num(p["cpu_median_s"]) for p in pts]
            ys = [max(num(p[error]), FLOOR) for p in pts]
            if line[0] != name:
                ax.loglog(xs, ys, "-", color="0.85", lw=0.8, zorder=1)
                continue
            ok = [i for i, p in enumerate(pts) if p["status"] == "ok"]
            style = {"color": color(name)} if panel == "method" else {}
            ax.loglog([xs[i] for i in ok], [ys[i] for i in ok], marker=marker(pts[0]["integrator"]), ms=4, lw=1.2,
                      label=label(line), zorder=3, **style)
            for i, p in enumerate(pts):
                if p["status"] != "ok":
                    mark_failure(ax, p["method"], xs[i], ys[i])
        mark(ax)
        ax.xaxis.set_minor_formatter(NullFormatter())  # decades only: minor labels collide
        ax.set_title(name, fontsize=10, **({"color": color(name)} if panel == "method" else {}))
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7 if panel == "method" else 6, **({"title": "integrator", "title_fontsize": 7} if panel == "method" else {}))
        if k // cols == nrows - 1 or k + cols >= len(panels):
            ax.set_xlabel("CPU s (median of the repeats)")
        if k % cols == 0:
            ax.set_ylabel(ylabel)
    for k in range(len(panels), nrows * cols):
        axes[k // cols][k % cols].set_visible(False)
    fig.suptitle(title, fontsize=9)
    save(fig, out, stem)


def work_precision(rows, out):
    """Small multiples: a panel per method in its colour, the other methods grey behind it."""
    for scene in dict.fromkeys(r["scene"] for r in rows if r["role"] == "run"):
        check = [r for r in rows if r["scene"] == scene and r["role"] == "check"]

        def mark(ax):
            if check:
                ax.axhline(num(check[0]["max_pose_error_rad"]), color="k", ls=":", lw=0.8)
        # A line per method, formulation (a mechanism's) and integrator: formulations are never pooled.
        small_multiples(rows, scene, "max_pose_error_rad", lambda r: (r["method"], r.get("formulation", ""), r["integrator"], tuned(r)),
                        "method", lambda line: " ".join(x for x in line[1:] if x), "max pose error, rad", mark,
                        "Work-precision on %s: a panel per method, grey the others; x a failed run (error up to the "
                        "failure); dotted: the reference vs its check" % scene, out, "work-precision-" + scene)


def benchmark_owner(r):
    """The benchmark's owners, as the style table gives them (sweep/benchmark_tables.cpp's benchmarkOwner): an
    integrator that owns its routes (IDA), else the method's owner (an engine, the in-house owner), else the
    method itself (a method this eigenmass does not know: a plugin's)."""
    return INTEGRATOR_OWNERS.get(r["integrator"]) or OWNERS.get(r["method"], r["method"])


def benchmark_levels(results):
    """The precision levels of the problem a benchmark folder holds: its plan's scene's `benchmark`."""
    plans = glob.glob(os.path.join(results, "*.plan.json"))
    if len(plans) != 1:
        return []
    scenes = read_json(plans[0]).get("scenes", [])
    if len(scenes) != 1:
        return []
    entry = scenes[0]
    path = entry["file"] if isinstance(entry, dict) else os.path.join(os.path.dirname(plans[0]), entry)
    return read_json(path).get("benchmark", {}).get("levels", [])


def benchmark(rows, results, out):
    """Error by the problem's own measure against CPU time: a panel per owner, its routes in colour, the
    others grey behind; dashed: the precision levels; x a failed run."""
    levels = benchmark_levels(results)

    def mark(ax):
        for level in levels:
            ax.axhline(level, color="k", ls="--", lw=0.7)

    def label(line):
        owner, method, formulation, integrator, tuning = line
        return " ".join(x for x in (method if owner == IN_HOUSE_OWNER[0] else "", formulation, integrator, tuning) if x)
    for scene in dict.fromkeys(r["scene"] for r in rows if r["role"] == "run"):
        small_multiples(rows, scene, "benchmark_error_m",
                        lambda r: (benchmark_owner(r), r["method"], r["formulation"], r["integrator"], tuned(r)), "owner", label,
                        "benchmark error, m", mark,
                        "Benchmark %s: error by the problem's measure against CPU time, a panel per owner, grey the "
                        "others; dashed: the precision levels; x a failed run" % scene, out, "benchmark-" + scene)


def cost_vs_size(runs, t_end, out):
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(12, 5))
    lines = {}
    for r in runs:
        lines.setdefault((" ".join(x for x in (r["method"], r.get("formulation", ""), tuned(r)) if x), r["integrator"], r["setting"]), []).append(r)
    for (method, integ, setting), pts in lines.items():
        pts.sort(key=lambda r: int(r["nu"]))
        n = [int(p["nu"]) for p in pts]
        per_s = [num(p["cpu_median_s"]) / (num(p["failure_time_s"]) if p["status"] != "ok" else t_end) for p in pts]
        label = "%s %s %g" % (method, integ, float(setting))
        a1.loglog(n, [num(p["cpu_per_rhs_s"]) * 1e6 for p in pts], marker=marker(integ), ms=3, label=label,
                  color=color(method))
        a2.loglog(n, per_s, marker=marker(integ), ms=3, color=color(method), label=label)
        for p, y in zip(pts, per_s):
            if p["status"] != "ok":
                mark_failure(a2, method, int(p["nu"]), y)
    label_pair(a1, a2, ("degrees of freedom n", "µs per right-hand-side evaluation"),
               ("degrees of freedom n", "CPU s per simulated second (x: failed, up to the failure)"))
    fig.suptitle("Cost against size (the paper's Fig. 4)")
    save(fig, out, "cost-vs-size")


def trajectories(rows, results, out):
    for scene in dict.fromkeys(r["scene"] for r in rows if r["role"] == "run"):
        ref_path = os.path.join(results, scene + ".reference.json")
        if not os.path.exists(ref_path):
            continue
        tr = read_json(ref_path).get("trajectory")
        if not tr:
            continue
        ref = {"t": tr["t"], "energy": tr["energy"], "kinetic": tr["kinetic"]}
        for i, name in enumerate(tr["q_names"]):
            ref[name] = [q[i] for q in tr["q"]]
        found = {}
        for r in rows:
            if r["scene"] == scene and r["role"] == "run":
                path = os.path.join(results, "%s.%s.%s.%g.csv" % (scene, r["method"], r["integrator"],
                                                                  float(r["setting"])))
                if os.path.exists(path):
                    found[r["method"]] = (r, read_traj_csv(path))
        if found:
            fig3(scene, ref, found, out)
            fig5(scene, ref, found, out)


def first_joint_to_leave(ref, runs):
    """The coordinate some run leaves the reference by 0.1 rad on first (the figure's angle)."""
    best = (math.inf, None)
    qnames = [k for k in ref if ".q" in k]
    for _, tr in runs.values():
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
        ax.plot(tr["t"], tr[q], lw=1, color=color(method), label="%s %s" % (method, row["integrator"]))
        if row["status"] != "ok":
            mark_failure(ax, method, tr["t"][-1], tr[q][-1])
        if row["coord_beyond_1e-1_s"]:
            t = float(row["coord_beyond_1e-1_s"])
            ax.axvline(t, color=color(method), ls="--", lw=0.8)
            ax.annotate("%s: 0.1 rad off at %.2f s" % (method, t), (t, ax.get_ylim()[1]), fontsize=7, rotation=90,
                        va="top", ha="right", color=color(method))
    ax.set_xlabel("time t, s")
    ax.set_ylabel("%s, rad" % q)
    ax.set_title("Fig. 3: %s of %s (dashed: the first joint coordinate 0.1 rad off the reference)" % (q, scene),
                 fontsize=9)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    save(fig, out, "fig3-" + scene)


def fig5(scene, ref, runs, out):
    scale = max(ref["kinetic"]) or 1.0
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(9, 7), sharex=True)
    for method, (_, tr) in runs.items():
        e0 = tr["energy"][0]
        a1.plot(tr["t"], tr["energy"], lw=1, color=color(method), label=method)
        a2.semilogy(tr["t"], [max(abs(e - e0) / scale, FLOOR) for e in tr["energy"]], lw=1, color=color(method),
                    label=method)
    a1.set_ylabel("total energy E, J")
    a2.set_ylabel("|E(t) - E(0)| / max kinetic energy")
    a2.set_xlabel("time t, s")
    a1.set_title("Fig. 5: total energy of %s and its relative error" % scene, fontsize=9)
    for a in (a1, a2):
        a.grid(alpha=0.3, which="both")
        a.legend(fontsize=8)
    save(fig, out, "fig5-" + scene)


DT_STYLES = ["-", "--", "-.", ":"]


def ensemble_cdf(plan, runs, t_end, claim, out):
    """A row per method (its colour), a column per scene, a line style per step; the plan's
    ensemble.claim (a published breakdown time), if it states one, dotted."""
    scenes = sorted({r["scene"] for r in runs})
    methods = list(dict.fromkeys(r["method"] for r in runs))
    fig, axes = plt.subplots(len(methods), len(scenes), figsize=(4.6 * len(scenes), 2.6 * len(methods)),
                             sharex=True, sharey=True, squeeze=False)
    for i, method in enumerate(methods):
        for j, scene in enumerate(scenes):
            ax = axes[i][j]
            mine = [r for r in runs if r["scene"] == scene and r["method"] == method]
            settings = sorted({float(r["setting"]) for r in mine}, reverse=True)
            t = []
            for k, dt in enumerate(settings):
                t = [num(r["coord_beyond_1e-1_s"]) for r in mine if float(r["setting"]) == dt]
                crossed = sorted(x for x in t if not math.isnan(x))
                xs = [0.0] + [x for x in crossed for _ in (0, 1)] + [t_end]
                ys = [0.0] + [y for n in range(len(crossed)) for y in (n / len(t), (n + 1) / len(t))] + \
                     [len(crossed) / len(t)]
                ax.plot(xs, ys, DT_STYLES[k % len(DT_STYLES)], color=color(method), lw=1.4, label="dt %g" % dt)
            if claim:
                ax.axvline(claim["t_s"], color="k", lw=0.8, ls=":")
            ax.set_title("%s, %s (%d members)" % (method, scene, len(t)), fontsize=9)
            ax.set_xlim(0, t_end)
            ax.set_ylim(0, 1.02)
            ax.grid(alpha=0.3)
            if i == len(methods) - 1:
                ax.set_xlabel("time t, s" + ("; dotted: " + claim["label"] if claim else ""))
            if j == 0:
                ax.set_ylabel("fraction beyond 0.1 rad")
            if i == 0 and j == 0:
                ax.legend(fontsize=7, loc="upper left")
    save(fig, out, plan + "-cdf")


def ensemble_prediction(plan, results, t_end, out):
    """Measured against predicted divergence time per member; a member still within 0.1 rad at t_end
    (censored: its time is only known to exceed t_end) is an open triangle at t_end, pointing up."""
    path = os.path.join(results, plan + "-prediction.csv")
    if not os.path.exists(path):
        return
    with open(path) as f:
        pred = [p for p in csv.DictReader(f) if float(p["threshold"]) == 0.1 and p["predicted_s"]]
    scenes = sorted({p["scene"] for p in pred})
    if not scenes:
        return
    fig, axes = plt.subplots(1, len(scenes), figsize=(4.8 * len(scenes), 4.4), sharey=True, squeeze=False)
    for ax, scene in zip(axes[0], scenes):
        for method in dict.fromkeys(p["method"] for p in pred):
            mine = [p for p in pred if p["scene"] == scene and p["method"] == method]
            seen = [p for p in mine if p["measured_s"]]
            censored = [float(p["predicted_s"]) for p in mine if not p["measured_s"]]
            ax.scatter([float(p["predicted_s"]) for p in seen], [float(p["measured_s"]) for p in seen], s=6,
                       color=color(method), alpha=0.5, label="%s (%d left, %d censored)" % (method, len(seen),
                                                                                         len(censored)))
            ax.scatter(censored, [t_end] * len(censored), s=14, marker="^", facecolors="none",
                       edgecolors=color(method), linewidths=0.6, alpha=0.6)
        x_max = min(3 * t_end, max([t_end * 1.5] + [1.03 * float(p["predicted_s"]) for p in pred]))  # censored ones lie far right
        ax.plot([0, x_max], [0, x_max], "k:", lw=0.8)
        ax.axhline(t_end, color="0.5", lw=0.6)
        ax.set_xlim(0, x_max)
        ax.set_ylim(0, t_end * 1.04)
        ax.set_title(scene + ": every member and step", fontsize=10)
        ax.set_xlabel("predicted from e(t0) and chi, s\nopen triangles at %g s: still within 0.1 rad (censored)"
                      % t_end)
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel("measured: pose beyond 0.1 rad, s")
    axes[0][0].legend(fontsize=7, loc="lower right")
    save(fig, out, plan + "-prediction")


# -------------------------------------------------------------------------------------- precision


def precision_figures(prec, out, source):
    """Error against CPU time and against the step or tolerance: a line per method and integrator."""
    scene = checked_name(prec["scene"], "%s: key scene" % source)
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(12, 5), sharey=True)
    lines = {}
    for p in prec["points"]:
        lines.setdefault((p["method"], p["integrator"]), []).append(p)
    for (method, integ), pts in lines.items():
        setting = [p.get("dt", p.get("step", p.get("tolerance"))) for p in pts]  # "step": older files
        err = [max(num(p["max_pose_error_rad"]), FLOOR) for p in pts]
        cpu = [num(p["run_time_s"]) for p in pts]
        ok = [i for i, p in enumerate(pts) if p["status"] == "ok"]
        for ax, xs in ((a1, cpu), (a2, setting)):
            ax.loglog([xs[i] for i in ok], [err[i] for i in ok], marker=marker(integ), color=color(method), lw=1.2,
                      ms=4, label="%s %s" % (method, integ))
            for i, p in enumerate(pts):
                if p["status"] != "ok":
                    mark_failure(ax, method, xs[i], err[i])
    label_pair(a1, a2, ("CPU time of the run, s", "max pose error against the reference, rad"),
               ("step dt, s, or tolerance", None))
    ref = prec["reference"]
    fig.suptitle("Work-precision on %s over %g s against %s %s tol %g (x: failed, error up to the failure)"
                 % (scene, prec["t_end"], ref["method"], ref["integrator"], ref["tolerance"]), fontsize=9)
    save(fig, out, scene + "-work-precision")


# ------------------------------------------------------------------------------------- trajectory


def trajectory_figures(csv_path, meta, out):
    """One run (simulate --out): its angles and speeds, and its energy balance, against time."""
    cols = read_traj_csv(csv_path)
    stem = os.path.basename(csv_path)[: -len(".csv")]
    if meta is None:  # a CSV from outside, without a sidecar: its columns against t, named by its file
        method, meta = stem, {}
        drawn = [k for k in cols if k != "t"]
        q = [k for k in drawn if ".q" in k or ".u" not in k][:12]
        u = [k for k in drawn if ".u" in k][:12]
        title = "%s (no sidecar: how it was made is not recorded)" % os.path.basename(csv_path)
    else:
        method = meta["method"]
        q = [k for k in cols if ".q" in k][:12]
        u = [k for k in cols if ".u" in k][:12]
        setting = "dt %g" % meta["dt"] if "dt" in meta else "tol %g" % meta["tolerance"]
        title = "%s: %s %s %s" % (meta["scene"], method, meta["integrator"], setting)
    if meta.get("failure"):
        title += " (failed at %g s: %s)" % (meta["failure"]["t"], meta["failure"]["kind"])
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(9, 7), sharex=True)
    for ax, names, unit in ((a1, q, "coordinates (rad, m)"), (a2, u, "speeds (rad/s, m/s)")):
        for name in names:
            ax.plot(cols["t"], cols[name], lw=1, label=name)
        if meta.get("failure") and cols["t"]:
            for name in names:
                mark_failure(ax, method, cols["t"][-1], cols[name][-1])
        ax.set_ylabel(unit)
        ax.grid(alpha=0.3)
        if names:  # an empty legend is a matplotlib warning in plot's output
            ax.legend(fontsize=6, ncol=2)
    a2.set_xlabel("time t, s")
    a1.set_title(title + ("; the first 12 of each" if len(q) == 12 else ""), fontsize=9)
    save(fig, out, stem + "-state")
    if not all(k in cols for k in ("energy", "kinetic", "dissipated")):
        return  # a CSV from outside without the energy columns: no energy balance to draw
    e0 = cols["energy"][0]
    scale = max(cols["kinetic"]) or 1.0
    fig, ax = plt.subplots(figsize=(9, 4.5))
    ax.semilogy(cols["t"], [max(abs(e + w - e0) / scale, FLOOR) for e, w in zip(cols["energy"], cols["dissipated"])],
                color=color(method), lw=1.2, label=method)
    if meta.get("failure") and cols["t"]:
        mark_failure(ax, method, cols["t"][-1], max(abs(cols["energy"][-1] + cols["dissipated"][-1] - e0) / scale, FLOOR))
    finish_against_time(fig, ax, "|E(t) + W_diss(t) - E(0)| / max kinetic energy", "Energy balance error: " + title, out,
                        stem + "-energy")
    loop_figure(cols, method, title, meta, out, stem)
    limits_figure(cols, method, title, meta, out, stem)


def limits_figure(cols, method, title, meta, out, stem):
    """A run with joint limits: each limited coordinate against time between its stops, its impacts marked
    (an engine's: where it crossed a stop), the first 6."""
    stops = [s for s in meta.get("limits", []) if s["coordinate"] in cols][:6]
    if not stops:
        return
    impacts = meta.get("impacts", {}).get("each", [])
    fig, axes = plt.subplots(len(stops), 1, figsize=(9, 2.2 + 1.6 * len(stops)), sharex=True, squeeze=False)
    for ax, s in zip(axes[:, 0], stops):
        name = s["coordinate"]
        ax.plot(cols["t"], cols[name], lw=1.1, color=color(method), label=name)
        for bound, ls in ((s["lower"], "--"), (s["upper"], ":")):
            ax.axhline(bound, color="k", lw=0.8, ls=ls)
        hits = [i["t"] for i in impacts if i["coordinate"] == name]
        if hits:
            ys = [s["lower"] if i.get("u_before", 0) < 0 else s["upper"] for i in impacts if i["coordinate"] == name]
            ax.plot(hits, ys, "x", color="tab:red", ms=5, label="impacts (%d)" % len(hits))
        ax.set_ylabel("%s (rad, m)\ne = %g" % (name, s["restitution"]), fontsize=8)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="upper right")
    axes[-1, 0].set_xlabel("time t, s")
    axes[0, 0].set_title("Joints against their stops (dashed: lower, dotted: upper): " + title, fontsize=9)
    save(fig, out, stem + "-limits")


def finish_against_time(fig, ax, ylabel, title, out, name):
    """One run's log-scale quantity against time: labels, grid, legend, saved as `name`."""
    ax.set_xlabel("time t, s")
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    save(fig, out, name)


LOOP_COLUMNS = (("loops.position_m", "position, m", "-"), ("loops.position_rad", "position, rad", "--"),
                ("loops.velocity_m_per_s", "velocity, m/s", "-."), ("loops.velocity_rad_per_s", "velocity, rad/s", ":"))


def loop_figure(cols, method, title, meta, out, stem):
    """A mechanism's run: its closures' violation against time (the CSV's loops.* columns)."""
    if not all(c in cols for c, _, _ in LOOP_COLUMNS):
        return  # a tree, or a CSV from outside: no loops to draw
    fig, ax = plt.subplots(figsize=(9, 4.5))
    for c, label, style in LOOP_COLUMNS:
        ax.semilogy(cols["t"], [max(abs(v), FLOOR) for v in cols[c]], ls=style, lw=1.2, color=color(method), label=label)
    if meta.get("failure") and cols["t"]:
        mark_failure(ax, method, cols["t"][-1], max(abs(cols["loops.position_m"][-1]), FLOOR))
    # A zero violation has no logarithm: it is drawn at FLOOR, and the axis says so.
    floored = any(abs(v) < FLOOR for c, _, _ in LOOP_COLUMNS for v in cols[c])
    finish_against_time(fig, ax, "largest |g| (position) and |G u| (velocity)" + (" (zeros drawn at %g)" % FLOOR if floored else ""),
                        "Constraint violation at the samples: " + title, out, stem + "-loops")


# ---------------------------------------------------------------------------------------- extreme


def extreme_figures(summary, out):
    cases = summary["cases"]
    labels = list(dict.fromkeys(r["label"] for c in cases for r in c["runs"]))
    methods = list(dict.fromkeys(m["name"] for c in cases for r in c["runs"] for m in r["methods"]))
    outcomes = {}
    for c in cases:
        for r in c["runs"]:
            for m in r["methods"]:
                outcomes[(c["name"], r["label"], m["name"])] = m["outcome"]
    fig, axes = plt.subplots(1, len(labels), figsize=(1.2 + 0.55 * len(methods) * len(labels), 1.4 + 0.32 * len(cases)),
                             sharey=True, squeeze=False)
    kinds = list(OUTCOME_COLORS) + sorted({o for o in outcomes.values()} - set(OUTCOME_COLORS))
    for ax, label in zip(axes[0], labels):
        for i, c in enumerate(cases):
            for j, m in enumerate(methods):
                o = outcomes.get((c["name"], label, m))
                fc = OUTCOME_COLORS.get(o, "0.8") if o else "white"
                ax.add_patch(plt.Rectangle((j, i), 1, 1, facecolor=fc, edgecolor="white", lw=1.5,
                                           gid="cell-%s-%s-%s" % (c["name"], m, o or "not-run")))
                if o == "failed":
                    ax.plot(j + 0.5, i + 0.5, "x", color="k", ms=6)
        ax.set_xlim(0, len(methods))
        ax.set_ylim(len(cases), 0)
        ax.set_xticks([j + 0.5 for j in range(len(methods))])
        ax.set_xticklabels(methods, rotation=60, ha="right", fontsize=8)
        for tick, m in zip(ax.get_xticklabels(), methods):
            tick.set_color(color(m))
        ax.set_yticks([i + 0.5 for i in range(len(cases))])
        ax.set_yticklabels([c["name"] for c in cases], fontsize=8)
        ax.set_title(label, fontsize=9)
        ax.set_xlabel("method")
    axes[0][0].set_ylabel("case")
    handles = [Patch(color=OUTCOME_COLORS.get(k, "0.8"), label=k) for k in kinds]
    handles.append(Patch(facecolor="white", edgecolor="0.5", label="not run"))
    fig.legend(handles=handles, loc="upper right", fontsize=8, ncol=len(handles))
    fig.suptitle("Extreme cases: the outcome of every method (x failed)", fontsize=10, x=0.3)
    save(fig, out, "extreme-outcomes")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("kind", choices=["report", "sweep", "extreme", "precision", "trajectory"])
    ap.add_argument("input")
    ap.add_argument("out")
    ap.add_argument("format", choices=["png", "svg", "pdf"])
    ap.add_argument("--csv-dir")
    ap.add_argument("--style", default="{}", help="JSON {colours: {method: colour}, markers: {integrator: marker}, "
                    "owners: {method: owner}, integrator_owners: {integrator: owner}, in_house_owner: name}")
    a = ap.parse_args()
    # Ended with eigenmass (SIGTERM on its death, SIGINT from the terminal):
    # the scratch folder goes with it.
    for sig, code in ((signal.SIGTERM, 143), (signal.SIGINT, 130)):
        signal.signal(sig, lambda *_, code=code: (shutil.rmtree(a.out, ignore_errors=True), os._exit(code)))
    FORMAT[0] = a.format
    style = json.loads(a.style)
    COLORS.update(style.get("colours", {}))
    MARKERS.update(style.get("markers", {}))
    OWNERS.update(style.get("owners", {}))
    INTEGRATOR_OWNERS.update(style.get("integrator_owners", {}))
    IN_HOUSE_OWNER[0] = style.get("in_house_owner")
    try:
        draw(a)
    except Exception as e:  # noqa: BLE001 - every failure is one line for eigenmass to print (exit 2)
        # A file of the right format but not of its shape, a file missing or empty.
        with open(os.path.join(a.out, "error.txt"), "w") as f:
            if isinstance(e, Refused):
                f.write(str(e)[:300].replace("\n", " "))
                sys.exit(2)
            if isinstance(e, KeyError):
                what = "key %s not found" % e
            elif isinstance(e, OSError) and e.filename:
                what = "%s: %s" % (e.filename, e.strerror)
            elif isinstance(e, StopIteration):
                what = "a file with no line"
            else:
                what = "%s: %s" % (type(e).__name__, e)
            f.write("%s: %s (not the shape of %s; nothing drawn)" % (a.input, what[:200].replace("\n", " "), KINDS[a.kind]))
        sys.exit(2)
    for w in WRITTEN:
        print(w)


def draw(a):
    if a.kind == "sweep":
        sweep_figures(a.input, a.out)
    elif a.kind == "trajectory":  # INPUT is the CSV; its sidecar <csv>.json, where there is one, says how it was made
        trajectory_figures(a.input, read_json(a.input + ".json") if os.path.exists(a.input + ".json") else None, a.out)
    else:
        data = read_json(a.input)
        {"report": lambda: report_figures(data, a.out, a.csv_dir, a.input), "extreme": lambda: extreme_figures(data, a.out),
         "precision": lambda: precision_figures(data, a.out, a.input)}[a.kind]()


if __name__ == "__main__":
    main()
