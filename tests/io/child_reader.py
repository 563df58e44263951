"""The file reads of the I/O tests, each in a child process with a time limit: a reader that
crashes or hangs on a file fails the test instead of taking pytest down with it."""

from __future__ import annotations

import json
import os
import select
import subprocess
import sys
from pathlib import Path

import corotate as cr

TIME_LIMIT = 20.0  # s per file: reads take milliseconds; a hang is a hang
WORKER = Path(__file__).with_name("read_worker.py")


class Reader:
    """The worker process (a script answering one JSON line per request); restarted after a
    crash or a hang."""

    def __init__(self, worker: Path = WORKER, time_limit: float = TIME_LIMIT) -> None:
        self.worker, self.time_limit = worker, time_limit
        self.process: subprocess.Popen | None = None

    def start(self) -> None:
        package_parent = str(Path(cr.__file__).resolve().parent.parent)
        env = {**os.environ, "PYTHONPATH": os.pathsep.join([package_parent, os.environ.get("PYTHONPATH", "")])}
        self.process = subprocess.Popen(
            [sys.executable, str(self.worker)], stdin=subprocess.PIPE, stdout=subprocess.PIPE, env=env, text=True
        )
        assert json.loads(self.readline(120.0) or "{}").get("status") == "ready", "the worker did not start"

    def readline(self, timeout: float) -> str | None:
        assert self.process is not None and self.process.stdout is not None
        ready, _, _ = select.select([self.process.stdout], [], [], timeout)
        return self.process.stdout.readline() if ready else None

    def read(self, kind: str, path: Path) -> dict:
        if self.process is None or self.process.poll() is not None:
            self.start()
        assert self.process is not None and self.process.stdin is not None
        self.process.stdin.write(f"{kind} {path}\n")
        self.process.stdin.flush()
        line = self.readline(self.time_limit)
        if line:
            return json.loads(line)
        self.stop()  # no answer in time: kill it; an empty line: it died
        return {"status": "hang" if line is None else f"crash (exit status {self.process.returncode})"}

    def stop(self) -> None:
        if self.process is not None and self.process.poll() is None:
            self.process.kill()
        if self.process is not None:
            self.process.wait()
