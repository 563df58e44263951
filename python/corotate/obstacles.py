"""Rigid obstacles a body touches: a ground plane and analytic shapes (sphere, box, capsule,
cylinder), static or moved between frames (a tool held by a haptic device).

Each is an exact signed distance in the C++ core (contact/obstacle.hpp); add one to a
simulation with ``Simulation.add_obstacle``. One obstacle may touch several simulations.
Moving it (``move_to``) is safe from another thread while a simulation steps: a step reads
one pose at its start and moves the obstacle, over its first step, from where that body last
saw it to the new pose (so its velocity, which friction feels, is the displacement over dt).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

import corotate._core as _core

from ._numbers import real_number

if TYPE_CHECKING:
    from numpy.typing import ArrayLike


def _vector(value: ArrayLike, name: str) -> np.ndarray:
    v = np.asarray(value, dtype=float)
    if v.shape != (3,):
        raise ValueError(f"{name} must be a 3-vector, got shape {v.shape}")
    if not np.all(np.isfinite(v)):
        raise ValueError(f"{name} must be finite, got {v.tolist()}")
    return v


def _frame_with_z(axis: ArrayLike, name: str) -> np.ndarray:
    """A rotation whose third column is the unit vector along `axis`."""
    z = _vector(axis, name)
    length = np.linalg.norm(z)
    if length == 0:
        raise ValueError(f"{name} must not be zero")
    z = z / length
    helper = np.eye(3)[np.argmin(np.abs(z))]  # the axis least aligned with z
    x = np.cross(helper, z)
    x /= np.linalg.norm(x)
    return np.column_stack([x, np.cross(z, x), z])


class Obstacle:
    """Base of the shapes: a rigid placement (``position``, ``rotation``) of a shape defined
    in its own frame. Not constructed directly."""

    _core: Any  # corotate._core.Obstacle

    def __init__(self, core: Any, position: ArrayLike, rotation: ArrayLike | None) -> None:
        self._core = core
        self.move_to(position, np.eye(3) if rotation is None else rotation)

    @property
    def position(self) -> np.ndarray:
        """(3,) where the shape's frame origin is (a plane's point, a shape's centre)."""
        return np.array(self._core.translation)

    @property
    def rotation(self) -> np.ndarray:
        """(3, 3) the shape's frame in the world (columns: its axes)."""
        return np.array(self._core.rotation)

    def move_to(self, position: ArrayLike, rotation: ArrayLike | None = None) -> None:
        """Place the obstacle (rotation: a proper rotation matrix; None keeps the current one).
        Raises ValueError for non-finite values or a matrix that is not a rotation (to 1e-9);
        the pose is then unchanged."""
        r = self.rotation if rotation is None else np.asarray(rotation, dtype=float)
        if r.shape != (3, 3):
            raise ValueError(f"rotation must be a 3 x 3 matrix, got shape {r.shape}")
        self._core.set_pose(r, _vector(position, "position"))

    def distance(self, points: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """Signed distances (m,) of world points (m, 3) (negative inside) and the outward unit
        normals (m, 3) of the nearest surface point."""
        d, n = self._core.distance(np.asarray(points, dtype=float).reshape(-1, 3))
        return np.asarray(d), np.asarray(n)

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self._core!r} at {self.position.tolist()})"


class Plane(Obstacle):
    """A ground plane through `point` with outward unit `normal`: the half-space behind it
    is solid."""

    def __init__(self, point: ArrayLike = (0.0, 0.0, 0.0), normal: ArrayLike = (0.0, 0.0, 1.0)) -> None:
        super().__init__(_core.HalfSpace(), point, _frame_with_z(normal, "normal"))

    @property
    def normal(self) -> np.ndarray:
        """(3,) the outward unit normal."""
        return self.rotation[:, 2]


class Sphere(Obstacle):
    """A solid sphere (a probe's tip, a ball)."""

    def __init__(self, center: ArrayLike, radius: float) -> None:
        super().__init__(_core.Sphere(real_number(radius, "radius")), center, None)

    @property
    def radius(self) -> float:
        return float(self._core.radius)


class Box(Obstacle):
    """A solid box of edge lengths `size` centred at `center`, its edges along the columns of
    `rotation` (default: the world axes)."""

    def __init__(self, center: ArrayLike, size: ArrayLike, rotation: ArrayLike | None = None) -> None:
        super().__init__(_core.Box(0.5 * _vector(size, "size")), center, rotation)


def _segment_pose(a: ArrayLike, b: ArrayLike) -> tuple[np.ndarray, np.ndarray, float]:
    start, end = _vector(a, "a"), _vector(b, "b")
    return 0.5 * (start + end), _frame_with_z(end - start, "b - a"), 0.5 * float(np.linalg.norm(end - start))


class Capsule(Obstacle):
    """The points within `radius` of the segment from `a` to `b` (an instrument's shaft)."""

    def __init__(self, a: ArrayLike, b: ArrayLike, radius: float) -> None:
        start, end = _vector(a, "a"), _vector(b, "b")
        if np.array_equal(start, end):  # a capsule of zero length is a sphere; allowed
            center, rotation, half = start, np.eye(3), 0.0
        else:
            center, rotation, half = _segment_pose(start, end)
        super().__init__(_core.Capsule(real_number(radius, "radius"), half), center, rotation)


class Cylinder(Obstacle):
    """A solid cylinder of `radius` whose axis runs from `a` to `b` (flat caps at both)."""

    def __init__(self, a: ArrayLike, b: ArrayLike, radius: float) -> None:
        center, rotation, half = _segment_pose(a, b)
        super().__init__(_core.Cylinder(real_number(radius, "radius"), half), center, rotation)
