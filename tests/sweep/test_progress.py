"""The progress bar: counts, the time left, and how it draws into a log file."""

import io

from corotate.sweep import ProgressBar
from corotate.sweep.progress import format_duration


def test_time_left_is_the_rest_over_this_starts_rate(monkeypatch):
    clock = [100.0]
    monkeypatch.setattr("corotate.sweep.progress.time.monotonic", lambda: clock[0])
    bar = ProgressBar(100, done=40, failed=0, stream=None)  # 40 found finished: they do not set the rate
    assert bar.line().endswith("40/100 runs, 0 failed, ? left")
    clock[0] += 10.0
    for _ in range(19):
        bar.update("done")
    bar.update("failed")
    # 20 runs in 10 s: 40 left take 20 s
    assert bar.seconds_left() == 20.0
    assert bar.line() == "sweep [" + "#" * 18 + "." * 12 + "] 60/100 runs, 1 failed, 0:00:20 left"
    bar.update("done", computed=False)  # written by another attempt: counted, not in the rate
    assert bar.finished == 61 and bar.computed == 20


def test_a_log_gets_a_line_per_tenth_and_the_last():
    log = io.StringIO()
    bar = ProgressBar(20, stream=log)
    for _ in range(20):
        bar.update("done")
    bar.close("all done")
    lines = log.getvalue().splitlines()
    assert [line.split("] ")[1].split(",")[0] for line in lines[:-1]] == [f"{k}/20 runs" for k in range(2, 21, 2)]
    assert lines[-1] == "all done"


def test_durations():
    assert format_duration(3725.4) == "1:02:05"
    assert format_duration(float("nan")) == "?"


class Terminal(io.StringIO):
    def isatty(self):
        return True


def test_a_terminal_gets_one_line_redrawn_in_place(monkeypatch):
    clock = [0.0]
    monkeypatch.setattr("corotate.sweep.progress.time.monotonic", lambda: clock[0])
    screen = Terminal()
    bar = ProgressBar(3, stream=screen)
    for _ in range(3):
        clock[0] += 1.0  # slower than the redraw limit of ten a second: each run redrawn
        bar.update("done")
    bar.close()
    assert screen.getvalue().count("\r") == 4 and screen.getvalue().endswith("3/3 runs, 0 failed, 0:00:00 left\n")
    assert "\n" not in screen.getvalue()[:-1]
