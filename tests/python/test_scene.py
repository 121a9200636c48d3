"""Scenes from Python: stepping, states as views of the C++ memory, contacts, energies, outputs,
errors."""
import csv
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import penalty

REPO = Path(__file__).resolve().parents[2]
CLI_DIR = REPO / "tests" / "cli"


@pytest.fixture
def scene():
    return penalty.builtin_scene()


def test_step_time_dt(scene):
    assert scene.dt == 0.005
    assert scene.time == 0.0
    scene.step(10)
    assert scene.time == pytest.approx(0.05, abs=1e-15)
    scene.step()
    assert scene.time == pytest.approx(0.055, abs=1e-15)
    with pytest.raises(ValueError, match=r"Scene.step: n = -1 is out of range"):
        scene.step(-1)


def test_states_by_path_and_name(scene):
    assert scene.states.keys() == ["/Floor/floor", "/SoftCube/cube", "/Ball/ball"]
    cube = scene.states["/SoftCube/cube"]
    assert scene.states["cube"] is not None and scene.states["cube"].path == cube.path
    assert cube.positions.shape == (125, 3) and cube.template == "Vec3d"
    ball = scene.states["ball"]
    assert ball.template == "Rigid3d"
    assert ball.positions.shape == (1, 7) and ball.velocities.shape == (1, 6)
    np.testing.assert_array_equal(ball.positions[0], [0.1, 1.2, 0.05, 0, 0, 0, 1])
    with pytest.raises(KeyError, match="no state 'nope'"):
        scene.states["nope"]


VEC1_DISTANCES = """<Node name="root" dt="0.01" gravity="0 0 0">
  <Node name="Body"><EulerImplicitSolver/><CGLinearSolver iterations="20" tolerance="1e-12" threshold="1e-20"/>
    <MechanicalObject name="dofs" position="3 4 0  0 0 2"/><UniformMass vertexMass="1"/>
    <Node name="distances"><MechanicalObject template="Vec1" name="d"/>
      <DistanceFromTargetMapping input="@../dofs" output="@d" targetPositions="0 0 0  0 0 0" restLengths="1"/>
    </Node>
  </Node>
</Node>
"""


def test_a_vec1_state_is_an_n_by_1_view(tmp_path):
    path = tmp_path / "distances.scn"
    path.write_text(VEC1_DISTANCES)
    scene = penalty.load_scene(path)
    assert scene.states.keys() == ["/Body/dofs", "/Body/distances/d"]
    d = scene.states["d"]
    assert d.template == "Vec1d" and d.mapped and d.size == 2
    assert d.positions.shape == (2, 1) and d.velocities.shape == (2, 1)
    np.testing.assert_array_equal(d.positions[:, 0], [4.0, 2.0])  # |(3,4,0)| - 1, |(0,0,2)| - 0
    assert np.shares_memory(d.positions, d.positions)


def test_positions_are_views_not_copies(scene):
    cube = scene.states["/SoftCube/cube"]
    x = cube.positions
    again = cube.positions
    # the same C++ buffer, read twice: same address, shared memory, nothing owned by numpy
    assert x.__array_interface__["data"][0] == again.__array_interface__["data"][0]
    assert np.shares_memory(x, again)
    assert not x.flags.owndata
    y0 = x[:, 1].copy()
    scene.step(20)
    # the array read before the steps sees the C++ state move (falling under gravity)
    assert np.all(x[:, 1] < y0)
    np.testing.assert_array_equal(x, cube.positions)


def test_writing_positions_moves_the_body(scene):
    cube = scene.states["/SoftCube/cube"]
    x = cube.positions
    x[:, 1] += 10.0  # lift the cube 10 m through the view
    np.testing.assert_array_equal(cube.positions[:, 1], x[:, 1])
    assert cube.positions[:, 1].min() > 10.0
    scene.step(1)
    # far above the floor, one step of free fall from rest: y decreases by g·dt² (implicit Euler)
    assert cube.positions[:, 1].min() > 10.0 - 0.01
    v = cube.velocities
    assert v[:, 1].mean() == pytest.approx(-9.81 * 0.005, rel=1e-3)


def test_rigid_centers_are_views(scene):
    ball = scene.states["ball"]
    c = ball.centers
    c[0] = [0.0, 5.0, 0.0]
    np.testing.assert_array_equal(ball.positions[0, :3], [0.0, 5.0, 0.0])
    ball.positions = np.array([[0.0, 6.0, 0.0, 0.0, 0.0, 0.0, 2.0]])  # the quaternion is normalised
    np.testing.assert_array_equal(ball.positions[0], [0.0, 6.0, 0.0, 0.0, 0.0, 0.0, 1.0])
    assert np.linalg.norm(ball.orientations[0]) == 1.0
    with pytest.raises(ValueError, match=r"expected shape \(1, 7\)"):
        ball.positions = np.zeros((2, 7))


def test_contacts_after_landing(scene):
    scene.step(60)  # the cube lands at about t = 0.1 s
    c = scene.contacts()
    n = len(c["penetration"])
    assert n > 0
    for key in ("point1", "point2", "normal", "tangential_force"):
        assert c[key].shape == (n, 3)
    np.testing.assert_allclose(np.linalg.norm(c["normal"], axis=1), 1.0, rtol=1e-12)
    active = c["penetration"] > 0
    assert active.any()
    # SOFA's law without damping: f_n = ks·pen on active contacts, 0 otherwise
    np.testing.assert_allclose(c["normal_force"][active], c["stiffness"][active] * c["penetration"][active], rtol=1e-12)
    assert np.all(c["normal_force"][~active] == 0.0)
    assert set(c["pairs"]) <= {"floor_triangles-cube_points", "ball_sphere-cube_points", "ball_sphere-floor_triangles",
                               "floor_triangles-ball_sphere", "cube_points-ball_sphere"}
    assert np.all(c["age"] >= 0) and np.all(c["friction_state"] == 0)


def test_energies(scene):
    e0 = scene.energies()
    assert e0["kinetic"] == 0.0 and e0["contact"] == 0.0
    scene.step(10)
    e = scene.energies()
    # only the cube (1 kg, 125 DOFs) and the ball (0.5 kg) move: ½ Σ m_i v_i²
    cube = scene.states["cube"].velocities
    ball = scene.states["ball"].velocities
    expected = 0.5 * (1.0 / 125) * np.sum(cube * cube) + 0.5 * 0.5 * np.sum(ball[:, :3] ** 2)
    assert e["kinetic"] == pytest.approx(expected, rel=1e-9)
    assert e["dissipated"] == e["dissipated_damping"] + e["dissipated_friction"]


def test_info_is_data(scene):
    info = scene.info()
    types = [c["type"] for c in info["components"]]
    assert "TetrahedronFEMForceField" in types
    mo = [c for c in info["components"] if c["type"] == "MechanicalObject" and c["name"] == "cube"][0]
    assert mo["built"] and "125 DOFs" in mo["role"]
    assert info["nodes"][0]["dt"] == 0.005
    assert info["pipelines"][0]["intersection"] == "NewProximity"
    assert "SoftCube" in info["text"]


def test_run_writes_the_cli_outputs(scene, output_dir):
    summary = scene.run(40, vtk=output_dir / "vtk", stats=output_dir / "stats.csv",
                        export_states=output_dir / "states", progress=False)
    assert summary["steps"] == 40
    assert scene.time == pytest.approx(0.2)
    rows = list(csv.DictReader(open(output_dir / "stats.csv")))
    assert len(rows) == 40
    assert float(rows[-1]["time"]) == pytest.approx(0.2)
    assert any((output_dir / "vtk").glob("*.pvd"))
    assert len(summary["state_files"]) == 3  # floor, cube, ball: all under the root solver, none mapped
    assert "steps: 40" in summary["text"]


def test_run_records_energies_per_step(output_dir):
    scene = penalty.builtin_scene()
    summary = scene.run(30, progress=False, record=True, stats=output_dir / "stats.csv")
    h = summary["history"]
    np.testing.assert_allclose(h["time"], 0.005 * np.arange(1, 31), rtol=1e-12)
    rows = list(csv.DictReader(open(output_dir / "stats.csv")))
    # the same numbers as the CLI's statistics file (written with %.17g or shorter)
    np.testing.assert_allclose(h["kinetic"], [float(r["kinetic_energy"]) for r in rows], rtol=1e-12)
    np.testing.assert_allclose(h["contacts"], [float(r["contacts"]) for r in rows])
    assert h["contacts"][-1] > 0


def test_run_calls_back_and_is_the_same_as_step():
    a, b = penalty.builtin_scene(), penalty.builtin_scene()
    calls = []
    a.run(30, progress=False, callback=lambda done, total: calls.append((done, total)))
    b.step(30)
    assert calls[0] == (1, 30) and calls[-1] == (30, 30) and len(calls) == 30
    for sa, sb in zip(a.states, b.states):
        np.testing.assert_array_equal(sa.positions, sb.positions)


def cli_error(*args):
    cli = os.environ.get("PENALTY_CLI", str(REPO / "build" / "release" / "bin" / "penalty"))
    if not Path(cli).exists():
        pytest.skip("penalty command line not built")
    r = subprocess.run([cli, *args], capture_output=True, text=True)
    prefix = "penalty: error: "
    line = [l for l in r.stderr.splitlines() if l.startswith(prefix)][0]
    return r.returncode, line[len(prefix):]


def test_scene_errors_have_the_cli_message():
    path = str(CLI_DIR / "malformed.scn")
    with pytest.raises(penalty.SceneError) as error:
        penalty.load_scene(path)
    assert "attribute 'totalMass': expected a number, found 'abc'" in str(error.value)
    assert isinstance(error.value, ValueError)
    code, message = cli_error("run", path)
    assert code == 1 and message == str(error.value)


def test_missing_file_raises():
    with pytest.raises(penalty.SceneError, match="cannot read: the path does not exist"):
        penalty.load_scene("/nonexistent/scene.scn")


def test_divergence_raises_with_the_cli_message():
    path = str(CLI_DIR / "diverges.scn")
    scene = penalty.load_scene(path)
    with pytest.raises(penalty.DivergedError) as error:
        scene.run(100, progress=False)
    assert "simulation diverged at step" in str(error.value)
    code, message = cli_error("run", path, "--steps", "100", "--quiet")
    assert code == 3 and message == str(error.value)


STATIC_FLOOR = """<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <DefaultAnimationLoop/>
  <CollisionPipeline/>
  <BruteForceBroadPhase/>
  <BVHNarrowPhase/>
  <NewProximityIntersection alarmDistance="0.1" contactDistance="0.02"/>
  <CollisionResponse response="PenalityContactForceField"/>
  <Node name="Cube">
    <EulerImplicitSolver rayleighStiffness="0.01"/>
    <CGLinearSolver iterations="50" tolerance="1e-9" threshold="1e-9"/>
    <RegularGridTopology nx="3" ny="3" nz="3" xmin="1" xmax="2" ymin="0.1" ymax="1.1" zmin="1" zmax="2"/>
    <MechanicalObject name="dofs" velocity="2 0 1"/>
    <UniformMass totalMass="1"/>
    <TetrahedronFEMForceField youngModulus="2000" poissonRatio="0.3" method="large"/>
    <SphereCollisionModel radius="0.1" contactStiffness="200"/>
  </Node>
  <Node name="Floor">
    <RegularGridTopology nx="50" ny="1" nz="50" xmin="0" xmax="9.8" ymin="0" ymax="0" zmin="0" zmax="9.8"/>
    <MechanicalObject name="points"/>
    <PointCollisionModel simulated="0" moving="0" contactStiffness="200"/>
  </Node>
</Node>"""


def test_a_static_floors_forces_are_the_reactions_of_its_current_contacts(tmp_path):
    # The floor (2 500 points, in no solver's subtree) is the cube solver's scratch: a solve
    # clears only the rows that solves wrote (docs/python.md). After each step its forces must be
    # the reactions of that step's contacts (f2 += normal_force·n on the Point side) in those
    # rows and 0 in every other, while the cube slides onto new rows.
    path = tmp_path / "floor.scn"
    path.write_text(STATIC_FLOOR)
    scene = penalty.load_scene(path)
    floor = scene.states["/Floor/points"]
    assert floor.size == 2500 and not floor.in_solver_subtree and not floor.mapped
    previous_rows, rows_left, steps_forced = set(), 0, 0
    for _ in range(60):
        scene.step()
        contacts = scene.contacts()
        assert contacts["pairs"] == ["SphereCollisionModel-PointCollisionModel"]
        expected = np.zeros((floor.size, 3))
        for row, force, normal in zip(contacts["dof2"], contacts["normal_force"], contacts["normal"]):
            expected[row] += force * normal
        np.testing.assert_allclose(floor.forces, expected, rtol=1e-12, atol=0)
        rows = set(np.nonzero(np.any(expected != 0, axis=1))[0])
        steps_forced += bool(rows)
        rows_left += len(previous_rows - rows)
        previous_rows = rows
    assert steps_forced >= 40  # the cube bounces, then slides on the floor
    assert rows_left >= 20  # rows forced at one step and no longer at the next: cleared


def test_a_callback_that_breaks_a_static_state_is_caught():
    # No step moves the static marker, so `penalty run` checks it after the first step only; a
    # callback may change any state between the steps, so with one the run checks it every step.
    scene = penalty.load_scene(REPO / "tests" / "scene" / "data" / "free_fall_beside_a_marker.scn")
    velocities = scene.states["/Marker/m"].velocities

    def break_marker(done, total):
        if done == 3:
            velocities[0, 2] = np.nan

    with pytest.raises(penalty.DivergedError, match=r"step 3 \(t = 0\.4.*'/Marker/m' DOF 0 is not finite"):
        scene.run(6, progress=False, callback=break_marker)


def test_run_writes_the_browser_viewer(scene, output_dir):
    # The same viewer as `penalty run --view`: 40 steps kept one in 10 give frames at steps
    # 0, 10, 20, 30 and the end (t = 0.2 s); the manifest's per-frame times and contact counts
    # are those of the run.
    import json
    scene.run(40, view=output_dir / "view", view_every=10, stats=output_dir / "stats.csv", progress=False)
    manifest = json.loads((output_dir / "view" / "run.json").read_text())
    frames = manifest["frames"]
    assert frames["count"] == 5
    assert frames["time"] == pytest.approx([0.0, 0.05, 0.1, 0.15, 0.2])
    rows = list(csv.DictReader(open(output_dir / "stats.csv")))
    assert frames["contacts"][-1] == int(rows[-1]["contacts"])
    assert (output_dir / "view" / "index.html").is_file()
    assert (output_dir / "view" / "positions.f32").stat().st_size > 0
