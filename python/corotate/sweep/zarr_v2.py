"""Writing Zarr groups and arrays in the Zarr format 2 layout, straight to files.

A run's group is a handful of small files; the zarr library writes each through an asyncio
round trip (zarr 3), about ten per run, which on a busy machine cost more than the scene
itself. Written here instead: a group is a folder with ``.zgroup`` and ``.zattrs``, an array a
folder with ``.zarray``, ``.zattrs`` and one file per chunk (named "i.j.k", edge chunks
padded to the full chunk shape), compressed with Zstandard through numcodecs. The same bytes
whichever zarr is installed (2 on Python 3.9/3.10, 3 later); reading goes through zarr and
xarray (``open_array``; the tests check the layout so), or, for the many small reads of a
whole sweep, ``read_region``. Array dimensions are named in the
``_ARRAY_DIMENSIONS`` attribute, xarray's convention, so one run's group also opens alone
with ``xarray.open_zarr``."""

from __future__ import annotations

import itertools
import json
import os
from pathlib import Path
from typing import Any

import numpy as np

_COMPRESSOR = {"id": "zstd", "level": 1}


def _write_json(path: Path, content: dict[str, Any]) -> None:
    path.write_text(json.dumps(content, allow_nan=False, indent=1))


def new_group(path: Path, attrs: dict[str, Any] | None = None) -> None:
    """Make path (a folder, created if absent; other files in it stay) a group, with these
    attributes if given (else set them later with set_attrs)."""
    path.mkdir(parents=True, exist_ok=True)
    _write_json(path / ".zgroup", {"zarr_format": 2})
    if attrs is not None:
        set_attrs(path, attrs)


def set_attrs(path: Path, attrs: dict[str, Any]) -> None:
    """Replace the attributes of the group or array at path (one file)."""
    _write_json(path / ".zattrs", attrs)


def write_array(group: Path, name: str, data: np.ndarray, chunks: tuple[int, ...], dims: tuple[str, ...]) -> None:
    """Store data as array ``name`` of the group at ``group``, cut into chunks of this shape."""
    import numcodecs

    codec = numcodecs.get_codec(dict(_COMPRESSOR))
    folder = group / name
    folder.mkdir()
    data = np.require(data, requirements="C")  # keeps 0-d arrays 0-d (ascontiguousarray does not)
    meta = {
        "zarr_format": 2,
        "shape": list(data.shape),
        "chunks": list(chunks),
        "dtype": data.dtype.str,
        "compressor": _COMPRESSOR,
        "fill_value": None,  # every chunk is written; a fill value would be read by xarray as "missing"
        "order": "C",
        "filters": None,
        "dimension_separator": ".",
    }
    counts = [-(-n // c) for n, c in zip(data.shape, chunks)]
    for index in itertools.product(*(range(k) for k in counts)):
        block = data[tuple(slice(i * c, (i + 1) * c) for i, c in zip(index, chunks))]
        if block.shape != tuple(chunks):  # an edge chunk: stored at the full chunk shape
            block = np.pad(block, [(0, c - n) for c, n in zip(chunks, block.shape)])
        key = ".".join(map(str, index)) if index else "0"
        (folder / key).write_bytes(codec.encode(np.ascontiguousarray(block)))
    _write_json(folder / ".zarray", meta)
    set_attrs(folder, {"_ARRAY_DIMENSIONS": list(dims)})


def read_region(folder: Path, shape: tuple[int, ...], chunks: tuple[int, ...], dtype: Any, region: Any) -> np.ndarray:
    """data[region] of the array written by write_array at folder: region is one slice (start,
    stop; no step) per dimension, within shape. Decodes only the chunks the region touches."""
    import numcodecs

    codec = numcodecs.get_codec(dict(_COMPRESSOR))
    dtype = np.dtype(dtype)
    out = np.empty([s.stop - s.start for s in region], dtype=dtype)
    touched = [range(s.start // c, -(-s.stop // c)) for s, c in zip(region, chunks)]
    for index in itertools.product(*touched):
        key = ".".join(map(str, index)) if index else "0"
        block = np.frombuffer(codec.decode((folder / key).read_bytes()), dtype=dtype).reshape(chunks)
        low = [max(s.start, i * c) for s, i, c in zip(region, index, chunks)]
        high = [min(s.stop, (i + 1) * c) for s, i, c in zip(region, index, chunks)]
        target = tuple(slice(lo - s.start, hi - s.start) for lo, hi, s in zip(low, high, region))
        out[target] = block[tuple(slice(lo - i * c, hi - i * c) for lo, hi, i, c in zip(low, high, index, chunks))]
    return out


def open_array(path: str | os.PathLike[str]) -> Any:
    """The array stored at path, read-only, through the zarr library."""
    import zarr

    return zarr.open_array(str(path), mode="r")
