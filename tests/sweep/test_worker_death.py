"""Nothing lost, nothing twice: workers killed with SIGKILL in the middle of a sweep, a sweep
stopped by Ctrl-C and started again, runs half-written by a dead worker."""

import collections
import os
import signal
import subprocess
import sys
import textwrap
import threading
import time
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("distributed", reason="sweeps run on dask.distributed (the extra [sweep])")
pytest.importorskip("xarray", reason="open_sweep returns an xarray Dataset (the extra [sweep])")

import corotate as cr
from corotate.sweep import SweepStore, load_spec
from corotate.sweep.scenes import cantilever

TABLE = cr.ParameterTable.grid(E=np.linspace(2e5, 1e6, 6), nu=[0.1, 0.3, 0.4], tip_load=np.linspace(-10.0, 10.0, 20))
VICTIM = 100  # the run whose worker kills itself, the first time it is tried


def killing_scene(marker, calls):
    """The cantilever, except that the first attempt at run VICTIM SIGKILLs its own worker
    half-way: after stepping, before returning. Each call leaves a file in calls."""
    victim = TABLE.row(VICTIM)

    def scene(E, nu, tip_load):
        open(os.path.join(calls, f"{E!r}_{nu!r}_{tip_load!r}_{os.urandom(6).hex()}"), "w").close()
        result = cantilever(E, nu, tip_load)
        if (E, nu, tip_load) == tuple(victim.values()) and not os.path.exists(marker):
            open(marker, "w").close()
            os.kill(os.getpid(), signal.SIGKILL)
        return result

    return scene


def assert_equal_to_runs_alone(out, runs):
    ds = cr.open_sweep(out)
    assert (ds.status == "done").all()
    tip, positions = ds.tip.values, ds.positions.values
    for run in runs:
        alone = cantilever(**TABLE.row(run))
        assert np.array_equal(tip[run], alone["tip"][1]) and np.array_equal(positions[run], alone["positions"][1])


def run_folders(out):
    return sorted(p.name for p in (out / "runs").iterdir() if p.is_dir())


def test_workers_killed_mid_sweep_lose_nothing_and_repeat_nothing(tmp_path, client):
    """One worker kills itself inside run VICTIM; the other is SIGKILLed from here after that,
    once 150 runs are stored, in whatever run it is in. Dask runs their tasks again on the restarted
    workers; every run is stored exactly once and equals the run done alone."""
    out = tmp_path / "killed.zarr"
    marker = tmp_path / "victim-killed"
    calls = tmp_path / "calls"
    calls.mkdir()
    pids_before = set(client.run(os.getpid).values())
    killed = []

    def kill_the_other_worker_later():
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline:
            if marker.exists() and len(os.listdir(out / "runs")) > 150:
                try:
                    alive = [pid for pid in client.run(os.getpid).values() if pid in pids_before]
                except Exception:  # a worker between death and restart: ask again
                    continue
                if alive:
                    os.kill(alive[0], signal.SIGKILL)
                    killed.append(alive[0])
                return
            time.sleep(0.01)

    killer = threading.Thread(target=kill_the_other_worker_later)
    killer.start()
    report = cr.run_sweep(killing_scene(str(marker), str(calls)), TABLE, out, scheduler=client, progress=False)
    killer.join()
    assert marker.exists() and len(killed) == 1  # both deaths happened
    assert not set(client.run(os.getpid).values()) & pids_before  # both workers are new processes
    assert (report.done, report.failed, report.missing) == (360, 0, 0)
    assert report.computed == list(range(360))
    assert run_folders(out) == [f"r{i:06d}" for i in range(360)]
    assert list((out / ".incoming").iterdir()) == []
    assert_equal_to_runs_alone(out, range(360))
    # each run computed once, but for the two in the hands of the killed workers
    per_run = collections.Counter(name.rsplit("_", 1)[0] for name in os.listdir(calls))
    assert len(per_run) == 360 and sum(per_run.values()) <= 362
    twice = [key for key, count in per_run.items() if count > 1]
    victim = TABLE.row(VICTIM)
    assert max(per_run.values()) == 2 and f"{victim['E']!r}_{victim['nu']!r}_{victim['tip_load']!r}" in twice


def test_ctrl_c_stops_the_command_and_the_restart_computes_only_what_is_missing(tmp_path, client):
    """`corotate sweep SPEC` in its own process group, sent SIGINT (what Ctrl-C at a terminal
    sends) once 60 runs are stored: it stops with status 130 and keeps them. Started again, it
    computes exactly the runs that were missing, counted by the scene's own log of its calls."""
    log = tmp_path / "calls"
    log.mkdir()
    spec = tmp_path / "spec.py"
    spec.write_text(
        textwrap.dedent(
            f"""
            import os
            import numpy as np
            import corotate as cr
            from corotate.sweep.scenes import cantilever

            table = cr.ParameterTable.grid(
                E=np.linspace(2e5, 1e6, 6), nu=[0.1, 0.3, 0.4], tip_load=np.linspace(-10.0, 10.0, 20)
            )
            out = "interrupted.zarr"

            def scene(E, nu, tip_load):
                result = cantilever(E, nu, tip_load)
                # one file per call: the test counts the calls
                name = f"{{E!r}}-{{nu!r}}-{{tip_load!r}}-{{os.getpid()}}-{{os.urandom(4).hex()}}"
                open(os.path.join({str(log)!r}, name), "w").close()
                return result
            """
        )
    )
    out = tmp_path / "interrupted.zarr"
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    command = subprocess.Popen(
        [sys.executable, "-m", "corotate", "sweep", str(spec), "--workers", "2"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=env,
        start_new_session=True,
        # Ctrl-C's default in the child even when this test runs in a process that ignores it
        # (a shell's background job does, and its children inherit that).
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    deadline = time.monotonic() + 120
    while not ((out / "runs").is_dir() and len(os.listdir(out / "runs")) > 60):
        assert command.poll() is None and time.monotonic() < deadline, command.communicate()
        time.sleep(0.01)
    os.killpg(command.pid, signal.SIGINT)
    _, stderr = command.communicate(timeout=60)
    assert command.returncode == 130, stderr
    assert "sweep interrupted:" in stderr and "run it again to compute the rest" in stderr

    store = SweepStore(out)
    kept = set(store.finished())
    assert 60 < len(kept) < 360
    calls_before = len(os.listdir(log))
    loaded = load_spec(spec)
    report = cr.run_sweep(loaded.scene, loaded.table, loaded.out, scheduler=client, progress=False)
    assert report.found == len(kept)
    assert report.computed == sorted(set(range(360)) - kept)
    assert len(os.listdir(log)) - calls_before == 360 - len(kept)  # the scene ran once per missing run
    assert (report.done, report.missing) == (360, 0)
    assert run_folders(out) == [f"r{i:06d}" for i in range(360)]
    assert_equal_to_runs_alone(out, range(360))


def test_runs_half_written_by_a_dead_worker_are_redone(tmp_path, client):
    out = tmp_path / "half.zarr"
    table = cr.ParameterTable.grid(E=[3e5, 6e5], nu=[0.3], tip_load=[-5.0, 5.0])
    first = cr.run_sweep(cantilever, table, out, scheduler=client, progress=False)
    assert first.computed == [0, 1, 2, 3]
    store = SweepStore(out)
    # what a worker killed while writing run 2 leaves: its folder in .incoming/ (run 2 itself
    # is gone), and a copy of run 3 in runs/ lacking its attributes (the completion marker)
    os.rename(store.run_path(2), store.incoming / "r000002.node7.4242.0123abcd")
    (store.run_path(3) / ".zattrs").unlink()
    again = cr.run_sweep(cantilever, table, out, scheduler=client, progress=False)
    assert sorted(again.removed) == ["r000002.node7.4242.0123abcd", "r000003"]
    assert (again.found, again.computed, again.done) == (2, [2, 3], 4)
    assert list(store.incoming.iterdir()) == []
    ds = cr.open_sweep(out)
    for run in range(4):
        assert np.array_equal(ds.positions.values[run], cantilever(**table.row(run))["positions"][1])
    assert Path(out / "runs" / "r000003" / ".zattrs").exists()


def test_a_ctrl_c_that_code_swallowed_is_still_remembered():
    """Within a sweep's wait, Ctrl-C raises KeyboardInterrupt and sets the event the loop
    checks at every finished task, so one that library code caught still stops the sweep;
    Python's own handler is back afterwards."""
    from corotate.sweep.runner import _ctrl_c_remembered

    # Python's own handler first, as in a terminal (a shell's background job ignores Ctrl-C).
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        swallowed_ctrl_c_is_remembered(_ctrl_c_remembered)
    finally:
        signal.signal(signal.SIGINT, previous)


def swallowed_ctrl_c_is_remembered(_ctrl_c_remembered):
    with _ctrl_c_remembered() as pressed:
        try:
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(1.0)  # the handler runs here
        except KeyboardInterrupt:
            pass  # swallowed, as by the code between the sweep's lines
        assert pressed.is_set()
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
