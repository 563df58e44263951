"""What a scene returns, checked and given dimension names and frame chunks.

A scene returns a mapping name -> value, each value one of
    a number                 a quantity of the run (no dimensions)
    an array (frames, ...)   one entry per frame: its first axis is named "frame", the others
                             "<name>_dim1", "<name>_dim2", ...
    (dims, array)            the dimension names given, as in xarray (e.g.
                             ``(("frame", "node", "xyz"), positions)``)
Arrays are stored in chunks of whole frames of about one MiB (at least one frame per chunk),
so reading a few frames of many runs reads only those frames."""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

CHUNK_BYTES = 1 << 20


def scene_outputs(returned: Any) -> dict[str, tuple[tuple[str, ...], np.ndarray]]:
    """name -> (dims, array) of what a scene returned; ValueError naming the bad entry."""
    if not isinstance(returned, Mapping):
        raise ValueError(f"the scene must return a mapping name -> array, got {type(returned).__name__}")
    outputs = {}
    for name, value in returned.items():
        if not isinstance(name, str) or not name.isidentifier() or name.startswith("_"):
            raise ValueError(f"output names must be identifiers not starting with '_', got {name!r}")
        if _has_dims(value):
            dims = (value[0],) if isinstance(value[0], str) else tuple(value[0])
            data = np.asarray(value[1])
        else:
            data = np.asarray(value)
            dims = ("frame", *(f"{name}_dim{k}" for k in range(1, data.ndim)))[: data.ndim]
        if data.dtype.kind not in "biuf":
            raise ValueError(f"output {name!r} must be numeric (bool, integer or float), got dtype {data.dtype}")
        if len(dims) != data.ndim or not all(isinstance(d, str) and d.isidentifier() for d in dims):
            raise ValueError(f"output {name!r}: {data.ndim} dimension names needed, got {dims!r}")
        if data.ndim and "run" in dims:
            raise ValueError(f"output {name!r}: the dimension name 'run' is the sweep's own")
        outputs[name] = (dims, np.array(data, order="C"))  # a copy: not a view of a simulation's state
    return outputs


def _has_dims(value: Any) -> bool:
    """Whether value is (dims, array): dims a name or a sequence of names."""
    if not (isinstance(value, tuple) and len(value) == 2):
        return False
    dims = value[0]
    return isinstance(dims, str) or (isinstance(dims, (tuple, list)) and all(isinstance(d, str) for d in dims))


def frame_chunks(dims: tuple[str, ...], data: np.ndarray) -> tuple[int, ...]:
    """Chunks of whole frames, about CHUNK_BYTES each, when the first dimension is "frame";
    else the whole array in one chunk. Every chunk extent is >= 1 (zarr's rule)."""
    whole = tuple(max(1, n) for n in data.shape)
    if not dims or dims[0] != "frame":
        return whole
    frame_bytes = max(1, math.prod(data.shape[1:]) * data.itemsize)
    frames = max(1, min(whole[0], CHUNK_BYTES // frame_bytes))
    return (frames, *whole[1:])
