"""Linear solver choices for the implicit step."""

from __future__ import annotations

from dataclasses import dataclass
from typing import cast

import corotate._core as _core

from .choices import PRECONDITIONERS, PreconditionerName, check_choice

_DEFAULTS = _core.PCGSettings()  # the defaults live in C++ (solvers/pcg.hpp)
_DEFAULT_PRECONDITIONER = cast(PreconditionerName, _DEFAULTS.preconditioner)


@dataclass(frozen=True)
class PCG:
    """Preconditioned conjugate gradients with an iteration cap (the paper's solver).

    max_iterations  cap on CG iterations per step; the step uses what it has at the cap
    tolerance       relative residual |b - A dv| / |b| at which CG stops early; None
                    (default): the preconditioner's, 2e-2 for "two_level" (its coarse
                    correction leaves a residual that moves the body little) and 1e-2 for
                    the others; sim.stats["tolerance"] says which was used. From 1e-4
                    up, with "two_level" or "reference_factor", the step assembles A in
                    float32 and CG multiplies with it (A to about 1e-7 per entry; below
                    1e-4, and for the step that builds the preconditioner, in double)
    preconditioner  "auto" (default): "reference_factor" below 6,000 unknowns, "two_level"
                    from there on, chosen at the first step;
                    "two_level" (smoothed aggregation with rigid-body modes: block-Jacobi
                    smoothing plus a coarse correction factorized once, turned with each
                    aggregate's rotation as the body moves),
                    "reference_factor" (Cholesky factor of the first step's system matrix,
                    reused, applied in each node's turned frame (the rotation of the
                    node and its neighbours), factorized afresh after a solve that ends
                    at the cap), "block_jacobi" (3x3 node blocks),
                    "jacobi" or "none"
    warm_start      start each solve from the previous step's answer

    The defaults are the fastest setting found to stay within 1% of a converged solve on
    the benchmark beam (docs: benchmarks, performance notes).
    """

    max_iterations: int = _DEFAULTS.max_iterations
    tolerance: float | None = None
    preconditioner: PreconditionerName = _DEFAULT_PRECONDITIONER
    warm_start: bool = _DEFAULTS.warm_start

    def _settings(self) -> _core.PCGSettings:
        check_choice(self.preconditioner, PRECONDITIONERS, "preconditioner")
        if self.tolerance is not None and not self.tolerance > 0:  # (0 is the C++ core's "default")
            raise ValueError(
                f"PCG: tolerance must be positive, or None for the preconditioner's default; got {self.tolerance!r}"
            )
        tolerance = 0.0 if self.tolerance is None else float(self.tolerance)
        return _core.PCGSettings(int(self.max_iterations), tolerance, bool(self.warm_start), self.preconditioner)

    def _args(self) -> tuple[str, _core.PCGSettings]:
        return "pcg", self._settings()


@dataclass(frozen=True)
class Direct:
    """Sparse direct solve by Cholesky factorization; the pattern is analysed (ordered) once,
    each step factorizes. From 4,000 unknowns: SuiteSparse CHOLMOD when corotate was built with
    it, else the library's own supernodal factorization (AMD ordering, dense kernels compiled
    per instruction set); below: Eigen's SimplicialLDLT. build_info() says which the build has."""

    def _args(self) -> tuple[str, _core.PCGSettings]:
        return "direct", _core.PCGSettings()
