"""The obstacles' signed distances against closed forms, their normals against the
distance's finite-difference gradient, poses, and bad input."""

import numpy as np
import pytest

import corotate as cr


def random_rotation(rng):
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q *= np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


def segment_distance(p, a, b):
    t = np.clip(((p - a) @ (b - a)) / ((b - a) @ (b - a)), 0, 1)
    return np.linalg.norm(p - (a + t[:, None] * (b - a)), axis=1)


def box_distance(local, half):
    q = np.abs(local) - half
    outside = np.linalg.norm(np.maximum(q, 0), axis=1)
    return outside + np.minimum(q.max(axis=1), 0)


def shapes(rng):
    """(obstacle, exact signed distance of world points) pairs, in general poses."""
    center, rot = rng.normal(size=3), random_rotation(rng)
    a, b = rng.normal(size=3), rng.normal(size=3)
    axis = (b - a) / np.linalg.norm(b - a)
    length = np.linalg.norm(b - a)

    def cylinder(p):
        rel = p - 0.5 * (a + b)
        along = rel @ axis
        radial = np.linalg.norm(rel - along[:, None] * axis, axis=1)
        q = np.stack([radial - 0.7, np.abs(along) - 0.5 * length], axis=1)
        return np.linalg.norm(np.maximum(q, 0), axis=1) + np.minimum(q.max(axis=1), 0)

    return [
        (cr.Plane(center, rot[:, 0]), lambda p: (p - center) @ rot[:, 0]),
        (cr.Sphere(center, 0.8), lambda p: np.linalg.norm(p - center, axis=1) - 0.8),
        (cr.Box(center, (0.4, 1.0, 1.6), rot), lambda p: box_distance((p - center) @ rot, np.array([0.2, 0.5, 0.8]))),
        (cr.Capsule(a, b, 0.3), lambda p: segment_distance(p, a, b) - 0.3),
        (cr.Cylinder(a, b, 0.7), cylinder),
    ]


@pytest.mark.parametrize("kind", range(5))
def test_signed_distance_and_normal(kind):
    rng = np.random.default_rng(kind)
    obstacle, exact = shapes(rng)[kind]
    points = obstacle.position + 1.5 * rng.normal(size=(400, 3))
    d, n = obstacle.distance(points)
    np.testing.assert_allclose(d, exact(points), atol=1e-12)
    assert (d < 0).any() and (d > 0).any()
    np.testing.assert_allclose(np.linalg.norm(n, axis=1), 1, atol=1e-12)
    # The normal is the distance's gradient (away from the medial surface, where it kinks).
    h = 1e-6
    grad = np.stack([(exact(points + h * e) - exact(points - h * e)) / (2 * h) for e in np.eye(3)], axis=1)
    smooth = np.linalg.norm(grad, axis=1) > 1 - 1e-6
    assert smooth.mean() > 0.9
    np.testing.assert_allclose(n[smooth], grad[smooth], atol=1e-5)


def test_move_to_moves_the_surface():
    ball = cr.Sphere((0, 0, 0), 1.0)
    rotation = random_rotation(np.random.default_rng(1))
    ball.move_to((1.0, 2.0, 3.0), rotation)
    np.testing.assert_allclose(ball.distance([[1.0, 2.0, 5.0]])[0], [1.0])
    np.testing.assert_allclose(ball.rotation, rotation)
    plane = cr.Plane((0, 0, 1), (0, 0, 2))  # the normal is normalised
    np.testing.assert_allclose(plane.normal, [0, 0, 1])
    np.testing.assert_allclose(plane.distance([[5.0, -3.0, 0.25]])[0], [-0.75])


@pytest.mark.parametrize(
    "make, match",
    [
        (lambda: cr.Sphere((0, 0, 0), -1.0), "radius must be positive"),
        (lambda: cr.Sphere((0, 0, 0), float("nan")), "radius must be positive"),
        (lambda: cr.Sphere((0, 0, np.inf), 1.0), "position must be finite"),
        (lambda: cr.Plane(normal=(0, 0, 0)), "normal must not be zero"),
        (lambda: cr.Box((0, 0, 0), (1, 0, 1)), "half extents must be positive"),
        (lambda: cr.Box((0, 0, 0), (1, 1)), "size must be a 3-vector"),
        (lambda: cr.Box((0, 0, 0), (1, 1, 1), np.diag([1.0, 1.0, 2.0])), "proper rotation"),
        (lambda: cr.Box((0, 0, 0), (1, 1, 1), np.diag([1.0, 1.0, -1.0])), "proper rotation"),
        (lambda: cr.Cylinder((0, 0, 0), (0, 0, 0), 1.0), "b - a must not be zero"),
        (lambda: cr.Capsule((0, 0, 0), (0, 0, 1), 0.0), "radius must be positive"),
    ],
)
def test_bad_shapes(make, match):
    with pytest.raises(ValueError, match=match):
        make()


def test_a_refused_pose_changes_nothing():
    box = cr.Box((1, 2, 3), (1, 1, 1))
    with pytest.raises(ValueError, match="proper rotation"):
        box.move_to((0, 0, 0), np.ones((3, 3)))
    with pytest.raises(ValueError, match="finite"):
        box.move_to((0, np.nan, 0))
    np.testing.assert_array_equal(box.position, [1, 2, 3])
    np.testing.assert_array_equal(box.rotation, np.eye(3))
