"""The parameter table of a sweep: one row per run, one column per scene parameter.

Built from a grid, a list of runs or a random design (a Latin hypercube from SciPy's
``qmc``), and checked before any run starts: every run has every parameter, and no value is
missing, NaN or infinite."""

from __future__ import annotations

import hashlib
import itertools
import json
import math
import numbers
from collections.abc import Iterable, Mapping, Sequence
from typing import Any, Union

import numpy as np

#: A parameter value as a scene receives it.
Value = Union[float, int, bool, str]


class ParameterTable:
    """An ordered table of runs.

    columns  mapping name -> sequence of values, all of the same length (one per run);
             values are numbers (float, int, bool) or strings, one kind per column
    Raises ValueError naming the parameter and the run for a missing (None), NaN or infinite
    value, columns of different lengths, a column mixing numbers and strings, or a name that
    is not a Python identifier (the scene receives the parameters as keyword arguments).

    ``len(table)`` is the number of runs; ``table.row(i)`` the keyword arguments of run i;
    ``table.columns`` the columns as (n_runs,) NumPy arrays (float64, int64, bool or str).
    Runs are numbered 0 .. n_runs-1 in the order given: the output folder names them so.
    """

    def __init__(self, columns: Mapping[str, Sequence[Any] | np.ndarray]) -> None:
        if not isinstance(columns, Mapping) or not columns:
            raise ValueError("a parameter table needs at least one parameter (a mapping name -> values)")
        lengths = {name: len(values) for name, values in columns.items()}
        if len(set(lengths.values())) != 1:
            raise ValueError(f"the parameter columns differ in length: {lengths}")
        if next(iter(lengths.values())) == 0:
            raise ValueError("the parameter table has no runs")
        self._columns = {_check_name(name): _column(name, values) for name, values in columns.items()}

    # --- designs --------------------------------------------------------------------
    @classmethod
    def grid(cls, **axes: Iterable[Any]) -> ParameterTable:
        """Every combination of the given values (the last parameter varies fastest).

        ``ParameterTable.grid(E=[1e6, 2e6], nu=[0.3, 0.45])`` has 4 runs."""
        if not axes:
            raise ValueError("grid() needs at least one parameter, e.g. grid(E=[1e6, 2e6])")
        values = {name: list(v) for name, v in axes.items()}
        for name, v in values.items():
            if not v:
                raise ValueError(f"grid(): parameter {name!r} has no values")
        rows = list(itertools.product(*values.values()))
        return cls({name: [row[k] for row in rows] for k, name in enumerate(values)})

    @classmethod
    def from_runs(cls, runs: Sequence[Mapping[str, Any]]) -> ParameterTable:
        """A list of runs, each a mapping name -> value; every run must name the same
        parameters (ValueError naming the run and the missing parameter otherwise)."""
        if not runs:
            raise ValueError("the parameter table has no runs")
        names = list(runs[0])
        for i, run in enumerate(runs):
            missing = [n for n in names if n not in run]
            extra = [n for n in run if n not in names]
            if missing or extra:
                what = f"lacks {missing}" if missing else f"has parameters {extra} that run 0 lacks"
                raise ValueError(f"run {i} of the parameter table {what}")
        return cls({name: [run[name] for run in runs] for name in names})

    @classmethod
    def latin_hypercube(
        cls,
        n: int,
        bounds: Mapping[str, tuple[float, float]],
        seed: int = 0,
        log: Iterable[str] = (),
    ) -> ParameterTable:
        """n runs of a Latin hypercube design (scipy.stats.qmc.LatinHypercube): each
        parameter's range cut into n equal strata, each stratum sampled once.

        bounds  mapping name -> (low, high), low < high
        seed    the random seed: the same seed gives the same table (and so the same sweep)
        log     names sampled uniformly in log scale (e.g. a Young's modulus over decades;
                both bounds > 0)"""
        from scipy.stats import qmc

        if isinstance(n, bool) or not isinstance(n, numbers.Integral) or n < 1:
            raise ValueError(f"latin_hypercube() needs n >= 1 runs, got {n!r}")
        if not bounds:
            raise ValueError("latin_hypercube() needs bounds for at least one parameter")
        log = set(log)
        unknown = log - set(bounds)
        if unknown:
            raise ValueError(f"log names parameters without bounds: {sorted(unknown)}")
        low, high = [], []
        for name, (lo, hi) in bounds.items():
            if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
                raise ValueError(f"the bounds of {name!r} must be finite with low < high, got ({lo}, {hi})")
            if name in log and lo <= 0:
                raise ValueError(f"{name!r} is sampled in log scale: its bounds must be > 0, got ({lo}, {hi})")
            low.append(math.log(lo) if name in log else lo)
            high.append(math.log(hi) if name in log else hi)
        unit = qmc.LatinHypercube(d=len(bounds), seed=seed).random(int(n))
        samples = qmc.scale(unit, low, high)
        columns = {}
        for k, name in enumerate(bounds):
            columns[name] = np.exp(samples[:, k]) if name in log else samples[:, k]
        return cls(columns)

    @classmethod
    def coerce(cls, table: Any) -> ParameterTable:
        """table as a ParameterTable: a ParameterTable, a mapping of columns, or a list of
        runs (mappings)."""
        if isinstance(table, ParameterTable):
            return table
        if isinstance(table, Mapping):
            return cls(table)
        if isinstance(table, Sequence) and not isinstance(table, str):
            return cls.from_runs(table)
        raise TypeError(
            "the parameter table must be a ParameterTable, a mapping name -> values or a list of runs, "
            f"got {type(table).__name__}"
        )

    # --- reading ----------------------------------------------------------------------
    def __len__(self) -> int:
        return len(next(iter(self._columns.values())))

    @property
    def names(self) -> list[str]:
        """The parameter names, in order."""
        return list(self._columns)

    @property
    def columns(self) -> dict[str, np.ndarray]:
        """name -> (n_runs,) array (a copy)."""
        return {name: values.copy() for name, values in self._columns.items()}

    def row(self, i: int) -> dict[str, Value]:
        """The parameters of run i as Python scalars (float, int, bool or str)."""
        return {name: values[i].item() for name, values in self._columns.items()}

    def to_json(self) -> dict[str, list[Value]]:
        """The columns as JSON-ready lists (floats round-trip exactly through JSON)."""
        return {name: values.tolist() for name, values in self._columns.items()}

    def fingerprint(self) -> str:
        """A SHA-256 of the names, kinds and values (identical tables, identical prints)."""
        described = {name: [str(values.dtype.kind), values.tolist()] for name, values in self._columns.items()}
        return hashlib.sha256(json.dumps(described, sort_keys=False).encode()).hexdigest()

    def __eq__(self, other: object) -> bool:
        return isinstance(other, ParameterTable) and self.fingerprint() == other.fingerprint()

    def __hash__(self) -> int:
        return hash(self.fingerprint())

    def __repr__(self) -> str:
        return f"ParameterTable({len(self)} runs of {', '.join(self.names)})"


def _check_name(name: object) -> str:
    if not isinstance(name, str) or not name.isidentifier():
        raise ValueError(f"parameter names must be Python identifiers (keyword arguments of the scene), got {name!r}")
    return name


def _column(name: str, values: Sequence[Any] | np.ndarray) -> np.ndarray:
    """values as a (n,) array of one kind, or ValueError naming the first bad run."""
    values = list(values.tolist() if isinstance(values, np.ndarray) else values)
    for i, v in enumerate(values):
        if v is None:
            raise ValueError(f"parameter {name!r} is missing in run {i}")
        if isinstance(v, np.generic):
            v = values[i] = v.item()
        if isinstance(v, str):
            continue
        if not isinstance(v, numbers.Real):
            raise ValueError(f"parameter {name!r} of run {i} is {v!r}: values must be numbers or strings")
        if not math.isfinite(v):
            raise ValueError(f"parameter {name!r} is {v} in run {i}: values must be finite")
    kinds = {"str" if isinstance(v, str) else "number" for v in values}
    if len(kinds) > 1:
        raise ValueError(f"parameter {name!r} mixes numbers and strings")
    if kinds == {"str"}:
        return np.array(values, dtype=str)
    if all(isinstance(v, bool) for v in values):
        return np.array(values, dtype=bool)
    if all(isinstance(v, numbers.Integral) for v in values):
        return np.array(values, dtype=np.int64)
    return np.array(values, dtype=np.float64)
