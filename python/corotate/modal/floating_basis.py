"""What a basis must be to ride on a floating frame (FloatingBody, the Exudyn export): built on
the body's mesh, and free of rigid-body motion."""

from __future__ import annotations

import numpy as np
import scipy.linalg as la

from ..body import Body
from .reduction import ModalBasis

#: A basis whose span reproduces a rigid-body motion to this share of its M-norm holds one.
_RIGID_RTOL = 1e-6


def check_floating_basis(body: Body, basis: ModalBasis) -> None:
    """Raise TypeError for objects of other types, ValueError when the basis was built on
    another mesh or holds a rigid-body motion (the frame carries those: both would move the
    body rigidly, and the floating frame's mass matrix would be singular)."""
    if not isinstance(body, Body):
        raise TypeError(f"body must be a corotate.Body, got {type(body).__name__}")
    if not isinstance(basis, ModalBasis):
        raise TypeError(f"basis must be a corotate.modal.ModalBasis, got {type(basis).__name__}")
    if basis.rest_positions.shape != body.mesh.points.shape or not np.array_equal(
        basis.rest_positions, body.mesh.points
    ):
        raise ValueError(
            f"the basis was not built on this body's mesh: its rest positions ({basis.rest_positions.shape[0]} "
            f"nodes) differ from the body's ({body.n_nodes} nodes)"
        )
    miss = _rigid_motion_miss(body, basis)
    if miss < _RIGID_RTOL:
        raise ValueError(
            f"the basis holds a rigid-body motion (its span reproduces one to {miss:.1e} of its norm): a floating "
            "frame needs a basis without one; hold nodes in craig_bampton(fixed_nodes=...) so that they define "
            "the frame"
        )


def _rigid_motion_miss(body: Body, basis: ModalBasis) -> float:
    """How well the basis's span misses every rigid-body motion: the smallest, over the rigid
    motions u (three translations, three rotations about the origin), of |u - P u|_M / |u|_M,
    P the M-orthogonal projection onto the span. Zero when the span holds one (the frame and
    the modes would both move the body rigidly). Judged on the motions themselves rather than on
    small eigenvalues, which a slender body's first mode next to stiff constraint modes also has."""
    X = basis.rest_positions
    rigid = np.zeros((X.size, 6))
    for a in range(3):
        rigid[a::3, a] = 1.0
        rigid[:, 3 + a] = np.cross(np.eye(3)[a], X).ravel()
    M = body.mass_matrix(lumped=False)
    Mrigid = M @ rigid
    gram = rigid.T @ Mrigid
    coupling = basis.vectors.T @ Mrigid
    reduced = basis.vectors.T @ (M @ basis.vectors)
    projected = coupling.T @ np.linalg.solve(reduced, coupling)
    rest = la.eigh(0.5 * (gram - projected + (gram - projected).T), gram, eigvals_only=True)
    return float(np.sqrt(max(rest[0], 0.0)))
