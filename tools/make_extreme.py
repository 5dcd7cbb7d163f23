#!/usr/bin/env python3
"""Writes the extreme-case gallery, data/scenes/extreme/ (docs/extreme.md):
one scene per hard case, each with a one-line `x-why` (what it stresses) and
an `x-extreme` block (the runs `eigenmass extreme` makes of it).

Run from the project root: python3 tools/make_extreme.py. The tuned numbers
(the near-crossing's inertia, the gimbal's launch rate, the spring constants)
are derived here, in closed form, and said where they are set.
"""
import copy, json, math, os, sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from make_scenes import ROD, GIMBAL, ball_equivalent, chain, scene, write  # noqa: E402
import make_mechanisms  # noqa: E402

OUT = "data/scenes/extreme"
G = 9.81
RUNS = ["rk4:1e-3", "rk8pd:1e-10"]  # the two settings every case is run under


def case(name, bodies, why, t_end=10.0, runs=RUNS, gravity=(0, 0, -G), **extreme):
    doc = scene(name, bodies, t_end)
    doc["gravity"] = list(gravity)
    doc = {"format": doc["format"], "name": name, "x-why": why, **doc}
    doc["x-extreme"] = {"runs": runs, **extreme}
    return doc


def rod(mass, length=1.0, axial_ratio=None):
    """A slender rod along z: transverse m l^2 / 12 (+ a small radius term as ROD), axial ROD's or a ratio of it."""
    transverse = ROD["inertia"][0] * mass * length ** 2
    axial = ROD["inertia"][2] * mass if axial_ratio is None else axial_ratio * transverse
    return {"mass": mass, "inertia": [transverse, transverse, axial]}


def near_crossing():
    """Two links, parallel x axes, no gravity. With l1 = 1, link 2's CM a2 = 0.7
    from its joint, A = [[J1 + m2 l1^2 + 2 b c + K2, K2 + b c], [K2 + b c, K2]]
    (c = cos q2, b = m2 l1 a2, J1 = link 1 about its joint, K2 = link 2 about
    its joint): the two eigenvalues meet exactly when K2 = (J1 + m2 l1^2) / 2, at
    cos q2 = -K2 / b. K2 is set eps above that, which leaves a smallest gap of
    exactly sqrt(2) eps = 1e-6 kg m^2 (near q2 = +-2.40 rad, where lambda = 0.517)."""
    m1, m2, a2 = 0.1, 1.0, 0.7
    I1 = m1 / 12.0                      # thin rod of length 1 about its CM
    J1 = I1 + m1 * 0.25                 # about its joint (CM 0.5 away)
    K2 = (J1 + m2 * 1.0) / 2 + 1e-6 / math.sqrt(2)
    I2 = K2 - m2 * a2 ** 2              # link 2 about its CM, transverse
    q2 = 1.0
    A11 = J1 + m2 + 2 * m2 * a2 * math.cos(q2) + K2
    A12 = K2 + m2 * a2 * math.cos(q2)
    u2 = 1.0
    u1 = -A12 * u2 / A11                # zero angular momentum: q2 turns steadily through both near-crossings
    l1 = {"name": "link1", "parent": "ground", "mass": m1, "inertia": [I1, I1, 1e-4],
          "joint": {"type": "revolute", "axis": [1, 0, 0], "in_parent": [0, 0, 0], "in_body": [0, 0, 0.5],
                    "q0": [0.0], "u0": [u1]}}
    l2 = {"name": "link2", "parent": "link1", "mass": m2, "inertia": [I2, I2, 1e-3],
          "joint": {"type": "revolute", "axis": [1, 0, 0], "in_parent": [0, 0, -0.5], "in_body": [0, 0, a2],
                    "q0": [q2], "u0": [u2]}}
    return case("near_crossing", [l1, l2],
                "Two links tuned (tools/make_extreme.py) so that A's two eigenvalues pass within 1e-6 kg m^2 of "
                "each other twice per turn of the elbow: eigenfactor rates grow as 1/gap.",
                gravity=(0, 0, 0))


def scaled_chain(name, factors, why):
    bodies = chain(len(factors), dict(GIMBAL))
    for b, f in zip(bodies, factors):
        b.update(rod(f))
    return case(name, bodies, why)


def thin_rods():
    bodies = chain(5, dict(GIMBAL))
    for b in bodies:
        b.update(rod(1.0, axial_ratio=1e-9))
    tip = bodies[-1]["joint"]
    bodies[-1]["joint"] = {"type": "ball", "in_parent": tip["in_parent"], "in_body": tip["in_body"],
                           "q0": [math.cos(0.25), math.sin(0.25), 0, 0], "u0": [0.3, -0.2, 0.5]}
    # u' carries round-off of eps cond(A) ~ 1e-4: rk8pd cannot meet 1e-10 (it
    # took 2e5-3e6 steps per simulated second, eigen-block 248 CPU-s for 1 s),
    # nor can the horizon run meet 1e-12 (Simbody, 120 CPU-s for 1 s).
    return case("thin_rods", bodies, t_end=2.0, runs=["rk4:1e-3", "rk8pd:1e-6"], reference_tol=1e-9, why=
                "Pendulum5 with rods whose axial inertia is 1e-9 of the transverse one and a ball joint at the "
                "tip: the tip's spin about its own axis is almost massless, cond(A) ~ 1e12.")


def gimbal_chain(root, name, why):
    """Two rods swinging about y from the bottom (link 2's axis is y too), with a
    small out-of-plane motion."""
    bodies = chain(2, dict(root))
    bodies[1]["joint"]["axis"] = [0, 1, 0]
    bodies[1]["joint"]["q0"] = [0.0]
    bodies[1]["joint"]["u0"] = [0.0]
    return case(name, bodies, why, t_end=5.0)


def gimbal_root(e):
    """Launched at 6 rad/s about the middle axis, enough to swing over the top:
    the middle angle then turns back short of pi/2, by a distance that the
    out-of-plane rates e set."""
    return {"type": "gimbal", "in_parent": [0, 0, 0], "in_body": [0, 0, 0.5], "q0": [0.0, 0.0, 0.0],
            "u0": [e, 6.0, e]}


# Out-of-plane rate found by bisection on a tight classical run
# (python3 tools/make_extreme.py --tune-gimbal) so that the middle angle's
# first peak is pi/2 - 5e-4.
GIMBAL_E = 0.00268746


def stiff(name, damped):
    """Three rods on x revolutes with joint springs of natural frequency
    ~3000 rad/s against a pendulum frequency of ~3 rad/s: rk4 at dt 1e-3 is
    stable only for omega dt < 2.79, here ~3. It is the ratio that matters:
    a larger k only makes the explicit reference slower (a 1e9 spring took
    Simbody 15 CPU-minutes for 0.5 s)."""
    bodies = chain(3, {"type": "revolute", "axis": [1, 0, 0], "in_parent": [0, 0, 0], "in_body": [0, 0, 0.5],
                       "q0": [0.4], "u0": [0.0]})
    k = 3000.0 ** 2 * (ROD["inertia"][0] + 0.25)   # omega^2 times a rod's inertia about its end
    c = 2 * math.sqrt(k * (ROD["inertia"][0] + 0.25)) if damped else 0.0  # critical damping of one joint
    for b in bodies:
        b["joint"]["axis"] = [1, 0, 0]
        b["joint"]["spring"] = {"k": round(k, 3), "c": round(c, 6), "q_rest": b["joint"]["q0"]}
    why = ("Joint springs 1e3 times faster than the pendulum (omega ~3000 rad/s"
           + (", critically damped" if damped else ", undamped")
           + "): rk4 steps above ~9e-4 s are unstable; the implicit bsimp is not bound by it.")
    return case(name, bodies, why, t_end=1.0, runs=RUNS + ["bsimp:1e-8"])


def fast_spin():
    arm = {"type": "gimbal", "in_parent": [0, 0, 0], "in_body": [0, 0, 0.5], "q0": [0.4, 0.2, 0.0],
           "u0": [0.0, 0.0, 0.0]}
    bodies = chain(2, arm)
    bodies[1].update({"name": "rotor", "mass": 1.0, "inertia": [0.0125, 0.0125, 0.025]})  # disk, radius ~0.22 m
    bodies[1]["joint"].update({"axis": [0, 0, 1], "in_parent": [0, 0, -0.5], "in_body": [0, 0, 0], "q0": [0.0],
                               "u0": [100.0]})
    return case("fast_spin", bodies,
                "A rotor spinning at 100 rad/s about its own axis at the end of a gimbal-rooted rod: strong "
                "gyroscopic coupling, 0.1 rad of spin per 1e-3 s step.")


def floating_chain():
    """Six rods on a free root in zero gravity, started tumbling: A depends on
    the free root's rotation only through the rods' relative angles; momentum
    is conserved (the slides' invariants)."""
    root = {"type": "free", "in_parent": [0, 0, 0], "in_body": [0, 0, 0.5],
            "q0": [0, 0, 0, 1, 0, 0, 0], "u0": [0.1, 0.0, 0.05, 0.3, -0.2, 0.5]}
    return case("floating_chain", chain(6, root),
                "Six rods on a free joint in zero gravity (a space tether), tumbling: six free speeds beside five "
                "revolute ones; linear and angular momentum are conserved.", gravity=(0, 0, 0))


def long_slider():
    """A carriage sliding down a 30 degree incline (prismatic), launched at
    20 m/s, carrying a double pendulum: after 10 s it is ~445 m away, so the
    joint points' coordinates carry 400 m beside 1 m levers."""
    c, s_ = math.cos(math.radians(30)), math.sin(math.radians(30))
    cart = {"name": "carriage", "parent": "ground", "mass": 5.0, "inertia": [0.2, 0.3, 0.4],
            "joint": {"type": "prismatic", "axis": [c, 0, -s_], "in_parent": [0, 0, 0], "in_body": [0, 0, 0],
                      "q0": [0.0], "u0": [20.0]}}
    bodies = [cart]
    for i in (1, 2):
        bodies.append({"name": "link%d" % i, "parent": "carriage" if i == 1 else "link1", **ROD,
                       "joint": {"type": "revolute", "axis": [0, 1, 0],
                                 "in_parent": [0, 0, 0] if i == 1 else [0, 0, -0.5], "in_body": [0, 0, 0.5],
                                 "q0": [0.8 if i == 1 else -0.4], "u0": [0.0]}})
    return case("long_slider", bodies,
                "A carriage launched at 20 m/s down a 30 degree incline (prismatic) with a double pendulum on it: "
                "~445 m of travel in 10 s beside 1 m links.")


def copy_scene(path, name, why, t_end=None, **extreme):
    doc = json.load(open(path))
    doc["name"] = name
    out = case(name, doc["bodies"], why, t_end or doc["simulate"]["t_end"], **extreme)
    out["gravity"] = doc["gravity"]
    return out


def mechanism_case(doc, name, why, t_end, **extreme):
    """A shipped mechanism (tools/make_mechanisms.py) as a gallery case: its loops kept."""
    out = case(name, doc["bodies"], why, t_end, gravity=doc["gravity"], **extreme)
    out["loops"] = doc["loops"]
    return out


def main():
    os.makedirs(OUT, exist_ok=True)
    falling = [1.0, 1e-4, 1e-8]
    docs = [
        near_crossing(),
        copy_scene("data/scenes/chain20.json", "chain20",
                   "Twenty links: eigenvalues of A nearly cross again and again (gaps below 1e-4 within 2 s)."),
        copy_scene("data/scenes/chain50.json", "chain50",
                   "Fifty links: dense near-crossings from the start; the dense N^3 eigenfactor products grow."),
        scaled_chain("mass_falling", falling,
                     "A gimbal-rooted three-rod chain whose masses fall by 1e4 per link (1, 1e-4, 1e-8 kg): cond(A) > 1e8."),
        scaled_chain("mass_rising", falling[::-1],
                     "The same chain with masses rising by 1e4 per link (1e-8, 1e-4, 1 kg): a nearly massless root "
                     "under heavy links."),
        thin_rods(),
        gimbal_chain(gimbal_root(GIMBAL_E), "gimbal_lock",
                     "A gimbal-rooted double pendulum whose middle gimbal angle turns back 5e-4 rad short of "
                     "pi/2 (tuned): A is nearly singular there."),
        gimbal_chain(ball_equivalent(gimbal_root(GIMBAL_E)), "gimbal_lock_ball",
                     "Control for gimbal_lock: the same motion with a ball root, which has no singular angle."),
        stiff("stiff_springs", damped=False),
        stiff("stiff_springs_damped", damped=True),
        fast_spin(),
        copy_scene("data/bench/chain100.json", "chain100",
                   "A hundred links for 10 s: size (N = 102) and near-crossings together.",
                   runs=["rk4:1e-3"]),  # under rk8pd 1e-10 one eigen-jacobi run alone exceeds 10 CPU-minutes
        floating_chain(),
        long_slider(),
        copy_scene("data/scenes/pendulum5.json", "long_horizon",
                   "Pendulum5 for 1000 s: far beyond the reference horizon (chaos), so only energy drift and "
                   "failures count.", t_end=1000.0, runs=["rk4:1e-3"], reference_tol=1e-8),
        mechanism_case(make_mechanisms.a02(2), "singular_fourbars",
                       "IFToMM A02 with N = 2: at 0.714 s and 1.228 s the cranks lie along the ground line and the "
                       "closures lose rank (1 to 3 degrees of freedom); ida's rows, chosen once, stop at the first, so "
                       "the reference is rk8pd with the projection.", 2.0, reference_integrator="rk8pd",
                       reference_tol=1e-12),
        mechanism_case(make_mechanisms.a04(), "redundant_bricard",
                       "Bricard's linkage (IFToMM A04): 5 coordinates, a hinge closure of 5 equations of rank 4 at every "
                       "position, one degree of freedom Grubler does not count: redundant rows.", 2.0),
    ]
    for d in docs:
        write(os.path.join(OUT, d["name"] + ".json"), d)


def first_peak(w, binary="build/bin/eigenmass"):
    """First maximum of the root gimbal's middle angle, from a tight classical run."""
    import csv, subprocess, tempfile
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "g.json")
        write(path, gimbal_chain(gimbal_root(w), "tune", ""))
        out = os.path.join(d, "g.csv")
        subprocess.run([binary, "simulate", path, "--method", "classical", "--integrator", "rk8pd", "--tol", "1e-12",
                        "--t-end", "2", "--output-dt", "1e-4", "--out", out, "--no-progress"], check=True,
                       stdout=subprocess.DEVNULL)
        rows = list(csv.DictReader(open(out)))
    q1 = [float(r["link1.q1"]) for r in rows]
    for a, b, c in zip(q1, q1[1:], q1[2:]):
        if b >= a and b >= c:
            return b
    return max(q1)


def tune_gimbal():
    """Bisection on the out-of-plane rate for a first peak of pi/2 - 5e-4."""
    lo, hi, target = 1e-4, 0.02, math.pi / 2 - 5e-4
    for _ in range(20):
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if first_peak(mid) > target else (lo, mid)
    print("GIMBAL_E = %.6g: first peak pi/2 - %.3e" % (lo, math.pi / 2 - first_peak(lo)))


if __name__ == "__main__":
    tune_gimbal() if "--tune-gimbal" in sys.argv else main()
