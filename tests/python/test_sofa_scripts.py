"""SofaPython3 scene scripts, unchanged: the Sofa / Sofa.Core / Sofa.Simulation / SofaRuntime
subset, controllers, data fields, errors naming the script's line, `penalty run scene.py`, and the
11 shared SOFA scenes rewritten as scripts giving bit-identical trajectories to their .scn."""
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import penalty
from penalty import sofa_api

HERE = Path(__file__).resolve().parent
SCRIPTS = HERE / "scripts"
SOFA_SCENES = HERE / "sofa_scenes"
REPO = HERE.parents[1]

SHARED_SCENES = ["AdvancedSolversMultipleGroupsSolver", "CompositeCollisionPipeline", "CompositeCollisionPipeline_none",
                 "Gravity", "MeshSpringForceField", "ModelizationSphereBased", "ModelizationTriangleBased",
                 "MultipleObjectsTwoCubes", "RegularGridSpringForceField", "SphereModel", "collisionMultiple"]


def load_script(path, data_dirs=(), **kwargs):
    """Runs createScene(root, **kwargs) of a script and builds it."""
    penalty._install_sofa_path()  # `import Sofa` in the script
    root = sofa_api.Node("root")
    namespace = {}
    exec(compile(Path(path).read_text(), str(path), "exec"), namespace)
    namespace["createScene"](root, **kwargs)
    object.__setattr__(root, "_file", str(path))
    sofa_api.init(root, build_options=([str(d) for d in data_dirs], None, 0, False))
    return root._penalty_scene


def test_script_scene_steps_and_controller_runs_every_step():
    scene = penalty.load_scene(SCRIPTS / "falling_cube.py")
    recorder = scene.root.recorder
    assert scene.dt == 0.01
    scene.step(150)
    assert recorder.begin_calls == 150 and recorder.end_calls == 150
    # the cube fell from y = 1 and rests on the floor: its lowest point is near y = 0, kept above
    # −contactDistance by the contacts (penalty springs allow a small penetration)
    assert recorder.lowest[0] < 1.0
    assert -0.1 < recorder.lowest[-1] < 0.15
    assert len(scene.contacts()["penetration"]) > 0


def test_data_fields_view_the_state():
    scene = penalty.load_scene(SCRIPTS / "falling_cube.py")
    dofs = scene.root.Cube.dofs
    value = dofs.position.value
    assert value.shape == (8, 3)
    assert np.shares_memory(value, scene.states["/Cube/dofs"].positions)
    assert not value.flags.writeable  # .value is read-only, as SofaPython3's
    np.testing.assert_array_equal(dofs.findData("position").value, value)
    np.testing.assert_array_equal(dofs.position.array(), value)
    with dofs.position.writeableArray() as wa:
        wa[:, 1] += 3.0
    assert scene.states["/Cube/dofs"].positions[:, 1].min() == 4.0
    assert scene.root.dt.value == 0.01
    np.testing.assert_array_equal(scene.root.gravity.value, [0, -9.81, 0])
    assert scene.root.Cube.name.value == "Cube"
    assert scene.root.getChild("Floor").getObject("triangles").getClassName() == "TriangleCollisionModel"
    assert dofs.getLinkPath() == "@/Cube/dofs"


def test_controller_writes_through_writeable_array():
    # same scene, the controller gives the cube 1 m/s along x at the first step: it drifts along +x
    scene = load_script(SCRIPTS / "falling_cube.py", push=1.0)
    root = scene.root
    x0 = scene.states["/Cube/dofs"].positions[:, 0].mean()
    sofa_api.animate(root, 0.01)
    sofa_api.animate(root, root.dt.value)
    assert scene.time == pytest.approx(0.02)
    assert scene.states["/Cube/dofs"].positions[:, 0].mean() - x0 == pytest.approx(0.02, rel=0.05)


def test_links_as_objects_and_data_equal_links_as_text():
    data = [REPO / "scenes"]
    a = load_script(SCRIPTS / "plate_links.py", data, links_as_objects=True)
    b = load_script(SCRIPTS / "plate_links.py", data, links_as_objects=False)
    assert a.states["plate"].positions.shape == (81, 3)
    for _ in range(80):
        a.step()
        b.step()
    np.testing.assert_array_equal(a.states["ball"].positions, b.states["ball"].positions)
    # the ball (r = 0.1 m) rests on the plate (y = 0) at about C + r = 0.12 m
    assert 0.1 < a.states["ball"].positions[0, 1] < 0.15
    assert len(a.contacts()["penetration"]) > 0


def test_bad_attribute_names_the_script_line():
    path = SCRIPTS / "bad_attribute.py"
    with pytest.raises(penalty.SceneError) as error:
        penalty.load_scene(path)
    assert str(error.value) == f"{path}:8: UniformMass 'mass': attribute 'totalMass': expected a number, found 'abc'"


def test_unsupported_api_names_what_is_missing():
    with pytest.raises(AttributeError, match=r"Sofa\.Core\.Mapping_Vec1d_Vec1d is not available in penalty's SofaPython3"):
        penalty.load_scene(SCRIPTS / "unsupported_api.py")
    root = sofa_api.Node("root")
    root.addObject("MechanicalObject", name="m", position=[0, 0, 0])
    sofa_api.init(root)
    with pytest.raises(AttributeError, match="Node 'root' has no attribute 'Missing'"):
        root.Missing
    with pytest.raises(AttributeError, match=r"MechanicalObject 'm' has no attribute 'positon' \(did you mean 'position'"):
        root.m.positon


def test_values_become_sofa_text():
    assert sofa_api.to_sofa_text([[0, 1.5], np.array([2.0, 1e-9])], "x") == "0 1.5 2.0 1e-09"
    assert sofa_api.to_sofa_text(True, "x") == "1"
    assert sofa_api.to_sofa_text(np.float64(0.1), "x") == "0.1"
    with pytest.raises(TypeError, match="attribute 'x'"):
        sofa_api.to_sofa_text({"a": 1}, "attribute 'x'")


def test_names_set_as_data_rename():
    root = sofa_api.Node("root")
    child = root.addChild("A")
    child.name = "Body"
    child.addObject("MechanicalObject", name="m", position=[0, 0, 0])
    child.m.name.value = "dofs"
    sofa_api.init(root)
    assert root._penalty_scene.states.keys() == ["/Body/dofs"]


def test_controller_exception_stops_the_run():
    class Stop(sofa_api.Controller):
        def onAnimateEndEvent(self, event):
            if self.getContext().getTime() >= 0.05 - 1e-12:
                raise StopIteration("enough")

    root = sofa_api.Node("root")
    body = root.addChild("Body")
    body.addObject("EulerImplicitSolver")
    body.addObject("CGLinearSolver", iterations=25, tolerance=1e-9, threshold=1e-9)
    body.addObject("MechanicalObject", name="dofs", position=[0, 1, 0])
    body.addObject("UniformMass", totalMass=1)
    root.addObject(Stop(name="stop"))
    sofa_api.init(root)
    scene = root._penalty_scene
    with pytest.raises(StopIteration, match="enough"):
        scene.run(100, progress=False)
    assert scene.time == pytest.approx(0.05)


def test_scene_with_controllers_is_freed():
    import gc
    import weakref
    scene = penalty.load_scene(SCRIPTS / "falling_cube.py")
    scene.step(2)
    positions = scene.states["/Cube/dofs"].positions
    expected = positions.copy()
    wrapper, core = weakref.ref(scene), weakref.ref(scene._scene)
    del scene
    gc.collect()
    assert wrapper() is None         # the script's nodes, controllers and hooks form no leaking cycle
    assert core() is not None        # the view keeps the C++ scene alive...
    np.testing.assert_array_equal(positions, expected)
    del positions
    gc.collect()
    assert core() is None            # ...and nothing else does


def test_reset_rebuilds_the_scene():
    root = sofa_api.Node("root")
    child = root.addChild("Ball")
    child.addObject("EulerImplicitSolver")
    child.addObject("CGLinearSolver", iterations=25, tolerance=1e-9, threshold=1e-9)
    child.addObject("MechanicalObject", name="dofs", position=[0, 1, 0])
    child.addObject("UniformMass", totalMass=1)
    sofa_api.init(root)
    for _ in range(5):
        sofa_api.animate(root)
    assert root.Ball.dofs.position.value[0, 1] < 1.0
    sofa_api.reset(root)
    assert root.time.value == 0.0
    assert root.Ball.dofs.position.value[0, 1] == 1.0


def test_standalone_script_runs_with_python():
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([penalty.sofa_path, str(Path(penalty.__file__).parents[1])]))
    r = subprocess.run([sys.executable, str(SCRIPTS / "falling_cube.py")], capture_output=True, text=True, env=env)
    assert r.returncode == 0, r.stderr
    assert "after 150 steps" in r.stdout


def test_script_command_runs_the_main_block():
    env = dict(os.environ, PYTHONPATH=str(Path(penalty.__file__).parents[1]))
    r = subprocess.run([sys.executable, "-m", "penalty", "script", str(SCRIPTS / "falling_cube.py")],
                       capture_output=True, text=True, env=env)
    assert r.returncode == 0, r.stderr
    assert "after 150 steps" in r.stdout


def cli():
    exe = os.environ.get("PENALTY_CLI", str(REPO / "build" / "release" / "bin" / "penalty"))
    if not Path(exe).exists():
        pytest.skip("penalty command line not built")
    return exe


def test_cli_runs_a_script(tmp_path):
    r = subprocess.run([cli(), "run", str(SCRIPTS / "falling_cube.py"), "--steps", "50", "--quiet",
                        "--stats", str(tmp_path / "s.csv")], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert "steps: 50" in r.stdout
    assert len((tmp_path / "s.csv").read_text().splitlines()) == 51
    bad = subprocess.run([cli(), "run", str(SCRIPTS / "bad_attribute.py")], capture_output=True, text=True)
    assert bad.returncode == 1
    assert f"bad_attribute.py:8: UniformMass 'mass': attribute 'totalMass'" in bad.stderr


@pytest.mark.parametrize("name", SHARED_SCENES)
def test_shared_scene_script_is_bit_identical_to_scn(name, shared_sofa):
    scn = penalty.load_scene(shared_sofa / "scenes" / f"{name}.scn", data_dirs=[shared_sofa])
    script = penalty.load_scene(SOFA_SCENES / f"{name}.py", data_dirs=[shared_sofa])
    # the same states in the same order; an unnamed MechanicalObject is "MechanicalObject1" in a .scn
    # (SOFA's XML naming) and "MechanicalObject" in a script (SofaPython3's), as in SOFA
    assert [s.node_path for s in script.states] == [s.node_path for s in scn.states]
    assert [s.name.rstrip("1") for s in script.states] == [s.name.rstrip("1") for s in scn.states]
    for step in range(300):
        scn.step()
        script.step()
        for a, b in zip(scn.states, script.states):
            assert np.array_equal(a.positions, b.positions) and np.array_equal(a.velocities, b.velocities), \
                f"{name}: state {a.path} differs at step {step}"
    assert scn.time == script.time


def test_cli_outputs_of_a_script_equal_those_of_its_scn(shared_sofa, tmp_path):
    outputs = {}
    for kind, scene in (("scn", shared_sofa / "scenes" / "CompositeCollisionPipeline.scn"),
                        ("py", SOFA_SCENES / "CompositeCollisionPipeline.py")):
        out = tmp_path / kind
        r = subprocess.run([cli(), "run", str(scene), "--data-dir", str(shared_sofa), "--steps", "60", "--quiet",
                            "--export-states", str(out / "states"), "--vtk", str(out / "vtk")],
                           capture_output=True, text=True)
        assert r.returncode == 0, r.stderr
        outputs[kind] = {p.relative_to(out): p.read_bytes() for p in sorted(out.rglob("*")) if p.is_file()}
    assert len(outputs["scn"]) > 10
    assert outputs["scn"].keys() == outputs["py"].keys()
    for name, content in outputs["scn"].items():
        assert outputs["py"][name] == content, f"{name} differs"


def test_a_script_with_a_direct_solver_and_a_mesh_matrix_mass_gives_the_scn_scenes_numbers():
    # MessageHandler.py's scene as a script, and the same beam in a .scn file (its first node; the
    # .scn's MatrixLinearSystem and natural ordering change the rounding only): 20 steps
    script = penalty.load_scene(SCRIPTS / "beam_direct_solver.py")
    scn = penalty.load_scene(REPO / "tests" / "scene" / "data" / "solvers" / "hexa_beam_matrix_mass_ldl.scn")
    script.step(20)
    scn.step(20)
    a = script.states["/Beam/DoFs"].positions
    b = scn.states["/Beam/DoFs"].positions
    assert np.abs(a - b).max() < 1e-9
    assert a[:, 1].min() < -0.5  # the free end went down: the beam bends under its weight
    info = script.info()
    roles = {c["type"]: c["role"] for c in info["components"]}
    assert "LDLT" in roles["SparseLDLSolver"]
    assert "consistent mass matrix of the hexahedra" in roles["MeshMatrixMass"]


def test_a_script_reads_a_mass_matrix_and_a_stiffness_matrix():
    # SofaPython3's Mass.assembleMMatrix() and ForceField.assembleKMatrix() (access_mass_matrix.py,
    # access_stiffness_matrix.py): scipy matrices over the component's state
    scene = penalty.load_scene(SCRIPTS / "beam_direct_solver.py")
    beam = scene.root.Beam
    m = beam.mass.assembleMMatrix()
    k = beam.FEM.assembleKMatrix()
    assert m.shape == (480, 480) and k.shape == (480, 480)
    assert abs(m.sum() / 3 - 320.0) < 1e-9  # the beam's mass, on each of the three components
    assert abs(m - m.T).max() < 1e-12 and m[0, 3] > 0  # consistent: the edges' blocks
    assert abs(k - k.T).max() < 1e-9 * abs(k).max()
    translation = np.tile([1.0, 0.0, 0.0], 160)
    assert np.abs(k @ translation).max() < 1e-9 * abs(k).max()  # a rigid translation stores no energy
    with pytest.raises(ValueError, match="not a mass"):
        beam.FEM.assembleMMatrix()
