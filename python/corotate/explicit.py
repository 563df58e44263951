"""Explicit stepping of mass-spring bodies: symplectic Euler or velocity Verlet with a
critical time step from the highest eigenfrequency, and sub-stepping."""

from __future__ import annotations

import math
import warnings
from typing import TYPE_CHECKING, Any, cast

import numpy as np

import corotate._core as _core

from ._numbers import real_number
from .body import Body
from .choices import (
    EXPLICIT_INTEGRATORS,
    ExplicitIntegratorName,
    FailurePolicy,
    OnUnstableName,
    TimeStepPolicyName,
    check_choice,
)
from .driven_body import DrivenBody, SimulationWarning
from .mass_spring import MassSpringBody

if TYPE_CHECKING:
    from collections.abc import Callable

    from numpy.typing import ArrayLike

__all__ = ["ExplicitSimulation"]

_DEFAULTS = _core.IntegratorSettings(integrator="verlet", time_step=0.0)  # the defaults live in C++
_DEFAULT_ON_UNSTABLE = cast(OnUnstableName, _DEFAULTS.on_unstable)
_DEFAULT_POLICY = cast(TimeStepPolicyName, _DEFAULTS.policy)


class ExplicitSimulation(DrivenBody):
    """Explicit simulation of a MassSpringBody or a finite-element Body, with the same
    surface as Simulation.

    body          MassSpringBody, or Body (any model; stepped with its lumped mass, e.g. the
                  explainer's StVK sheet with symplectic Euler)
    dt            step [s] that step() advances, e.g. a frame time; None = the stable step
    integrator    "verlet" (velocity Verlet, default) or "symplectic_euler"
    on_unstable   what happens when dt exceeds the stable step safety * dt_crit:
                  "substep" (default: split it into equal stable substeps), "raise"
                  (ValueError naming dt and the limit) or "allow" (take it; experiments only)
    policy        how dt_crit is estimated: "fixed" (default; once, from a bound of the
                  stiffness valid in every configuration: conservative) or "online" (the
                  linearised system at the current positions, re-estimated when a node
                  has moved more than 5 % of the shortest rest length since the last one)
    safety        fraction of dt_crit a substep may use, in (0, 1] (default 0.9)
    gravity       (3,) acceleration [m/s^2]
    mass_damping  alpha [1/s]: force -alpha m v on every free node (velocity damping)

    dt_crit = (sqrt(c^2 + 4 w^2) - c) / w^2 (= 2 / w undamped), with w^2 the highest
    eigenvalue of M^-1 K found by Lanczos and c that of M^-1 C plus mass_damping; it holds
    for both integrators (see cpp/.../critical_time_step.hpp).

    positions, velocities and external_forces are (n, 3) float64 views of the state held in
    C++ (no copies); write into them between steps. Pinned nodes keep their velocity.
    A step producing non-finite values raises RuntimeError and restores the state.

    Settable later: dt, integrator, on_unstable, policy, gravity, on_failure; body and time
    are read-only (reset() goes back to the rest state at t = 0).
    """

    def __init__(
        self,
        body: MassSpringBody | Body,
        dt: float | None = None,
        integrator: ExplicitIntegratorName = "verlet",
        on_unstable: OnUnstableName = _DEFAULT_ON_UNSTABLE,
        policy: TimeStepPolicyName = _DEFAULT_POLICY,
        safety: float = _DEFAULTS.safety,
        gravity: ArrayLike = (0.0, 0.0, 0.0),
        mass_damping: float = _DEFAULTS.mass_damping,
        on_failure: FailurePolicy = "warn",
    ) -> None:
        if not isinstance(body, (MassSpringBody, Body)):
            raise TypeError("body must be a corotate.MassSpringBody or a corotate.Body")
        self._body = body
        self._settings: dict[str, Any] = dict(
            time_step=self._check_dt(dt),
            integrator=integrator,
            policy=policy,
            on_unstable=on_unstable,
            safety=real_number(safety, "safety"),
            mass_damping=real_number(mass_damping, "mass_damping"),
        )
        check_choice(integrator, EXPLICIT_INTEGRATORS, "integrator")
        if isinstance(body, MassSpringBody):
            self._rest = body.nodes
            model: _core.ForceModel = body._model
        else:  # a finite-element body, stepped with its lumped mass
            self._rest = body.mesh.points
            model = body._force_model
        self._sim = _core.Simulation(model, _core.IntegratorSettings(**self._settings))
        self.gravity = gravity
        self._set_failure_policy(on_failure)

    @staticmethod
    def _check_dt(dt: float | None) -> float:
        if dt is None:
            return 0.0
        dt = real_number(dt, "time step dt")
        if not (dt > 0) or not math.isfinite(dt):
            raise ValueError(f"time step dt must be positive and finite (or None for the stable step), got {dt}")
        return dt

    def _configure(self, **changes: Any) -> None:
        settings = {**self._settings, **changes}
        self._sim.settings = _core.IntegratorSettings(**settings)
        self._settings = settings

    # --- settings ----------------------------------------------------------------------
    @property
    def dt(self) -> float | None:
        """The step step() advances [s]; None = the stable step. Settable."""
        return self._settings["time_step"] or None

    @dt.setter
    def dt(self, value: float | None) -> None:
        self._configure(time_step=self._check_dt(value))

    @property
    def integrator(self) -> str:
        """ "verlet" or "symplectic_euler" (settable)."""
        return self._settings["integrator"]

    @integrator.setter
    def integrator(self, name: str) -> None:
        self._configure(integrator=name)

    @property
    def on_unstable(self) -> str:
        """ "substep", "raise" or "allow" (settable)."""
        return self._settings["on_unstable"]

    @on_unstable.setter
    def on_unstable(self, value: str) -> None:
        self._configure(on_unstable=value)

    @property
    def policy(self) -> str:
        """ "fixed" or "online" (settable)."""
        return self._settings["policy"]

    @policy.setter
    def policy(self, value: str) -> None:
        self._configure(policy=value)

    # --- time step ---------------------------------------------------------------------
    @property
    def critical_time_step(self) -> float:
        """dt_crit [s] that the next step uses (by the policy)."""
        return self._sim.stability()["critical_step"]

    @property
    def stable_time_step(self) -> float:
        """safety * dt_crit [s]: the largest substep taken."""
        return self._settings["safety"] * self.critical_time_step

    def stability(self, which: str = "current") -> dict:
        """The stability estimate: critical_step [s], omega_max [rad/s], lambda_max
        (of M^-1 K, Ritz value + residual), damping_rate c [1/s], bound (bool), and the
        Lanczos details. which: "current" (what the steps use), "configuration" (the
        linearised system at the current positions) or "bound" (valid for all positions)."""
        if which == "current":
            return self._sim.stability()
        if which not in ("configuration", "bound"):
            raise ValueError(f"unknown estimate {which!r}; choose 'current', 'configuration' or 'bound'")
        return self._sim.estimate_stability(which == "bound")

    # --- stepping ----------------------------------------------------------------------
    def step(self, n: int = 1, progress: Callable[[int, int], object] | None = None) -> None:
        """Advance n steps of dt, each in as many stable substeps as needed.

        progress, if given, is called as progress(done, n) after each step; it may not call
        the simulation, and what it raises fails the call (as in Simulation.step).

        Raises ValueError for non-finite state or loads and, with on_unstable="raise", when
        dt exceeds the stable step; RuntimeError when a step produces non-finite values.
        In every case the state is left exactly as it was before the call. With
        on_unstable="allow", a dt beyond the critical step gives a SimulationWarning (once per
        simulation, and again after reset())."""
        self._warn_if_allowed_unstable()
        self._step(n, progress)

    def _warn_if_allowed_unstable(self) -> None:
        """on_unstable="allow" takes a step beyond the stability limit on purpose, but a run
        that grows by 1e100 before it fails must not be the first sign of it."""
        dt = self._settings["time_step"]
        if self._settings["on_unstable"] != "allow" or not dt or "allowed_unstable" in self._warned:
            return
        limit = self.critical_time_step
        if dt > limit:
            self._warned.add("allowed_unstable")
            warnings.warn(
                f"dt = {dt:.4g} s is {dt / limit:.3g} times the critical step dt_crit = {limit:.4g} s and "
                "on_unstable='allow' takes it anyway: the run is unstable and will blow up; use 'substep' (the "
                "default) unless that is the experiment",
                SimulationWarning,
                stacklevel=3,
            )

    def advance(self, duration: float) -> None:
        """Advance by duration [s] (needs dt set): round(duration / dt) steps."""
        if self.dt is None:
            raise ValueError("advance needs a fixed dt; with dt=None use step(n)")
        self.step(int(round(float(duration) / self.dt)))  # noqa: RUF046 (dt may be a NumPy float)

    def damping_forces(self) -> np.ndarray:
        """(n, 3) spring damping forces at the current positions and velocities."""
        return self._sim.damping_forces()

    @property
    def stats(self) -> dict:
        """Since reset_stats(): steps, substeps, ms_per_step, simulated_time, wall_time
        [s], estimate_time [s] and estimates (dt_crit estimates), real_time_ratio; and the
        last step's substeps (last_substeps) and their size (last_substep [s]). The wall
        time is that of the step() calls, progress callbacks excluded."""
        return self._sim.stats
