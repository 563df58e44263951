"""Reduced St. Venant-Kirchhoff forces as polynomials in the modal coordinates (Barbic &
James 2005), and modal derivatives to enrich the basis (Idelsohn & Cardona 1985).

A StVK body's energy is a quartic polynomial in the displacement u, so its tangent K_T(u)
is quadratic and the reduced tangent Phi^T K_T(Phi q) Phi is

    T(q) = K + sum_i q_i A_i + sum_ij q_i q_j B_ij,

with the forces f(q) = -(K q + 1/2 sum q_i A_i q + 1/3 sum q_i q_j B_ij q) that ModalBody
evaluates. The coefficients are read off the full model's tangent at a few displacements:

    K(+a phi_i), K(-a phi_i)          ->  A_i, B_ii
    K(a phi_i + b phi_j), i < j       ->  B_ij

(r (r + 3) / 2 tangent assemblies, once). Being a polynomial identity it is exact for any
amplitudes a, b up to round-off; they are chosen to keep the strains moderate.

Modal derivatives: d phi_i / d q_j = -K^-1 (dK_T/du[phi_j]) phi_i, the shapes a bending mode
drags along when it grows (for a plate: the in-plane stretching that a basis of bending modes
lacks, without which reduced StVK locks).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse.linalg as sla

from ..body import Body

if TYPE_CHECKING:
    from collections.abc import Iterable

    from numpy.typing import ArrayLike

    from .reduction import ModalBasis

__all__ = ["reduced_stvk_tensors", "modal_derivatives"]


def _require_stvk(body: Body) -> None:
    if not isinstance(body, Body) or body.model != "stvk" or body.project_psd:
        raise ValueError("reduced StVK forces need a Body with model='stvk' (and no PSD projection)")


def _amplitude(body: Body, vector: np.ndarray, relative: float) -> float:
    size = float(np.ptp(body.mesh.points, axis=0).min())  # the smallest extent (a plate's thickness)
    return relative * size / float(np.abs(vector).max())


def reduced_stvk_tensors(
    body: Body, basis: ModalBasis, relative_amplitude: float = 0.1
) -> tuple[np.ndarray, np.ndarray]:
    """(A (r, r, r), B (r, r, r, r)) of the reduced StVK forces for ModalBody(quadratic=A,
    cubic=B); index order A[l, k, i] = (A_i)_lk, B[l, k, i, j] = (B_ij)_lk. Each vector is
    displaced by relative_amplitude times the body's smallest extent for the read-off."""
    _require_stvk(body)
    P = basis.vectors
    r = basis.size
    X = body.mesh.points

    def reduced_tangent(u: np.ndarray) -> np.ndarray:
        return np.asarray(P.T @ (body.tangent_matrix(X + u.reshape(-1, 3)) @ P))

    K0 = reduced_tangent(np.zeros(P.shape[0]))
    s = np.array([_amplitude(body, P[:, i], relative_amplitude) for i in range(r)])
    A = np.empty((r, r, r))
    B = np.empty((r, r, r, r))
    for i in range(r):
        plus, minus = reduced_tangent(s[i] * P[:, i]), reduced_tangent(-s[i] * P[:, i])
        A[:, :, i] = (plus - minus) / (2 * s[i])
        B[:, :, i, i] = (plus + minus - 2 * K0) / (2 * s[i] ** 2)
    for i in range(r):
        for j in range(i + 1, r):
            a, b = s[i], s[j]
            mixed = reduced_tangent(a * P[:, i] + b * P[:, j])
            Bij = (mixed - K0 - a * A[:, :, i] - b * A[:, :, j] - a * a * B[:, :, i, i] - b * b * B[:, :, j, j]) / (
                2 * a * b
            )
            B[:, :, i, j] = B[:, :, j, i] = Bij
    return A, B


def modal_derivatives(
    body: Body,
    vectors: ArrayLike,
    fixed_dofs: ArrayLike,
    pairs: Iterable[tuple[int, int]],
    relative_amplitude: float = 0.1,
) -> np.ndarray:
    """(3n, len(pairs)) modal derivatives psi_ij = -K^-1 (dK_T/du[v_j]) v_i of the columns v of
    ``vectors`` (3n, k) (normal modes, a static shape, ...), for the given index pairs, with
    ``fixed_dofs`` held (zero there); pass them to craig_bampton(extra_vectors=...).
    dK_T/du[v] = (K_T(X + s v) - K_T(X - s v)) / 2s, exact for StVK (K_T is quadratic in u)."""
    _require_stvk(body)
    V = np.array(vectors, dtype=np.float64, ndmin=2)
    n_dofs = 3 * body.n_nodes
    if V.shape[0] != n_dofs or not np.all(np.isfinite(V)):
        raise ValueError(f"vectors must be a finite ({n_dofs}, k) array")
    pair_list = [(int(i), int(j)) for i, j in pairs]
    for i, j in pair_list:
        if not (0 <= i < V.shape[1] and 0 <= j < V.shape[1]):
            raise ValueError(f"pair ({i}, {j}) is out of range for {V.shape[1]} vectors")
    X = body.mesh.points
    free = np.setdiff1d(np.arange(n_dofs), np.asarray(fixed_dofs, dtype=np.int64))
    solve = sla.factorized(body.stiffness_matrix().tocsc()[free][:, free].tocsc())
    out = np.zeros((n_dofs, len(pair_list)))
    directional = {}
    for j in sorted({j for _, j in pair_list}):
        s = _amplitude(body, V[:, j], relative_amplitude)
        u = (s * V[:, j]).reshape(-1, 3)
        directional[j] = (body.tangent_matrix(X + u) - body.tangent_matrix(X - u)) / (2 * s)
    for c, (i, j) in enumerate(pair_list):
        rhs = -(directional[j] @ V[:, i])
        out[free, c] = solve(rhs[free])
    return out
