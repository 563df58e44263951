"""Static uniaxial tension of a bar, for the closed-form checks of the hyperelastic laws."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse.linalg as spla


def pull_bar(body, length, width, stretches, tolerance):
    """Yields (stretch, positions, end force) at equilibrium for each end stretch of a bar
    [0, length] x [0, width] x [0, h]: x-displacement prescribed on both end faces, lateral
    contraction free everywhere, rigid motions removed by three single-DOF supports. Newton
    on the body's forces and stiffness (a static solve), from the previous equilibrium
    stretched along x; converged when the free residual is below tolerance [N]."""
    mesh = body.mesh
    left, right = mesh.nodes_on_plane("x", 0.0), mesh.nodes_on_plane("x", length)
    fixed = [3 * i for i in left] + [3 * i for i in right]
    origin, corner_y = mesh.nearest_node((0, 0, 0)), mesh.nearest_node((0, width, 0))
    fixed += [3 * origin + 1, 3 * origin + 2, 3 * corner_y + 2]
    free = np.setdiff1d(np.arange(3 * mesh.n_nodes), fixed)
    x, previous = mesh.points.copy(), 1.0
    for stretch in stretches:
        x[:, 0] *= stretch / previous
        previous = stretch
        for _ in range(30):
            r = body.internal_forces(x).ravel()[free]
            if np.linalg.norm(r) < tolerance:
                break
            K = body.stiffness_matrix(x).tocsc()[free][:, free]
            dx = x.ravel().copy()
            dx[free] += spla.spsolve(K, r)
            x = dx.reshape(-1, 3)
        else:
            pytest.fail(f"Newton did not converge at stretch {stretch}")
        yield stretch, x, -body.internal_forces(x)[right, 0].sum()
