"""penalty.load_scene(..., overrides=...) and `python3 -m penalty run --set`: the parsed scene is
changed before it is built (docs/sweeps.md)."""
from pathlib import Path

import numpy as np
import pytest

import penalty
from penalty.__main__ import main

SCENE = Path(__file__).resolve().parents[2] / "scenes" / "damped_bounce.scn"


def test_overrides_change_the_built_scene():
    s = penalty.load_scene(SCENE, overrides={"/root.dt": 5e-5, "/BallA/ball_a.position": [0.0, 0.3, 0.0]})
    assert s.dt == 5e-5
    np.testing.assert_array_equal(s.states["/BallA/ball_a"].positions, [[0.0, 0.3, 0.0]])
    # The same as a list of strings, and equal to editing the file.
    t = penalty.load_scene(SCENE, overrides=["/.dt=5e-05", "/BallA/ball_a.position=0 0.3 0"])
    assert t.dt == s.dt
    np.testing.assert_array_equal(t.states["/BallA/ball_a"].positions, s.states["/BallA/ball_a"].positions)


def test_stiffness_override_equals_the_edited_file(tmp_path):
    edited = tmp_path / "edited.scn"
    edited.write_text(SCENE.read_text().replace('name="ball_b_point" contactStiffness="20"',
                                                'name="ball_b_point" contactStiffness="35"'))
    a = penalty.load_scene(edited)
    b = penalty.load_scene(SCENE, overrides={"/BallB/ball_b_point.contactStiffness": 35})
    c = penalty.load_scene(SCENE)
    for s in (a, b, c):
        s.run(8000, progress=False)  # the balls touch the plate at step 4779
    assert a.energies() == b.energies()
    np.testing.assert_array_equal(a.states["/BallB/ball_b"].velocities, b.states["/BallB/ball_b"].velocities)
    # The override took effect: ball B bounced differently from the file's stiffness.
    assert a.states["/BallB/ball_b"].velocities[0, 1] != c.states["/BallB/ball_b"].velocities[0, 1]


def test_errors_name_the_path_or_attribute():
    with pytest.raises(penalty.SceneError, match=r"damped_bounce.scn:37: PointCollisionModel 'ball_b_point': "
                                                 r"attribute 'contactStiffness': expected a number, found 'abc'"):
        penalty.load_scene(SCENE, overrides={"/BallB/ball_b_point.contactStiffness": "abc"})
    with pytest.raises(penalty.SceneError, match=r"no node 'BallC' in '/'"):
        penalty.load_scene(SCENE, overrides={"/BallC/ball_c.position": "0 0 0"})
    with pytest.raises(penalty.SceneError, match=r"no attribute 'stiffness' in the file, and penalty does not read "
                                                 r"it for PointCollisionModel"):
        penalty.load_scene(SCENE, overrides={"/BallB/ball_b_point.stiffness": 1})
    with pytest.raises(ValueError, match=r"--set '/BallB=1': expected PATH.attribute=value"):
        penalty.load_scene(SCENE, overrides=["/BallB=1"])


def test_module_command_line_set(capsys):
    assert main(["run", str(SCENE), "--steps", "10", "--quiet", "--set", "/.dt=1e-4"]) == 0
    assert main(["run", str(SCENE), "--steps", "10", "--quiet", "--set", "/.dt"]) == 2
    assert "--set '/.dt': expected PATH.attribute=value (no '=')" in capsys.readouterr().err
    assert main(["run", str(SCENE), "--steps", "10", "--quiet", "--set", "/Nope.dt=1"]) == 1
    assert "no node or component 'Nope' in '/'" in capsys.readouterr().err


def test_overrides_apply_to_sofapython3_scripts():
    script = Path(__file__).resolve().parent / "scripts" / "falling_cube.py"
    assert penalty.load_scene(script, overrides={"/.dt": 0.00123}).dt == 0.00123
    with pytest.raises(penalty.SceneError, match=r"falling_cube.py: --set '/Nope.dt=1': no node or component 'Nope'"):
        penalty.load_scene(script, overrides={"/Nope.dt": 1})
