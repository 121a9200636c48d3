"""Gravity: SOFA's example scene Gravity.scn written as a SofaPython3 script.

Run it with `penalty run Gravity.py --data-dir ../shared/sofa` or load it with
penalty.load_scene; the meshes (mesh/...) come from SOFA's data folder."""
import Sofa
import Sofa.Core
import Sofa.Simulation
import SofaRuntime


def createScene(rootNode):
    rootNode.dt = 0.03333
    for plugin in [
            'Sofa.Component.Collision.Detection.Algorithm',
            'Sofa.Component.Collision.Detection.Intersection',
            'Sofa.Component.Collision.Geometry',
            'Sofa.Component.Collision.Response.Contact',
            'Sofa.Component.IO.Mesh',
            'Sofa.Component.LinearSolver.Iterative',
            'Sofa.Component.Mapping.Linear',
            'Sofa.Component.Mass',
            'Sofa.Component.MechanicalLoad',
            'Sofa.Component.ODESolver.Backward',
            'Sofa.Component.SolidMechanics.Spring',
            'Sofa.Component.StateContainer',
            'Sofa.Component.Topology.Container.Constant',
            'Sofa.Component.Topology.Container.Grid',
            'Sofa.GL.Component.Rendering3D',
    ]:
        rootNode.addObject('RequiredPlugin', pluginName=plugin)
    rootNode.addObject('CollisionPipeline', verbose=0, depth=10, draw=0)
    rootNode.addObject('BruteForceBroadPhase')
    rootNode.addObject('BVHNarrowPhase')
    rootNode.addObject('MinProximityIntersection', name='Proximity', alarmDistance=0.75, contactDistance=0.5)
    rootNode.addObject('CollisionResponse', name='Response', response='PenalityContactForceField')
    rootNode.addObject('DefaultAnimationLoop')
    torus1 = rootNode.addChild('Torus1')
    torus1.addObject('Gravity', gravity=[0, -10, 0])
    torus1.addObject('EulerImplicitSolver', name='cg_odesolver', printLog=False, rayleighStiffness=0.1, rayleighMass=0.1)
    torus1.addObject('CGLinearSolver', iterations=25, name='linear solver', tolerance=1.0e-9, threshold=1.0e-9)
    torus1.addObject('MechanicalObject', dx=0, dy=20, dz=0, ry=90)
    torus1.addObject('UniformMass', totalMass=10)
    torus1.addObject('RegularGridTopology', nx=6, ny=5, nz=2, xmin=-7.5, xmax=7.5, ymin=-6, ymax=6, zmin=-1.75, zmax=1.75)
    torus1.addObject('RegularGridSpringForceField', name='Springs', stiffness=350, damping=1)
    visu = torus1.addChild('Visu')
    visu.addObject('MeshOBJLoader', name='meshLoader_0', filename='mesh/torus2_scale3.obj', handleSeams=1)
    visu.addObject('OglModel', name='Visual', src='@meshLoader_0', color='blue')
    visu.addObject('BarycentricMapping', input='@..', output='@Visual')
    surf = torus1.addChild('Surf')
    surf.addObject('MeshOBJLoader', name='loader', filename='mesh/torus2_scale3.obj')
    surf.addObject('MeshTopology', src='@loader')
    surf.addObject('MechanicalObject', src='@loader')
    surf.addObject('TriangleCollisionModel')
    surf.addObject('LineCollisionModel')
    surf.addObject('PointCollisionModel')
    surf.addObject('BarycentricMapping')
    torus2 = rootNode.addChild('Torus2')
    torus2.addObject('Gravity', gravity=[0, 10, 0])
    torus2.addObject('EulerImplicitSolver', name='cg_odesolver', printLog=False)
    torus2.addObject('CGLinearSolver', iterations=25, name='linear solver', tolerance=1.0e-9, threshold=1.0e-9)
    torus2.addObject('MechanicalObject', dx=0, dy=-20, dz=0)
    torus2.addObject('UniformMass', totalMass=10)
    torus2.addObject('RegularGridTopology', nx=6, ny=5, nz=2, xmin=-7.5, xmax=7.5, ymin=-6, ymax=6, zmin=-1.75, zmax=1.75)
    torus2.addObject('RegularGridSpringForceField', name='Springs', stiffness=350, damping=1)
    visu2 = torus2.addChild('Visu')
    visu2.addObject('MeshOBJLoader', name='meshLoader_3', filename='mesh/torus2_scale3.obj', handleSeams=1)
    visu2.addObject('OglModel', name='Visual', src='@meshLoader_3', color='blue')
    visu2.addObject('BarycentricMapping', input='@..', output='@Visual')
    surf2 = torus2.addChild('Surf')
    surf2.addObject('MeshOBJLoader', name='loader', filename='mesh/torus2_scale3.obj')
    surf2.addObject('MeshTopology', src='@loader')
    surf2.addObject('MechanicalObject', src='@loader')
    surf2.addObject('TriangleCollisionModel')
    surf2.addObject('LineCollisionModel')
    surf2.addObject('PointCollisionModel')
    surf2.addObject('BarycentricMapping')
    floor = rootNode.addChild('Floor')
    floor.addObject('MeshOBJLoader', name='loader', filename='mesh/floor2b.obj')
    floor.addObject('MeshTopology', src='@loader')
    floor.addObject('MechanicalObject', src='@loader', dy=30.25, scale=0.7, rx=180)
    floor.addObject('TriangleCollisionModel', name='FloorTri1', simulated=0, moving=0)
    floor.addObject('LineCollisionModel', name='FloorLine1', simulated=0, moving=0)
    floor.addObject('PointCollisionModel', name='FloorPoint1', simulated=0, moving=0)
    floor.addObject('MeshOBJLoader', name='meshLoader_1', filename='mesh/floor2b.obj', scale=0.5, handleSeams=1)
    floor.addObject('OglModel', name='FloorV', src='@meshLoader_1', texturename='textures/floor.bmp', rx=180, dy=30)
    floor2 = rootNode.addChild('Floor2')
    floor2.addObject('MeshOBJLoader', name='loader', filename='mesh/floor2b.obj')
    floor2.addObject('MeshTopology', src='@loader')
    floor2.addObject('MechanicalObject', src='@loader', dy=-30.25, scale=0.7)
    floor2.addObject('TriangleCollisionModel', name='FloorTri2', simulated=0, moving=0)
    floor2.addObject('LineCollisionModel', name='FloorLine2', simulated=0, moving=0)
    floor2.addObject('PointCollisionModel', name='FloorPoint2', simulated=0, moving=0)
    floor2.addObject('MeshOBJLoader', name='meshLoader_2', filename='mesh/floor2b.obj', scale=0.5, handleSeams=1)
    floor2.addObject('OglModel', name='FloorV', src='@meshLoader_2', texturename='textures/floor.bmp', dy=-30)
    return rootNode


if __name__ == "__main__":
    root = Sofa.Core.Node("root")
    createScene(root)
    Sofa.Simulation.init(root)
    for _ in range(100):
        Sofa.Simulation.animate(root, root.dt.value)
    print("t =", root.time.value)
