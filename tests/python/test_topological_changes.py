"""Topological changes from Python (docs/topological-changes.md): the scene's dynamic topologies,
removals and additions between steps with every component following, errors that change nothing,
numpy views of states that shrink and grow, and SofaPython3 controllers calling the modifiers'
removeTetrahedra / addPoints."""
from pathlib import Path

import numpy as np
import pytest

import penalty
from penalty import sofa_api

HERE = Path(__file__).resolve().parent
SCRIPTS = HERE / "scripts"


def _cube_scene(tmp_path, extra=""):
    """The tetrahedral cube of scripts/cut_cube.py as a .scn file (27 points, 48 tetrahedra)."""
    import importlib.util
    spec = importlib.util.spec_from_file_location("cut_cube_mesh", SCRIPTS / "cut_cube.py")
    penalty._install_sofa_path()
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    points, tets = module.grid_tetrahedra(2, 0.5)
    text = f"""<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <Node name="Cube">
    <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
    <CGLinearSolver iterations="100" tolerance="1e-12" threshold="1e-12"/>
    <TetrahedronSetTopologyContainer name="volume" position="{' '.join(' '.join(map(str, p)) for p in points)}"
        tetrahedra="{' '.join(' '.join(map(str, t)) for t in tets)}"/>
    <TetrahedronSetTopologyModifier/>
    <MechanicalObject name="dofs"/>
    <DiagonalMass massDensity="1000"/>
    <TetrahedronFEMForceField youngModulus="1e5" poissonRatio="0.3" method="large"/>
    {extra}
  </Node>
</Node>
"""
    path = tmp_path / "cube.scn"
    path.write_text(text)
    return penalty.load_scene(path), points, tets


def test_topologies_and_their_elements(tmp_path):
    scene, points, tets = _cube_scene(tmp_path)
    assert scene.topologies() == ["/Cube/volume"]
    t = scene.topology("/Cube/volume")
    assert t["level"] == "tetrahedra" and t["points"] == 27
    np.testing.assert_array_equal(t["tetrahedra"], tets)
    assert t["tetrahedra"].dtype == np.int32 and t["triangles"].shape[1] == 3
    assert scene.topology("volume")["revision"] == t["revision"]  # by name too
    with pytest.raises(ValueError, match="/Cube/volume"):
        scene.topology("nope")


def test_remove_tetrahedra_swaps_the_last_into_the_hole(tmp_path):
    scene, points, tets = _cube_scene(tmp_path)
    scene.step(2)
    revision = scene.topology("volume")["revision"]
    scene.remove_elements("/Cube/volume", "tetrahedra", [0])
    t = scene.topology("volume")
    # SOFA's removeTetrahedraProcess: the last tetrahedron takes index 0
    assert len(t["tetrahedra"]) == 47
    np.testing.assert_array_equal(t["tetrahedra"][0], tets[-1])
    np.testing.assert_array_equal(t["tetrahedra"][1:], tets[1:-1])
    assert t["revision"] != revision
    assert t["points"] == 27  # every point is still used by another tetrahedron
    scene.step(3)  # the mass and the force field follow: the run goes on
    assert np.all(np.isfinite(scene.states["/Cube/dofs"].positions))


def test_bad_removals_change_nothing(tmp_path):
    scene, _, tets = _cube_scene(tmp_path)
    before = scene.topology("volume")
    for bad, message in (([48], "tetrahedra 48 .entry 0.: out of range, the container has 48"),
                       ([3, 3], "tetrahedra 3 is listed twice"), ([-1], "out of range")):
        with pytest.raises(ValueError, match=message):
            scene.remove_elements("volume", "tetrahedra", bad)
    with pytest.raises(ValueError, match="unknown element kind 'prisms'"):
        scene.remove_elements("volume", "prisms", [0])
    after = scene.topology("volume")
    np.testing.assert_array_equal(after["tetrahedra"], before["tetrahedra"])
    assert after["revision"] == before["revision"]


def test_numpy_views_after_the_state_shrinks_and_grows(tmp_path):
    scene, points, tets = _cube_scene(tmp_path)
    dofs = scene.states["/Cube/dofs"]
    view = dofs.positions
    assert view.shape == (27, 3)
    # the tetrahedra around point 0 (a corner): removing them leaves it isolated, so it goes, and
    # the last point (26) takes its index (SOFA's swap-and-pop of the state)
    around = [k for k, t in enumerate(tets) if 0 in t]
    last = view[26].copy()
    scene.remove_elements("volume", "tetrahedra", around)
    now = dofs.positions
    assert now.shape == (26, 3)
    np.testing.assert_array_equal(now[0], last)
    # the old view still points at valid memory: its first 26 rows are the state
    assert view.shape == (27, 3)
    np.testing.assert_array_equal(view[:26], now)
    # growth: two points appended, each at the mean of its ancestors
    scene.add_elements("volume", "points", count=2, ancestors=[[1, 2], [4, 13]])
    grown = dofs.positions
    assert grown.shape == (28, 3)
    np.testing.assert_allclose(grown[26], (now[1] + now[2]) / 2)
    np.testing.assert_allclose(grown[27], (now[4] + now[13]) / 2)
    assert scene.topology("volume")["points"] == 28
    # a degenerate tetrahedron (four points in the plane z = 0) is refused, nothing changes
    with pytest.raises(ValueError, match=r"new tetrahedron 0 \(26 1 2 4\) is degenerate"):
        scene.add_elements("volume", "tetrahedra", [[26, 1, 2, 4]])
    assert len(scene.topology("volume")["tetrahedra"]) == 48 - len(around)
    # tetrahedra on the new points: their faces and edges are created
    scene.add_elements("volume", "tetrahedra", [[26, 4, 27, 2]])
    t = scene.topology("volume")
    assert len(t["tetrahedra"]) == 48 - len(around) + 1
    assert any(set(f) == {26, 27, 4} for f in t["triangles"].tolist())
    scene.step(2)
    assert np.all(np.isfinite(dofs.positions))


def load_script(path, **kwargs):
    penalty._install_sofa_path()
    root = sofa_api.Node("root")
    namespace = {}
    exec(compile(Path(path).read_text(), str(path), "exec"), namespace)
    namespace["createScene"](root, **kwargs)
    object.__setattr__(root, "_file", str(path))
    sofa_api.init(root)
    return root._penalty_scene


def test_controller_removes_tetrahedra_through_the_modifier():
    scene = load_script(SCRIPTS / "cut_cube.py", cut_from=3)
    root = scene.root
    for _ in range(10):
        sofa_api.animate(root, root.dt.value)
    assert root.cutter.steps == 10
    t = scene.topology("/Cube/volume")
    assert len(t["tetrahedra"]) == 48 - 8
    positions = scene.states["/Cube/dofs"].positions
    assert positions.shape[0] == t["points"]
    assert np.all(np.isfinite(positions))


def test_modifier_errors_name_the_component():
    scene = load_script(SCRIPTS / "cut_cube.py", cut_from=1000)
    modifier = scene.root.Cube.modifier
    with pytest.raises(ValueError, match="out of range"):
        modifier.removeTetrahedra([480])
    with pytest.raises(NotImplementedError, match="removeTetrahedra"):
        modifier.removeTetrahedra([0], False)
    modifier.addPoints(1)
    assert scene.states["/Cube/dofs"].positions.shape == (28, 3)
