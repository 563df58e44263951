"""A deformable body: a mesh, a material and a force model."""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from . import _core
from .material import Material
from .mesh import Mesh

MODELS = ("corotational", "linear")


def _csr(triple, n_dofs: int) -> sp.csr_matrix:
    data, indices, indptr = triple
    return sp.csr_matrix((data, indices, indptr), shape=(n_dofs, n_dofs))


class Body:
    """A mesh of one cell type with a material and a force model.

    mesh      Mesh (tetra, hexahedron or hexahedron20 cells)
    material  Material
    model     "corotational" (per-element rotation, eqs 3-4 of the paper; default) or
              "linear" (small-displacement FEM, f = -K (x - X))

    Element matrices are computed when the body is created; degenerate or inverted
    elements raise ValueError naming the element.
    """

    def __init__(self, mesh: Mesh, material: Material, model: str = "corotational"):
        if not isinstance(mesh, Mesh):
            raise TypeError("mesh must be a corotate.Mesh (see corotate.read_mesh, corotate.box)")
        if not isinstance(material, Material):
            raise TypeError("material must be a corotate.Material")
        if model not in MODELS:
            raise ValueError(f"unknown model {model!r}; choose one of {', '.join(MODELS)}")
        self.mesh = mesh
        self.material = material
        self.model = model
        self._force_model = _core.ForceModel(model, mesh.cell_type, mesh.points, mesh.cells, material._core())

    @property
    def n_nodes(self) -> int:
        return self.mesh.n_nodes

    def internal_forces(self, positions) -> np.ndarray:
        """Internal elastic forces (n, 3) at positions (n, 3)."""
        return self._force_model.internal_forces(self._check_positions(positions))

    def energy(self, positions) -> float:
        """Elastic energy at positions (n, 3)."""
        return self._force_model.energy(self._check_positions(positions))

    def stiffness_matrix(self, positions=None) -> sp.csr_matrix:
        """Stiffness K (3n x 3n, DOF = 3*node + axis) at positions (default: rest).

        For the co-rotational model this is the rotated stiffness sum R_e K_e R_e^T."""
        x = self.mesh.points if positions is None else self._check_positions(positions)
        return _csr(self._force_model.stiffness_csr(x), 3 * self.n_nodes)

    def mass_matrix(self, lumped: bool = False) -> sp.csr_matrix:
        """Consistent (default) or lumped mass matrix (3n x 3n)."""
        return _csr(self._force_model.mass_csr(bool(lumped)), 3 * self.n_nodes)

    def _check_positions(self, positions) -> np.ndarray:
        x = np.ascontiguousarray(positions, dtype=np.float64)
        if x.shape != (self.n_nodes, 3):
            raise ValueError(f"positions must have shape ({self.n_nodes}, 3), got {x.shape}")
        return x
