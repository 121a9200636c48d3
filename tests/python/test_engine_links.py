"""A Data linked to an engine's output follows the engine while the scene runs (docs/python.md,
"Data linked to an engine output"; SOFA's BaseData parent links and DataEngine's lazy update): a
controller writes a TransformEngine's input at each AnimateBeginEvent, and the states whose
`position` links the engine's `output_position` take the new output before the step's solve; a
step without a write keeps the solve's positions. Equal to SOFA HEAD's numbers to the bit."""
import importlib.util
import json
import os

import numpy as np

import penalty

penalty._install_sofa_path()
import Sofa  # noqa: E402,F401  (penalty's)

HERE = os.path.dirname(os.path.abspath(__file__))


def scenario():
    spec = importlib.util.spec_from_file_location("engine_links", os.path.join(HERE, "scripts", "engine_links.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_states_linked_to_an_engine_output_equal_sofa_heads():
    module = scenario()
    got = module.run()
    ref = json.load(open(os.path.join(HERE, "scripts", "engine_links_sofa_head.json")))
    for key in ("free", "falling", "falling_velocity", "free_after_write"):
        assert np.array_equal(np.array(got[key]), np.array(ref[key])), key


def test_the_followed_output_is_the_engines_transform_in_closed_form():
    module = scenario()
    got = module.run()
    points = np.array(module.POINTS, dtype=float)

    def turned(degrees):  # TransformEngine's rotation about x, in degrees
        a = np.radians(degrees)
        r = np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])
        return points @ r.T

    for step, x in enumerate(got["free"], start=1):  # 10 degrees more at each step's AnimateBeginEvent
        assert np.abs(np.array(x) - turned(10 * step)).max() < 1e-12
    assert np.abs(np.array(got["free_after_write"]) - turned(45)).max() < 1e-12  # read right after the write
    # falling points (implicit Euler, h = 0.01, g = -9.81, no stiffness: v_n = -n·g·h, x += h·v):
    # the engine's output (the points lifted by 0.1 more) replaces the positions at steps 1 and 3,
    # before that step's solve; steps 2 and 4 go on from the solve's positions
    h, g = 0.01, 9.81
    lift = [0.1, 0.1, 0.2, 0.2]
    y = None
    for step in range(1, 5):
        base = lift[step - 1] if step % 2 == 1 else y
        y = base - step * g * h * h
        x = np.array(got["falling"][step - 1])
        assert np.abs(x[:, 1] - (points[:, 1] + y)).max() < 1e-12, step
        assert np.abs(np.array(got["falling_velocity"][step - 1])[:, 1] + step * g * h).max() < 1e-12


def test_a_state_keeps_its_values_when_a_write_leaves_its_link_clean():
    """A write to an engine no state links (or to another Data) leaves the states' solve values."""
    module = scenario()
    root = Sofa.Core.Node("root")
    module.createScene(root)
    root.removeObject(root.controller)
    Sofa.Simulation.init(root)
    Sofa.Simulation.animate(root, root.dt.value)
    before = root.Falling.points.position.value.copy()
    root.Free.turn.rotation[0] += 30  # another engine: the falling points do not follow it
    assert np.array_equal(root.Falling.points.position.value, before)
    assert abs(root.Free.points.position.value[2, 2] - 0.5) < 1e-12  # sin(30°): the free points do
