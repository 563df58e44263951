"""Craig-Bampton reduction of a body to a few modes, orthonormalised as ADAMS does.

The basis of a Craig-Bampton model (Craig & Bampton 1968) holds two kinds of shapes:

* fixed-boundary normal modes: eigenvectors of K phi = omega^2 M phi with the fixed DOFs and
  the interface (boundary) DOFs held at zero;
* constraint modes: the static shape of a unit displacement of one interface DOF with all
  other interface DOFs held, psi = -K_ii^-1 K_ib for the interior DOFs i.

Their union is not orthogonal. Solving the reduced eigenproblem T^T K T v = w^2 T^T M T v and
taking Phi = T V makes it so: Phi^T M Phi = I and Phi^T K Phi = diag(w^2), the form a
multibody program integrates. Static loads at the interface nodes are then reproduced
exactly (the constraint modes span the static response to them); other loads are
approximated by the normal modes, better with more of them.

K and M are the body's stiffness at rest and its consistent mass (every force model has the
same K at rest). One sparse factorisation of K_ii serves the constraint modes and the
shift-invert eigen solve (ARPACK through SciPy's eigsh).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
import scipy.sparse.linalg as sla

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from ..body import Body

__all__ = ["BasisWarning", "ModalBasis", "craig_bampton", "node_dofs"]


def node_dofs(nodes: ArrayLike, n_nodes: int, what: str = "nodes") -> np.ndarray:
    """The DOF indices 3*node + axis of the given nodes (all three axes), checked."""
    idx = np.asarray(nodes)
    if idx.dtype == bool:
        if idx.shape != (n_nodes,):
            raise ValueError(f"a boolean {what} mask needs one entry per node ({n_nodes})")
        idx = np.flatnonzero(idx)
    idx = idx.ravel()
    if idx.size and not np.issubdtype(idx.dtype, np.integer):
        raise ValueError(f"{what} must be integer node indices, got dtype {idx.dtype}")
    idx = idx.astype(np.int64)
    bad = idx[(idx < 0) | (idx >= n_nodes)]
    if bad.size:
        raise ValueError(f"{what}: node {int(bad[0])} is out of range [0, {n_nodes})")
    return (3 * np.unique(idx)[:, None] + np.arange(3)).ravel()


@dataclass(frozen=True)
class ModalBasis:
    """An M-orthonormal reduction basis and what it was built from.

    vectors          (3n, r) C-contiguous float64, DOF = 3*node + axis; zero on fixed DOFs.
                     vectors.T @ M @ vectors = I, vectors.T @ K @ vectors = diag(eigenvalues).
    eigenvalues      (r,) omega^2 of the reduced model [1/s^2], ascending.
    rest_positions   (n, 3) the mesh's rest positions.
    fixed_dofs       DOF indices held at zero.
    interface_nodes  node indices whose constraint modes are in the basis.
    n_normal_modes   fixed-boundary normal modes used.
    n_extra          extra vectors (modal derivatives, static shapes...) kept in the basis.
    """

    vectors: np.ndarray
    eigenvalues: np.ndarray
    rest_positions: np.ndarray
    fixed_dofs: np.ndarray
    interface_nodes: np.ndarray
    n_normal_modes: int
    n_extra: int = 0

    def __post_init__(self) -> None:
        """Check everything at construction, in the user's terms (a NaN in a vector would
        give NaN displacements, a wrong shape a raw IndexError steps later); store the
        arrays as C-contiguous float64 / int64 copies."""
        rest = _finite_array(self.rest_positions, "rest_positions")
        if rest.ndim != 2 or rest.shape[1] != 3:
            raise ValueError(f"ModalBasis rest_positions must have shape (n, 3), got {rest.shape}")
        n = rest.shape[0]
        vectors = _finite_array(self.vectors, "vectors")
        if vectors.ndim != 2 or vectors.shape[0] != 3 * n or vectors.shape[1] < 1:
            raise ValueError(
                f"ModalBasis vectors must have shape (3n, r) = ({3 * n}, r), one row per DOF of the {n} rest "
                f"positions and r >= 1 columns, got {vectors.shape}"
            )
        r = vectors.shape[1]
        eigenvalues = _finite_array(self.eigenvalues, "eigenvalues")
        if eigenvalues.shape != (r,):
            raise ValueError(f"ModalBasis eigenvalues must have shape ({r},), one per vector, got {eigenvalues.shape}")
        fixed = _index_array(self.fixed_dofs, 3 * n, "fixed_dofs", "DOF")
        interface = _index_array(self.interface_nodes, n, "interface_nodes", "node")
        for name in ("n_normal_modes", "n_extra"):
            value = getattr(self, name)
            if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)) or value < 0:
                raise ValueError(f"ModalBasis {name} must be an integer >= 0, got {value!r}")
            object.__setattr__(self, name, int(value))
        for name, value in (
            ("rest_positions", rest),
            ("vectors", vectors),
            ("eigenvalues", eigenvalues),
            ("fixed_dofs", fixed),
            ("interface_nodes", interface),
        ):
            object.__setattr__(self, name, value)

    @property
    def size(self) -> int:
        """Number of basis vectors r."""
        return int(self.vectors.shape[1])

    @property
    def frequencies(self) -> np.ndarray:
        """(r,) natural frequencies of the reduced model [Hz]."""
        return np.sqrt(np.maximum(self.eigenvalues, 0.0)) / (2 * np.pi)


def _finite_array(value: ArrayLike, name: str) -> np.ndarray:
    try:
        a = np.array(value, dtype=np.float64, order="C")
    except (TypeError, ValueError) as e:
        raise ValueError(f"ModalBasis {name} must be an array of numbers ({e})") from None
    bad = np.argwhere(~np.isfinite(a))
    if len(bad):
        where = ", ".join(map(str, bad[0].tolist()))
        raise ValueError(f"ModalBasis {name} holds {a[tuple(bad[0])]} at [{where}] ({len(bad)} non-finite value(s))")
    return a


def _index_array(value: ArrayLike, end: int, name: str, what: str) -> np.ndarray:
    a = np.asarray(value)
    if a.ndim != 1 or (a.size and a.dtype.kind not in "iu"):
        raise ValueError(f"ModalBasis {name} must be a 1-D array of integer {what} indices, got shape {a.shape}")
    a = a.astype(np.int64)
    bad = a[(a < 0) | (a >= end)]
    if bad.size:
        raise ValueError(f"ModalBasis {name}: {what} {int(bad[0])} is out of range [0, {end})")
    return a


def _free_dofs(n_dofs: int, fixed_dofs: np.ndarray) -> np.ndarray:
    return np.setdiff1d(np.arange(n_dofs), fixed_dofs)


def _fixed_dof_set(n_nodes: int, fixed_nodes: ArrayLike, fixed_dofs: ArrayLike | None) -> np.ndarray:
    fixed = node_dofs(fixed_nodes, n_nodes, "fixed_nodes")
    if fixed_dofs is not None:
        extra = np.asarray(fixed_dofs).ravel()
        if extra.size and not np.issubdtype(extra.dtype, np.integer):
            raise ValueError("fixed_dofs must be integer DOF indices (3*node + axis)")
        if extra.size and (extra.min() < 0 or extra.max() >= 3 * n_nodes):
            raise ValueError(f"fixed_dofs must lie in [0, {3 * n_nodes})")
        fixed = np.union1d(fixed, extra.astype(np.int64))
    return fixed


class BasisWarning(UserWarning):
    """A reduction basis built without a vector the caller handed in (it is linearly
    dependent on the vectors before it)."""


#: A column whose part outside the span of the columns before it is below this share of its
#: own M-norm is linearly dependent on them (round-off leaves ~1e-14 of a truly dependent one).
DEPENDENCY_RTOL = 1e-9


def orthonormalize(
    vectors: np.ndarray, K: sp.spmatrix, M: sp.spmatrix, rtol: float = DEPENDENCY_RTOL
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Basis Phi spanning the columns of ``vectors`` with Phi^T M Phi = I and Phi^T K Phi =
    diag(w^2) (the reduced eigenproblem), the w^2 ascending, and the indices of the columns
    dropped as linearly dependent.

    The columns are M-orthonormalised one after the other (Gram-Schmidt, each projection
    done twice so the result is orthogonal to round-off). A column is dependent when what is
    left of it after projecting out the columns before it is below rtol times its own M-norm:
    the test is relative per column, so a column's scale (a static shape of 1e-8 m next to
    unit-norm modes) does not decide whether it is kept."""
    M = sp.csr_matrix(M)
    Q = np.zeros((vectors.shape[0], vectors.shape[1]))
    MQ = np.zeros_like(Q)
    kept = 0
    dropped = []
    for j in range(vectors.shape[1]):
        v = vectors[:, j]
        peak = np.abs(v).max()
        v = v / peak if peak > 0 else v  # scale to O(1) before squaring: no under- or overflow
        norm = np.sqrt(max(float(v @ (M @ v)), 0.0))
        for _ in range(2):
            v = v - Q[:, :kept] @ (MQ[:, :kept].T @ v)
        Mv = M @ v
        rest = np.sqrt(max(float(v @ Mv), 0.0))
        if norm == 0.0 or rest <= rtol * norm:
            dropped.append(j)
            continue
        Q[:, kept] = v / rest
        MQ[:, kept] = Mv / rest
        kept += 1
    Q = Q[:, :kept]
    Kr = Q.T @ (K @ Q)
    lam, V = la.eigh(0.5 * (Kr + Kr.T))
    return np.ascontiguousarray(Q @ V), lam, np.array(dropped, dtype=np.int64)


def craig_bampton(
    body: Body,
    fixed_nodes: ArrayLike,
    n_modes: int,
    interface_nodes: ArrayLike = (),
    fixed_dofs: ArrayLike | None = None,
    extra_vectors: ArrayLike | None = None,
) -> ModalBasis:
    """Reduce ``body`` to an orthonormalised Craig-Bampton basis.

    body             the body (its stiffness at rest and consistent mass are used)
    fixed_nodes      nodes clamped in all three axes (int indices or a boolean mask)
    n_modes          number of fixed-boundary normal modes (>= 0; at least one vector overall)
    interface_nodes  nodes whose 3 DOFs each get a constraint mode (e.g. loaded or joint nodes)
    fixed_dofs       further single DOFs held at zero (3*node + axis), e.g. for pinned supports
    extra_vectors    (3n, k) further shapes to include (e.g. modal derivatives); their fixed
                     DOFs are zeroed
    returns          ModalBasis with r = n_modes + 3 * len(interface_nodes) + k vectors; an
                     extra vector that is linearly dependent on the vectors before it (judged
                     relative to its own norm, so its scale does not matter) is left out with
                     a BasisWarning naming its column

    Raises ValueError for out-of-range nodes, interface nodes that are also fixed, or more
    modes than the free interior DOFs; RuntimeError when the body is not held (K_ii singular).
    """
    if isinstance(n_modes, (bool, np.bool_)) or not isinstance(n_modes, (int, np.integer)) or n_modes < 0:
        raise ValueError(f"n_modes must be an integer >= 0, got {n_modes!r}")
    n = body.n_nodes
    fixed = _fixed_dof_set(n, fixed_nodes, fixed_dofs)
    boundary = node_dofs(interface_nodes, n, "interface_nodes")
    if np.intersect1d(boundary, fixed).size:
        raise ValueError("an interface node is also fixed: a fixed node cannot carry a constraint mode")
    interior = np.setdiff1d(_free_dofs(3 * n, fixed), boundary)
    if n_modes > interior.size - 2:
        raise ValueError(f"n_modes={n_modes} exceeds what the {interior.size} interior DOFs allow")
    extra = None
    if extra_vectors is not None:
        extra = np.array(extra_vectors, dtype=np.float64, ndmin=2)
        if extra.shape[0] != 3 * n:
            raise ValueError(f"extra_vectors must have shape (3n, k) = ({3 * n}, k), got {extra.shape}")
        if not np.all(np.isfinite(extra)):
            raise ValueError("extra_vectors must be finite")
        extra[fixed] = 0.0
    if n_modes + boundary.size + (0 if extra is None else extra.shape[1]) == 0:
        raise ValueError("the basis would be empty: ask for normal modes, interface nodes or extra vectors")

    K = body.stiffness_matrix().tocsc()
    M = body.mass_matrix(lumped=False).tocsc()
    Kii = K[interior][:, interior].tocsc()
    Mii = M[interior][:, interior].tocsc()
    try:
        factor = sla.splu(Kii)
    except RuntimeError as err:
        raise RuntimeError(f"the interior stiffness is singular (is the body held?): {err}") from None

    columns = []
    if n_modes:
        op = sla.LinearOperator(Kii.shape, matvec=factor.solve, dtype=np.float64)
        # A fixed start vector: ARPACK's default is random, and the modes it returns then differ from
        # call to call by its tolerance (a 2e-10 principal angle on a thin plate), so the same
        # input would not give the same basis. A seeded random vector is as unlikely as ARPACK's own
        # to be orthogonal to a wanted mode (a constant one would be, to every antisymmetric mode).
        start = np.random.default_rng(0).standard_normal(interior.size)
        lam, vecs = sla.eigsh(Kii, k=n_modes, M=Mii, sigma=0.0, which="LM", OPinv=op, v0=start)
        order = np.argsort(lam)
        block = np.zeros((3 * n, n_modes))
        block[interior] = vecs[:, order]
        columns.append(block)
    if boundary.size:
        Kib = K[interior][:, boundary].toarray()
        block = np.zeros((3 * n, boundary.size))
        block[interior] = -factor.solve(Kib)
        block[boundary, np.arange(boundary.size)] = 1.0
        columns.append(block)
    if extra is not None:
        columns.append(extra)
    vectors, eigenvalues, dropped = orthonormalize(np.hstack(columns), K, M)
    # The modes and constraint modes come first and are independent by construction (a
    # fixed-boundary mode is zero on the interface, a constraint mode is not): what is dropped
    # is an extra vector, named by its column in extra_vectors.
    for j in dropped - (n_modes + boundary.size):
        assert extra is not None  # only extra vectors can be dependent
        why = (
            "is linearly dependent on the modes and the extra vectors before it (what is new in it is below "
            f"{DEPENDENCY_RTOL:g} of its own norm)"
            if np.any(extra[:, j])
            else "is zero outside the fixed DOFs"
        )
        warnings.warn(f"extra_vectors[:, {j}] {why}: it is left out of the basis", BasisWarning, stacklevel=2)
    # A sparse LU of a singular K_ii need not fail; a rigid-body mode in the basis shows, with
    # an eigenvalue at round-off (~1e-16 of the element scale K_ii / M_ii). A slender body's
    # first mode is far below that scale but far above round-off (a 10 m cantilever of 8 cm
    # section: 5e-10 of it), so the threshold sits between the two.
    scale = float(np.median(K.diagonal()[interior] / M.diagonal()[interior]))
    if eigenvalues[0] <= 1e-12 * scale:
        raise RuntimeError(
            "the interior stiffness is singular: the body is not held (a rigid-body mode has zero frequency)"
        )
    return ModalBasis(
        vectors=vectors,
        eigenvalues=eigenvalues,
        rest_positions=body.mesh.points.copy(),
        fixed_dofs=fixed,
        interface_nodes=np.unique(boundary // 3),
        n_normal_modes=int(n_modes),
        n_extra=0 if extra is None else int(extra.shape[1]) - len(dropped),
    )
