"""Scenes to look at: a cloth hanging from two corners and a soft cube landing on a pinned
base, both mass-spring bodies stepped explicitly. Each writes a ParaView time series
(OUT/<scene>.pvd + one .vtu per frame) and a PNG of the last frame (needs matplotlib:
``pip install matplotlib``, or the extra ``corotate-fem[plot]``; skipped with a message otherwise)."""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .body import Body
from .choices import ExplicitIntegratorName
from .explicit import ExplicitSimulation
from .mass_spring import MassSpringBody
from .material import Material
from .mesh import Mesh, rectangle
from .output import TimeSeriesWriter

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["hanging_cloth", "dropped_cube", "plot_springs"]

FPS = 60


def _run(
    name: str, sim: ExplicitSimulation, body: MassSpringBody, out: str | os.PathLike[str], frames: int, title: str
) -> ExplicitSimulation:
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    pvd = out / f"{name}.pvd"
    with TimeSeriesWriter(pvd, body.geometry) as writer:
        writer.write(sim.time, sim.positions, {"velocity": sim.velocities})
        for _ in range(frames):
            sim.step(1)
            writer.write(sim.time, sim.positions, {"velocity": sim.velocities})
    png = plot_springs(body, sim.positions, out / f"{name}.png", title=f"{title}, t = {sim.time:.2f} s")
    s = sim.stats
    print(
        f"corotate scenes {name}: {body.n_nodes} nodes, {body.n_springs} springs; {frames} frames of 1/{FPS} s, "
        f"{s['substeps'] / max(s['steps'], 1):.1f} substeps per frame (dt_crit = {sim.critical_time_step:.3g} s), "
        f"{s['ms_per_step']:.2f} ms per frame, real-time ratio {s['real_time_ratio']:.1f}"
    )
    print(f"  wrote {pvd} ({frames + 1} frames)" + (f" and {png}" if png else ""))
    return sim


def hanging_cloth(
    out: str | os.PathLike[str] = "corotate-scenes",
    n: int = 32,
    frames: int = 240,
    integrator: ExplicitIntegratorName = "verlet",
) -> ExplicitSimulation:
    """A 1 x 1 m cloth (n x n particles, E = 0.5 MPa, 1 mm thick, 200 kg/m^3), horizontal at
    the start, pinned at two corners of one edge, falls, swings and, with velocity damping
    (1.5 1/s; it costs no step size), comes to hang below the pinned edge within a few
    seconds."""
    body = MassSpringBody.cloth(n, n, size=(1.0, 1.0), E=5e5, thickness=1e-3, density=200.0, bending=0.01, beta=1e-5)
    sim = ExplicitSimulation(body, dt=1 / FPS, integrator=integrator, gravity=(0, 0, -9.81), mass_damping=1.5)
    sim.fix([body.n_nodes - n, body.n_nodes - 1])
    return _run("cloth", sim, body, out, frames, "cloth hanging from two corners")


def dropped_cube(
    out: str | os.PathLike[str] = "corotate-scenes",
    cells: int = 6,
    frames: int = 240,
    speed: float = 1.0,
    integrator: ExplicitIntegratorName = "verlet",
) -> ExplicitSimulation:
    """A soft 0.5 m cube lattice (E = 40 kPa, 1000 kg/m^3) lands on a base, squashes by a
    fifth and settles about 7 % lower (velocity damping 1 1/s; much softer lattices collapse
    under their own weight, a known weakness of mass-spring solids): at t = 0 it
    moves down at ``speed`` m/s (dropped from speed^2 / 2g), its bottom layer is pinned to
    the base from that moment, and the rest squashes and wobbles under gravity. (There is no
    contact handling: the pinned bottom layer is the base.)"""
    body = MassSpringBody.lattice((cells, cells, cells), size=(0.5, 0.5, 0.5), E=4e4, density=1000.0, beta=1e-4)
    sim = ExplicitSimulation(body, dt=1 / FPS, integrator=integrator, gravity=(0, 0, -9.81), mass_damping=1.0)
    bottom = np.flatnonzero(np.isclose(body.nodes[:, 2], 0.0))
    sim.fix(bottom)
    sim.velocities[:, 2] = -speed
    sim.velocities[bottom] = 0.0
    return _run("cube", sim, body, out, frames, "soft cube dropped on a pinned base")


def pyplot() -> Any:
    """matplotlib.pyplot on the Agg backend, or None (with a message) when matplotlib is not
    installed: the PNGs are optional, the ParaView series are not."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("  PNG skipped: matplotlib is not installed (pip install matplotlib)")
        return None
    return plt


def stvk_sheet(
    out: str | os.PathLike[str] = "corotate-scenes",
    cells: int = 16,
    frames: int = 240,
    integrator: ExplicitIntegratorName = "symplectic_euler",
) -> ExplicitSimulation:
    """The explainer's demo: a 2D St. Venant-Kirchhoff sheet of linear triangles, 1 x 1 m in
    the vertical x-z plane (E = 50 kPa, nu = 0.3, 1000 kg/m^3, 1 cm thick), pinned at its
    two top corners, swinging and stretching under gravity; symplectic Euler at the stable
    step (sub-stepped per frame). Gravity lies in the sheet's plane, so it stays plane: plane
    stress in 2D."""
    flat = rectangle((1.0, 1.0), (cells, cells))
    points = np.column_stack([flat.points[:, 0], np.zeros(flat.n_nodes), flat.points[:, 1] - 1.0])
    mesh = Mesh(points, flat.cells[:, [0, 2, 1]], "triangle")  # normal +y after the turn
    body = Body(mesh, Material(E=5e4, nu=0.3, density=1000.0), model="stvk", thickness=0.01)
    # StVK stiffens as it stretches: the online policy re-estimates the stable step as it moves.
    sim = ExplicitSimulation(
        body, dt=1 / FPS, integrator=integrator, policy="online", safety=0.7, gravity=(0, 0, -9.81), mass_damping=0.1
    )
    top = mesh.nodes_on_plane("z", 0.0)
    sim.fix([top[np.argmin(points[top, 0])], top[np.argmax(points[top, 0])]])
    sim.velocities[:, 0] = 1.0  # a push sideways, so it swings
    sim.velocities[sim.fixed_nodes] = 0.0

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    pvd = out / "sheet.pvd"
    with TimeSeriesWriter(pvd, mesh) as writer:
        writer.write(sim.time, sim.positions, {"velocity": sim.velocities})
        for _ in range(frames):
            sim.step(1)
            writer.write(sim.time, sim.positions, {"velocity": sim.velocities})
    png = plot_sheet(mesh, sim.positions, out / "sheet.png", f"StVK sheet pinned at two corners, t = {sim.time:.2f} s")
    s = sim.stats
    print(
        f"corotate scenes sheet: {mesh.n_nodes} nodes, {mesh.n_cells} StVK triangles; {frames} frames of 1/{FPS} s, "
        f"{s['substeps'] / max(s['steps'], 1):.1f} substeps per frame (dt_crit = {sim.critical_time_step:.3g} s), "
        f"{s['ms_per_step']:.2f} ms per frame, real-time ratio {s['real_time_ratio']:.1f}"
    )
    print(f"  wrote {pvd} ({frames + 1} frames)" + (f" and {png}" if png else ""))
    return sim


def plot_sheet(mesh: Mesh, positions: ArrayLike, path: str | os.PathLike[str], title: str = "") -> Path | None:
    """Draw a sheet in the x-z plane (its triangles at positions (n, 3)) into a PNG; returns
    the path, or None when matplotlib is not installed."""
    plt = pyplot()
    if plt is None:
        return None
    x = np.asarray(positions)
    fig, ax = plt.subplots(figsize=(6, 6))
    ax.triplot(x[:, 0], x[:, 2], mesh.cells, color="tab:blue", linewidth=0.5)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("z [m]")
    ax.set_title(title)
    path = Path(path)
    fig.savefig(path, dpi=120, bbox_inches="tight")
    plt.close(fig)
    return path


def plot_springs(
    body: MassSpringBody, positions: ArrayLike, path: str | os.PathLike[str], title: str = ""
) -> Path | None:
    """Draw the springs at positions (n, 3) into a PNG at path; returns the path, or None
    (with a message) when matplotlib is not installed."""
    plt = pyplot()
    if plt is None:
        return None
    from mpl_toolkits.mplot3d.art3d import Line3DCollection

    x = np.asarray(positions)
    keep = body.kinds != 2  # bending springs / room diagonals only clutter the picture
    segments = x[body.springs[keep]]
    fig = plt.figure(figsize=(6, 6))
    ax = fig.add_subplot(projection="3d")
    ax.add_collection3d(Line3DCollection(segments, colors="tab:blue", linewidths=0.4))
    lo, hi = x.min(axis=0), x.max(axis=0)
    centre, half = (lo + hi) / 2, (hi - lo).max() / 2 * 1.05
    for set_lim, c in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), centre):
        set_lim(c - half, c + half)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_zlabel("z [m]")
    ax.set_title(title)
    path = Path(path)
    fig.savefig(path, dpi=120, bbox_inches="tight")
    plt.close(fig)
    return path
