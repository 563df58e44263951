"""A run whose scene raises is recorded as failed with its message while the rest completes;
bad input is refused with a clear error before any run starts."""

import os
import socket

import numpy as np
import pytest

pytest.importorskip("distributed", reason="sweeps run on dask.distributed (the extra [sweep])")
pytest.importorskip("xarray", reason="open_sweep returns an xarray Dataset (the extra [sweep])")

import corotate as cr
from corotate.sweep.scenes import cantilever


def test_runs_that_raise_are_recorded_with_their_message_and_the_rest_completes(tmp_path, client):
    # nu = 0.5 is an impossible material (Material raises ValueError); a 1e9 N tip load on the
    # soft beam inverts its elements in the first step (RuntimeError under on_failure="raise")
    table = cr.ParameterTable.grid(E=[2e5, 5e5], nu=[0.3, 0.5], tip_load=[5.0, 1e9])
    out = tmp_path / "failures.zarr"
    report = cr.run_sweep(cantilever, table, out, scheduler=client, progress=False)
    assert (report.done, report.failed, report.missing) == (2, 6, 0)
    ds = cr.open_sweep(out)
    for run in range(8):
        row = table.row(run)
        if row["nu"] == 0.5:
            assert ds.status.values[run] == "failed"
            assert ds.error.values[run].startswith("ValueError: ") and "nu" in ds.error.values[run]
        elif row["tip_load"] == 1e9:
            assert ds.status.values[run] == "failed"
            assert ds.error.values[run].startswith("RuntimeError: ") and "invert" in ds.error.values[run]
        else:
            assert ds.status.values[run] == "done" and ds.error.values[run] == ""
            assert np.array_equal(ds.positions.values[run], cantilever(**row)["positions"][1])
            continue
        assert np.isnan(ds.positions.values[run]).all()  # no output: NaN in the data set
    # failed runs count as finished: not computed again, unless asked
    again = cr.run_sweep(cantilever, table, out, scheduler=client, progress=False)
    assert (again.found, again.computed) == (8, [])
    retried = cr.run_sweep(cantilever, table, out, scheduler=client, progress=False, retry_failed=True)
    assert retried.computed == [run for run in range(8) if ds.status.values[run] == "failed"]
    assert (retried.done, retried.failed) == (2, 6)


def counting_scene(log):
    def scene(E, nu, tip_load):
        open(os.path.join(log, f"{E}-{nu}-{tip_load}"), "w").close()
        return cantilever(E, nu, tip_load)

    return scene


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.mark.parametrize(
    "columns, message",
    [
        ({"E": [1e6, 2e6], "nu": [0.3, float("nan")], "tip_load": [1.0, 2.0]}, "parameter 'nu' is nan in run 1"),
        ({"E": [1e6, 2e6], "nu": [0.3, None], "tip_load": [1.0, 2.0]}, "parameter 'nu' is missing in run 1"),
        (
            [{"E": 1e6, "nu": 0.3, "tip_load": 1.0}, {"E": 1e6, "nu": 0.3}],
            r"run 1 of the parameter table lacks \['tip_load'\]",
        ),
    ],
)
def test_a_table_with_missing_or_nan_entries_is_refused_before_any_run(tmp_path, columns, message):
    out = tmp_path / "out.zarr"
    with pytest.raises(ValueError, match=message):
        cr.run_sweep(counting_scene(str(tmp_path)), columns, out, scheduler="tcp://127.0.0.1:1", progress=False)
    assert not out.exists() and os.listdir(tmp_path) == []


def test_a_folder_holding_a_different_sweep_is_refused_before_any_run(tmp_path, client):
    log = tmp_path / "calls"
    log.mkdir()
    out = tmp_path / "out.zarr"
    scene = counting_scene(str(log))
    table = cr.ParameterTable.grid(E=[3e5], nu=[0.3], tip_load=[1.0, 2.0])
    cr.run_sweep(scene, table, out, scheduler=client, progress=False)
    assert len(os.listdir(log)) == 2
    listing = sorted(str(p.relative_to(out)) for p in out.rglob("*"))
    other_table = cr.ParameterTable.grid(E=[3e5], nu=[0.3], tip_load=[1.0, 3.0])
    with pytest.raises(ValueError, match=r"holds a different sweep .* parameter table differ"):
        cr.run_sweep(scene, other_table, out, scheduler=client, progress=False)
    with pytest.raises(ValueError, match="holds a different sweep"):
        cr.run_sweep(counting_scene, table, out, scheduler=client, progress=False)  # another scene function
    assert len(os.listdir(log)) == 2  # no run started
    assert sorted(str(p.relative_to(out)) for p in out.rglob("*")) == listing  # nothing written
    other = tmp_path / "notes"
    other.mkdir()
    (other / "notes.txt").write_text("mine")
    with pytest.raises(ValueError, match="not empty and holds no corotate sweep"):
        cr.run_sweep(scene, table, other, scheduler=client, progress=False)
    assert os.listdir(other) == ["notes.txt"]


def test_an_unreachable_scheduler_is_reported_before_any_run(tmp_path):
    out = tmp_path / "out.zarr"
    address = f"tcp://127.0.0.1:{free_port()}"  # nobody listens there
    table = cr.ParameterTable.grid(E=[3e5], nu=[0.3], tip_load=[1.0])
    with pytest.raises(RuntimeError, match=f"cannot reach the Dask scheduler at {address}"):
        cr.run_sweep(counting_scene(str(tmp_path)), table, out, scheduler=address, connect_timeout=1.0, progress=False)
    assert not out.exists() and os.listdir(tmp_path) == []


def test_bad_arguments_are_named(tmp_path):
    table = cr.ParameterTable.grid(E=[3e5], nu=[0.3], tip_load=[1.0])
    with pytest.raises(ValueError, match="threads_per_run must be an integer >= 1"):
        cr.run_sweep(cantilever, table, tmp_path / "a", threads_per_run=0)
    with pytest.raises(ValueError, match="workers must be an integer >= 1"):
        cr.run_sweep(cantilever, table, tmp_path / "a", workers=0)
    with pytest.raises(ValueError, match="workers sizes the LocalCluster only"):
        cr.run_sweep(cantilever, table, tmp_path / "a", workers=2, scheduler="tcp://127.0.0.1:1")
    with pytest.raises(TypeError, match="scene must be a function"):
        cr.run_sweep("cantilever", table, tmp_path / "a")
    with pytest.raises(ValueError, match="cannot be sent to the workers"):
        lock = __import__("threading").Lock()
        cr.run_sweep(lambda E, nu, tip_load: lock, table, tmp_path / "a")
    assert os.listdir(tmp_path) == []


def crashing_scene(E, nu, tip_load):
    """The cantilever, but E = 666 kills its worker process each time, as a crash in native code would."""
    if E == 666.0:
        os.kill(os.getpid(), 9)
    return cantilever(E, nu, tip_load)


def test_a_run_that_kills_every_worker_it_is_tried_on_is_recorded_as_failed(tmp_path):
    """With Dask's allowed-failures at 0, one death is enough: the task of runs 2 and 3 (two
    runs a task) dies, its runs are tried one by one, run 3 alone completes and run 2's death
    is recorded as its failure. (run_sweep's LocalCluster sends a worker one task at a time:
    no task waits on a worker behind another, to die with it.)"""
    import dask

    from corotate.sweep import local_cluster

    table = cr.ParameterTable({"E": [3e5, 4e5, 666.0, 5e5], "nu": [0.3] * 4, "tip_load": [1.0] * 4})
    with dask.config.set({"distributed.scheduler.allowed-failures": 0}):
        client, cluster = local_cluster(workers=2)
    with cluster, client:
        report = cr.run_sweep(
            crashing_scene, table, tmp_path / "out.zarr", scheduler=client, runs_per_task=2, progress=False
        )
    assert (report.done, report.failed, report.computed) == (3, 1, [0, 1, 2, 3])
    ds = cr.open_sweep(tmp_path / "out.zarr")
    assert list(ds.status.values) == ["done", "done", "failed", "done"]
    assert ds.error.values[2].startswith("the worker running it died each time it was tried")
    assert np.array_equal(ds.tip.values[3], cantilever(5e5, 0.3, 1.0)["tip"][1])
