"""Running a helper script of this package in a child process with a time limit, for work
that can crash or hang inside third-party code (fTetWild; meshio readers that loop forever
on a corrupt file): the caller's process survives and gets an exception naming what happened."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
from pathlib import Path

PACKAGE_PARENT = str(Path(__file__).resolve().parent.parent)


class ChildFailed(Exception):
    """The child crashed, exited with an error or ran past its time limit; the message says
    which (the caller turns it into its own RuntimeError or ValueError)."""


def run_script(script: Path, args: list[str], time_limit: float, cwd: str | None = None) -> None:
    """python script *args in a child process (which can import corotate) in cwd; returns
    when it exits with status 0, else raises ChildFailed."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in (PACKAGE_PARENT, os.environ.get("PYTHONPATH")) if p)}
    try:
        done = subprocess.run(
            [sys.executable, str(script), *args], cwd=cwd, env=env, capture_output=True, timeout=time_limit, check=False
        )
    except subprocess.TimeoutExpired:
        raise ChildFailed(f"it did not finish within {time_limit:g} s and was stopped") from None
    if done.returncode != 0:
        raise ChildFailed(f"{_exit_reason(done.returncode)}{_last_lines(done.stderr)}")


def _exit_reason(code: int) -> str:
    if code < 0:
        try:
            name = signal.Signals(-code).name
        except ValueError:
            name = f"signal {-code}"
        return f"its process was killed by {name} (a crash)"
    return f"its process exited with status {code}"


def _last_lines(stderr: bytes, n: int = 5) -> str:
    lines = stderr.decode("utf-8", errors="replace").strip().splitlines()[-n:]
    return (":\n" + "\n".join(lines)) if lines else ""
