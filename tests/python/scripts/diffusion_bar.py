"""Heat diffusion along a small tetrahedral bar (Vec1d temperatures), one end held at 1."""
import sys
import json
import numpy as np
import Sofa
import Sofa.Core
import Sofa.Simulation


def createScene(root):
    root.dt = 0.01
    root.gravity = [0, -9.81, 0]
    root.addObject("RequiredPlugin", pluginName=["Sofa.Component.Diffusion", "Sofa.Component.ODESolver.Backward",
                                                 "Sofa.Component.LinearSolver.Iterative", "Sofa.Component.Mass",
                                                 "Sofa.Component.StateContainer", "Sofa.Component.Topology.Container.Grid",
                                                 "Sofa.Component.Topology.Container.Dynamic", "Sofa.Component.Topology.Mapping",
                                                 "Sofa.Component.Constraint.Projective"])
    root.addObject("DefaultAnimationLoop")
    grid = root.addObject("RegularGridTopology", name="grid", nx=4, ny=2, nz=2, xmin=0, xmax=1, ymin=0, ymax=0.2, zmin=0, zmax=0.2)
    bar = root.addChild("Bar")
    tets = bar.addObject("TetrahedronSetTopologyContainer", name="tets")
    bar.addObject("TetrahedronSetTopologyModifier")
    bar.addObject("Hexa2TetraTopologicalMapping", input=grid.linkpath, output=tets.linkpath)
    geometry = bar.addObject("MechanicalObject", name="geometry", position="@../grid.position", tags="3dgeometry")
    heat = bar.addChild("Heat")
    heat.addObject("EulerImplicitSolver", firstOrder=True)
    heat.addObject("CGLinearSolver", iterations=200, tolerance=1e-12, threshold=1e-30)
    heat.addObject("MechanicalObject", name="T", template="Vec1d", size=16, position=[1.0] + [0.0] * 15)
    heat.addObject("MeshMatrixMass", template="Vec1d,Vec3d", massDensity=1.0, topology=tets.linkpath, geometryState=geometry.linkpath)
    heat.addObject("FixedConstraint", indices=0)
    heat.addObject("TetrahedronDiffusionFEMForceField", template="Vec1d", constantDiffusionCoefficient=0.05,
                   tagMechanics="3dgeometry", topology=tets.linkpath)


if __name__ == "__main__":
    root = Sofa.Core.Node("root")
    createScene(root)
    Sofa.Simulation.init(root)
    out = []
    for _ in range(int(sys.argv[2]) if len(sys.argv) > 2 else 10):
        Sofa.Simulation.animate(root, root.dt.value)
        out.append(np.array(root.Bar.Heat.T.position.value).ravel().tolist())
    json.dump(out, open(sys.argv[1], "w"))
    print(out[-1][:6])
