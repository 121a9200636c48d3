"""TetrahedronFEMForceField's localStiffnessFactor (element i's Young's modulus is
factor[i·M/N]·E) and updateStiffness (a write after init acts at the next step, as SOFA's
handleEvent(AnimateBeginEvent) recomputes the material stiffness; without it, at reinit())."""
import numpy as np

from penalty import sofa_api


def beam(young=200.0, factors=None, update=True, solver="CGLinearSolver"):
    root = sofa_api.Node("root")
    root.gravity = [0, -9.81, 0]
    root.dt = 0.01
    root.addObject("DefaultAnimationLoop")
    n = root.addChild("B")
    n.addObject("EulerImplicitSolver", rayleighStiffness=0.1, rayleighMass=0.1)
    if solver == "CGLinearSolver":
        n.addObject("CGLinearSolver", iterations=100, tolerance=1e-14, threshold=1e-14)
    else:
        n.addObject(solver)
    n.addObject("RegularGridTopology", name="grid", nx=2, ny=2, nz=4, xmin=0, xmax=1, ymin=0, ymax=1, zmin=0, zmax=3)
    n.addObject("MechanicalObject", name="mo")
    n.addObject("UniformMass", totalMass=1.0)
    n.addObject("BoxROI", name="box", box=[-1, -1, -0.1, 2, 2, 0.1])
    n.addObject("FixedProjectiveConstraint", indices="@box.indices")
    extra = {} if factors is None else {"localStiffnessFactor": factors}
    n.addObject("TetrahedronFEMForceField", name="ff", youngModulus=young, poissonRatio=0.3, updateStiffness=update, **extra)
    sofa_api.init(root)
    return root


def run(root, steps=4):
    for _ in range(steps):
        sofa_api.animate(root, root.dt.value)
    return root.B.mo.position.value.copy()


def test_a_factor_of_two_is_twice_the_youngs_modulus_to_the_bit():
    for solver in ("CGLinearSolver", "SparseLDLSolver"):  # the force and the assembled matrix
        assert np.array_equal(run(beam(factors=[2.0], solver=solver)), run(beam(young=400.0, solver=solver))), solver
        assert not np.array_equal(run(beam(solver=solver)), run(beam(young=400.0, solver=solver)))


def test_factors_index_the_elements_proportionally():
    # 2x2x4 grid: 3 cells of 6 tetrahedra (N = 18); M = 3 factors: element i takes factor i·3/18,
    # one per cell, the same as the cells' own moduli given through 18 factors
    per_element = [f for f in (1.0, 2.0, 4.0) for _ in range(6)]
    assert np.array_equal(run(beam(factors=[1.0, 2.0, 4.0])), run(beam(factors=per_element)))


def test_a_written_factor_acts_at_the_next_step_with_update_stiffness_else_at_reinit():
    written = beam(update=True)
    written.B.ff.localStiffnessFactor.value = [2.0]
    assert np.array_equal(run(written), run(beam(young=400.0)))
    kept = beam(update=False)
    kept.B.ff.localStiffnessFactor.value = [2.0]
    assert np.array_equal(run(kept), run(beam(update=False)))  # SOFA reads it at reinit() only
    kept.B.ff.reinit()
    reference = beam(update=False)
    run(reference)
    reference.B.ff.localStiffnessFactor.value = [2.0]
    reference.B.ff.reinit()
    assert np.array_equal(run(kept), run(reference))
