"""Type checks for numeric parameters: a bool is not a number (``Material(E=True)`` would
otherwise mean E = 1 Pa), and neither is a string that float() happens to parse."""

from __future__ import annotations

import numbers

import numpy as np


def real_number(value: object, name: str) -> float:
    """value as a float if it is a real number (int, float, NumPy scalar or 0-d array), else TypeError
    naming the parameter; bools (Python and NumPy) are rejected."""
    if isinstance(value, np.ndarray) and value.ndim == 0 and value.dtype.kind in "iuf":
        return float(value)  # a 0-d array, as NumPy reductions return
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a real number, got {type(value).__name__} {value!r}")
    return float(value)
