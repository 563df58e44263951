"""A modal body on a floating frame of reference: it moves as a whole (free, held by a joint, or
driven along a prescribed motion) and deforms in its modes, with the inertia coupling between
the two (centrifugal, Coriolis and Euler forces) and, optionally, geometric stiffening by its
inertial loads. The C++ core (cpp/include/corotate/modal/floating_frame_body.hpp) steps it
without allocating; this class checks input and converts between the world and the frame."""

from __future__ import annotations

import numbers
import threading
from collections.abc import Callable
from typing import TYPE_CHECKING, ClassVar

import numpy as np

import corotate._core as _core

from .._attributes import SettableOnly
from ..body import Body
from .floating_basis import check_floating_basis
from .frame_stiffening import inertial_geometric_stiffness
from .modal_body import _one_at_a_time
from .reduction import ModalBasis, node_dofs

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["FloatingBody", "FrameMotion"]

#: A prescribed frame motion: t -> (position (3,), rotation (3, 3), velocity (3,), angular
#: velocity (3,)), all in the world.
FrameMotion = Callable[[float], "tuple[ArrayLike, ArrayLike, ArrayLike, ArrayLike]"]

_SUPPORTS = ("free", "spherical", "revolute")


# These checks run for every step of a driven body (drive), so they are written for speed: the
# rotation's took 45 us with np.allclose and np.linalg.det, 7 us as written (AVX2 EPYC), of a
# driven 20-mode step that now takes 48 us in all.
_IDENTITY = np.eye(3)


def _vector3(value: ArrayLike, what: str) -> np.ndarray:
    v = np.asarray(value, dtype=np.float64)
    if v.shape != (3,) or not np.isfinite(v).all():
        raise ValueError(f"{what} must be 3 finite numbers, got {value!r}")
    return v


def _rotation(value: ArrayLike, what: str) -> np.ndarray:
    R = np.asarray(value, dtype=np.float64)
    if R.shape != (3, 3) or not np.isfinite(R).all():
        raise ValueError(f"{what} must be a finite 3 x 3 rotation matrix, got shape {R.shape}")
    (a, b, c), (d, e, f), (g, h, i) = R.tolist()
    determinant = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)
    if np.abs(R.T @ R - _IDENTITY).max() > 1e-9 or determinant <= 0:
        raise ValueError(f"{what} is not a rotation matrix (R^T R = I, det R = 1)")
    return R


class FloatingBody(SettableOnly):
    """A flexible body whose reduced deformation rides on a floating frame of reference.

    Node i is at p + R (X_i - o + Psi_i q): p, R the frame's position and rotation, X the mesh's
    rest positions, o the frame's origin in the mesh, Psi the basis (no rigid-body motion in it:
    the frame carries that), q the modal coordinates. The inertia follows from the consistent
    mass and the basis once (mass matrix, centrifugal, Coriolis and Euler forces); a step costs
    O(r^2), whatever the mesh. The step is implicit and time-reversible and balances the world
    momenta exactly: an undamped free body keeps its linear and angular momentum to round-off
    and its energy without drift.

    body        Body the basis was built on (its consistent mass and stiffness at rest; its
                mesh and materials for the stiffening)
    basis       ModalBasis without rigid-body motion, e.g. craig_bampton(fixed_nodes=...): the
                fixed nodes then move with the frame
    origin      the frame's origin: a node index, a point (3,) in the mesh, or None for the
                mesh's (0, 0, 0); supports act there
    support     "free", "spherical" (the origin held, any rotation) or "revolute" (the origin
                held, rotation about ``axis``)
    axis        (3,) the revolute joint's axis in the mesh's axes at rest (fixed in the world)
    stiffening  True: geometric stiffening by the inertial loads of the frame's motion and of
                gravity (twelve load cases, corotate.modal.frame_stiffening; needs fixed DOFs in
                the basis); False: linear modes, as in Exudyn's ObjectFFRFreducedOrder
    dt          time step [s]
    gravity     (3,) [m/s^2] on the whole body
    rayleigh    (alpha [1/s], beta [s]): modal damping alpha M_r + beta K_r

    State (world frame unless named otherwise): ``position``, ``rotation``, ``velocity``
    (of the origin), ``angular_velocity``, ``q``, ``modal_velocities``, ``time``; set them with
    set_state(). Bad input raises ValueError and leaves the state as it was; so does a step
    that fails.

    Threads: one call at a time per body; a call while another thread's step() runs raises
    RuntimeError.
    """

    _READ_ONLY_HINTS: ClassVar[dict[str, str]] = {
        "position": "use set_state(position=...)",
        "rotation": "use set_state(rotation=...)",
        "q": "use set_state(q=...)",
        "time": "it advances with step()",
    }

    def __init__(
        self,
        body: Body,
        basis: ModalBasis,
        *,
        origin: int | ArrayLike | None = None,
        support: str = "free",
        axis: ArrayLike = (0.0, 0.0, 1.0),
        stiffening: bool = True,
        dt: float = 0.01,
        gravity: ArrayLike = (0.0, 0.0, 0.0),
        rayleigh: tuple[float, float] = (0.0, 0.0),
    ) -> None:
        check_floating_basis(body, basis)
        points = body.mesh.points
        self._origin = self._origin_point(origin, points)
        self._basis = basis
        self._n_nodes = len(points)
        if not isinstance(stiffening, (bool, np.bool_)):
            raise TypeError(f"stiffening must be True or False, got {stiffening!r}")
        alpha, beta = (float(v) for v in rayleigh)
        if not (np.isfinite(alpha) and np.isfinite(beta) and alpha >= 0 and beta >= 0):
            raise ValueError(f"rayleigh must be two finite numbers >= 0, got {rayleigh!r}")
        M = body.mass_matrix(lumped=False).tocsr()
        V = basis.vectors
        K_r = V.T @ (body.stiffness_matrix() @ V)
        K_r = 0.5 * (K_r + K_r.T)
        M_r = V.T @ (M @ V)
        self._busy = threading.Lock()
        self._rest = np.ascontiguousarray(points - self._origin)
        self._core = _core.FloatingFrame(
            self._rest, M[0::3, 0::3].tocsc(), V, K_r, alpha * 0.5 * (M_r + M_r.T) + beta * K_r
        )
        if stiffening:
            self._core.set_geometric_stiffness(list(inertial_geometric_stiffness(body, basis, self._origin)))
        self._motion: FrameMotion | None = None
        self._last_iterations = 0
        self._support = "free"
        self.set_support(support, axis)
        self.gravity = gravity
        self.dt = dt

    @staticmethod
    def _origin_point(origin: int | ArrayLike | None, points: np.ndarray) -> np.ndarray:
        if origin is None:
            return np.zeros(3)
        if isinstance(origin, numbers.Integral) and not isinstance(origin, bool):
            if not 0 <= int(origin) < len(points):
                raise ValueError(f"the frame's origin node {origin} does not exist: the mesh has {len(points)} nodes")
            return np.array(points[int(origin)], dtype=np.float64)
        return _vector3(origin, "origin")

    # -- settings -----------------------------------------------------------------------------

    @property
    def dt(self) -> float:
        """Time step [s] (settable; > 0)."""
        return self._dt

    @dt.setter
    def dt(self, value: float) -> None:
        dt = float(value)
        if not (np.isfinite(dt) and dt > 0):
            raise ValueError(f"dt must be a positive, finite time step, got {value!r}")
        self._dt = dt

    @property
    def gravity(self) -> np.ndarray:
        """(3,) gravity [m/s^2] in the world (settable)."""
        return self._gravity.copy()

    @gravity.setter
    def gravity(self, value: ArrayLike) -> None:
        g = _vector3(value, "gravity")
        self._core.set_gravity(g)
        self._gravity = g

    @property
    def support(self) -> str:
        """ "free", "spherical" or "revolute" (set with set_support)."""
        return self._support

    @_one_at_a_time
    def set_support(self, kind: str, axis: ArrayLike = (0.0, 0.0, 1.0)) -> None:
        """Hold the frame's origin: kind "free", "spherical" or "revolute" (about ``axis``,
        (3,) in the frame, fixed in the world). Under a support the origin's velocity must be
        zero (and, revolute, the angular velocity along the axis) when the next step starts."""
        if kind not in _SUPPORTS:
            raise ValueError(f"support must be one of {', '.join(_SUPPORTS)}, got {kind!r}")
        self._core.set_support(kind, _vector3(axis, "axis"))
        self._support = kind

    @property
    def stiffening(self) -> bool:
        """Whether the inertial loads stiffen the body (set when it is made)."""
        return bool(self._core.stiffening)

    # -- state --------------------------------------------------------------------------------

    @property
    def n_modes(self) -> int:
        """Number of modal coordinates r."""
        return int(self._core.n_modes)

    @property
    def n_nodes(self) -> int:
        """Number of mesh nodes."""
        return self._n_nodes

    @property
    def mass(self) -> float:
        """Total mass [kg]."""
        return float(self._core.mass)

    @property
    def origin(self) -> np.ndarray:
        """(3,) the frame's origin in the mesh [m]."""
        return self._origin.copy()

    @property
    def position(self) -> np.ndarray:
        """(3,) world position of the frame's origin [m]."""
        return np.asarray(self._core.position)

    @property
    def rotation(self) -> np.ndarray:
        """(3, 3) the frame's rotation (frame to world)."""
        return np.asarray(self._core.rotation)

    @property
    def velocity(self) -> np.ndarray:
        """(3,) world velocity of the frame's origin [m/s]."""
        return self.rotation @ self._core.velocity[0:3]

    @property
    def angular_velocity(self) -> np.ndarray:
        """(3,) the frame's angular velocity in the world [rad/s]."""
        return self.rotation @ self._core.velocity[3:6]

    @property
    def q(self) -> np.ndarray:
        """(r,) modal coordinates (a copy)."""
        return np.asarray(self._core.zeta)

    @property
    def modal_velocities(self) -> np.ndarray:
        """(r,) dq/dt (a copy)."""
        return np.asarray(self._core.velocity[6:])

    @property
    def time(self) -> float:
        """Simulated time [s]."""
        return float(self._core.time)

    @property
    def energy(self) -> float:
        """Kinetic + elastic + gravitational energy [J] (the stiffening's share left out)."""
        return float(self._core.energy)

    @property
    def linear_momentum(self) -> np.ndarray:
        """(3,) world linear momentum [kg m/s]."""
        return np.asarray(self._core.linear_momentum)

    @property
    def angular_momentum(self) -> np.ndarray:
        """(3,) world angular momentum about the world origin [kg m^2/s]."""
        return np.asarray(self._core.angular_momentum)

    @_one_at_a_time
    def set_state(
        self,
        position: ArrayLike | None = None,
        rotation: ArrayLike | None = None,
        velocity: ArrayLike | None = None,
        angular_velocity: ArrayLike | None = None,
        q: ArrayLike | None = None,
        modal_velocities: ArrayLike | None = None,
    ) -> None:
        """Set any part of the state (world frame; None keeps it): position (3,), rotation
        (3, 3), velocity (3,) of the origin, angular_velocity (3,), q (r,), modal_velocities
        (r,). All checked before anything changes."""
        r = self.n_modes
        p = self.position if position is None else _vector3(position, "position")
        R = self.rotation if rotation is None else _rotation(rotation, "rotation")
        v = self.velocity if velocity is None else _vector3(velocity, "velocity")
        w = self.angular_velocity if angular_velocity is None else _vector3(angular_velocity, "angular_velocity")
        zeta = self.q if q is None else self._modal(q, "q")
        eta = self.modal_velocities if modal_velocities is None else self._modal(modal_velocities, "modal_velocities")
        velocities = np.concatenate([R.T @ v, R.T @ w, eta])
        assert velocities.shape == (6 + r,)
        self._core.set_state(p, R, zeta, velocities)

    def _nodes(self, nodes: ArrayLike | None, what: str = "nodes") -> np.ndarray:
        """Node indices (m,), in the caller's order, checked against the mesh (all for None)."""
        if nodes is None:
            return np.arange(self._n_nodes)
        node_dofs(nodes, self._n_nodes, what)  # raises for a bad index, a wrong dtype or mask
        idx = np.asarray(nodes)
        return np.flatnonzero(idx) if idx.dtype == bool else idx.astype(np.int64).ravel()

    def _rows(self, idx: np.ndarray) -> np.ndarray:
        """(3m, r) the basis's rows of the nodes idx, in their order."""
        return self._basis.vectors.reshape(self._n_nodes, 3, -1)[idx].reshape(3 * len(idx), -1)

    def _modal(self, value: ArrayLike, what: str) -> np.ndarray:
        x = np.asarray(value, dtype=np.float64)
        if x.shape != (self.n_modes,) or not np.all(np.isfinite(x)):
            raise ValueError(f"{what} must be {self.n_modes} finite numbers, got shape {x.shape}")
        return x

    # -- loads and motion -----------------------------------------------------------------

    @_one_at_a_time
    def apply_forces(self, nodes: ArrayLike, forces: ArrayLike, frame: str = "world") -> None:
        """Constant forces on nodes, replacing those applied before (an empty list removes them).

        nodes    (m,) node indices
        forces   (m, 3) [N]
        frame    "world": fixed directions; "body": turning with the frame (follower loads)
        """
        idx = self._nodes(nodes)
        if len(np.unique(idx)) != len(idx):
            raise ValueError("apply_forces: a node is listed twice; add its forces into one row")
        F = np.asarray(forces, dtype=np.float64).reshape(-1, 3) if np.size(forces) else np.zeros((0, 3))
        if F.shape != (len(idx), 3) or not np.all(np.isfinite(F)):
            raise ValueError(f"forces must be a finite ({len(idx)}, 3) array, one row per node")
        if frame not in ("world", "body"):
            raise ValueError(f"frame must be 'world' or 'body', got {frame!r}")
        self._core.set_node_loads(self._rest[idx], self._rows(idx), F, frame)

    @_one_at_a_time
    def drive(self, motion: FrameMotion | None) -> None:
        """Prescribe the frame's motion: ``motion(t)`` returns (position (3,), rotation (3, 3),
        velocity (3,), angular_velocity (3,)) in the world at time t; step() then moves the
        frame along it and solves the modes alone (a hub driven by a motor). None releases
        the frame to its support. The motion is checked at the next step (NaN or a matrix that
        is not a rotation raise ValueError, the state unchanged)."""
        if motion is not None and not callable(motion):
            raise TypeError("motion must be a callable t -> (position, rotation, velocity, angular_velocity) or None")
        self._motion = motion

    @_one_at_a_time
    def step(self, n: int = 1) -> None:
        """Advance n steps of dt. Raises ValueError for bad input (a prescribed motion that
        returns NaN, ...) and RuntimeError when the implicit iterations fail; the state is then
        as before the call."""
        if isinstance(n, bool) or not isinstance(n, numbers.Integral) or n < 0:
            raise ValueError(f"n must be an integer >= 0, got {n!r}")
        if self._motion is None:
            self._last_iterations = int(self._core.step(self._dt, int(n))[0])
            return
        saved = (self.position, self.rotation, self._core.velocity, self.q, self.time)
        iterations = 0
        try:
            for _ in range(int(n)):
                t = self.time + self._dt
                p, R, v, w = self._motion(t)
                p, R = _vector3(p, "the motion's position"), _rotation(R, "the motion's rotation")
                v, w = _vector3(v, "the motion's velocity"), _vector3(w, "the motion's angular velocity")
                iterations += self._core.step_prescribed(self._dt, p, R, R.T @ v, R.T @ w)[0]
        except BaseException:
            self._core.set_state(saved[0], saved[1], saved[3], saved[2])
            self._core.time = saved[4]
            raise
        self._last_iterations = iterations

    @property
    def last_iterations(self) -> int:
        """Newton iterations of the last step() call, all its steps together."""
        return self._last_iterations

    # -- output ---------------------------------------------------------------------------

    def displacements(self, nodes: ArrayLike | None = None) -> np.ndarray:
        """(m, 3) the nodes' deformation in the frame, Psi q [m] (all nodes for None)."""
        idx = self._nodes(nodes)
        return (self._rows(idx) @ self.q).reshape(-1, 3)

    def positions(self, nodes: ArrayLike | None = None) -> np.ndarray:
        """(m, 3) world positions p + R (X - o + Psi q) of the nodes (all for None) [m]."""
        idx = self._nodes(nodes)
        local = self._rest[idx] + self.displacements(idx)
        return self.position + local @ self.rotation.T
