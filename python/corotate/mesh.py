"""Volume meshes for corotate: the :class:`Mesh` container, file I/O and
structured-grid generators.

The facts about each cell type (node count, reference nodes, edges, boundary faces,
the mirror map that turns a cell inside out, the generator name) come from the C++
core's cell-type table, :func:`cell_types`; this module restates none of them.
meshio is imported only when a file is read or written.

Conventions
-----------
* ``points``  (n, 3) float64 rest positions, C-contiguous.
* ``cells``   (m, k) int64 node indices, C-contiguous, 0-based.
* ``cell_type`` is a meshio/VTK name, and node order within a cell follows VTK:

  - ``"tetra"`` (k = 4): nodes 0, 1, 2 form a triangle whose right-hand normal
    points towards node 3, which makes the signed volume positive.
  - ``"tetra10"`` (k = 10): corners as ``"tetra"``, then the edge mid-nodes
    4:(0,1) 5:(1,2) 6:(2,0) 7:(0,3) 8:(1,3) 9:(2,3) (Gmsh's second-order tet
    after meshio's reordering).
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
import os
import warnings
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable

import numpy as np

from . import _core
from .regions import check_cell_regions

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = [
    "SUPPORTED_CELL_TYPES",
    "VOLUME_CELL_TYPES",
    "SOLID_ELEMENTS",
    "cell_types",
    "Mesh",
    "read_mesh",
    "write_mesh",
    "box",
    "beam",
    "rectangle",
]


def cell_types() -> dict[str, dict[str, Any]]:
    """The cell-type table of the C++ core: every registered element's facts.

    returns  dict cell type name -> dict with ``name`` (meshio), ``generator_name``
             (the ``element`` of :func:`box`), ``domain`` ("simplex" or "cube"),
             ``dim`` (3 solid, 2 membrane), ``order`` (1 linear, 2 quadratic),
             ``num_nodes`` k, ``num_corners``, ``num_stiffness_points``,
             ``reference_nodes`` (k, dim), ``edges`` (ne, 2) corner pairs (node
             num_corners + i of a quadratic cell sits on edge i), ``faces`` (nf, c)
             corner nodes of each boundary face, counter-clockwise seen from
             outside, ``mirror`` (k,) the renumbering that turns a cell inside
             out, ``models`` (the force models available for it).
    """
    return {name: dict(facts) for name, facts in _CELL_TYPES.items()}


_CELL_TYPES: dict[str, dict[str, Any]] = {facts["name"]: facts for facts in _core.cell_types()}

#: Node count per cell for each supported meshio/VTK cell type.
SUPPORTED_CELL_TYPES = {name: int(facts["num_nodes"]) for name, facts in _CELL_TYPES.items()}
#: The solid cell types among them (what read_mesh reads).
VOLUME_CELL_TYPES = tuple(name for name, facts in _CELL_TYPES.items() if facts["dim"] == 3)

# Generator element names ("tet4", ...) -> meshio cell types.
_ELEMENTS = {str(_CELL_TYPES[name]["generator_name"]): name for name in VOLUME_CELL_TYPES}
#: The ``element`` names the generators (:func:`box`, :func:`beam`) accept, one per solid cell type.
SOLID_ELEMENTS = tuple(_ELEMENTS)


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
    repair     merge coincident nodes and drop duplicate cells (a warning counts
               each) instead of raising ValueError for them (volume cells).
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
                not finite or a node index is out of range; for volume cells also
                if cells are duplicated, nodes coincide, a cell names a node twice
                or cells overlap (see :mod:`corotate.mesh_checks`); the message
                names the offending node / cell.
    """

    def __init__(
        self,
        points: ArrayLike,
        cells: ArrayLike,
        cell_type: str = "tetra",
        cell_regions: ArrayLike | None = None,
        repair: bool = False,
    ) -> None:
        self.cell_type = _check_cell_type(cell_type)
        self.points = _check_points(points)
        self.cells = _check_cells(cells, self.cell_type, len(self.points))
        self.cell_regions = None if cell_regions is None else check_cell_regions(cell_regions, len(self.cells))
        if self.cell_type in VOLUME_CELL_TYPES:  # one solid: see mesh_checks
            from .mesh_checks import check_volume_mesh

            self.points, self.cells, kept = check_volume_mesh(self, repair=repair)
            if self.cell_regions is not None and len(kept) != len(self.cell_regions):
                self.cell_regions = self.cell_regions[kept]

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

        Each cell's volume is the integral of det(dX/dxi) by its element's own
        quadrature in the C++ core, exact for straight and for curved
        (quadratic) cells.
        """
        return np.asarray(_core.cell_volumes(self.cell_type, self.points, self.cells), dtype=np.float64)

    def boundary_faces(self) -> np.ndarray:
        """The faces on the body's surface, oriented outward.

        returns  (f, c) int64 corner nodes of each face: triangles for tetra and
                 tetra10, quads for hexahedron and hexahedron20 (the mid-edge nodes are
                 left out). A face is on the surface when no other
                 cell shares it.
        """
        local = np.asarray(_CELL_TYPES[self.cell_type]["faces"], dtype=np.int64)
        if local.size == 0:
            raise ValueError(
                f"boundary faces need a volume mesh, got {self.cell_type!r} cells (a sheet is its own surface)"
            )
        faces = self.cells[:, local].reshape(-1, local.shape[1])  # outward per cell
        key = np.sort(faces, axis=1)
        _, first, counts = np.unique(key, axis=0, return_index=True, return_counts=True)
        return faces[np.sort(first[counts == 1])]

    def connected_parts(self) -> np.ndarray:
        """(n,) int64: the connected piece of each node (cells that share a node are one
        piece), numbered in the order of each piece's first node."""
        import scipy.sparse as sp
        from scipy.sparse.csgraph import connected_components

        rows = np.repeat(np.arange(self.n_cells), self.cells.shape[1])
        incidence = sp.csr_matrix(
            (np.ones(self.cells.size), (self.cells.ravel(), rows)), shape=(self.n_nodes, self.n_cells)
        )
        _, labels = connected_components(incidence @ incidence.T, directed=False)
        _, first = np.unique(labels, return_index=True)
        order = np.empty(len(first), dtype=np.int64)
        order[np.argsort(first)] = np.arange(len(first))
        return order[labels]

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


# --------------------------------------------------------------------------
# Reading and writing
# --------------------------------------------------------------------------


def _meshio() -> Any:
    try:
        import meshio
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError("reading/writing mesh files needs meshio: pip install meshio") from e
    return meshio


def read_mesh(source: str | os.PathLike[str] | Any, remove_unused_nodes: bool = False, repair: bool = False) -> Mesh:
    """Read a volume mesh from a file or take it from a meshio.Mesh.

    source  a path in any format meshio reads (.vtu, .vtk, .msh, .xdmf, ...),
            or a TetGen pair given as either ``name.node`` or ``name.ele``
            (both must exist; 0- or 1-based as the .node file's first index
            says), or a ``meshio.Mesh`` already in memory.
    remove_unused_nodes
            nodes no cell refers to (they would have no mass and no stiffness)
            are an error by default: they are what a truncated file leaves (an
            Abaqus file cut at 80 % keeps all nodes but a few cells). True drops
            them and renumbers the rest, keeping their order; a warning says how
            many were dropped.
    repair  merge coincident nodes and drop duplicate cells, with a warning
            counting each, instead of raising (see :class:`Mesh`).
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
                ones), holds other volume cells (wedges, pyramids, unknown
                types), or several supported volume types (one type per body);
                has nodes no cell uses (see remove_unused_nodes), duplicate
                cells, coincident nodes (see repair) or overlapping cells.
    """
    from . import mesh_io

    regions = None
    if _is_meshio_mesh(source):
        label = "meshio.Mesh"
        points, cells, cell_type = mesh_io.volume_cells(source, label, stacklevel=2)
        regions = mesh_io.volume_cell_regions(source, cell_type, label)
    else:
        from .mesh_files import read_mesh_file

        path = Path(os.fspath(source))
        label = str(path)
        m = read_mesh_file(path)
        points, cells, cell_type = mesh_io.volume_cells(m, label, stacklevel=2)
        regions = mesh_io.volume_cell_regions(m, cell_type, label)
    try:
        mesh = Mesh(points, cells, cell_type, regions, repair=repair)  # validates before any renumbering
    except ValueError as e:
        raise ValueError(f"{label}: {e}") from e
    mesh = _drop_unused_nodes(mesh, label, remove_unused_nodes)
    _fix_orientation(mesh, label)
    return mesh


def _is_meshio_mesh(obj: Any) -> bool:
    """A meshio.Mesh (or look-alike), as opposed to a path."""
    if isinstance(obj, (str, bytes, os.PathLike)):
        return False
    return hasattr(obj, "points") and hasattr(obj, "cells")


def _drop_unused_nodes(mesh: Mesh, path: str | os.PathLike[str], remove: bool) -> Mesh:
    """Mesh without the nodes no cell uses (others keep their order); ValueError for
    unused nodes unless remove."""
    used = np.zeros(mesh.n_nodes, dtype=bool)
    used[mesh.cells] = True
    n_unused = int((~used).sum())
    if n_unused == 0:
        return mesh
    if not remove:
        raise ValueError(
            f"{path}: {n_unused} of {mesh.n_nodes} node(s) are used by no cell (node {int(np.argmin(used))} is "
            "the first): is the file truncated? (a cut file keeps its nodes but loses cells); "
            "read_mesh(..., remove_unused_nodes=True) drops them"
        )
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
    mirror = np.asarray(_CELL_TYPES[mesh.cell_type]["mirror"], dtype=np.int64)
    mesh.cells[negative] = mesh.cells[negative][:, mirror]
    moved = ", ".join(f"{a}<->{b}" for a, b in enumerate(mirror.tolist()) if a < b)
    warnings.warn(
        f"{path}: reordered {n_neg} of {mesh.n_cells} {mesh.cell_type} cell(s) with negative volume "
        f"(nodes {moved} swapped)",
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
    element  a solid's generator name (``cell_types()[t]["generator_name"]``):
             "tet4": each cuboid cut into 6 tets sharing one of its diagonals
                     (Kuhn / Freudenthal split), mirrored from cuboid to cuboid
                     along each axis so the mesh is conforming and symmetric about
                     every plane between cuboid pairs: a beam with an even number
                     of cells across bends in its plane of load (one diagonal
                     direction everywhere would twist it sideways, by 10% of the
                     deflection on a 4 x 4 cross-section);
             "tet10": the same tets with a node in the middle of each edge;
             "hex8": one "hexahedron" per cuboid;
             "hex20": one "hexahedron20" per cuboid.
             Mid-edge nodes are shared with the neighbouring cells.
    origin   (3,) the box's minimum corner
    returns  Mesh; nodes numbered x-major with z fastest (quadratic elements:
             corner and mid-nodes interleaved on the half-step grid in the same
             order), so a slab of constant x holds consecutive indices. The
             generator is the C++ core's (meshes/structured_box.hpp), the same
             one the C++ benchmark and tests use.
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
    points, conn, cell_type = _core.structured_box(element, [int(c) for c in counts], lengths, start)
    return Mesh(points, conn, cell_type)


def beam(
    length: float = 5.0, width: float = 1.0, height: float = 1.0, cells: ArrayLike = (10, 2, 2), element: str = "tet4"
) -> Mesh:
    """A box from the origin: x in [0, length], y in [0, width], z in [0, height].

    cells    (3,) cuboids along x, y, z
    element  "tet4", "tet10", "hex8" or "hex20" (see :func:`box`)
    returns  Mesh
    """
    return box(size=(length, width, height), cells=cells, element=element, origin=(0.0, 0.0, 0.0))


def _cell_counts(cells: ArrayLike) -> np.ndarray:
    c = np.asarray(cells)
    if c.shape != (3,) or c.dtype.kind not in "iu" or np.any(c < 1):
        raise ValueError(f"cells must be three integers >= 1, got {cells!r}")
    return c.astype(np.int64)


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
