"""How far CG's tolerance may go per preconditioner (docs/notes/performance.md, the tolerance).

The scene of tests/solvers/test_pcg_follows_rotation.py: a 30 cm bar of jittered tets hanging
from the nodes at one end of its top edge swings down through 90 degrees under gravity
(dt = 0.01 s, 150 steps). For each preconditioner and tolerance the study runs the default
capped PCG and reports how far the centroid strays from a direct solve of every step, as a
percentage of how far it travels, with the CG iterations per step.

    python -m studies.tolerance_per_preconditioner --out tolerance   # tolerance.csv, tolerance.png
(--cells 40,8,8 is the same bar at 15,360 tets: about a minute.)
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

import corotate as cr

from ._common import output_folder, parser, pyplot, save_figure, write_csv
from .scenes import SOFT, jittered_box


def centroids(body: cr.Body, fixed: np.ndarray, solver: cr.PCG | cr.Direct, steps: int) -> tuple[np.ndarray, float]:
    """The centroid after each step ((steps, 3)), and the CG iterations per step."""
    sim = cr.Simulation(body, dt=0.01, gravity=(0, 0, -9.81), solver=solver)
    sim.fix(fixed)
    out = []
    for _ in range(steps):
        sim.step(1)
        out.append(sim.positions.mean(axis=0))
    return np.array(out), sim.stats["iterations_per_step"]


def main(argv: Sequence[str] | None = None) -> int:
    p = parser(__doc__, "tolerance")
    p.add_argument("--cells", default="20,4,4", help="cells along x, y, z (default 20,4,4: 1,920 tets)")
    p.add_argument("--preconditioners", default="two_level,reference_factor")
    p.add_argument("--tolerances", default="1e-2,2e-2,3e-2")
    p.add_argument("--steps", type=int, default=150)
    args = p.parse_args(argv)
    cells = tuple(int(c) for c in args.cells.split(","))
    if len(cells) != 3 or min(cells) < 1 or cells[1] % 4 or cells[2] % 4:
        p.error("--cells: three positive counts, the last two multiples of 4")
    out = output_folder(args.out)
    mesh = jittered_box((0.3, 0.06, 0.06), cells, jitter=0.25)
    # The test's three fixed nodes at 20 x 4 x 4, as many per unit of edge area when refined.
    fixed = np.argsort(np.linalg.norm(mesh.points - [0.0, 0.03, 0.06], axis=1))[: 3 * (cells[1] // 4) ** 2]
    body = cr.Body(mesh, SOFT)
    reference, _ = centroids(body, fixed, cr.Direct(), args.steps)
    travel = np.abs(reference - mesh.points.mean(axis=0)).max()
    print(f"{mesh.n_cells} tets, {args.steps} steps, centroid travel {travel:.3f} m")
    print("preconditioner     tolerance  max deviation [% of travel]  CG iterations per step")
    rows = []
    for preconditioner in args.preconditioners.split(","):
        for tolerance in (float(t) for t in args.tolerances.split(",")):
            solver = cr.PCG(preconditioner=preconditioner, tolerance=tolerance)
            c, iterations = centroids(body, fixed, solver, args.steps)
            deviation = float(100 * np.abs(c - reference).max() / travel)
            rows.append([preconditioner, tolerance, deviation, float(iterations)])
            print(f"{preconditioner:18s} {tolerance:9.0e}  {deviation:27.3f}  {iterations:22.2f}")
    header = ["preconditioner", "tolerance", "max_deviation_percent_of_travel", "iterations_per_step"]
    csv_path = write_csv(out / "tolerance.csv", header, rows)
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6, 4))
    for name in args.preconditioners.split(","):
        mine = [r for r in rows if r[0] == name]
        ax.plot([r[1] for r in mine], [r[2] for r in mine], "o-", label=name)
    ax.set_xscale("log")
    ax.set_xlabel("relative tolerance of the capped PCG")
    ax.set_ylabel("centroid off a direct solve [% of travel]")
    ax.set_title(f"Hanging bar, {mesh.n_cells} tets, {args.steps} steps")
    ax.grid(alpha=0.3)
    ax.legend()
    png = save_figure(fig, out / "tolerance.png")
    print(f"wrote {csv_path} and {png}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
