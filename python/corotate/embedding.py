"""A detailed render surface carried by a coarse simulated body (the paper's §2.2.2).

The body is simulated; the surface (vertices and triangles, e.g. an OBJ/STL/PLY file) is
only shown. Coupled once, each surface vertex keeps an element of the body and its local
coordinates there, so each frame its position is a fixed weighted sum of that element's
nodes. The C++ core does the coupling (with a grid search) and the per-frame work, writing
into this object's preallocated arrays; see cpp/include/corotate/embedding/.

    surface = cr.EmbeddedSurface.from_file(body, "dog.obj")
    print(surface.report)           # vertices outside the body and how far
    for frame in range(300):
        sim.step(5)
        surface.update(sim)         # surface.positions, surface.normals: (nv, 3) arrays
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

import corotate._core as _core

from ._scene_nodes import SceneNodes, body_rows
from .body import Body
from .mesh import VOLUME_CELL_TYPES, Mesh
from .output import TimeSeriesWriter

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["EmbeddedSurface", "read_surface"]

NormalsMode = Literal["area", "rotated", "none"]
_NORMALS = ("area", "rotated", "none")


# Surface formats whose every cell is a face (of 3 or more vertices).
_FACE_FORMATS = (".obj", ".off", ".ply", ".stl")


def read_surface(path: str | os.PathLike[str], remove_unused_vertices: bool = False) -> Mesh:
    """Read a triangle surface from a file (.obj, .stl, .ply, .off, .vtu, ...; the reader
    :func:`corotate.read_mesh` uses, so a file gets the same verdict on every path).

    Triangles are kept, quads and polygons are split into triangles (a fan from their first
    vertex), other cells (lines, points, volume cells) are ignored, and so are the vertices
    only they use. Vertices that no cell at all uses are an error by default: they are what a
    truncated file leaves (an OBJ cut after its vertices and a few faces);
    remove_unused_vertices=True drops them.

    path     the file
    returns  Mesh of cell type "triangle" on the vertices the triangles use (in file order)

    Raises FileNotFoundError / ValueError (naming the file) for a missing, unreadable or
    truncated file, one without triangles or quads, or one with a triangle twice (in any
    vertex order).
    """
    from .mesh_checks import duplicate_cells
    from .mesh_files import read_mesh_file

    path = Path(os.fspath(path))
    m = read_mesh_file(path)
    blocks = []
    n_points = len(m.points)
    in_any_cell = np.zeros(n_points, dtype=bool)
    for block in m.cells:
        data = np.asarray(block.data)
        if data.dtype.kind not in "iu" or data.ndim != 2:
            raise ValueError(f"{path}: {block.type} cells are not an (m, k) array of node indices")
        if data.size and (data.min() < 0 or data.max() >= n_points):
            raise ValueError(f"{path}: a {block.type} cell refers to a vertex out of range [0, {n_points})")
        in_any_cell[data.ravel()] = True
        if path.suffix.lower() in _FACE_FORMATS and block.type not in ("triangle", "quad", "polygon"):
            # These formats hold faces only: meshio makes a "line" of a face of 2 vertices.
            raise ValueError(f"{path}: a face with {data.shape[1]} vertices (is the file truncated or corrupt?)")
        if block.type == "triangle":
            blocks.append(data)
        elif block.type in ("quad", "polygon"):
            if data.shape[1] < 3:
                raise ValueError(f"{path}: a face with {data.shape[1]} vertices (is the file truncated or corrupt?)")
            blocks += [data[:, [0, k, k + 1]] for k in range(1, data.shape[1] - 1)]  # a fan
    if not blocks:
        found = sorted({b.type for b in m.cells})
        raise ValueError(f"{path} holds no triangles or quads (cell types found: {found})")
    if not remove_unused_vertices and not in_any_cell.all():
        raise ValueError(
            f"{path}: {int((~in_any_cell).sum())} of {n_points} vertices are used by no cell (vertex "
            f"{int(np.argmin(in_any_cell))} is the first): is the file truncated? "
            "read_surface(..., remove_unused_vertices=True) drops them"
        )
    triangles = np.concatenate(blocks).astype(np.int64)
    copies = duplicate_cells(triangles)
    if len(copies):
        i, j = copies[0].tolist()
        raise ValueError(
            f"{path}: triangle {j} repeats triangle {i} ({len(copies)} duplicate triangle(s) in all): a surface "
            "crosses itself there or the file is corrupt"
        )
    try:
        mesh = Mesh(np.asarray(m.points, dtype=np.float64)[:, :3], triangles, "triangle")
    except ValueError as e:
        raise ValueError(f"{path}: {e}") from e
    used = np.unique(mesh.cells)
    if len(used) < mesh.n_nodes:  # vertices of the ignored cells
        new_index = np.full(mesh.n_nodes, -1, dtype=np.int64)
        new_index[used] = np.arange(len(used))
        mesh = Mesh(mesh.points[used], new_index[mesh.cells], "triangle")
    return mesh


class EmbeddedSurface:
    """A triangle surface embedded in a tet, hex or hex20 body.

    body        Body or volume Mesh (any solid cell type) that carries it
    vertices    (nv, 3) surface vertices at the body's rest configuration
    triangles   (nt, 3) vertex indices (may be empty: a point cloud, whose normals are zero)
    max_outside_distance
                a vertex farther outside the body than this many element sizes (the
                longest edge of its element's bounding box) raises ValueError: the surface
                does not belong to the body (wrong units or placement). Default 1.

    Coupling (once, in C++): a vertex inside an element is assigned to it (barycentric
    coordinates for tets, the inverse isoparametric map by Newton for hexes); a vertex inside
    no element goes, as in the paper, to the element minimising the sum of its absolute
    local coordinates (for hexes the natural-coordinate excess outside [-1, 1]).
    ``report`` says how many vertices fell outside and how far.

    Attributes (read-only)
    ----------------------
    mesh        the surface at rest, a Mesh of cell type "triangle"
    positions   (nv, 3) float64 surface positions after the last update (rest at first)
    normals     (nv, 3) float64 unit vertex normals after the last update
    elements    (nv,) element of each vertex;  local_coordinates (nv, 3)
    outside_distances  (nv,) distance outside the body / element size (0 inside)
    report      {"outside": count, "max_outside_distance": largest, "farthest_vertex": index}

    ``update`` overwrites positions and normals in place (no new arrays), so views of them
    (e.g. a renderer's vertex buffer) stay valid.
    """

    def __init__(
        self,
        body: Body | Mesh,
        vertices: ArrayLike,
        triangles: ArrayLike,
        max_outside_distance: float = 1.0,
    ) -> None:
        volume = body.mesh if isinstance(body, Body) else body
        if not isinstance(volume, Mesh):
            raise TypeError("body must be a corotate.Body or a volume corotate.Mesh")
        if volume.cell_type not in VOLUME_CELL_TYPES:
            raise ValueError(f"a surface embeds in {', '.join(VOLUME_CELL_TYPES)} cells, not {volume.cell_type!r}")
        tri = np.asarray(triangles)
        if tri.size == 0:
            tri = np.zeros((0, 3), dtype=np.int64)
        self._mesh = Mesh(vertices, tri, "triangle")  # checks shapes, finiteness and indices
        if self._mesh.n_nodes == 0:
            raise ValueError("the surface has no vertices")
        self._n_body_nodes = volume.n_nodes
        self._core = _core.SurfaceEmbedding(
            volume.cell_type,
            volume.points,
            volume.cells,
            self._mesh.points,
            self._mesh.cells,
            max_outside_distance=float(max_outside_distance),
        )
        self._positions = self._mesh.points.copy()
        self._normals = np.ascontiguousarray(self._core.rest_normals)
        self._scene: SceneNodes | None = None  # set by Scene.embedded_surface

    @classmethod
    def from_file(
        cls,
        body: Body | Mesh,
        path: str | os.PathLike[str],
        max_outside_distance: float = 1.0,
        remove_unused_vertices: bool = False,
    ) -> EmbeddedSurface:
        """The surface in a file (.obj, .stl, .ply, ...; read and checked by :func:`read_surface`,
        which says what remove_unused_vertices does)."""
        surface = read_surface(path, remove_unused_vertices=remove_unused_vertices)
        return cls(body, surface.points, surface.cells, max_outside_distance=max_outside_distance)

    @property
    def mesh(self) -> Mesh:
        return self._mesh

    @property
    def n_vertices(self) -> int:
        return self._mesh.n_nodes

    @property
    def n_triangles(self) -> int:
        return self._mesh.n_cells

    @property
    def positions(self) -> np.ndarray:
        return self._positions

    @property
    def normals(self) -> np.ndarray:
        return self._normals

    @property
    def elements(self) -> np.ndarray:
        return np.asarray(self._core.elements)

    @property
    def local_coordinates(self) -> np.ndarray:
        return np.asarray(self._core.local_coordinates)

    @property
    def outside_distances(self) -> np.ndarray:
        return np.asarray(self._core.outside_distances)

    @property
    def report(self) -> dict[str, Any]:
        return dict(self._core.report)

    def update(self, state: Any, normals: NormalsMode = "area") -> None:
        """Move the surface to the body's current positions.

        state    a Simulation (anything with ``.positions``) or body positions (n, 3); for a
                 scene's surface (``Scene.embedded_surface``) also the scene's simulation or
                 its positions, of which it takes its body's nodes
        normals  "area" (default): area-weighted normals of the deformed surface;
                 "rotated": the rest normals turned by each vertex's element rotation
                 (cheaper on a fine surface; exact for rigid motions, blind to bending
                 within an element); "none": leave the normals as they are.
        Raises ValueError for positions of the wrong shape or with NaN (nothing is changed).
        """
        if normals not in _NORMALS:
            raise ValueError(f"normals must be one of {_NORMALS}, got {normals!r}")
        x = getattr(state, "positions", state)
        x = body_rows(np.asarray(x, dtype=np.float64), self._n_body_nodes, self._scene, "body positions")
        if normals == "rotated":
            self._core.rotated_normals(x, self._normals)  # checks x before writing anything
        self._core.embed(x, self._positions)
        if normals == "area":
            self._core.vertex_normals(self._positions, self._normals)

    def series_writer(self, path_pvd: str | os.PathLike[str]) -> TimeSeriesWriter:
        """A ParaView series writer for this surface (its own .pvd, e.g. beside the body's);
        write frames with :meth:`write_frame`."""
        return TimeSeriesWriter(path_pvd, self._mesh)

    def write_frame(self, writer: TimeSeriesWriter, time: float) -> Path:
        """Write the current positions (and "normal" point data) as one frame of writer."""
        return writer.write(time, self._positions, {"normal": self._normals})
