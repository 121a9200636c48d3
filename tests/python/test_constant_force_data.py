"""ConstantForceField's Data read from Python as SOFA's init and update callbacks leave them
(docs/python.md, "Engines over moving states", the ConstantForceField reader): `indices` every point
when none are given (ConstantForceField::init); `forces` and `totalForce` the scene's values until
the callbacks first run (the first addForce: isComponentStateValid), then what they made of them
(one force spread over the indices, computeForceFromSingleForce; `totalForce` T / n each;
`totalForce` the sum of the forces in index order, computeForceFromForcesVector), kept while the
component is Invalid after an `indices` write of another count. The expected values are SOFA HEAD's
(2a278d8 with SofaPython3 87be1a3, the same calls through `sofa-head-python`)."""
import numpy as np
import pytest

from penalty import sofa_api

# SOFA HEAD's (forces, totalForce, indices) after init, after step 1, after `indices = [0, 1]`
# (before the next step), after step 2, after `indices = [1, 2, 3]` and step 3
SOFA_HEAD = {
    "one": [
        ([[0, -1, 0]], [0, 0, 0], [0, 1, 2]),
        ([[0, -1, 0], [0, -1, 0], [0, -1, 0]], [0, -3, 0], [0, 1, 2]),
        ([[0, -1, 0], [0, -1, 0], [0, -1, 0]], [0, -3, 0], [0, 1]),
        ([[0, -1, 0], [0, -1, 0], [0, -1, 0]], [0, -3, 0], [0, 1]),
        ([[0, -1, 0], [0, -1, 0], [0, -1, 0]], [0, -3, 0], [1, 2, 3]),
    ],
    "total": [
        ([], [0, -3, 0], [0, 1, 2]),
        ([[0, -1, 0], [0, -1, 0], [0, -1, 0]], [0, -3, 0], [0, 1, 2]),
        ([[0, -1, 0], [0, -1, 0], [0, -1, 0]], [0, -3, 0], [0, 1]),
        ([[0, -1.5, 0], [0, -1.5, 0]], [0, -3, 0], [0, 1]),
        ([[0, -1, 0], [0, -1, 0], [0, -1, 0]], [0, -3, 0], [1, 2, 3]),
    ],
    "every": [
        ([[0, -1, 0]], [0, 0, 0], [0, 1, 2, 3]),
        ([[0, -1, 0], [0, -1, 0], [0, -1, 0], [0, -1, 0]], [0, -4, 0], [0, 1, 2, 3]),
        ([[0, -1, 0], [0, -1, 0], [0, -1, 0], [0, -1, 0]], [0, -4, 0], [0, 1]),
        ([[0, -1, 0], [0, -1, 0], [0, -1, 0], [0, -1, 0]], [0, -4, 0], [0, 1]),
        ([[0, -1, 0], [0, -1, 0], [0, -1, 0], [0, -1, 0]], [0, -4, 0], [1, 2, 3]),
    ],
}
ATTRIBUTES = {
    "one": dict(indices=[0, 1, 2], forces=[[0, -1, 0]]),
    "total": dict(indices=[0, 1, 2], totalForce=[0, -3, 0]),
    "every": dict(forces=[[0, -1, 0]]),
}


def scene(n=4, **push):
    root = sofa_api.Node("root")
    root.dt = 0.01
    root.gravity = [0, 0, 0]
    root.addObject("DefaultAnimationLoop")
    node = root.addChild("N")
    node.addObject("EulerImplicitSolver")
    node.addObject("CGLinearSolver", iterations=40, tolerance=1e-12, threshold=1e-12)
    node.addObject("MechanicalObject", name="dofs", position=[[i, 0, 0] for i in range(n)])
    node.addObject("UniformMass", totalMass=1)
    node.addObject("ConstantForceField", name="push", **push)
    sofa_api.init(root)
    return root


def read(root):
    push = root.N.push
    return (push.forces.value.tolist(), push.totalForce.value.tolist(), push.indices.value.tolist())


@pytest.mark.parametrize("case", sorted(SOFA_HEAD))
def test_forces_total_force_and_indices_read_as_sofa_heads(case):
    root = scene(**ATTRIBUTES[case])
    got = [read(root)]
    sofa_api.animate(root, 0.01)
    got.append(read(root))
    root.N.push.indices.value = [0, 1]
    got.append(read(root))  # the callbacks wait for the next addForce
    sofa_api.animate(root, 0.01)
    got.append(read(root))
    root.N.push.indices.value = [1, 2, 3]
    sofa_api.animate(root, 0.01)
    got.append(read(root))
    expected = [tuple(np.array(v, dtype=float).tolist() for v in row) for row in SOFA_HEAD[case]]
    for k, (g, e) in enumerate(zip(got, expected)):
        assert g == e, (case, k)


def test_total_force_is_the_sum_of_the_spread_forces():
    # computeForceFromForcesVector, the last callback, sums ten 0.1 from 0: 0.9999999999999999
    # (SOFA HEAD's), not 10 * 0.1
    root = scene(n=10, forces=[[0.1, 0, 0]])
    sofa_api.animate(root, 0.01)
    assert root.N.push.totalForce.value.tolist() == [0.9999999999999999, 0.0, 0.0]
