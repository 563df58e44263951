"""Modal stresses: the linear (small-strain) stress of each basis vector at the element
centres, computed once; the stress of a modal state is then sum_i q_i sigma_i.

sigma = lambda tr(eps) I + 2 mu eps (each cell's material) with eps = sym(grad u), grad u = sum_a u_a (x) dN_a/dX at
the element centre (the core's element centre gradients, for every solid cell type).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

import corotate._core as _core

from ..mesh import VOLUME_CELL_TYPES

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from ..body import Body
    from .reduction import ModalBasis

__all__ = ["centre_gradients", "linear_stress", "modal_stresses"]


def centre_gradients(body: Body) -> np.ndarray:
    """(m, k, 3) shape-function gradients dN_a/dX at each element's centre."""
    mesh = body.mesh
    if mesh.cell_type not in VOLUME_CELL_TYPES:
        raise ValueError(f"modal stresses need solid cells ({', '.join(VOLUME_CELL_TYPES)}), not {mesh.cell_type!r}")
    G = _core.centre_gradients(mesh.cell_type, mesh.points, mesh.cells)
    return np.asarray(G).reshape(mesh.n_cells, -1, 3)


def linear_stress(body: Body, displacement: ArrayLike, gradients: np.ndarray | None = None) -> np.ndarray:
    """(m, 3, 3) small-strain stress at the element centres for the displacement ((n, 3) or
    (3n,)); pass ``gradients`` (centre_gradients) to reuse them."""
    u = np.asarray(displacement, dtype=np.float64)
    if u.size == 3 * body.n_nodes:
        u = u.reshape(-1, 3)
    if u.shape != (body.n_nodes, 3) or not np.all(np.isfinite(u)):
        raise ValueError(f"displacement must be a finite ({body.n_nodes}, 3) or ({3 * body.n_nodes},) array")
    G = centre_gradients(body) if gradients is None else gradients
    H = np.einsum("eai,eaj->eij", u[body.mesh.cells], G)  # grad u per element
    eps = 0.5 * (H + H.transpose(0, 2, 1))
    lam, mu = body.cell_lame()  # each cell's material
    trace = np.trace(eps, axis1=1, axis2=2)
    return (lam * trace)[:, None, None] * np.eye(3) + 2 * mu[:, None, None] * eps


def modal_stresses(body: Body, basis: ModalBasis) -> np.ndarray:
    """(r, m, 3, 3) linear stress of each basis vector at the element centres; the stress of
    modal coordinates q is np.tensordot(q, modal_stresses, axes=1)."""
    G = centre_gradients(body)
    return np.array([linear_stress(body, basis.vectors[:, i], G) for i in range(basis.size)])
