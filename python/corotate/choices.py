"""The named choices of the API, one source of truth: the name lists come from the C++ core
(``corotate._core``); the ``Literal`` types mirror them for type checkers, and
tests/test_choices.py checks that the two agree. Cell types are the exception: they are
the keys of the core's cell-type table (``corotate.cell_types()``), which grows with every
registered element, so ``CellType`` is a plain string checked against that table."""

from __future__ import annotations

from typing import Literal

import corotate._core as _core

ModelName = Literal[
    "linear", "corotational", "stvk", "neohookean", "fixed_corotated", "neohookean_log", "mooney_rivlin"
]
CellType = str  # a key of corotate.cell_types()
PreconditionerName = Literal["none", "jacobi", "block_jacobi", "reference_factor", "two_level", "auto"]
ImplicitIntegratorName = Literal["linearized", "newton"]
ExplicitIntegratorName = Literal["symplectic_euler", "verlet"]
TimeStepPolicyName = Literal["fixed", "online"]
OnUnstableName = Literal["substep", "raise", "allow"]
MassKind = Literal["consistent", "lumped"]
FeedbackMethod = Literal["linear", "corotational", "averaged"]
FailurePolicy = Literal["ignore", "warn", "raise"]

MODELS: tuple[str, ...] = tuple(_core.model_names())
CELL_TYPES: tuple[str, ...] = tuple(_core.cell_type_names())
PRECONDITIONERS: tuple[str, ...] = tuple(_core.preconditioner_names())
EXPLICIT_INTEGRATORS: tuple[str, ...] = tuple(_core.explicit_integrator_names())
IMPLICIT_INTEGRATORS: tuple[str, ...] = tuple(n for n in _core.integrator_names() if n not in EXPLICIT_INTEGRATORS)
TIME_STEP_POLICIES: tuple[str, ...] = tuple(_core.time_step_policy_names())
ON_UNSTABLE: tuple[str, ...] = tuple(_core.on_unstable_names())
MASS_KINDS: tuple[str, ...] = ("consistent", "lumped")
FEEDBACK_METHODS: tuple[str, ...] = tuple(_core.feedback_method_names())
FAILURE_POLICIES: tuple[str, ...] = tuple(_core.failure_policy_names())


def check_choice(value: object, choices: tuple[str, ...], what: str) -> str:
    """value if it is one of choices, else ValueError naming what and the choices."""
    if value not in choices:
        raise ValueError(f"unknown {what} {value!r}; choose one of {', '.join(choices)}")
    return str(value)
