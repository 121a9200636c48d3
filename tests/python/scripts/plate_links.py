"""A ball dropped on the project's plate mesh (scenes/mesh/plate.obj), the loader's outputs
linked either as text ("@loader", "@loader.position") or as Python objects (loader,
loader.position): both give the same scene."""
import Sofa.Core


def createScene(rootNode, links_as_objects=True):
    rootNode.dt = 0.005
    rootNode.addObject("DefaultAnimationLoop")
    rootNode.addObject("CollisionPipeline")
    rootNode.addObject("BruteForceBroadPhase")
    rootNode.addObject("BVHNarrowPhase")
    rootNode.addObject("NewProximityIntersection", alarmDistance=0.15, contactDistance=0.02)
    rootNode.addObject("CollisionResponse", response="PenalityContactForceField")
    rootNode.addObject("EulerImplicitSolver", rayleighStiffness=0.05, rayleighMass=0.1)
    rootNode.addObject("CGLinearSolver", iterations=200, tolerance=1e-12, threshold=1e-18)

    plate = rootNode.addChild("Plate")
    loader = plate.addObject("MeshOBJLoader", name="loader", filename="mesh/plate.obj")
    if links_as_objects:
        plate.addObject("MeshTopology", src=loader)
        plate.addObject("MechanicalObject", name="plate", position=loader.position)
    else:
        plate.addObject("MeshTopology", src="@loader")
        plate.addObject("MechanicalObject", name="plate", position="@loader.position")
    plate.addObject("UniformMass", totalMass=1)
    plate.addObject("FixedProjectiveConstraint", fixAll=True)
    plate.addObject("TriangleCollisionModel", name="plate_triangles", simulated=False, moving=False)

    ball = rootNode.addChild("Ball")
    ball.addObject("MechanicalObject", name="ball", position=(-0.67, 0.15, -0.67))
    ball.addObject("UniformMass", totalMass=0.1)
    ball.addObject("SphereCollisionModel", name="ball_sphere", radius=0.1)
