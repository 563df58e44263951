"""A sweep spec file for ``corotate sweep SPEC``: a Python file that defines

    scene   the scene function (required)
    table   the parameter table: a ParameterTable, a mapping name -> values or a list of
            runs (required)
    out     the default output folder (optional; else SPEC's name with .zarr, next to it)

A Python file because a scene is code; the table is then whatever the file computes
(``ParameterTable.grid(...)``, ``ParameterTable.latin_hypercube(...)``, rows read from a CSV
file, ...). The file is imported once by the command, not by the workers: the scene is sent
to them by value, so they need corotate but not the file."""

from __future__ import annotations

import hashlib
import importlib.util
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable

from .table import ParameterTable


@dataclass
class SweepSpec:
    """What a spec file defines: the scene, the table, and the default output folder."""

    scene: Callable[..., Any]
    table: ParameterTable
    out: Path


def load_spec(path: str | Path) -> SweepSpec:
    """Import the spec file at path. Raises FileNotFoundError for a missing file and ValueError
    when it lacks ``scene`` or ``table`` or they are of the wrong kind."""
    import cloudpickle

    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"no sweep spec file {path}")
    if path.suffix != ".py":
        raise ValueError(f"a sweep spec is a Python file (.py) defining scene and table, got {path}")
    name = "corotate_sweep_spec_" + hashlib.sha256(str(path.resolve()).encode()).hexdigest()[:12]
    loader_spec = importlib.util.spec_from_file_location(name, path)
    if loader_spec is None or loader_spec.loader is None:
        raise ValueError(f"cannot import the sweep spec {path}")
    module = importlib.util.module_from_spec(loader_spec)
    sys.modules[name] = module  # cloudpickle sends the module's functions by value only when it is registered
    loader_spec.loader.exec_module(module)
    cloudpickle.register_pickle_by_value(module)
    scene = getattr(module, "scene", None)
    if not callable(scene):
        raise ValueError(f"the sweep spec {path} must define scene, a function of the parameters")
    if not hasattr(module, "table"):
        raise ValueError(f"the sweep spec {path} must define table (a ParameterTable, mapping or list of runs)")
    table = ParameterTable.coerce(module.table)
    out = Path(getattr(module, "out", path.with_suffix(".zarr")))
    if not out.is_absolute():
        out = path.parent / out
    return SweepSpec(scene=scene, table=table, out=out)
