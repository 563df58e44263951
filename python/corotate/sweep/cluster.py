"""The Dask cluster a sweep runs on: a LocalCluster started for it, or one the caller names."""

from __future__ import annotations

import os
from typing import Any

EXTRA_HINT = "pip install 'corotate-fem[sweep]'"

# The LocalCluster's settings (Dask configuration keys, read when the cluster starts):
LOCAL_SETTINGS = {
    # a worker holds only the task it runs, so a run that crashes its worker takes no queued
    # task of another run down with it (each death counts against every task on the worker,
    # and allowed-failures of them fail the task)
    "distributed.scheduler.worker-saturation": 1.0,
    # no dashboard is shown: the workers' sampling profiler and frequent monitoring would only
    # take time from the runs (measured: runs 5-10 % slower on two busy cores)
    "distributed.worker.profile.enabled": False,
    "distributed.worker.memory.monitor-interval": "1s",
    "distributed.admin.system-monitor.interval": "2s",
}


def local_cluster(workers: int | None = None, threads_per_run: int = 1) -> tuple[Any, Any]:
    """Start the LocalCluster run_sweep starts by default: (a distributed.Client, the cluster).

    workers          worker processes (default: cores // threads_per_run), one thread each
    threads_per_run  the corotate threads a run will use (only sizes the default)
    Its workers ignore Ctrl-C (the sweep's own process handles it). Close the client, then the
    cluster, when done; pass the client to run_sweep(scheduler=...) to run several sweeps on it."""
    import dask
    from distributed import Client, LocalCluster

    from .worker_plugin import IgnoreCtrlC

    n = workers or max(1, (os.cpu_count() or 1) // threads_per_run)
    with dask.config.set(LOCAL_SETTINGS):
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=":0")
    client = Client(cluster, set_as_default=False)
    # register_plugin since distributed 2023.9.2; register_worker_plugin before
    register = getattr(client, "register_plugin", None) or getattr(client, "register_worker_plugin")  # noqa: B009
    register(IgnoreCtrlC())
    return client, cluster


def connect(scheduler: Any, workers: int | None, threads: int, timeout: float) -> tuple[Any, Any]:
    """(client, the LocalCluster started here or None) for run_sweep's scheduler argument; the
    client is None when the caller gave one (the caller closes it)."""
    try:
        from distributed import Client
    except ImportError as err:
        raise ImportError(f"the sweep runs on dask.distributed: {EXTRA_HINT}") from err
    if isinstance(scheduler, Client):
        return None, None
    if scheduler is None:
        return local_cluster(workers, threads)
    target = scheduler if isinstance(scheduler, str) else getattr(scheduler, "scheduler_address", None)
    if target is None:
        raise TypeError(
            "scheduler must be None, an address such as 'tcp://host:8786', a dask Cluster or a Client, "
            f"got {type(scheduler).__name__}"
        )
    try:
        return Client(target, timeout=timeout, set_as_default=False), None
    except (OSError, TimeoutError) as err:
        raise RuntimeError(f"cannot reach the Dask scheduler at {target} (waited {timeout} s): {err}") from err


def close(client: Any, cluster: Any) -> None:
    """Close what connect opened (a Client given by the caller stays open)."""
    if client is not None:
        client.close(timeout=10)
    if cluster is not None:
        cluster.close(timeout=20)
