"""The rest of SofaPython3's API scripts use (docs/python.md, "SofaPython3's API"):
Sofa.Simulation.load/unload/reset, Sofa.import_sofa_python_scene, Sofa.Helper's messages and
MessageHandler, SofaRuntime.Timer, `with node:`, getContext(), Sofa.Gui as SOFA's batch GUI,
unavailable modules failing only when used, and the matrices of a force field and a mass (those
the implicit solve uses)."""
import importlib
import os
import sys

import numpy as np
import pytest

import penalty
from penalty import sofa_api

penalty._install_sofa_path()
import Sofa  # noqa: E402  (penalty's, from penalty.sofa_path)
import Sofa.Gui  # noqa: E402
import Sofa.Helper  # noqa: E402
import SofaRuntime  # noqa: E402


def falling(root=None):
    root = root or Sofa.Core.Node("root")
    with root.addChild("Ball") as ball:
        ball.addObject("EulerImplicitSolver")
        ball.addObject("CGLinearSolver", iterations=25, tolerance=1e-9, threshold=1e-9)
        ball.addObject("MechanicalObject", name="dofs", position=[0, 1, 0])
        ball.addObject("UniformMass", name="mass", totalMass=2)
    return root


def test_reset_puts_the_states_back_and_keeps_written_data_and_memory():
    root = falling()
    Sofa.Simulation.init(root)
    view = root.Ball.dofs.position.value
    for _ in range(5):
        Sofa.Simulation.animate(root, root.dt.value)
    assert root.Ball.dofs.position.value[0, 1] < 1.0
    root.gravity.value = [0, -1, 0]
    Sofa.Simulation.reset(root)
    assert root.time.value == 0.0 and root.Ball.dofs.position.value[0, 1] == 1.0
    assert np.shares_memory(view, root.Ball.dofs.position.value)
    assert root.gravity.value.tolist() == [0, -1, 0]


def test_unload_empties_the_root():
    root = falling()
    Sofa.Simulation.init(root)
    Sofa.Simulation.unload(root)
    assert len(root.children) == 0 and len(root.objects) == 0


def test_load_a_scn_file_as_nodes(tmp_path):
    scn = tmp_path / "two.scn"
    scn.write_text('<Node dt="0.005" gravity="0 0 0"><Node name="child1"><MechanicalObject template="Rigid3d" '
                   'position="0 0 0 0 0 0 1"/></Node><Node name="child2"><MechanicalObject template="Rigid3d" '
                   'position="1 1 1 0 0 0 1"/></Node></Node>')
    loaded = Sofa.Simulation.load(str(scn))
    root = Sofa.Core.Node("root")
    root.addChild(loaded)
    assert [c.name.value for c in loaded.children] == ["child1", "child2"]
    Sofa.Simulation.init(root)
    assert root.root.child2.MechanicalObject.position.value.tolist() == [[1, 1, 1, 0, 0, 0, 1]]


def test_import_sofa_python_scene(tmp_path):
    (tmp_path / "piece.py").write_text("def createScene(root):\n    root.addObject('MechanicalObject', name='m', "
                                       "position=[0, 0, 0])\n")
    module = Sofa.import_sofa_python_scene(str(tmp_path / "piece.py"))
    root = Sofa.Core.Node("root")
    module.createScene(root.addChild("A"))
    Sofa.Simulation.init(root)
    assert root.A.m.position.value.tolist() == [[0, 0, 0]]


def test_messages_and_message_handler(capsys):
    seen = []

    class Handler(Sofa.Helper.MessageHandler):
        def process(self, msg):
            seen.append(msg)

    root = falling()
    with Handler():
        Sofa.Helper.msg_info("plain info")
        Sofa.Helper.msg_warning(root.Ball.dofs, "object warning")
        Sofa.Helper.msg_error("Sender", "string sender error")
    Sofa.Helper.msg_info("after the block")
    out, err = capsys.readouterr()
    # as SOFA HEAD through SofaPython3 (errors on stderr, the others on stdout)
    assert "[INFO]    [PythonScript] plain info" in out
    assert "[WARNING] [MechanicalObject(dofs)] object warning" in out
    assert "[ERROR]   [Sender] string sender error" in err
    assert [(m["type"], m["sender"], m["message"]) for m in seen] == [
        ("Info", "PythonScript", "plain info"), ("Warning", "MechanicalObject", "object warning"),
        ("Error", "Sender", "string sender error")]
    assert seen[1]["component"] is root.Ball.dofs


def test_timer_records_a_named_interval():
    SofaRuntime.Timer.setEnabled("t", True)
    SofaRuntime.Timer.begin("t")
    SofaRuntime.Timer.end("t")
    assert SofaRuntime.Timer.isEnabled("t") and SofaRuntime.Timer.getRecords("t")["total_time"] >= 0.0


def test_context_and_time():
    root = falling()
    Sofa.Simulation.init(root)
    Sofa.Simulation.animate(root, 0.01)
    ctx = root.Ball.dofs.getContext()
    assert ctx is root.Ball and ctx.getTime() == pytest.approx(0.01) and ctx.getDt() == 0.01
    assert ctx.getGravity().tolist() == [0, -9.81, 0]


def test_gui_main_loop_runs_as_sofas_batch_gui(monkeypatch, capsys):
    monkeypatch.setenv("PENALTY_GUI_ITERATIONS", "7")
    root = falling()
    Sofa.Simulation.init(root)
    Sofa.Gui.GUIManager.Init("myscene", "imgui")
    Sofa.Gui.GUIManager.createGUI(root, __file__)
    Sofa.Gui.GUIManager.SetDimension(1080, 1080)
    Sofa.Gui.GUIManager.MainLoop(root)
    Sofa.Gui.GUIManager.closeGUI()
    assert root.time.value == pytest.approx(0.07)
    assert "[INFO]    [BatchGUI] Computing 7 iterations." in capsys.readouterr().out


def test_unavailable_modules_fail_only_when_used():
    gui_plugin = importlib.import_module("SofaImGui")  # imports
    from Sofa import SofaDeformable  # noqa: F401  (a name of an unavailable module imports too)
    from Sofa.Types import RGBAColor
    with pytest.raises(ImportError, match=r"SofaImGui.init\(...\): SofaImGui is not available in penalty .SOFA's ImGui GUI"):
        gui_plugin.init()
    with pytest.raises(ImportError, match=r"Sofa.Types.RGBAColor\(...\): Sofa.Types is not available in penalty"):
        RGBAColor("blue")
    assert "SofaImGui" in sys.modules


def test_stiffness_and_mass_matrices_are_those_of_the_solve():
    root = Sofa.Core.Node("root")
    with root.addChild("Beam") as beam:
        beam.addObject("EulerImplicitSolver")
        beam.addObject("CGLinearSolver", iterations=25, tolerance=1e-9, threshold=1e-9)
        beam.addObject("RegularGridTopology", nx=2, ny=2, nz=3, xmin=0, xmax=1, ymin=0, ymax=1, zmin=0, zmax=2)
        beam.addObject("MechanicalObject", name="dofs")
        beam.addObject("UniformMass", name="mass", totalMass=12)
        beam.addObject("HexahedronFEMForceField", name="fem", youngModulus=1000, poissonRatio=0.3)
    Sofa.Simulation.init(root)
    for _ in range(3):
        Sofa.Simulation.animate(root, root.dt.value)
    k = root.Beam.fem.assembleKMatrix()
    m = root.Beam.mass.assembleMMatrix()
    assert k.shape == (36, 36) and m.shape == (36, 36)
    np.testing.assert_allclose(m.diagonal(), 1.0)  # 12 kg on 12 points
    core = root._penalty_scene._scene
    dx = np.random.default_rng(1).normal(size=(12, 3))
    core._probe_force("/Beam/fem", root.Beam.dofs.position.value, root.Beam.dofs.velocity.value)
    np.testing.assert_allclose(k @ dx.ravel(), core._probe_dforce("/Beam/fem", dx, 1.0, 0.0).ravel(), rtol=1e-12,
                               atol=1e-9)
    assert np.allclose(k.toarray(), k.toarray().T)
    os.environ.pop("PENALTY_GUI_ITERATIONS", None)
