#!/usr/bin/env python3
"""The paper's claims as distributions, from an ensemble sweep's merged files
(docs/results.md; data/plans/paper-ensemble.json):

    python3 tools/ensemble_summary.py data/plans/paper-ensemble.json results/paper-ensemble > docs/results/paper-ensemble-claims.md
    python3 tools/ensemble_summary.py --sigma PLAN RESULTS [PLAN RESULTS ...] > docs/results/paper-sigma.md
    python3 tools/ensemble_summary.py --check-ensemble CASES.csv ENSEMBLE.csv   # this file's statistics = eigenmass's

Reads <plan>.csv (one row per case, with its member) and <plan>-prediction.csv;
writes Markdown tables: when each method's joint angles leave the reference by
0.1 rad, over all members (a member that never leaves within t_end counts as
"later than t_end", never as a time), where the plan's ensemble.claim (the paper's 7.2 s) falls; the
energy ranking per member; the Lyapunov prediction against measurement.

One convention with eigenmass (sweep/ensemble.hpp): a member that never
crosses is censored everywhere, +inf ("later than t_end") in the order
statistics; quantiles are type 7 and the median's interval is from the order
statistics, as `--merge` writes them in <plan>-ensemble.csv (--check-ensemble
proves the two agree). With n <= 5 members the median's interval is the
pair (min, max), whose coverage 1 - 2^(1-n) is below 95 % (93.8 % at n = 5);
Wilson's interval also covers less than its nominal 95 % at such n. A member
crossing exactly at t_end is an event, not censored.

The prediction's ratio measured / predicted is fitted by a censored
regression (Tobit; a log-normal accelerated-failure-time model): log T =
a + b log P + s e, e ~ N(0, 1), with T right-censored at t_end, maximized by
statsmodels' GenericLikelihoodModel (Wald intervals from its Hessian). The
censoring point t_end is the same for every member, so given P it is not
informative; a Kaplan-Meier curve of the ratio T / P, censored at t_end / P,
was not: that point falls with the prediction. Libraries (Debian's):
Wilson's interval is statsmodels' proportion_confint, the binomial law
scipy's, the normal law scipy's.
"""
import argparse, csv, json, math, os, sys, warnings
from collections import defaultdict

import numpy as np
from scipy.stats import binom, norm
from statsmodels.base.model import GenericLikelihoodModel
from statsmodels.stats.proportion import proportion_confint



def claim_of(plan, plan_path):
    """The plan's ensemble.claim: (time, label), e.g. the paper's "after about 7.2 s" (method b)."""
    c = plan.get("ensemble", {}).get("claim")
    if not c:
        sys.exit("%s: ensemble.claim: missing (the published time the members are held against)" % plan_path)
    return c["t_s"], c["label"]


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def num(x):
    return float(x) if x not in ("", None) else math.inf


def quantile(xs, p):
    """Type 7 (numpy's default) over values that may include +inf (censored members:
    a quantile that reaches one is +inf, never interpolated; eigenmass's quantile)."""
    xs = sorted(xs)
    h = p * (len(xs) - 1)
    lo = int(math.floor(h))
    hi = min(lo + 1, len(xs) - 1)
    if math.isinf(xs[hi]) or math.isinf(xs[lo]):
        return xs[hi] if h > lo else xs[lo]
    return xs[lo] + (h - lo) * (xs[hi] - xs[lo])


def median_ci(xs, level=0.95):
    """Distribution-free interval for the median from the order statistics: the widest
    symmetric pair (x_(l), x_(n+1-l)) whose exact binomial coverage is at least `level`."""
    xs, n = sorted(xs), len(xs)
    cdf = lambda k: binom.cdf(k, n, 0.5)  # P(Binomial(n, 1/2) <= k)
    l = 0
    while l + 1 <= n // 2 and 1 - 2 * cdf(l) >= level:  # P(x_(l+1) <= median < x_(n-l)) = 1 - 2 P(B <= l)
        l += 1
    return xs[max(l - 1, 0)], xs[n - max(l, 1)]


def wilson(k, n):
    """Wilson's 95 % score interval of a proportion k / n (statsmodels)."""
    if n == 0:
        return math.nan, math.nan
    lo, hi = proportion_confint(k, n, alpha=0.05, method="wilson")
    return max(0.0, float(lo)), min(1.0, float(hi))


def per_member(runs, column):
    """{(scene, dt, member): {method: the column's value}}."""
    out = defaultdict(dict)
    for r in runs:
        out[(r["scene"], float(r["setting"]), r["member"])][r["method"]] = num(r[column])
    return out


class CensoredNormal(GenericLikelihoodModel):
    """y = X beta + s e, e ~ N(0, 1); where `censored`, only y >= the value given is known
    (Tobit; with y = log T, the log-normal accelerated-failure-time model). Params: beta, log s."""

    def __init__(self, endog, exog, censored):
        self.censored = np.asarray(censored, bool)
        super().__init__(endog, exog, extra_params_names=["log_sigma"])

    def loglikeobs(self, params):
        beta, log_s = params[:-1], params[-1]
        z = (self.endog - self.exog @ beta) / np.exp(log_s)
        return np.where(self.censored, norm.logsf(z), norm.logpdf(z) - log_s)


def censored_fit(y, X, censored):
    """(estimates, standard errors) of CensoredNormal's beta and log s, or None where the fit does
    not converge or nothing is observed. Starts at least squares over all values (deterministic BFGS)."""
    if all(censored):
        return None
    start = np.append(np.linalg.lstsq(X, y, rcond=None)[0], math.log(max(float(np.std(y)), 1e-3)))
    with warnings.catch_warnings():  # its degrees-of-freedom bookkeeping does not count log s; the fit does not use it
        warnings.filterwarnings("ignore", message="df_(model|resid)")
        r = CensoredNormal(y, X, censored).fit(start_params=start, method="bfgs", maxiter=5000, disp=0)
    if not r.mle_retvals["converged"] or not np.all(np.isfinite(r.bse)):
        return None
    return r.params, r.bse


def ratio_fits(pairs, t_end):
    """From (predicted, measured or None) pairs: the median ratio measured / predicted with the
    slope fixed at 1 (log T - log P = a + s e: exp(a) [95 %]) and the slope b of log T on log P
    [95 %] (b = 1: the ratio does not move with the prediction); each "-" where the fit fails."""
    P = np.array([p for p, _ in pairs])
    censored = np.array([t is None for _, t in pairs])
    y = np.log(np.array([t_end if t is None else t for _, t in pairs]))
    x = np.log(P)
    z = 1.959963984540054  # the normal's 97.5 % point
    ratio = censored_fit(y - x, np.ones((len(y), 1)), censored)
    slope = censored_fit(y, np.column_stack([np.ones_like(x), x]), censored)
    r = "-" if ratio is None else "%.2f [%.2f, %.2f]" % tuple(math.exp(ratio[0][0] + k * z * ratio[1][0]) for k in (0, -1, 1))
    b = "-" if slope is None else "%.2f [%.2f, %.2f]" % tuple(slope[0][1] + k * z * slope[1][1] for k in (0, -1, 1))
    return r, b


def fmt(t, t_end):
    return "> %g" % t_end if math.isinf(t) else "%.2f" % t


SIGMA_LINE = ("pendulum5", "eigen", "rk4", 0.001)  # the line every sigma plan runs (data/plans/sigma/)


def sigma_table(pairs):
    """One row per ensemble (plan, results): its sigma and, for SIGMA_LINE's runs, the median time beyond
    0.1 rad, P(< the plans' ensemble.claim) and the shipped state's rank, each with its 95 % interval (docs/results.md,
    "The perturbation size")."""
    print("# The perturbation size sigma (%s, %s, %s dt %g)\n" % SIGMA_LINE)
    print("Generated by `python3 tools/ensemble_summary.py --sigma %s` from the sweeps' merged files. A member is "
          "the shipped state with every angle and speed offset by a normal draw of sigma (member 0 unperturbed); "
          "times are when the joint angles leave the reference by 0.1 rad (a member that never leaves counts as "
          "later than t_end). Brackets: 95 %% intervals (the median's from its order statistics, each fraction's "
          "by Wilson's score).\n" % " ".join(pairs))
    rows_out, claims = [], set()
    for plan_path, results in zip(pairs[::2], pairs[1::2]):
        with open(plan_path) as f:
            plan = json.load(f)
        claims.add(claim_of(plan, plan_path)[0])
        sigma = plan["ensemble"]["perturb"]["q"]
        scene, method, integrator, dt = SIGMA_LINE
        rs = [r for r in rows(os.path.join(results, plan["name"] + ".csv")) if r["role"] == "run" and
              r["scene"] == scene and r["method"] == method and r["integrator"] == integrator and
              abs(float(r["setting"]) - dt) < 1e-12]
        if not rs:
            sys.exit("%s: no run of %s, %s, %s dt %g in %s" % (plan_path, scene, method, integrator, dt, results))
        t = [num(r["coord_beyond_1e-1_s"]) for r in rs]
        m0 = [num(r["coord_beyond_1e-1_s"]) for r in rs if r["member"] == "0"]
        others = [num(r["coord_beyond_1e-1_s"]) for r in rs if r["member"] != "0"]
        lo, hi = median_ci(t)
        k_below = sum(1 for x in t if x < claim_of(plan, plan_path)[0])
        k_rank = sum(1 for x in others if x < m0[0])
        t_end = plan["t_end"]
        rows_out.append((sigma, "| %.0e | %d | %s [%s, %s] | %.2f [%.2f, %.2f] | %.2f [%.2f, %.2f] |" % (
            sigma, len(t), fmt(quantile(t, .5), t_end), fmt(lo, t_end), fmt(hi, t_end), k_below / len(t),
            *wilson(k_below, len(t)), k_rank / len(others), *wilson(k_rank, len(others)))))
    if len(claims) != 1:
        sys.exit("the plans' ensemble.claim differ (%s): one table holds one claim" % ", ".join(map(str, sorted(claims))))
    print("| sigma (rad, rad/s) | members | median (s) | P(< %g s) | shipped state later than |" % claims.pop())
    print("|---:|---:|---|---|---|")
    for _, line in sorted(rows_out):
        print(line.replace("e-0", "e-"))


THRESHOLD_KEYS = {0.001: "1e-3", 0.1: "1e-1"}  # the merged CSV's column names (sweep/sweep_report.cpp, beyondKey)
CHECK_REL = 1e-12  # two type-7 interpolations, a + d (b - a) here and GSL's (1 - d) a + d b: last bits apart


def check_ensemble(cases_path, ensemble_path):
    """Recompute every row of eigenmass's <plan>-ensemble.csv (median, quartiles, min, max and the
    median's interval) from the per-case <plan>.csv with this file's statistics; exit 1 naming any
    that differ. Proves both apply one convention."""
    cases = [r for r in rows(cases_path) if r["role"] != "reference"]
    groups = defaultdict(list)
    for r in cases:
        groups[(r["scene"], "reference-horizon" if r["role"] == "check" else r["method"], r["integrator"],
                float(r["setting"]))].append(r)
    checked, bad = 0, []
    same = lambda a, b: a == b or (math.isfinite(a) and math.isfinite(b) and abs(a - b) <= CHECK_REL * max(abs(a), abs(b)))
    ensemble = rows(ensemble_path)
    missing = [k for k in ("median_s", "median_lo_s", "median_hi_s") if ensemble and k not in ensemble[0]]
    if missing:
        sys.exit("%s: no column %s: not an ensemble file of this eigenmass (--merge writes it)" % (ensemble_path, missing[0]))
    for e in ensemble:
        members = groups[(e["scene"], e["method"], e["integrator"], float(e["setting"]))]
        column = "%s_beyond_%s_s" % ("pose" if e["metric"] == "pose" else "coord", THRESHOLD_KEYS[float(e["threshold"])])
        t = [num(r[column]) for r in members]  # "" (never crossed): +inf, censored
        if len(t) != int(e["members"]):
            bad.append("%s: %d members in %s, %s in %s" % (column, len(t), cases_path, e["members"], ensemble_path))
            continue
        lo, hi = median_ci(t)
        mine = {"median_s": quantile(t, .5), "q1_s": quantile(t, .25), "q3_s": quantile(t, .75), "min_s": min(t),
                "max_s": max(t), "median_lo_s": lo, "median_hi_s": hi}
        for k, v in mine.items():
            checked += 1
            if not same(v, float(e[k])):
                bad.append("%s %s %s %s %s %s: %s %r here, %r in %s" % (e["scene"], e["method"], e["setting"], e["metric"],
                                                                       e["threshold"], column, k, v, float(e[k]), ensemble_path))
    for b in bad:
        print(b, file=sys.stderr)
    print("%d statistics of %s recomputed from %s: %d differ" % (checked, ensemble_path, cases_path, len(bad)))
    return 1 if bad or not checked else 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sigma", nargs="+", metavar="PLAN RESULTS", help="pairs of a sigma plan and its results folder")
    ap.add_argument("--check-ensemble", nargs=2, metavar=("CASES_CSV", "ENSEMBLE_CSV"),
                    help="recompute eigenmass's <plan>-ensemble.csv from <plan>.csv; exit 1 where they differ")
    ap.add_argument("plan", nargs="?", help="the ensemble plan (JSON)")
    ap.add_argument("results", nargs="?", help="its merged results folder")
    a = ap.parse_args()
    if a.check_ensemble:
        return check_ensemble(*a.check_ensemble)
    if a.sigma:
        if len(a.sigma) % 2:
            ap.error("--sigma: PLAN RESULTS pairs, got %d values" % len(a.sigma))
        return sigma_table(a.sigma)
    if not (a.plan and a.results):
        ap.error("PLAN and RESULTS are required (or --sigma, or --check-ensemble)")
    plan_path, results = a.plan, a.results
    with open(plan_path) as f:
        plan = json.load(f)
    name, t_end = plan["name"], plan["t_end"]
    claim_s, claim_label = claim_of(plan, plan_path)
    merged = rows(os.path.join(results, name + ".csv"))
    runs = [r for r in merged if r["role"] == "run"]
    groups = defaultdict(list)
    for r in runs:
        groups[(r["scene"], r["method"], float(r["setting"]))].append(r)
    members = len(next(iter(groups.values())))
    print("# The paper's claims as distributions (%s, %d members per scene)\n" % (name, members))
    sigma = plan["ensemble"]["perturb"]
    print("Generated by `python3 tools/ensemble_summary.py %s` from the sweep's merged files. Each member is "
          "pendulum5 (gimbal root) or pendulum5_ball (the same state with the root as a ball) with every angle "
          "and speed offset by a normal draw of sigma = %g rad and %g rad/s (member 0 unperturbed; seed %d), run for "
          "%g s under rk4 and compared with its own Simbody reference (RK-Merson 1e-10). Every median and fraction "
          "below is of these members at this sigma: a distribution over nearby states, whose quantiles move with "
          "sigma (docs/results.md, \"The perturbation size\").\n" % (
              plan_path + " " + results, sigma.get("q", 0), sigma.get("u", 0), plan["ensemble"].get("seed", 1), t_end))
    print("## When the joint angles leave the reference by 0.1 rad\n")
    print("Quantiles over all members; a member that never leaves within %g s counts as later than %g s, and a "
          "failed run as leaving when it stops. `P(< %g s)`: the fraction of members that leave before %s, "
          "i.e. the percentile at which %g s falls. `member 0`: the shipped state itself, and "
          "`its rank`: the fraction of the other members that leave before it. Brackets: 95 %% intervals, the "
          "median's from its order statistics (exact binomial, distribution-free), each fraction's by Wilson's "
          "score (sampling uncertainty of %d members, not of sigma's choice).\n" % (
              t_end, t_end, claim_s, claim_label, claim_s, members))
    print("| scene | method | dt | member 0 | its rank [95 %%] | q1 | median [95 %%] | q3 | left by %g s | failed | P(< %g s) [95 %%] |" % (t_end, claim_s))
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for (scene, method, dt), rs in sorted(groups.items(), key=lambda kv: (kv[0][0], kv[0][1], -kv[0][2])):
        t = [num(r["coord_beyond_1e-1_s"]) for r in rs]
        m0 = [num(r["coord_beyond_1e-1_s"]) for r in rs if r["member"] == "0"]
        left = sum(1 for x in t if not math.isinf(x))
        failed = sum(1 for r in rs if r["status"] != "ok")
        k_below = sum(1 for x in t if x < claim_s)
        below, (b_lo, b_hi) = k_below / len(t), wilson(k_below, len(t))
        lo, hi = median_ci(t)
        rank = "-"
        if m0:
            others = [num(r["coord_beyond_1e-1_s"]) for r in rs if r["member"] != "0"]
            k = sum(1 for x in others if x < m0[0])
            r_lo, r_hi = wilson(k, len(others))
            rank = "%.2f [%.2f, %.2f]" % (k / len(others), r_lo, r_hi)
        print("| %s | %s | %g | %s | %s | %s | %s [%s, %s] | %s | %d / %d | %d | %.2f [%.2f, %.2f] |" % (
            scene, method, dt, fmt(m0[0], t_end) if m0 else "-", rank, fmt(quantile(t, .25), t_end),
            fmt(quantile(t, .5), t_end), fmt(lo, t_end), fmt(hi, t_end), fmt(quantile(t, .75), t_end), left, len(t),
            failed, below, b_lo, b_hi))
    print()
    print("## Which method leaves first, member by member\n")
    print("Fraction of the members in which eigen's joint angles leave the reference by 0.1 rad strictly before "
          "classical's, and before eigen-jacobi's (a member where neither leaves within %g s is a tie, counted "
          "against), with Wilson's 95 %% interval.\n" % t_end)
    print("| scene | dt | eigen before classical [95 %] | eigen before eigen-jacobi [95 %] |")
    print("|---|---:|---:|---:|")
    when = per_member(runs, "coord_beyond_1e-1_s")
    first = defaultdict(lambda: [0, 0, 0])
    for (scene, dt, _), w in when.items():
        if all(k in w for k in ("classical", "eigen", "eigen-jacobi")):
            f = first[(scene, dt)]
            f[0] += 1
            f[1] += w["eigen"] < w["classical"]
            f[2] += w["eigen"] < w["eigen-jacobi"]
    for (scene, dt), (n, c, j) in sorted(first.items(), key=lambda kv: (kv[0][0], -kv[0][1])):
        (c_lo, c_hi), (j_lo, j_hi) = wilson(c, n), wilson(j, n)
        print("| %s | %g | %.2f [%.2f, %.2f] | %.2f [%.2f, %.2f] |" % (scene, dt, c / n, c_lo, c_hi, j / n, j_lo, j_hi))
    print()
    print("## Energy ranking per member\n")
    print("Fraction of members in which the largest relative energy error ranks eigen > eigen-jacobi > classical "
          "(each method up to where it stopped), and in which eigen > classical alone.\n")
    print("| scene | dt | eigen > eigen-jacobi > classical | eigen > classical |")
    print("|---|---:|---:|---:|")
    by_member = per_member(runs, "energy_error_max")
    tally = defaultdict(lambda: [0, 0, 0])
    for (scene, dt, _), e in by_member.items():
        if not all(k in e for k in ("classical", "eigen", "eigen-jacobi")):
            continue
        c = tally[(scene, dt)]
        c[0] += 1
        c[1] += e["eigen"] > e["eigen-jacobi"] > e["classical"]
        c[2] += e["eigen"] > e["classical"]
    for (scene, dt), (n, full, pair) in sorted(tally.items(), key=lambda kv: (kv[0][0], -kv[0][1])):
        print("| %s | %g | %.2f | %.2f |" % (scene, dt, full / n, pair / n))
    print()
    pred_path = os.path.join(results, name + "-prediction.csv")
    if os.path.exists(pred_path):
        print("## Divergence time predicted from the Lyapunov exponent\n")
        print("t_pred = t0 + ln(0.1 rad / e(t0)) / chi, from the run's largest pose error e(t0) up to t0 = %g s "
              "and its member's Lyapunov exponent chi (Benettin twin). Ratio measured / predicted (pose, 0.1 rad) over "
              "the members with both; `chi` is the median exponent of the scene's members.\n" % (t_end / 10))
        pred = [p for p in rows(pred_path) if float(p["threshold"]) == 0.1]
        lam = defaultdict(list)
        for p in pred:
            lam[p["scene"]].append(float(p["lyapunov_per_s"]))
        ratio = defaultdict(list)  # the uncensored members' measured / predicted
        pairs = defaultdict(list)  # (predicted, measured or None: still within 0.1 rad at t_end)
        count = defaultdict(int)
        for p in pred:
            k = (p["scene"], p["method"], float(p["setting"]))
            count[k] += 1
            if not p["predicted_s"]:
                continue
            measured = float(p["measured_s"]) if p["measured_s"] else None
            pairs[k].append((float(p["predicted_s"]), measured))
            if measured is not None:
                ratio[k].append(measured / float(p["predicted_s"]))
        print("Members that never leave within %g s are censored: their time is only known to exceed %g s. The naive "
              "columns drop them, which biases the ratio low wherever many are censored (small steps). The censored "
              "regression keeps them (Tobit, i.e. a log-normal accelerated-failure-time fit: log T = a + b log P + s e, "
              "T right-censored at %g s, the same point for every member, so not informative given P): `ratio` is "
              "exp(a) with b held at 1, the median of measured / predicted; `slope` is b fitted, 1 where the ratio does "
              "not move with the prediction. Brackets: 95 %% Wald intervals. `-`: the fit does not converge.\n" % (
                  t_end, t_end, t_end))
        print("| scene | chi (1/s) | method | dt | predicted | censored | naive: median [q1, q3] of the uncensored | "
              "censored regression: ratio [95 %] | slope [95 %] |")
        print("|---|---:|---|---:|---:|---:|---|---|---|")
        for k in sorted(count, key=lambda k: (k[0], k[1], -k[2])):
            x = ratio[k]
            q = (lambda p: "%.2f" % quantile(x, p)) if x else (lambda p: "-")
            r, b = ratio_fits(pairs[k], t_end)
            print("| %s | %.2f | %s | %g | %d / %d | %d | %s [%s, %s] | %s | %s |" % (
                k[0], quantile(lam[k[0]], .5), k[1], k[2], len(pairs[k]), count[k], len(pairs[k]) - len(x), q(.5), q(.25),
                q(.75), r, b))
        print()


if __name__ == "__main__":
    sys.exit(main())
