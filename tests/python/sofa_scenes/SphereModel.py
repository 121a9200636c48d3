"""SphereModel: SOFA's example scene SphereModel.scn written as a SofaPython3 script.

Run it with `penalty run SphereModel.py --data-dir ../shared/sofa` or load it with
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
            'Sofa.Component.SolidMechanics.FEM.Elastic',
            'Sofa.Component.StateContainer',
            'Sofa.Component.Topology.Container.Grid',
            'Sofa.Component.Visual',
            'Sofa.GL.Component.Rendering3D',
    ]:
        rootNode.addObject('RequiredPlugin', pluginName=plugin)
    rootNode.addObject('DefaultAnimationLoop')
    rootNode.addObject('VisualStyle', displayFlags='showBehaviorModels showForceFields showCollision')
    rootNode.addObject('CollisionPipeline', verbose=0)
    rootNode.addObject('BruteForceBroadPhase')
    rootNode.addObject('BVHNarrowPhase')
    rootNode.addObject('CollisionResponse', name='Response', response='PenalityContactForceField')
    rootNode.addObject('DiscreteIntersection')
    cubeFEM = rootNode.addChild('cubeFEM')
    cubeFEM.addObject('EulerImplicitSolver', name='cg_odesolver', printLog=False, rayleighStiffness=0.1, rayleighMass=0.1)
    cubeFEM.addObject('CGLinearSolver', iterations=25, name='linear solver', tolerance=1.0e-9, threshold=1.0e-9)
    cubeFEM.addObject('RegularGridTopology', nx=5, ny=5, nz=5, xmin=-3.5, xmax=3.5, ymin=-3.5, ymax=3.5, zmin=-3.5, zmax=3.5)
    cubeFEM.addObject('MechanicalObject')
    cubeFEM.addObject('UniformMass', vertexMass=0.25)
    cubeFEM.addObject('TetrahedronFEMForceField', name='FEM', youngModulus=25, poissonRatio=0.3, computeGlobalMatrix=False, updateStiffnessMatrix=False, method='large')
    visu = cubeFEM.addChild('Visu')
    visu.addObject('MeshOBJLoader', name='meshLoader_0', filename='mesh/smCube125.obj', handleSeams=1)
    visu.addObject('OglModel', name='Visual', src='@meshLoader_0', color='red')
    visu.addObject('SubsetMapping', input='@..', output='@Visual')
    surf = cubeFEM.addChild('Surf')
    surf.addObject('VisualStyle', displayFlags='hideCollision')
    surf.addObject('SphereLoader', filename='mesh/smCube27b.sph')
    surf.addObject('MechanicalObject', position='@[-1].position')
    surf.addObject('SphereCollisionModel', listRadius='@[-2].listRadius')
    surf.addObject('BarycentricMapping')
    rootNode.addObject('SphereLoader', filename='mesh/floor.sph')
    rootNode.addObject('MechanicalObject', position='@[-1].position', translation=[0, -12.5, 0])
    rootNode.addObject('SphereCollisionModel', name='Floor', listRadius='@[-2].listRadius', simulated=0, moving=0, contactStiffness=1000)
    floorVisual = rootNode.addChild('FloorVisual')
    floorVisual.addObject('MeshOBJLoader', name='meshLoader_1', filename='mesh/floor2.obj', translation=[0, -12.5, 0], handleSeams=1)
    floorVisual.addObject('OglModel', name='FloorV', src='@meshLoader_1', texturename='textures/floor2.bmp')
    return rootNode


if __name__ == "__main__":
    root = Sofa.Core.Node("root")
    createScene(root)
    Sofa.Simulation.init(root)
    for _ in range(100):
        Sofa.Simulation.animate(root, root.dt.value)
    print("t =", root.time.value)
