"""Threads on a busy machine: the standard beam's step (bench/README.md: 5 x 1 x 1 m, E = 1e7
Pa, corotate.PCG(), dt = 0.01 s, clamped at x = 0) with the default thread setting, on one
thread and on two, while other processes keep the cores busy, as a renderer, a haptic loop or
other jobs do on a user's machine.

    python bench/contention.py [--busy 2] [--viewer] [--cells 40,8,8 80,16,16] [--steps 20] [--repeats 5]

--busy N starts N processes that spin on the CPU (not pinned: the scheduler places them, as
it places other jobs) for the whole run; --busy 0 measures the idle machine. --viewer also
runs `corotate view` (the live viewer: a body stepped in real time and drawn every frame;
needs the [view] extra and a display: xvfb-run -a python bench/contention.py --viewer, where
the drawing is done by the CPU) for the whole run. The settings run
in turns (each with its own simulation, after 10 settling steps); the medians of --repeats
runs of --steps steps are printed with each setting's ratio to one thread. The default is
the thread count corotate starts with (1 unless COROTATE_THREADS says otherwise; a row of its
own when it is neither 1 nor 2). Prints the CPU, the code path and the load average before
and after.
"""

from __future__ import annotations

import argparse
import multiprocessing
import os
import subprocess
import sys
import time

import numpy as np
from bench_machine import describe_machine

import corotate as cr


def spin(stop: multiprocessing.synchronize.Event) -> None:
    """Keeps one core busy until stop is set."""
    while not stop.is_set():
        sum(i * i for i in range(20000))


def beam_simulation(cells: tuple[int, int, int]) -> cr.Simulation:
    mesh = cr.beam(5.0, 1.0, 1.0, cells=cells)
    sim = cr.Simulation(cr.Body(mesh, cr.Material(E=1e7, nu=0.3, density=1000.0)), dt=0.01, gravity=(0, 0, -9.81))
    sim.fix(mesh.nodes_on_plane("x", 0.0))
    return sim


def measure(cells: tuple[int, int, int], settings: dict[str, int], steps: int, repeats: int) -> None:
    sims = {}
    for name, threads in settings.items():
        cr.set_threads(threads)
        sims[name] = beam_simulation(cells)
        sims[name].step(10)  # the preconditioner built, the beam moving
    times: dict[str, list[float]] = {name: [] for name in settings}
    for _ in range(repeats):
        for name, threads in settings.items():
            cr.set_threads(threads)
            t0 = time.perf_counter()
            sims[name].step(steps)
            times[name].append((time.perf_counter() - t0) / steps * 1e3)
    tets = 6 * cells[0] * cells[1] * cells[2]
    print(f"{tets:,} tets, {steps} steps x {repeats} runs, in turns:")
    one = np.median(times["one thread"])
    for name in settings:
        median = np.median(times[name])
        print(
            f"  {name:28s} {median:8.2f} ms/step (runs {min(times[name]):.2f}-{max(times[name]):.2f}),"
            f" {median / one:.2f}x one thread"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--busy", type=int, default=2, help="processes that keep the cores busy (default 2)")
    parser.add_argument(
        "--cells", nargs="+", default=["40,8,8", "80,16,16"], help="beam cells, e.g. 40,8,8 (15,360 tets)"
    )
    parser.add_argument("--viewer", action="store_true", help="run the live viewer too (needs a display)")
    parser.add_argument("--steps", type=int, default=20, help="steps per timed run (default 20)")
    parser.add_argument("--repeats", type=int, default=5, help="timed runs per setting (default 5)")
    args = parser.parse_args()
    if args.busy < 0 or args.steps < 1 or args.repeats < 1:
        parser.error("--busy must be >= 0, --steps and --repeats >= 1")
    try:
        cells = [tuple(int(c) for c in text.split(",")) for text in args.cells]
    except ValueError:
        parser.error("--cells takes triples such as 40,8,8")
    if any(len(c) != 3 or min(c) < 1 for c in cells):
        parser.error("--cells takes triples of positive integers such as 40,8,8")

    default = cr.threads()
    # The default is measured as its own row only when it is not one of the others.
    settings = {"one thread": 1}
    if cr.have_openmp():
        settings["two threads"] = 2
    if default not in settings.values():
        settings[f"default ({default} threads)"] = default
    print(describe_machine())
    print(f"the default thread count here: {default}")
    stop = multiprocessing.Event()
    busy = [multiprocessing.Process(target=spin, args=(stop,), daemon=True) for _ in range(args.busy)]
    for process in busy:
        process.start()
    viewer = None
    if args.viewer:
        viewer = subprocess.Popen(
            [sys.executable, "-m", "corotate", "view", "--frames", "1000000"],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.PIPE,
            text=True,
        )
    try:
        time.sleep(5.0 if viewer else 1.0 if busy else 0.0)  # (the viewer's window and first frames)
        if viewer and viewer.poll() is not None:
            sys.exit(f"contention.py: the viewer stopped: {viewer.communicate()[1].strip()[-500:]}")
        print(
            f"{args.busy} busy processes{' and the live viewer' if viewer else ''} on {os.cpu_count()} cores;"
            f" load average {os.getloadavg()[0]:.1f}"
        )
        for c in cells:
            measure(c, settings, args.steps, args.repeats)
        print(f"load average at the end {os.getloadavg()[0]:.1f}")
    finally:
        stop.set()
        for process in busy:
            process.join()
        if viewer:
            viewer.terminate()
            viewer.wait()
        cr.set_threads(default)


if __name__ == "__main__":
    main()
