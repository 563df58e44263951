"""Geometric (initial-stress) stiffness in modal space: per load case (SIMPACK; the
paper's eqs 7-8) and per mode (the paper's method, eqs 9-11).

Both need K_sigma0, the geometric stiffness of a *linear* stress state. A St. Venant-Kirchhoff
body gives K_sigma(x) (Body.geometric_stiffness): its blocks are linear in the second
Piola-Kirchhoff stress S, and S is linear plus quadratic in the displacement u, so

    K_sigma0[u] = (K_sigma(X + u) - K_sigma(X - u)) / 2

is exactly the part linear in u (the quadratic part cancels), for any size of u.

The paper's alternative for programs that only output tangents (ABAQUS): with the mode
scaled down to s phi, (K_T(X + s phi) - K_L(X + s phi)) / s, K_L the linear stiffness of the
mesh moved to X + s phi. It differs from K_sigma0[phi] by terms of order s (the initial
displacement matrix is not exactly the linear stiffness of the moved mesh) and by the
round-off of a difference of two large matrices divided by s.

Where they cannot work: for a flat plate the linear stress of a bending mode is
antisymmetric through the thickness, so its K_sigma0 integrates to (nearly) zero over the
thickness, while the real stiffening comes from membrane stress that grows with the square
of the deflection. See README "Modal flexible bodies".
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla

from ..body import Body
from ..mesh import Mesh

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from .reduction import ModalBasis

__all__ = [
    "linear_geometric_stiffness",
    "mode_geometric_stiffness",
    "scaled_mode_geometric_stiffness",
    "load_geometric_stiffness",
]


def _require_stvk(body: Body) -> None:
    if not isinstance(body, Body) or body.model != "stvk":
        raise ValueError("the geometric stiffness needs a Body with model='stvk' (its stress measure)")


def _nodes(vector: np.ndarray) -> np.ndarray:
    return vector.reshape(-1, 3)


def linear_geometric_stiffness(body: Body, displacement: ArrayLike) -> sp.csr_matrix:
    """K_sigma0[u]: the geometric stiffness (3n x 3n sparse) of the linear stress state of the
    displacement u ((n, 3) or (3n,)), exact for a StVK body."""
    _require_stvk(body)
    u = np.asarray(displacement, dtype=np.float64).reshape(-1, 3)
    X = body.mesh.points
    return 0.5 * (body.geometric_stiffness(X + u) - body.geometric_stiffness(X - u))


def _project(basis: ModalBasis, K: Any) -> np.ndarray:
    P = basis.vectors
    Kr = P.T @ (K @ P)
    return np.asarray(Kr)


def mode_geometric_stiffness(body: Body, basis: ModalBasis) -> np.ndarray:
    """The paper's eqs 9-10: A[:, :, i] = Phi^T K_sigma0[phi_i] Phi for each basis vector i, an
    (r, r, r) tensor A[l, k, i] for ModalBody(quadratic=...), whose force is eq (11):
    f = -1/2 sum_i q_i A_i q."""
    _require_stvk(body)
    r = basis.size
    A = np.empty((r, r, r))
    for i in range(r):
        A[:, :, i] = _project(basis, linear_geometric_stiffness(body, basis.vectors[:, i]))
    return A


def scaled_mode_geometric_stiffness(body: Body, basis: ModalBasis, amplitude: float = 1e-3) -> np.ndarray:
    """The paper's alternative to mode_geometric_stiffness: for each mode, (K_T(X + s phi) -
    K_L(X + s phi)) / s projected on the basis, s chosen so that the largest nodal
    displacement is ``amplitude`` times the mesh's largest extent. Returns (r, r, r) like
    mode_geometric_stiffness."""
    _require_stvk(body)
    if not (np.isfinite(amplitude) and amplitude > 0):
        raise ValueError("amplitude must be a positive number")
    mesh = body.mesh
    size = float(np.ptp(mesh.points, axis=0).max())
    r = basis.size
    A = np.empty((r, r, r))
    for i in range(r):
        phi = basis.vectors[:, i]
        s = amplitude * size / np.abs(phi).max()
        x = mesh.points + s * _nodes(phi)
        moved = Body(Mesh(x, mesh.cells, mesh.cell_type), body.materials, model="linear", regions=body.regions)
        K = (body.tangent_matrix(x) - moved.stiffness_matrix()) / s
        A[:, :, i] = _project(basis, K)
    return A


def load_geometric_stiffness(body: Body, basis: ModalBasis, loads: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Eqs 7-8 (SIMPACK): for each unit load case P_i ((k, n, 3) nodal forces), the linear
    static displacement u_i = K^-1 P_i (with the basis's fixed DOFs), K_sigma0^i =
    K_sigma0[u_i] and its modal projection. Returns (modal loads (k, r) = Phi^T P_i, modal
    geometric stiffness (k, r, r)) for ModalBody.set_load_cases."""
    _require_stvk(body)
    n = body.n_nodes
    P = np.array(loads, dtype=np.float64, ndmin=3)
    if P.shape[1:] != (n, 3) or not np.all(np.isfinite(P)):
        raise ValueError(f"loads must be a finite (k, {n}, 3) array of unit load cases")
    free = np.setdiff1d(np.arange(3 * n), basis.fixed_dofs)
    K = body.stiffness_matrix().tocsc()
    solve = sla.factorized(K[free][:, free].tocsc())
    modal_loads = np.empty((len(P), basis.size))
    geometric = np.empty((len(P), basis.size, basis.size))
    for i, load in enumerate(P):
        f = load.ravel()
        u = np.zeros(3 * n)
        u[free] = solve(f[free])
        modal_loads[i] = basis.vectors.T @ f
        geometric[i] = _project(basis, linear_geometric_stiffness(body, u))
    return modal_loads, geometric
