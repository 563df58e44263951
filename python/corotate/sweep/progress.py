"""A progress bar for a sweep on stderr: runs done, failed, and the time left.

On a terminal one line is redrawn (at most ten times a second); into a file or pipe a line is
written at each tenth of the sweep and at the end, so a batch job's log stays short. The
time left is the runs still to do over the rate of the runs computed since this start (runs
found finished in the folder do not count towards the rate)."""

from __future__ import annotations

import sys
import time
from typing import TextIO


def format_duration(seconds: float) -> str:
    """h:mm:ss of a number of seconds ("?" when not known yet)."""
    if seconds != seconds or seconds == float("inf"):  # NaN or inf
        return "?"
    seconds = round(seconds)
    return f"{seconds // 3600}:{seconds % 3600 // 60:02d}:{seconds % 60:02d}"


class ProgressBar:
    """Counts finished runs and shows them.

    total        runs in the sweep
    done         runs already finished (successfully) when this start began
    failed       runs already recorded as failed when it began
    stream       where to draw (default sys.stderr); None draws nothing
    """

    WIDTH = 30

    def __init__(self, total: int, done: int = 0, failed: int = 0, stream: TextIO | None = sys.stderr) -> None:
        self.total, self.done, self.failed = total, done, failed
        self.computed = 0
        self.stream = stream
        self._start = time.monotonic()
        self._last_draw = -1.0
        self._last_tenth = (done + failed) * 10 // max(total, 1)
        self._last_count = -1  # runs finished at the last line written into a log
        self._tty = bool(stream is not None and getattr(stream, "isatty", lambda: False)())

    @property
    def finished(self) -> int:
        return self.done + self.failed

    def seconds_left(self) -> float:
        """Estimated seconds to finish (NaN before the first run of this start finished)."""
        if self.computed == 0:
            return float("nan")
        rate = self.computed / max(time.monotonic() - self._start, 1e-9)
        return (self.total - self.finished) / rate

    def line(self) -> str:
        """The bar as text, e.g. ``[#####.....] 500/1000 runs, 3 failed, 0:00:41 left``."""
        filled = self.WIDTH * self.finished // max(self.total, 1)
        return (
            f"sweep [{'#' * filled}{'.' * (self.WIDTH - filled)}] {self.finished}/{self.total} runs, "
            f"{self.failed} failed, {format_duration(self.seconds_left())} left"
        )

    def update(self, status: str, computed: bool = True) -> None:
        """Count one finished run ("done" or "failed"); computed=False for a run some other
        attempt had already written."""
        if status == "failed":
            self.failed += 1
        else:
            self.done += 1
        self.computed += int(computed)
        self._draw(final=False)

    def close(self, note: str = "") -> None:
        """Draw the last state (and a note, e.g. why the sweep stopped) and end the line."""
        self._draw(final=True)
        if self.stream is not None:
            if self._tty:
                self.stream.write("\n")
            if note:
                self.stream.write(note + "\n")
            self.stream.flush()

    def _draw(self, final: bool) -> None:
        if self.stream is None:
            return
        if self._tty:
            now = time.monotonic()
            if final or now - self._last_draw >= 0.1:
                self._last_draw = now
                self.stream.write("\r" + self.line())
                self.stream.flush()
            return
        tenth = self.finished * 10 // max(self.total, 1)
        if tenth > self._last_tenth or (final and self._last_count != self.finished):
            self._last_tenth, self._last_count = tenth, self.finished
            self.stream.write(self.line() + "\n")
            self.stream.flush()
