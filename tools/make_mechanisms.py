#!/usr/bin/python3
"""Writes IFToMM's benchmark problems A01, A02, A04 and A05 as eigenmass scenes
(data/scenes/mechanisms/): the numbers are the library's specifications
(González, Dopico, Lugrís and Cuadrado; library of computational benchmark
problems for multibody system dynamics, problems A01, A02, A04 and A05)."""
import json
import math
import os
import re
import sys

import numpy as np
from scipy.integrate import solve_ivp
from scipy.special import ellipj, ellipk

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data", "scenes", "mechanisms")
ROD = 1.0 / 12.0  # a uniform 1 kg, 1 m rod about its CM, kg m^2
THIN = 1e-6       # its moment about its own axis: any small value, the motion is planar about z


def rod(name, parent, in_parent, q0, u0):
    return {"name": name, "parent": parent, "mass": 1.0, "inertia": [THIN, ROD, ROD],
            "joint": {"type": "revolute", "axis": [0, 0, 1], "in_parent": in_parent, "in_body": [-0.5, 0, 0],
                      "q0": [q0], "u0": [u0]}}


LEVELS_UNKNOWN = ("its precision levels were not reachable here: eigenmass uses A02's, 1e-1 and 1e-3 m, which its "
                  "specification states for links of the same 1 m")


def a02(n, t_end=20.0, output_dt=0.05):
    """N four-bars in a row: N+1 cranks of 1 m, 1 kg from the ground points (i, 0),
    vertical at the start; N couplers of 1 m, 1 kg joining their tips; B0 (the
    first crank's tip) moves at 1 m/s along x. Each coupler hangs from the tip
    of the crank before it and is closed on the next crank's tip by a ball."""
    bodies, loops = [], []
    for i in range(n + 1):
        bodies.append(rod("crank%d" % i, "ground", [float(i), 0, 0], math.pi / 2, -1.0))
    for i in range(1, n + 1):
        bodies.append(rod("coupler%d" % i, "crank%d" % (i - 1), [0.5, 0, 0], -math.pi / 2, 1.0))
        loops.append({"name": "B%d" % i, "type": "ball", "body_a": "coupler%d" % i, "point_a": [0.5, 0, 0],
                      "body_b": "crank%d" % i, "point_b": [0.5, 0, 0]})
    return {
        "format": "eigenmass-scene/1", "name": "iftomm_a02_n%d" % n,
        "x-comment": "IFToMM benchmark A02, the N four-bar mechanism, N = %d: %d cranks and %d couplers, every link a "
                     "uniform 1 m, 1 kg rod; gravity 9.81 m/s^2 along -y; at the start the cranks stand vertical and B0 "
                     "moves at 1 m/s along +x (every crank turns at -1 rad/s, the couplers translate). Where the cranks "
                     "lie along the ground line (every half turn) the closures lose rank: the degrees of freedom jump "
                     "from 1 to N+1, and a formulation must pass through on the branch where the cranks stay parallel." % (n, n + 1, n),
        "x-source": "Specification of problem A02 (IFToMM library of computational benchmark problems; Gonzalez, Dopico, "
                    "Lugris, Cuadrado, Multibody System Dynamics 16 (2006) 179-190): N = 40, L = 1 m, m = 1 kg per link, "
                    "g = 9.81, B0's initial x-velocity 1 m/s, 20 s; its error measure is B0's x over 400 output steps at "
                    "the precision levels 1e-1 and 1e-3 m. Written by tools/make_mechanisms.py.",
        "gravity": [0, -9.81, 0], "bodies": bodies, "loops": loops,
        "simulate": {"t_end": t_end, "output_dt": output_dt},
        "benchmark": {"problem": "A02" if n == 40 else "A02-N%d" % n,
                      "measure": [{"name": "B0_x", "body": "crank0", "point": [0.5, 0, 0], "axis": "x"}],
                      "t_end": 20.0, "outputs": 400, "levels": [1e-1, 1e-3],
                      "x-source": "A02's specification: B0 (the first crank's tip)'s x over 400 output steps of 20 s, "
                                  "precision levels 1e-1 and 1e-3 m" + ("" if n == 40 else "; N = %d is eigenmass's small "
                                  "variant of the problem (the specification's N is 40)" % n) + ".",
                      "solution": a02_solution(n),
                      "x-solution": "B0's x on the parallel branch, where every crank turns by the same angle psi: "
                                    "M psi'' = -b cos psi with M = (N+1)/3 + N and b = g ((N+1)/2 + N), integrated by "
                                    "SciPy's DOP853 at 3e-14 (within 1e-9 m of its run at 1e-13; docs/theory.md §15, "
                                    "A02's parallel branch); eigenmass's stand-in for the specification's reference file, "
                                    "not reachable here. Written by tools/make_mechanisms.py."}}


def a02_solution(n, t_end=20.0, outputs=400):
    """B0's x on A02's parallel branch (docs/theory.md §15, "A02's parallel branch"): every crank
    turns by the same psi and every coupler translates with the cranks' tips, so with
    M = (N+1)/3 + N (kg m^2: N+1 cranks about their pivots, N couplers moving at psi' L) and
    b = g ((N+1)/2 + N) (the potential b sin psi), M psi'' = -b cos psi; B0's x = cos psi.
    Integrated by SciPy's DOP853 at rtol = atol = 3e-14 (its floor): within 1e-9 m of its run at
    1e-13, which is itself 1e-9 m from the run at 1e-12 (so the error is ~1e-10 m), and the
    energy conserved to 1e-12 relative."""
    g, m_eq = 9.81, (n + 1) / 3.0 + n
    b = g * ((n + 1) / 2.0 + n)
    t = np.arange(1, outputs + 1) * (t_end / outputs)
    def solve(tol):
        s = solve_ivp(lambda _, y: [y[1], -(b / m_eq) * math.cos(y[0])], (0.0, t_end), [math.pi / 2, -1.0],
                      method="DOP853", rtol=tol, atol=tol, t_eval=t)
        assert s.success
        return s.y
    y, coarse = solve(3e-14), solve(1e-13)
    energy = 0.5 * m_eq * y[1] ** 2 + b * np.sin(y[0])
    assert np.max(np.abs(np.cos(y[0]) - np.cos(coarse[0]))) < 1e-9
    assert np.max(np.abs(energy - (0.5 * m_eq + b))) < 1e-12 * (0.5 * m_eq + b)
    return [[float(x)] for x in np.cos(y[0])]


def a01_solution(t_end=2000.0, outputs=4000):
    """The mass's x and y in closed form: the pendulum released at rest from theta0 = pi/2
    (theta from the downward vertical) swings as sin(theta/2) = k sn(K(k) - w t, k),
    cos(theta/2) = dn(K(k) - w t, k), k = sin(theta0 / 2), w^2 = m g L / (m L^2 + I), with
    the scene's own I = 1e-9 kg m^2 about the mass's CM (it slows the ideal pendulum by 5e-10
    relative: 3e-6 m over 2000 s); x = sin theta, y = -cos theta (SciPy's ellipj, ellipk)."""
    g, m, L, inertia = 9.81, 1.0, 1.0, 1e-9
    w = math.sqrt(m * g * L / (m * L * L + inertia))
    k2 = 0.5  # k^2 = sin(pi/4)^2
    t = np.arange(1, outputs + 1) * (t_end / outputs)
    sn, _, dn, _ = ellipj(ellipk(k2) - w * t, k2)
    k = math.sqrt(k2)
    return [[float(2 * k * a * d), float(-(1 - 2 * k2 * a * a))] for a, d in zip(sn, dn)]


def a01():
    """A 1 kg point mass on a massless 1 m link, released at rest from the horizontal."""
    return {
        "format": "eigenmass-scene/1", "name": "iftomm_a01",
        "x-comment": "IFToMM benchmark A01, the simple pendulum: a point mass of 1 kg on a massless link of 1 m, released "
                     "at rest with the link horizontal (the mass at x = +1 m), gravity 9.81 m/s^2 along -y, 2000 s. A tree: "
                     "the revolute joint at the origin. The point mass is a body with a vanishing inertia about its CM "
                     "(1e-9 kg m^2 about every axis: 1e-9 of m L^2).",
        "x-source": "Specification of problem A01 (IFToMM library; Gonzalez, Dopico, Lugris, Cuadrado 2006): m = 1 kg, "
                    "L = 1 m, g = 9.81, x0 = (1, 0) at rest, 2000 s; its error measure is the mass's x and y.",
        "gravity": [0, -9.81, 0],
        "bodies": [{"name": "mass", "parent": "ground", "mass": 1.0, "inertia": [1e-9, 1e-9, 1e-9],
                    "joint": {"type": "revolute", "axis": [0, 0, 1], "in_parent": [0, 0, 0], "in_body": [-1.0, 0, 0],
                              "q0": [0.0], "u0": [0.0]}}],
        "simulate": {"t_end": 2000, "output_dt": 0.01},
        "benchmark": {"problem": "A01",
                      "measure": [{"name": "P1_x", "body": "mass", "point": [0, 0, 0], "axis": "x"},
                                  {"name": "P1_y", "body": "mass", "point": [0, 0, 0], "axis": "y"}],
                      "t_end": 2000, "outputs": 4000, "levels": [1e-1, 1e-3],
                      "x-source": "A01's specification (lim.ii.udc.es/mbsbenchmark/dist/A01/A01_specification.xml): the "
                                  "mass's x and y over 2000 s, maximum errors 1e-1 (low precision) and 1e-3 (high), "
                                  "measured with 4000 output steps and a threshold value of 1e-3. eigenmass measures "
                                  "the largest absolute gap of x and y at those 4000 steps; how the specification's "
                                  "error formula uses its threshold was not reachable here, so the threshold is not applied.",
                      "solution": a01_solution(),
                      "x-solution": "The mass's x and y in closed form (Jacobi's elliptic functions, SciPy's ellipj): "
                                    "sin(theta/2) = k sn(K - w t, k), k = sin(pi/4), w^2 = m g L / (m L^2 + I) with the "
                                    "scene's I = 1e-9 kg m^2 (the ideal point mass's pendulum lies 3e-6 m from it at "
                                    "2000 s). Written by tools/make_mechanisms.py."}}


def bar(name, parent, along, in_parent, in_body, axis):
    """A uniform 1 m, 1 kg bar of square section 0.1 m along body axis `along`
    (0, 1, 2), hinged on `axis`; every frame is the world's at q = 0."""
    side, length = 0.1, 1.0
    inertia = [(length ** 2 + side ** 2) / 12.0] * 3
    inertia[along] = 2 * side ** 2 / 12.0
    return {"name": name, "parent": parent, "mass": 1.0, "inertia": inertia,
            "joint": {"type": "revolute", "axis": axis, "in_parent": in_parent, "in_body": in_body,
                      "q0": [0.0], "u0": [0.0]}}


def a04(t_end=10.0, output_dt=0.01):
    """Bricard's linkage: five bars O1-P1 (x), P1-P2 (-y), P2-P3 (z), P3-P4 (-x),
    P4-O2 (+y) between the ground points O1 = (0,0,0) and O2 = (0,0,1), each
    hinge's axis square to both bars it joins; the fifth bar is hinged to the
    ground at O2 on x by a closure: 5 coordinates, 5 closure equations, rank 4."""
    bodies = [
        bar("bar1", "ground", 0, [0, 0, 0], [-0.5, 0, 0], [0, 1, 0]),
        bar("bar2", "bar1", 1, [0.5, 0, 0], [0, 0.5, 0], [0, 0, 1]),
        bar("bar3", "bar2", 2, [0, -0.5, 0], [0, 0, -0.5], [1, 0, 0]),
        bar("bar4", "bar3", 0, [0, 0, 0.5], [0.5, 0, 0], [0, 1, 0]),
        bar("bar5", "bar4", 1, [-0.5, 0, 0], [0, -0.5, 0], [0, 0, 1]),
    ]
    loops = [{"name": "O2", "type": "hinge", "body_a": "bar5", "point_a": [0, 0.5, 0], "body_b": "ground",
              "point_b": [0, 0, 1], "axis_a": [1, 0, 0], "axis_b": [1, 0, 0]}]
    return {
        "format": "eigenmass-scene/1", "name": "iftomm_a04",
        "x-comment": "IFToMM benchmark A04, Bricard's overconstrained linkage: five bars of 1 m, 1 kg, square section "
                     "0.1 m, six revolute pairs, each axis square to the two bars it joins; O1 = (0,0,0), P1 = (1,0,0), "
                     "P2 = (1,-1,0), P3 = (1,-1,1), P4 = (0,-1,1), O2 = (0,0,1); gravity 9.81 m/s^2 along -y; released "
                     "at rest. Grubler counts 0 degrees of freedom, it has 1: the hinge closure's 5 equations have rank 4 "
                     "at every position, which a formulation must handle as redundant.",
        "x-source": "Specification of problem A04 (IFToMM library; Gonzalez, Dopico, Lugris, Cuadrado 2006): bars 1 m, "
                    "1 kg, section 0.1 m, gravity along -y; the geometry and the start at rest as the OpenSim port builds it "
                    "(RehabEngGroup/MBSbenchmarksInOpenSim, src/A04-BricardsMechanism: pin axes y, z, x, y, z, x, no initial "
                    "speed), its horizon 10 s as that port runs it (the specification's own horizon and error point P3 "
                    "were not reachable here). Written by tools/make_mechanisms.py.",
        "gravity": [0, -9.81, 0], "bodies": bodies, "loops": loops,
        "simulate": {"t_end": t_end, "output_dt": output_dt},
        "benchmark": {"problem": "A04",
                      "measure": [{"name": "P3_%s" % a, "body": "bar3", "point": [0, 0, 0.5], "axis": a} for a in "xyz"],
                      "t_end": 10.0, "outputs": 1000, "levels": [1e-1, 1e-3],
                      "x-source": "A04's error point P3 (the OpenSim port compares its displacements), at (1, -1, 1) at "
                                  "the start: bar3's end; its x, y and z every 0.01 s of the port's 10 s (the "
                                  "specification's horizon and output steps were not reachable here); " + LEVELS_UNKNOWN + "."}}


def brick(mass, hx, hy, hz):
    """Principal moments of a uniform box of half-sides hx, hy, hz about its CM."""
    return [mass * (hy ** 2 + hz ** 2) / 3, mass * (hx ** 2 + hz ** 2) / 3, mass * (hx ** 2 + hy ** 2) / 3]


def a05(t_end=10.0, output_dt=0.01):
    """The stiff flyball governor, z up: a shaft turning about z on the ground
    at 2 pi rad/s; a slider on it (s = 0.5 m up); two rods hinged at the
    shaft's top, 0.05 m either side, each with a 5 kg point mass welded at its
    far end and a stiff spring-damper from the slider's side to its middle.
    A tree: the point springs are its only force elements besides gravity."""
    rho, point = 3000.0, 5.0
    bar = rho * 1.0 * 0.01 * 0.01                      # 0.3 kg: 1 m x 0.01 m x 0.01 m
    slider = rho * 0.1 ** 3                            # 3 kg: a 0.1 m cube
    bar_inertia = brick(bar, 0.005, 0.005, 0.5)        # about its CM, long axis z
    # A rod with its point mass at its tip (0.5 m from its middle) is one rigid
    # body: mass 5.3 kg, CM c = 5 * 0.5 / 5.3 from the middle toward the tip,
    # moments about that CM by the parallel-axis theorem (the point mass adds
    # nothing about the rod's own axis).
    rod_mass = bar + point
    c = point * 0.5 / rod_mass
    shift = bar * c ** 2 + point * (0.5 - c) ** 2
    rod_inertia = [bar_inertia[0] + shift, bar_inertia[1] + shift, bar_inertia[2]]
    tilt = 2 * math.pi / 3  # each rod from pointing up to 30 degrees below the horizontal, outward
    bodies = [
        {"name": "shaft", "parent": "ground", "mass": bar, "inertia": bar_inertia,
         "joint": {"type": "revolute", "axis": [0, 0, 1], "in_parent": [0, 0, 0], "in_body": [0, 0, -0.5],
                   "q0": [0.0], "u0": [2 * math.pi]}},
        {"name": "slider", "parent": "shaft", "mass": slider, "inertia": brick(slider, 0.05, 0.05, 0.05),
         "joint": {"type": "prismatic", "axis": [0, 0, 1], "in_parent": [0, 0, -0.5], "in_body": [0, 0, 0],
                   "q0": [0.5], "u0": [0.0]}},
    ]
    for name, side, sign in (("rod1", 0.05, 1.0), ("rod2", -0.05, -1.0)):
        bodies.append({"name": name, "parent": "shaft", "mass": rod_mass, "inertia": rod_inertia,
                       "joint": {"type": "revolute", "axis": [0, 1, 0], "in_parent": [side, 0, 0.5],
                                 "in_body": [0, 0, -0.5 - c], "q0": [sign * tilt], "u0": [0.0]}})
    forces = [{"name": "spring%d" % i, "type": "spring", "body_a": "slider", "point_a": [side, 0, 0], "body_b": rod,
               "point_b": [0, 0, -c], "k": 8e5, "c": 4e4, "length": 0.5}
              for i, (rod, side) in enumerate((("rod1", 0.05), ("rod2", -0.05)), start=1)]
    return {
        "format": "eigenmass-scene/1", "name": "iftomm_a05",
        "x-comment": "IFToMM benchmark A05, the stiff flyball governor (z up here): a shaft (1 x 0.01 x 0.01 m, "
                     "3000 kg/m^3: 0.3 kg) turning about the vertical at 2 pi rad/s; a slider (0.1 m cube, 3 kg) on it at "
                     "s = 0.5 m; two rods like the shaft hinged at its top 0.05 m either side, 30 degrees below the "
                     "horizontal, each with a 5 kg point mass at its end (rod and mass are one body here: 5.3 kg, CM 0.4717 m "
                     "from the rod's middle, moments by the parallel-axis theorem); two spring-dampers (k = 8e5 N/m, "
                     "c = 4e4 N s/m, rest length 0.5 m, at rest at the start) from the slider's sides (+-0.05 m) to the "
                     "rods' middles. Stiff: the springs' time constant c/k = 0.05 s against the spin of 1 s.",
        "x-source": "Specification of problem A05 (IFToMM library; Gonzalez, Dopico, Lugris, Cuadrado 2006) as tabled by "
                    "the OpenSim port (RehabEngGroup/MBSbenchmarksInOpenSim, help/benchmarks/A05_FlyballGovernor.rst and "
                    "src/A05-FlyballGovernor: dimensions, density, point masses, K, C, rest length, s = 0.5 m, "
                    "alpha = 30 degrees, 2 pi rad/s; the pins at (+-0.05, 0, 0.5) on the shaft, the springs from "
                    "(+-0.05, 0, 0) on the slider to the rods' CMs); the error measure is the slider's s; the horizon "
                    "10 s as that port reports it (its parameter file runs 350 s; the specification's own horizon was "
                    "not reachable here). Written by tools/make_mechanisms.py.",
        "gravity": [0, 0, -9.81], "bodies": bodies, "forces": forces,
        "simulate": {"t_end": t_end, "output_dt": output_dt},
        "benchmark": {"problem": "A05",
                      "measure": [{"name": "s", "body": "slider", "point": [0, 0, 0], "axis": "z"}],
                      "t_end": 10.0, "outputs": 1000, "levels": [1e-3, 1e-5],
                      "x-source": "A05's error measure, the slider's s (its height: s less a constant), every 0.01 s of "
                                  "the port's 10 s; the specification's levels were not reachable here: eigenmass uses "
                                  "1e-3 and 1e-5 m, the slider moving by centimetres."}}


def write(doc):
    path = os.path.join(OUT, doc["name"] + ".json")
    text = json.dumps(doc, indent=1)
    # A row of a solution (a list of numbers) on one line.
    text = re.sub(r"\[\s*(-?[0-9][^\[\]{}]*?)\s*\]", lambda m: "[" + re.sub(r"\s+", "", m.group(1)).replace(",", ", ") + "]", text)
    with open(path, "w") as f:
        f.write(text + "\n")
    print(path)


if __name__ == "__main__":
    write(a01())
    write(a02(40))
    write(a02(2))
    write(a04())
    write(a05())
    sys.exit(0)
