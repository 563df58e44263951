"""The paper's Fig. 5 (§2.2.2): a thin plate of quadratic hexahedra (Hex20) bent through a
large rotation, by linear FEM and by the co-rotational formulation side by side. Linear FEM
moves every point along the straight tangent of its small-displacement path, so under a large
rotation the plate grows (its mid-line lengthens), which does not look plausible; the
co-rotational plate bends and keeps its length.

    python -m studies.fig5_thin_wall --out thin-wall
writes thinwall_linear.pvd and thinwall_corotational.pvd (one frame per load level, for
ParaView), thinwall.csv (mid-line growth per load level) and thinwall.png (both mid-lines).
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path
from typing import NamedTuple

import numpy as np

from corotate import Body, Direct, Material, Mesh, Simulation, TimeSeriesWriter, box

from ._common import output_folder, parser, pyplot, write_csv


class ThinWallResult(NamedTuple):
    mesh: Mesh
    load: np.ndarray  # (frames,) tip load [N] of each frame
    positions: dict[str, list[np.ndarray]]  # model -> (n, 3) positions per frame
    growth: dict[str, np.ndarray]  # model -> (frames,) mid-line length / rest length - 1
    tip_rotation: dict[str, float]  # model -> slope angle at the tip in the last frame [deg]


def midline_nodes(mesh: Mesh) -> np.ndarray:
    """Nodes on the plate's mid-line (mid-width, mid-thickness), ordered along x."""
    p = mesh.points
    lo, hi = p.min(axis=0), p.max(axis=0)
    mid = (lo + hi) / 2
    on = np.isclose(p[:, 1], mid[1]) & np.isclose(p[:, 2], mid[2])
    nodes = np.flatnonzero(on)
    return nodes[np.argsort(p[nodes, 0])]


def midline_length(positions: np.ndarray, nodes: np.ndarray) -> float:
    """Length of the polyline through positions[nodes]."""
    return float(np.linalg.norm(np.diff(positions[nodes], axis=0), axis=1).sum())


def thin_wall(
    out: str | os.PathLike[str] | None = "thin-wall",
    cells: tuple[int, int] = (12, 2),
    frames: int = 12,
    bending: float = 3.0,
) -> ThinWallResult:
    """A 1 m x 0.2 m x 2 cm plate (cells[0] x cells[1] x 1 Hex20, E = 10 MPa, nu = 0.3),
    clamped at x = 0, loaded at its free edge by a vertical force P rising in ``frames``
    equal steps to P L^2 / EI = ``bending`` (3: the co-rotational tip turns by about 55
    degrees). Each frame is a static equilibrium (Newton from the previous one), for the
    linear and the co-rotational model.

    Writes OUT/thinwall_linear.pvd and OUT/thinwall_corotational.pvd (one frame per load
    level), OUT/thinwall.csv and OUT/thinwall.png (both mid-lines in the x-z plane); out=None
    writes nothing. Returns the positions and the growth of the mid-line per frame.
    """
    length, width, thickness = 1.0, 0.2, 0.02
    material = Material(E=1e7, nu=0.3, density=1000.0)
    mesh = box((length, width, thickness), (cells[0], cells[1], 1), element="hex20")
    inertia = width * thickness**3 / 12
    total = bending * material.E * inertia / length**2
    clamped = mesh.nodes_on_plane("x", 0.0)
    tip = mesh.nodes_on_plane("x", length)
    line = midline_nodes(mesh)
    rest_length = midline_length(mesh.points, line)
    loads = total * np.arange(frames + 1) / frames

    positions: dict[str, list[np.ndarray]] = {}
    growth: dict[str, np.ndarray] = {}
    tip_rotation: dict[str, float] = {}
    for model in ("linear", "corotational"):
        sim = Simulation(Body(mesh, material, model=model), solver=Direct())
        sim.fix(clamped)
        frames_x = [sim.positions.copy()]
        for load in loads[1:]:
            sim.external_forces[:] = 0.0
            sim.external_forces[tip, 2] = -load / len(tip)  # equal nodal shares: a resultant of P
            sim.solve_static(load_steps=1, tolerance=1e-6)  # the thin plate's round-off floor is ~2e-8
            frames_x.append(sim.positions.copy())
        positions[model] = frames_x
        growth[model] = np.array([midline_length(x, line) / rest_length - 1 for x in frames_x])
        last = frames_x[-1][line[-2:]]
        slope = last[1] - last[0]
        tip_rotation[model] = float(np.degrees(np.arctan2(-slope[2], slope[0])))

    result = ThinWallResult(mesh, loads, positions, growth, tip_rotation)
    if out is not None:
        _write(result, Path(out), line)
    return result


def _write(result: ThinWallResult, out: Path, line: np.ndarray) -> None:
    out = output_folder(out)
    for model, frames_x in result.positions.items():
        with TimeSeriesWriter(out / f"thinwall_{model}.pvd", result.mesh) as writer:
            for k, x in enumerate(frames_x):
                writer.write(float(k), x)  # "time" = load step
    header = ["load_N"] + [f"{m}_midline_growth" for m in result.growth]
    rows = ([load, *(float(g[k]) for g in result.growth.values())] for k, load in enumerate(result.load))
    csv_path = write_csv(out / "thinwall.csv", header, rows)
    plt = pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.5), sharey=True)
    for ax, model, label in zip(axes, ("linear", "corotational"), ("a) linear FEM", "b) co-rotational FEM")):
        for k in range(0, len(result.load), max(1, len(result.load) // 4)):
            x = result.positions[model][k][line]
            ax.plot(x[:, 0], x[:, 2], color=plt.cm.viridis(k / (len(result.load) - 1)), linewidth=1.5)
        x = result.positions[model][-1][line]
        ax.plot(x[:, 0], x[:, 2], "k", linewidth=2.5)
        ax.plot([0, 1], [0.01, 0.01], "k--", linewidth=0.8)
        ax.set_aspect("equal")
        ax.set_xlabel("x [m]")
        ax.set_title(f"{label}: mid-line {100 * result.growth[model][-1]:+.2f} % longer")
    axes[0].set_ylabel("z [m]")
    fig.suptitle("Thin Hex20 plate under a tip load (paper Fig. 5): increasing load, last frame black")
    png = out / "thinwall.png"
    fig.savefig(png, dpi=110, bbox_inches="tight")
    plt.close(fig)
    g = {m: f"{100 * v[-1]:+.1f} %" for m, v in result.growth.items()}
    rot = {m: f"{v:.0f} deg" for m, v in result.tip_rotation.items()}
    print(f"thin wall: {result.mesh.n_cells} Hex20 cells; mid-line growth {g}, tip slope {rot}")
    print(f"wrote {out / 'thinwall_linear.pvd'}, {out / 'thinwall_corotational.pvd'}, {csv_path} and {png}")


def main(argv: Sequence[str] | None = None) -> int:
    p = parser(__doc__, "thin-wall")
    p.add_argument("--cells", type=int, nargs=2, default=(12, 2), help="Hex20 cells along x and y (default 12 2)")
    p.add_argument("--frames", type=int, default=12, help="load levels (default 12)")
    p.add_argument("--bending", type=float, default=3.0, help="the last load as P L^2 / EI (default 3)")
    args = p.parse_args(argv)
    thin_wall(args.out, tuple(args.cells), args.frames, args.bending)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
