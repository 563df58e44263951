"""Volume meshes for corotate: the :class:`Mesh` container, file I/O and
structured-grid generators.

Everything here is pure NumPy; meshio is imported only when a file is read or
written, so generating meshes works without it.

Conventions
-----------
* ``points``  (n, 3) float64 rest positions, C-contiguous.
* ``cells``   (m, k) int64 node indices, C-contiguous, 0-based.
* ``cell_type`` is a meshio/VTK name, and node order within a cell follows VTK:

  - ``"tetra"`` (k = 4): nodes 0, 1, 2 form a triangle whose right-hand normal
    points towards node 3, which makes the signed volume positive.
  - ``"hexahedron"`` (k = 8): 0:(-,-,-) 1:(+,-,-) 2:(+,+,-) 3:(-,+,-), then
    4..7 the same at +z.
  - ``"hexahedron20"`` (k = 20): corners 0-7 as for the hexahedron, then the
    edge mid-nodes 8:(0,1) 9:(1,2) 10:(2,3) 11:(3,0) 12:(4,5) 13:(5,6)
    14:(6,7) 15:(7,4) 16:(0,4) 17:(1,5) 18:(2,6) 19:(3,7).
  - ``"triangle"`` (k = 3): a sheet (membrane) in space or a 2D body in the
    z = 0 plane; any node order (see :func:`rectangle`). Only built in memory:
    :func:`read_mesh` reads volume meshes.
"""

from __future__ import annotations

import importlib
import itertools
import os
import warnings
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable

import numpy as np

from .regions import check_cell_regions

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = [
    "SUPPORTED_CELL_TYPES",
    "Mesh",
    "read_mesh",
    "write_mesh",
    "box",
    "beam",
    "rectangle",
]

#: Node count per cell for each supported meshio/VTK cell type.
SUPPORTED_CELL_TYPES = {"tetra": 4, "hexahedron": 8, "hexahedron20": 20, "triangle": 3}
#: The solid cell types among them (what read_mesh reads).
VOLUME_CELL_TYPES = ("tetra", "hexahedron", "hexahedron20")

# Generator element names -> meshio cell types.
_ELEMENTS = {"tet4": "tetra", "hex8": "hexahedron", "hex20": "hexahedron20"}

# Node permutation that mirrors a cell (turns its signed volume around) while
# keeping it the same element: swap nodes 1 and 2 of a tet; swap the bottom and
# top faces of a hex (for hex20 the bottom/top edge mid-nodes follow, and the
# vertical edges keep their mid-nodes).
_FLIP = {
    "tetra": np.array([0, 2, 1, 3]),
    "hexahedron": np.array([4, 5, 6, 7, 0, 1, 2, 3]),
    "hexahedron20": np.array([4, 5, 6, 7, 0, 1, 2, 3, 12, 13, 14, 15, 8, 9, 10, 11, 16, 17, 18, 19]),
}

# Unit-cube corner offsets in VTK hexahedron order.
_HEX_CORNERS = np.array(
    [
        [0, 0, 0],
        [1, 0, 0],
        [1, 1, 0],
        [0, 1, 0],
        [0, 0, 1],
        [1, 0, 1],
        [1, 1, 1],
        [0, 1, 1],
    ],
    dtype=np.int64,
)

# The hexahedron20 edges (pairs of corners) in VTK mid-node order 8..19.
# Faces of each cell with their nodes counter-clockwise seen from outside (VTK orderings).
_TET_FACES = np.array([[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]], dtype=np.int64)
_HEX_FACES = np.array(
    [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]], dtype=np.int64
)

_HEX20_EDGES = np.array(
    [
        [0, 1],
        [1, 2],
        [2, 3],
        [3, 0],
        [4, 5],
        [5, 6],
        [6, 7],
        [7, 4],
        [0, 4],
        [1, 5],
        [2, 6],
        [3, 7],
    ],
    dtype=np.int64,
)


def _supported_list() -> str:
    return ", ".join(SUPPORTED_CELL_TYPES)


def _volume_list() -> str:
    return ", ".join(VOLUME_CELL_TYPES)


# --------------------------------------------------------------------------
# Mesh
# --------------------------------------------------------------------------


class Mesh:
    """A volume mesh with a single element type.

    Parameters
    ----------
    points     (n, 3) float-like rest positions; stored as a C-contiguous
               float64 copy.
    cells      (m, k) integer node indices (0-based); stored as a C-contiguous
               int64 copy. k must match ``cell_type``.
    cell_type  "tetra", "hexahedron" or "hexahedron20" (VTK node orderings,
               see the module docstring).
    cell_regions  optional (m,) integer region id of each cell (a body's
               material per region, see Body); read_mesh reads them from
               cell data such as Gmsh's physical groups.

    Attributes
    ----------
    points     (n, 3) float64
    cells      (m, k) int64
    cell_type  str
    cell_regions  (m,) int64 or None

    Raises
    ------
    ValueError  if the cell type is unsupported, a shape is wrong, a point is
                not finite or a node index is out of range; the message names
                the offending node / cell.
    """

    def __init__(
        self, points: ArrayLike, cells: ArrayLike, cell_type: str = "tetra", cell_regions: ArrayLike | None = None
    ) -> None:
        self.cell_type = _check_cell_type(cell_type)
        self.points = _check_points(points)
        self.cells = _check_cells(cells, self.cell_type, len(self.points))
        self.cell_regions = None if cell_regions is None else check_cell_regions(cell_regions, len(self.cells))

    @property
    def n_nodes(self) -> int:
        """Number of nodes n."""
        return int(self.points.shape[0])

    @property
    def n_cells(self) -> int:
        """Number of cells m."""
        return int(self.cells.shape[0])

    def __repr__(self) -> str:
        return f"Mesh(n_nodes={self.n_nodes}, n_cells={self.n_cells}, cell_type={self.cell_type!r})"

    # -- node selection ---------------------------------------------------

    def nodes_where(self, predicate: Callable[[np.ndarray], ArrayLike]) -> np.ndarray:
        """Indices of the nodes for which ``predicate`` holds.

        predicate  callable taking points (n, 3) float64 (a read-only view)
                   and returning a bool mask (n,)
        returns    (j,) int64 ascending node indices
        """
        view = self.points.view()
        view.flags.writeable = False  # the predicate must not move the mesh
        mask = np.asarray(predicate(view))
        if mask.shape != (self.n_nodes,):
            raise ValueError(f"predicate must return a mask of shape ({self.n_nodes},), got shape {mask.shape}")
        if mask.dtype != np.bool_:
            raise ValueError(f"predicate must return a bool mask, got dtype {mask.dtype}")
        return np.flatnonzero(mask).astype(np.int64)

    def nodes_on_plane(self, axis: int | str, value: float, tol: float = 1e-9) -> np.ndarray:
        """Indices of the nodes with ``|points[:, axis] - value| <= tol``.

        axis     0, 1, 2 or "x", "y", "z"
        value    plane coordinate along ``axis``
        tol      absolute tolerance (same units as the points)
        returns  (j,) int64 ascending node indices
        """
        a = _axis_index(axis)
        return self.nodes_where(lambda p: np.abs(p[:, a] - value) <= tol)

    def nodes_in_box(self, lower: ArrayLike, upper: ArrayLike) -> np.ndarray:
        """Indices of the nodes inside the closed axis-aligned box.

        lower    (3,) minimum corner
        upper    (3,) maximum corner, ``upper >= lower`` component-wise
        returns  (j,) int64 ascending node indices
        """
        lo = _as_vec3(lower, "lower")
        hi = _as_vec3(upper, "upper")
        if np.any(hi < lo):
            raise ValueError(f"box upper {hi.tolist()} is below lower {lo.tolist()}")
        return self.nodes_where(lambda p: np.all((p >= lo) & (p <= hi), axis=1))

    def nearest_node(self, point: ArrayLike) -> int:
        """Index of the node closest to ``point``.

        point    (3,) query position
        returns  int node index (the lowest one on ties)
        """
        if self.n_nodes == 0:
            raise ValueError("nearest_node on a mesh without nodes")
        q = _as_vec3(point, "point")
        d2 = np.sum((self.points - q) ** 2, axis=1)
        return int(np.argmin(d2))

    # -- geometry ---------------------------------------------------------

    def cell_volumes(self) -> np.ndarray:
        """Signed volume of every cell.

        returns  (m,) float64; positive for cells in VTK orientation. For
                 triangles: the (unsigned) areas, as a sheet has no inside.

        Tets are exact. Hexahedra use 2x2x2 Gauss quadrature of det J of the
        trilinear corner map, which is exact for that map (det J has degree
        <= 2 in each reference coordinate). hexahedron20 cells use their
        corner nodes only, so curved edges are ignored.
        """
        x = self.points[self.cells]  # (m, k, 3)
        if self.cell_type == "triangle":
            return 0.5 * np.linalg.norm(np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]), axis=1)
        if self.cell_type == "tetra":
            return _tet_volumes(x)
        return _hex_volumes(x[:, :8, :])

    def boundary_faces(self) -> np.ndarray:
        """The faces on the body's surface, oriented outward.

        returns  (f, 3) int64 node triangles for tetra; (f, 4) corner quads for
                 hexahedron and hexahedron20 (the mid-edge nodes are left out).
                 A face is on the surface when no other cell shares it.
        """
        if self.cell_type == "triangle":
            raise ValueError("boundary faces need a volume mesh, got 'triangle' cells (a sheet is its own surface)")
        local = _TET_FACES if self.cell_type == "tetra" else _HEX_FACES
        faces = self.cells[:, :8][:, local].reshape(-1, local.shape[1])  # outward per cell
        key = np.sort(faces, axis=1)
        _, first, counts = np.unique(key, axis=0, return_index=True, return_counts=True)
        return faces[np.sort(first[counts == 1])]

    # -- conversion -------------------------------------------------------

    def to_meshio(self, point_data: Mapping[str, ArrayLike] | None = None) -> Any:
        """This mesh as a ``meshio.Mesh`` (copies of the arrays).

        point_data  optional dict name -> (n,) or (n, k) array, one row per node
        returns     meshio.Mesh with one cell block of type ``cell_type``
        """
        meshio = _meshio()
        data = _check_point_data(point_data, self.n_nodes)
        return meshio.Mesh(
            self.points.copy(), [(self.cell_type, self.cells.copy())], point_data=data, cell_data=_region_data(self)
        )

    def to_pyvista(self) -> Any:
        """This mesh as a ``pyvista.UnstructuredGrid`` (needs pyvista, which
        corotate does not depend on: ``pip install pyvista``)."""
        try:
            pyvista = importlib.import_module("pyvista")  # optional, not a dependency
        except ImportError as e:
            raise ImportError("Mesh.to_pyvista needs pyvista, which is not installed: pip install pyvista") from e
        return pyvista.from_meshio(self.to_meshio())


def _check_cell_type(cell_type: str) -> str:
    if not isinstance(cell_type, str) or cell_type not in SUPPORTED_CELL_TYPES:
        raise ValueError(f"unsupported cell type {cell_type!r}; supported: {_supported_list()}")
    return cell_type


def _check_points(points: ArrayLike) -> np.ndarray:
    p = np.array(points, dtype=np.float64, order="C", copy=True)
    if p.ndim != 2 or p.shape[1] != 3:
        raise ValueError(f"points must have shape (n, 3), got {p.shape}")
    bad = ~np.isfinite(p)
    if bad.any():
        node, coord = np.argwhere(bad)[0]
        kind = "NaN" if np.isnan(p[node, coord]) else "inf"
        raise ValueError(
            f"points contain {kind} at node {node} ({int(bad.any(axis=1).sum())} non-finite node(s) in total)"
        )
    return p


def _check_cells(cells: ArrayLike, cell_type: str, n_nodes: int) -> np.ndarray:
    k = SUPPORTED_CELL_TYPES[cell_type]
    c = np.asarray(cells)
    if c.size == 0:
        # An empty list has no dtype or shape worth checking.
        c = np.zeros((0, k), dtype=np.int64)
    if c.dtype.kind not in "iu":
        raise ValueError(f"cells must hold integer node indices, got dtype {c.dtype}")
    return _index_block(c, k, n_nodes, f"cells of type {cell_type!r}", "")


def _index_block(c: np.ndarray, k: int, n_nodes: int, what: str, prefix: str) -> np.ndarray:
    """c as a fresh (m, k) int64 C-order array with every index in [0, n_nodes), else ValueError:
    what names the block in the shape message, prefix starts the message about a bad cell."""
    if c.ndim != 2 or c.shape[1] != k:
        raise ValueError(f"{what} must have shape (m, {k}), got {c.shape}")
    c = np.array(c, dtype=np.int64, order="C", copy=True)
    bad = (c < 0) | (c >= n_nodes)
    if bad.any():
        cell, local = np.argwhere(bad)[0]
        raise ValueError(
            f"{prefix}cell {cell} has node index {c[cell, local]} out of range "
            f"[0, {n_nodes}) ({int(bad.any(axis=1).sum())} bad cell(s) in total)"
        )
    return c


def _axis_index(axis: int | str) -> int:
    names = {"x": 0, "y": 1, "z": 2}
    if isinstance(axis, str) and axis.lower() in names:
        return names[axis.lower()]
    if isinstance(axis, (int, np.integer)) and not isinstance(axis, bool) and 0 <= axis <= 2:
        return int(axis)
    raise ValueError(f"axis must be 0, 1, 2, 'x', 'y' or 'z', got {axis!r}")


def _as_vec3(v: ArrayLike, name: str) -> np.ndarray:
    a = np.asarray(v, dtype=np.float64)
    if a.shape != (3,):
        raise ValueError(f"{name} must have shape (3,), got {a.shape}")
    return a


def _tet_volumes(x: np.ndarray) -> np.ndarray:
    """Signed tet volumes. x  (m, 4, 3) corner positions -> (m,)."""
    e = x[:, 1:, :] - x[:, :1, :]  # edges from node 0, rows = edge vectors
    return np.linalg.det(e) / 6.0


def _hex_gauss_derivatives() -> np.ndarray:
    """Trilinear shape-function gradients at the 2x2x2 Gauss points.

    returns  (8, 8, 3): [gauss point, corner, d/d(xi, eta, zeta)], reference
             cube [-1, 1]^3, corners in VTK order.
    """
    s = 2 * _HEX_CORNERS - 1  # corner signs in {-1, +1}
    g = 1.0 / np.sqrt(3.0)
    gp = np.array(list(itertools.product((-g, g), repeat=3)))  # (8, 3)
    # N_a = prod_d (1 + s_ad * xi_d) / 8; dN_a/dxi_j keeps s_aj, drops factor j.
    factors = 1.0 + gp[:, None, :] * s[None, :, :]  # (gp, corner, 3)
    dn = np.empty((8, 8, 3))
    for j in range(3):
        others = [d for d in range(3) if d != j]
        dn[:, :, j] = s[None, :, j] * np.prod(factors[:, :, others], axis=2) / 8.0
    return dn


_HEX_DN = _hex_gauss_derivatives()


def _hex_volumes(x: np.ndarray) -> np.ndarray:
    """Signed trilinear hex volumes. x  (m, 8, 3) VTK-ordered corners -> (m,)."""
    # J[c, g, i, j] = sum_a x[c, a, i] * dN[g, a, j]; all Gauss weights are 1.
    jac = np.einsum("cai,gaj->cgij", x, _HEX_DN)
    return np.linalg.det(jac).sum(axis=1)


# --------------------------------------------------------------------------
# Reading and writing
# --------------------------------------------------------------------------


def _meshio() -> Any:
    try:
        import meshio
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError("reading/writing mesh files needs meshio: pip install meshio") from e
    return meshio


def read_mesh(source: str | os.PathLike[str] | Any, remove_unused_nodes: bool = True) -> Mesh:
    """Read a volume mesh from a file or take it from a meshio.Mesh.

    source  a path in any format meshio reads (.vtu, .vtk, .msh, .xdmf, ...),
            or a TetGen pair given as either ``name.node`` or ``name.ele``
            (both must exist; 0- or 1-based as the .node file's first index
            says), or a ``meshio.Mesh`` already in memory.
    remove_unused_nodes
            drop nodes no cell refers to (they would have no mass and no
            stiffness) and renumber the rest, keeping their order; a warning
            says how many were dropped.
    returns  Mesh with one of the supported cell types; its cell_regions are the
             cells' region ids where the file has them (cell data
             ``gmsh:physical``, ``cell_regions``, ``medit:ref`` or
             ``CellEntityIds``, the first found), else None.

    Cells with negative signed volume are mirrored into VTK orientation (for
    tets: nodes 1 and 2 swapped) with a warning giving their count.
    Lower-dimensional cells (boundary triangles, lines, vertices, as Gmsh
    writes for physical groups) are dropped with a warning giving their count.

    Files are treated as untrusted: whatever meshio does with a corrupt file
    (it may call ``sys.exit``) ends here as a ValueError naming the file, and
    the cell count meshio returns is checked against the count the file
    declares (VTU, legacy VTK, ASCII Gmsh), so no cell is lost silently.

    Raises
    ------
    FileNotFoundError  if a file is missing (the message has the path).
    ValueError  if the file cannot be parsed or is inconsistent (the message
                names the file and the problem), holds no supported volume
                cells (the message lists the types found and the supported
                ones), holds other volume cells (wedges, tetra10, unknown
                types), or several supported volume types (one type per body).
    """
    from . import mesh_io

    regions = None
    if _is_meshio_mesh(source):
        label = "meshio.Mesh"
        points, cells, cell_type = mesh_io.volume_cells(source, label, stacklevel=2)
        regions = mesh_io.volume_cell_regions(source, cell_type, label)
    else:
        path = Path(os.fspath(source))
        label = str(path)
        if path.suffix.lower() in (".node", ".ele"):
            points, cells, cell_type = mesh_io.read_tetgen(path)
        else:
            m = mesh_io.read_meshio_file(path)
            points, cells, cell_type = mesh_io.volume_cells(m, label, stacklevel=2)
            regions = mesh_io.volume_cell_regions(m, cell_type, label)
    try:
        mesh = Mesh(points, cells, cell_type, regions)  # validates before any renumbering
    except ValueError as e:
        raise ValueError(f"{label}: {e}") from e
    if remove_unused_nodes:
        mesh = _drop_unused_nodes(mesh, label)
    _fix_orientation(mesh, label)
    return mesh


def _is_meshio_mesh(obj: Any) -> bool:
    """A meshio.Mesh (or look-alike), as opposed to a path."""
    if isinstance(obj, (str, bytes, os.PathLike)):
        return False
    return hasattr(obj, "points") and hasattr(obj, "cells")


def _drop_unused_nodes(mesh: Mesh, path: str | os.PathLike[str]) -> Mesh:
    """Mesh without the nodes no cell uses (others keep their order)."""
    used = np.zeros(mesh.n_nodes, dtype=bool)
    used[mesh.cells] = True
    n_unused = int((~used).sum())
    if n_unused == 0:
        return mesh
    new_index = np.cumsum(used) - 1
    warnings.warn(
        f"{path}: removed {n_unused} node(s) not used by any cell; "
        "remaining nodes were renumbered in their original order",
        stacklevel=3,
    )
    return Mesh(mesh.points[used], new_index[mesh.cells], mesh.cell_type, mesh.cell_regions)


def _fix_orientation(mesh: Mesh, path: str | os.PathLike[str]) -> None:
    """Mirror negatively oriented cells in place, warning with their count."""
    negative = mesh.cell_volumes() < 0
    n_neg = int(negative.sum())
    if n_neg == 0:
        return
    mesh.cells[negative] = mesh.cells[negative][:, _FLIP[mesh.cell_type]]
    what = "nodes 1 and 2 swapped" if mesh.cell_type == "tetra" else "top and bottom faces swapped"
    warnings.warn(
        f"{path}: reordered {n_neg} of {mesh.n_cells} {mesh.cell_type} cell(s) with negative volume ({what})",
        stacklevel=3,
    )


def write_mesh(path: str | os.PathLike[str], mesh: Mesh, point_data: Mapping[str, ArrayLike] | None = None) -> None:
    """Write a mesh with meshio (format from the file extension).

    path        output file, e.g. "out.vtu"
    mesh        Mesh
    point_data  optional dict name -> (n,) or (n, k) array, one row per node
    """
    meshio = _meshio()
    data = _check_point_data(point_data, mesh.n_nodes)
    out = meshio.Mesh(mesh.points, [(mesh.cell_type, mesh.cells)], point_data=data, cell_data=_region_data(mesh))
    meshio.write(os.fspath(path), out)


def _region_data(mesh: Mesh) -> dict:
    """meshio cell data holding the mesh's cell_regions (read back by read_mesh)."""
    return {} if mesh.cell_regions is None else {"cell_regions": [mesh.cell_regions.copy()]}


def _check_point_data(point_data: Mapping[str, ArrayLike] | None, n_nodes: int) -> dict:
    """Validate a name -> (n, ...) array dict; returns float/ints as arrays."""
    out = {}
    for name, values in (point_data or {}).items():
        a = np.asarray(values)
        if a.ndim == 0 or a.shape[0] != n_nodes:
            raise ValueError(f"point_data[{name!r}] must have one row per node ({n_nodes}), got shape {a.shape}")
        out[str(name)] = a
    return out


# --------------------------------------------------------------------------
# Structured generators
# --------------------------------------------------------------------------


def box(
    size: ArrayLike = (1.0, 1.0, 1.0),
    cells: ArrayLike = (1, 1, 1),
    element: str = "tet4",
    origin: ArrayLike = (0.0, 0.0, 0.0),
) -> Mesh:
    """A structured mesh of an axis-aligned box.

    size     (3,) edge lengths (lx, ly, lz), all > 0
    cells    (3,) number of cuboids (nx, ny, nz) along each axis, all >= 1
    element  "tet4": each cuboid cut into 6 tets sharing one of its diagonals
                     (Kuhn / Freudenthal split), mirrored from cuboid to cuboid
                     along each axis so the mesh is conforming and symmetric about
                     every plane between cuboid pairs: a beam with an even number
                     of cells across bends in its plane of load (one diagonal
                     direction everywhere would twist it sideways, by 10% of the
                     deflection on a 4 x 4 cross-section);
             "hex8": one "hexahedron" per cuboid;
             "hex20": one "hexahedron20" per cuboid, edge mid-nodes shared
                     with the neighbouring cells.
    origin   (3,) the box's minimum corner
    returns  Mesh; nodes numbered x-major with z fastest (hex20: corner and
             mid-nodes interleaved on the half-step grid in the same order),
             so a slab of constant x holds consecutive indices.
    """
    if element not in _ELEMENTS:
        raise ValueError(f"unknown element {element!r}; choose one of {', '.join(_ELEMENTS)}")
    lengths = _as_vec3(size, "size")
    if not np.all(np.isfinite(lengths) & (lengths > 0)):
        raise ValueError(f"size must be finite and positive, got {lengths.tolist()}")
    counts = _cell_counts(cells)
    start = _as_vec3(origin, "origin")
    if not np.all(np.isfinite(start)):
        raise ValueError(f"origin must be finite, got {start.tolist()}")

    # hex20 needs nodes at half steps; build the grid at that resolution and
    # keep only corners and edge mid-points.
    sub = 2 if element == "hex20" else 1
    axes = [np.linspace(start[d], start[d] + lengths[d], sub * counts[d] + 1) for d in range(3)]
    shape = tuple(sub * counts + 1)
    keep = _grid_node_mask(shape, element)
    node_id = np.full(shape, -1, dtype=np.int64)
    node_id[keep] = np.arange(int(keep.sum()))
    ijk = np.argwhere(keep)  # C order = z fastest, matching node_id
    points = np.column_stack([axes[d][ijk[:, d]] for d in range(3)])

    local = _local_offsets(element)  # (cells per cuboid, k, 3) in half-steps if sub=2
    cuboid = np.indices(tuple(counts)).reshape(3, -1).T  # (N, 3) cuboid indices
    base = sub * cuboid  # (N, 3) cuboid corners
    if element == "tet4":  # the split mirrored in every odd cuboid along each axis
        parity = cuboid % 2
        mirrored = _mirrored_kuhn_tets()  # (2, 2, 2, 6, 4, 3)
        idx = base[:, None, None, :] + mirrored[parity[:, 0], parity[:, 1], parity[:, 2]]
    else:
        idx = base[:, None, None, :] + local[None, :, :, :]  # (N, c, k, 3)
    conn = node_id[idx[..., 0], idx[..., 1], idx[..., 2]]
    return Mesh(points, conn.reshape(-1, local.shape[1]), _ELEMENTS[element])


def beam(
    length: float = 5.0, width: float = 1.0, height: float = 1.0, cells: ArrayLike = (10, 2, 2), element: str = "tet4"
) -> Mesh:
    """A box from the origin: x in [0, length], y in [0, width], z in [0, height].

    cells    (3,) cuboids along x, y, z
    element  "tet4", "hex8" or "hex20" (see :func:`box`)
    returns  Mesh
    """
    return box(size=(length, width, height), cells=cells, element=element, origin=(0.0, 0.0, 0.0))


def _cell_counts(cells: ArrayLike) -> np.ndarray:
    c = np.asarray(cells)
    if c.shape != (3,) or c.dtype.kind not in "iu" or np.any(c < 1):
        raise ValueError(f"cells must be three integers >= 1, got {cells!r}")
    return c.astype(np.int64)


def _grid_node_mask(shape: tuple[int, ...], element: str) -> np.ndarray:
    """Which grid points become nodes: all of them, or for hex20 (half-step
    grid) the corners and edge mid-points, i.e. at most one odd index."""
    if element != "hex20":
        return np.ones(shape, dtype=bool)
    i, j, k = np.indices(shape)
    return (i % 2 + j % 2 + k % 2) <= 1


def _local_offsets(element: str) -> np.ndarray:
    """Grid offsets of each element's nodes inside one cuboid.

    returns  (c, k, 3) int64: c elements per cuboid, k nodes each; for hex20
             the offsets are in half steps (corners at 0 or 2).
    """
    if element == "hex8":
        return _HEX_CORNERS[None]
    if element == "hex20":
        corners = 2 * _HEX_CORNERS
        mids = corners[_HEX20_EDGES].sum(axis=1) // 2
        return np.concatenate([corners, mids])[None]
    return _kuhn_tets()


def _kuhn_tets() -> np.ndarray:
    """The 6 Kuhn tets of the unit cube as corner offsets, positively oriented.

    Each tet walks from (0,0,0) to (1,1,1) along the cube edges, one axis at a
    time in the order of a permutation; all six share that diagonal.
    returns  (6, 4, 3) int64
    """
    tets = []
    for perm in itertools.permutations(range(3)):
        steps = np.eye(3, dtype=np.int64)[list(perm)]
        verts = np.vstack([np.zeros(3, dtype=np.int64), np.cumsum(steps, axis=0)])
        # The volume sign is the permutation's parity; swap 1 and 2 if odd.
        if np.linalg.det(verts[1:] - verts[0]) < 0:
            verts = verts[[0, 2, 1, 3]]
        tets.append(verts)
    return np.array(tets)


def _mirrored_kuhn_tets() -> np.ndarray:
    """The Kuhn tets mirrored along any subset of the axes, positively oriented.

    returns  (2, 2, 2, 6, 4, 3) int64: [mx, my, mz] holds the split of the unit
             cube mirrored along the axes whose flag is 1 (offset o -> 1 - o).
    """
    kuhn = _kuhn_tets()
    out = np.empty((2, 2, 2, *kuhn.shape), dtype=np.int64)
    for flags in itertools.product((0, 1), repeat=3):
        f = np.array(flags)
        tets = np.where(f == 1, 1 - kuhn, kuhn)
        if f.sum() % 2 == 1:  # an odd number of mirrors reverses the orientation
            tets = tets[:, [0, 2, 1, 3]]
        out[flags] = tets
    return out


def rectangle(size: ArrayLike = (1.0, 1.0), cells: ArrayLike = (1, 1), origin: ArrayLike = (0.0, 0.0)) -> Mesh:
    """A structured triangle mesh of a rectangle in the z = 0 plane (a sheet).

    size     (2,) edge lengths (lx, ly), both > 0
    cells    (2,) number of squares (nx, ny) along x and y, both >= 1; each is cut
             into two triangles along its diagonal from (min x, min y) to
             (max x, max y)
    origin   (2,) the rectangle's minimum corner (x, y)
    returns  Mesh of "triangle" cells, counter-clockwise seen from +z (normal +z);
             nodes numbered x-major with y fastest: node (i, j) is i * (ny + 1) + j.
    """
    lengths = np.asarray(size, dtype=np.float64)
    if lengths.shape != (2,) or not np.all(np.isfinite(lengths) & (lengths > 0)):
        raise ValueError(f"size must be two finite positive lengths, got {size!r}")
    counts = np.asarray(cells)
    if counts.shape != (2,) or counts.dtype.kind not in "iu" or np.any(counts < 1):
        raise ValueError(f"cells must be two integers >= 1, got {cells!r}")
    start = np.asarray(origin, dtype=np.float64)
    if start.shape != (2,) or not np.all(np.isfinite(start)):
        raise ValueError(f"origin must be two finite coordinates, got {origin!r}")
    nx, ny = (int(c) for c in counts)
    xs = np.linspace(start[0], start[0] + lengths[0], nx + 1)
    ys = np.linspace(start[1], start[1] + lengths[1], ny + 1)
    gx, gy = np.meshgrid(xs, ys, indexing="ij")
    points = np.column_stack([gx.ravel(), gy.ravel(), np.zeros(gx.size)])
    i, j = (a.ravel() for a in np.meshgrid(np.arange(nx), np.arange(ny), indexing="ij"))
    n00 = i * (ny + 1) + j
    n10, n01, n11 = n00 + ny + 1, n00 + 1, n00 + ny + 2
    tris = np.concatenate([np.column_stack([n00, n10, n11]), np.column_stack([n00, n11, n01])])
    return Mesh(points, tris, "triangle")
