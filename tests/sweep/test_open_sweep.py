"""open_sweep: outputs of every kind (scalars, frames, ints, runs of different lengths) over
all runs, NaN where a run has none, read lazily from the folder."""

import numpy as np
import pytest

pytest.importorskip("xarray", reason="open_sweep returns an xarray Dataset (the extra [sweep])")
pytest.importorskip("dask", reason="open_sweep reads lazily with dask (the extra [sweep])")

from corotate.sweep import ParameterTable, SweepStore, open_sweep
from corotate.sweep.outputs import scene_outputs

TABLE = ParameterTable({"frames": [3, 1, 2, 3]})


def test_runs_of_different_lengths_scalars_and_missing_runs(tmp_path):
    store = SweepStore(tmp_path / "out.zarr")
    store.create("f" * 64, "test:scene", TABLE)
    written = {}
    for run in (0, 1, 3):  # run 2 never finished
        frames = TABLE.row(run)["frames"]
        x = np.arange(frames * 2, dtype=np.float64).reshape(frames, 2) + 100 * run
        outputs = {"x": x, "peak": float(x.max()), "steps": np.int64(10 * run), "ok": True}
        written[run] = outputs
        store.write_run(run, TABLE.row(run), scene_outputs(outputs), "done", seconds=0.25)
    ds = open_sweep(store.path)
    assert list(ds.status.values) == ["done", "done", "missing", "done"]
    assert ds.x.dims == ("run", "frame", "x_dim1") and ds.x.shape == (4, 3, 2)
    assert ds.x.chunks is not None  # lazy until asked
    x = ds.x.values
    for run, outputs in written.items():
        frames = TABLE.row(run)["frames"]
        assert np.array_equal(x[run, :frames], outputs["x"]) and np.isnan(x[run, frames:]).all()
    assert np.isnan(x[2]).all()
    assert list(ds.peak.values[[0, 1, 3]]) == [written[r]["peak"] for r in (0, 1, 3)] and np.isnan(ds.peak.values[2])
    assert ds.steps.dtype == np.float64  # an int output with a missing run: NaN needs floats
    assert list(ds.seconds.values[[0, 3]]) == [0.25, 0.25] and np.isnan(ds.seconds.values[2])
    assert list(ds.frames.values) == [3, 1, 2, 3]
    assert ds.attrs["scene"] == "test:scene"


def test_whole_runs_keep_their_dtype_and_a_frame_slice_reads_only_its_chunks(tmp_path):
    table = ParameterTable({"k": [1, 2]})
    store = SweepStore(tmp_path / "out.zarr")
    store.create("f" * 64, "test:scene", table)
    for run in range(2):
        frames = np.arange(20 * 50000, dtype=np.int64).reshape(20, 50000) * (run + 1)  # 400 kB a frame: 2 a chunk
        store.write_run(run, table.row(run), scene_outputs({"big": frames, "flag": run == 1}), "done")
    ds = open_sweep(store.path)
    assert ds.big.dtype == np.int64 and ds.flag.dtype == bool and list(ds.flag.values) == [False, True]
    assert ds.big.data.chunks[1][:2] == (2, 2)
    # remove every chunk file but the one holding frame 15: reading that frame still works
    for run in range(2):
        for chunk in (store.run_path(run) / "big").glob("*.*"):
            if chunk.name not in ("7.0", ".zarray", ".zattrs"):
                chunk.unlink()
    assert np.array_equal(ds.big.isel(frame=15).values[1], np.arange(15 * 50000, 16 * 50000) * 2)


def test_a_folder_without_a_sweep_is_named(tmp_path):
    with pytest.raises(ValueError, match="holds no corotate sweep"):
        open_sweep(tmp_path)
