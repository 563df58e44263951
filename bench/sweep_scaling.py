#!/usr/bin/env python3
"""Sweep scaling: the same sweep of the cantilever (E, nu, tip load) on a LocalCluster of one
worker and of two, each worker stepping its scenes on one thread. Prints both wall times,
their ratio and the machine's load (on a shared machine the other work takes cores too).

    python bench/sweep_scaling.py

The clusters (corotate.sweep.local_cluster, the LocalCluster run_sweep starts by default) are
started before the clock starts: a LocalCluster takes a few seconds to start, once per sweep.
Each sweep writes into a fresh temporary folder.
"""

import argparse
import functools
import os
import tempfile
import time
from pathlib import Path

import numpy as np

import corotate as cr
from corotate.sweep import local_cluster
from corotate.sweep.scenes import cantilever


def timed_sweep(workers: int, scene, table, out: Path) -> tuple[float, float, float]:
    """(wall seconds of the sweep, mean seconds of one run inside its worker, CPU seconds of
    this process: the scheduler, the nannies and the client, which share the cores with the
    workers)."""
    client, cluster = local_cluster(workers)  # as run_sweep starts it
    with cluster, client:
        client.wait_for_workers(workers)
        start, cpu = time.perf_counter(), time.process_time()
        report = cr.run_sweep(scene, table, out, scheduler=client, runs_per_task=1, progress=False)
        seconds, cpu = time.perf_counter() - start, time.process_time() - cpu
    if report.done != len(table):
        raise RuntimeError(f"{len(table) - report.done} runs did not finish: {report}")
    return seconds, float(cr.open_sweep(out).seconds.mean()), cpu


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--runs", type=int, default=32, help="runs in the sweep (default 32)")
    parser.add_argument(
        "--cells", type=int, nargs=3, default=(20, 4, 4), help="beam cuboids, 6 tets each (default 20 4 4: 1,920 tets)"
    )
    parser.add_argument("--frames", type=int, default=150, help="frames of 5 steps per run (default 150)")
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
        one, run_one, cpu_one = timed_sweep(1, scene, table, Path(folder) / "one.zarr")
        print(f"  1 worker:  {one:.2f} s (a run took {run_one:.3f} s in its worker; this process: {cpu_one:.2f} s CPU)")
        two, run_two, cpu_two = timed_sweep(2, scene, table, Path(folder) / "two.zarr")
        print(f"  2 workers: {two:.2f} s (a run took {run_two:.3f} s in its worker; this process: {cpu_two:.2f} s CPU)")
    print(f"  speed-up: {one / two:.2f}x")
    if run_two > 1.2 * run_one:
        print("  (each run was slower with two workers: other processes were using the cores)")
    print(f"  load average after: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
