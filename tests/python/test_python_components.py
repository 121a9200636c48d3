"""SofaPython3's Python components in the C++ solve: a force field written in Python gives the
bits of the same force field in C++ (PlaneForceField, addForce/addDForce in the implicit CG solve),
passes the finite-difference checks the C++ force fields pass (one harness for both, through the
scene's probe of one force field), a Python mapping gives the bits of IdentityMapping, and a
DataEngine updates when its inputs change."""
import numpy as np
import pytest

from penalty import sofa_api


class PythonPlane(sofa_api.ForceFieldVec3d):
    """PlaneForceField (normal, d, stiffness, damping) in Python, with the operations of
    src/mechanics/external_loads.cpp in the same order (so the same bits)."""

    def __init__(self, *args, **kwargs):
        sofa_api.ForceFieldVec3d.__init__(self, *args, **kwargs)
        self.addData("stiffness", type="double", value=kwargs.get("stiffness", 500.0))
        self.addData("damping", type="double", value=kwargs.get("damping", 5.0))
        self.normal = np.array(kwargs.get("normal", [0.0, 1.0, 0.0]))
        self.d = float(kwargs.get("d", 0.0))
        self.active = np.zeros(0, dtype=bool)

    def addForce(self, mparams, f, x, v):
        n, k, c = self.normal, self.stiffness.value, self.damping.value
        x, v = x.value, v.value
        depth = (x[:, 0] * n[0] + x[:, 1] * n[1]) + x[:, 2] * n[2] - self.d
        self.active = depth < 0.0
        force = n[None, :] * (-k * depth)[:, None] - v * (-c * depth)[:, None]
        with f.writeableArray() as wa:
            wa[self.active] += force[self.active]

    def addDForce(self, mparams, df, dx):
        n = self.normal
        fact = -self.stiffness.value * mparams["kFactor"]
        dx = dx.value
        t = fact * ((dx[:, 0] * n[0] + dx[:, 1] * n[1]) + dx[:, 2] * n[2])
        with df.writeableArray() as wa:
            wa[self.active] += n[None, :] * t[self.active, None]

    def addKToMatrix(self, mparams, n_nodes, n_dofs):
        k = np.zeros((n_nodes * n_dofs, n_nodes * n_dofs))
        block = -self.stiffness.value * mparams["kFactor"] * np.outer(self.normal, self.normal)
        for p in np.flatnonzero(self.active):
            k[3 * p:3 * p + 3, 3 * p:3 * p + 3] += block
        return k


class PythonCubicSprings(sofa_api.ForceFieldVec3d):
    """f = -k (x - x0)^3 per coordinate (a nonlinear field written in Python): K = -3k (x - x0)^2."""

    def init(self):
        self.x0 = self.getContext().dofs.rest_position.value.copy()
        self.k = 40.0
        self.x = self.x0.copy()

    def addForce(self, mparams, f, x, v):
        self.x = x.value.copy()
        with f.writeableArray() as wa:
            wa[:] += -self.k * (self.x - self.x0) ** 3

    def addDForce(self, mparams, df, dx):
        with df.writeableArray() as wa:
            wa[:] += mparams["kFactor"] * (-3.0 * self.k * (self.x - self.x0) ** 2) * dx.value

    def addKToMatrix(self, mparams, n_nodes, n_dofs):
        return np.diag((mparams["kFactor"] * -3.0 * self.k * (self.x - self.x0) ** 2).ravel())


def particles(python_plane: bool):
    root = sofa_api.Node("root")
    root.dt = 0.01
    body = root.addChild("Body")
    body.addObject("EulerImplicitSolver", rayleighStiffness=0.1, rayleighMass=0.1)
    body.addObject("CGLinearSolver", iterations=40, tolerance=1e-12, threshold=1e-12)
    rng = np.random.default_rng(7)
    points = rng.uniform([-1, 0.05, -1], [1, 0.4, 1], size=(12, 3))
    body.addObject("MechanicalObject", name="dofs", position=points, velocity=rng.normal(0, 0.3, size=(12, 3)))
    body.addObject("UniformMass", totalMass=0.6)
    if python_plane:
        body.addObject(PythonPlane(name="plane", stiffness=500.0, damping=5.0, normal=[0, 1, 0], d=0.0))
    else:
        body.addObject("PlaneForceField", name="plane", normal=[0, 1, 0], d=0.0, stiffness=500.0, damping=5.0)
    sofa_api.init(root)
    return root


def test_python_force_field_equals_the_cpp_one_bit_for_bit():
    cpp, python = particles(False), particles(True)
    touched = 0
    for step in range(150):
        sofa_api.animate(cpp)
        sofa_api.animate(python)
        a, b = cpp.Body.dofs, python.Body.dofs
        assert np.array_equal(a.position.value, b.position.value), f"positions differ at step {step}"
        assert np.array_equal(a.velocity.value, b.velocity.value), f"velocities differ at step {step}"
        touched += int(np.count_nonzero(python.Body.plane.active))
    assert touched > 50  # the plane acted (implicit solve through addDForce)


def _check_force_field(scene, path, x, v, rng):
    """One harness for C++ and Python force fields (through the scene's probe of one force field):
    central differences of f give K dx (addDForce), and the assembled K (addKToMatrix / C++'s
    stiffness triplets) times dx gives the same."""
    core = scene._scene
    dx = rng.normal(size=x.shape)
    core._probe_force(path, x, v)
    k_dx = core._probe_dforce(path, dx, 1.0, 0.0)
    eps = 1e-6
    fd = (core._probe_force(path, x + eps * dx, v) - core._probe_force(path, x - eps * dx, v)) / (2 * eps)
    core._probe_force(path, x, v)
    scale = max(np.abs(k_dx).max(), 1e-12)
    assert np.abs(fd - k_dx).max() <= 1e-6 * scale + 1e-9, path
    k = core._stiffness_matrix(path)
    assert np.allclose(k @ dx.ravel(), k_dx.ravel(), rtol=1e-12, atol=1e-12 * scale), path
    return scale


@pytest.mark.parametrize("python_plane", [False, True])
def test_plane_force_field_passes_the_finite_difference_checks(python_plane):
    root = particles(python_plane)
    rng = np.random.default_rng(3)
    x = root.Body.dofs.position.value.copy()
    x[:6, 1] = -0.05  # half of the points below the plane
    v = np.zeros_like(x)  # SOFA's PlaneForceField leaves the damping's dependence on x out of K
    assert _check_force_field(root._penalty_scene, "/Body/plane", x, v, rng) > 1.0


@pytest.mark.parametrize("kind", ["MeshSpringForceField", "python cubic"])
def test_nonlinear_force_fields_pass_the_finite_difference_checks(kind):
    root = sofa_api.Node("root")
    body = root.addChild("Body")
    body.addObject("EulerImplicitSolver")
    body.addObject("CGLinearSolver", iterations=25, tolerance=1e-9, threshold=1e-9)
    body.addObject("RegularGridTopology", nx=2, ny=2, nz=3, xmin=0, xmax=1, ymin=0, ymax=1, zmin=0, zmax=2)
    body.addObject("MechanicalObject", name="dofs")
    body.addObject("UniformMass", totalMass=1)
    if kind == "MeshSpringForceField":
        body.addObject("MeshSpringForceField", name="ff", stiffness=300, damping=0)
    else:
        body.addObject(PythonCubicSprings(name="ff"))
    sofa_api.init(root)
    rng = np.random.default_rng(11)
    x = root.Body.dofs.position.value + rng.normal(0, 0.1, size=(12, 3))
    _check_force_field(root._penalty_scene, "/Body/ff", x, np.zeros_like(x), rng)


class PythonIdentity(sofa_api.Mapping_Vec3d_Vec3d):
    """IdentityMapping in Python (SofaPython3's example-mapping.py without its offset)."""

    def apply(self, m, out, inp):
        with out.writeableArray() as wa:
            wa[:] = inp.value

    def applyJ(self, m, out, inp):
        with out.writeableArray() as wa:
            wa[:] = inp.value

    def applyJT(self, m, out, inp):
        with out.writeableArray() as wa:
            wa[:] += inp.value


def mapped_bodies(python_mapping: bool):
    root = sofa_api.Node("root")
    body = root.addChild("Body")
    body.addObject("EulerImplicitSolver", rayleighStiffness=0.05)
    body.addObject("CGLinearSolver", iterations=40, tolerance=1e-12, threshold=1e-12)
    rng = np.random.default_rng(5)
    dofs = body.addObject("MechanicalObject", name="dofs", position=rng.uniform(0.05, 0.3, size=(6, 3)))
    body.addObject("UniformMass", totalMass=1.0)
    child = body.addChild("Surface")
    out = child.addObject("MechanicalObject", name="points", position=dofs.position.value)
    child.addObject("PlaneForceField", name="plane", normal=[0, 1, 0], d=0.0, stiffness=800.0, damping=2.0)
    if python_mapping:
        child.addObject(PythonIdentity(name="map", input=dofs.linkpath, output=out.linkpath))
    else:
        child.addObject("IdentityMapping", name="map", input="@../dofs", output="@points")
    sofa_api.init(root)
    return root


def test_python_mapping_equals_identity_mapping_bit_for_bit():
    cpp, python = mapped_bodies(False), mapped_bodies(True)
    for step in range(100):
        sofa_api.animate(cpp)
        sofa_api.animate(python)
        assert np.array_equal(cpp.Body.dofs.position.value, python.Body.dofs.position.value), step
        assert np.array_equal(cpp.Body.Surface.points.position.value, python.Body.Surface.points.position.value), step
    assert python.Body.dofs.position.value[:, 1].min() < 0.0  # they reached the plane, through J and Jᵀ


def test_data_engine_updates_when_an_input_changed():
    class Sum(sofa_api.DataEngine):
        def __init__(self, *args, **kwargs):
            sofa_api.DataEngine.__init__(self, *args, **kwargs)
            self.addData("a", type="double", value=1.0)
            self.addData("b", type="double", value=2.0)
            self.addData("total", type="double", value=0.0)
            self.addInput(self.a)
            self.addInput(self.b)
            self.addOutput(self.total)
            self.updates = 0

        def update(self):
            self.updates += 1
            self.total.value = self.a.value + self.b.value

    root = sofa_api.Node("root")
    engine = root.addObject(Sum(name="sum"))
    sofa_api.init(root)
    assert engine.total.value == 3.0 and engine.updates == 1
    assert engine.total.value == 3.0 and engine.updates == 1  # inputs unchanged: no update
    engine.b.value = 5.0
    assert engine.updates == 1                                # lazily: when an output is read
    assert engine.total.value == 6.0 and engine.updates == 2


def test_python_components_take_sofapython3s_names_and_data():
    ff = PythonPlane("positional")
    assert ff.name.value == "positional" and ff.getClassName() == "PythonPlane"
    assert ff.rayleighStiffness.value == 0.0 and ff.listening.value == 1
    c = sofa_api.Controller(name="c")
    assert c.listening.value == 1 and c.getClassName() == "Controller"
    c.name = "renamed"  # a Data: renames, as SofaPython3
    assert c.getName() == "renamed"
    c.extra = 3  # not a Data: a Python attribute
    assert c.extra == 3
