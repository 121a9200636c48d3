"""Every public function of the Python module checks its arguments: a TypeError for the wrong
kind, a ValueError for a wrong shape or value, each naming the argument, never a crash, a
MemoryError, a silent truncation or a silent NaN. The fuzz test runs in a child process, so a
segmentation fault fails the test instead of killing pytest."""
import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

import penalty
from penalty import collision

SCENE = Path(__file__).resolve().parents[2] / "scenes" / "damped_bounce.scn"


def contacts_on_dofs_0_to_3():
    ff = penalty.PenaltyForceField()
    n = np.tile([0.0, 1.0, 0.0], (4, 1))
    ff.add_contacts([0, 1, 2, 3], [0, 1, 2, 3], n, 0.1, 100.0)
    return ff


# ---- the reported cases, one by one ---------------------------------------------------------------
@pytest.mark.parametrize("call, match", [
    (lambda ff: ff.stiffness_matrix(1, 1), r"m1 = 1 is outside state 1 \(size 1\)"),
    (lambda ff: ff.damping_matrix(1, 1), r"m1 = 1 is outside state 1 \(size 1\)"),
    (lambda ff: ff.stiffness_matrix(0), r"m1 = 0 is outside state 1 \(size 0\)"),
    (lambda ff: ff.stiffness_matrix(-1), r"stiffness_matrix: n1 = -1 is out of range"),
    (lambda ff: ff.damping_matrix(4, -2), r"damping_matrix: n2 = -2 is out of range"),
    (lambda ff: ff.stiffness_matrix(10**12), r"n1 = 1000000000000 is out of range"),
])
def test_matrices_with_contacts_outside_the_states_are_value_errors(call, match):
    ff = contacts_on_dofs_0_to_3()
    with pytest.raises(ValueError, match=match):
        call(ff)
    assert ff.stiffness_matrix(4).shape == (12, 12)  # the field is still usable


def test_float_indices_are_not_truncated():
    ff = penalty.PenaltyForceField()
    with pytest.raises(ValueError, match=r"m1: 0.7 is not a whole number"):
        ff.add_contacts([0.7], [0], [[0, 1, 0]], 0.1, 100.0)
    with pytest.raises(TypeError, match=r"m2: expected numbers, found booleans"):
        ff.add_contacts([0], [True], [[0, 1, 0]], 0.1, 100.0)
    ff.add_contacts([1.0], [2], [[0, 1, 0]], 0.1, 100.0)  # a whole float is an index
    assert list(ff.contacts()["m1"]) == [1]
    with pytest.raises(ValueError, match=r"edges: 1.5 is not a whole number"):
        collision.LineModel(np.zeros((3, 3)), [[0, 1.5]])


def test_nan_positions_are_refused_not_zero_forces():
    ff = contacts_on_dofs_0_to_3()
    x = np.zeros((4, 3))
    x[2, 1] = np.nan
    with pytest.raises(ValueError, match=r"x1: row 2 holds nan \(every value must be finite\)"):
        ff.add_force(x)
    with pytest.raises(ValueError, match=r"v2: row 0 holds inf"):
        ff.add_force(np.zeros((4, 3)), np.zeros((4, 3)), None, np.full((4, 3), np.inf))
    with pytest.raises(ValueError, match="k_factor must be finite"):
        ff.add_dforce(np.zeros((4, 3)), k_factor=np.nan)


def test_sphere_radius_is_checked_at_construction():
    with pytest.raises(ValueError, match=r"radius: -1 must be a finite number > 0"):
        collision.SphereModel(np.zeros((2, 3)), radius=-1)
    with pytest.raises(ValueError, match=r"radius: expected one number or 2 radii"):
        collision.SphereModel(np.zeros((2, 3)), radius=[0.1, 0.2, 0.3])
    with pytest.raises(ValueError, match=r"radius: nan must be"):
        collision.RigidSphereModel(np.zeros((1, 3)), radius=float("nan"))
    with pytest.raises(ValueError, match=r"points: row 1 holds nan"):
        collision.PointModel([[0, 0, 0], [np.nan, 0, 0]])
    with pytest.raises(TypeError, match=r"detect: alarm_distance must be a number"):
        a = collision.PointModel(np.zeros((1, 3)))
        collision.detect(a, collision.PointModel(np.ones((1, 3))), "MinProximity", alarm_distance="far")


def test_load_scene_names_dt_not_a_command_line_option():
    for bad in (-1, 0.0, float("nan"), 1e-300, 1e6):
        with pytest.raises(ValueError, match=r"load_scene: dt = .* is out of range \[1e-100, 86400\] s") as e:
            penalty.load_scene(SCENE, dt=bad)
        assert "--dt" not in str(e.value)
    with pytest.raises(TypeError, match=r"load_scene: dt must be a number, not str"):
        penalty.load_scene(SCENE, dt="0.01")
    with pytest.raises(ValueError, match=r"builtin_scene: dt = -1.0 is out of range"):
        penalty.builtin_scene(dt=-1)
    with pytest.raises(ValueError, match=r"load_scene: threads = -1 is out of range \(0 to 1024\)"):
        penalty.load_scene(SCENE, threads=-1)
    with pytest.raises(TypeError, match=r"load_scene: threads must be an integer, not float"):
        penalty.load_scene(SCENE, threads=2.5)
    with pytest.raises(TypeError, match=r"overrides: expected a dict"):
        penalty.load_scene(SCENE, overrides=5)
    # one folder alone is a list of one, not a list of letters
    scene = penalty.load_scene(SCENE, data_dirs=str(SCENE.parent))
    assert scene.dt > 0


def test_scene_methods_check_their_arguments():
    scene = penalty.builtin_scene()
    with pytest.raises(ValueError, match=r"Scene.step: n = -1 is out of range"):
        scene.step(-1)
    with pytest.raises(TypeError, match=r"Scene.step: n must be an integer, not float"):
        scene.step(1.5)
    with pytest.raises(ValueError, match=r"Scene.run: vtk_every = 0 is out of range"):
        scene.run(2, vtk_every=0)
    with pytest.raises(ValueError, match=r"Scene.run: divergence_factor = nan is out of range"):
        scene.run(2, divergence_factor=float("nan"))
    with pytest.raises(TypeError, match=r"Scene.run: callback must be callable"):
        scene.run(2, callback=3)
    cube = scene.states["/SoftCube/cube"]
    with pytest.raises(ValueError, match=r"positions: row 3 holds nan"):
        x = np.array(cube.positions)
        x[3, 0] = np.nan
        cube.positions = x
    with pytest.raises(ValueError, match=r"positions: frame 0 has a zero quaternion"):
        scene.states["/Ball/ball"].positions = np.zeros((1, 7))
    assert scene.time == 0.0  # nothing ran


# ---- fuzz: every binding, many wrong arguments, in a child process ---------------------------------
FUZZ = textwrap.dedent(r'''
    import json, sys, traceback
    import numpy as np
    import penalty
    from penalty import collision

    SCENE = sys.argv[1]
    rng = np.random.default_rng(1)
    BAD = [None, True, -1, 0, 2**31, 2**63 - 1, 10**30, -1e300, 1e300, float("nan"), float("inf"), 0.5, "x", b"x",
           [], [[]], [1, 2], [[1, 2]], [[1, 2, 3, 4]], np.zeros((0, 3)), np.zeros((2, 3)), np.full((2, 3), np.nan),
           np.full((3, 3), 1e300), np.zeros((2, 3), dtype=np.float32), np.zeros((2, 3), dtype=bool),
           np.zeros((2, 3), dtype=np.int64), np.array([["a", "b", "c"]]), np.zeros((3, 3, 3)), np.zeros(3),
           np.array([0.7, 1.2]), np.array([-5, 7]), np.arange(12).reshape(4, 3)[:, ::-1], object(), {"a": 1}]
    outcomes = {}

    def attempt(name, f, *args, **kwargs):
        try:
            f(*args, **kwargs)
            kind = "ok"
        except (TypeError, ValueError, LookupError) as e:  # LookupError: states[key] only
            kind = type(e).__name__ if not isinstance(e, LookupError) or name == "States[]" else f"UNEXPECTED {e!r}"
            if not str(e):
                kind = "empty message"
        except Exception as e:  # noqa: BLE001 - recorded, then the parent fails on it
            kind = f"UNEXPECTED {type(e).__name__}: {e}"
        outcomes.setdefault(name, {}).setdefault(kind, 0)
        outcomes[name][kind] += 1

    def fresh_field():
        ff = penalty.PenaltyForceField(damping=0.5, friction=True)
        ff.add_contacts([0, 1, 2, 3], [0, 1, 2, 3], np.tile([0.0, 1.0, 0.0], (4, 1)), 0.1, 100.0)
        ff.add_force(np.zeros((4, 3)), np.zeros((4, 3)))
        return ff

    for bad in BAD:
        for position in range(5):
            args = [[0], [0], [[0.0, 1.0, 0.0]], 0.1, 100.0]
            args[position] = bad
            attempt("add_contacts", penalty.PenaltyForceField().add_contacts, *args)
        for keyword in ("element1", "element2", "mu_s", "mu_v", "old_index"):
            attempt("add_contacts", penalty.PenaltyForceField().add_contacts, [0], [0], [[0, 1, 0]], 0.1, 100.0,
                    **{keyword: bad})
        attempt("add_force", fresh_field().add_force, bad)
        attempt("add_force", fresh_field().add_force, np.zeros((4, 3)), bad)
        attempt("add_force", fresh_field().add_force, np.zeros((4, 3)), np.zeros((4, 3)), bad)
        attempt("add_force", fresh_field().add_force, np.zeros((4, 3)), np.zeros((4, 3)), None, bad)
        attempt("add_dforce", fresh_field().add_dforce, bad)
        attempt("add_dforce", fresh_field().add_dforce, np.zeros((4, 3)), bad)
        attempt("add_dforce", fresh_field().add_dforce, np.zeros((4, 3)), k_factor=bad)
        for method in ("stiffness_matrix", "damping_matrix"):
            attempt(method, getattr(fresh_field(), method), bad)
            attempt(method, getattr(fresh_field(), method), 4, bad)
            attempt(method, getattr(fresh_field(), method), bad, 4)
        for keyword in ("damping", "friction", "tangential_stiffness_ratio", "tangential_damping", "time_step"):
            attempt("PenaltyForceField", penalty.PenaltyForceField, **{keyword: bad})
        attempt("PointModel", collision.PointModel, bad)
        attempt("LineModel", collision.LineModel, np.zeros((3, 3)), bad)
        attempt("LineModel", collision.LineModel, bad, [[0, 1]])
        attempt("TriangleModel", collision.TriangleModel, np.zeros((3, 3)), bad)
        attempt("SphereModel", collision.SphereModel, np.zeros((2, 3)), radius=bad)
        attempt("SphereModel", collision.SphereModel, bad)
        attempt("RigidSphereModel", collision.RigidSphereModel, bad)
        attempt("RigidSphereModel", collision.RigidSphereModel, np.zeros((1, 7)), radius=bad)
        for keyword in ("contact_distance", "contact_stiffness"):
            attempt("PointModel", collision.PointModel, np.zeros((2, 3)), **{keyword: bad})
        model = collision.PointModel(np.zeros((2, 3)))
        attempt("points", setattr, model, "points", bad)
        for keyword in ("alarm_distance", "contact_distance", "angle_cone", "use_line_line"):
            attempt("detect", collision.detect, collision.SphereModel(np.zeros((1, 3)), 0.1),
                    collision.PointModel(np.zeros((1, 3))), "MinProximity", **{keyword: bad})
        attempt("detect", collision.detect, model, model, bad)
        attempt("load_scene", penalty.load_scene, SCENE, dt=bad)
        attempt("load_scene", penalty.load_scene, SCENE, threads=bad)
        attempt("load_scene", penalty.load_scene, SCENE, data_dirs=bad)
        attempt("load_scene", penalty.load_scene, SCENE, overrides=bad)
        attempt("load_scene", penalty.load_scene, bad)
        attempt("builtin_scene", penalty.builtin_scene, dt=bad)
    scene = penalty.load_scene(SCENE)
    state = scene.states[0]
    for bad in BAD:
        attempt("Scene.step", scene.step, bad)
        for keyword in ("vtk_every", "export_every", "view_every", "divergence_factor", "progress", "callback",
                        "export_mapped"):
            attempt("Scene.run", scene.run, 1, **{keyword: bad})
        attempt("Scene.run", scene.run, bad)
        for field in ("positions", "velocities", "forces", "rest_positions", "external_forces"):
            attempt(f"State.{field}", setattr, state, field, bad)
        attempt("States[]", lambda key: scene.states[key], bad)
    # random shapes and values
    for _ in range(300):
        n = int(rng.integers(0, 6))
        values = rng.normal(size=(n, 3)) * 10.0 ** rng.integers(-320, 320)
        attempt("random add_force", fresh_field().add_force, values)
        attempt("random stiffness_matrix", fresh_field().stiffness_matrix, int(rng.integers(-3, 8)), int(rng.integers(-3, 8)))
        attempt("random SphereModel", collision.SphereModel, values, radius=float(rng.normal()))
    json.dump(outcomes, sys.stdout)
''')


def test_fuzz_every_binding_raises_type_or_value_errors_and_never_crashes(tmp_path):
    script = tmp_path / "fuzz.py"
    script.write_text(FUZZ)
    env = dict(os.environ, PYTHONPATH=str(Path(penalty.__file__).parents[1]))
    r = subprocess.run([sys.executable, str(script), str(SCENE)], capture_output=True, text=True, env=env,
                       cwd=tmp_path, timeout=600)
    assert r.returncode == 0, f"the child died (exit {r.returncode}: a negative code is a signal)\n{r.stderr[-3000:]}"
    outcomes = json.loads(r.stdout)
    unexpected = {name: kinds for name, kinds in outcomes.items()
                  if any(k.startswith("UNEXPECTED") or k == "empty message" for k in kinds)}
    assert not unexpected, json.dumps(unexpected, indent=1)
    # every binding was reached and refused something
    assert len(outcomes) >= 25
    assert all(("TypeError" in kinds or "ValueError" in kinds) for name, kinds in outcomes.items()
               if not name.startswith("random") and name != "States[]"), json.dumps(outcomes, indent=1)
