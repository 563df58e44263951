"""The standard beam on two builds of the benchmark executable, run in turns: the same machine,
two instruction-set levels (a build configured with -DCOROTATE_CLONES_UP_TO_V3=ON runs the
AVX2 code an AVX2 machine runs, on an AVX-512 machine), or any two builds to compare.

    cmake -S . -B build -DCOROTATE_PYTHON=OFF && cmake --build build
    cmake -S . -B build-v3 -DCOROTATE_PYTHON=OFF -DCOROTATE_CLONES_UP_TO_V3=ON && cmake --build build-v3
    taskset -c 1 python bench/code_paths.py build/corotate_bench build-v3/corotate_bench

Each round runs every build once (--sizes, --configs; no reference solve); the table gives,
per build, size and configuration, the median ms per step of the rounds, its assembly and
solve phases, the CG iterations, the ratio to the paper configuration's median in the same
build and the first step (with the preconditioner's setup). Prints the CPU and each build's code path first.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
from collections import defaultdict
from pathlib import Path

import numpy as np
from bench_machine import cpu_name


def run(executable: str, sizes: str, configs: str) -> tuple[str, list[list[str]]]:
    """(the code path it printed, its table rows) of one benchmark run."""
    out = subprocess.run(
        [executable, "--sizes", sizes, "--configs", configs, "--no-reference"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    path = next((line.split(":", 1)[1].strip() for line in out.splitlines() if line.startswith("instruction set")), "?")
    rows = [line.split() for line in out.splitlines() if line.startswith("beam ")]
    return path, rows


def main() -> None:
    parser = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0], formatter_class=argparse.RawTextHelpFormatter
    )
    parser.add_argument("builds", nargs="+", help="corotate_bench executables to compare")
    parser.add_argument("--sizes", default="2,4,8", help="beam sizes (default: %(default)s)")
    parser.add_argument("--configs", default="paper,default", help="configurations (default: %(default)s)")
    parser.add_argument("--rounds", type=int, default=3, help="runs of each build, in turns (default: %(default)s)")
    args = parser.parse_args()
    for b in args.builds:
        if not Path(b).is_file():
            sys.exit(f"code_paths.py: no benchmark executable at {b} (build it first: see --help)")
    # (build, tets, config) -> [ms/step, asm, solve, iterations, first step] of each round
    times: dict[tuple[str, int, str], list[list[float]]] = defaultdict(list)
    paths = {}
    for _ in range(args.rounds):
        for b in args.builds:
            paths[b], rows = run(b, args.sizes, args.configs)
            for r in rows:  # beam NxNxN tets config precmp 1st ms/step asm solve iters ...
                times[(b, int(r[2]), r[3])].append([float(v) for v in (r[6], r[7], r[8], r[9], r[5])])
    print(f"CPU: {cpu_name()}; medians of {args.rounds} rounds, the builds in turns, one run each per round")
    for b in args.builds:
        print(f"  {b}: {paths[b]}")
    header = ("build: code path", "tets", "config", "ms/step", "asm", "solve", "iters", "/paper", "1st_ms")
    print("{:32s} {:>7s} {:10s} {:>8s} {:>7s} {:>7s} {:>6s} {:>7s} {:>8s}".format(*header))
    for b in args.builds:
        for (build, tets, config), runs in sorted(times.items(), key=lambda kv: (kv[0][1], kv[0][2])):
            if build != b:
                continue
            ms, asm, solve, its, first = np.median(np.array(runs), axis=0)
            paper = times.get((b, tets, "paper"))
            ratio = ms / np.median([r[0] for r in paper]) if paper else float("nan")
            label = f"{Path(b).parent.name}: {paths[b].split(' ')[0]}"
            print(
                f"{label:32s} {tets:7d} {config:10s} {ms:8.3f} {asm:7.3f} {solve:7.3f} {its:6.2f} {ratio:7.2f}"
                f" {first:8.1f}"
            )


if __name__ == "__main__":
    main()
