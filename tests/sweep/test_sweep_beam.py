"""A 1,000-run sweep of the cantilever on a LocalCluster of 2 workers: every run stored once,
equal to the last bit to the same run done alone in this process, opened as one labelled
xarray Dataset."""

import numpy as np
import pytest

pytest.importorskip("distributed", reason="sweeps run on dask.distributed (the extra [sweep])")
pytest.importorskip("xarray", reason="open_sweep returns an xarray Dataset (the extra [sweep])")

import corotate as cr
from corotate.sweep.scenes import cantilever

TABLE = cr.ParameterTable.grid(
    E=np.linspace(2e5, 1e6, 10), nu=np.linspace(0.0, 0.45, 10), tip_load=np.linspace(-20.0, 20.0, 10)
)


def test_a_thousand_runs_on_two_workers_equal_each_run_done_alone(tmp_path, client):
    out = tmp_path / "beam.zarr"
    report = cr.run_sweep(cantilever, TABLE, out, workers=2, progress=False)  # its own LocalCluster
    assert (report.total, report.done, report.failed, report.missing, report.found) == (1000, 1000, 0, 0, 0)
    assert report.computed == list(range(1000)) and report.removed == []
    assert sorted(p.name for p in (out / "runs").iterdir() if p.is_dir()) == [f"r{i:06d}" for i in range(1000)]
    assert list((out / ".incoming").iterdir()) == []

    ds = cr.open_sweep(out)
    assert dict(ds.sizes) == {"run": 1000, "frame": 5, "xyz": 3, "node": 20}
    assert (ds.status == "done").all() and (ds.error == "").all()
    assert np.array_equal(ds.E.values, TABLE.columns["E"]) and np.array_equal(
        ds.tip_load.values, TABLE.columns["tip_load"]
    )
    positions, tip, time = ds.positions.values, ds.tip.values, ds.time.values
    for run in range(1000):
        alone = cantilever(**TABLE.row(run))
        assert np.array_equal(positions[run], alone["positions"][1]), run
        assert np.array_equal(tip[run], alone["tip"][1]), run
        assert np.array_equal(time[run], alone["time"]), run
    # the physics is there: a load up lifts the tip, a load down lowers it, none leaves it at rest
    final_z = ds.tip.isel(frame=-1, xyz=2).values
    load = ds.tip_load.values
    assert np.all(final_z[load > 0] > 0) and np.all(final_z[load < 0] < 0)
    # the grid unfolds into one dimension per parameter
    grid = ds.set_index(run=["E", "nu", "tip_load"]).unstack("run")
    assert dict(grid.tip.sizes) == {"E": 10, "nu": 10, "tip_load": 10, "frame": 5, "xyz": 3}
    assert float(grid.tip.isel(E=3, nu=4, tip_load=5, frame=2, xyz=2)) == tip[3 * 100 + 4 * 10 + 5, 2, 2]

    # started again: everything is found, nothing computed
    again = cr.run_sweep(cantilever, TABLE, out, scheduler=client, progress=False)
    assert (again.found, again.computed, again.done) == (1000, [], 1000)
