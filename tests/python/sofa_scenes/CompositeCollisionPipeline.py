"""CompositeCollisionPipeline: SOFA's example scene CompositeCollisionPipeline.scn written as a SofaPython3 script.

Run it with `penalty run CompositeCollisionPipeline.py --data-dir ../shared/sofa` or load it with
penalty.load_scene; the meshes (mesh/...) come from SOFA's data folder."""
import Sofa
import Sofa.Core
import Sofa.Simulation
import SofaRuntime


def createScene(rootNode):
    rootNode.dt = 0.01
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
            'Sofa.Component.StateContainer',
            'Sofa.Component.Topology.Container.Constant',
            'Sofa.Component.Visual',
    ]:
        rootNode.addObject('RequiredPlugin', pluginName=plugin)
    rootNode.addObject('DefaultAnimationLoop')
    rootNode.addObject('VisualStyle', displayFlags='showVisualModels hideBehaviorModels showCollisionModels hideMappings hideForceFields')
    rootNode.addObject('MeshOBJLoader', name='torus_loader', filename='mesh/torus.obj')
    fixedTorusAndFallingSphere_1 = rootNode.addChild('FixedTorusAndFallingSphere_1')
    fallingSphere = fixedTorusAndFallingSphere_1.addChild('FallingSphere')
    fallingSphere.addObject('EulerImplicitSolver', name='odesolver')
    fallingSphere.addObject('CGLinearSolver', name='linear_solver', iterations=250, tolerance=1.0e-9, threshold=1.0e-9)
    fallingSphere.addObject('MechanicalObject', name='rigid', template='Rigid3d', position=[-5, 10, 0, 0, 0, 0, 1])
    fallingSphere.addObject('UniformMass', totalMass=1.0)
    collision = fallingSphere.addChild('Collision')
    collision.addObject('MechanicalObject', name='collision_rigid')
    collision.addObject('SphereCollisionModel', name='sphere', radius=1, contactStiffness=1)
    collision.addObject('IdentityMapping', input='@../rigid', output='@collision_rigid')
    fixedTorus = fixedTorusAndFallingSphere_1.addChild('FixedTorus')
    collision2 = fixedTorus.addChild('Collision')
    collision2.addObject('MechanicalObject', name='collision_torus', src='@../../../torus_loader', translation=[-5, 0, 0], scale3d=[0.8, 0.8, 0.8])
    collision2.addObject('MeshTopology', name='topology', src='@../../../torus_loader')
    collision2.addObject('TriangleCollisionModel', name='triangle_collision', simulated=0, moving=0, contactStiffness=1)
    collision2.addObject('LineCollisionModel', name='line_collision', simulated=0, moving=0, contactStiffness=1)
    collision2.addObject('PointCollisionModel', name='point_collision', simulated=0, moving=0, contactStiffness=1)
    fixedTorusAndFallingSphere_2 = rootNode.addChild('FixedTorusAndFallingSphere_2')
    fallingSphere2 = fixedTorusAndFallingSphere_2.addChild('FallingSphere')
    fallingSphere2.addObject('EulerImplicitSolver', name='odesolver')
    fallingSphere2.addObject('CGLinearSolver', name='linear_solver', iterations=250, tolerance=1.0e-9, threshold=1.0e-9)
    fallingSphere2.addObject('MechanicalObject', name='rigid', template='Rigid3d', position=[5, 10, 0, 0, 0, 0, 1])
    fallingSphere2.addObject('UniformMass', totalMass=1.0)
    collision3 = fallingSphere2.addChild('Collision')
    collision3.addObject('MechanicalObject', name='collision_rigid')
    collision3.addObject('SphereCollisionModel', name='sphere', radius=0.7, contactStiffness=1)
    collision3.addObject('IdentityMapping', input='@../rigid', output='@collision_rigid')
    fixedTorus2 = fixedTorusAndFallingSphere_2.addChild('FixedTorus')
    collision4 = fixedTorus2.addChild('Collision')
    collision4.addObject('MechanicalObject', name='collision_torus', src='@../../../torus_loader', translation=[5, 0, 0], scale3d=[0.5, 0.5, 0.5])
    collision4.addObject('MeshTopology', name='topology', src='@../../../torus_loader')
    collision4.addObject('TriangleCollisionModel', name='triangle_collision', simulated=0, moving=0, contactStiffness=1)
    collision4.addObject('LineCollisionModel', name='line_collision', simulated=0, moving=0, contactStiffness=1)
    collision4.addObject('PointCollisionModel', name='point_collision', simulated=0, moving=0, contactStiffness=1)
    rootNode.addObject('BruteForceBroadPhase', name='broad_phase_large')
    rootNode.addObject('BVHNarrowPhase', name='narrow_phase_large')
    rootNode.addObject('NewProximityIntersection', name='intersection_large', alarmDistance=5, contactDistance=1)
    rootNode.addObject('CollisionResponse', name='response_large', response='PenalityContactForceField')
    rootNode.addObject('SubCollisionPipeline', name='collision_pipeline_large', collisionModels='@/FixedTorusAndFallingSphere_1/FallingSphere/Collision/sphere         @FixedTorusAndFallingSphere_1/FixedTorus/Collision/triangle_collision @FixedTorusAndFallingSphere_1/FixedTorus/Collision/line_collision @FixedTorusAndFallingSphere_1/FixedTorus/Collision/point_collision', broadPhaseDetection='@broad_phase_large', narrowPhaseDetection='@narrow_phase_large', intersectionMethod='@intersection_large', contactManager='@response_large')
    rootNode.addObject('BruteForceBroadPhase', name='broad_phase_small')
    rootNode.addObject('BVHNarrowPhase', name='narrow_phase_small')
    rootNode.addObject('NewProximityIntersection', name='intersection_small', alarmDistance=2.5, contactDistance=0.6)
    rootNode.addObject('CollisionResponse', name='response_small', response='PenalityContactForceField')
    rootNode.addObject('SubCollisionPipeline', name='collision_pipeline_small', collisionModels='@FixedTorusAndFallingSphere_2/FallingSphere/Collision/sphere          @FixedTorusAndFallingSphere_2/FixedTorus/Collision/triangle_collision @FixedTorusAndFallingSphere_2/FixedTorus/Collision/line_collision @FixedTorusAndFallingSphere_2/FixedTorus/Collision/point_collision', broadPhaseDetection='@broad_phase_small', narrowPhaseDetection='@narrow_phase_small', intersectionMethod='@intersection_small', contactManager='@response_small')
    rootNode.addObject('CompositeCollisionPipeline', name='composite_pipeline', subCollisionPipelines='@collision_pipeline_large @collision_pipeline_small')
    return rootNode


if __name__ == "__main__":
    root = Sofa.Core.Node("root")
    createScene(root)
    Sofa.Simulation.init(root)
    for _ in range(100):
        Sofa.Simulation.animate(root, root.dt.value)
    print("t =", root.time.value)
