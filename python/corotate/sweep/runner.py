"""Running a sweep on a Dask cluster: every run of the table not yet in the output folder, in
tasks of a few runs, each run written by its worker straight into the folder the moment it
is finished (store.py says how, so that nothing is lost and nothing is there twice)."""

from __future__ import annotations

import contextlib
import functools
import os
import signal
import sys
import threading
import time
import uuid
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

from .cluster import close, connect
from .identity import scene_name, sweep_fingerprint
from .outputs import scene_outputs
from .progress import ProgressBar
from .store import SweepStore
from .table import ParameterTable


@dataclass
class SweepReport:
    """What one call of run_sweep did.

    path      the output folder
    total     runs in the table
    done      runs finished successfully in the folder now
    failed    runs recorded as failed in the folder now (error messages: open_sweep(path).error)
    found     finished runs found at the start, not computed again
    computed  indices of the runs this call computed
    removed   half-written runs (of workers that died) found at the start, removed and redone
    seconds   wall time of the call
    """

    path: Path
    total: int
    done: int
    failed: int
    found: int
    computed: list[int] = field(default_factory=list)
    removed: list[str] = field(default_factory=list)
    seconds: float = 0.0

    @property
    def missing(self) -> int:
        """Runs neither done nor failed (0 after a complete sweep)."""
        return self.total - self.done - self.failed


def run_sweep(
    scene: Callable[..., Any],
    table: Any,
    out: str | os.PathLike[str],
    *,
    scheduler: Any = None,
    workers: int | None = None,
    threads_per_run: int = 1,
    retry_failed: bool = False,
    runs_per_task: int | None = None,
    progress: bool = True,
    connect_timeout: float = 10.0,
) -> SweepReport:
    """Run ``scene(**row)`` for every row of the table on a Dask cluster, into the Zarr folder ``out``.

    scene            a function of the parameters (keyword arguments named as the table's
                     columns) that builds a body and a simulation, steps it and returns a
                     mapping name -> number, (frames, ...) array or (dims, array) (see
                     corotate.sweep.outputs). What it raises (a ValueError for an impossible
                     material, a RuntimeError for a step that diverges, ...) is recorded as
                     that run's failure, with its message; the other runs go on.
    table            a ParameterTable, a mapping name -> values, or a list of runs
    out              the output folder: created if absent; if it holds this same sweep
                     (same scene name and source, same table), the runs already finished
                     there are kept and only the others computed
    scheduler        None: a dask.distributed LocalCluster on this machine (its workers are
                     processes, so a script must start the sweep under
                     ``if __name__ == "__main__":``); a scheduler address
                     ("tcp://host:8786"); a dask Cluster object (e.g. dask-jobqueue's
                     SLURMCluster); or a distributed.Client
    workers          LocalCluster only: worker processes (default: cores // threads_per_run)
    threads_per_run  corotate.set_threads() in each worker while it steps a scene (default 1:
                     a worker per core is the faster way to use the cores for many runs)
    retry_failed     compute runs recorded as failed again (default: keep them)
    runs_per_task    runs a Dask task computes one after the other (default: up to 16, fewer
                     when there are few runs per worker); Dask costs a few ms per task, which
                     matters for runs of milliseconds; for runs of minutes, 1 balances best.
                     Every run is still written on its own the moment it is finished
    progress         draw a progress bar on stderr
    connect_timeout  seconds to wait for a scheduler address to answer
    returns          SweepReport

    Raises, before any run starts and without creating or changing the folder: ValueError for
    a bad table (missing, NaN or infinite entries), a folder holding a different sweep or other
    files, a scene that cannot be sent to the workers; RuntimeError for a scheduler that does
    not answer, or another process running a sweep into the same folder.

    Ctrl-C (KeyboardInterrupt) cancels the runs not yet finished, shuts a LocalCluster down and
    is raised again; the next call with the same arguments resumes. A run whose worker dies is
    run again on another worker by Dask; a run that kills every worker it is tried on (three by
    default: Dask's distributed.scheduler.allowed-failures) is recorded as failed.
    """
    started = time.monotonic()
    table = ParameterTable.coerce(table)
    if not callable(scene):
        raise TypeError(f"scene must be a function of the parameters, got {type(scene).__name__}")
    _check_count(threads_per_run, "threads_per_run")
    if workers is not None:
        _check_count(workers, "workers")
    if runs_per_task is not None:
        _check_count(runs_per_task, "runs_per_task")
    if workers is not None and scheduler is not None:
        raise ValueError("workers sizes the LocalCluster only; an existing scheduler has the workers it has")
    blob = _pickled(scene)
    fingerprint, name = sweep_fingerprint(scene, table), scene_name(scene)
    store = SweepStore(out)
    store.check_compatible(fingerprint, name)
    own_client, cluster = connect(scheduler, workers, threads_per_run, connect_timeout)
    client = own_client or scheduler
    try:
        with store.locked():
            store.check_compatible(fingerprint, name)  # again: another process may have begun meanwhile
            store.create(fingerprint, name, table)
            removed = store.remove_incomplete()
            finished = store.finished()
            if retry_failed:
                for run in [run for run, status in finished.items() if status == "failed"]:
                    store.discard(run)
                    del finished[run]
            todo = [run for run in range(len(table)) if run not in finished]
            statuses = list(finished.values())
            bar = ProgressBar(
                len(table),
                statuses.count("done"),
                statuses.count("failed"),
                stream=sys.stderr if progress else None,
            )
            _run_all(client, store, table, todo, blob, threads_per_run, runs_per_task, bar)
            store.remove_incomplete()  # copies of tasks that lost the race to write
    except KeyboardInterrupt:
        if cluster is not None:  # our workers die mid-run: no log lines from them about it
            from .worker_plugin import mute_logs

            with contextlib.suppress(Exception):  # only cosmetic: never in the way of stopping
                own_client.run(mute_logs)
        raise
    finally:
        close(own_client, cluster)
    now = store.finished()
    statuses = list(now.values())
    return SweepReport(
        path=store.path,
        total=len(table),
        done=statuses.count("done"),
        failed=statuses.count("failed"),
        found=len(finished),
        # what this call's tasks wrote, whichever attempt of a task it was
        computed=[run for run in todo if run in now],
        removed=removed,
        seconds=time.monotonic() - started,
    )


@contextlib.contextmanager
def _ctrl_c_remembered() -> Any:
    """Within it, Ctrl-C (SIGINT) raises KeyboardInterrupt as usual and is also remembered (the
    event it yields is set), so that one that code between the sweep's own lines swallowed is
    raised again at the next finished task: the interrupted command of the tests once ran the
    whole sweep to its end. Only in the main thread where SIGINT has Python's default handler;
    elsewhere nothing changes."""
    pressed = threading.Event()
    if threading.current_thread() is not threading.main_thread() or (
        signal.getsignal(signal.SIGINT) is not signal.default_int_handler
    ):
        yield pressed
        return

    def handler(signum: int, frame: Any) -> None:
        pressed.set()
        raise KeyboardInterrupt

    signal.signal(signal.SIGINT, handler)
    try:
        yield pressed
    finally:
        signal.signal(signal.SIGINT, signal.default_int_handler)


def _run_all(
    client: Any,
    store: SweepStore,
    table: ParameterTable,
    todo: list[int],
    blob: bytes,
    threads: int,
    runs_per_task: int | None,
    bar: ProgressBar,
) -> None:
    """Submit the runs of todo in tasks of a few runs each and wait for all. Ctrl-C cancels
    what is left."""
    from distributed import as_completed

    try:
        from distributed import KilledWorker
    except ImportError:  # distributed before 2022.9
        from distributed.scheduler import KilledWorker

    token = uuid.uuid4().hex[:8]
    batch_of: dict[str, list[int]] = {}

    def submit(batches: list[list[int]]) -> list[Any]:
        keys = [f"corotate-sweep-r{batch[0]}-{len(batch)}-{token}" for batch in batches]
        batch_of.update(zip(keys, batches))
        rows = [[table.row(run) for run in batch] for batch in batches]
        n = len(batches)
        return client.map(
            run_task, [str(store.path)] * n, batches, rows, [blob] * n, [threads] * n, key=keys, pure=False
        )

    size = runs_per_task or _auto_runs_per_task(len(todo), client)
    futures = submit([todo[i : i + size] for i in range(0, len(todo), size)])
    pending = as_completed(futures, loop=client.loop)
    with _ctrl_c_remembered() as pressed:
        try:
            for future in pending:
                if pressed.is_set():
                    raise KeyboardInterrupt
                batch = batch_of.pop(future.key)
                try:
                    outcomes = future.result()
                except KilledWorker as err:
                    if len(batch) > 1:  # one of its runs kills workers: try each unfinished one alone
                        alone = [[run] for run in batch if store.status(run) is None]
                        outcomes = [(run, store.status(run), True) for run in batch if [run] not in alone]
                        for retry in submit(alone):
                            futures.append(retry)
                            pending.add(retry)
                    else:  # this run killed each worker it was tried on: a crash in it, not bad luck
                        message = f"the worker running it died each time it was tried (a crash in the scene?): {err}"
                        wrote = store.write_run(batch[0], table.row(batch[0]), {}, "failed", error=message)
                        outcomes = [(batch[0], "failed", wrote)]
                except Exception as err:  # not the scene's own errors: those are recorded as failures
                    raise RuntimeError(
                        f"runs {batch} could not be computed and written to {store.path}: {err}"
                    ) from err
                future.release()
                for _run, status, wrote in outcomes:
                    bar.update(status, computed=wrote)
        except KeyboardInterrupt:
            client.cancel(futures)
            bar.close(
                f"sweep interrupted: {bar.finished} of {bar.total} runs finished and kept in {store.path}; "
                "run it again to compute the rest"
            )
            raise
        except BaseException:
            client.cancel(futures)
            bar.close()
            raise
        if pressed.is_set():  # pressed as the last task finished
            bar.close("sweep interrupted: all runs finished and kept; nothing is left to compute")
            raise KeyboardInterrupt
    bar.close()


def _auto_runs_per_task(n_runs: int, client: Any) -> int:
    """Runs per task: enough that Dask's own cost per task (a few ms) does not add up over
    thousands of small runs, few enough that every worker gets at least ~16 tasks to share
    at the end; never more than 16."""
    workers = max(1, len(client.scheduler_info().get("workers", {})))
    return max(1, min(16, n_runs // (16 * workers)))


def run_task(
    path: str, runs: list[int], rows: list[dict[str, Any]], blob: bytes, threads: int
) -> list[tuple[int, str, bool]]:
    """Some runs, on a worker: compute each scene and write it. Returns (run, status, written)
    for each; a run already in the folder (written by an earlier attempt of a retried task) is
    not computed again."""
    from .. import set_threads

    store = SweepStore(path)
    set_threads(threads)
    scene = _unpickled(blob)
    outcomes = []
    for run, params in zip(runs, rows):
        status = store.status(run)
        if status is not None:
            outcomes.append((run, status, False))
            continue
        status, wrote = _run_one(store, scene, run, params)
        outcomes.append((run, status, wrote))
    return outcomes


def _run_one(store: SweepStore, scene: Callable[..., Any], run: int, params: dict[str, Any]) -> tuple[str, bool]:
    """Compute one run and write it: (status, whether this call wrote it)."""
    start = time.perf_counter()
    outputs: dict[str, Any] = {}
    error = None
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            outputs = scene_outputs(scene(**params))
        except Exception as err:  # the run's failure, recorded; Ctrl-C and SystemExit are not caught
            error = f"{type(err).__name__}: {err}"
    status = "done" if error is None else "failed"
    messages = sorted({f"{w.category.__name__}: {w.message}" for w in caught})
    seconds = time.perf_counter() - start
    wrote = store.write_run(run, params, outputs, status, error=error, warnings=messages, seconds=seconds)
    return (status if wrote else (store.status(run) or status)), wrote


def _check_count(value: object, name: str) -> None:
    if isinstance(value, bool) or not isinstance(value, int) or value < 1:
        raise ValueError(f"{name} must be an integer >= 1, got {value!r}")


def _pickled(scene: Callable[..., Any]) -> bytes:
    import cloudpickle

    try:
        return bytes(cloudpickle.dumps(scene))
    except Exception as err:
        raise ValueError(f"the scene function cannot be sent to the workers (pickling it failed): {err}") from err


@functools.lru_cache(maxsize=8)
def _unpickled(blob: bytes) -> Callable[..., Any]:
    """The scene of a blob, unpickled once per worker process."""
    import cloudpickle

    scene: Callable[..., Any] = cloudpickle.loads(blob)
    return scene
