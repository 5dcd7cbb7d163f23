"""The Python module against the CLI (ctest -L python): the same numbers to the
last digit, the same report but for timings and provenance, a numpy method equal
to classical, and the CLI's one-line messages as exceptions."""
import csv
import json
import os
import subprocess

import numpy as np
import pytest

import eigenmass as em

SRC = os.environ["EM_SOURCE"]
BIN = os.environ["EM_BIN"]


def scene(name):
    return os.path.join(SRC, "data", "scenes", name)


def cli(*args):
    r = subprocess.run([os.path.join(BIN, "eigenmass"), *args], capture_output=True, text=True)
    return r.returncode, r.stdout, r.stderr


@pytest.mark.parametrize("path, engine", [(scene("pendulum5.json"), "inhouse"), (scene("tree_mixed.json"), "simbody"),
                                          (scene("planar_sled.json"), "dart"),
                                          (os.path.join(SRC, "data", "robots", "ur5.urdf"), "mujoco")])
def test_equations_equal_the_cli_to_the_last_digit(path, engine):
    status, out, _ = cli("equations", path, "--engine", engine)
    assert status == 0
    j = json.loads(out)
    e = em.equations(em.load(path), engine=engine)
    assert np.array_equal(e["A"], np.array(j["A"]))
    assert np.array_equal(e["B"], np.array(j["B"]))
    assert np.array_equal(e["udot"], np.array(j["udot"]))
    assert e["total"] == j["energy"]["total"]
    assert np.allclose(e["eigenvalues"], j["eigenvalues"], rtol=1e-13, atol=0)


def test_equations_at_a_state_the_scene_order():
    s = em.load(scene("tree_mixed.json"))
    rng = np.random.default_rng(3)
    q, u = s.q0 + 0.1 * rng.standard_normal(s.nq), rng.standard_normal(s.nu)
    for k, name in enumerate(s.q_names):  # renormalize the quaternions (ball joints: their .q0..q3)
        if name.endswith(".q0") and name[:-3] + ".q3" in s.q_names and name[:-3] + ".q4" not in s.q_names:
            q[k:k + 4] /= np.linalg.norm(q[k:k + 4])
    a, b = em.equations(s, q=q, u=u), em.equations(s, engine="simbody", q=q, u=u)
    assert np.abs(a["udot"] - b["udot"]).max() <= 1e-12 * np.abs(a["udot"]).max() * np.linalg.cond(a["A"])


def test_simulate_equals_the_cli_csv(tmp_path):
    out = str(tmp_path / "run.csv")
    status, _, _ = cli("simulate", scene("pendulum5.json"), "--method", "eigen-jacobi", "--t-end", "1", "--out", out, "--no-progress")
    assert status == 0
    with open(out) as f:
        rows = list(csv.reader(f))
    header, data = rows[0], np.array(rows[1:], dtype=float)
    r = em.simulate(em.load(scene("pendulum5.json")), method="eigen-jacobi", t_end=1)
    assert r["status"] == "ok" and r["failure"] is None
    assert np.array_equal(r["t"], data[:, 0])
    for k, name in enumerate(r["q_names"]):
        assert np.array_equal(r["q"][:, k], data[:, header.index(name)])
    for k, name in enumerate(r["u_names"]):
        assert np.array_equal(r["u"][:, k], data[:, header.index(name)])
    assert np.array_equal(r["energy"], data[:, header.index("energy")])


def strip(report):
    """The report without what differs between two runs of one comparison: CPU times and provenance."""
    if isinstance(report, dict):
        return {k: strip(v) for k, v in report.items()
                if k not in ("provenance", "run_time_s", "sample_time_s") and not k.startswith("cpu")}
    if isinstance(report, list):
        return [strip(v) for v in report]
    return report


def test_compare_equals_the_cli_report(tmp_path):
    out = str(tmp_path / "r.json")
    status, _, _ = cli("compare", scene("pendulum5.json"), "--t-end", "1", "--methods", "classical,eigen,mujoco", "--out", out,
                       "--no-progress")
    assert status == 0
    with open(out) as f:
        want = json.load(f)
    got = em.compare(em.load(scene("pendulum5.json")), methods=["classical", "eigen", "mujoco"], t_end=1)
    assert strip(got) == strip(want)


def test_a_numpy_method_equals_classical_under_the_same_integrator():
    s = em.load(scene("pendulum5.json"))

    def mine(t, q, u):
        e = em.equations(s, q=q, u=u)
        return np.linalg.solve(e["A"], e["B"])

    a = em.simulate(s, method=("mine", mine), t_end=0.5)
    b = em.simulate(s, method="classical", t_end=0.5)
    assert a["status"] == "ok"
    # Two backward-stable solves of one A u' = B differ by ~eps cond(A) (~1e-14 here), grown over 0.5 s.
    assert np.abs(a["q"] - b["q"]).max() < 1e-11
    rep = em.compare(s, methods=["classical", ("mine", mine)], t_end=0.5)
    names = [m["name"] for m in rep["methods"]]
    assert names == ["classical", "mine"]
    assert abs(rep["methods"][1]["max_pose_error_rad"] - rep["methods"][0]["max_pose_error_rad"]) < 1e-11


@pytest.mark.parametrize("integrator", ["ida", "trapezoidal"])
def test_a_python_method_is_never_run_as_classical_by_an_integrator_of_the_formation(integrator):
    # ida and the trapezoidal rule integrate the formation's A and B: they would never call f.
    s = em.load(scene("pendulum5.json"))
    calls = []

    def mine(t, q, u):
        calls.append(t)
        return -q[: len(u)]

    with pytest.raises(ValueError, match="comes from outside the formation"):
        em.simulate(s, method=("mine", mine), integrator=integrator, t_end=0.5)
    assert not calls


def test_a_python_method_that_raises_fails_its_run_not_the_interpreter():
    s = em.load(scene("pendulum5.json"))

    def broken(t, q, u):
        if t > 0.1:
            raise ZeroDivisionError("my bug")
        return np.zeros(s.nu)

    r = em.simulate(s, method=("broken", broken), t_end=0.5)
    assert r["status"] == "failed"
    assert r["failure"]["kind"] == "plugin"
    assert "my bug" in r["failure"]["cause"]


@pytest.mark.parametrize("args, call", [
    (["equations", os.path.join(SRC, "tests", "scenes", "malformed", "zero_axis.json")],
     lambda: em.load(os.path.join(SRC, "tests", "scenes", "malformed", "zero_axis.json"))),
    (["equations", "/nonexistent.json"], lambda: em.load("/nonexistent.json")),
    (["equations", os.path.join(SRC, "data", "scenes", "pendulum5.json"), "--balance-inertia"],
     lambda: em.load(scene("pendulum5.json"), balance_inertia=True)),
])
def test_bad_inputs_raise_with_the_cli_message(args, call):
    status, _, err = cli(*args)
    assert status == 2
    with pytest.raises(Exception) as e:
        call()
    # The CLI's line, its flags named as the module's keywords (issue 53 item 11).
    assert "eigenmass: error: " + str(e.value) + "\n" == err.replace("--balance-inertia", "balance_inertia")


def test_import_options_are_named_as_keywords():
    with pytest.raises(RuntimeError, match=r"ur5.urdf: lock_joints: no joint named 'nope'$"):
        em.load(os.path.join(SRC, "data", "robots", "ur5.urdf"), lock_joints=["nope"])


def test_bad_arguments_raise_not_crash():
    s = em.load(scene("pendulum5.json"))
    with pytest.raises(ValueError, match="7 numbers expected"):
        em.equations(s, q=np.zeros(3))
    with pytest.raises(ValueError, match="unknown method 'nope'"):
        em.simulate(s, method="nope")
    with pytest.raises(ValueError, match="dt"):
        em.simulate(s, dt=-1)
    with pytest.raises(ValueError, match="unknown engine"):
        em.equations(s, engine="gazebo")


def test_plot_and_sweep_are_the_cli_commands(tmp_path):
    s = em.load(scene("pendulum5.json"))
    rep = str(tmp_path / "r.json")
    with open(rep, "w") as f:
        json.dump(em.compare(s, methods=["classical"], t_end=0.5), f)
    out = em.plot(rep, out=str(tmp_path / "figures"))
    assert os.path.exists(tmp_path / "figures" / "pendulum5-divergence.png"), out
    with pytest.raises(RuntimeError, match="cannot open the report"):
        em.plot(str(tmp_path / "missing.json"))


LIB = os.environ.get("EM_LIB", "")


def test_outside_methods_live_only_for_the_call(tmp_path):
    """Issue 53 item 8: a plugin, a recorded run and a Python function are the call's; the same names work again."""
    import pathlib
    s = em.load(scene("pendulum5.json"))
    ok = pathlib.Path(LIB) / "libhostile_ok.so"
    run = tmp_path / "run.csv"
    assert cli("simulate", scene("pendulum5.json"), "--t-end", "0.5", "--out", str(run), "--no-progress")[0] == 0
    for _ in range(2):  # the second identical call once failed: "a method of that name exists"
        rep = em.compare(s, methods=["classical"], t_end=0.5, plugins={"mine": ok}, runs={"rec": run})
        assert [m["name"] for m in rep["methods"]] == ["classical", "mine", "rec"]
        assert em.simulate(s, method=("f", lambda t, q, u: np.zeros(s.nu)), t_end=0.01)["status"] == "ok"
    with pytest.raises(ValueError, match="libhostile_null.so"):  # its probe fails: the name is not left behind
        em.compare(s, t_end=0.5, plugins={"bad": os.path.join(LIB, "libhostile_null.so")})
    assert not {"mine", "rec", "f", "bad"} & set(em.methods())


@pytest.mark.parametrize("exc", [KeyboardInterrupt, SystemExit])
def test_ctrl_c_and_sys_exit_in_a_python_method_end_the_call(exc):
    """Issue 53 item 9: they once became the method's failure, and the script went on."""
    s = em.load(scene("pendulum5.json"))

    def interrupted(t, q, u):
        raise exc()

    with pytest.raises(exc):
        em.simulate(s, method=("interrupted", interrupted), t_end=0.1)
    with pytest.raises(exc):
        em.compare(s, methods=[("interrupted", interrupted)], t_end=0.1)
    assert "interrupted" not in em.methods()


@pytest.mark.parametrize("value, said", [(None, "None"), (1.0, "a float (a scalar)"),
                                         (np.zeros((1, 1)), "an array of shape (1, 1)"), (np.zeros(3), "an array of shape (3,)")])
def test_a_wrong_return_is_named_as_python_sees_it(value, said):
    s = em.load(scene("pendulum5.json"))
    r = em.simulate(s, method=("wrong", lambda t, q, u: value), t_end=0.01)
    assert r["failure"]["cause"] == "the Python method returned " + said + ", not a vector of nu = 7 numbers"


@pytest.mark.parametrize("call, message", [
    (lambda s: em.compare(s, methods=["simbody"], dt=1e-3, t_end=0.1), r"^dt: .*none is among methods$"),
    (lambda s: em.compare(s, methods=["simbody"], integrator="rk4", t_end=0.1), r"^integrator: .*none is among methods$"),
    (lambda s: em.compare(s, methods=[("my method", lambda t, q, u: q)], t_end=0.1), r"^methods: the name 'my method'"),
    (lambda s: em.simulate(s, method=("a\x1bb", lambda t, q, u: q), t_end=0.1), r"^method: the name 'a\\x1bb'"),
    (lambda s: em.compare(s, methods=[], t_end=0.1), r"^methods: none"),
    (lambda s: em.compare(s, methods=["classical", "classical"], t_end=0.1), r"listed twice"),
    (lambda s: em.compare(s, t_end=-1), r"^t_end: must be > 0"),
    (lambda s: em.compare(s, dt=-1, t_end=0.1), r"^dt: must be > 0"),
    (lambda s: em.equations(s, u=np.full(s.nu, 1e200)), r"^u link1.u0: speed 1e\+200 rad/s beyond \+-1e\+06"),
    (lambda s: em.equations(s, q=np.full(s.nq, 1e20)), r"^q link1.q0: angle 1e\+20 rad beyond \+-10000 rad$"),
    (lambda s: em.load(b"/x.json"), r"^path: a path as text"),
])
def test_python_refuses_what_the_cli_refuses_naming_the_keyword(call, message):
    """Issue 53 item 11: each was accepted (or named a CLI flag)."""
    s = em.load(scene("pendulum5.json"))
    with pytest.raises(ValueError, match=message):
        call(s)


def test_paths_may_be_pathlike(tmp_path):
    import pathlib
    a, b = em.load(pathlib.Path(scene("pendulum5.json"))), em.load(scene("pendulum5.json"))
    assert a.sha256 == b.sha256


def test_a_mechanism_compares_as_on_the_cli(tmp_path):
    """Loops in the module (issue 50): Andrews' squeezer, the CLI's reference (classical under ida), the same report."""
    out = str(tmp_path / "r.json")
    path = scene(os.path.join("mechanisms", "andrews.json"))
    status, _, err = cli("compare", path, "--t-end", "0.01", "--methods", "classical,articulated", "--out", out, "--no-progress")
    assert status == 0, err
    with open(out) as f:
        want = json.load(f)
    got = em.compare(em.load(path), methods=["classical", "articulated"], t_end=0.01)
    assert strip(got) == strip(want)
    assert got["methods"][0]["loops"]["rank"] == 6
    assert got["methods"][0]["loops"]["max_position_violation_m"] < 1e-9


def test_a_mechanisms_equations_equal_the_cli():
    """equations on a mechanism (issue 50): the constrained u', G, its rank and lambda, as the CLI prints them."""
    path = scene(os.path.join("mechanisms", "andrews.json"))
    status, out, _ = cli("equations", path)
    assert status == 0
    j = json.loads(out)
    e = em.equations(em.load(path))
    assert np.array_equal(e["udot"], np.array(j["udot"]))
    assert np.array_equal(e["G"], np.array(j["loops"]["G"]))
    assert e["rank"] == j["loops"]["rank"] == 6
    assert np.array_equal(e["lambda"], np.concatenate([c["lambda"] for c in j["loops"]["closures"]]))
    # The constrained u' keeps the loops: G u' = -c (here u = 0 at the start, so c = 0 and G u' = 0).
    assert np.abs(e["G"] @ e["udot"]).max() < 1e-9 * np.abs(e["udot"]).max()


def test_a_mechanism_runs_every_formulation_and_returns_its_violation_and_lambda():
    """Issue 50: formulation= as --formulation; the loops object and, per sample, the violation and lambda."""
    s = em.load(scene(os.path.join("mechanisms", "iftomm_a04.json")))
    for f, settings in (("projection", dict(integrator="rk8pd", tol=1e-10)),
                        ("coordinate-partitioning", dict(integrator="rk8pd", tol=1e-10)),
                        ("augmented-lagrangian", dict(integrator="trapezoidal", dt=1e-3))):
        r = em.simulate(s, t_end=0.5, formulation=f, **settings)
        assert r["status"] == "ok"
        assert r["loops"]["formulation"] == f
        assert r["loops"]["rank"] == 4  # Bricard: 5 rows of rank 4
        assert r["loop_violation"].shape == (len(r["t"]), 4)
        assert r["lambda"].shape == (len(r["t"]), 5)
        assert r["lambda_names"][0] == "lambda.O2.0"
        assert r["loop_violation"].max() < 1e-9  # each closes Bricard's hinge over 0.5 s
    rep = em.compare(s, methods=["classical"], formulation="coordinate-partitioning", tol=1e-10, t_end=0.1)
    assert rep["methods"][0]["loops"]["formulation"] == "coordinate-partitioning"
    with pytest.raises(ValueError, match="formulation: 'lagrange' is not one of"):
        em.simulate(s, formulation="lagrange")
    with pytest.raises(ValueError, match="augmented-lagrangian runs under its own integrator trapezoidal, not rk4"):
        em.simulate(s, integrator="rk4", dt=1e-3, formulation="augmented-lagrangian")
    with pytest.raises(ValueError, match="formulation: scene 'pendulum5' has no loops"):
        em.simulate(em.load(scene("pendulum5.json")), formulation="projection")


def test_load_assembles_an_open_start_as_the_cli_does(tmp_path):
    """Issue 73's doubtful list: load() had no assemble. A02 (N = 2) with its first crank turned 0.01 rad is open by
    ~0.01 m: refused as written, assembled with assemble=True, and s.assembly is the sidecar's object."""
    doc = json.load(open(scene("mechanisms/iftomm_a02_n2.json")))
    doc["bodies"][1]["joint"]["q0"][0] += 0.01
    path = tmp_path / "open.json"
    path.write_text(json.dumps(doc))
    with pytest.raises(Exception, match="--assemble|assemble"):
        em.load(path)
    s = em.load(path, assemble=True)
    assert s.assembly["gap_before"] > 5e-3
    assert s.assembly["max_change_q"] > 1e-3
    assert em.load(scene("mechanisms/iftomm_a02_n2.json")).assembly is None
    csv_path = tmp_path / "open.csv"
    assert cli("simulate", str(path), "--t-end", "0.05", "--assemble", "--out", str(csv_path))[0] == 0
    assert s.assembly == json.load(open(str(csv_path) + ".json"))["scene_source"]["assembly"]
