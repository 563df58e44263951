"""Mass-spring bodies (paper §2.1): point masses joined by springs with stiffness k,
damping d and rest length l0; elastic force eq. (1), damping force eq. (2).

Builders: :meth:`MassSpringBody.cloth` (grid with structural, shear and bending springs,
the paper's Fig. 1), :meth:`MassSpringBody.lattice` (cube cells with edges, face and room
diagonals, Fig. 2) and :meth:`MassSpringBody.from_mesh` (springs on the elements of a tet
or hex mesh, so one mesh runs as mass-spring or as FEM). They set k from a Young's
modulus by the rule in ``cpp/include/corotate/models/spring_builders.hpp``: every cell
adds alpha_s E V / l_s^2 to each of its springs, which keeps the small-strain stiffness of
every homogeneous strain independent of the resolution; the cube lattice then behaves
like an isotropic solid with Young's modulus E and Poisson ratio 1/4, the cloth like a
membrane with E t and Poisson ratio 1/3 (the only ratios central springs can give). The
damping follows d = beta k (the spring form of Rayleigh damping beta K).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

import corotate._core as _core

from .material import Material
from .mesh import Mesh

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["MassSpringBody", "SpringGeometry"]

SPRING_KINDS = ("structural", "shear", "bending")  # cloth; lattice/mesh: edge, face diagonal, room diagonal


@dataclass
class SpringGeometry:
    """Cells to draw or write a mass-spring body with (TimeSeriesWriter accepts it).

    points     (n, 3) rest positions
    cells      (c, k) node indices
    cell_type  meshio name: "quad" (cloth), "hexahedron" (lattice), the mesh's type, or "line"
    """

    points: np.ndarray
    cells: np.ndarray
    cell_type: str

    @property
    def n_nodes(self) -> int:
        return self.points.shape[0]


def _per_item(value: ArrayLike, n: int, name: str) -> np.ndarray:
    a = np.asarray(value, dtype=np.float64)
    if a.ndim == 0:
        return np.full(n, float(a))
    if a.shape != (n,):
        raise ValueError(f"{name} must be a scalar or have shape ({n},), got {a.shape}")
    return np.ascontiguousarray(a)


def _csr(triple: tuple[np.ndarray, np.ndarray, np.ndarray], n_dofs: int) -> sp.csr_matrix:
    data, indices, indptr = triple
    return sp.csr_matrix((data, indices, indptr), shape=(n_dofs, n_dofs))


class MassSpringBody:
    """Point masses joined by linear springs.

    nodes         (n, 3) rest positions [m]
    springs       (m, 2) node index pairs
    stiffness     k [N/m]: scalar or (m,), >= 0
    masses        [kg]: scalar or (n,), > 0
    damping       d [N s/m]: scalar or (m,), >= 0 (default 0)
    rest_lengths  l0 [m]: (m,) (default: the distances in ``nodes``)
    geometry      SpringGeometry for output (default: the springs as lines)
    kinds         (m,) int spring class (0/1/2: structural/shear/bending for cloth; edge/face
                  diagonal/room diagonal for lattices and meshes), informative only

    Bad input raises ValueError naming the node or spring: mass <= 0, k < 0, a node index
    out of range, a spring between coincident nodes (zero length: no direction).
    """

    def __init__(
        self,
        nodes: ArrayLike,
        springs: ArrayLike,
        stiffness: ArrayLike,
        masses: ArrayLike,
        damping: ArrayLike = 0.0,
        rest_lengths: ArrayLike | None = None,
        geometry: SpringGeometry | None = None,
        kinds: ArrayLike | None = None,
    ) -> None:
        x = np.ascontiguousarray(nodes, dtype=np.float64)
        if x.ndim != 2 or x.shape[1] != 3:
            raise ValueError(f"nodes must have shape (n, 3), got {x.shape}")
        s = np.asarray(springs)
        if s.size == 0:
            s = s.reshape(0, 2)
        if s.ndim != 2 or s.shape[1] != 2:
            raise ValueError(f"springs must have shape (m, 2), got {s.shape}")
        if s.size and not np.issubdtype(s.dtype, np.integer):
            raise ValueError("spring node indices must be integers")
        s = np.ascontiguousarray(s, dtype=np.int64)
        n, m = x.shape[0], s.shape[0]
        bad = np.flatnonzero(((s < 0) | (s >= n)).any(axis=1))
        if bad.size:
            k = int(bad[0])
            node = int(s[k, 0] if not 0 <= s[k, 0] < n else s[k, 1])
            raise ValueError(f"spring {k} refers to node {node}, out of range [0, {n})")
        if rest_lengths is None:
            rest_lengths = np.linalg.norm(x[s[:, 1]] - x[s[:, 0]], axis=1) if m else np.zeros(0)
        self.nodes = x
        self.springs = s
        self.stiffness = _per_item(stiffness, m, "stiffness")
        self.damping = _per_item(damping, m, "damping")
        self.rest_lengths = _per_item(rest_lengths, m, "rest_lengths")
        self.masses = _per_item(masses, n, "masses")
        self.kinds = np.zeros(m, dtype=np.int64) if kinds is None else np.asarray(kinds, dtype=np.int64)
        self.geometry = geometry if geometry is not None else SpringGeometry(x, s, "line")
        # Validates everything else (masses, k, d, l0, coincident nodes) with named messages.
        self._model = _core.MassSpring(x, s, self.stiffness, self.damping, self.rest_lengths, self.masses)

    # --- builders ----------------------------------------------------------------------
    @classmethod
    def _from_system(cls, d: dict, nodes: np.ndarray | None = None) -> MassSpringBody:
        x = d["nodes"] if nodes is None else nodes
        geometry = SpringGeometry(x, np.ascontiguousarray(d["cells"], dtype=np.int64), d["cell_type"])
        return cls(x, d["springs"], d["stiffness"], d["masses"], d["damping"], d["rest_lengths"], geometry, d["kinds"])

    @classmethod
    def cloth(
        cls,
        nx: int = 32,
        ny: int = 32,
        size: Sequence[float] = (1.0, 1.0),
        E: float = 1e6,
        thickness: float = 1e-3,
        density: float = 1000.0,
        bending: float = 0.01,
        beta: float = 0.0,
        plane: str = "xy",
        origin: ArrayLike = (0.0, 0.0, 0.0),
    ) -> MassSpringBody:
        """A rectangular cloth of nx x ny particles (the paper's Fig. 1).

        size       (width, height) [m]; the cloth spans [0, width] x [0, height] in ``plane``
                   ("xy": horizontal at z = 0; "xz": vertical at y = 0), shifted by origin
        E          Young's modulus [Pa]; thickness [m]; density [kg/m^3]
        bending    bending springs' stiffness as a fraction of E * thickness (0: none)
        beta       damping time [s]: d = beta k
        Node (i, j), i along the first axis, has index j * nx + i. Springs: structural
        (kind 0), shear (1), bending (2); geometry: quads.
        """
        d = _core.cloth_grid(
            int(nx),
            int(ny),
            float(size[0]),
            float(size[1]),
            float(E),
            float(thickness),
            float(density),
            float(bending),
            float(beta),
        )
        x = d["nodes"]
        if plane == "xz":
            x = np.ascontiguousarray(x[:, [0, 2, 1]])
        elif plane != "xy":
            raise ValueError(f"unknown plane {plane!r}; choose 'xy' or 'xz'")
        return cls._from_system(d, x + np.asarray(origin, dtype=np.float64))

    @classmethod
    def lattice(
        cls,
        cells: Sequence[int] = (4, 4, 4),
        size: ArrayLike = (1.0, 1.0, 1.0),
        E: float = 1e6,
        density: float = 1000.0,
        beta: float = 0.0,
        origin: ArrayLike = (0.0, 0.0, 0.0),
    ) -> MassSpringBody:
        """A box of cube cells with springs along edges, face and room diagonals (Fig. 2).

        cells   (nx, ny, nz) cubes; size (3,) extent [m] from origin
        E       Young's modulus [Pa]: with cubic cells the lattice is isotropic with this E
                and Poisson ratio 1/4 at every resolution; density [kg/m^3]
        beta    damping time [s]: d = beta k
        Node (i, j, k) has index (k * (ny + 1) + j) * (nx + 1) + i; geometry: hexahedra.
        """
        c = [int(v) for v in cells]
        d = _core.cube_lattice(
            c[0], c[1], c[2], np.asarray(size, dtype=np.float64), float(E), float(density), float(beta)
        )
        return cls._from_system(d, d["nodes"] + np.asarray(origin, dtype=np.float64))

    @classmethod
    def from_mesh(cls, mesh: Mesh, material: Material, diagonals: bool = True, beta: float = 0.0) -> MassSpringBody:
        """Springs on the elements of a tetra or hexahedron mesh.

        Each element's edges get springs (hexahedra also face and room diagonals unless
        diagonals=False, which leaves zero-energy shear modes); k from material.E by the
        rule that keeps the energy of a uniform dilation exact for any element shape
        (material.nu is not representable: central springs have nu = 1/4); masses
        density x element volume shared by the element's nodes; d = beta k.
        """
        if not isinstance(mesh, Mesh):
            raise TypeError("mesh must be a corotate.Mesh")
        if not isinstance(material, Material):
            raise TypeError("material must be a corotate.Material")
        d = _core.springs_from_mesh(
            mesh.points,
            mesh.cells,
            mesh.cell_type,
            float(material.E),
            float(material.density),
            float(beta),
            bool(diagonals),
        )
        return cls._from_system(d)

    # --- queries -----------------------------------------------------------------------
    @property
    def n_nodes(self) -> int:
        return self.nodes.shape[0]

    @property
    def n_springs(self) -> int:
        return self.springs.shape[0]

    @property
    def total_mass(self) -> float:
        return float(self.masses.sum())

    def internal_forces(self, positions: ArrayLike) -> np.ndarray:
        """Elastic spring forces (n, 3) of eq. (1) at positions (n, 3)."""
        return self._model.internal_forces(self._check(positions))

    def damping_forces(self, positions: ArrayLike, velocities: ArrayLike) -> np.ndarray:
        """Damping forces (n, 3) of eq. (2) at positions and velocities (n, 3)."""
        return self._model.damping_forces(self._check(positions), self._check(velocities, "velocities"))

    def energy(self, positions: ArrayLike) -> float:
        """Spring energy sum k (l - l0)^2 / 2 at positions (n, 3)."""
        return self._model.energy(self._check(positions))

    def stiffness_matrix(self, positions: ArrayLike | None = None) -> sp.csr_matrix:
        """K = -d f / d x (3n x 3n, DOF = 3*node + axis) at positions (default: rest)."""
        x = self.nodes if positions is None else self._check(positions)
        return _csr(self._model.stiffness_csr(x), 3 * self.n_nodes)

    def damping_matrix(self, positions: ArrayLike | None = None) -> sp.csr_matrix:
        """C = -d f_damping / d v (3n x 3n) at positions (default: rest)."""
        x = self.nodes if positions is None else self._check(positions)
        return _csr(self._model.damping_csr(x), 3 * self.n_nodes)

    def stiffness_bound(self) -> sp.csr_matrix:
        """The configuration-independent upper bound of K: blocks k I (3n x 3n)."""
        return _csr(self._model.stiffness_bound_csr(), 3 * self.n_nodes)

    def mass_matrix(self) -> sp.csr_matrix:
        """Diagonal mass matrix (3n x 3n)."""
        return sp.diags(np.repeat(self.masses, 3)).tocsr()

    def _check(self, positions: ArrayLike | None, what: str = "positions") -> np.ndarray:
        x = np.ascontiguousarray(positions, dtype=np.float64)
        if x.shape != (self.n_nodes, 3):
            raise ValueError(f"{what} must have shape ({self.n_nodes}, 3), got {x.shape}")
        return x

    def __repr__(self) -> str:
        return f"MassSpringBody({self.n_nodes} nodes, {self.n_springs} springs, {self.total_mass:.4g} kg)"
