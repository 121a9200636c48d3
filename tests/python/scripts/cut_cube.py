"""A SofaPython3 scene whose controller cuts: a tetrahedral cube (2 × 2 × 2 cells, 6 tetrahedra
each) hangs from its top corners; from step `cut_from` on, the controller removes its first
tetrahedron each step through TetrahedronSetTopologyModifier.removeTetrahedra (docs/topological-changes.md)."""
import Sofa
import Sofa.Core


def grid_tetrahedra(n, size):
    points = [[x * size, y * size, z * size] for z in range(n + 1) for y in range(n + 1) for x in range(n + 1)]
    idx = lambda x, y, z: x + (n + 1) * (y + (n + 1) * z)
    tets = []
    for z in range(n):
        for y in range(n):
            for x in range(n):
                c = [idx(x + (k & 1), y + ((k >> 1) & 1), z + ((k >> 2) & 1)) for k in range(8)]
                # Kuhn's six tetrahedra around the diagonal c0–c7, positively oriented
                for a, b in ((1, 3), (3, 2), (2, 6), (6, 4), (4, 5), (5, 1)):
                    tets.append([c[0], c[b], c[a], c[7]])
    return points, tets


class Cutter(Sofa.Core.Controller):
    def __init__(self, *args, **kwargs):
        Sofa.Core.Controller.__init__(self, *args, **kwargs)
        self.modifier = kwargs["modifier"]
        self.cut_from = kwargs["cut_from"]
        self.steps = 0

    def onAnimateBeginEvent(self, event):
        self.steps += 1
        if self.steps >= self.cut_from:
            self.modifier.removeTetrahedra([0])


def createScene(rootNode, cut_from=3):
    rootNode.dt = 0.01
    rootNode.gravity = [0, -9.81, 0]
    rootNode.addObject("DefaultAnimationLoop")
    body = rootNode.addChild("Cube")
    body.addObject("EulerImplicitSolver", rayleighStiffness=0.1, rayleighMass=0.1)
    body.addObject("CGLinearSolver", iterations=100, tolerance=1e-12, threshold=1e-12)
    points, tets = grid_tetrahedra(2, 0.5)
    body.addObject("TetrahedronSetTopologyContainer", name="volume", position=points, tetrahedra=tets)
    body.addObject("TetrahedronSetTopologyModifier", name="modifier")
    body.addObject("MechanicalObject", name="dofs")
    body.addObject("DiagonalMass", massDensity=1000)
    body.addObject("TetrahedronFEMForceField", youngModulus=1e5, poissonRatio=0.3, method="large")
    body.addObject("BoxROI", name="top", box=[-0.01, 0.99, -0.01, 1.01, 1.01, 1.01])
    body.addObject("FixedProjectiveConstraint", indices="@top.indices")
    rootNode.addObject(Cutter(name="cutter", modifier=body.modifier, cut_from=cut_from))
    return rootNode
