"""SofaPython3's linear system views (docs/python.md, Sofa.SofaLinearSystem / Sofa.SofaLinearSolver):
A(), b(), x() of a MatrixLinearSystem and of a direct linear solver are the system the last step
solved: A·x = b, A = m·M + b·B + k·K with the fixed DOFs' rows and columns replaced by the identity,
equal to SOFA HEAD's matrix on a small beam."""
import importlib.util
import json
import os

import numpy as np
import pytest

import penalty

penalty._install_sofa_path()
import Sofa  # noqa: E402  (penalty's)
import Sofa.Core  # noqa: E402
import Sofa.Simulation  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


def beam(template="CompressedRowSparseMatrixd", steps=2):
    spec = importlib.util.spec_from_file_location("linear_system_beam", os.path.join(HERE, "scripts", "linear_system_beam.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    root = Sofa.Core.Node("root")
    module.create(root, template)
    Sofa.Simulation.init(root)
    for _ in range(steps):
        Sofa.Simulation.animate(root, root.dt.value)
    return root


def test_the_system_is_the_solved_one_and_the_product_of_the_assembled_operators():
    root = beam()
    A, b, x = root.system.A(), root.system.b(), root.system.x()
    assert A.shape == (36, 36) and b.shape == (36,) and x.shape == (36,)
    # the equation the direct solve solved
    assert np.abs(A @ x - b).max() <= 1e-12 * max(1.0, np.abs(b).max())
    assert np.abs(b).max() > 1e-3  # a real right-hand side (gravity, 2 steps in)
    # A = m·M + k·K (Euler implicit: m = 1 + h·rm, k = −h·(h + rs)), fixed DOFs → identity rows/columns
    h, rm, rs = 0.01, 0.2, 0.1
    mass = next(o for o in root.objects if o.getClassName() == "UniformMass").assembleMMatrix()
    fem = next(o for o in root.objects if o.getClassName() == "HexahedronFEMForceField").assembleKMatrix()
    fixed = np.zeros(36, dtype=bool)
    for i in np.asarray(root.box.indices.value).ravel():
        fixed[3 * int(i):3 * int(i) + 3] = True
    assert fixed.sum() == 12
    free = ~fixed
    rng = np.random.default_rng(20261129)
    for _ in range(4):
        v = rng.normal(size=36)
        vf = np.where(free, v, 0.0)
        expected = (1 + h * rm) * (mass @ vf) - h * (h + rs) * (fem @ vf)
        expected = np.where(free, expected, v)
        assert np.abs(A @ v - expected).max() <= 1e-12 * np.abs(expected).max()
    # the solver's view is the same system
    assert np.array_equal(root.solver.A().toarray(), A.toarray())
    assert np.array_equal(root.solver.b(), b) and np.array_equal(root.solver.x(), x)
    assert np.array_equal(root.system.get_system_matrix().toarray(), A.toarray())
    assert np.array_equal(root.system.get_rhs_vector(), b)
    assert np.array_equal(root.system.get_solution_vector(), x)


def test_the_views_equal_sofa_heads_numbers():
    ref = json.load(open(os.path.join(HERE, "scripts", "linear_system_beam_sofa_head.json")))
    expected = np.zeros(ref["shape"])
    expected[ref["rows"], ref["cols"]] = ref["values"]
    for template in ("CompressedRowSparseMatrixd", "CompressedRowSparseMatrixMat3x3d"):
        root = beam(template)
        A = root.system.A().toarray()
        scale = np.abs(expected).max()
        assert np.abs(A - expected).max() <= 1e-12 * scale, template
        assert np.array_equal(A != 0, expected != 0), template  # the same pattern of nonzeros
        assert np.abs(root.system.b() - ref["b"]).max() <= 1e-12 * np.abs(ref["b"]).max()
        assert np.abs(root.system.x() - ref["x"]).max() <= 1e-12 * np.abs(ref["x"]).max()
        assert np.abs(root.dofs.position.value.ravel() - ref["positions"]).max() <= 1e-12


def test_before_the_first_step_there_is_no_system_and_a_fed_system_has_its_own_matrix():
    root = beam(steps=0)
    assert root.system.A() is None and root.system.b().shape == (0,)
    # a second MatrixLinearSystem fed by a CompositeLinearSystem, mass only and unprojected
    # (SofaPython3's access_mass_matrix.py): A = m·M, its b and x empty
    root = Sofa.Core.Node("root")
    root.dt = 0.01
    root.addObject("DefaultAnimationLoop")
    root.addObject("EulerImplicitSolver", rayleighStiffness=0.1, rayleighMass=0.2)
    matrices = root.addChild("matrices")
    matrices.addObject("MatrixLinearSystem", name="system")
    matrices.addObject("MatrixLinearSystem", name="M", assembleStiffness=False, assembleDamping=False,
                       applyProjectiveConstraints=False)
    root.addObject("CompositeLinearSystem", name="composite", linearSystems="@matrices/system @matrices/M",
                   solverLinearSystem="@matrices/system")
    root.addObject("SparseLDLSolver", linearSystem="@composite")
    body = root.addChild("Body")
    body.addObject("MechanicalObject", name="dofs")
    body.addObject("UniformMass", name="mass", totalMass=2.0)
    body.addObject("RegularGridTopology", nx=2, ny=2, nz=2, xmin=0, xmax=1, ymin=0, ymax=1, zmin=0, zmax=1)
    body.addObject("FixedProjectiveConstraint", indices=[0])
    body.addObject("HexahedronFEMForceField", youngModulus=500, poissonRatio=0.3)
    Sofa.Simulation.init(root)
    Sofa.Simulation.animate(root, 0.01)
    m_view = root.matrices.M.A()
    mass = root.Body.mass.assembleMMatrix()
    assert np.abs(m_view.toarray() - (1 + 0.01 * 0.2) * mass.toarray()).max() <= 1e-15
    assert root.matrices.M.b().shape == (0,)
    solved = root.matrices.system.A()
    assert solved[0, 0] == 1.0 and solved[0, 3] == 0.0  # DOF 0 fixed: identity row
    assert np.abs(solved @ root.matrices.system.x() - root.matrices.system.b()).max() <= 1e-12


def test_a_cg_solved_full_matrix_system_is_a_dense_array():
    # SofaPython3's access_matrix.py: CGLinearSolver template="FullMatrix" on a MatrixLinearSystem
    root = Sofa.Core.Node("root")
    root.dt = 0.01
    root.addObject("DefaultAnimationLoop")
    root.addObject("EulerImplicitSolver", rayleighStiffness=0.1, rayleighMass=0.1)
    system = root.addObject("MatrixLinearSystem", template="FullMatrix", name="system")
    root.addObject("CGLinearSolver", template="FullMatrix", iterations=200, tolerance=1e-20, threshold=1e-20)
    root.addObject("MechanicalObject", name="dofs")
    root.addObject("UniformMass", totalMass=2.0)
    root.addObject("RegularGridTopology", nx=2, ny=2, nz=2, xmin=0, xmax=1, ymin=0, ymax=1, zmin=0, zmax=1)
    root.addObject("FixedProjectiveConstraint", indices=[0, 1])
    root.addObject("HexahedronFEMForceField", youngModulus=500, poissonRatio=0.3)
    Sofa.Simulation.init(root)
    Sofa.Simulation.animate(root, 0.01)
    A = system.get_system_matrix()
    assert isinstance(A, np.ndarray) and A.shape == (24, 24)
    assert np.abs(A @ system.x() - system.b()).max() <= 1e-9 * np.abs(system.b()).max()


def test_a_view_before_init_names_the_call():
    root = Sofa.Core.Node("root")
    system = root.addObject("MatrixLinearSystem", name="system")
    with pytest.raises(RuntimeError, match=r"A\(\): call Sofa.Simulation.init"):
        system.A()
