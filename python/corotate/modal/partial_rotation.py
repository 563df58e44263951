"""Partial rotation of displacements (the paper's §3.2).

A modal (linear) solution moves every point along straight lines: the tip of a bending
cantilever rises but never moves back towards the clamp. Where parts of a structure turn
as a whole (a beam's span, the crank arms of an axle), the displacements of each such
domain are rotated by that domain's rotation.

Per frame and domain k:
  1. the rotation R_k of its (four) representative points, rest -> modally displaced, in the
     least-squares sense (Kabsch: the polar factor of the points' covariance matrix);
  2. each node's displacement u is replaced by R(theta / 2) u, theta the rotation vector of R_k.

Why half the angle: for a rigid rotation by theta about a pivot at distance r, the linear
modal displacement is the tangent of length r theta, the true one the chord, of length
2 r sin(theta / 2) and turned by theta / 2 from the tangent. Turning the modal displacement
by theta / 2 gives the chord's direction exactly and its length to second order in theta:
the rigid motion is then right to second order, where turning by theta would double the
shortening.

Blending where domains meet: node i gets the rotation vector sum_k w_ik theta_k, with
w_ik = 1 on domain k's nodes, falling linearly to 0 at ``blend_distance`` from them, and the
weights of a node scaled to sum to at most 1 (so where two domains overlap it gets their
weighted mean; a node outside every band keeps its modal displacement). Rotation vectors
are blended linearly, which for the 10-15 degree rotations of the method differs from a
proper rotation average by far less than the method's own error.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from scipy.spatial import cKDTree
from scipy.spatial.transform import Rotation

if TYPE_CHECKING:
    from collections.abc import Sequence

    from numpy.typing import ArrayLike

__all__ = ["PartialRotation", "least_squares_rotation"]


def least_squares_rotation(rest: np.ndarray, moved: np.ndarray) -> np.ndarray:
    """The proper rotation R minimising sum |R (p_i - p_mean) - (x_i - x_mean)|^2 (Kabsch)."""
    a = rest - rest.mean(axis=0)
    b = moved - moved.mean(axis=0)
    U, _, Vt = np.linalg.svd(a.T @ b)
    d = np.sign(np.linalg.det(Vt.T @ U.T))
    return Vt.T @ np.diag([1.0, 1.0, d]) @ U.T


class PartialRotation:
    """Rotate modal displacements domain by domain.

    rest_positions   (n, 3) the body's rest positions (ModalBasis.rest_positions)
    domains          sequence of node-index arrays, one per domain
    representative   sequence of node-index arrays (the paper uses four points per domain;
                     at least three, not on one line), one per domain
    blend_distance   width [m] of the band outside each domain over which its rotation fades
                     out (0: only the domain's own nodes turn)
    """

    def __init__(
        self,
        rest_positions: ArrayLike,
        domains: Sequence[ArrayLike],
        representative: Sequence[ArrayLike],
        blend_distance: float = 0.0,
    ) -> None:
        X = np.asarray(rest_positions, dtype=np.float64)
        if X.ndim != 2 or X.shape[1] != 3 or not np.all(np.isfinite(X)):
            raise ValueError("rest_positions must be a finite (n, 3) array")
        if len(domains) != len(representative) or len(domains) == 0:
            raise ValueError("give one representative point set per domain (and at least one domain)")
        if not (np.isfinite(blend_distance) and blend_distance >= 0):
            raise ValueError("blend_distance must be >= 0")
        n = len(X)
        self._rest = X
        self._points = []
        weights = np.zeros((n, len(domains)))
        for k, (dom, rep) in enumerate(zip(domains, representative)):
            d = self._nodes(dom, n, f"domain {k}")
            p = self._nodes(rep, n, f"representative points of domain {k}")
            if p.size < 3 or np.linalg.matrix_rank(X[p] - X[p].mean(axis=0), tol=1e-9 * np.ptp(X)) < 2:
                raise ValueError(f"domain {k} needs at least three representative points not on one line")
            self._points.append(p)
            weights[d, k] = 1.0
            if blend_distance > 0:
                dist, _ = cKDTree(X[d]).query(X)
                weights[:, k] = np.maximum(weights[:, k], 1.0 - dist / blend_distance)
        total = weights.sum(axis=1, keepdims=True)
        self._weights = weights / np.maximum(total, 1.0)
        self._affected = np.flatnonzero(self._weights.sum(axis=1) > 0)
        self.rotations = np.tile(np.eye(3), (len(domains), 1, 1))  #: (k, 3, 3) of the last call

    @staticmethod
    def _nodes(nodes: ArrayLike, n: int, what: str) -> np.ndarray:
        idx = np.atleast_1d(np.asarray(nodes))
        if idx.ndim != 1 or idx.size == 0 or not np.issubdtype(idx.dtype, np.integer):
            raise ValueError(f"{what} must be a non-empty 1-D array of node indices")
        if idx.min() < 0 or idx.max() >= n:
            raise ValueError(f"{what}: node index out of range [0, {n})")
        return idx.astype(np.int64)

    @property
    def weights(self) -> np.ndarray:
        """(n, k) blend weights of the domains' rotations per node (a copy)."""
        return self._weights.copy()

    def apply(self, displacements: ArrayLike) -> np.ndarray:
        """(n, 3) modal displacements -> the partially rotated displacements (a new array);
        ``rotations`` holds the domains' least-squares rotations afterwards."""
        u = np.asarray(displacements, dtype=np.float64)
        if u.shape != self._rest.shape or not np.all(np.isfinite(u)):
            raise ValueError(f"displacements must be a finite array of shape {self._rest.shape}")
        rotvecs = np.empty((len(self._points), 3))
        for k, p in enumerate(self._points):
            self.rotations[k] = least_squares_rotation(self._rest[p], self._rest[p] + u[p])
            rotvecs[k] = Rotation.from_matrix(self.rotations[k]).as_rotvec()
        out = u.copy()
        i = self._affected
        half = Rotation.from_rotvec(0.5 * (self._weights[i] @ rotvecs))
        out[i] = half.apply(u[i])
        return out
