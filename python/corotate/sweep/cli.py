"""``corotate sweep SPEC``: run a sweep spec file from the command line."""

from __future__ import annotations

import argparse
import sys
from typing import Any

DESCRIPTION = (
    "Run every run of a parameter sweep on a Dask cluster and store the results in a Zarr folder (one "
    "group per run; open the whole sweep with corotate.open_sweep(OUT) as one xarray Dataset). SPEC is "
    "a Python file that defines scene (a function of the parameters that builds a body and a "
    "simulation, steps it and returns a mapping name -> array) and table (a corotate.ParameterTable, "
    "e.g. ParameterTable.grid(E=[...], nu=[...]), a mapping name -> values or a list of runs), and "
    "optionally out (the output folder, relative to SPEC). Runs already finished in OUT are kept: "
    "running the same command again after a crash or Ctrl-C computes only what is missing. A run "
    "whose scene raises is recorded as failed with its message. Needs the extra [sweep]: "
    "pip install 'corotate-fem[sweep]'. See docs/guide/sweeps.md."
)


def add_sweep_command(sub: Any) -> None:
    """Add ``sweep`` to the subcommands of the corotate command line."""
    sweep = sub.add_parser(
        "sweep",
        help="run a parameter sweep (a scene over a table of parameters) on a Dask cluster into a Zarr folder",
        description=DESCRIPTION,
    )
    sweep.add_argument("spec", metavar="SPEC", help="the sweep spec: a Python file defining scene and table")
    sweep.add_argument("--out", help="output folder (default: SPEC's out, else SPEC with the suffix .zarr)")
    sweep.add_argument(
        "--scheduler",
        help="address of a running Dask scheduler (e.g. tcp://10.0.0.5:8786, or one started by dask-jobqueue); "
        "default: a LocalCluster on this machine",
    )
    sweep.add_argument(
        "--workers", type=int, help="LocalCluster worker processes (default: cores // --threads-per-run)"
    )
    sweep.add_argument(
        "--threads-per-run",
        type=int,
        default=1,
        help="corotate threads (set_threads) each worker steps its scene with (default 1)",
    )
    sweep.add_argument(
        "--runs-per-task",
        type=int,
        help="runs one Dask task computes (default: up to 16, for runs of milliseconds; 1 for runs of minutes)",
    )
    sweep.add_argument("--retry-failed", action="store_true", help="compute runs recorded as failed again")
    sweep.add_argument(
        "--connect-timeout", type=float, default=10.0, help="seconds to wait for --scheduler to answer (default 10)"
    )
    sweep.add_argument("--no-progress", dest="progress", action="store_false", help="no progress bar on stderr")
    sweep.set_defaults(func=run_sweep_command)


def run_sweep_command(args: argparse.Namespace) -> int:
    """The ``sweep`` command: 0 when every run is done or failed, 130 after Ctrl-C."""
    from .runner import run_sweep
    from .spec import load_spec

    spec = load_spec(args.spec)
    out = args.out or spec.out
    try:
        report = run_sweep(
            spec.scene,
            spec.table,
            out,
            scheduler=args.scheduler,
            workers=args.workers,
            threads_per_run=args.threads_per_run,
            retry_failed=args.retry_failed,
            runs_per_task=args.runs_per_task,
            progress=args.progress,
            connect_timeout=args.connect_timeout,
        )
    except KeyboardInterrupt:
        print("corotate sweep: interrupted; run the same command again to resume", file=sys.stderr)
        return 130
    print(
        f"corotate sweep: {report.total} runs in {report.path}: {report.done} done, {report.failed} failed; "
        f"this start found {report.found} finished, computed {len(report.computed)}, "
        f"removed {len(report.removed)} half-written (and computed them), in {report.seconds:.1f} s"
    )
    print(f"  open it with: corotate.open_sweep({str(report.path)!r})")
    return 0
