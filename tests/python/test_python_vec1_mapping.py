"""A mapping written in Python onto a Vec1d state (Sofa.Core.Mapping_Vec3d_Vec1d, SofaPython3's
example-mapping_3_to_1.py): apply, applyJ, applyJT with (n, 1) arrays on the output side, equal to
the C++ DistanceFromTargetMapping it rewrites."""
import numpy as np

import penalty

penalty._install_sofa_path()
import Sofa  # noqa: E402  (penalty's)
import Sofa.Core  # noqa: E402
import Sofa.Simulation  # noqa: E402

TARGETS = np.array([[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 3.0, 0.0]])


class Distances(Sofa.Core.Mapping_Vec3d_Vec1d):
    """|x_i − target_i|, its Jacobian the unit directions (DistanceFromTargetMapping without
    geometric stiffness)."""

    def __init__(self, *args, **kwargs):
        Sofa.Core.Mapping_Vec3d_Vec1d.__init__(self, *args, **kwargs)
        self.directions = np.zeros((3, 3))
        self.shapes = set()

    def apply(self, m, out, inp):
        d = inp.value - TARGETS
        norms = np.sqrt(d[:, 0] * d[:, 0] + d[:, 1] * d[:, 1] + d[:, 2] * d[:, 2])
        self.directions = d / norms[:, None]
        self.shapes.add(out.value.shape)
        with out.writeableArray() as w:
            w[:, 0] = norms

    def applyJ(self, m, out, inp):
        with out.writeableArray() as w:
            w[:, 0] = (self.directions * inp.value).sum(axis=1)

    def applyJT(self, m, inp, out):
        with inp.writeableArray() as w:
            w += self.directions * out.value


def scene(python):
    root = Sofa.Core.Node("root")
    root.dt = 0.01
    root.gravity = [0, -9.81, 0]
    root.addObject("DefaultAnimationLoop")
    body = root.addChild("Body")
    body.addObject("EulerImplicitSolver", rayleighStiffness=0, rayleighMass=0)
    body.addObject("CGLinearSolver", iterations=25, tolerance=1e-12, threshold=1e-12)
    points = body.addObject("MechanicalObject", name="points", position=[[1, 1, 1], [3, 1, 0], [0, 4, 1]])
    body.addObject("UniformMass", totalMass=3.0)
    mapped = body.addChild("Distances")
    values = mapped.addObject("MechanicalObject", name="d", template="Vec1d", position=[0.0, 0.0, 0.0])
    if python:
        mapping = mapped.addObject(Distances(name="map", input=points.linkpath, output=values.linkpath))
    else:
        mapping = mapped.addObject("DistanceFromTargetMapping", input=points.linkpath, output=values.linkpath,
                                   targetPositions=TARGETS.ravel().tolist(), geometricStiffness="None")
    Sofa.Simulation.init(root)
    return root, mapping


def test_a_python_vec1_mapping_equals_the_cpp_one():
    (py_root, py_map), (cpp_root, _) = scene(True), scene(False)
    assert py_root.Body.Distances.d.position.value.shape == (3, 1)
    for _ in range(3):
        Sofa.Simulation.animate(py_root, py_root.dt.value)
        Sofa.Simulation.animate(cpp_root, cpp_root.dt.value)
    x = py_root.Body.points.position.value
    assert np.array_equal(x, cpp_root.Body.points.position.value)
    d = py_root.Body.Distances.d.position.value[:, 0]
    assert np.abs(d - cpp_root.Body.Distances.d.position.value[:, 0]).max() <= 1e-15
    assert np.abs(d - np.linalg.norm(x - TARGETS, axis=1)).max() <= 1e-15
    v = py_root.Body.Distances.d.velocity.value[:, 0]  # mapped by applyJ
    assert np.abs(v).max() > 1e-3 and np.abs(v - cpp_root.Body.Distances.d.velocity.value[:, 0]).max() <= 1e-15
    assert py_map.shapes == {(3, 1)}  # SofaPython3 hands a Vec1d output as (n, 1)
    assert py_map.getTemplateName() == "Vec3d,Vec1d"
