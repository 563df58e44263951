"""A ready-made scene for sweeps: the cantilever of the README, under a tip load.

Used by the tests, the benchmark and the guide; a template for writing a scene."""

from __future__ import annotations

from typing import Any

import numpy as np


def cantilever(
    E: float,
    nu: float,
    tip_load: float,
    *,
    length: float = 1.0,
    width: float = 0.2,
    cells: tuple[int, int, int] = (4, 1, 1),
    density: float = 1000.0,
    dt: float = 0.01,
    frames: int = 5,
    steps_per_frame: int = 2,
) -> dict[str, Any]:
    """A beam clamped at x = 0 and pulled along +z by a tip load, stepped from rest.

    E, nu       Young's modulus [Pa] and Poisson ratio of the material
    tip_load    total force [N] along +z, shared equally by the nodes of the end x = length
    length, width, cells   the beam: length x width x width from the origin, cells cuboids of
                6 tets each along (x, y, z)
    density, dt, frames, steps_per_frame   material density, time step [s], frames kept and
                implicit steps per frame
    returns     {"time": (frames,) [s],
                 "tip": (("frame", "xyz"), (frames, 3)): the mean displacement of the end nodes [m],
                 "positions": (("frame", "node", "xyz"), (frames, n_nodes, 3)): all nodes [m]}

    Raises ValueError for an impossible material (nu >= 0.5, E <= 0) and RuntimeError when a
    step fails (on_failure="raise": a load so large that elements invert)."""
    from .. import Body, Material, Simulation, beam

    mesh = beam(length, width, width, cells=cells)
    body = Body(mesh, Material(E=E, nu=nu, density=density))
    sim = Simulation(body, dt=dt, on_failure="raise")
    sim.fix(mesh.nodes_on_plane("x", 0.0))
    tip = mesh.nodes_on_plane("x", length)
    sim.external_forces[tip] = (0.0, 0.0, tip_load / len(tip))
    time = np.empty(frames)
    positions = np.empty((frames, mesh.n_nodes, 3))
    for frame in range(frames):
        sim.step(steps_per_frame)
        time[frame] = sim.time
        positions[frame] = sim.positions
    tip_path = positions[:, tip].mean(axis=1) - mesh.points[tip].mean(axis=0)
    return {
        "time": time,
        "tip": (("frame", "xyz"), tip_path),
        "positions": (("frame", "node", "xyz"), positions),
    }
