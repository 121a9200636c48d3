"""A small SofaPython3 scene: a spring cube falls on a fixed triangle floor; a controller counts
the steps, records the lowest point and pushes the cube sideways through writeableArray."""
import numpy as np

import Sofa
import Sofa.Core
import Sofa.Simulation
import SofaRuntime


class Recorder(Sofa.Core.Controller):
    def __init__(self, *args, **kwargs):
        Sofa.Core.Controller.__init__(self, *args, **kwargs)
        self.cube = kwargs["cube"]
        self.begin_calls = 0
        self.end_calls = 0
        self.lowest = []
        self.push = kwargs.get("push", 0.0)

    def onAnimateBeginEvent(self, event):
        self.begin_calls += 1
        if self.push and self.begin_calls == 1:
            with self.cube.dofs.velocity.writeableArray() as v:
                v[:, 0] += self.push

    def onAnimateEndEvent(self, event):
        self.end_calls += 1
        self.lowest.append(float(self.cube.dofs.position.value[:, 1].min()))


def createScene(rootNode, push=0.0):
    SofaRuntime.importPlugin("Sofa.Component.StateContainer")
    rootNode.dt = 0.01
    rootNode.gravity = [0, -9.81, 0]
    rootNode.addObject("RequiredPlugin", pluginName="Sofa.Component.Collision.Geometry")
    rootNode.addObject("DefaultAnimationLoop")
    rootNode.addObject("CollisionPipeline")
    rootNode.addObject("BruteForceBroadPhase")
    rootNode.addObject("BVHNarrowPhase")
    rootNode.addObject("MinProximityIntersection", alarmDistance=0.3, contactDistance=0.1)
    rootNode.addObject("CollisionResponse", response="PenalityContactForceField")

    cube = rootNode.addChild("Cube")
    cube.addObject("EulerImplicitSolver", rayleighStiffness=0.1, rayleighMass=0.1)
    cube.addObject("CGLinearSolver", iterations=50, tolerance=1e-9, threshold=1e-9)
    corners = np.array([[x, y, z] for z in (0.0, 1.0) for y in (1.0, 2.0) for x in (0.0, 1.0)])
    cube.addObject("MechanicalObject", name="dofs", template="Vec3d", position=corners)
    cube.addObject("MeshTopology", hexas=[[0, 1, 3, 2, 4, 5, 7, 6]])
    cube.addObject("UniformMass", totalMass=1.0)
    cube.addObject("MeshSpringForceField", stiffness=500, damping=1)
    cube.addObject("PointCollisionModel", name="points")

    floor = rootNode.addChild("Floor")
    floor.addObject("MechanicalObject", name="dofs", position=[[-5, 0, -5], [5, 0, -5], [5, 0, 5], [-5, 0, 5]])
    floor.addObject("MeshTopology", triangles=[0, 2, 1, 0, 3, 2])
    floor.addObject("TriangleCollisionModel", name="triangles", simulated=False, moving=False)

    rootNode.addObject(Recorder(name="recorder", cube=cube, push=push))
    return rootNode


if __name__ == "__main__":
    root = Sofa.Core.Node("root")
    createScene(root)
    Sofa.Simulation.init(root)
    for _ in range(150):
        Sofa.Simulation.animate(root, root.dt.value)
    print(f"lowest {root.recorder.lowest[-1]:.6f} after {root.recorder.end_calls} steps")
