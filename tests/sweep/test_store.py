"""The output folder: a run appears whole or not at all, once, and a different sweep is refused."""

import json
import os

import numpy as np
import pytest

pytest.importorskip("zarr", reason="the sweep stores runs with zarr (the extra [sweep])")

from corotate.sweep import ParameterTable, SweepStore
from corotate.sweep.outputs import CHUNK_BYTES, frame_chunks, scene_outputs
from corotate.sweep.store import run_name
from corotate.sweep.zarr_v2 import open_array


def run_folders(store):
    return sorted(p.name for p in store.runs.iterdir() if p.is_dir())


TABLE = ParameterTable.grid(E=[1e6, 2e6], load=[1.0, 2.0])


def outputs(seed):
    rng = np.random.default_rng(seed)
    return scene_outputs({"tip": (("frame", "xyz"), rng.random((7, 3))), "peak": rng.random()})


@pytest.fixture
def store(tmp_path):
    store = SweepStore(tmp_path / "out.zarr")
    store.create("f" * 64, "scenes:beam", TABLE)
    return store


def test_a_run_is_written_whole_with_its_parameters(store):
    written = outputs(0)
    assert store.write_run(2, TABLE.row(2), written, "done", seconds=0.5)
    attrs = store.run_attrs(2)
    assert attrs["status"] == "done" and attrs["params"] == {"E": 2e6, "load": 1.0} and attrs["run"] == 2
    assert attrs["outputs"] == {
        "peak": {"dims": [], "shape": [], "chunks": [], "dtype": "<f8"},
        "tip": {"dims": ["frame", "xyz"], "shape": [7, 3], "chunks": [7, 3], "dtype": "<f8"},
    }
    assert np.array_equal(open_array(store.run_path(2) / "tip")[...], written["tip"][1])
    assert open_array(store.run_path(2) / "peak")[...] == written["peak"][1]
    assert store.finished() == {2: "done"}
    assert os.listdir(store.incoming) == []


def test_a_second_attempt_at_a_run_leaves_the_first_copy_alone(store):
    first, second = outputs(1), outputs(2)
    assert store.write_run(1, TABLE.row(1), first, "done")
    assert not store.write_run(1, TABLE.row(1), second, "done")  # lost the race: nothing written
    assert np.array_equal(open_array(store.run_path(1) / "tip")[...], first["tip"][1])
    assert run_folders(store) == [run_name(1)]
    assert os.listdir(store.incoming) == []


def test_what_a_dead_writer_leaves_is_found_and_removed(store):
    store.write_run(0, TABLE.row(0), outputs(0), "done")
    store.write_run(3, TABLE.row(3), {}, "failed", error="ValueError: nu")
    # a worker killed while writing run 1: its folder in .incoming/, never renamed
    (store.incoming / "r000001.host.123.abc").mkdir(parents=True)
    (store.incoming / "r000001.host.123.abc" / ".zgroup").write_text("{}")
    # run 2 copied into runs/ by hand, without its attributes (the completion marker)
    (store.runs / "r000002").mkdir()
    (store.runs / "r000002" / ".zgroup").write_text('{"zarr_format": 2}')
    assert store.finished() == {0: "done", 3: "failed"}
    assert sorted(store.remove_incomplete()) == ["r000001.host.123.abc", "r000002"]
    assert run_folders(store) == ["r000000", "r000003"]
    assert os.listdir(store.incoming) == []


def test_a_different_sweep_or_foreign_files_are_refused_before_anything_changes(store, tmp_path):
    store.check_compatible("f" * 64, "scenes:beam")  # the same sweep: fine
    before = sorted(os.listdir(store.path))
    with pytest.raises(ValueError, match=r"holds a different sweep \(scene scenes:beam, 4 runs of E, load"):
        store.check_compatible("e" * 64, "scenes:beam")
    assert sorted(os.listdir(store.path)) == before
    foreign = tmp_path / "photos"
    foreign.mkdir()
    (foreign / "cat.png").write_bytes(b"")
    with pytest.raises(ValueError, match="not empty and holds no corotate sweep"):
        SweepStore(foreign).check_compatible("f" * 64, "scenes:beam")
    SweepStore(tmp_path / "empty").check_compatible("f" * 64, "scenes:beam")  # absent: fine
    assert not (tmp_path / "empty").exists()
    root = json.loads((store.path / ".zattrs").read_text())["corotate_sweep"]
    assert root["table"] == {"E": [1e6, 1e6, 2e6, 2e6], "load": [1.0, 2.0, 1.0, 2.0]}
    assert store.table() == TABLE


def test_one_process_at_a_time(store):
    with store.locked():
        with pytest.raises(RuntimeError, match="another process is running a sweep into"):
            with SweepStore(store.path).locked():
                pass
    with store.locked():  # released
        pass


def test_frames_are_chunked_by_whole_frames_of_about_a_mebibyte():
    frame = np.zeros((1000, 3))  # 24 kB a frame: 43 frames a chunk
    assert frame_chunks(("frame", "node", "xyz"), np.zeros((100, 1000, 3))) == (CHUNK_BYTES // 24000, 1000, 3)
    assert frame_chunks(("frame", "node", "xyz"), np.zeros((5, 1000, 3))) == (5, 1000, 3)
    assert frame_chunks(("frame", "n"), np.zeros((3, 10**6))) == (1, 10**6)  # 8 MB a frame: one a chunk
    assert frame_chunks(("node", "xyz"), frame) == (1000, 3)
    assert frame_chunks((), np.float64(1.0)) == ()
    assert frame_chunks(("frame",), np.zeros(0)) == (1,)


@pytest.mark.parametrize(
    "returned, message",
    [
        ([1.0], "must return a mapping"),
        ({"_hidden": 1.0}, "identifiers not starting with '_'"),
        ({"name": "text"}, "must be numeric"),
        ({"x": (("frame",), np.zeros((2, 3)))}, "2 dimension names needed"),
        ({"x": (("run", "xyz"), np.zeros((2, 3)))}, "'run' is the sweep's own"),
    ],
)
def test_bad_scene_outputs_are_named(returned, message):
    with pytest.raises(ValueError, match=message):
        scene_outputs(returned)


def test_outputs_get_frame_first_dimension_names():
    named = scene_outputs({"positions": np.zeros((4, 5, 3)), "energy": 1.5, "time": ("frame", np.arange(4.0))})
    assert named["positions"][0] == ("frame", "positions_dim1", "positions_dim2")
    assert named["energy"][0] == () and named["time"][0] == ("frame",)


def test_a_run_opens_alone_in_xarray_with_its_dimension_names(store):
    xr = pytest.importorskip("xarray", reason="the extra [sweep]")
    frames = np.arange(100 * 2 * 3, dtype=np.float64).reshape(100, 2, 3)
    many = np.random.default_rng(5).random((100, 1000, 3))  # 43 frames a chunk: 3 chunks, the last padded
    store.write_run(0, TABLE.row(0), scene_outputs({"p": (("frame", "node", "xyz"), many), "f": frames}), "done")
    run = xr.open_zarr(store.run_path(0), consolidated=False)
    assert run.p.dims == ("frame", "node", "xyz") and run.f.dims == ("frame", "f_dim1", "f_dim2")
    assert run.p.encoding["chunks"] == (43, 1000, 3)
    assert np.array_equal(run.p.values, many) and np.array_equal(run.f.values, frames)
    assert run.attrs["params"] == {"E": 1e6, "load": 1.0}
