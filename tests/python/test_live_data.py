"""The live object model (docs/python.md, "The object model"): every Data of a built component or
node reads its current value with SOFA's type, and a write after init changes the next step as
SOFA's component takes it, checked bit for bit against a fresh scene built with the new value (and
against SOFA HEAD's behaviour where it differs from a fresh build: the delay of a gravity write)."""
from pathlib import Path

import numpy as np
import pytest

import penalty
from penalty import _core, sofa_api
from penalty.sofa_api.graph import type_fields
from penalty.sofa_api.text import parse_value

HERE = Path(__file__).resolve().parent
SOFA_SCENES = HERE / "sofa_scenes"


def beam(young=100.0, box=(-1, -1, -0.1, 2, 2, 0.1), indices="@box.indices", kind="hexa", gravity=(0, -9.81, 0),
         rayleigh=0.1, iterations=50, total_mass=1.0, stiffness=100.0, dt=0.01, fixes=()):
    """A 3x3x4 grid beam fixed at z = 0, under gravity (what SOFA HEAD ran for the write table);
    `fixes`: SOFA quirks to fix (--fix-sofa-quirk)."""
    root = sofa_api.Node("root")
    root.gravity = list(gravity)
    root.dt = dt
    root.addObject("DefaultAnimationLoop")
    n = root.addChild("B")
    n.addObject("EulerImplicitSolver", name="ode", rayleighStiffness=rayleigh, rayleighMass=0.1)
    n.addObject("CGLinearSolver", name="cg", iterations=iterations, tolerance=1e-12, threshold=1e-12)
    n.addObject("RegularGridTopology", name="grid", nx=3, ny=3, nz=4, xmin=0, xmax=1, ymin=0, ymax=1, zmin=0, zmax=2)
    n.addObject("MechanicalObject", name="mo")
    n.addObject("UniformMass", name="mass", totalMass=total_mass)
    n.addObject("BoxROI", name="box", box=list(box))
    n.addObject("FixedProjectiveConstraint", name="fix", indices=indices)
    if kind == "hexa":
        n.addObject("HexahedronFEMForceField", name="ff", youngModulus=young, poissonRatio=0.3)
    elif kind == "tetra":
        n.addObject("TetrahedronFEMForceField", name="ff", youngModulus=young, poissonRatio=0.3)
    elif kind == "springs":
        n.addObject("MeshSpringForceField", name="ff", stiffness=stiffness, damping=0)
    elif kind == "grid_springs":
        n.addObject("RegularGridSpringForceField", name="ff", stiffness=stiffness, damping=0)
    sofa_api.init(root, build_options=([], None, 0, False, [], list(fixes)))
    return root


def run(root, steps=5):
    for _ in range(steps):
        sofa_api.animate(root, root.dt.value)
    return root.B.mo.position.value.copy(), root.B.mo.velocity.value.copy()


def same(a, b):
    return all(np.array_equal(x, y) for x, y in zip(a, b))


# ---- reading ------------------------------------------------------------------------------------

def test_data_read_with_sofa_types_after_init():
    root = beam()
    ff, mo, box, fix, mass = root.B.ff, root.B.mo, root.B.box, root.B.fix, root.B.mass
    # SOFA HEAD through SofaPython3 prints the same for this scene (docs/python.md)
    assert isinstance(ff.youngModulus.value, np.ndarray) and ff.youngModulus.value.tolist() == [100.0]
    assert ff.method.value == "large" and isinstance(ff.method.value, str)
    assert ff.poissonRatio.value.tolist() == [0.3]
    assert box.indices.value.dtype == np.int32 and box.indices.value.tolist() == [0, 1, 2, 3, 4, 5, 6, 7, 8]
    assert fix.indices.value.tolist() == box.indices.value.tolist()  # the linked Data reads its parent's value
    assert fix.indices.getValueString() == "0 1 2 3 4 5 6 7 8"
    assert fix.indices.getLinkPath() == "@/B/fix.indices" and str(fix.indices.linkpath) == "@/B/fix.indices"
    assert isinstance(root.dt.value, float) and root.dt.value == 0.01
    assert root.gravity.value.tolist() == [0, -9.81, 0] and root.gravity.getValueString() == "0 -9.81 0"
    assert mass.totalMass.value == 1.0 and mass.vertexMass.value == pytest.approx(1.0 / 36)
    assert mo.position.value.shape == (36, 3) and not mo.position.value.flags.writeable
    assert ff.printLog.value == 0 and isinstance(ff.printLog.value, int)  # SOFA's bool Data read as int
    assert mo.name.value == "mo" and mo.getPathName() == "/B/mo" and mo.getLinkPath() == "@/B/mo"
    assert str(mo.linkpath) == "@/B/mo" and mo.linkpath.target() is mo
    assert root.B.ff.getClassName() == "HexahedronFEMForceField"


def test_unnamed_objects_take_sofapython3s_names():
    root = sofa_api.Node("root")
    a = root.addChild("A")
    mo = a.addObject("MechanicalObject", position=[0, 0, 0])
    fix = a.addObject("FixedConstraint", indices=[0])
    assert mo.name.value == "MechanicalObject"      # SofaPython3: the class name, no counter
    assert fix.name.value == "FixedProjectiveConstraint"  # the older name gives SOFA's class
    sofa_api.init(root)
    assert root._penalty_scene.states.keys() == ["/A/MechanicalObject"]
    assert root.A.MechanicalObject.position.value.tolist() == [[0, 0, 0]]


def _read_everything(root):
    """Reads every Data of every built component and node; returns how many were compared with
    their default (not written by the script, not a live value)."""
    compared = 0
    nodes = [root]
    while nodes:
        node = nodes.pop()
        nodes.extend(node._children)
        for d in node.getDataFields():
            d.value
        for obj in node._objects:
            if getattr(obj, "_python", False):
                continue
            fields = obj._fields()
            for name, field in fields.items():
                if field.get("link"):
                    obj.findLink(name).getValueString()
                    continue
                value = obj._make_data(name).value
                written = name in obj._values
                built_topology = "Topology" in obj._type and name in (
                    "edges", "triangles", "quads", "tetrahedra", "hexahedra", "tetras", "hexas")
                live = built_topology or field["live"] == "state" or field["live"] == "read-only" or name in (
                    "name", "size", "vertexMass", "totalMass", "indices", "position", "listRadius")
                if written or live or field["default"] == "" or field["python_form"] == "none":
                    continue
                expected = parse_value(field["default"], field["python_form"], field.get("columns", 0))
                if isinstance(expected, np.ndarray):
                    assert np.array_equal(np.asarray(value), expected), f"{obj._describe()}.{name}"
                else:
                    assert value == expected, f"{obj._describe()}.{name}: {value!r} != {expected!r}"
                compared += 1
    return compared


@pytest.mark.parametrize("name", ["CompositeCollisionPipeline", "Gravity", "MeshSpringForceField", "SphereModel",
                                  "collisionMultiple", "RegularGridSpringForceField", "ModelizationTriangleBased"])
def test_every_data_of_every_component_reads_its_default(name, shared_sofa):
    scene = penalty.load_scene(SOFA_SCENES / f"{name}.py", data_dirs=[shared_sofa])
    assert _read_everything(scene.root) > 50


def test_registry_defaults_equal_sofa_defaults():
    """The registry's default of each attribute penalty reads equals SOFA's declared default (its
    catalog) for every registered type SOFA's catalog knows (Vec3d versions; MechanicalObject and
    UniformMass also Rigid3d), but the differences listed with their reason. A registry default
    "" (none: the attribute is required, or absent means empty) and links are not compared; a
    scalar 0 equals a vector of zeros."""
    checked, differ = 0, []
    for t in _core._component_types():
        for rigid in (False, True):
            if rigid and t not in ("MechanicalObject", "UniformMass"):
                continue
            sofa = {row[0]: row for row in _core._sofa_data_catalog(t, rigid)}
            for field in type_fields(t, False, rigid).values():
                name = field["name"]
                if not field["read_by_penalty"] or name not in sofa or sofa[name][4] or (t, name) in KNOWN_DIFFERENCES:
                    continue
                registry = _registry_default(t, name)
                if not registry or registry.startswith("("):
                    continue
                form = sofa[name][2].replace(":2", ":1")  # compared as flat lists of numbers
                ours = parse_value(registry, form)
                theirs = parse_value(sofa[name][3], form)
                checked += 1
                if isinstance(ours, (str, list)):
                    equal = ours == theirs
                else:
                    a, b = np.asarray(ours, dtype=float).ravel(), np.asarray(theirs, dtype=float).ravel()
                    equal = np.array_equal(a, b) or (a.size == 1 and b.size > 0 and np.all(b == a[0]))
                if not equal:
                    differ.append(f"{t}.{name}: registry {registry!r}, SOFA {sofa[name][3]!r}")
    assert checked > 60
    assert differ == []


#: Registry defaults that differ from SOFA's declared default, with the reason.
KNOWN_DIFFERENCES = {
    ("MeshSpringForceField", "stiffness"): "SOFA declares SpringForceField's per-spring stiffness vector under this "
                                           "name (default 100); in a scene the name is the alias of linesStiffness "
                                           "(default 0), which the registry describes",
    ("MeshSpringForceField", "damping"): "as stiffness: SpringForceField's vector (5) or the alias of linesDamping (0)",
    ("CollisionResponse", "response"): "SOFA's empty response means its default contact, PenalityContactForceField",
    ("MeshGmshLoader", "createSubelements"): "MeshGmshLoader::doLoad sets it to 1 when the scene does not",
    ("SpringForceField", "lengths"): "SOFA's empty list gives every spring the rest length 0, as the registry's 0",
    ("TrianglePressureForceField", "cauchyStress"): "both zero; SOFA writes the 3x3 matrix with brackets",
    ("BoxROI", "box"): "penalty's box when none is given; SOFA's Data is empty",
    ("BoxROI", "drawSize"): "drawing only",
    ("RestShapeSpringsForceField", "stiffness"): "SOFA's Data is empty until init sets 100 (what a read gives)",
    ("RestShapeSpringsForceField", "activeDirections"): "the registry's text gives both templates' defaults",
}


def _registry_default(type_name, attribute):
    for name, default in _core._registry_attribute_defaults(type_name):
        if name == attribute:
            return default
    return None


# ---- writing --------------------------------------------------------------------------------------

def test_write_youngs_modulus_takes_effect_at_reinit_as_sofa():
    fresh = run(beam(young=400.0))
    unchanged = run(beam())
    root = beam()
    root.B.ff.youngModulus.value = [400.0]
    assert root.B.ff.youngModulus.value.tolist() == [400.0]  # the Data holds it at once
    assert same(run(root), unchanged)  # SOFA HEAD: not used before reinit()
    root = beam()
    root.B.ff.youngModulus.value = [400.0]
    root.B.ff.reinit()
    assert same(run(root), fresh)
    root = beam(kind="tetra")
    root.B.ff.youngModulus.value = [400.0]
    root.B.ff.reinit()
    assert same(run(root), run(beam(kind="tetra", young=400.0)))


@pytest.mark.parametrize("write, fresh", [
    (lambda r: setattr(r.B.fix.indices, "value", [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10]),
     dict(indices=[0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10])),
    (lambda r: setattr(r.B.box.box, "value", [[-1, -1, -0.1, 2, 0.2, 0.1]]), dict(box=(-1, -1, -0.1, 2, 0.2, 0.1))),
    # SOFA HEAD's lazy UniformMass update fixed (test_live_write_quirks.py checks the quirk)
    (lambda r: setattr(r.B.mass.totalMass, "value", 3.0), dict(total_mass=3.0, fixes=["uniform_mass_lazy_write"])),
    (lambda r: setattr(r.B.ode.rayleighStiffness, "value", 0.5), dict(rayleigh=0.5)),
    (lambda r: setattr(r.B.cg.iterations, "value", 3), dict(iterations=3)),
    (lambda r: setattr(r.dt, "value", 0.02), dict(dt=0.02)),
])
def test_write_takes_effect_at_the_next_step_as_a_fresh_scene(write, fresh):
    root = beam(fixes=fresh.get("fixes", ()))
    write(root)
    assert same(run(root), run(beam(**fresh)))
    assert not same(run(beam()), run(beam(**fresh)))  # the write matters


def test_write_spring_stiffness_at_the_next_step_with_the_quirk_fixed():
    """mesh_spring_stiffness_write fixed: stiffness / rest length per spring, as a fresh scene
    (the quirk itself: test_live_write_quirks.py)."""
    root = beam(kind="springs", fixes=["mesh_spring_stiffness_write"])
    root.B.ff.stiffness.value = 400.0
    assert same(run(root), run(beam(kind="springs", stiffness=400.0)))


def test_write_mid_run_keeps_the_states_and_the_time():
    """A write after 3 steps, then 4 steps: as 3 steps of the old scene, then a fresh scene with the
    new value given those states."""
    a = beam()
    run(a, 3)
    x_view = a.B.mo.position.value  # a view of the state's memory
    a.B.fix.indices.value = list(range(12))
    ra = run(a, 4)
    assert np.shares_memory(x_view, a.B.mo.position.value)  # the memory of the state stays
    assert a.time.value == pytest.approx(0.07)
    b = beam()
    run(b, 3)
    c = beam(indices=list(range(12)))
    with c.B.mo.position.writeableArray() as x:
        x[:] = b.B.mo.position.value
    with c.B.mo.velocity.writeableArray() as v:
        v[:] = b.B.mo.velocity.value
    c.time.value = b.time.value
    assert same(ra, run(c, 4))


def test_gravity_write_reaches_child_nodes_one_step_late_as_sofa():
    """SOFA HEAD copies the root's context down at the end of a step: masses of the root take a
    written gravity at the next step, the others one step later (measured through SofaPython3:
    velocities -1.081 at the root, -1.962 below it after the first step)."""
    def build():
        root = sofa_api.Node("root")
        root.addObject("EulerImplicitSolver")
        root.addObject("CGLinearSolver", iterations=25, tolerance=1e-12, threshold=1e-12)
        root.addObject("MechanicalObject", name="mo", position=[0, 0, 0])
        root.addObject("UniformMass", vertexMass=1)
        c = root.addChild("C")
        c.addObject("MechanicalObject", name="mo", position=[0, 0, 0])
        c.addObject("UniformMass", vertexMass=1)
        c.addChild("D").addObject("MechanicalObject", name="mo", position=[0, 0, 0])
        c.D.addObject("UniformMass", vertexMass=1)
        sofa_api.init(root)
        return root
    r = build()
    sofa_api.animate(r, 0.1)
    r.gravity.value = [0, -1, 0]
    sofa_api.animate(r, 0.1)
    assert r.mo.velocity.value[0][1] == pytest.approx(-1.081, abs=1e-12)
    assert r.C.mo.velocity.value[0][1] == pytest.approx(-1.962, abs=1e-12)
    assert r.C.D.mo.velocity.value[0][1] == pytest.approx(-1.962, abs=1e-12)
    sofa_api.animate(r, 0.1)
    assert r.C.D.mo.velocity.value[0][1] == pytest.approx(-2.062, abs=1e-12)
    # without SOFA's delay: every node at the next step, as a fresh scene
    r = build()
    r._penalty_scene._scene._set_gravity_write_delay(False)
    sofa_api.animate(r, 0.1)
    r.gravity.value = [0, -1, 0]
    sofa_api.animate(r, 0.1)
    assert r.C.D.mo.velocity.value[0][1] == pytest.approx(-1.081, abs=1e-12)


def test_gravity_write_without_delay_equals_a_fresh_scene():
    root = beam()
    root._penalty_scene._scene._set_gravity_write_delay(False)
    root.gravity.value = [0, -3, 0]
    assert same(run(root), run(beam(gravity=(0, -3, 0))))


def test_writes_sofa_ignores_are_refused_with_the_reason():
    root = beam(kind="grid_springs")
    with pytest.raises(ValueError, match="RegularGridSpringForceField 'ff': data 'stiffness' cannot be written "
                                         "after init: SOFA's RegularGridSpringForceField reads it at init only"):
        root.B.ff.stiffness.value = 400.0
    with pytest.raises(ValueError, match="links are resolved at init"):
        beam().B.ff.topology.read("@../grid")
    with pytest.raises(ValueError, match="a component keeps its name after init"):
        root.B.ff.name.value = "other"
    with pytest.raises(ValueError, match="penalty does not simulate it"):
        root.B.mo.restScale.value = 2.0
    with pytest.raises(ValueError, match="SOFA copies the root's gravity over a child node's"):
        root.B.gravity.value = [0, 0, 0]


def test_a_bad_value_is_refused_naming_the_attribute():
    root = beam()
    with pytest.raises(penalty.SceneError, match=r"test_live_data.py:\d+: UniformMass 'mass': attribute 'totalMass': "
                                                 r"must be > 0, found '-1'"):
        root.B.mass.totalMass.value = -1
    with pytest.raises(ValueError, match="expected 36 points .3 numbers each., found 6 numbers"):
        root.B.mo.position.value = [[0, 0, 0], [1, 1, 1]]


def test_a_controller_moves_a_rigid_tool():
    """A controller writes a Rigid3d state's frame every step (Rigid3d positions are copies: the
    write goes through .value or writeableArray)."""
    class Mover(sofa_api.Controller):
        def __init__(self, *a, **k):
            sofa_api.Controller.__init__(self, *a, **k)
            self.tool = k["tool"]

        def onAnimateBeginEvent(self, event):
            with self.tool.position.writeableArray() as frames:
                frames[0, 0] += 0.1
                frames[0, 3:] = [0, 0, np.sin(0.05), np.cos(0.05)]

    root = sofa_api.Node("root")
    tool = root.addChild("Tool").addObject("MechanicalObject", name="frame", template="Rigid3d",
                                           position=[0, 0, 0, 0, 0, 0, 1])
    root.addObject(Mover(name="mover", tool=tool))
    sofa_api.init(root)
    for _ in range(3):
        sofa_api.animate(root)
    x = root.Tool.frame.position.value
    assert x[0, 0] == pytest.approx(0.3) and x[0, 5:].tolist() == pytest.approx([np.sin(0.05), np.cos(0.05)])


def test_objects_added_after_init_are_built_before_the_next_step():
    root = beam()
    run(root, 2)
    ball = root.addChild("Ball")
    ball.addObject("EulerImplicitSolver")
    ball.addObject("CGLinearSolver", iterations=25, tolerance=1e-9, threshold=1e-9)
    ball.addObject("MechanicalObject", name="dofs", position=[0, 5, 0])
    ball.addObject("UniformMass", totalMass=1)
    ball.init()
    sofa_api.animate(root, root.dt.value)
    assert root.Ball.dofs.position.value[0, 1] < 5.0  # it falls
    assert "/Ball/dofs" in root._penalty_scene.states.keys()


def test_a_write_and_reinit_during_the_collision_phase_wait_for_the_next_step():
    """SOFA's collision-phase events run inside the C++ step: a reinit() there cannot replace the
    simulation being stepped; the write takes effect at the next step."""
    class Stiffen(sofa_api.Controller):
        def __init__(self, *a, **k):
            sofa_api.Controller.__init__(self, *a, **k)
            self.fem = k["fem"]

        def onCollisionEndEvent(self, event):
            if self.getContext().getTime() == 0.0:
                self.fem.youngModulus.value = [400.0]
                self.fem.reinit()

    root = beam()
    root.addObject(Stiffen(name="stiffen", fem=root.B.ff))
    root.init()
    reference = beam()
    sofa_api.animate(reference)  # the first step with the old value (the write waits)
    reference.B.ff.youngModulus.value = [400.0]
    reference.B.ff.reinit()
    assert same(run(root, 4), run(reference, 3))


def test_topology_data_read_what_was_built(tmp_path):
    """A topology's points and elements as built (from a loader, or a grid's), as SOFA HEAD gives
    them through SofaPython3 for the same scene."""
    root = beam()
    assert root.B.grid.hexahedra.value.shape == (12, 8)
    assert root.B.grid.position.value.shape == (36, 3)
    mesh = tmp_path / "tri.obj"
    mesh.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    r = sofa_api.Node("root")
    s = r.addChild("S")
    s.addObject("MeshOBJLoader", name="loader", filename=str(mesh))
    s.addObject("MeshTopology", name="topo", src="@loader")
    s.addObject("MechanicalObject", name="mo", src="@loader")
    sofa_api.init(r)
    assert r.S.topo.triangles.value.tolist() == [[0, 1, 2]]
    assert r.S.topo.edges.value.tolist() == [[1, 2], [2, 0], [0, 1]]
    assert r.S.topo.position.value.tolist() == [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
    assert r.S.loader.position.value.shape == (3, 3)
