"""ValuesFromPositions as a live engine (docs/python.md, "Engines over moving states"): over moving
positions it runs again when they move, and its outputs, the scalar `values` per point and element
and the vectors, are read from Python as SOFA HEAD's (tests/python/scripts/values_from_positions.py
through `sofa-head-python`, 2a278d8 with SofaPython3 87be1a3) to the bit over 40 steps. A scalar
field over several values is interpolated over the x extent of the scene's bounding box
(ValuesFromPositions::doUpdate): taken from the root node's `bbox` when a scene file fixes it, and
refused otherwise, naming the component (SOFA computes the box from every component's computeBBox,
which penalty does not reproduce)."""
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
        "values_from_positions", os.path.join(HERE, "scripts", "values_from_positions.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    sofa_head = json.load(open(os.path.join(HERE, "scripts", "values_from_positions_sofa_head.json")))
    return scenario().run(str(tmp_path_factory.mktemp("vfp"))), sofa_head


def test_outputs_read_after_each_step_are_sofa_heads(runs):
    got, ref = runs
    assert len(got) == len(ref) == 6
    for k, (g, r) in enumerate(zip(got, ref)):
        assert g.keys() == r.keys()
        for key in r:
            assert np.array_equal(np.array(g[key]), np.array(r[key])), (k, key)


def value_from_position(p, direction, values, bmin, bmax):
    """ValuesFromPositions::valueFromPosition, in SOFA's order of operations."""
    coef = p[0] * direction[0] + p[1] * direction[1] + p[2] * direction[2]
    coef = (coef - bmin) / (bmax - bmin)
    coef *= len(values) - 1
    v = int(np.floor(coef))
    if v < 0:
        return values[0]
    if v >= len(values) - 1:
        return values[-1]
    coef -= v
    return values[v] * (1 - coef) + values[v + 1] * coef


def test_the_scalar_field_follows_the_moving_points(runs):
    _, ref = runs
    # interpolated over x in [-1, 4] (the root's bbox), at the points as read at each step
    for row in ref:
        expected = [value_from_position(p, (0.3, 1, 0.2), [1, 3, 2, 7], -1.0, 4.0) for p in row["x"]]
        assert row["vfp.values"] == expected
    assert ref[0]["vfp.values"][4] == 2.92  # (2, 0, 0): coef 3 (0.6 + 1) / 5 = 0.96 between 1 and 3
    assert ref[1]["vfp.values"] != ref[0]["vfp.values"]  # the beam fell: run again
    assert ref[-1]["still.values"] == ref[0]["still.values"]  # over the rest positions: once
    assert ref[0]["vec.pointVectors"] == [[1.0, 1.0, 0.0]] * 20


def test_a_scalar_field_without_a_fixed_scene_bbox_is_refused(tmp_path):
    scene = tmp_path / "no_bbox.scn"
    scene.write_text(scenario().SCENE.replace(' bbox="-1 -2 -3 4 5 6"', ""))
    root = sofa_api.load(str(scene))
    sofa_api.init(root)
    with pytest.raises(ValueError, match=r"no_bbox.scn:\d+: ValuesFromPositions 'vfp': .*fixed bbox"):
        root.Beam.vfp.values.value
    assert root.Beam.vec.pointVectors.value.tolist() == [[1.0, 1.0, 0.0]] * 20  # a vector field needs no box
    notes = penalty.load_scene(scene).info()["warnings"]
    assert [n.split(": ")[1] for n in notes if "cannot be read" in n] == ["ValuesFromPositions 'vfp'",
                                                                           "ValuesFromPositions 'still'"]


def test_a_scripts_root_bbox_is_not_fixed():
    # SofaPython3's root.bbox is a Data SOFA's visitors compute again (Node::parse alone fixes it)
    root = sofa_api.Node("root")
    root.bbox = [[-1, -2, -3], [4, 5, 6]]
    root.addObject("DefaultAnimationLoop")
    node = root.addChild("N")
    node.addObject("MechanicalObject", name="dofs", position=[[0, 0, 0], [1, 0, 0]])
    one = node.addObject("ValuesFromPositions", name="one", inputValues=[5], direction=[1, 0, 0])
    two = node.addObject("ValuesFromPositions", name="two", inputValues=[1, 3], direction=[1, 0, 0])
    sofa_api.init(root)
    assert one.values.value.tolist() == [5.0, 5.0]  # one value: no box needed
    with pytest.raises(ValueError, match="a script's root.bbox is not fixed"):
        two.values.value


def test_written_inputs_run_the_engine_again(tmp_path):
    # SOFA HEAD gives the same reads (inputValues and direction are inputs: addInput)
    path = tmp_path / "vfp.scn"
    path.write_text(scenario().SCENE)
    root = sofa_api.load(str(path))
    sofa_api.init(root)
    vfp = root.Beam.vfp
    assert vfp.values.value[:3].tolist() == [2.2, 2.38, 2.5599999999999996]
    vfp.inputValues.value = [0, 10]
    assert vfp.values.value[:3].tolist() == [2.0, 2.3, 2.6]  # 10 (0.3 x + 1) / 5
    vfp.direction.value = [1, 0, 0]
    assert vfp.values.value[:3].tolist() == [2.0, 3.0, 4.0]  # 10 (x + 1) / 5
