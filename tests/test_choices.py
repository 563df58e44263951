"""The choices Python offers come from the C++ core, and the Literal types that mirror them
for type checkers agree with it; defaults are the core's too."""

from __future__ import annotations

from typing import get_args

import corotate as cr
import corotate._core as _core
from corotate import choices


def test_literal_types_match_the_core_lists():
    assert set(get_args(choices.ModelName)) == set(_core.model_names())
    assert set(get_args(choices.PreconditionerName)) == set(_core.preconditioner_names())
    assert set(get_args(choices.ExplicitIntegratorName)) == set(_core.explicit_integrator_names())
    assert set(get_args(choices.ImplicitIntegratorName)) | set(get_args(choices.ExplicitIntegratorName)) == set(
        _core.integrator_names()
    )
    assert set(get_args(choices.TimeStepPolicyName)) == set(_core.time_step_policy_names())
    assert set(get_args(choices.OnUnstableName)) == set(_core.on_unstable_names())
    assert set(get_args(choices.FeedbackMethod)) == set(_core.feedback_method_names())
    assert set(get_args(choices.FailurePolicy)) == set(_core.failure_policy_names())


def test_cell_types_come_from_the_core_table_alone():
    # One table, bound from C++: the names, the Mesh's list and the choices are its keys.
    table = cr.cell_types()
    assert list(table) == _core.cell_type_names() == list(cr.SUPPORTED_CELL_TYPES)
    assert choices.CELL_TYPES == tuple(table)


def test_models_per_cell_type():
    assert _core.models_for_cell_type("triangle") == ["stvk"]
    assert set(_core.models_for_cell_type("hexahedron20")) == set(_core.model_names())
    assert _core.models_for_cell_type("wedge") == []


def test_python_defaults_are_the_core_defaults():
    core = _core.PCGSettings()
    pcg = cr.PCG()
    assert pcg.tolerance is None and core.tolerance == 0.0  # the preconditioner's own
    assert (pcg.max_iterations, pcg._settings().tolerance, pcg.preconditioner, pcg.warm_start) == (
        core.max_iterations,
        core.tolerance,
        core.preconditioner,
        core.warm_start,
    )
    mesh = cr.box((1, 1, 1), (1, 1, 1), "tet4")
    sim = cr.Simulation(cr.Body(mesh, cr.Material()))
    assert sim.dt == _core.IntegratorSettings().time_step


def test_settings_take_effect_and_bad_settings_change_nothing():
    mesh = cr.box((1, 1, 1), (1, 1, 1), "tet4")
    sim = cr.ExplicitSimulation(cr.Body(mesh, cr.Material()), dt=1e-4)
    sim.integrator = "symplectic_euler"
    assert sim._sim.settings.integrator == "symplectic_euler"
    try:
        sim.policy = "sometimes"
    except ValueError as e:
        assert "unknown time-step policy 'sometimes'" in str(e)
    else:
        raise AssertionError("an unknown policy was accepted")
    assert sim._sim.settings.policy == "fixed" and sim.policy == "fixed"


def test_type_stubs_name_every_public_symbol():
    import ast
    from pathlib import Path

    stub = Path(_core.__file__).with_name("_core.pyi")
    if not stub.exists():  # an installed wheel without the source tree's stub beside the module
        stub = Path(__file__).parents[1] / "python" / "corotate" / "_core.pyi"
    tree = ast.parse(stub.read_text())
    declared = {node.name for node in tree.body if isinstance(node, (ast.ClassDef, ast.FunctionDef))}
    public = {name for name in dir(_core) if not name.startswith("_")}
    assert public - declared == set(), "regenerate python/corotate/_core.pyi (see its docstring)"


def test_bound_enums_match_the_name_lists():
    def members(enum):
        return [name.lower() for name in enum.__members__]

    assert members(_core.IntegratorKind) == _core.integrator_names()
    assert members(_core.TimeStepPolicy) == _core.time_step_policy_names()
    assert members(_core.OnUnstable) == _core.on_unstable_names()
    assert members(_core.PreconditionerKind) == _core.preconditioner_names()
