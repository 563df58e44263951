"""What the viewer draws by default: the boundary of the simulated body itself."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..surfaces import boundary_triangles


class BodySurface:
    """The boundary triangles of a body's mesh over the simulation's positions (a view: no
    copy, nothing to update). Triangle sheets are drawn whole."""

    def __init__(self, sim: Any) -> None:
        self._sim = sim
        mesh = sim.body.mesh
        self.triangles = mesh.cells.copy() if mesh.cell_type == "triangle" else boundary_triangles(mesh)

    @property
    def positions(self) -> np.ndarray:
        return self._sim.positions
