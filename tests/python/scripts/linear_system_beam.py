"""A small beam with SparseLDLSolver and MatrixLinearSystem: the linear system views after 2 steps.
Runs with SOFA HEAD (sofa-head-python) and with penalty (PYTHONPATH with penalty's sofa_compat)."""
import sys
import numpy as np
import Sofa
import Sofa.Core
import Sofa.Simulation
from Sofa import SofaLinearSystem, SofaLinearSolver  # noqa: F401 (SofaPython3 registers the views on import)


def create(root, template):
    root.dt = 0.01
    root.gravity = [0, -9.81, 0]
    root.addObject("RequiredPlugin", pluginName=["Sofa.Component.ODESolver.Backward", "Sofa.Component.LinearSolver.Direct",
                                                 "Sofa.Component.LinearSystem", "Sofa.Component.Engine.Select",
                                                 "Sofa.Component.Constraint.Projective", "Sofa.Component.Mass",
                                                 "Sofa.Component.SolidMechanics.FEM.Elastic", "Sofa.Component.StateContainer",
                                                 "Sofa.Component.Topology.Container.Grid"])
    root.addObject("DefaultAnimationLoop")
    root.addObject("EulerImplicitSolver", rayleighStiffness=0.1, rayleighMass=0.2)
    root.addObject("MatrixLinearSystem", name="system", template=template)
    root.addObject("SparseLDLSolver", name="solver", template=template, linearSystem="@system")
    root.addObject("MechanicalObject", name="dofs")
    root.addObject("UniformMass", totalMass=2.0)
    root.addObject("RegularGridTopology", nx=2, ny=2, nz=3, xmin=0, xmax=1, ymin=0, ymax=1, zmin=0, zmax=2)
    root.addObject("BoxROI", name="box", box=[-1, -1, -0.1, 2, 2, 0.1])
    root.addObject("FixedProjectiveConstraint", indices="@box.indices")
    root.addObject("HexahedronFEMForceField", youngModulus=500, poissonRatio=0.3, method="large")


if __name__ == "__main__":
    out = {}
    for template in ("CompressedRowSparseMatrixd", "CompressedRowSparseMatrixMat3x3d"):
        root = Sofa.Core.Node("root")
        create(root, template)
        Sofa.Simulation.init(root)
        for _ in range(2):
            Sofa.Simulation.animate(root, root.dt.value)
        A = root.system.A()
        out[template + "_A"] = A.toarray()
        out[template + "_b"] = np.asarray(root.system.b())
        out[template + "_x"] = np.asarray(root.system.x())
        out[template + "_solverA"] = root.solver.A().toarray()
        out[template + "_solverb"] = np.asarray(root.solver.b())
        out[template + "_pos"] = np.array(root.dofs.position.value)
        print(template, A.shape, A.nnz, type(root.system.b()))
    np.savez(sys.argv[1], **out)
