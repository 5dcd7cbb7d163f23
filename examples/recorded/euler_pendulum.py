#!/usr/bin/python3
"""A run made outside eigenmass: explicit Euler on a single pendulum, logged as
body poses (docs/report-format.md, "Outside runs"). It uses numpy and none of
eigenmass's code; eigenmass then judges it:

    /usr/bin/python3 euler_pendulum.py --dt 1e-3 --out euler.csv
    eigenmass compare pendulum1.json --methods classical --run euler=euler.csv

The scene (pendulum1.json): a body of mass m hanging from a hinge about the
world y axis, its CM a distance l below the hinge, inertia I about its CM, so
(I + m l^2) theta'' = -m g l sin(theta); theta = q0 = 1 rad at rest.
"""
import argparse
import time

import numpy as np

M, L, I_CM, G = 1.0, 0.5, 0.02, 9.81
THETA0, OMEGA0 = 1.0, 0.0


def pose(theta):
    """CM position and orientation quaternion [w, x, y, z] of the bob at angle theta (about +y)."""
    r_rel = np.array([[np.cos(theta), 0, np.sin(theta)], [0, 1, 0], [-np.sin(theta), 0, np.cos(theta)]])
    cm = -r_rel @ np.array([0.0, 0.0, L])  # the joint point is L above the CM along the body's z
    return cm, np.array([np.cos(theta / 2), 0.0, np.sin(theta / 2), 0.0])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--dt", type=float, default=1e-3, help="Euler step (s)")
    ap.add_argument("--t-end", type=float, default=2.0)
    ap.add_argument("--every", type=int, default=10, help="log every this many steps")
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    steps = int(round(a.t_end / a.dt))
    theta, omega = THETA0, OMEGA0
    rows = []
    c0 = time.process_time()
    for k in range(steps + 1):
        if k % a.every == 0:
            cm, q = pose(theta)
            rows.append([k * a.dt, *cm, *q])
        alpha = -M * G * L * np.sin(theta) / (I_CM + M * L * L)
        theta, omega = theta + a.dt * omega, omega + a.dt * alpha  # explicit Euler
    cpu = time.process_time() - c0
    with open(a.out, "w") as f:
        f.write("# simulator: examples/recorded/euler_pendulum.py, explicit Euler dt %g\n# cpu_s: %.6f\n" % (a.dt, cpu))
        f.write("t,bob.x,bob.y,bob.z,bob.qw,bob.qx,bob.qy,bob.qz\n")
        for r in rows:
            f.write(",".join("%.17g" % x for x in r) + "\n")


if __name__ == "__main__":
    main()
