"""What every simulation object shares: the zero-copy state views, gravity and fixed nodes."""

from __future__ import annotations

import warnings
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
import scipy.sparse as sp

from ._attributes import SettableOnly

if TYPE_CHECKING:
    from collections.abc import Callable

    from numpy.typing import ArrayLike


class SimulationWarning(UserWarning):
    """A run that goes wrong without producing NaN: a stalled linear solve, inverted
    elements, or energy growing while nothing drives the body (see Simulation's
    ``on_failure``). Issued once per kind and simulation."""


_FAILURES = (
    (
        "stalled_steps",
        "the linear solve stalled at its iteration cap (relative residual >= 1) in {n} step(s): raise "
        "PCG(max_iterations=...) or use a stronger preconditioner; the steps are not to be trusted",
    ),
    (
        "inverted_steps",
        "{n} step(s) started with inverted or flat elements (det F <= 0; {last} in the last one): the load or the "
        "time step is too large for this mesh, or the material too soft",
    ),
    (
        "energy_growth_steps",
        "the total energy grew by more than 1 % above the lowest it reached in {n} step(s) while nothing drove the "
        "body: a run-away "
        "(too few PCG iterations, or a time step too large for the linearised step)",
    ),
)


class _FormerMethod(float):
    """The value of a state query that became a property (cheap queries without arguments
    are properties, like MassSpringBody.total_mass): a float that can still be called, as
    code written for the method does, with a DeprecationWarning."""

    _name: str

    def __new__(cls, value: float, name: str) -> _FormerMethod:
        obj = super().__new__(cls, value)
        obj._name = name
        return obj

    def __call__(self) -> float:
        warnings.warn(
            f"{self._name} is a property now: write sim.{self._name} without the ()", DeprecationWarning, stacklevel=2
        )
        return float(self)


_VIEW_HINT = "write into the view instead, e.g. sim.{name}[:] = values"


class DrivenBody(SettableOnly):
    """Base of Simulation and ExplicitSimulation. Subclasses set ``self._sim`` (the C++
    simulation), ``self._body`` and ``self._rest`` ((n, 3) rest positions).

    Every public attribute either takes effect when assigned (gravity, on_failure, dt, ...)
    or is read-only and raises AttributeError.

    Threads: one call at a time per simulation. step() releases the GIL; a call from another
    thread while it runs (fix, gravity, step, reset, stats, ...) raises RuntimeError("the
    simulation is busy: ...") instead of racing it. The NumPy views (positions, velocities,
    external_forces) cannot be guarded: do not write into them while another thread steps."""

    _sim: Any  # corotate._core.Simulation
    _body: Any  # Body or MassSpringBody
    _rest: np.ndarray
    _warned: set[str]
    _READ_ONLY_HINTS: ClassVar[dict[str, str]] = {
        "time": "it advances with step(); reset() goes back to t = 0",
        "body": "a simulation steps its own copy of the body's model; create a new simulation for another body",
        "positions": _VIEW_HINT.format(name="positions"),
        "velocities": _VIEW_HINT.format(name="velocities"),
        "external_forces": _VIEW_HINT.format(name="external_forces"),
        "fixed_nodes": "use fix(nodes) (replaces the set), also_fix(nodes) (adds to it) or free()",
        "attachments": "use attach(), move_attachments() and detach()",
        "stats": "reset_stats() starts them afresh",
    }

    @property
    def body(self) -> Any:
        """The body simulated (read-only)."""
        return self._body

    def _set_failure_policy(self, on_failure: str) -> None:
        self._sim.failure_policy = on_failure
        self._warned = set()

    @property
    def on_failure(self) -> str:
        """What a stalled solve, inverted elements or a run-away do: "warn" (a
        SimulationWarning, once per kind), "raise" (RuntimeError, the state restored) or
        "ignore". Settable."""
        return str(self._sim.failure_policy)

    @on_failure.setter
    def on_failure(self, value: str) -> None:
        self._set_failure_policy(value)

    def _step(self, n: int, progress: Callable[[int, int], object] | None) -> None:
        if isinstance(n, (bool, np.bool_)) or not isinstance(n, (int, np.integer)):
            raise TypeError(f"step count n must be an integer, got {type(n).__name__} {n!r}")
        if progress is not None and not callable(progress):
            raise TypeError(f"progress must be a callable progress(done, n), got {type(progress).__name__}")
        self._sim.step(int(n), progress)
        stats = self._sim.stats
        for key, text in _FAILURES:
            if stats[key] > 0 and key not in self._warned:
                self._warned.add(key)
                message = text.format(n=stats[key], last=stats["inverted_elements"])
                warnings.warn(message, SimulationWarning, stacklevel=3)

    @property
    def positions(self) -> np.ndarray:
        """(n, 3) current node positions (a writable view)."""
        return self._sim.positions

    @property
    def velocities(self) -> np.ndarray:
        """(n, 3) current node velocities (a writable view)."""
        return self._sim.velocities

    @property
    def external_forces(self) -> np.ndarray:
        """(n, 3) external nodal forces [N], kept between steps (a writable view)."""
        return self._sim.external_forces

    @property
    def accelerations(self) -> np.ndarray:
        """(n, 3) (v_new - v_old) / dt of the last step (zero before the first; a new array)."""
        return self._sim.accelerations

    @property
    def gravity_forces(self) -> np.ndarray:
        """(n, 3) the nodal forces of gravity, M g with the simulation's mass (a new array)."""
        return self._sim.gravity_forces

    def mass_matrix(self) -> sp.csr_matrix:
        """The mass matrix the integrator uses (3n x 3n; lumped for explicit integrators)."""
        data, indices, indptr = self._sim.mass_csr()
        n = 3 * len(self._rest)
        return sp.csr_matrix((data, indices, indptr), shape=(n, n))

    @property
    def displacements(self) -> np.ndarray:
        """(n, 3) positions minus rest positions (a new array)."""
        return self.positions - self._rest

    @property
    def time(self) -> float:
        """Simulated time [s]."""
        return self._sim.time

    @property
    def gravity(self) -> np.ndarray:
        """(3,) gravitational acceleration [m/s^2]."""
        return np.array(self._sim.gravity)

    @gravity.setter
    def gravity(self, g: ArrayLike) -> None:
        g = np.asarray(g, dtype=np.float64)
        if g.shape != (3,):
            raise ValueError("gravity must be a 3-vector")
        self._sim.gravity = g

    def _node_list(self, nodes: ArrayLike) -> list[int]:
        """Int indices (or one int, or a boolean mask with one entry per node) as a list."""
        nodes = np.asarray(nodes)
        if nodes.dtype == bool:
            if nodes.shape != (self.body.n_nodes,):
                raise ValueError("a boolean node mask needs one entry per node")
            nodes = np.flatnonzero(nodes)
        if nodes.size and not np.issubdtype(nodes.dtype, np.integer):
            raise ValueError("node indices must be integers")
        return [int(i) for i in nodes.ravel()]

    def fix(self, nodes: ArrayLike) -> None:
        """Fix exactly the given nodes (int indices or a boolean mask) in all three axes:
        the set REPLACES the nodes fixed before (``also_fix`` adds to them). Fixed nodes feel
        no force and keep the velocity they have (zero unless set); writing into
        ``positions``/``velocities`` between steps prescribes their motion. Cheap at any
        time (the solver keeps its preconditioner)."""
        self._sim.fixed_nodes = self._node_list(nodes)

    def also_fix(self, nodes: ArrayLike) -> None:
        """Fix the given nodes (int indices or a boolean mask) IN ADDITION to those fixed
        already, e.g. a loaded point after clamping a face (``fix`` replaces the set)."""
        added = self._node_list(nodes)
        self._sim.fixed_nodes = sorted(set(self._sim.fixed_nodes).union(added))

    @staticmethod
    def _targets(nodes: list[int], targets: ArrayLike) -> np.ndarray:
        targets = np.asarray(targets, dtype=np.float64)
        if targets.shape == (3,) and len(nodes) == 1:
            targets = targets.reshape(1, 3)
        if targets.shape != (len(nodes), 3):
            raise ValueError(f"targets must have shape ({len(nodes)}, 3), one row per node; got {targets.shape}")
        return targets

    def attach(self, nodes: ArrayLike, targets: ArrayLike, stiffness: ArrayLike) -> None:
        """Pull nodes towards target points with zero-rest-length springs: the right way to
        drag a body (a vertex grabbed with the mouse, a tool).

        nodes      int indices, one int, or a boolean mask
        targets    (m, 3) points [m], or (3,) for one node
        stiffness  k [N/m] > 0, one number for all or m numbers

        Each spring adds the force k (target - x) to its node and its stiffness k I to the
        system an implicit step solves, so it is stable for any k (a very stiff spring acts
        like a fixed node moved to the target; an explicit step shrinks its stable step to
        cover k / m). Move the targets between frames with move_attachments(); release with
        detach(). None of these rebuilds anything (no factorization or preconditioner), so
        a grab or release costs no extra frame time. Re-attaching an attached node replaces
        its target and stiffness; a node that is also fixed stays fixed.

        Do not drag through ``external_forces[i] = k * (target - x)``: that spring is
        explicit (its force is frozen over the step), so beyond k ~ m / dt^2 every step
        overshoots more than the last and the body flies away.

        Raises ValueError (nothing changed) for an index out of range or listed twice,
        targets of the wrong shape or not finite, or a stiffness that is not positive and
        finite."""
        node_list = self._node_list(nodes)
        points = self._targets(node_list, targets)
        k = np.asarray(stiffness, dtype=np.float64)
        if k.ndim == 0:
            k = np.full(len(node_list), float(k))
        if k.shape != (len(node_list),):
            raise ValueError(f"stiffness must be one number or {len(node_list)} numbers (one per node); got {k.shape}")
        self._sim.attach(node_list, points, k)

    def move_attachments(self, nodes: ArrayLike, targets: ArrayLike) -> None:
        """New targets ((m, 3), or (3,) for one node) for attached nodes, e.g. the mouse
        position each frame. Raises ValueError (nothing changed) for a node that is not
        attached or a target that is not finite."""
        node_list = self._node_list(nodes)
        self._sim.move_attachments(node_list, self._targets(node_list, targets))

    def detach(self, nodes: ArrayLike | None = None) -> None:
        """Release the given attached nodes, or all of them (nodes=None)."""
        if nodes is None:
            self._sim.detach_all()
        else:
            self._sim.detach(self._node_list(nodes))

    @property
    def attachments(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(nodes (m,), targets (m, 3), stiffness (m,)) of the attachment springs (copies)."""
        nodes, targets, stiffness = self._sim.attachments
        return np.asarray(nodes, dtype=np.int64), targets, stiffness

    def attachment_forces(self) -> np.ndarray:
        """(m, 3) forces k (target - x) the springs exert on their nodes, in the order of
        ``attachments`` (what a user dragging the body feels, with the opposite sign)."""
        nodes, targets, stiffness = self.attachments
        return stiffness[:, None] * (targets - self.positions[nodes])

    def free(self) -> None:
        """Release all fixed nodes."""
        self._sim.fixed_nodes = []

    @property
    def fixed_nodes(self) -> np.ndarray:
        return np.array(self._sim.fixed_nodes, dtype=np.int64)

    def internal_forces(self) -> np.ndarray:
        """(n, 3) internal elastic forces at the current positions."""
        return self._sim.internal_forces()

    @property
    def energy(self) -> float:
        """Elastic energy [J] at the current positions. (Was a method: ``sim.energy()`` still
        works, with a DeprecationWarning.)"""
        return _FormerMethod(self._sim.energy(), "energy")

    @property
    def kinetic_energy(self) -> float:
        """1/2 v^T M v [J] with the mass the integrator uses (Simulation: its mass kind;
        ExplicitSimulation: lumped). (Was a method: ``sim.kinetic_energy()`` still works,
        with a DeprecationWarning.)"""
        return _FormerMethod(self._sim.kinetic_energy(), "kinetic_energy")

    def reset_stats(self) -> None:
        """Start the statistics afresh."""
        self._sim.reset_stats()

    def reset(self) -> None:
        """Back to the rest state: positions = rest, velocities and external forces zero,
        time 0, statistics reset, warm starts and stability estimates cleared (a stepped
        run then repeats a fresh simulation's). Kept: fixed nodes, attachments, gravity, the
        settings (dt, integrator, solver) and on_failure. Loud-failure warnings may be issued again."""
        self._sim.reset()
        self._warned = set()
