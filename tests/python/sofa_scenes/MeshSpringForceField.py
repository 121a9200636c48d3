"""MeshSpringForceField: SOFA's example scene MeshSpringForceField.scn written as a SofaPython3 script.

Run it with `penalty run MeshSpringForceField.py --data-dir ../shared/sofa` or load it with
penalty.load_scene; the meshes (mesh/...) come from SOFA's data folder."""
import Sofa
import Sofa.Core
import Sofa.Simulation
import SofaRuntime


def createScene(rootNode):
    rootNode.dt = 0.01
    rootNode.gravity = [0, -9, 0]
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
            'Sofa.GL.Component.Rendering3D',
    ]:
        rootNode.addObject('RequiredPlugin', pluginName=plugin)
    rootNode.addObject('DefaultAnimationLoop')
    rootNode.addObject('CollisionPipeline', depth=6, verbose=0, draw=0)
    rootNode.addObject('BruteForceBroadPhase')
    rootNode.addObject('BVHNarrowPhase')
    rootNode.addObject('NewProximityIntersection', name='Proximity', alarmDistance=0.5, contactDistance=0.2)
    rootNode.addObject('CollisionResponse', name='Response', response='PenalityContactForceField')
    chainSpring = rootNode.addChild('ChainSpring')
    torusFixed = chainSpring.addChild('TorusFixed')
    torusFixed.addObject('MeshOBJLoader', name='loader', filename='mesh/torus2_for_collision.obj')
    torusFixed.addObject('MeshTopology', src='@loader')
    torusFixed.addObject('MechanicalObject', src='@loader')
    torusFixed.addObject('TriangleCollisionModel', simulated=0, moving=0)
    torusFixed.addObject('MeshOBJLoader', name='meshLoader_3', filename='mesh/torus2.obj', handleSeams=1)
    torusFixed.addObject('OglModel', name='Visual', src='@meshLoader_3', color='gray')
    torusSpring1 = chainSpring.addChild('TorusSpring1')
    torusSpring1.addObject('EulerImplicitSolver', name='cg_odesolver', printLog=False, rayleighStiffness=0.1, rayleighMass=0.1)
    torusSpring1.addObject('CGLinearSolver', iterations=100, name='linear solver', tolerance=1.0e-9, threshold=1.0e-9)
    torusSpring1.addObject('MeshGmshLoader', name='loader', filename='mesh/torus_low_res.msh', translation=[2.5, 0, 0])
    torusSpring1.addObject('MeshTopology', src='@loader')
    torusSpring1.addObject('MechanicalObject', src='@loader')
    torusSpring1.addObject('UniformMass', totalMass=5)
    torusSpring1.addObject('MeshSpringForceField', name='Springs', tetrasStiffness=1000, tetrasDamping=0)
    visu1 = torusSpring1.addChild('Visu1')
    visu1.addObject('MeshOBJLoader', name='meshLoader_0', filename='mesh/torus.obj', translation=[2.5, 0, 0], handleSeams=1)
    visu1.addObject('OglModel', name='Visual', src='@meshLoader_0', color='green')
    visu1.addObject('BarycentricMapping', input='@..', output='@Visual')
    surf1 = torusSpring1.addChild('Surf1')
    surf1.addObject('MeshOBJLoader', name='loader', filename='mesh/torus_for_collision.obj', translation=[2.5, 0, 0])
    surf1.addObject('MeshTopology', src='@loader')
    surf1.addObject('MechanicalObject', src='@loader')
    surf1.addObject('TriangleCollisionModel')
    surf1.addObject('BarycentricMapping')
    torusSpring2 = chainSpring.addChild('TorusSpring2')
    torusSpring2.addObject('EulerImplicitSolver', name='cg_odesolver', printLog=False)
    torusSpring2.addObject('CGLinearSolver', iterations=25, name='linear solver', tolerance=1.0e-9, threshold=1.0e-9)
    torusSpring2.addObject('MeshGmshLoader', name='loader', filename='mesh/torus2_low_res.msh', translation=[5, 0, 0])
    torusSpring2.addObject('MeshTopology', src='@loader')
    torusSpring2.addObject('MechanicalObject', src='@loader')
    torusSpring2.addObject('UniformMass', totalMass=5)
    torusSpring2.addObject('MeshSpringForceField', name='Springs', tetrasStiffness=200, tetrasDamping=0)
    visu2 = torusSpring2.addChild('Visu2')
    visu2.addObject('MeshOBJLoader', name='meshLoader_2', filename='mesh/torus2.obj', translation=[5, 0, 0], handleSeams=1)
    visu2.addObject('OglModel', name='Visual', src='@meshLoader_2', color='blue')
    visu2.addObject('BarycentricMapping', input='@..', output='@Visual')
    surf2 = torusSpring2.addChild('Surf2')
    surf2.addObject('MeshOBJLoader', name='loader', filename='mesh/torus2_for_collision.obj', translation=[5, 0, 0])
    surf2.addObject('MeshTopology', src='@loader')
    surf2.addObject('MechanicalObject', src='@loader')
    surf2.addObject('TriangleCollisionModel')
    surf2.addObject('BarycentricMapping')
    torusSpring3 = chainSpring.addChild('TorusSpring3')
    torusSpring3.addObject('EulerImplicitSolver', name='cg_odesolver', printLog=False)
    torusSpring3.addObject('CGLinearSolver', iterations=100, name='linear solver', tolerance=1.0e-9, threshold=1.0e-9)
    torusSpring3.addObject('MeshGmshLoader', name='loader', filename='mesh/torus_low_res.msh', translation=[7.5, 0, 0])
    torusSpring3.addObject('MeshTopology', src='@loader')
    torusSpring3.addObject('MechanicalObject', src='@loader')
    torusSpring3.addObject('UniformMass', totalMass=0.5)
    torusSpring3.addObject('MeshSpringForceField', name='Springs', tetrasStiffness=400, tetrasDamping=0)
    visu3 = torusSpring3.addChild('Visu3')
    visu3.addObject('MeshOBJLoader', name='meshLoader_1', filename='mesh/torus.obj', translation=[7.5, 0, 0], handleSeams=1)
    visu3.addObject('OglModel', name='Visual', src='@meshLoader_1', color='green')
    visu3.addObject('BarycentricMapping', input='@..', output='@Visual')
    surf3 = torusSpring3.addChild('Surf3')
    surf3.addObject('MeshOBJLoader', name='loader', filename='mesh/torus_for_collision.obj', translation=[7.5, 0, 0])
    surf3.addObject('MeshTopology', src='@loader')
    surf3.addObject('MechanicalObject', src='@loader')
    surf3.addObject('TriangleCollisionModel')
    surf3.addObject('BarycentricMapping')
    torusSpring4 = chainSpring.addChild('TorusSpring4')
    torusSpring4.addObject('EulerImplicitSolver', name='cg_odesolver', printLog=False)
    torusSpring4.addObject('CGLinearSolver', iterations=100, name='linear solver', tolerance=1.0e-9, threshold=1.0e-9)
    torusSpring4.addObject('MeshGmshLoader', name='loader', filename='mesh/torus2_low_res.msh', translation=[10, 0, 0])
    torusSpring4.addObject('MeshTopology', src='@loader')
    torusSpring4.addObject('MechanicalObject', src='@loader')
    torusSpring4.addObject('UniformMass', totalMass=0.5)
    torusSpring4.addObject('MeshSpringForceField', name='Springs', tetrasStiffness=400, tetrasDamping=0)
    visu4 = torusSpring4.addChild('Visu4')
    visu4.addObject('MeshOBJLoader', name='meshLoader_4', filename='mesh/torus2.obj', translation=[10, 0, 0], handleSeams=1)
    visu4.addObject('OglModel', name='Visual', src='@meshLoader_4', color='red')
    visu4.addObject('BarycentricMapping', input='@..', output='@Visual')
    surf4 = torusSpring4.addChild('Surf4')
    surf4.addObject('MeshOBJLoader', name='loader', filename='mesh/torus2_for_collision.obj', translation=[10, 0, 0])
    surf4.addObject('MeshTopology', src='@loader')
    surf4.addObject('MechanicalObject', src='@loader')
    surf4.addObject('TriangleCollisionModel')
    surf4.addObject('BarycentricMapping')
    return rootNode


if __name__ == "__main__":
    root = Sofa.Core.Node("root")
    createScene(root)
    Sofa.Simulation.init(root)
    for _ in range(100):
        Sofa.Simulation.animate(root, root.dt.value)
    print("t =", root.time.value)
