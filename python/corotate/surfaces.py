"""Triangle surfaces made from what the project has: the boundary of a volume mesh, and
refinement by subdivision, e.g. a fine render surface for :class:`~corotate.EmbeddedSurface`
from a coarse body's own boundary."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from .mesh import Mesh

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = [
    "boundary_surface",
    "boundary_triangles",
    "loop_subdivide",
    "split_at_centroids",
    "sphere_surface",
    "surface_nodes",
]


def boundary_triangles(mesh: Mesh) -> np.ndarray:
    """(f, 3) indices into the volume mesh's own nodes of its boundary triangles, outward
    (the faces no other cell shares; two triangles per hexahedron face; hexahedron20 cells
    use their corners). What a viewer draws over the simulated positions. Mesh.boundary_faces
    finds the faces; each quad becomes two triangles."""
    outer = mesh.boundary_faces()
    if outer.shape[1] == 4:
        outer = np.concatenate([outer[:, [0, 1, 2]], outer[:, [0, 2, 3]]])
    return outer


def surface_nodes(mesh: Mesh) -> np.ndarray:
    """(s,) int64, sorted: every node on a volume mesh's surface, the boundary faces' corners
    and, for quadratic cells, the mid-edge nodes of their edges (what touches an obstacle:
    left out, the mid-edge nodes would pass through it)."""
    from .mesh import _CELL_TYPES

    faces = mesh.boundary_faces()
    corners = np.unique(faces)
    facts = _CELL_TYPES[mesh.cell_type]
    if facts["order"] == 1:
        return corners
    edges, first_mid = np.asarray(facts["edges"]), int(facts["num_corners"])
    n = mesh.n_nodes

    def keys(pairs: np.ndarray) -> np.ndarray:
        pairs = np.sort(pairs, axis=1)
        return pairs[:, 0] * n + pairs[:, 1]

    around = np.stack([faces, np.roll(faces, -1, axis=1)], axis=-1).reshape(-1, 2)  # each face's edges
    cell_edges = mesh.cells[:, edges].reshape(-1, 2)
    on_surface = np.isin(keys(cell_edges), keys(around))
    mids = mesh.cells[:, first_mid : first_mid + len(edges)].reshape(-1)[on_surface]
    return np.unique(np.concatenate([corners, mids]))


def boundary_surface(mesh: Mesh) -> Mesh:
    """The boundary of a volume mesh as a triangle Mesh with outward normals: the cell faces
    no other cell shares, on only the nodes they use (renumbered in their original order).
    Hexahedra give two triangles per boundary face; hexahedron20 cells use their corners."""
    outer = boundary_triangles(mesh)
    used = np.unique(outer)
    index = np.full(mesh.n_nodes, -1, dtype=np.int64)
    index[used] = np.arange(len(used))
    return Mesh(mesh.points[used], index[outer], "triangle")


def sphere_surface(radius: float = 1.0, n_vertices: int = 400, centre: ArrayLike = (0.0, 0.0, 0.0)) -> Mesh:
    """A closed triangulated sphere: n_vertices evenly spread points (a Fibonacci spiral) and
    their convex hull, all faces oriented outward."""
    from scipy.spatial import ConvexHull

    if not (radius > 0 and np.isfinite(radius)):
        raise ValueError(f"radius must be finite and positive, got {radius}")
    if int(n_vertices) < 4:
        raise ValueError(f"a sphere needs at least 4 vertices, got {n_vertices}")
    k = np.arange(int(n_vertices)) + 0.5
    polar, azimuth = np.arccos(1 - 2 * k / len(k)), np.pi * (1 + 5**0.5) * k
    unit = np.column_stack([np.cos(azimuth) * np.sin(polar), np.sin(azimuth) * np.sin(polar), np.cos(polar)])
    faces = ConvexHull(unit).simplices.copy()
    normal = np.cross(unit[faces[:, 1]] - unit[faces[:, 0]], unit[faces[:, 2]] - unit[faces[:, 0]])
    inward = np.einsum("ij,ij->i", normal, unit[faces].mean(axis=1)) < 0
    faces[inward] = faces[inward][:, [0, 2, 1]]
    return Mesh(radius * unit + np.asarray(centre, dtype=np.float64), faces, "triangle")


def _edges(triangles: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Unique edges (E, 2), the edge of each face side (F, 3; side s joins corners s and
    s+1) and the number of faces on each edge (E,)."""
    sides = np.stack([triangles, np.roll(triangles, -1, axis=1)], axis=2)  # (F, 3, 2)
    edges, side_edge, counts = np.unique(
        np.sort(sides.reshape(-1, 2), axis=1), axis=0, return_inverse=True, return_counts=True
    )
    return edges, side_edge.reshape(-1, 3), counts


def loop_subdivide(surface: Mesh) -> Mesh:
    """One step of Loop subdivision (Loop 1987): every triangle becomes four and the surface
    gets smoother, converging to a C2 limit surface away from extraordinary vertices.

    New edge points are 3/8 (a + b) + 1/8 (c + d) (c, d opposite the edge); old vertices
    move to (1 - n beta) v + beta sum(neighbours), beta = (5/8 - (3/8 + cos(2 pi / n) / 4)^2) / n.
    Edges with other than two faces (open borders, non-manifold edges) take their midpoints,
    and their vertices stay where they are. Returns a new triangle Mesh (V + E vertices)."""
    if surface.cell_type != "triangle":
        raise ValueError(f"loop_subdivide needs a triangle mesh, got {surface.cell_type!r}")
    x, tri = surface.points, surface.cells
    n_vertices = surface.n_nodes
    edges, side_edge, counts = _edges(tri)
    # Edge points: the sum of the opposite corners over the edge's faces.
    opposite = np.zeros((len(edges), 3))
    for s in range(3):
        np.add.at(opposite, side_edge[:, s], x[tri[:, (s + 2) % 3]])
    midpoint = 0.5 * (x[edges[:, 0]] + x[edges[:, 1]])
    interior = counts == 2
    edge_points = midpoint.copy()
    edge_points[interior] = 0.75 * midpoint[interior] + 0.125 * opposite[interior]

    # Vertex points from the neighbour sums (each edge once per direction).
    adjacency = sp.coo_matrix(
        (np.ones(2 * len(edges)), (edges.ravel(), edges[:, ::-1].ravel())), shape=(n_vertices, n_vertices)
    ).tocsr()
    valence = np.asarray(adjacency.sum(axis=1)).ravel()
    n = np.maximum(valence, 1)
    beta = (5 / 8 - (3 / 8 + np.cos(2 * np.pi / n) / 4) ** 2) / n
    moved = (1 - n * beta)[:, None] * x + beta[:, None] * (adjacency @ x)
    fixed = np.zeros(n_vertices, dtype=bool)
    fixed[edges[~interior].ravel()] = True
    fixed |= valence == 0
    vertex_points = np.where(fixed[:, None], x, moved)

    e = side_edge + n_vertices  # new vertex index of each side's edge point
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    ab, bc, ca = e[:, 0], e[:, 1], e[:, 2]
    faces = np.concatenate([np.column_stack(f) for f in ((a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca))])
    return Mesh(np.concatenate([vertex_points, edge_points]), faces, "triangle")


def split_at_centroids(surface: Mesh) -> Mesh:
    """Every triangle split into three at its centroid (the same surface, V + F vertices and
    3F triangles; the orientation is kept)."""
    if surface.cell_type != "triangle":
        raise ValueError(f"split_at_centroids needs a triangle mesh, got {surface.cell_type!r}")
    tri = surface.cells
    m = np.arange(surface.n_cells) + surface.n_nodes
    centroids = surface.points[tri].mean(axis=1)
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    faces = np.concatenate([np.column_stack(f) for f in ((a, b, m), (b, c, m), (c, a, m))])
    return Mesh(np.concatenate([surface.points, centroids]), faces, "triangle")
