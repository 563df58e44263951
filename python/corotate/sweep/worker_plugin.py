"""The LocalCluster's workers and Ctrl-C: they ignore it, since only the process that runs the
sweep stops it, and they die without a word when it does."""

from __future__ import annotations

import logging
import signal
import threading
from typing import Any

from distributed import WorkerPlugin


class IgnoreCtrlC(WorkerPlugin):
    """Ctrl-C at a terminal reaches every process of the terminal's group, the LocalCluster's
    workers too. Only run_sweep's process is to act on it (cancel, shut the workers down,
    report); this keeps each worker from printing a KeyboardInterrupt of its own. Installed on
    every worker, those restarted after a death included."""

    name = "corotate-sweep-ignore-ctrl-c"

    def setup(self, worker: Any) -> None:
        if threading.current_thread() is threading.main_thread():  # where signals are handled
            signal.signal(signal.SIGINT, signal.SIG_IGN)


def mute_logs() -> None:
    """Run on each worker (Client.run) before a cluster is shut down mid-run: Dask's own
    messages about the tasks cut short and the scheduler gone are expected then."""
    logging.getLogger("distributed").setLevel(logging.CRITICAL)
