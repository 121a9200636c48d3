"""The tunnelling guard from Python (docs/no-tunnelling.md): load_scene(no_tunnelling=),
Scene.no_tunnelling, Scene.tunnelling(), run()'s summary["tunnelling"], contact_advice() and the
command line's --no-tunnelling / info --contact-advice. The case: a 1 kg ball (sphere r = 0.1 m)
thrown at 50 m/s onto a static two-triangle sheet; its one spring stores ½·ks·(C + r)² = 24 J
against ½·m·v² = 1250 J, and it moves 0.25 m a step, beyond A + r = 0.15 m: it passes."""
import numpy as np
import pytest

import penalty
from penalty.__main__ import main

SCENE = """<?xml version="1.0"?>
<Node name="root" dt="0.005" gravity="0 -9.81 0">
  <DefaultAnimationLoop/>
  <CollisionPipeline name="pipeline"{guard}/>
  <BruteForceBroadPhase/>
  <BVHNarrowPhase/>
  <NewProximityIntersection alarmDistance="0.05" contactDistance="0.02"/>
  <CollisionResponse response="PenalityContactForceField"/>
  <Node name="Sheet">
    <MeshTopology position="-0.5 0 -0.5  0.5 0 -0.5  0.5 0 0.5  -0.5 0 0.5" triangles="0 2 1  0 3 2"/>
    <MechanicalObject name="sheet"/>
    <TriangleCollisionModel name="sheet_triangles" simulated="0" moving="0" contactStiffness="20"/>
  </Node>
  <Node name="Ball">
    <EulerImplicitSolver rayleighStiffness="0" rayleighMass="0"/>
    <CGLinearSolver iterations="200" tolerance="1e-12" threshold="1e-20"/>
    <MechanicalObject name="ball" position="0.03 0.3 0.04" velocity="0 -50 0"/>
    <UniformMass totalMass="1"/>
    <SphereCollisionModel name="ball_sphere" radius="0.1" contactStiffness="20"/>
  </Node>
</Node>
"""


@pytest.fixture
def ball_scene(tmp_path):
    def write(guard=""):
        path = tmp_path / f"ball{guard or '_plain'}.scn"
        path.write_text(SCENE.format(guard=f' noTunnelling="{guard}"' if guard else ""))
        return path
    return write


def _ball_y(scene):
    return scene.states["/Ball/ball"].positions[0, 1]


def test_warn_reports_the_crossing_and_keeps_the_trajectory(ball_scene):
    off = penalty.load_scene(ball_scene())
    warn = penalty.load_scene(ball_scene(), no_tunnelling="warn")
    assert off.no_tunnelling == "off" and off.tunnelling() is None
    assert warn.no_tunnelling == "warn"
    crossings = []
    for _ in range(20):
        off.step()
        warn.step()
        report = warn.tunnelling()
        crossings += report["crossings"]
        np.testing.assert_array_equal(off.states["/Ball/ball"].positions, warn.states["/Ball/ball"].positions)
        np.testing.assert_array_equal(off.states["/Ball/ball"].velocities, warn.states["/Ball/ball"].velocities)
    assert len(crossings) == 1  # the ball passes the sheet once
    c = crossings[0]
    assert 0.0 <= c["toi"] <= 1.0 and c["depth"] > 0.0
    assert "sheet_triangles" in (c["model1"], c["model2"]) and "ball_sphere" in (c["model1"], c["model2"])
    assert _ball_y(off) < 0.0  # through, unguarded


@pytest.mark.parametrize("mode", ["substep", "stiffen"])
def test_substep_and_stiffen_keep_the_ball_above_the_sheet(ball_scene, mode):
    s = penalty.load_scene(ball_scene(mode))  # the scene attribute
    assert s.no_tunnelling == mode
    summary = s.run(60, progress=False)
    t = summary["tunnelling"]
    assert t["mode"] == mode and t["crossings"] == 0
    assert t["prevented"] > 0 or t["stiffened_contacts"] > 0
    assert _ball_y(s) > 0.0


def test_run_sets_the_mode_and_the_summary_has_the_totals(ball_scene):
    s = penalty.load_scene(ball_scene())
    assert s.run(1, progress=False)["tunnelling"] is None
    summary = s.run(19, progress=False, no_tunnelling="warn")
    assert s.no_tunnelling == "warn"
    assert summary["tunnelling"]["crossings"] == 1 and summary["tunnelling"]["crossing_steps"] == 1
    assert "step" in summary["tunnelling"]["first_crossing"]
    s.no_tunnelling = "off"
    assert s.tunnelling() is None
    with pytest.raises(ValueError, match="sometimes"):
        s.no_tunnelling = "sometimes"


def test_contact_advice_is_the_closed_forms(ball_scene):
    s = penalty.load_scene(ball_scene())
    (a,) = s.contact_advice(impact_speed=50.0)
    assert a["mass"] == 1.0 and a["reach"] == pytest.approx(0.12) and a["alarm"] == pytest.approx(0.15)
    assert a["max_dt_detection"] == pytest.approx(0.15 / 50.0)
    assert a["min_ks_energy"] == pytest.approx(50.0 ** 2 / 0.12 ** 2)
    assert not a["safe"]


def test_command_line(ball_scene, capsys):
    assert main(["run", str(ball_scene()), "--steps", "20", "--quiet", "--no-tunnelling", "warn"]) == 0
    out = capsys.readouterr().out
    assert "tunnelling guard (warn): 1 crossings in 1 steps" in out
    assert main(["info", str(ball_scene()), "--contact-advice", "--impact-speed", "50"]) == 0
    assert "smallest contact stiffness" in capsys.readouterr().out


def _sofa_ball(guard):
    from penalty import sofa_api
    root = sofa_api.Node("root")
    root.gravity = [0, -9.81, 0]
    root.dt = 0.005
    root.addObject("DefaultAnimationLoop")
    root.addObject("CollisionPipeline", name="pipeline", noTunnelling=guard)
    root.addObject("BruteForceBroadPhase")
    root.addObject("BVHNarrowPhase")
    root.addObject("NewProximityIntersection", alarmDistance=0.05, contactDistance=0.02)
    root.addObject("CollisionResponse", response="PenalityContactForceField")
    sheet = root.addChild("Sheet")
    sheet.addObject("MeshTopology", position=[[-0.5, 0, -0.5], [0.5, 0, -0.5], [0.5, 0, 0.5], [-0.5, 0, 0.5]],
                    triangles=[[0, 2, 1], [0, 3, 2]])
    sheet.addObject("MechanicalObject", name="sheet")
    sheet.addObject("TriangleCollisionModel", name="sheet_triangles", simulated=False, moving=False, contactStiffness=20)
    ball = root.addChild("Ball")
    ball.addObject("EulerImplicitSolver", rayleighStiffness=0, rayleighMass=0)
    ball.addObject("CGLinearSolver", iterations=200, tolerance=1e-12, threshold=1e-20)
    ball.addObject("MechanicalObject", name="ball", position=[0.03, 0.6, 0.04], velocity=[0, -50, 0])
    ball.addObject("UniformMass", name="mass", totalMass=1.0)
    ball.addObject("SphereCollisionModel", name="ball_sphere", radius=0.1, contactStiffness=20)
    sofa_api.init(root)
    return root


@pytest.mark.parametrize("guard", ["warn", "substep"])
def test_the_guard_survives_a_live_write_that_rebuilds_the_scene(guard):
    """A Data written after init rebuilds the scene at the next step (live_writes.cpp): the guard
    comes with the new simulation and pipelines, with the mode set at run time."""
    from penalty import sofa_api
    root = _sofa_ball(guard)
    scene = root._penalty_scene
    sofa_api.animate(root, root.dt.value)
    root.Ball.mass.totalMass.value = 1.5  # a write: the next step runs a rebuilt scene
    crossings = 0
    for _ in range(20):
        sofa_api.animate(root, root.dt.value)
        crossings += len(scene.tunnelling()["crossings"])
    assert scene.no_tunnelling == guard
    assert crossings == (1 if guard == "warn" else 0)
    y = root.Ball.ball.position.value[0, 1]
    assert (y < 0.0) if guard == "warn" else (y > 0.0)
