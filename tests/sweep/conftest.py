"""A two-worker LocalCluster shared by the sweep tests (starting one takes seconds)."""

import pytest


@pytest.fixture(scope="session")
def client():
    """A distributed.Client of a LocalCluster: 2 worker processes of 1 thread, as run_sweep
    starts by default on this machine; workers killed by a test are restarted by their nanny."""
    distributed = pytest.importorskip("distributed", reason="sweeps run on dask.distributed (the extra [sweep])")
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0")
    client = distributed.Client(cluster, set_as_default=False)
    yield client
    client.close()
    cluster.close()
