"""A controller writing a BoxROI's `box` or `orientedBox` at each step (docs/python.md, "Engines
over moving states"): the scene is built again before the step and the box selects from the
moving positions. SOFA HEAD's BoxROI orders the corners of each box and computes its oriented
boxes in roiInit, at init only: a box written with a corner above the other selects nothing, and a
written oriented box leaves the one of init tested (quirk `box_roi_write`, reproduced by default).
Equal to SOFA HEAD's numbers (tests/python/scripts/box_writes.py through `sofa-head-python`) to the
bit over 60 steps."""
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
    spec = importlib.util.spec_from_file_location("box_writes", os.path.join(HERE, "scripts", "box_writes.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def sofa_head():
    return json.load(open(os.path.join(HERE, "scripts", "box_writes_sofa_head.json")))


@pytest.mark.parametrize("mode", ["box", "inverted", "oriented"])
def test_box_written_each_step_selects_as_sofa_head(mode):
    got = scenario().run(mode)
    ref = sofa_head()[mode]
    assert got["indices"] == ref["indices"]
    assert np.array_equal(np.array(got["x"]), np.array(ref["x"]))


def test_the_written_boxes_change_the_selection():
    ref = sofa_head()
    assert ref["box"]["indices"][4] == [0, 1, 2, 10, 11, 12]  # the box reaches the falling beam
    assert all(i == [] for i in ref["inverted"]["indices"])  # corners not ordered: nothing
    assert all(i == [0, 1, 2] for i in ref["oriented"]["indices"])  # the oriented box of init


def test_with_the_quirk_fixed_a_written_box_selects_as_a_fresh_scene():
    fixed = ([], None, 0, False, [], ["box_roi_write"])
    module = scenario()
    inverted = module.run("inverted", init=lambda root: sofa_api.init(root, build_options=fixed))
    box = module.run("box")
    # corners ordered: the inverted box is the box
    assert inverted["indices"] == box["indices"]
    assert np.array_equal(np.array(inverted["x"]), np.array(box["x"]))
    oriented = module.run("oriented", init=lambda root: sofa_api.init(root, build_options=fixed))
    assert oriented["indices"] != sofa_head()["oriented"]["indices"]  # the written oriented box is tested
