"""A picture of a run: the body's surface at several instants in one shaded 3D view (PNG).

For a quick look without ParaView (the demo writes one next to its time series). Needs
matplotlib, the ``plot`` extra: ``pip install 'corotate-fem[plot]'``.
"""

from __future__ import annotations

import importlib
import os
from collections.abc import Sequence
from typing import Any

import numpy as np

from .mesh import Mesh

__all__ = ["render_snapshots"]


def _pyplot() -> Any:
    try:
        matplotlib = importlib.import_module("matplotlib")
    except ImportError as e:
        raise ImportError("pictures need matplotlib, which is not installed: pip install 'corotate-fem[plot]'") from e
    matplotlib.use("Agg")  # files only: no display needed
    return importlib.import_module("matplotlib.pyplot")


def _display_axes(up: str) -> list[int]:
    """The model axes drawn as the plot's x, y, z: a cyclic turn (right-handed) that puts
    the axis of `up` last."""
    if len(up) != 2 or up[0] not in "+-" or up[1] not in "xyz":
        raise ValueError(f"up must be one of +x, -x, +y, -y, +z, -z, got {up!r}")
    k = "xyz".index(up[1])
    return [(k + 1) % 3, (k + 2) % 3, k]


def _signs(up: str) -> np.ndarray:
    """Mirror two axes (a half turn, still right-handed) when up points down an axis."""
    return np.array([1.0, -1.0, -1.0]) if up[0] == "-" else np.ones(3)


def render_snapshots(
    path: str | os.PathLike[str],
    mesh: Mesh,
    snapshots: Sequence[tuple[float, np.ndarray]],
    title: str = "",
    view: tuple[float, float] = (12.0, -75.0),
    up: str = "+z",
) -> str:
    """Draw the surface at each (time, (n, 3) positions) snapshot into one PNG.

    Earlier snapshots are drawn fainter; faces are coloured by the magnitude of the
    displacement from the rest positions (one colour scale for all snapshots) and shaded
    by their orientation. view is matplotlib's (elevation, azimuth) in degrees; up ("+z",
    "-y", ...) the axis drawn upward (against gravity).
    returns the path written.
    """
    axes = _display_axes(up)
    if not snapshots:
        raise ValueError("render_snapshots needs at least one (time, positions) snapshot")
    states = []
    for t, x in snapshots:
        x = np.asarray(x, dtype=float)
        if x.shape != mesh.points.shape:
            raise ValueError(f"positions at t = {t} must have shape {mesh.points.shape}, got {x.shape}")
        if not np.isfinite(x).all():
            raise ValueError(f"positions at t = {t} are not all finite")
        states.append((float(t), x[:, axes] * _signs(up)))
    plt = _pyplot()
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    rest = mesh.points[:, axes] * _signs(up)
    faces = mesh.boundary_faces()
    largest = max(float(np.linalg.norm(x - rest, axis=1).max()) for _, x in states) or 1.0
    colours = plt.get_cmap("viridis")
    light = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])

    fig = plt.figure(figsize=(8.0, 5.0), dpi=110)
    ax = fig.add_subplot(projection="3d")
    for k, (_, x) in enumerate(states):
        polys = x[faces]  # (f, corners, 3)
        normal = np.cross(polys[:, 1] - polys[:, 0], polys[:, -1] - polys[:, 0])
        normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), 1e-300)
        shade = 0.45 + 0.55 * np.abs(normal @ light)
        u = np.linalg.norm(x - rest, axis=1)[faces].mean(axis=1) / largest
        rgba = colours(u)
        rgba[:, :3] *= shade[:, None]
        rgba[:, 3] = 0.25 + 0.75 * (k + 1) / len(states)  # the last snapshot opaque
        ax.add_collection3d(Poly3DCollection(polys, facecolors=rgba, edgecolors="none"))
    every = np.concatenate([rest] + [x for _, x in states])
    lo, hi = every.min(axis=0), every.max(axis=0)
    centre, half = (lo + hi) / 2, (hi - lo).max() / 2
    ax.set(xlim=(centre[0] - half, centre[0] + half), ylim=(centre[1] - half, centre[1] + half))
    labels = [("-" if sign < 0 else "") + "xyz"[a] + " [m]" for a, sign in zip(axes, _signs(up))]
    ax.set(zlim=(centre[2] - half, centre[2] + half), xlabel=labels[0], ylabel=labels[1], zlabel=labels[2])
    ax.set_box_aspect((1, 1, 1))
    ax.view_init(*view)
    mappable = plt.cm.ScalarMappable(cmap=colours, norm=plt.Normalize(0.0, largest))
    fig.colorbar(mappable, ax=ax, shrink=0.6, label="displacement [m]")
    times = ", ".join(f"{t:g}" for t, _ in states)
    ax.set_title(
        f"{title}\nt = {times} s (fainter = earlier)" if title else f"t = {times} s (fainter = earlier)", fontsize=9
    )
    fig.tight_layout()
    fig.savefig(os.fspath(path))
    plt.close(fig)
    return os.fspath(path)
