"""How far CG's tolerance may go per preconditioner (bench/README.md, "fourth round").

The scene of tests/solvers/test_pcg_follows_rotation.py: a 30 cm bar of jittered tets hanging
from the nodes at one end of its top edge swings down through 90 degrees under gravity
(dt = 0.01 s, 150 steps). For each preconditioner and tolerance the script runs the default
capped PCG and prints how far the centroid strays from a direct solve of every step, as a
percentage of how far it travels, with the CG iterations per step.

Run: python bench/tolerance_per_preconditioner.py [--cells 20,4,4] [--preconditioners
two_level,reference_factor] [--tolerances 1e-2,2e-2,3e-2]
(--cells 40,8,8 is the same bar at 15,360 tets: about a minute.)
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

import corotate as cr

# The test's mesh and material, not a copy of them.
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "solvers"))
from test_pcg_follows_rotation import MAT, jittered_box


def centroids(body: cr.Body, fixed: np.ndarray, solver, steps: int) -> tuple[np.ndarray, float]:
    """The centroid after each step, and the CG iterations per step."""
    sim = cr.Simulation(body, dt=0.01, gravity=(0, 0, -9.81), solver=solver)
    sim.fix(fixed)
    out = []
    for _ in range(steps):
        sim.step(1)
        out.append(sim.positions.mean(axis=0))
    return np.array(out), sim.stats["iterations_per_step"]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cells", default="20,4,4", help="cells along x, y, z (default 20,4,4: 1,920 tets)")
    parser.add_argument("--preconditioners", default="two_level,reference_factor")
    parser.add_argument("--tolerances", default="1e-2,2e-2,3e-2")
    parser.add_argument("--steps", type=int, default=150)
    args = parser.parse_args()
    cells = tuple(int(c) for c in args.cells.split(","))
    if len(cells) != 3 or min(cells) < 1 or cells[1] % 4 or cells[2] % 4:
        parser.error("--cells: three positive counts, the last two multiples of 4")
    mesh = jittered_box((0.3, 0.06, 0.06), cells, jitter=0.25)
    # The test's three fixed nodes at 20 x 4 x 4, as many per unit of edge area when refined.
    fixed = np.argsort(np.linalg.norm(mesh.points - [0.0, 0.03, 0.06], axis=1))[: 3 * (cells[1] // 4) ** 2]
    body = cr.Body(mesh, MAT)
    reference, _ = centroids(body, fixed, cr.Direct(), args.steps)
    travel = np.abs(reference - mesh.points.mean(axis=0)).max()
    print(f"{mesh.n_cells} tets, {args.steps} steps, centroid travel {travel:.3f} m")
    print("preconditioner     tolerance  max deviation [% of travel]  CG iterations per step")
    for preconditioner in args.preconditioners.split(","):
        for tolerance in (float(t) for t in args.tolerances.split(",")):
            solver = cr.PCG(preconditioner=preconditioner, tolerance=tolerance)
            c, iterations = centroids(body, fixed, solver, args.steps)
            deviation = 100 * np.abs(c - reference).max() / travel
            print(f"{preconditioner:18s} {tolerance:9.0e}  {deviation:27.3f}  {iterations:22.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
