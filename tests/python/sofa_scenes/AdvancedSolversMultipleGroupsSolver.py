"""AdvancedSolversMultipleGroupsSolver: SOFA's example scene AdvancedSolversMultipleGroupsSolver.scn written as a SofaPython3 script.

Run it with `penalty run AdvancedSolversMultipleGroupsSolver.py --data-dir ../shared/sofa` or load it with
penalty.load_scene; the meshes (mesh/...) come from SOFA's data folder."""
import Sofa
import Sofa.Core
import Sofa.Simulation
import SofaRuntime


def createScene(rootNode):
    rootNode.dt = 0.01
    rootNode.gravity = [0, 0, -9.81]
    for plugin in [
            'Sofa.Component.Collision.Detection.Algorithm',
            'Sofa.Component.Collision.Detection.Intersection',
            'Sofa.Component.Collision.Geometry',
            'Sofa.Component.Collision.Response.Contact',
            'Sofa.Component.LinearSolver.Iterative',
            'Sofa.Component.Mass',
            'Sofa.Component.ODESolver.Backward',
            'Sofa.Component.SolidMechanics.Spring',
            'Sofa.Component.StateContainer',
            'Sofa.Component.Topology.Container.Constant',
            'Sofa.Component.Visual',
    ]:
        rootNode.addObject('RequiredPlugin', pluginName=plugin)
    rootNode.addObject('VisualStyle', displayFlags='showForceFields showCollisionModels')
    rootNode.addObject('CollisionPipeline')
    rootNode.addObject('BruteForceBroadPhase')
    rootNode.addObject('BVHNarrowPhase')
    rootNode.addObject('CollisionResponse', response='PenalityContactForceField')
    rootNode.addObject('MinProximityIntersection', alarmDistance=0.5, contactDistance=0.2)
    rootNode.addObject('DefaultAnimationLoop')
    solverNode = rootNode.addChild('SolverNode')
    solverNode.addObject('EulerImplicitSolver', name='EulerImplicit', rayleighStiffness=0.1, rayleighMass=0.1)
    solverNode.addObject('CGLinearSolver', name='CG Solver', iterations=25, tolerance=1e-5, threshold=1e-5)
    cubeSphere1 = solverNode.addChild('CubeSphere1')
    cubeSphere1.addObject('MechanicalObject', name='Particles', template='Vec3', position=[0, 0, 1, 1, 0, 1, 0, 1, 1, 1, 1, 1, 0, 0, 2, 1, 0, 2, 0, 1, 2, 1, 1, 2], translation=[-2, 1, 2])
    cubeSphere1.addObject('MeshTopology', name='Topology', hexas=[0, 4, 6, 2, 1, 5, 7, 3])
    cubeSphere1.addObject('UniformMass', name='Mass', totalMass=1)
    cubeSphere1.addObject('MeshSpringForceField', name='Springs', stiffness=100, damping=1)
    cubeSphere1.addObject('SphereCollisionModel', name='Spheres Cube1', radius=0.4)
    cubeSphere2 = solverNode.addChild('CubeSphere2')
    cubeSphere2.addObject('MechanicalObject', name='Particles', template='Vec3', position=[0, 0, 1, 1, 0, 1, 0, 1, 1, 1, 1, 1, 0, 0, 2, 1, 0, 2, 0, 1, 2, 1, 1, 2], translation=[0, 0, 6])
    cubeSphere2.addObject('MeshTopology', name='Topology', hexas=[0, 4, 6, 2, 1, 5, 7, 3])
    cubeSphere2.addObject('UniformMass', name='Mass', totalMass=1)
    cubeSphere2.addObject('MeshSpringForceField', name='Springs', stiffness=100, damping=1)
    cubeSphere2.addObject('SphereCollisionModel', name='Spheres Cube2', radius=0.4)
    cubeGeometry1 = solverNode.addChild('CubeGeometry1')
    cubeGeometry1.addObject('MechanicalObject', name='Particles', template='Vec3', position=[0, 0, 1, 1, 0, 1, 0, 1, 1, 1, 1, 1, 0, 0, 2, 1, 0, 2, 0, 1, 2, 1, 1, 2], translation=[0, 1, 2])
    cubeGeometry1.addObject('MeshTopology', name='Topology', hexas=[0, 4, 6, 2, 1, 5, 7, 3])
    cubeGeometry1.addObject('UniformMass', name='Mass', totalMass=1)
    cubeGeometry1.addObject('MeshSpringForceField', name='Springs', stiffness=100, damping=1)
    cubeGeometry1.addObject('TriangleCollisionModel', name='Triangles CubeGeometry1')
    cubeGeometry1.addObject('LineCollisionModel', name='Lines CubeGeometry1')
    cubeGeometry1.addObject('PointCollisionModel', name='Points CubeGeometry1')
    cubeGeometry2 = solverNode.addChild('CubeGeometry2')
    cubeGeometry2.addObject('MechanicalObject', name='Particles', template='Vec3', position=[0, 0, 1, 1, 0, 1, 0, 1, 1, 1, 1, 1, 0, 0, 2, 1, 0, 2, 0, 1, 2, 1, 1, 2], translation=[2, 1, 2])
    cubeGeometry2.addObject('MeshTopology', name='Topology', hexas=[0, 4, 6, 2, 1, 5, 7, 3])
    cubeGeometry2.addObject('UniformMass', name='Mass', totalMass=1)
    cubeGeometry2.addObject('MeshSpringForceField', name='Springs', stiffness=100, damping=1)
    cubeGeometry2.addObject('TriangleCollisionModel', name='Triangles CubeGeometry2')
    cubeGeometry2.addObject('LineCollisionModel', name='Lines CubeGeometry2')
    cubeGeometry2.addObject('PointCollisionModel', name='Points CubeGeometry2')
    saladBowl = rootNode.addChild('SaladBowl')
    saladBowl.addObject('MeshTopology', name='Topology Salad Bowl', filename='mesh/SaladBowl.obj')
    saladBowl.addObject('MechanicalObject', name='Particles Salad Bowl', scale=10)
    saladBowl.addObject('TriangleCollisionModel', name='Triangles Salad Bowl', moving=0, simulated=0)
    saladBowl.addObject('LineCollisionModel', name='Lines Salad Bowl', moving=0, simulated=0)
    saladBowl.addObject('PointCollisionModel', name='Points Salad Bowl', moving=0, simulated=0)
    return rootNode


if __name__ == "__main__":
    root = Sofa.Core.Node("root")
    createScene(root)
    Sofa.Simulation.init(root)
    for _ in range(100):
        Sofa.Simulation.animate(root, root.dt.value)
    print("t =", root.time.value)
