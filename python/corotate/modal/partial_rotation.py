"""Partial rotation of displacements (the paper's §3.2).

A modal (linear) solution moves every point along straight lines: the tip of a bending
cantilever rises but never moves back towards the clamp. Where parts of a structure turn
as a whole (a beam's span, the crank arms of an axle), the displacements of each such
domain are rotated by that domain's rotation.

Per frame and domain k (in the C++ core, cpp/include/corotate/modal/partial_rotation.hpp,
allocation-free; ModalBody applies it while recovering displacements):
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

import corotate._core as _core

if TYPE_CHECKING:
    from collections.abc import Sequence

    from numpy.typing import ArrayLike

__all__ = ["PartialRotation", "least_squares_rotation"]


def least_squares_rotation(rest: ArrayLike, moved: ArrayLike) -> np.ndarray:
    """The proper rotation R minimising sum |R (p_i - p_mean) - (x_i - x_mean)|^2 (Kabsch) for
    (m, 3) rest points p and moved points x: the fit PartialRotation makes per domain, for
    measuring how far a part of any solution turned."""
    return np.asarray(_core.least_squares_rotation(rest, moved))


class PartialRotation:
    """Rotate modal displacements domain by domain.

    rest_positions   (n, 3) the body's rest positions (ModalBasis.rest_positions)
    domains          sequence of node-index arrays, one per domain
    representative   sequence of node-index arrays (the paper uses four points per domain;
                     at least three, not on one line), one per domain
    blend_distance   width [m] of the band outside each domain over which its rotation fades
                     out (0: only the domain's own nodes turn)

    Pass it to ModalBody(partial_rotation=...) to rotate while recovering, or call apply(u).
    Bad input raises ValueError.
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
        weights = np.zeros((n, len(domains)))
        points, domain_nodes = [], []
        for k, (dom, rep) in enumerate(zip(domains, representative)):
            d = self._nodes(dom, n, f"domain {k}")
            domain_nodes.append(d)
            points.append(self._nodes(rep, n, f"representative points of domain {k}"))
            weights[d, k] = 1.0
            if blend_distance > 0:
                dist, _ = cKDTree(X[d]).query(X)
                weights[:, k] = np.maximum(weights[:, k], 1.0 - dist / blend_distance)
        total = weights.sum(axis=1, keepdims=True)
        weights /= np.maximum(total, 1.0)
        affected = np.flatnonzero(weights.sum(axis=1) > 0)
        # The core checks the representative points (three or more, not on one line).
        self._core = _core.PartialRotation(X, [p.tolist() for p in points], affected, weights[affected])
        self._weights = weights
        self._shape = X.shape
        self._definition = (domain_nodes, points, float(blend_distance))

    @staticmethod
    def _nodes(nodes: ArrayLike, n: int, what: str) -> np.ndarray:
        idx = np.atleast_1d(np.asarray(nodes))
        if idx.ndim != 1 or idx.size == 0 or not np.issubdtype(idx.dtype, np.integer):
            raise ValueError(f"{what} must be a non-empty 1-D array of node indices")
        if idx.min() < 0 or idx.max() >= n:
            raise ValueError(f"{what}: node index out of range [0, {n})")
        return idx.astype(np.int64)

    def to_arrays(self) -> dict[str, np.ndarray]:
        """The definition as flat arrays (for a .npz file); from_arrays rebuilds it."""
        domains, points, blend = self._definition
        return {
            "domain_nodes": np.concatenate(domains),
            "domain_sizes": np.array([d.size for d in domains]),
            "representative_nodes": np.concatenate(points),
            "representative_sizes": np.array([p.size for p in points]),
            "blend_distance": np.array(blend),
        }

    @classmethod
    def from_arrays(cls, rest_positions: ArrayLike, arrays: dict[str, np.ndarray]) -> PartialRotation:
        """The PartialRotation of to_arrays() on these rest positions."""

        def split(nodes: np.ndarray, sizes: np.ndarray) -> list[np.ndarray]:
            return np.split(nodes, np.cumsum(sizes)[:-1])

        return cls(
            rest_positions,
            split(arrays["domain_nodes"], arrays["domain_sizes"]),
            split(arrays["representative_nodes"], arrays["representative_sizes"]),
            float(arrays["blend_distance"]),
        )

    @property
    def core(self) -> _core.PartialRotation:
        """The C++ object that fits and rotates (what ModalBody hands to the recovery)."""
        return self._core

    @property
    def n_nodes(self) -> int:
        return int(self._shape[0])

    @property
    def n_domains(self) -> int:
        return int(self._core.n_domains)

    @property
    def weights(self) -> np.ndarray:
        """(n, k) blend weights of the domains' rotations per node (a copy)."""
        return self._weights.copy()

    @property
    def rotations(self) -> np.ndarray:
        """(k, 3, 3) the domains' least-squares rotations of the last apply() or recovery."""
        return np.array([self._core.rotation(k) for k in range(self.n_domains)])

    def apply(self, displacements: ArrayLike, out: np.ndarray | None = None) -> np.ndarray:
        """(n, 3) modal displacements -> the partially rotated displacements (into ``out``, a
        C-contiguous float64 (n, 3) array, which may be the input; else a new array)."""
        u = np.asarray(displacements, dtype=np.float64)
        if u.shape != self._shape or not np.all(np.isfinite(u)):
            raise ValueError(f"displacements must be a finite array of shape {self._shape}")
        if out is None:
            out = np.empty(self._shape)
        _core.rotate_displacements(self._core, u, out)
        return out
