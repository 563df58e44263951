"""Parameter sweeps on Dask: a scene run over a table of parameters, stored as a Zarr data set.

    import corotate as cr
    from corotate.sweep.scenes import cantilever

    table = cr.ParameterTable.grid(E=[1e6, 2e6], nu=[0.3, 0.4], load=[10.0, 20.0])
    report = cr.run_sweep(cantilever, table, "cantilever.zarr")   # a LocalCluster by default
    ds = cr.open_sweep("cantilever.zarr")                          # one xarray.Dataset over "run"

Importing this package imports neither Dask, zarr nor xarray: they load when a sweep runs or
opens (the extra [sweep]). docs/guide/sweeps.md is the guide.
"""

from __future__ import annotations

from .cluster import local_cluster
from .dataset import open_sweep
from .progress import ProgressBar
from .runner import SweepReport, run_sweep
from .spec import SweepSpec, load_spec
from .store import SweepStore
from .table import ParameterTable

__all__ = [
    "ParameterTable",
    "run_sweep",
    "open_sweep",
    "SweepReport",
    "SweepStore",
    "SweepSpec",
    "load_spec",
    "local_cluster",
    "ProgressBar",
]
