#!/usr/bin/env python3
"""Writes the generated scenes of data/scenes/ (chains, ball-rooted pendulum5)
and data/bench/ (the 100-link chain of the benchmark): the one definition of
the chains that tests, benchmark and docs use.

Run from the project root: python3 tools/make_scenes.py. The hand-written
scenes (tree_mixed, forest, spring_damper) are not generated.
"""
import json, math, os

ROD = {"mass": 1.0, "inertia": [0.08395833333333334, 0.08395833333333334, 0.0012500000000000002]}


def link(i, parent, joint):
    return {"name": "link%d" % i, "parent": parent, **ROD, "joint": joint}


def chain(n, root):
    """n slender rods: `root` joint at the origin, revolutes alternating x, y."""
    bodies = [link(1, "ground", root)]
    for i in range(2, n + 1):
        bodies.append(link(i, "link%d" % (i - 1), {
            "type": "revolute", "axis": [1, 0, 0] if i % 2 == 0 else [0, 1, 0],
            "in_parent": [0, 0, -0.5], "in_body": [0, 0, 0.5],
            "q0": [round(0.5 * math.sin(1.3 * i), 6)], "u0": [round(0.2 * math.cos(0.7 * i), 6)]}))
    return bodies


GIMBAL = {"type": "gimbal", "in_parent": [0, 0, 0], "in_body": [0, 0, 0.5],
          "q0": [0.6, -0.5, 0.3], "u0": [0.2, -0.1, 0.3]}


def rx(a): c, s = math.cos(a), math.sin(a); return [[1, 0, 0], [0, c, -s], [0, s, c]]
def ry(a): c, s = math.cos(a), math.sin(a); return [[c, 0, s], [0, 1, 0], [-s, 0, c]]
def rz(a): c, s = math.cos(a), math.sin(a); return [[c, -s, 0], [s, c, 0], [0, 0, 1]]
def mul(a, b): return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
def col(m, j): return [m[i][j] for i in range(3)]


def quat(R):
    w = math.sqrt(max(0.0, 1 + R[0][0] + R[1][1] + R[2][2])) / 2
    return [w, (R[2][1] - R[1][2]) / (4 * w), (R[0][2] - R[2][0]) / (4 * w), (R[1][0] - R[0][1]) / (4 * w)]


def ball_equivalent(g):
    """Ball joint in the same physical state as a gimbal (x-y-z) joint."""
    q, u = g["q0"], g["u0"]
    R1 = rx(q[0]); R12 = mul(R1, ry(q[1])); R = mul(R12, rz(q[2]))
    axes = [[1, 0, 0], col(R1, 1), col(R12, 2)]  # gimbal axes in the parent frame
    w = [sum(axes[k][i] * u[k] for k in range(3)) for i in range(3)]
    return {"type": "ball", "in_parent": g["in_parent"], "in_body": g["in_body"],
            "q0": quat(R), "u0": w}


def scene(name, bodies, t_end=10.0):
    return {"format": "eigenmass-scene/1", "name": name, "gravity": [0, 0, -9.81],
            "bodies": bodies, "simulate": {"t_end": t_end, "output_dt": 0.01}}


def write(path, doc):
    with open(path, "w") as f:
        json.dump(doc, f, indent=2)
        f.write("\n")


if __name__ == "__main__":
    for n in list(range(1, 11)) + [20, 50]:
        write("data/scenes/chain%02d.json" % n, scene("chain%02d" % n, chain(n, GIMBAL)))
    # Sizes only the benchmark uses (kept out of data/scenes, which every scene test walks).
    os.makedirs("data/bench", exist_ok=True)
    for n in (100, 200):
        write("data/bench/chain%d.json" % n, scene("chain%d" % n, chain(n, GIMBAL)))
    p5 = json.load(open("data/scenes/pendulum5.json"))
    p5["name"] = "pendulum5_ball"
    p5["bodies"][0]["joint"] = ball_equivalent(p5["bodies"][0]["joint"])
    write("data/scenes/pendulum5_ball.json", p5)
