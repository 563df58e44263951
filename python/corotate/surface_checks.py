"""Checks of a triangle surface that is to bound a volume (before :func:`corotate.tetrahedralize`).

A mesher fed a surface with a vertex far off (a corrupt coordinate: 1e308 in an OBJ, a
byte-flipped STL float) fills a bounding box millions of times too large: fTetWild then
runs for minutes or crashes. An open or non-manifold surface bounds no volume, and a
mesher "repairs" it into some solid the user never drew. So the surface is checked first,
and every problem is named in the user's terms (vertex and edge indices, counts).
"""

from __future__ import annotations

import numpy as np

from .mesh_checks import merge_coincident_nodes

__all__ = ["OUTLIER_FACTOR", "check_closed_surface", "enclosed_volume", "outlier_vertices"]

#: A vertex farther from the surface's median point than this many times the median
#: vertex distance is an outlier. Real shapes stay far below (a 100:1 rod: 2); fTetWild
#: crashes or runs for minutes at 1e3 and more.
OUTLIER_FACTOR = 100.0


def outlier_vertices(points: np.ndarray, factor: float = OUTLIER_FACTOR) -> np.ndarray:
    """Indices (k,) of the vertices farther than factor x the median distance from the
    median point (per axis) of points (n, 3); farthest first."""
    if len(points) == 0:
        return np.zeros(0, dtype=np.int64)
    with np.errstate(over="ignore", invalid="ignore"):
        distance = np.linalg.norm(points - np.median(points, axis=0), axis=1)
    typical = np.median(distance)
    far = np.flatnonzero(~(distance <= factor * typical)) if typical > 0 else np.zeros(0, dtype=np.int64)
    return far[np.argsort(-distance[far], kind="stable")]


def enclosed_volume(points: np.ndarray, triangles: np.ndarray) -> float:
    """Signed volume enclosed by a closed, consistently oriented triangle surface
    (divergence theorem; positive for outward normals)."""
    x = points[triangles]
    with np.errstate(over="ignore", invalid="ignore"):
        return float(np.einsum("ij,ij->i", x[:, 0], np.cross(x[:, 1], x[:, 2])).sum() / 6)


def check_closed_surface(points: np.ndarray, triangles: np.ndarray, label: str = "the surface") -> None:
    """Raise ValueError unless the triangles (nt, 3) on points (nv, 3) form a closed,
    edge-manifold surface of sane extent, enclosing a volume: no outlier vertex (see
    OUTLIER_FACTOR); with coincident vertices welded and triangles without area left out,
    every edge shared by exactly two triangles; a finite non-zero enclosed volume. label
    starts the messages; vertex numbers in them are those after welding."""
    if len(triangles) == 0:
        raise ValueError(f"{label} has no triangles")
    far = outlier_vertices(points)
    if len(far):
        shown = ", ".join(str(int(i)) for i in far[:5])
        more = f" ({len(far)} in all)" if len(far) > 5 else ""
        raise ValueError(
            f"{label}: vertex {shown}{more} lies more than {OUTLIER_FACTOR:g} times farther from the surface's median "
            f"point than the median vertex (vertex {int(far[0])} at {points[far[0]].tolist()}): a corrupt "
            "coordinate? A mesher would fill a bounding box sized by it"
        )
    # Exporters split vertices at texture seams or sharp edges (a PLY or an OBJ with a vertex
    # per face corner): the surface is judged with coincident vertices welded, and without
    # the triangles that welding (or the file) leaves without area at a repeated vertex.
    points, triangles, _ = merge_coincident_nodes(points, triangles)
    ordered = np.sort(triangles, axis=1)
    triangles = triangles[(ordered[:, 0] != ordered[:, 1]) & (ordered[:, 1] != ordered[:, 2])]
    if len(triangles) == 0:
        raise ValueError(f"{label} has no triangle with three distinct vertices")
    edges = np.sort(np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]), axis=1)
    unique, counts = np.unique(edges, axis=0, return_counts=True)
    open_edges, shared = unique[counts == 1], unique[counts > 2]
    if len(open_edges):
        a, b = open_edges[0].tolist()
        raise ValueError(
            f"{label} is not closed: {len(open_edges)} edge(s) belong to one triangle only (e.g. the edge between "
            f"vertices {a} and {b}); a volume needs a watertight surface"
        )
    if len(shared):
        a, b = shared[0].tolist()
        raise ValueError(
            f"{label} is not manifold: {len(shared)} edge(s) are shared by more than two triangles (e.g. the edge "
            f"between vertices {a} and {b})"
        )
    volume = abs(enclosed_volume(points, triangles))
    if not np.isfinite(volume):
        raise ValueError(f"{label}: the enclosed volume overflows (coordinates too large)")
    if not volume > 0:
        raise ValueError(f"{label} encloses no volume")
