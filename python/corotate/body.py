"""A deformable body: a mesh, its material(s) and a force model."""

from __future__ import annotations

from typing import TYPE_CHECKING, ClassVar

import numpy as np
import scipy.sparse as sp

import corotate._core as _core

from ._attributes import SettableOnly
from .choices import MODELS, ModelName
from .material import Material
from .mesh import Mesh
from .regions import Materials, check_cell_regions, dense_regions, materials_by_region
from .surfaces import boundary_triangles, surface_nodes

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

#: Models that are full geometrically nonlinear (hyperelastic, total Lagrangian).
HYPERELASTIC_MODELS = tuple(m for m in MODELS if m not in ("linear", "corotational"))


def _csr(triple: tuple[np.ndarray, np.ndarray, np.ndarray], n_dofs: int) -> sp.csr_matrix:
    data, indices, indptr = triple
    return sp.csr_matrix((data, indices, indptr), shape=(n_dofs, n_dofs))


_IMMUTABLE = "a Body is immutable after construction (simulations step copies of its model); create a new Body"


def _read_only_copy(mesh: Mesh, check: bool = True) -> Mesh:
    """A copy of mesh (checked afresh: the caller may have changed it since it was built;
    check=False for a mesh the library built from checked parts) whose arrays cannot be
    written."""
    if check:
        copy = Mesh(mesh.points, mesh.cells, mesh.cell_type, mesh.cell_regions)
    else:
        from .mesh_checks import _unchecked

        regions = None if mesh.cell_regions is None else mesh.cell_regions.copy()
        copy = _unchecked(Mesh, mesh.points.copy(), mesh.cells.copy(), mesh.cell_type, regions)
    copy.points.flags.writeable = False
    copy.cells.flags.writeable = False
    return copy


class ModelQueries:
    """The force model's answers at given positions, for Body and JoinedBody (which provide
    ``_force_model``, ``n_nodes`` and ``_rest_points``)."""

    _force_model: _core.ForceModel

    @property
    def n_nodes(self) -> int:
        raise NotImplementedError

    @property
    def _rest_points(self) -> np.ndarray:
        raise NotImplementedError

    def internal_forces(self, positions: ArrayLike) -> np.ndarray:
        """Internal elastic forces (n, 3) at positions (n, 3)."""
        return self._force_model.internal_forces(self._check_positions(positions))

    def energy(self, positions: ArrayLike) -> float:
        """Elastic energy at positions (n, 3)."""
        return self._force_model.energy(self._check_positions(positions))

    def stiffness_matrix(self, positions: ArrayLike | None = None) -> sp.csr_matrix:
        """Stiffness K (3n x 3n, DOF = 3*node + axis) at positions (default: rest).

        For the co-rotational model this is the rotated stiffness sum R_e K_e R_e^T; for the
        hyperelastic models the exact Hessian of the energy (element-wise PSD-projected with
        project_psd)."""
        x = self._rest_points if positions is None else self._check_positions(positions)
        return _csr(self._force_model.stiffness_csr(x), 3 * self.n_nodes)

    def geometric_stiffness(self, positions: ArrayLike | None) -> sp.csr_matrix:
        """Initial-stress (geometric) stiffness K_sigma at positions (n, 3), hyperelastic models.

        K_sigma has blocks sum_q w_q (G_a^T S G_b) I_3 (S the second Piola-Kirchhoff stress,
        G_a = dN_a/dX at quadrature point q), the stress part of K_T = K_0 + K_u + K_sigma
        (paper eq. 6). Raises ValueError for "linear" and "corotational"."""
        return _csr(self._force_model.geometric_stiffness_csr(self._check_positions(positions)), 3 * self.n_nodes)

    def tangent_matrix(self, positions: ArrayLike | None = None) -> sp.csr_matrix:
        """The exact tangent -df/dx (3n x 3n) at positions (default: rest): for the
        co-rotational model it includes the derivative of the rotations, which
        stiffness_matrix leaves out (for hexahedra it is not symmetric: their force is not
        the gradient of an energy); for the other models it equals stiffness_matrix."""
        x = self._rest_points if positions is None else self._check_positions(positions)
        return _csr(self._force_model.tangent_csr(x), 3 * self.n_nodes)

    def mass_matrix(self, lumped: bool = False) -> sp.csr_matrix:
        """Consistent (default) or lumped mass matrix (3n x 3n)."""
        return _csr(self._force_model.mass_csr(bool(lumped)), 3 * self.n_nodes)

    def _check_positions(self, positions: ArrayLike | None) -> np.ndarray:
        x = np.ascontiguousarray(positions, dtype=np.float64)
        if x.shape != (self.n_nodes, 3):
            raise ValueError(f"positions must have shape ({self.n_nodes}, 3), got {x.shape}")
        return x


class Body(ModelQueries, SettableOnly):
    """A mesh of one cell type with its material(s) and a force model.

    mesh      Mesh (any solid cell type of corotate.cell_types(); triangle cells for sheets)
    material  Material (every cell), or one per region: a list (region ids 0, 1, ...) or a
              dict {region id: Material}
    regions   (m,) int region id of each cell, for several materials; default: the mesh's
              cell_regions (read_mesh takes them from Gmsh physical groups). A region id
              without a material raises ValueError naming the cell. Every model, the mass
              (each cell's density), modal reductions and force feedback use each cell's
              material; a body of one region is the homogeneous body exactly.
    model     "corotational" (per-element rotation, eqs 3-4 of the paper; default),
              "linear" (small-displacement FEM, f = -K (x - X)), or a full nonlinear
              (hyperelastic, total-Lagrangian) model with exact tangent stiffness:
              "stvk" (St. Venant-Kirchhoff, W = mu E:E + lambda/2 tr(E)^2, E the Green
              strain), "neohookean" (stable Neo-Hookean of Smith et al. 2018, defined and
              finite for inverted elements), "fixed_corotated" (fixed co-rotated, Stomakhin
              et al. 2012), "neohookean_log" (the classic compressible Neo-Hookean, undefined
              for inverted elements) or "mooney_rivlin" (C10, C01 and a bulk modulus, in
              isochoric invariants: cr.Material(law="mooney_rivlin", C10=..., C01=..., bulk=...)).
              All agree at small strain (same stiffness at rest).
    thickness sheet thickness [m] for triangle meshes (required there; membranes support
              model="stvk" only, with plane-stress Lame parameters). Not for solids.
    project_psd  hyperelastic models: project each element stiffness onto the nearest
              positive semi-definite matrix (for implicit solves of compressed or inverted
              states); the stiffness is then no longer the exact Hessian there.

    Element matrices are computed when the body is created; degenerate or inverted
    elements (zero-area triangles) raise ValueError naming the element.

    A Body is immutable: mesh, material, model, thickness and project_psd are read-only
    (assigning raises AttributeError); for another material create a new Body. The body
    keeps its own copy of the mesh, with read-only arrays: changing the Mesh passed in
    afterwards (``mesh.points[:, 2] += 1``) changes neither the body nor its simulations.
    """

    _READ_ONLY_HINTS: ClassVar[dict[str, str]] = {
        name: _IMMUTABLE
        for name in ("mesh", "material", "materials", "regions", "model", "thickness", "project_psd", "n_nodes")
    }

    def __init__(
        self,
        mesh: Mesh,
        material: Materials,
        model: ModelName = "corotational",
        thickness: float | None = None,
        project_psd: bool = False,
        regions: ArrayLike | None = None,
        *,
        _parts_checked: bool = False,
    ) -> None:
        # _parts_checked (internal): a Scene's joined mesh, each of whose parts was checked
        # as a Body's mesh; joined, their nodes may coincide where they touch.
        if not isinstance(mesh, Mesh):
            raise TypeError("mesh must be a corotate.Mesh (see corotate.read_mesh, corotate.box)")
        by_region = materials_by_region(material)
        if isinstance(material, Material):
            regions = None  # one material: every cell has it, whatever its region
        elif regions is None:
            regions = mesh.cell_regions
        cell_regions = None if regions is None else check_cell_regions(regions, mesh.n_cells)
        self._dense_materials = dense_regions(by_region, cell_regions)
        if cell_regions is not None:
            cell_regions.flags.writeable = False
        if mesh.cell_type == "triangle":
            if thickness is None:
                raise ValueError("a triangle (sheet) mesh needs thickness=... [m]")
            thickness = float(thickness)
        elif thickness is not None:
            raise ValueError(f"thickness applies to triangle sheets only, not to {mesh.cell_type!r} cells")
        if project_psd and model not in HYPERELASTIC_MODELS:
            raise ValueError(f"project_psd applies to the hyperelastic models {HYPERELASTIC_MODELS}, not {model!r}")
        self._mesh = _read_only_copy(mesh, check=not _parts_checked)
        self._materials = by_region
        self._regions = cell_regions
        self._model = model
        self._thickness = thickness
        self._project_psd = bool(project_psd)
        # The C++ model (precomputed element data); every simulation steps its own copy.
        self._force_model = _core.ForceModel(
            model,
            mesh.cell_type,
            self._mesh.points,
            self._mesh.cells,
            self._core_materials(),
            thickness=1.0 if thickness is None else thickness,
            project_psd=self._project_psd,
        )

    @property
    def mesh(self) -> Mesh:
        """The body's own copy of the mesh (read-only, arrays included)."""
        return self._mesh

    @property
    def material(self) -> Material:
        """The material of a body of one material (read-only: a new material needs a new Body);
        ValueError for a body of several (see materials and regions)."""
        if len(self._materials) > 1:
            raise ValueError("this body has several materials: see body.materials and body.regions")
        return next(iter(self._materials.values()))

    @property
    def materials(self) -> dict[int, Material]:
        """{region id: Material} (a body of one material: {0: material}; read-only)."""
        return dict(self._materials)

    @property
    def regions(self) -> np.ndarray | None:
        """(m,) int64 region id of each cell (a read-only array); None when the body has no
        regions (one material for every cell)."""
        return self._regions

    def _core_materials(self) -> _core.RegionMaterials:
        """The core's materials: one, or one per region with each cell's (dense) region."""
        materials, index = self._dense_materials
        if index is None:
            return _core.RegionMaterials(materials[0]._core())
        return _core.RegionMaterials([m._core() for m in materials], index)

    def cell_lame(self) -> tuple[np.ndarray, np.ndarray]:
        """(lambda (m,), mu (m,)): the small-strain Lame parameters [Pa] of each cell's material."""
        materials, index = self._dense_materials
        lame = np.array([m.lame for m in materials])
        cells = np.zeros(self.mesh.n_cells, dtype=np.int64) if index is None else index
        return lame[cells, 0], lame[cells, 1]

    @property
    def model(self) -> str:
        """The force model's name (read-only)."""
        return self._model

    @property
    def thickness(self) -> float | None:
        """Sheet thickness [m] of triangle meshes, None for solids (read-only)."""
        return self._thickness

    @property
    def project_psd(self) -> bool:
        """Whether element stiffnesses are PSD-projected (read-only)."""
        return self._project_psd

    @property
    def n_nodes(self) -> int:
        return self.mesh.n_nodes

    @property
    def _rest_points(self) -> np.ndarray:
        return self._mesh.points

    # What a simulation of the body reads of its surface and pieces (JoinedBody has the same).
    def _boundary_triangles(self) -> np.ndarray:
        return boundary_triangles(self._mesh)

    def _surface_nodes(self) -> np.ndarray:
        return surface_nodes(self._mesh)

    def _parts(self) -> np.ndarray:
        return self._mesh.connected_parts()
