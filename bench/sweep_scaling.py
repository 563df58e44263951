#!/usr/bin/env python3
"""Sweep scaling: the same sweep of the cantilever (E, nu, tip load) on a LocalCluster of one
worker and of two, each worker stepping its scenes on one thread. Prints both wall times,
their ratio and the machine's load (on a shared machine the other work takes cores too).

    python bench/sweep_scaling.py --runs 48

The clusters are started before the clock starts (a LocalCluster takes a few seconds to
start; that cost is paid once per sweep, not per run). Each sweep writes into a fresh
temporary folder.
"""

import argparse
import functools
import os
import tempfile
import time
from pathlib import Path

import numpy as np

import corotate as cr
from corotate.sweep.scenes import cantilever


def timed_sweep(workers: int, scene, table, out: Path) -> tuple[float, float]:
    """(wall seconds of the sweep, mean seconds of one run inside its worker)."""
    from distributed import Client, LocalCluster

    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster:
        with Client(cluster, set_as_default=False) as client:
            client.wait_for_workers(workers)
            start = time.perf_counter()
            report = cr.run_sweep(scene, table, out, scheduler=client, runs_per_task=1, progress=False)
            seconds = time.perf_counter() - start
    if report.done != len(table):
        raise RuntimeError(f"{len(table) - report.done} runs did not finish: {report}")
    return seconds, float(cr.open_sweep(out).seconds.mean())


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--runs", type=int, default=48, help="runs in the sweep (default 48)")
    parser.add_argument(
        "--cells", type=int, nargs=3, default=(20, 4, 4), help="beam cuboids, 6 tets each (default 20 4 4: 1,920 tets)"
    )
    parser.add_argument("--frames", type=int, default=20, help="frames of 5 steps per run (default 20)")
    args = parser.parse_args()
    scene = functools.partial(
        cantilever, length=1.0, width=0.2, cells=tuple(args.cells), frames=args.frames, steps_per_frame=5
    )
    table = cr.ParameterTable.latin_hypercube(
        args.runs, {"E": (2e5, 2e6), "nu": (0.1, 0.45), "tip_load": (-10.0, 10.0)}, seed=1, log=["E"]
    )
    start = time.perf_counter()
    scene(**table.row(0))
    alone = time.perf_counter() - start
    print(
        f"sweep scaling: {args.runs} runs of a {6 * int(np.prod(args.cells))}-tet cantilever, {args.frames * 5} "
        f"steps each ({alone:.3f} s for one run alone); {os.cpu_count()} cores"
    )
    print(f"  load average before: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    with tempfile.TemporaryDirectory() as folder:
        one, run_one = timed_sweep(1, scene, table, Path(folder) / "one.zarr")
        print(f"  1 worker:  {one:.2f} s (a run took {run_one:.3f} s in its worker)")
        two, run_two = timed_sweep(2, scene, table, Path(folder) / "two.zarr")
        print(f"  2 workers: {two:.2f} s (a run took {run_two:.3f} s in its worker)")
    print(f"  speed-up: {one / two:.2f}x")
    if run_two > 1.2 * run_one:
        print("  (each run was slower with two workers: other processes were using the cores)")
    print(f"  load average after: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
