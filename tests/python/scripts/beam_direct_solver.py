"""The scene of SofaPython3's examples/MessageHandler.py (without its message handler): a
hexahedral cantilever with a consistent MeshMatrixMass, fixed through a BoxROI, integrated by
EulerImplicitSolver with SparseLDLSolver. tests/python/test_sofa_scripts.py compares it with
tests/scene/data/solvers/hexa_beam_matrix_mass_ldl.scn; SOFA HEAD gives the .scn's numbers."""


def createScene(root):
    root.dt = 0.02
    root.gravity = [0, -9.81, 0]
    root.addObject("RequiredPlugin", pluginName=["Sofa.Component.Constraint.Projective", "Sofa.Component.Engine.Select",
                                                 "Sofa.Component.LinearSolver.Direct", "Sofa.Component.Mass",
                                                 "Sofa.Component.ODESolver.Backward",
                                                 "Sofa.Component.SolidMechanics.FEM.Elastic",
                                                 "Sofa.Component.StateContainer", "Sofa.Component.Topology.Container.Grid"])
    root.addObject("DefaultAnimationLoop")
    beam = root.addChild("Beam")
    beam.addObject("EulerImplicitSolver", rayleighStiffness=0.1, rayleighMass=0.1, printLog=False)
    beam.addObject("SparseLDLSolver", template="CompressedRowSparseMatrixd")
    beam.addObject("MechanicalObject", name="DoFs")
    beam.addObject("MeshMatrixMass", name="mass", totalMass=320)
    beam.addObject("RegularGridTopology", name="grid", nx=4, ny=4, nz=10, xmin=-9, xmax=-6, ymin=0, ymax=3, zmin=0, zmax=19)
    beam.addObject("BoxROI", name="box", box=[-10, -1, -0.0001, -5, 4, 0.0001])
    beam.addObject("FixedProjectiveConstraint", indices="@box.indices")
    beam.addObject("HexahedronFEMForceField", name="FEM", youngModulus=4000, poissonRatio=0.3, method="large")
    return root
