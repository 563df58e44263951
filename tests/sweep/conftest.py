"""A two-worker LocalCluster shared by the sweep tests (starting one takes seconds)."""

import pytest


@pytest.fixture(scope="session")
def client():
    """A distributed.Client of a LocalCluster as run_sweep starts it on this machine: 2 worker
    processes of 1 thread; workers killed by a test are restarted by their nanny."""
    pytest.importorskip("distributed", reason="sweeps run on dask.distributed (the extra [sweep])")
    from corotate.sweep import local_cluster

    client, cluster = local_cluster(workers=2)
    yield client
    client.close()
    cluster.close()
