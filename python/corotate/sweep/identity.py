"""What makes two sweeps the same sweep: the scene function (its name and source) and the
parameter table. The output folder keeps this fingerprint, so a second, different sweep
cannot be mixed into it."""

from __future__ import annotations

import functools
import hashlib
import inspect
import json
from typing import Any, Callable

from .table import ParameterTable


def scene_name(scene: Callable[..., Any]) -> str:
    """``module:qualname`` of the scene function (a functools.partial: the function's name and
    the bound arguments)."""
    if isinstance(scene, functools.partial):
        bound = ", ".join([*map(repr, scene.args), *(f"{k}={v!r}" for k, v in sorted(scene.keywords.items()))])
        return f"partial({scene_name(scene.func)}, {bound})"
    module = getattr(scene, "__module__", None) or "?"
    name = getattr(scene, "__qualname__", None) or type(scene).__qualname__
    return f"{module}:{name}"


def scene_source(scene: Callable[..., Any]) -> str:
    """The source text of the scene function ('' where Python cannot find it, e.g. a
    function typed at the interactive prompt)."""
    while isinstance(scene, functools.partial):
        scene = scene.func
    try:
        return inspect.getsource(scene)
    except (OSError, TypeError):
        return ""


def sweep_fingerprint(scene: Callable[..., Any], table: ParameterTable) -> str:
    """A SHA-256 over the scene's name and source and the table's fingerprint."""
    source = hashlib.sha256(scene_source(scene).encode()).hexdigest()
    described = json.dumps([scene_name(scene).split(":", 1)[-1], source, table.fingerprint()])
    return hashlib.sha256(described.encode()).hexdigest()
