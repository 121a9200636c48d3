"""ModelizationTriangleBased: SOFA's example scene ModelizationTriangleBased.scn written as a SofaPython3 script.

Run it with `penalty run ModelizationTriangleBased.py --data-dir ../shared/sofa` or load it with
penalty.load_scene; the meshes (mesh/...) come from SOFA's data folder."""
import Sofa
import Sofa.Core
import Sofa.Simulation
import SofaRuntime


def createScene(rootNode):
    rootNode.dt = 0.01
    rootNode.gravity = [0, -9.81, 0]
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
    rootNode.addObject('VisualStyle', displayFlags='showBehavior showCollisionModels')
    rootNode.addObject('CollisionPipeline')
    rootNode.addObject('BruteForceBroadPhase')
    rootNode.addObject('BVHNarrowPhase')
    rootNode.addObject('CollisionResponse', response='PenalityContactForceField')
    rootNode.addObject('DefaultAnimationLoop')
    rootNode.addObject('MinProximityIntersection', alarmDistance=1, contactDistance=0.5)
    cube = rootNode.addChild('Cube')
    cube.addObject('EulerImplicitSolver', name='EulerImplicit', rayleighStiffness=0.1, rayleighMass=0.1)
    cube.addObject('CGLinearSolver', name='CG Solver', iterations=25, tolerance=1e-5, threshold=1e-5)
    cube.addObject('MechanicalObject', name='Particles', template='Vec3', position=[0, 0, 1, 1, 0, 1, 0, 1, 1, 1, 1, 1, 0, 0, 2, 1, 0, 2, 0, 1, 2, 1, 1, 2])
    cube.addObject('MeshTopology', name='Topology', hexas=[0, 4, 6, 2, 1, 5, 7, 3])
    cube.addObject('UniformMass', name='Mass', totalMass=1)
    cube.addObject('MeshSpringForceField', name='Springs', stiffness=100, damping=1)
    cube.addObject('TriangleCollisionModel', name='Triangles For Collision')
    cube.addObject('LineCollisionModel', name='Lines For Collision')
    cube.addObject('PointCollisionModel', name='Points For Collision')
    floor = rootNode.addChild('Floor')
    floor.addObject('MeshTopology', name='Topology Floor', filename='mesh/floor.obj')
    floor.addObject('MechanicalObject', name='Floor Particles')
    floor.addObject('TriangleCollisionModel', name='Floor Triangle For Collision', moving=0, simulated=0)
    return rootNode


if __name__ == "__main__":
    root = Sofa.Core.Node("root")
    createScene(root)
    Sofa.Simulation.init(root)
    for _ in range(100):
        Sofa.Simulation.animate(root, root.dt.value)
    print("t =", root.time.value)
