"""Scenes that a study and a test share, so that both run the same bodies."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

import corotate as cr

SOFT = cr.Material(E=1e6, nu=0.33, density=1000.0)  # the armadillo's material in Table 1


def jittered_box(size: Sequence[float], cells: Sequence[int], jitter: float = 0.2, seed: int = 0) -> cr.Mesh:
    """A tet box whose interior nodes move by up to `jitter` cell sizes: an unstructured-like
    mesh (no two elements alike) with the box's boundary.

    size   (3,) edge lengths [m]
    cells  (3,) cubes per direction (each cut into tets by cr.box)
    returns a tetra Mesh with the nodes of cr.box(size, cells), the interior ones moved
    """
    mesh = cr.box(tuple(size), cells=tuple(cells), element="tet4")
    p = mesh.points.copy()
    inner = np.all((p > 1e-9) & (p < np.asarray(size) - 1e-9), axis=1)
    h = size[0] / cells[0]
    p[inner] += np.random.default_rng(seed).uniform(-jitter, jitter, (inner.sum(), 3)) * h
    return cr.Mesh(p, mesh.cells, "tetra")
