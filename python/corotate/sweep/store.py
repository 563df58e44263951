"""The output folder of a sweep: a Zarr store with one group per run, written so that nothing
is lost and nothing is there twice.

Layout (Zarr format 2, readable by zarr 2 and 3 and xarray; written by zarr_v2.py)::

    OUT/                   root group; attribute "corotate_sweep": the fingerprint, the scene's
                           name, the parameter names and the whole table
    OUT/runs/r000042/      run 42: attributes "run", "params", "status" ("done" or "failed"),
                           "error", "warnings", "seconds", "outputs" (name -> dims, shape,
                           chunks, dtype); one array per scene output
    OUT/.incoming/         runs being written (removed when the sweep starts and ends)
    OUT/.lock              held by the process running the sweep

A run is written into a fresh folder of .incoming/ under a unique name, its attributes with
the status (the completion marker) last, and then renamed into runs/ in one step. A rename onto an
existing run fails, so a task that ran twice (its worker presumed dead, then not) leaves one
copy; a worker killed while writing leaves only a folder in .incoming/, which the next start
removes and recomputes. A folder in runs/ without the marker (copied in half by hand, say) is
treated the same way."""

from __future__ import annotations

import errno
import fcntl
import json
import os
import shutil
import socket
import uuid
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np

from . import zarr_v2
from .outputs import frame_chunks
from .table import ParameterTable

FORMAT = 1
STATUSES = ("done", "failed")
_ROOT_KEY = "corotate_sweep"


def run_name(run: int) -> str:
    """The group name of run ``run`` under runs/ (r000042; more digits past a million runs)."""
    return f"r{run:06d}"


def _read_attrs(folder: Path) -> dict[str, Any]:
    """The attributes of the Zarr (format 2) group at folder ({} if it has none yet)."""
    try:
        with open(folder / ".zattrs") as f:
            attrs = json.load(f)
    except (OSError, ValueError):
        return {}
    return attrs if isinstance(attrs, dict) else {}


class SweepStore:
    """The output folder of one sweep (see the module's docstring for the layout)."""

    def __init__(self, path: str | os.PathLike[str]) -> None:
        self.path = Path(path).absolute()  # the workers may start elsewhere (a cluster node)
        self.runs = self.path / "runs"
        self.incoming = self.path / ".incoming"

    # --- the sweep as a whole ---------------------------------------------------------------
    def description(self) -> dict[str, Any] | None:
        """The root's "corotate_sweep" attribute, or None where the folder holds no sweep."""
        description = _read_attrs(self.path).get(_ROOT_KEY)
        return description if isinstance(description, dict) else None

    def check_compatible(self, fingerprint: str, scene: str) -> None:
        """Raise ValueError unless the folder is absent, empty, or holds this very sweep.
        Reads only: nothing is created or changed."""
        if not self.path.exists():
            return
        if not self.path.is_dir():
            raise ValueError(f"the sweep output {self.path} is a file, not a folder")
        description = self.description()
        if description is None:
            if any(entry.name not in (".lock", ".incoming") for entry in self.path.iterdir()):
                raise ValueError(
                    f"the sweep output folder {self.path} is not empty and holds no corotate sweep: "
                    "choose a new or empty folder"
                )
            return
        if description.get("format") != FORMAT:
            raise ValueError(f"{self.path} holds a sweep of format {description.get('format')}, expected {FORMAT}")
        if description.get("fingerprint") != fingerprint:
            raise ValueError(
                f"the output folder {self.path} holds a different sweep (scene {description.get('scene')}, "
                f"{description.get('n_runs')} runs of {', '.join(description.get('parameters', []))}; "
                f"fingerprint {str(description.get('fingerprint'))[:12]}, this sweep's {fingerprint[:12]}: "
                f"scene {scene}): its scene function or parameter table differ. Choose another folder, "
                "or delete this one to start afresh"
            )

    def create(self, fingerprint: str, scene: str, table: ParameterTable) -> None:
        """Write the root group and runs/ if the folder holds no sweep yet."""
        self.path.mkdir(parents=True, exist_ok=True)
        if self.description() is None:
            description = {
                "format": FORMAT,
                "fingerprint": fingerprint,
                "scene": scene,
                "n_runs": len(table),
                "parameters": table.names,
                "table": table.to_json(),
            }
            zarr_v2.new_group(self.path, {_ROOT_KEY: description})
        if not self.runs.exists():
            zarr_v2.new_group(self.runs, {})

    def table(self) -> ParameterTable:
        """The parameter table the folder was created with."""
        description = self.description()
        if description is None:
            raise ValueError(f"{self.path} holds no corotate sweep (no '{_ROOT_KEY}' attribute on its root group)")
        return ParameterTable(description["table"])

    @contextmanager
    def locked(self) -> Iterator[None]:
        """Hold OUT/.lock while the block runs: RuntimeError if another process runs a sweep into
        this folder (the lock goes with its process, so a killed sweep leaves none behind)."""
        self.path.mkdir(parents=True, exist_ok=True)
        with open(self.path / ".lock", "a") as lock:
            try:
                fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError as err:
                raise RuntimeError(
                    f"another process is running a sweep into {self.path} (it holds {lock.name})"
                ) from err
            try:
                yield
            finally:
                fcntl.flock(lock, fcntl.LOCK_UN)

    # --- runs ---------------------------------------------------------------------------
    def run_path(self, run: int) -> Path:
        return self.runs / run_name(run)

    def run_attrs(self, run: int) -> dict[str, Any]:
        return _read_attrs(self.run_path(run))

    def status(self, run: int) -> str | None:
        """ "done" or "failed" for a finished run, None for one not (completely) written."""
        status = self.run_attrs(run).get("status")
        return status if status in STATUSES else None

    def finished(self) -> dict[int, str]:
        """run -> status of every completely written run."""
        if not self.runs.is_dir():
            return {}
        found = {}
        for entry in os.scandir(self.runs):
            if entry.is_dir() and entry.name.startswith("r") and entry.name[1:].isdigit():
                status = self.status(int(entry.name[1:]))
                if status is not None:
                    found[int(entry.name[1:])] = status
        return found

    def remove_incomplete(self) -> list[str]:
        """Delete what dead workers left: everything in .incoming/ and folders in runs/
        without the completion marker. Returns their names. Call it only while no task of
        this sweep runs (at the start and the end of a sweep)."""
        removed = []
        if self.incoming.is_dir():
            for entry in os.scandir(self.incoming):
                _remove(Path(entry.path))
                removed.append(entry.name)
        if self.runs.is_dir():
            for entry in os.scandir(self.runs):
                if entry.is_dir() and entry.name.startswith("r") and self.status(int(entry.name[1:])) is None:
                    _remove(Path(entry.path))
                    removed.append(entry.name)
        return removed

    def discard(self, run: int) -> None:
        """Remove a finished run (to compute it again): renamed away first, so a reader never
        sees it half-deleted."""
        target = self.incoming / f"{run_name(run)}.discarded.{uuid.uuid4().hex}"
        self.incoming.mkdir(exist_ok=True)
        os.rename(self.run_path(run), target)
        _remove(target)

    def write_run(
        self,
        run: int,
        params: dict[str, Any],
        outputs: dict[str, tuple[tuple[str, ...], np.ndarray]],
        status: str,
        error: str | None = None,
        warnings: list[str] | None = None,
        seconds: float = 0.0,
    ) -> bool:
        """Write run ``run`` atomically. Returns False (and writes nothing) when the run is
        already there: another attempt of the same task finished first."""
        if status not in STATUSES:
            raise ValueError(f"status must be one of {STATUSES}, got {status!r}")
        self.incoming.mkdir(exist_ok=True)
        temporary = self.incoming / f"{run_name(run)}.{socket.gethostname()}.{os.getpid()}.{uuid.uuid4().hex}"
        try:
            zarr_v2.new_group(temporary)
            described: dict[str, dict[str, Any]] = {}
            for name, (dims, data) in outputs.items():
                chunks = frame_chunks(dims, data)
                zarr_v2.write_array(temporary, name, data, chunks, dims)
                # the arrays described once more here: open_sweep reads one file per run
                described[name] = {"dims": list(dims), "shape": list(data.shape), "chunks": list(chunks)}
                described[name]["dtype"] = data.dtype.str
            zarr_v2.set_attrs(
                temporary,
                {
                    "run": int(run),
                    "params": params,
                    "outputs": described,
                    "error": error,
                    "warnings": list(warnings or []),
                    "seconds": float(seconds),
                    "status": status,  # the completion marker: in the last file written
                },
            )
            try:
                os.rename(temporary, self.run_path(run))
            except OSError as err:
                if err.errno in (errno.EEXIST, errno.ENOTEMPTY) and self.status(run) is not None:
                    return False
                raise
            return True
        finally:
            if temporary.exists():
                _remove(temporary)


def _remove(path: Path) -> None:
    shutil.rmtree(path, ignore_errors=True)
