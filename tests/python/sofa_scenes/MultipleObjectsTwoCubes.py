"""MultipleObjectsTwoCubes: SOFA's example scene MultipleObjectsTwoCubes.scn written as a SofaPython3 script.

Run it with `penalty run MultipleObjectsTwoCubes.py --data-dir ../shared/sofa` or load it with
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
    rootNode.addObject('MinProximityIntersection', alarmDistance=1, contactDistance=0.5)
    rootNode.addObject('DefaultAnimationLoop')
    cube1 = rootNode.addChild('Cube1')
    cube1.addObject('EulerImplicitSolver', name='EulerImplicit Cube1', rayleighStiffness=0.1, rayleighMass=0.1)
    cube1.addObject('CGLinearSolver', name='CG Solver Cube1', iterations=25, tolerance=1e-5, threshold=1e-5)
    cube1.addObject('MechanicalObject', name='Particles Cube1', template='Vec3', position=[0, 0, 1, 1, 0, 1, 0, 1, 1, 1, 1, 1, 0, 0, 2, 1, 0, 2, 0, 1, 2, 1, 1, 2], translation=[0.5, 2, 0])
    cube1.addObject('MeshTopology', name='Topology Cube1', hexas=[0, 4, 6, 2, 1, 5, 7, 3])
    cube1.addObject('UniformMass', name='Mass Cube1', totalMass=1)
    cube1.addObject('MeshSpringForceField', name='Springs Cube1', stiffness=100, damping=1)
    cube1.addObject('SphereCollisionModel', name='Spheres For Collision Cube1', radius=0.2)
    cube2 = rootNode.addChild('Cube2')
    cube2.addObject('EulerImplicitSolver', name='EulerImplicit Cube2')
    cube2.addObject('CGLinearSolver', name='CG Solver Cube2', iterations=25, tolerance=1e-5, threshold=1e-5)
    cube2.addObject('MechanicalObject', name='Particles Cube2', template='Vec3', position=[0, 0, 1, 1, 0, 1, 0, 1, 1, 1, 1, 1, 0, 0, 2, 1, 0, 2, 0, 1, 2, 1, 1, 2])
    cube2.addObject('MeshTopology', name='Topology Cube2', hexas=[0, 4, 6, 2, 1, 5, 7, 3])
    cube2.addObject('UniformMass', name='Mass Cube2', totalMass=1)
    cube2.addObject('MeshSpringForceField', name='Springs Cube2', stiffness=15, damping=1)
    cube2.addObject('TriangleCollisionModel', name='Triangles For Collision')
    cube2.addObject('LineCollisionModel', name='Lines For Collision')
    cube2.addObject('PointCollisionModel', name='Points For Collision')
    floor = rootNode.addChild('Floor')
    floor.addObject('MeshTopology', name='Topology Floor', filename='mesh/floor.obj')
    floor.addObject('MechanicalObject', name='Particles Floor')
    floor.addObject('TriangleCollisionModel', name='Triangle For Collision Floor', moving=0, simulated=0)
    return rootNode


if __name__ == "__main__":
    root = Sofa.Core.Node("root")
    createScene(root)
    Sofa.Simulation.init(root)
    for _ in range(100):
        Sofa.Simulation.animate(root, root.dt.value)
    print("t =", root.time.value)
