"""Rigid obstacles a body touches: a ground plane, analytic shapes (sphere, box, capsule,
cylinder) and closed triangle meshes, static or moved between frames (a tool held by a haptic device).

Each is an exact signed distance in the C++ core (contact/obstacle.hpp); add one to a
simulation with ``Simulation.add_obstacle``. One obstacle may touch several simulations.
Moving it (``move_to``) is safe from another thread while a simulation steps: a step reads
one pose at its start and moves the obstacle, over its first step, from where that body last
saw it to the new pose (so its velocity, which friction feels, is the displacement over dt).
"""

from __future__ import annotations

import os
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


class TriangleMesh(Obstacle):
    """A closed triangle mesh (a tool or a fixture of any shape, or another body's surface).

    vertices   (n, 3) in the mesh's own frame, placed in the world by `position` and
               `rotation` (like the other shapes: ``move_to`` moves it rigidly)
    triangles  (m, 3) vertex indices

    The distance is exact (nearest triangle by a bounding-volume hierarchy) and signed by the
    angle-weighted pseudonormals, which needs a closed, consistently oriented surface:
    ValueError names a non-finite vertex, an index out of range, a zero-area triangle, an edge
    with one triangle (a hole) or more than two, or two triangles wound against each other.
    An inward-wound mesh is turned outward. Self-intersection is not checked.

    ``set_vertices`` moves the vertices themselves (an animated or deforming surface, with
    velocities that friction and the contact's path feel).
    """

    def __init__(
        self,
        vertices: ArrayLike,
        triangles: ArrayLike,
        position: ArrayLike = (0.0, 0.0, 0.0),
        rotation: ArrayLike | None = None,
    ) -> None:
        v = np.asarray(vertices, dtype=float)
        if v.ndim != 2 or v.shape[1] != 3:
            raise ValueError(f"vertices must have shape (n, 3), got {v.shape}")
        t = np.asarray(triangles)
        if t.size and not np.issubdtype(t.dtype, np.integer):
            raise ValueError(f"triangles must hold integer vertex indices, got {t.dtype}")
        super().__init__(_core.TriangleMesh(v, t), position, rotation)

    @classmethod
    def read(
        cls, path: str | os.PathLike[str], position: ArrayLike = (0.0, 0.0, 0.0), rotation: ArrayLike | None = None
    ) -> TriangleMesh:
        """The closed surface in a file (STL, OBJ, PLY, OFF, VTU...; read as
        :func:`corotate.read_surface` reads it: quads are split). FileNotFoundError or
        ValueError for a missing or unreadable file, one without triangles, or a surface that is
        not closed (see the class)."""
        from .embedding import read_surface

        surface = read_surface(path)
        try:
            return cls(surface.points, surface.cells, position, rotation)
        except ValueError as e:
            raise ValueError(f"{path}: {e}") from e

    @property
    def vertices(self) -> np.ndarray:
        """(n, 3) the vertices in the mesh's own frame (a copy)."""
        return np.asarray(self._core.vertices)

    @property
    def triangles(self) -> np.ndarray:
        """(m, 3) the triangles, wound outward."""
        return np.asarray(self._core.triangles)

    def set_vertices(self, vertices: ArrayLike, velocities: ArrayLike | None = None) -> None:
        """Move the vertices ((n, 3), own frame) with their velocities ((n, 3) [m/s], zero if
        None): over the next step a body sees the surface move from where it was by the
        velocities times dt to here. ValueError for a wrong shape or non-finite values (the
        mesh is then unchanged)."""
        v = np.asarray(vertices, dtype=float)
        u = None if velocities is None else np.asarray(velocities, dtype=float)
        self._core.set_vertices(v, u)

    def distribute(self, points: ArrayLike, forces: ArrayLike) -> np.ndarray:
        """(n, 3) vertex forces equivalent to point `forces` (m, 3) at world `points` (m, 3)
        on the surface: each split by the barycentric weights of the nearest surface point
        (world frame in and out)."""
        p = np.asarray(points, dtype=float).reshape(-1, 3)
        f = np.asarray(forces, dtype=float).reshape(-1, 3)
        r, t = self.rotation, self.position
        return np.asarray(self._core.distribute((p - t) @ r, f @ r)) @ r.T
