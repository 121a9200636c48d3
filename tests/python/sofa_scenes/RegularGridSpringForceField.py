"""RegularGridSpringForceField: SOFA's example scene RegularGridSpringForceField.scn written as a SofaPython3 script.

Run it with `penalty run RegularGridSpringForceField.py --data-dir ../shared/sofa` or load it with
penalty.load_scene; the meshes (mesh/...) come from SOFA's data folder."""
import Sofa
import Sofa.Core
import Sofa.Simulation
import SofaRuntime


def createScene(rootNode):
    rootNode.dt = 0.02
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
    rootNode.addObject('CollisionPipeline', depth=6, verbose=0, draw=0)
    rootNode.addObject('BruteForceBroadPhase')
    rootNode.addObject('BVHNarrowPhase')
    rootNode.addObject('NewProximityIntersection', name='Proximity', alarmDistance=0.3, contactDistance=0.2)
    rootNode.addObject('CollisionResponse', name='Response', response='PenalityContactForceField')
    rootNode.addObject('DefaultAnimationLoop')
    chain = rootNode.addChild('Chain')
    torusFixed = chain.addChild('TorusFixed')
    torusFixed.addObject('MeshOBJLoader', name='loader', filename='mesh/torus2_for_collision.obj')
    torusFixed.addObject('MeshTopology', src='@loader')
    torusFixed.addObject('MechanicalObject', src='@loader')
    torusFixed.addObject('TriangleCollisionModel', simulated=0, moving=0)
    torusFixed.addObject('MeshOBJLoader', name='meshLoader_3', filename='mesh/torus2.obj', handleSeams=1)
    torusFixed.addObject('OglModel', name='Visual', src='@meshLoader_3', color='gray')
    torusFFD1 = chain.addChild('TorusFFD1')
    torusFFD1.addObject('EulerImplicitSolver', name='cg_odesolver', printLog=False, rayleighStiffness=0.1, rayleighMass=0.1)
    torusFFD1.addObject('CGLinearSolver', iterations=25, name='linear solver', tolerance=1.0e-9, threshold=1.0e-9)
    torusFFD1.addObject('MechanicalObject', translation=[2.5, 0, 0])
    torusFFD1.addObject('UniformMass', totalMass=5)
    torusFFD1.addObject('RegularGridTopology', nx=6, ny=2, nz=5, xmin=-2.5, xmax=2.5, ymin=-0.5, ymax=0.5, zmin=-2, zmax=2)
    torusFFD1.addObject('RegularGridSpringForceField', name='Springs', stiffness=200, damping=2)
    visu = torusFFD1.addChild('Visu')
    visu.addObject('MeshOBJLoader', name='meshLoader_4', filename='mesh/torus.obj', handleSeams=1)
    visu.addObject('OglModel', name='Visual', src='@meshLoader_4', dx=2.5, color='yellow')
    visu.addObject('BarycentricMapping', input='@..', output='@Visual')
    surf2 = torusFFD1.addChild('Surf2')
    surf2.addObject('MeshOBJLoader', name='loader', filename='mesh/torus_for_collision.obj')
    surf2.addObject('MeshTopology', src='@loader')
    surf2.addObject('MechanicalObject', src='@loader', translation=[2.5, 0, 0])
    surf2.addObject('TriangleCollisionModel')
    surf2.addObject('BarycentricMapping')
    torusFFD2 = chain.addChild('TorusFFD2')
    torusFFD2.addObject('EulerImplicitSolver', name='cg_odesolver', printLog=False)
    torusFFD2.addObject('CGLinearSolver', iterations=25, name='linear solver', tolerance=1.0e-9, threshold=1.0e-9)
    torusFFD2.addObject('MechanicalObject', dx=5)
    torusFFD2.addObject('UniformMass', totalMass=5)
    torusFFD2.addObject('RegularGridTopology', nx=6, ny=5, nz=2, xmin=-2.5, xmax=2.5, ymin=-2, ymax=2, zmin=-0.5, zmax=0.5)
    torusFFD2.addObject('RegularGridSpringForceField', name='Springs', stiffness=200, damping=2)
    visu2 = torusFFD2.addChild('Visu')
    visu2.addObject('MeshOBJLoader', name='meshLoader_1', filename='mesh/torus2.obj', handleSeams=1)
    visu2.addObject('OglModel', name='Visual', src='@meshLoader_1', dx=5, color='yellow')
    visu2.addObject('BarycentricMapping', input='@..', output='@Visual')
    surf22 = torusFFD2.addChild('Surf2')
    surf22.addObject('MeshOBJLoader', name='loader', filename='mesh/torus2_for_collision.obj')
    surf22.addObject('MeshTopology', src='@loader')
    surf22.addObject('MechanicalObject', src='@loader', dx=5)
    surf22.addObject('TriangleCollisionModel')
    surf22.addObject('BarycentricMapping')
    torusFFD3 = chain.addChild('TorusFFD3')
    torusFFD3.addObject('EulerImplicitSolver', name='cg_odesolver', printLog=False)
    torusFFD3.addObject('CGLinearSolver', iterations=25, name='linear solver', tolerance=1.0e-9, threshold=1.0e-9)
    torusFFD3.addObject('MechanicalObject', dx=7.5)
    torusFFD3.addObject('UniformMass', totalMass=5)
    torusFFD3.addObject('RegularGridTopology', nx=6, ny=2, nz=5, xmin=-2.5, xmax=2.5, ymin=-0.5, ymax=0.5, zmin=-2, zmax=2)
    torusFFD3.addObject('RegularGridSpringForceField', name='Springs', stiffness=200, damping=2)
    visu3 = torusFFD3.addChild('Visu')
    visu3.addObject('MeshOBJLoader', name='meshLoader_2', filename='mesh/torus.obj', handleSeams=1)
    visu3.addObject('OglModel', name='Visual', src='@meshLoader_2', dx=7.5, color='yellow')
    visu3.addObject('BarycentricMapping', input='@..', output='@Visual')
    surf23 = torusFFD3.addChild('Surf2')
    surf23.addObject('MeshOBJLoader', name='loader', filename='mesh/torus_for_collision.obj')
    surf23.addObject('MeshTopology', src='@loader')
    surf23.addObject('MechanicalObject', src='@loader', dx=7.5)
    surf23.addObject('TriangleCollisionModel')
    surf23.addObject('BarycentricMapping')
    torusFFD4 = chain.addChild('TorusFFD4')
    torusFFD4.addObject('EulerImplicitSolver', name='cg_odesolver', printLog=False)
    torusFFD4.addObject('CGLinearSolver', iterations=25, name='linear solver', tolerance=1.0e-9, threshold=1.0e-9)
    torusFFD4.addObject('MechanicalObject', dx=10)
    torusFFD4.addObject('UniformMass', totalMass=5)
    torusFFD4.addObject('RegularGridTopology', nx=6, ny=5, nz=2, xmin=-2.5, xmax=2.5, ymin=-2, ymax=2, zmin=-0.5, zmax=0.5)
    torusFFD4.addObject('RegularGridSpringForceField', name='Springs', stiffness=200, damping=2)
    visu4 = torusFFD4.addChild('Visu')
    visu4.addObject('MeshOBJLoader', name='meshLoader_0', filename='mesh/torus2.obj', handleSeams=1)
    visu4.addObject('OglModel', name='Visual', src='@meshLoader_0', dx=10, color='yellow')
    visu4.addObject('BarycentricMapping', input='@..', output='@Visual')
    surf24 = torusFFD4.addChild('Surf2')
    surf24.addObject('MeshOBJLoader', name='loader', filename='mesh/torus2_for_collision.obj')
    surf24.addObject('MeshTopology', src='@loader')
    surf24.addObject('MechanicalObject', src='@loader', dx=10)
    surf24.addObject('TriangleCollisionModel')
    surf24.addObject('BarycentricMapping')
    return rootNode


if __name__ == "__main__":
    root = Sofa.Core.Node("root")
    createScene(root)
    Sofa.Simulation.init(root)
    for _ in range(100):
        Sofa.Simulation.animate(root, root.dt.value)
    print("t =", root.time.value)
