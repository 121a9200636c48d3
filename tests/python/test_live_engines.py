"""Engines whose input is a state's moving positions run again when an output is read after the
positions changed (docs/python.md, "Engines over moving states"; SOFA's DDGNode::updateIfDirty →
DataEngine::update): a BoxROI over `@dofs.position` feeding a FixedProjectiveConstraint, a free
state following a TransformEngine over a falling beam, a Python DataEngine whose input is the
beam's positions. Equal to SOFA HEAD's numbers (tests/python/scripts/moving_engines.py through
`sofa-head-python`) to the bit over 60 steps."""
import importlib.util
import json
import os

import numpy as np

import penalty

penalty._install_sofa_path()
import Sofa  # noqa: E402,F401  (penalty's)

HERE = os.path.dirname(os.path.abspath(__file__))


def scenario():
    spec = importlib.util.spec_from_file_location("moving_engines", os.path.join(HERE, "scripts", "moving_engines.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_engines_over_moving_states_equal_sofa_heads():
    got = scenario().run()
    ref = json.load(open(os.path.join(HERE, "scripts", "moving_engines_sofa_head.json")))
    assert got["box_indices"] == ref["box_indices"]  # the points in the box change as the beam falls
    assert ref["box_indices"][0] == [] and ref["box_indices"][-1] == [5, 6, 7, 15, 16, 17]
    for key in ("box", "copy", "lowest"):
        assert np.array_equal(np.array(got[key]), np.array(ref[key])), key
    assert [row[1] for row in got["lowest"]] == list(range(1, 61))  # one update per step, at the read


def test_a_python_engine_over_a_moving_state_updates_only_when_read_after_a_change():
    module = scenario()
    root = Sofa.Core.Node("root")
    module.createScene(root)
    root.removeObject(root.reader)
    Sofa.Simulation.init(root)
    engine = root.Beam.lowest
    for _ in range(3):
        Sofa.Simulation.animate(root, root.dt.value)
    assert engine.counter == 0  # nothing read its output
    lowest = engine.lowest.value
    assert engine.counter == 1
    assert lowest == np.min(root.Beam.dofs.position.value[:, 1])
    assert engine.lowest.value == lowest and engine.counter == 1  # the positions did not change
    Sofa.Simulation.animate(root, root.dt.value)
    assert engine.lowest.value < lowest and engine.counter == 2


def test_a_box_written_after_init_selects_from_the_moving_positions_as_sofa_head():
    """A write of BoxROI.box builds the scene again (states kept); the engine then selects from the
    current positions at its next read. SOFA HEAD (the same calls through `sofa-head-python`): the
    indices and the positions below, bit for bit."""
    module = scenario()
    root = Sofa.Core.Node("root")
    module.createScene(root)
    Sofa.Simulation.init(root)
    for _ in range(15):
        Sofa.Simulation.animate(root, root.dt.value)
    root.Box.box.box.value = [[-0.1, -0.6, -0.1, 2.1, -0.15, 0.6]]
    for _ in range(10):
        Sofa.Simulation.animate(root, root.dt.value)
    assert root.Box.box.indices.value.tolist() == [0, 1, 2, 3, 4, 10, 11, 12, 13, 14]
    assert root.Box.fix.indices.value.tolist() == [0, 1, 2, 3, 4, 10, 11, 12, 13, 14]
    assert root.Box.dofs.position.value[0].tolist() == [7.151061276944174e-10, -0.2890780291116304,
                                                        -8.366678893668382e-09]
    assert root.Copy.copy.position.value[4].tolist() == [5.090570885566521, 0.31648131443453753,
                                                         1.0342301784343284e-05]
