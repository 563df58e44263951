"""Stepping a body frame by frame: implicit co-rotational dynamics and static equilibrium."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

import corotate._core as _core

from ._numbers import real_number
from .body import Body
from .choices import IMPLICIT_INTEGRATORS, MASS_KINDS, FailurePolicy, ImplicitIntegratorName, MassKind, check_choice
from .contact import ContactMembers
from .driven_body import DrivenBody
from .joined_body import JoinedBody
from .solvers import PCG, Direct

if TYPE_CHECKING:
    from collections.abc import Callable

    from numpy.typing import ArrayLike

_DEFAULTS = _core.IntegratorSettings()  # the defaults live in C++ (integrators/integrator.hpp)


class Simulation(ContactMembers, DrivenBody):
    """Implicit (backward Euler) simulation of one body.

    body        Body
    dt          time step [s]
    solver      PCG(...) or Direct(); default PCG() for "linearized", Direct() for "newton"
    gravity     (3,) acceleration [m/s^2], default (0, 0, 0)
    mass        "consistent" (default; the better choice for implicit steps) or "lumped"
    rayleigh    (alpha, beta): damping C = alpha M + beta K, default (0, 0)
    integrator  "linearized" (default): each step solves
                (M + dt C + dt^2 K) dv = dt (f + f_ext) - (dt C + dt^2 K) v once, with K the
                stiffness at the start of the step (Baraff & Witkin; the paper's scheme);
                "newton": each step minimises the incremental potential by Newton iterations
                with a backtracking line search until the gradient is below newton_tolerance
                (relative to the loads and momentum); beta must be 0 then.
    newton_iterations, newton_tolerance   limits of the "newton" integrator (20, 1e-6)
    matrix_reuse_angle   "linearized": the step keeps an earlier step's system matrix while
                no element has turned by more than this angle [rad] beyond its body's
                rotation since it was assembled (the forces always use the current
                rotations, so a body comes to the same rest; at most 0.5; 0 assembles at
                every step, as the paper does).
                stats["kept_matrix_steps"] counts the steps that kept it.

    The derivations: cpp/include/corotate/integrators/implicit_integrator.hpp.

    positions, velocities and external_forces are (n, 3) float64 NumPy views of the state
    held in C++: no copies. Write into them between steps to move fixed nodes or apply
    loads (e.g. ``sim.external_forces[tip] = (0, 0, -10)``).

    Contact: add_obstacle(cr.Plane(), friction=0.5) and the other shapes of
    corotate.obstacles (contact.py has the members: contacts, contact_force, ...).

    Settable later: dt, solver, gravity, on_failure, contact_nodes, contact_settings; body
    and time are read-only (reset() goes back to the rest state at t = 0).
    """

    def __init__(
        self,
        body: Body | JoinedBody,
        dt: float = _DEFAULTS.time_step,
        solver: PCG | Direct | None = None,
        gravity: ArrayLike = (0.0, 0.0, 0.0),
        mass: MassKind = "consistent",
        rayleigh: tuple[float, float] = (_DEFAULTS.mass_damping, _DEFAULTS.stiffness_damping),
        integrator: ImplicitIntegratorName = "linearized",
        newton_iterations: int = _DEFAULTS.newton_iterations,
        newton_tolerance: float = _DEFAULTS.newton_tolerance,
        matrix_reuse_angle: float = _DEFAULTS.matrix_reuse_angle,
        on_failure: FailurePolicy = "warn",
    ) -> None:
        if not isinstance(body, (Body, JoinedBody)):
            raise TypeError("body must be a corotate.Body (or a Scene's JoinedBody)")
        check_choice(mass, MASS_KINDS, "mass")
        check_choice(integrator, IMPLICIT_INTEGRATORS, "integrator")
        if solver is None:
            solver = Direct() if integrator == "newton" else PCG()
        _check_solver(solver)
        alpha, beta = (real_number(v, "rayleigh") for v in rayleigh)
        self._body = body
        self._solver = solver
        settings = _core.IntegratorSettings(
            integrator=integrator,
            time_step=real_number(dt, "dt"),
            mass_damping=alpha,
            stiffness_damping=beta,
            lumped_mass=mass == "lumped",
            newton_iterations=int(newton_iterations),
            newton_tolerance=float(newton_tolerance),
            matrix_reuse_angle=real_number(matrix_reuse_angle, "matrix_reuse_angle"),
        )
        kind, pcg = solver._args()
        self._sim = _core.Simulation(body._force_model, settings, kind, pcg)
        self._obstacles = []
        self._contact_nodes_set = False
        self._contact_surface = None
        self._rest = body._rest_points
        self.gravity = gravity
        self._set_failure_policy(on_failure)

    @property
    def dt(self) -> float:
        """Time step [s] (settable; the integrator is rebuilt, its warm start dropped)."""
        return self._sim.settings.time_step

    @dt.setter
    def dt(self, value: float) -> None:
        s = self._sim.settings
        self._sim.settings = _core.IntegratorSettings(
            integrator=s.integrator,
            time_step=real_number(value, "dt"),  # its range is checked in C++
            mass_damping=s.mass_damping,
            stiffness_damping=s.stiffness_damping,
            lumped_mass=s.lumped_mass,
            newton_iterations=s.newton_iterations,
            newton_tolerance=s.newton_tolerance,
            policy=s.policy,
            on_unstable=s.on_unstable,
            safety=s.safety,
            matrix_reuse_angle=s.matrix_reuse_angle,
        )

    @property
    def solver(self) -> PCG | Direct:
        """The linear solver, PCG(...) or Direct() (settable: the new one builds its
        preconditioner or factorization afresh; the last step's answer stays the warm start)."""
        return self._solver

    @solver.setter
    def solver(self, solver: PCG | Direct) -> None:
        _check_solver(solver)
        self._sim.set_solver(*solver._args())
        self._solver = solver

    # --- stepping ---------------------------------------------------------------------
    def step(self, n: int = 1, progress: Callable[[int, int], object] | None = None) -> None:
        """Advance n time steps.

        progress, if given, is called as progress(done, n) after each step (a progress bar:
        ``bar = tqdm(total=n); sim.step(n, lambda done, n: bar.update())``). It may not call
        the simulation (it runs inside the step: RuntimeError "busy"); what it raises fails
        the call. Ctrl-C interrupts a long call between steps.

        Raises ValueError for non-finite positions, velocities or forces and RuntimeError
        when a step fails (non-finite result, solver breakdown); in every case the state is
        left exactly as it was before the call."""
        self._step(n, progress)

    def solve_static(
        self,
        load_steps: int = 1,
        tolerance: float = 1e-8,
        max_iterations: int = 100,
        prescribed: ArrayLike | None = None,
        progress: Callable[[int, int], object] | None = None,
    ) -> dict:
        """Move the body to static equilibrium under external forces and gravity.

        Newton iterations (a step that would blow the residual up is halved), with
        load_steps equal load increments. Fixed nodes keep their positions, or, with
        prescribed ((n, 3) positions of which the fixed nodes' rows are used), move to those
        in the same increments (displacement control). Velocities become zero.
        Returns {"residual_history": [[...] per load step], "iterations": total}: residual
        norms on the free DOFs relative to the load (or, under pure displacement control, to
        the first residual times load_steps). Raises RuntimeError with the residuals, and
        restores the state, if it does not converge. progress(done, load_steps), if given,
        is called after each load step (as in step()); Ctrl-C interrupts between load steps,
        the state restored."""
        if prescribed is not None:
            prescribed = np.ascontiguousarray(prescribed, dtype=np.float64)
            if prescribed.shape != (self.body.n_nodes, 3):
                raise ValueError(f"prescribed must have shape ({self.body.n_nodes}, 3), got {prescribed.shape}")
        if progress is not None and not callable(progress):
            raise TypeError(f"progress must be a callable progress(done, n), got {type(progress).__name__}")
        return self._sim.solve_static(int(load_steps), float(tolerance), int(max_iterations), prescribed, progress)

    @property
    def stats(self) -> dict:
        """Statistics: last step's CG iterations, residual, tolerance, phase times [ms], Newton iterations
        and relative gradient norms ("newton" integrator); and over all
        steps since reset_stats(): steps, iterations_per_step, ms_per_step,
        simulated_time, wall_time [s] and real_time_ratio (simulated / wall time). The wall
        time is that of the step() calls (checks and commit included, progress callbacks
        excluded); the phase times are the integrator's."""
        return self._sim.stats


def _check_solver(solver: object) -> None:
    if not isinstance(solver, (PCG, Direct)):
        raise TypeError(f"solver must be corotate.PCG(...) or corotate.Direct(), got {type(solver).__name__}")
