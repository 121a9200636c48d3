"""A controller writing a ConstantForceField's `indices` and `forces` with counts that do not fit
each other (docs/python.md, "Writing a Data after init"): SOFA HEAD's update callbacks
(ConstantForceField::updateFromIndices, updateFromForcesVector, updateFromTotalForce) make the
component Invalid, applying no force, until a write makes the counts fit again; the write is taken,
never refused. Equal to SOFA HEAD's numbers (tests/python/scripts/constant_force_writes.py through
`sofa-head-python`, 2a278d8 with SofaPython3 87be1a3) to the bit over 30 steps: the positions and
the Data read after each step."""
import importlib.util
import json
import os

import numpy as np
import pytest

import penalty

penalty._install_sofa_path()
import Sofa  # noqa: E402,F401  (penalty's)

from penalty import sofa_api  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


def scenario():
    spec = importlib.util.spec_from_file_location(
        "constant_force_writes", os.path.join(HERE, "scripts", "constant_force_writes.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def runs():
    sofa_head = json.load(open(os.path.join(HERE, "scripts", "constant_force_writes_sofa_head.json")))
    return scenario().run(), sofa_head


@pytest.mark.parametrize("data", ["x", "indices", "forces", "totalForce"])
def test_writes_of_mismatched_counts_give_sofa_heads_steps(runs, data):
    got, ref = runs
    assert len(got[data]) == len(ref[data]) == 30
    for step, (g, r) in enumerate(zip(got[data], ref[data]), start=1):
        assert np.array_equal(np.array(g), np.array(r)), (data, step)


def test_the_component_is_invalid_while_the_counts_do_not_fit(runs):
    _, ref = runs
    x = np.array(ref["x"])  # (step, point, xyz)
    v = np.diff(x, axis=0) / 0.01  # the velocity over each step from step 2 on
    # steps 6 to 10 (4 forces for 2 indices) and 16 to 20 (2 for 3): no force, the particles coast
    for first, last in ((6, 10), (16, 20)):
        assert np.array_equal(v[first - 1], v[last - 2])
    # valid again: steps 11 to 15 push points 0 and 1 only, 21 to 25 points 1, 2 and 3
    assert not np.array_equal(v[11 - 2], v[12 - 2])
    assert np.array_equal(v[21 - 2][0], v[22 - 2][0]) and not np.array_equal(v[21 - 2][1], v[22 - 2][1])


def test_a_scene_file_with_mismatched_counts_is_refused(tmp_path):
    scene = tmp_path / "mismatch.scn"
    scene.write_text('<Node name="root" dt="0.01"><Node name="N"><MechanicalObject position="0 0 0 1 0 0 2 0 0"/>'
                     '<ConstantForceField indices="0 1" forces="1 0 0 0 1 0 0 0 1"/></Node></Node>')
    with pytest.raises(penalty.SceneError, match="3 forces for 2 indices"):
        penalty.load_scene(scene)
