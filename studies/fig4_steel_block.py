"""The paper's steel-block accuracy example (section 2.2.1, Figs. 3-4): linear, co-rotational
and full geometrically nonlinear (St. Venant-Kirchhoff, total Lagrangian) static answers on
the same tet mesh, compared at the loaded corner node.

Block 5 x 5 x 1.5 m, E = 2.1e11 Pa, nu = 0.3, bottom face (z = 0) clamped. The total force
of 1.3e10 N in -z is spread in equal shares over the top-face nodes of the corner patch
x, y in [4, 5]: a force on a single node is a point load, whose displacement grows without
bound as the mesh is refined (the paper notes the singularity), so it is not a fair measure
of the formulations. The curves are the displacement of the corner node (5, 5, 1.5).

    python -m studies.fig4_steel_block --out steel-block    # steel_block.csv, steel_block.png
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from corotate import Body, Direct, Material, Simulation, box
from corotate.choices import ModelName

from ._common import output_folder, parser, pyplot, write_csv

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

MODELS: tuple[ModelName, ...] = ("linear", "corotational", "stvk")
TOTAL_FORCE = 1.3e10  # N, in -z


def steel_block(cells: tuple[int, int, int] = (7, 7, 3), levels: int = 10, fractions: ArrayLike | None = None) -> dict:
    """Load-displacement curves of the corner node for the three formulations.

    cells      (3,) cubes per direction, each cut into 6 tets ((7, 7, 3): 882 tets)
    levels     load levels from F/levels to F (ignored when fractions is given)
    fractions  explicit load fractions in (0, 1], increasing
    returns    {"load": (k,) N, "linear" | "corotational" | "stvk": (k, 3) corner
               displacement [m], "tets": number of elements}
    """
    mesh = box((5.0, 5.0, 1.5), cells, "tet4")
    material = Material(E=2.1e11, nu=0.3, density=7850.0)
    p = mesh.points
    patch = np.flatnonzero(np.isclose(p[:, 2], 1.5) & (p[:, 0] >= 4 - 1e-9) & (p[:, 1] >= 4 - 1e-9))
    corner = mesh.nearest_node((5.0, 5.0, 1.5))
    fractions = np.arange(1, levels + 1) / levels if fractions is None else np.asarray(fractions, dtype=float)
    result = {"load": TOTAL_FORCE * fractions, "tets": mesh.n_cells}
    for model in MODELS:
        sim = Simulation(Body(mesh, material, model=model), solver=Direct())
        sim.fix(mesh.nodes_on_plane("z", 0.0))
        curve = []
        for f in fractions:  # each level starts from the previous equilibrium
            sim.external_forces[patch] = (0.0, 0.0, -TOTAL_FORCE * f / patch.size)
            sim.solve_static(load_steps=1, tolerance=1e-9)
            curve.append(sim.displacements[corner])
        result[model] = np.array(curve)
    return result


def write_table(result: dict, path: Path) -> Path:
    """One row per load level: load [N], then u_x, u_y, u_z [m] for each formulation."""
    header = ["load_N"] + [f"{m}_u{a}_m" for m in MODELS for a in "xyz"]
    rows = (
        [load, *(float(result[m][k, a]) for m in MODELS for a in range(3))] for k, load in enumerate(result["load"])
    )
    return write_csv(path, header, rows)


def plot(result: dict, path: Path) -> Path:
    """The paper's Fig. 4: corner displacement in x, y and z against the load (PNG)."""
    plt = pyplot()
    labels = {"linear": "linear", "corotational": "co-rotational", "stvk": "full nonlinear (StVK)"}
    styles = {"linear": "k--", "corotational": "C0-o", "stvk": "C3-s"}
    fig, axes = plt.subplots(1, 3, figsize=(14, 4.2), constrained_layout=True)
    load = np.concatenate([[0.0], result["load"]]) / 1e9
    for a, ax in enumerate(axes):
        for m in MODELS:
            u = np.concatenate([[0.0], result[m][:, a]])
            ax.plot(load, u * 1e3, styles[m], label=labels[m], markersize=3)
        ax.set_xlabel("force [GN]")
        ax.set_ylabel(f"corner displacement {'xyz'[a]} [mm]")
        ax.grid(alpha=0.3)
    axes[0].legend()
    fig.suptitle(f"Steel block, corner node (5, 5, 1.5): {result['tets']} tets")
    fig.savefig(path, dpi=120, bbox_inches="tight")
    plt.close(fig)
    return path


def main(argv: Sequence[str] | None = None) -> int:
    p = parser(__doc__, "steel-block")
    p.add_argument(
        "--cells", type=int, nargs=3, default=(7, 7, 3), help="cubes per direction (default 7 7 3: 882 tets)"
    )
    p.add_argument("--levels", type=int, default=10, help="load levels (default 10)")
    args = p.parse_args(argv)
    out = output_folder(args.out)
    result = steel_block(tuple(args.cells), args.levels)
    print(f"{result['tets']} tets; corner (5, 5, 1.5) at the full load of {TOTAL_FORCE:.2g} N [mm]:")
    for m in MODELS:
        print(f"  {m:13s} " + "  ".join(f"u_{a} {1e3 * result[m][-1, k]:8.2f}" for k, a in enumerate("xyz")))
    csv_path = write_table(result, out / "steel_block.csv")
    png = plot(result, out / "steel_block.png")
    print(f"wrote {csv_path} and {png}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
