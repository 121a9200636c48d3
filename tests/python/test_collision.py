"""Collision detection alone, from numpy arrays: worked numbers on a floor of two triangles."""
import numpy as np
import pytest

from penalty import collision

FLOOR_POINTS = [[-1, 0, -1], [1, 0, -1], [1, 0, 1], [-1, 0, 1]]
FLOOR_TRIANGLES = [[0, 2, 1], [0, 3, 2]]


def floor():
    return collision.TriangleModel(FLOOR_POINTS, FLOOR_TRIANGLES, name="floor", simulated=False, moving=False)


def test_point_above_triangle_min_proximity():
    points = collision.PointModel([[0.2, 0.05, 0.1], [0.0, 2.0, 0.0]], name="points")
    out = collision.detect(floor(), points, "MinProximity", alarm_distance=0.1, contact_distance=0.02)
    assert out["support"] == "supported" and out["model1"] == "floor" and out["model2"] == "points"
    # only the point 0.05 m above the floor is within the alarm distance; the far one is not
    np.testing.assert_array_equal(out["element2"], [0])
    np.testing.assert_allclose(out["point1"], [[0.2, 0.0, 0.1]], atol=1e-12)
    np.testing.assert_allclose(out["point2"], [[0.2, 0.05, 0.1]], atol=1e-12)
    np.testing.assert_allclose(out["normal"], [[0.0, 1.0, 0.0]], atol=1e-12)
    # value = distance − contact distance = 0.05 − 0.02
    np.testing.assert_allclose(out["distance"], [0.03], rtol=1e-12)


def test_moving_the_points_through_the_view_changes_the_detection():
    points = collision.PointModel([[0.2, 0.05, 0.1]], name="points")
    points.points[0, 1] = 0.5  # beyond the alarm distance
    out = collision.detect(floor(), points, "MinProximity", alarm_distance=0.1, contact_distance=0.02)
    assert len(out["distance"]) == 0


def test_sphere_over_floor_new_proximity():
    ball = collision.SphereModel([[0.0, 0.3, 0.0]], radius=0.25, name="ball")
    out = collision.detect(ball, floor(), "NewProximity", alarm_distance=0.1, contact_distance=0.02)
    assert out["model1"] == "floor" and out["model2"] == "ball"  # SOFA's registered order
    # the centre is on the shared edge of both triangles: one output per triangle, gap 0.3 − 0.25
    assert len(out["distance"]) == 2
    np.testing.assert_allclose(out["distance"], [0.03, 0.03], rtol=1e-12)
    np.testing.assert_allclose(out["normal"], [[0, 1, 0], [0, 1, 0]], atol=1e-12)


def test_bad_input_raises():
    with pytest.raises(ValueError, match="point index 7"):
        collision.TriangleModel(FLOOR_POINTS, [[0, 1, 7]])
    with pytest.raises(ValueError, match="method"):
        collision.detect(floor(), floor(), "Nope")
    with pytest.raises(TypeError, match="unknown intersection parameter 'alarm'"):
        collision.detect(floor(), floor(), "MinProximity", alarm=1.0)


def test_rigid_sphere_matches_vec3_sphere_min_proximity():
    frames = [[0.3, 0.2, -0.2, 0.0, 0.0, 0.38268343, 0.92387953]]   # rotated 45° about z: no effect on a sphere
    rigid = collision.RigidSphereModel(frames, radius=0.15, name="rigid")
    plain = collision.SphereModel([[0.3, 0.2, -0.2]], radius=0.15, name="plain")
    a = collision.detect(floor(), rigid, "MinProximity", alarm_distance=0.1, contact_distance=0.02)
    b = collision.detect(floor(), plain, "MinProximity", alarm_distance=0.1, contact_distance=0.02)
    assert len(a["distance"]) == 1
    np.testing.assert_allclose(a["distance"], b["distance"], rtol=1e-12)
    np.testing.assert_allclose(a["distance"], [0.2 - 0.15 - 0.02], rtol=1e-12)  # gap minus contact distance
    np.testing.assert_allclose(rigid.points, [[0.3, 0.2, -0.2]])
    rigid.points[0, 1] = 1.0   # the view moves the frame
    assert len(collision.detect(floor(), rigid, "MinProximity", alarm_distance=0.1, contact_distance=0.02)["distance"]) == 0
