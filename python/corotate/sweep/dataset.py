"""The whole sweep as one labelled xarray Dataset, read lazily (Dask arrays over the stored chunks)."""

from __future__ import annotations

import os
import uuid
from typing import Any

import numpy as np

from . import zarr_v2
from .store import SweepStore, run_name


def open_sweep(path: str | os.PathLike[str]) -> Any:
    """The sweep in folder ``path`` as an xarray.Dataset over the dimension ``run``.

    returns  xarray.Dataset with
             - coordinates ``run`` (0 .. n_runs-1) and one per parameter (e.g. ``E(run)``);
             - ``status(run)``: "done", "failed" or "missing" (not computed yet);
               ``error(run)``: a failed run's message ("" otherwise); ``seconds(run)``: its
               compute time;
             - each scene output as ``name(run, ...)`` with the scene's dimensions after
               ``run`` (e.g. ``tip(run, frame, xyz)``): Dask arrays, one chunk per run and
               stored chunk, read from the folder when computed (``.values``, ``.load()``,
               ``.sel(...)``). Runs without the output (failed, missing) and runs with fewer
               frames are NaN there (the output is then float64).

    A grid sweep unfolds into one dimension per parameter with
    ``ds.set_index(run=["E", "nu"]).unstack("run")``.
    Raises ValueError when the folder holds no corotate sweep; ImportError without the extra
    [sweep] (xarray, dask).
    """
    try:
        import dask.array as da
        import xarray as xr
    except ImportError as err:
        raise ImportError("open_sweep needs xarray and dask: pip install 'corotate-fem[sweep]'") from err
    store = SweepStore(path)
    description = store.description()
    if description is None:
        raise ValueError(f"{store.path} holds no corotate sweep (run_sweep writes one)")
    table = store.table()
    n = len(table)
    status = np.full(n, "missing", dtype=object)
    error = np.full(n, "", dtype=object)
    seconds = np.full(n, np.nan)
    found: dict[str, dict[int, dict[str, Any]]] = {}
    for run, run_status in sorted(store.finished().items()):
        attrs = store.run_attrs(run)
        status[run], error[run] = run_status, attrs.get("error") or ""
        seconds[run] = attrs.get("seconds", np.nan)
        for name, meta in attrs.get("outputs", {}).items():
            found.setdefault(name, {})[run] = {**meta, "folder": store.run_path(run) / name}
    data_vars: dict[str, Any] = {
        "status": ("run", status.astype(str)),
        "error": ("run", error.astype(str)),
        "seconds": ("run", seconds),
    }
    for name, stored in found.items():
        data_vars[name] = _output(da, name, stored, n)
    coords: dict[str, Any] = {"run": np.arange(n)}
    coords.update({name: ("run", values) for name, values in table.columns.items()})
    attrs = {key: description[key] for key in ("scene", "fingerprint", "parameters")}
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)


def _output(da: Any, name: str, stored: dict[int, dict[str, Any]], n: int) -> tuple[tuple[str, ...], Any]:
    """(("run", *dims), Dask array) of one output over all runs; NaN where a run lacks it."""
    first_run, first = next(iter(stored.items()))
    for run, meta in stored.items():
        if meta["dims"] != first["dims"]:
            raise ValueError(
                f"output {name!r} has dimensions {tuple(meta['dims'])} in {run_name(run)} but "
                f"{tuple(first['dims'])} in {run_name(first_run)}: a scene must return each output "
                "with the same dimensions in every run"
            )
    shape = tuple(max(meta["shape"][k] for meta in stored.values()) for k in range(len(first["dims"])))
    uniform = len(stored) == n and all(tuple(meta["shape"]) == shape for meta in stored.values())
    dtype = np.result_type(*(np.dtype(meta["dtype"]) for meta in stored.values())) if uniform else np.float64
    steps = [max(meta["chunks"][k] for meta in stored.values()) for k in range(len(shape))]
    chunks = ((1,) * n, *(_chunks_along(extent, step) for extent, step in zip(shape, steps)))
    array = da.map_blocks(
        _read_block,
        stored=_Opaque(stored),
        dtype=dtype,
        chunks=chunks,
        meta=np.empty((0,) * (1 + len(shape)), dtype),
        name=f"corotate-sweep-{name}-{uuid.uuid4().hex}",  # no hashing of the whole sweep's description
    )
    return ("run", *first["dims"]), array


class _Opaque:
    """The runs' descriptions handed to every block as one object: Dask walks a dict argument
    through for every block (seconds for a thousand runs), an object it does not."""

    def __init__(self, stored: dict[int, dict[str, Any]]) -> None:
        self.stored = stored


def _chunks_along(extent: int, step: int) -> tuple[int, ...]:
    """Chunk sizes covering extent in steps of step (one empty chunk for extent 0)."""
    if extent == 0:
        return (0,)
    return (step,) * (extent // step) + ((extent % step,) if extent % step else ())


def _read_block(stored: _Opaque, block_info: Any = None) -> np.ndarray:
    """One run's part of an output (NaN outside what the run stored)."""
    info = block_info[None]
    (run, _), *location = info["array-location"]
    dtype = np.dtype(info["dtype"])
    fill = np.nan if dtype.kind == "f" else 0  # not float: every run has it whole (see _output)
    out = np.full([1, *(stop - start for start, stop in location)], fill, dtype=dtype)
    meta = stored.stored.get(run)
    if meta is not None:
        region = [slice(start, min(stop, extent)) for (start, stop), extent in zip(location, meta["shape"])]
        if all(s.stop > s.start for s in region) or not region:
            values = zarr_v2.read_region(
                meta["folder"], tuple(meta["shape"]), tuple(meta["chunks"]), meta["dtype"], region
            )
            within_run = out.reshape(out.shape[1:])  # a view: the run axis has length 1
            within_run[tuple(slice(0, s.stop - s.start) for s in region)] = values
    return out
