"""collisionMultiple: SOFA's example scene collisionMultiple.scn written as a SofaPython3 script.

Run it with `penalty run collisionMultiple.py --data-dir ../shared/sofa` or load it with
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
            'Sofa.Component.ODESolver.Backward',
            'Sofa.Component.SolidMechanics.Spring',
            'Sofa.Component.StateContainer',
            'Sofa.Component.Topology.Container.Constant',
            'Sofa.Component.Topology.Container.Grid',
            'Sofa.GL.Component.Rendering3D',
    ]:
        rootNode.addObject('RequiredPlugin', pluginName=plugin)
    rootNode.addObject('CollisionPipeline', verbose=0, depth=10, draw=0)
    rootNode.addObject('DefaultAnimationLoop')
    rootNode.addObject('BruteForceBroadPhase')
    rootNode.addObject('BVHNarrowPhase')
    rootNode.addObject('MinProximityIntersection', name='Proximity', alarmDistance=0.75, contactDistance=0.5)
    rootNode.addObject('CollisionResponse', name='Response', response='PenalityContactForceField')
    rootNode.addObject('MeshOBJLoader', name='Loader-torus', filename='mesh/torus2_scale3.obj')
    rootNode.addObject('MeshOBJLoader', name='Loader-dragon', filename='mesh/dragon.obj')
    rootNode.addObject('MeshOBJLoader', name='Loader-frog_body', filename='mesh/frog_body.obj')
    rootNode.addObject('MeshOBJLoader', name='Loader-frog_eyes', filename='mesh/frog_eyes.obj')
    rootNode.addObject('MeshOBJLoader', name='Loader-frog_eyebrows', filename='mesh/frog_eyebrows.obj')
    rootNode.addObject('MeshOBJLoader', name='Loader-frog_lips', filename='mesh/frog_lips.obj')
    rootNode.addObject('MeshOBJLoader', name='Loader-floor', filename='mesh/floor2b.obj')
    torus = rootNode.addChild('Torus')
    torus.addObject('EulerImplicitSolver', name='cg_odesolver', printLog=False, rayleighStiffness=0.1, rayleighMass=0.1)
    torus.addObject('CGLinearSolver', iterations=25, name='linear solver', tolerance=1.0e-9, threshold=1.0e-9)
    torus.addObject('MechanicalObject', dx=0, dy=20, dz=29, rz=64)
    torus.addObject('UniformMass', totalMass=10)
    torus.addObject('RegularGridTopology', nx=6, ny=5, nz=2, xmin=-7.5, xmax=7.5, ymin=-6, ymax=6, zmin=-1.75, zmax=1.75)
    torus.addObject('RegularGridSpringForceField', name='Springs', stiffness=350, damping=1)
    visuTorus = torus.addChild('VisuTorus')
    visuTorus.tags = 'Visual'
    visuTorus.addObject('OglModel', name='Visual', src='@../../Loader-torus', color='blue')
    visuTorus.addObject('BarycentricMapping', input='@..', output='@Visual')
    surf = torus.addChild('Surf')
    surf.addObject('MeshOBJLoader', name='loader', filename='mesh/torus2_scale3.obj')
    surf.addObject('MeshTopology', src='@loader')
    surf.addObject('MechanicalObject', src='@loader')
    surf.addObject('TriangleCollisionModel')
    surf.addObject('LineCollisionModel')
    surf.addObject('PointCollisionModel')
    surf.addObject('BarycentricMapping')
    dragon = rootNode.addChild('Dragon')
    dragon.addObject('EulerImplicitSolver', name='cg_odesolver', printLog=False)
    dragon.addObject('CGLinearSolver', iterations=25, name='linear solver', tolerance=1.0e-9, threshold=1.0e-9)
    dragon.addObject('MechanicalObject', dx=20, dy=20, dz=29, rx=33)
    dragon.addObject('UniformMass', totalMass=10)
    dragon.addObject('RegularGridTopology', nx=6, ny=5, nz=3, xmin=-11, xmax=11, ymin=-7, ymax=7, zmin=-4, zmax=4)
    dragon.addObject('RegularGridSpringForceField', name='Springs', stiffness=350, damping=1)
    visuDragon = dragon.addChild('VisuDragon')
    visuDragon.tags = 'Visual'
    visuDragon.addObject('OglModel', name='Visual', src='@../../Loader-dragon', color='red')
    visuDragon.addObject('BarycentricMapping', input='@..', output='@Visual')
    surf2 = dragon.addChild('Surf')
    surf2.addObject('MeshOBJLoader', name='loader', filename='mesh/dragon.obj')
    surf2.addObject('MeshTopology', src='@loader')
    surf2.addObject('MechanicalObject', src='@loader')
    surf2.addObject('TriangleCollisionModel')
    surf2.addObject('LineCollisionModel')
    surf2.addObject('PointCollisionModel')
    surf2.addObject('BarycentricMapping')
    frog = rootNode.addChild('Frog')
    frog.addObject('EulerImplicitSolver', name='cg_odesolver', printLog=False)
    frog.addObject('CGLinearSolver', iterations=25, name='linear solver', tolerance=1.0e-9, threshold=1.0e-9)
    frog.addObject('MechanicalObject', dx=-20, dy=20, dz=29, ry=10)
    frog.addObject('UniformMass', totalMass=10)
    frog.addObject('RegularGridTopology', nx=6, ny=3, nz=5, xmin=-10, xmax=8, ymin=-3, ymax=2.5, zmin=-7, zmax=7)
    frog.addObject('RegularGridSpringForceField', name='Springs', stiffness=350, damping=1)
    visualFrog = frog.addChild('VisualFrog')
    visualFrog.tags = 'Visual'
    visu1 = visualFrog.addChild('Visu1')
    visu1.addObject('OglModel', name='VisualBody', src='@../../../Loader-frog_body', normals=0, color=[0.17, 0.70, 0.05])
    visu1.addObject('BarycentricMapping', input='@..', output='@VisualBody')
    visu2 = visualFrog.addChild('Visu2')
    visu2.addObject('OglModel', name='VisualEyes', src='@../../../Loader-frog_eyes', normals=0, color=[0.04, 0.19, 0.52])
    visu2.addObject('BarycentricMapping', input='@..', output='@VisualEyes')
    visu3 = visualFrog.addChild('Visu3')
    visu3.addObject('OglModel', name='VisualEyebrows', src='@../../../Loader-frog_eyebrows', normals=0, color=[0.44, 0.43, 0.00])
    visu3.addObject('BarycentricMapping', input='@..', output='@VisualEyebrows')
    visu4 = visualFrog.addChild('Visu4')
    visu4.addObject('OglModel', name='VisualLips', src='@../../../Loader-frog_lips', normals=0, color=[0.47, 0.25, 0.03])
    visu4.addObject('BarycentricMapping', input='@..', output='@VisualLips')
    surf3 = frog.addChild('Surf')
    surf3.addObject('MeshOBJLoader', name='loader', filename='mesh/frog-push25.obj')
    surf3.addObject('MeshTopology', src='@loader')
    surf3.addObject('MechanicalObject', src='@loader')
    surf3.addObject('TriangleCollisionModel')
    surf3.addObject('LineCollisionModel')
    surf3.addObject('PointCollisionModel')
    surf3.addObject('BarycentricMapping')
    floor = rootNode.addChild('Floor')
    floor.addObject('MeshOBJLoader', name='loader', filename='mesh/floor2b.obj')
    floor.addObject('MeshTopology', src='@loader')
    floor.addObject('MechanicalObject', src='@loader', dy=-10.25, scale=0.5)
    floor.addObject('TriangleCollisionModel', name='FloorTriangleModel', simulated=0, moving=0)
    floor.addObject('LineCollisionModel', name='FloorLineModel', simulated=0, moving=0)
    floor.addObject('PointCollisionModel', name='FloorPointModel', simulated=0, moving=0)
    visu = floor.addChild('Visu')
    visu.addObject('OglModel', name='FloorV', src='@../../../Loader-floor', scale=0.5, texturename='textures/floor.bmp', dy=-10)
    return rootNode


if __name__ == "__main__":
    root = Sofa.Core.Node("root")
    createScene(root)
    Sofa.Simulation.init(root)
    for _ in range(100):
        Sofa.Simulation.animate(root, root.dt.value)
    print("t =", root.time.value)
