"""Collision detection alone, from numpy arrays.

    from penalty import collision
    floor = collision.TriangleModel(points, triangles, name="floor", simulated=False, moving=False)
    balls = collision.SphereModel(centers, radius=0.1, name="balls")
    out = collision.detect(floor, balls, "MinProximity", alarm_distance=0.1, contact_distance=0.02)

Models: PointModel(points), LineModel(points, edges), TriangleModel(points, triangles),
SphereModel(centers, radius) (a number or one radius per sphere), RigidSphereModel(frames,
radius) (frames (n, 7) x y z qx qy qz qw, or (n, 3) centres); keywords name, contact_distance,
contact_stiffness, simulated, moving, self_collision, group. `model.points` views the model's
points (move them, then detect again). detect(model1, model2, method, **parameters) returns the
detection outputs as arrays (see docs/python.md).
"""
from ._core import collision as _compiled

CollisionModel = _compiled.CollisionModel
PointModel = _compiled.PointModel
LineModel = _compiled.LineModel
TriangleModel = _compiled.TriangleModel
SphereModel = _compiled.SphereModel
RigidSphereModel = _compiled.RigidSphereModel
detect = _compiled.detect

__all__ = ["CollisionModel", "PointModel", "LineModel", "TriangleModel", "SphereModel", "RigidSphereModel", "detect"]
