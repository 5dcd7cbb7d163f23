#!/usr/bin/env python3
"""Writes tests/scenes/malformed/: one defect per scene, and expected.json
mapping each file to the JSON path and the phrase its error must name.
Run from the project root: python3 tools/make_malformed.py."""
import copy, json, os

OUT = "tests/scenes/malformed"
BASE = {
    "format": "eigenmass-scene/1", "name": "base", "gravity": [0, 0, -9.81],
    "bodies": [
        {"name": "upper", "parent": "ground", "mass": 1.0, "inertia": [0.08, 0.08, 0.002],
         "joint": {"type": "gimbal", "in_parent": [0, 0, 0], "in_body": [0, 0, 0.5],
                   "q0": [0.1, 0.2, 0.3], "u0": [0, 0, 0]}},
        {"name": "lower", "parent": "upper", "mass": 1.0, "inertia": [0.08, 0.08, 0.002],
         "joint": {"type": "revolute", "axis": [1, 0, 0], "in_parent": [0, 0, -0.5],
                   "in_body": [0, 0, 0.5], "q0": [0.4], "u0": [0.1]}}],
}
cases = {}


def case(name, path, phrase, edit=None, text=None):
    doc = copy.deepcopy(BASE)
    if edit:
        edit(doc)
    body = text if text is not None else json.dumps(doc, indent=1)
    with open(os.path.join(OUT, name + ".json"), "w") as f:
        f.write(body)
    cases[name + ".json"] = {"path": path, "phrase": phrase}


def b(i):
    return lambda d: d["bodies"][i]


def setk(getter, key, value):
    def f(d):
        getter(d)[key] = value
    return f


def delk(getter, key):
    def f(d):
        del getter(d)[key]
    return f


J0 = lambda d: d["bodies"][0]["joint"]
J1 = lambda d: d["bodies"][1]["joint"]
os.makedirs(OUT, exist_ok=True)
case("bad_json", "(document)", "invalid JSON at line", text='{"format": "eigenmass-scene/1",\n "name": "x",\n "bodies": [}')
case("not_an_object", "(document)", "expected a JSON object", text="[1, 2, 3]")
case("wrong_format", "format", "unsupported format", setk(lambda d: d, "format", "eigenmass-scene/2"))
case("unknown_top_key", "gravty", "unknown key", setk(lambda d: d, "gravty", [0, 0, -9.81]))
case("unknown_body_key", "bodies[1].masss", "unknown key", setk(b(1), "masss", 1.0))
case("unknown_joint_key", "bodies[0].joint.q_0", "unknown key", setk(J0, "q_0", [0, 0, 0]))
case("missing_mass", "bodies[0].mass", "missing required key", delk(b(0), "mass"))
case("zero_mass", "bodies[1].mass", "must be > 0", setk(b(1), "mass", 0))
case("negative_mass", "bodies[1].mass", "must be > 0", setk(b(1), "mass", -2.5))
case("inertia_not_pd", "bodies[0].inertia", "not positive definite", setk(b(0), "inertia", [0.08, 0.08, -0.002]))
case("inertia_products_not_pd", "bodies[1].inertia", "not positive definite",
     setk(b(1), "inertia", [1.0, 1.0, 1.0, 1.5, 0.0, 0.0]))
case("inertia_triangle", "bodies[1].inertia", "triangle inequality", setk(b(1), "inertia", [0.1, 0.1, 0.5]))
case("inertia_wrong_length", "bodies[0].inertia", "expected 3 or 6 numbers", setk(b(0), "inertia", [1, 1, 1, 0]))
case("cycle", "bodies[0].parent", "cycle", lambda d: (d["bodies"][0].update(parent="lower")))
case("self_parent", "bodies[1].parent", "own parent", setk(b(1), "parent", "lower"))
case("unknown_parent", "bodies[1].parent", "unknown parent", setk(b(1), "parent", "uper"))
case("duplicate_name", "bodies[1].name", "duplicate name", setk(b(1), "name", "upper"))
case("ground_name", "bodies[1].name", "reserved", setk(b(1), "name", "ground"))
case("empty_bodies", "bodies", "empty body list", setk(lambda d: d, "bodies", []))
case("zero_axis", "bodies[1].joint.axis", "zero axis", setk(J1, "axis", [0, 0, 0]))
case("missing_axis", "bodies[1].joint.axis", "missing required key", delk(J1, "axis"))
case("universal_not_perpendicular", "bodies[1].joint.axes", "not perpendicular",
     lambda d: (J1(d).update(type="universal", axes=[[1, 0, 0], [0.1, 1, 0]], q0=[0, 0], u0=[0, 0]), J1(d).pop("axis")))
case("axis_on_gimbal", "bodies[0].joint.axis", "not allowed on a gimbal joint", setk(J0, "axis", [1, 0, 0]))
case("spring_on_ball", "bodies[0].joint.spring", "not allowed on a ball joint",
     lambda d: J0(d).update(type="ball", q0=[1, 0, 0, 0], spring={"k": 1}))
case("unknown_joint_type", "bodies[1].joint.type", "unknown joint type", setk(J1, "type", "hinge"))
case("q0_wrong_length", "bodies[1].joint.q0", "expected 1 number, got 2", setk(J1, "q0", [0.1, 0.2]))
case("u0_wrong_length", "bodies[0].joint.u0", "expected 3 numbers, got 2", setk(J0, "u0", [1, 2]))
case("ball_q0_length", "bodies[0].joint.q0", "expected 4 numbers, got 3",
     lambda d: J0(d).update(type="ball", q0=[1, 0, 0]))
case("zero_quaternion", "bodies[0].joint.q0", "zero quaternion", lambda d: J0(d).update(type="ball", q0=[0, 0, 0, 0]))
case("nan_string", "bodies[0].mass", "expected a number", setk(b(0), "mass", "NaN"))
case("inf_string", "gravity[2]", "expected a number", setk(lambda d: d, "gravity", [0, 0, "Infinity"]))
case("huge_number", "bodies[1].joint.in_body[2]", "not a finite number",
     text=json.dumps(BASE, indent=1).replace('"in_body": [\n     0,\n     0,\n     0.5\n    ],\n    "q0": [\n     0.4', '"in_body": [\n     0,\n     0,\n     1e999\n    ],\n    "q0": [\n     0.4'))
case("duplicate_key", "bodies[0].mass", "duplicate key",
     text=json.dumps(BASE, indent=1).replace('"mass": 1.0,', '"mass": 1.0, "mass": 2.0,', 1))
case("missing_in_body", "bodies[1].joint.in_body", "missing required key", delk(J1, "in_body"))
case("negative_damping", "bodies[1].joint.spring.c", "must be >= 0", setk(J1, "spring", {"k": 1, "c": -0.5}))
case("spring_wrong_length", "bodies[0].joint.spring.k", "expected 3 numbers, got 2", setk(J0, "spring", {"k": [1, 2]}))
case("output_dt_zero", "simulate.output_dt", "must be > 0", setk(lambda d: d, "simulate", {"t_end": 1, "output_dt": 0}))
case("name_not_string", "name", "expected a string", setk(lambda d: d, "name", 5))
# Hostile input: names and keys that would corrupt a header, a path or the terminal;
# values that would make an error message huge or its construction recurse.
case("newline_key", "a\\nb", "unknown key", text='{"a\\nb": 1}')
case("fuzz_newline_overflow", "\\n", "not a finite number", text='{"\\n":4e626')
case("escape_in_name", "name", "outside letters", setk(lambda d: d, "name", "\u001b[31mred"))
case("comma_in_body_name", "bodies[1].name", "outside letters", setk(b(1), "name", "a,b"))
case("dotdot_scene_name", "name", "outside letters", setk(lambda d: d, "name", "../../x"))
case("long_name", "name", "over 64 long", setk(lambda d: d, "name", "n" * 65))
case("deep_nesting", "gravity" + "[0]" * 63, "nested deeper than 64",
     text='{"format": "eigenmass-scene/1", "gravity": ' + "[" * 100000 + "]" * 100000 + "}")
case("huge_list_as_mass", "bodies[0].mass", "got a list of 20000", setk(b(0), "mass", [0.5] * 20000))
case("huge_angle", "bodies[1].joint.q0[0]", "beyond", setk(J1, "q0", [1e20]))
case("huge_speed", "bodies[1].joint.u0[0]", "beyond +-1e+06", setk(J1, "u0", [2e6]))
case("gravity_huge", "gravity", "beyond 10000 (a thousand g)", setk(lambda d: d, "gravity", [0, 0, -1e308]))
case("grid_not_whole", "simulate.t_end", "whole multiple of output_dt",
     setk(lambda d: d, "simulate", {"t_end": 1, "output_dt": 0.3}))
# Mechanisms (docs/scene-format.md, "Mechanisms"): loops and point springs.
def top(key, value):
    return setk(lambda d: d, key, value)
case("loop_unknown_body", "loops[0].body_a", "unknown body 'nobody'",
     top("loops", [{"name": "l", "type": "ball", "body_a": "nobody", "body_b": "ground"}]))
case("loop_to_itself", "loops[0].body_b", "joins body 'upper' to itself",
     top("loops", [{"name": "l", "type": "ball", "body_a": "upper", "body_b": "upper"}]))
case("loop_zero_axis", "loops[0].axis_a", "zero axis",
     top("loops", [{"name": "l", "type": "hinge", "body_a": "lower", "body_b": "ground", "axis_a": [0, 0, 0], "axis_b": [1, 0, 0]}]))
case("loop_open_at_start", "loops[0]", "loop 'l' is open by 0.488 m at the initial state",
     top("loops", [{"name": "l", "type": "ball", "body_a": "upper", "body_b": "ground"}]))
# A hinge whose axes are opposed: its two direction rows vanish there, its
# turn is pi (docs/theory.md eq. (M4b)): open, not closed.
def _opposed_axis_b():
    import math
    a, b, c = BASE["bodies"][0]["joint"]["q0"]  # upper's gimbal angles, R = Rx(a) Ry(b) Rz(c)
    Rx = [[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]]
    Ry = [[math.cos(b), 0, math.sin(b)], [0, 1, 0], [-math.sin(b), 0, math.cos(b)]]
    Rz = [[math.cos(c), -math.sin(c), 0], [math.sin(c), math.cos(c), 0], [0, 0, 1]]
    mul = lambda A, B: [[sum(A[i][k] * B[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
    R = mul(mul(Rx, Ry), Rz)
    return [-R[i][0] for i in range(3)]  # -R x: opposed to axis_a = x as upper holds it
case("loop_hinge_axes_opposed", "loops[0]", "loop 'l' is open by 3.14 rad at the initial state",
     top("loops", [{"name": "l", "type": "hinge", "body_a": "upper", "point_a": [0, 0, 0.5], "body_b": "ground",
                    "axis_a": [1, 0, 0], "axis_b": _opposed_axis_b()}]))
case("loop_unknown_type", "loops[0].type", "unknown loop type 'cam'",
     top("loops", [{"name": "l", "type": "cam", "body_a": "upper", "body_b": "ground"}]))
case("loop_universal_without_axis_b", "loops[0].axis_b", "missing required key",
     top("loops", [{"name": "l", "type": "universal", "body_a": "upper", "point_a": [0, 0, 0.5], "body_b": "ground",
                    "axis_a": [1, 0, 0]}]))
case("loop_slider_with_axis_b", "loops[0].axis_b", "unknown key",
     top("loops", [{"name": "l", "type": "slider", "body_a": "upper", "body_b": "ground", "axis_a": [1, 0, 0],
                    "axis_b": [0, 1, 0]}]))
case("loop_universal_axes_parallel", "loops[0]", "loop 'l' is open by 1.57 rad at the initial state",
     top("loops", [{"name": "l", "type": "universal", "body_a": "upper", "point_a": [0, 0, 0.5], "body_b": "ground",
                    "axis_a": [1, 0, 0], "axis_b": _opposed_axis_b()}]))
case("loop_slider_off_its_line", "loops[0]", "loop 'l' is open by 0.0993 m at the initial state",
     top("loops", [{"name": "l", "type": "slider", "body_a": "ground", "point_a": [0, 0, 0], "body_b": "upper",
                    "point_b": [0, 0, 0], "axis_a": [0, 0, 1]}]))
case("force_negative_k", "forces[0].k", "must be >= 0",
     top("forces", [{"name": "s", "type": "spring", "body_a": "lower", "body_b": "ground", "k": -1, "length": 1}]))
case("force_huge_length", "forces[0].length", "1e+300 m beyond 10000 m",
     top("forces", [{"name": "s", "type": "spring", "body_a": "lower", "body_b": "ground", "k": 1, "length": 1e300}]))
case("loop_far_point", "loops[0].point_a", "a coordinate beyond +-10000 m",
     top("loops", [{"name": "l", "type": "ball", "body_a": "upper", "point_a": [1e300, 0, 0], "body_b": "ground"}]))
case("force_zero_length", "forces[0].length", "a rest length must be > 0",
     top("forces", [{"name": "s", "type": "spring", "body_a": "lower", "body_b": "ground", "k": 1, "length": 0}]))
case("force_coincident_points", "forces[0]", "its two points coincide",
     top("forces", [{"name": "s", "type": "spring", "body_a": "upper", "point_a": [0, 0, 0.5], "body_b": "ground", "k": 1, "length": 1}]))
# Merged into expected.json: some of its scenes were written by hand (free
# joints, a few hostile ones), and rewriting it whole dropped them.
expected_path = os.path.join(OUT, "expected.json")
expected = json.load(open(expected_path)) if os.path.exists(expected_path) else {}
expected.update(cases)
with open(expected_path, "w") as f:
    json.dump(expected, f, indent=1, sort_keys=True)
    f.write("\n")
print(len(cases), "malformed scenes")
