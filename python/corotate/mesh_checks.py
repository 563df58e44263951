"""Checks that a volume mesh is one solid: what :class:`corotate.Mesh` verifies for
every solid cell type (the core's cell-type table), with a clear verdict instead of a body that is
silently wrong.

* duplicate cells (the same nodes, in any order) double the mass there;
* coincident nodes (two nodes at one position that no cell holds both of) leave the cells
  on either side unconnected: a "tet soup", each cell with its own copies of its corners,
  falls apart;
* a cell that names one node twice has no volume;
* overlapping (tangled) cells: in a valid mesh every interior face is shared by exactly
  two cells, which lie on opposite sides of it. Two cells on the same side of a shared
  face (after turning inverted cells around), or a face of three or more cells, overlap;
  so does a mesh whose cell volumes add up to more than the volume its boundary encloses
  (a 1 m3 box holding 1.667 m3 of cells).

Duplicates and coincident nodes can be repaired (``Mesh(..., repair=True)``,
``read_mesh(..., repair=True)``, or :func:`drop_duplicate_cells` and
:func:`merge_coincident_nodes` on arrays); overlap cannot, the mesh must be rebuilt.
"""

from __future__ import annotations

import warnings
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

if TYPE_CHECKING:
    from .mesh import Mesh

__all__ = [
    "COINCIDENT_TOLERANCE",
    "check_volume_mesh",
    "coincident_node_pairs",
    "drop_duplicate_cells",
    "duplicate_cells",
    "merge_coincident_nodes",
]

#: Two nodes closer than this fraction of the mesh's bounding-box diagonal coincide.
COINCIDENT_TOLERANCE = 1e-10

_REPAIR_HINT = "Mesh(..., repair=True) or read_mesh(..., repair=True) repairs it"


def _row_groups(rows: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Equal rows of rows (r, k) grouped: (group of each row (r,), rows per group (g,),
    first row of each group (g,)). np.unique(axis=0) does the same, several times slower."""
    if len(rows) == 0:
        empty = np.zeros(0, dtype=np.int64)
        return empty, empty, empty
    base = int(rows.max()) + 1
    if base ** rows.shape[1] < 2**62:  # each row as one integer: one stable argsort, 4x faster than lexsort
        key = np.zeros(len(rows), dtype=np.int64)
        for column in rows.T:
            key = key * base + column
        order = np.argsort(key, kind="stable")  # stable: a group's first row comes first
        starts = np.ones(len(rows), dtype=bool)
        starts[1:] = key[order[1:]] != key[order[:-1]]
    else:
        order = np.lexsort(rows.T[::-1])
        ordered = rows[order]
        starts = np.ones(len(rows), dtype=bool)
        starts[1:] = (ordered[1:] != ordered[:-1]).any(axis=1)
    group = np.empty(len(rows), dtype=np.int64)
    group[order] = np.cumsum(starts) - 1
    return group, np.bincount(group), order[starts]


def duplicate_cells(cells: np.ndarray) -> np.ndarray:
    """(d, 2) pairs (first, duplicate) of cells (m, k) with the same node set, the
    duplicate after the first; node order does not matter."""
    if len(cells) == 0:
        return np.zeros((0, 2), dtype=np.int64)
    inverse, _, first = _row_groups(np.sort(cells, axis=1))
    copies = np.flatnonzero(first[inverse] != np.arange(len(cells)))
    return np.column_stack([first[inverse[copies]], copies]).astype(np.int64)


def drop_duplicate_cells(cells: np.ndarray) -> tuple[np.ndarray, int]:
    """cells (m, k) without the cells that repeat an earlier one (any node order), and how
    many were dropped."""
    copies = duplicate_cells(cells)[:, 1]
    return np.delete(cells, copies, axis=0), len(copies)


def coincident_node_pairs(points: np.ndarray, tolerance: float = COINCIDENT_TOLERANCE) -> np.ndarray:
    """(p, 2) pairs i < j of nodes closer than tolerance x the bounding-box diagonal,
    sorted."""
    if len(points) < 2:
        return np.zeros((0, 2), dtype=np.int64)
    diagonal = float(np.linalg.norm(points.max(axis=0) - points.min(axis=0)))
    pairs = cKDTree(points).query_pairs(tolerance * diagonal, output_type="ndarray")
    pairs = np.sort(pairs.astype(np.int64), axis=1)
    return pairs[np.lexsort((pairs[:, 1], pairs[:, 0]))]


def merge_coincident_nodes(
    points: np.ndarray, cells: np.ndarray, tolerance: float = COINCIDENT_TOLERANCE
) -> tuple[np.ndarray, np.ndarray, int]:
    """(points, cells, merged): each group of coincident nodes (see coincident_node_pairs)
    becomes its lowest-numbered node and the others are dropped (merged counts them); the
    remaining nodes keep their order."""
    pairs = coincident_node_pairs(points, tolerance)
    if len(pairs) == 0:
        return points, cells, 0
    n = len(points)
    graph = sp.coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    _, group = connected_components(graph, directed=False)
    lowest = np.full(group.max() + 1, n, dtype=np.int64)
    np.minimum.at(lowest, group, np.arange(n))
    target = lowest[group]  # the node each node becomes
    kept = target == np.arange(n)
    renumber = np.cumsum(kept) - 1
    return points[kept], renumber[target][cells], int(n - kept.sum())


def check_volume_mesh(mesh: Mesh, repair: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The mesh's (points, cells, kept), checked as the module docstring says; with repair,
    coincident nodes merged and duplicate cells dropped first (a warning counts each);
    kept: the indices of the input cells that remain (for data per cell, such as regions).

    Raises ValueError naming the first cells or nodes at fault and how many there are."""
    points, cells = mesh.points, mesh.cells
    kept = np.arange(len(cells))
    if repair:
        points, cells, merged = merge_coincident_nodes(points, cells)
        kept = np.delete(kept, duplicate_cells(cells)[:, 1])
        cells, dropped = drop_duplicate_cells(cells)
        for count, what in ((merged, "coincident node(s) merged"), (dropped, "duplicate cell(s) dropped")):
            if count:
                warnings.warn(f"mesh repaired: {count} {what}", stacklevel=3)
    copies = duplicate_cells(cells)
    if len(copies):
        i, j = copies[0].tolist()
        raise ValueError(
            f"cell {j} repeats cell {i} (the same nodes{'' if np.array_equal(cells[i], cells[j]) else ', permuted'}; "
            f"{len(copies)} duplicate cell(s) in all): duplicates double the mass; {_REPAIR_HINT}"
        )
    pairs = _apart(coincident_node_pairs(points), cells, len(points))
    if len(pairs):
        i, j = pairs[0].tolist()
        raise ValueError(
            f"nodes {i} and {j} are at the same position {points[i].tolist()} ({len(pairs)} coincident pair(s) in "
            f"all): cells that meet there are not connected (a 'tet soup' falls apart); {_REPAIR_HINT}"
        )
    ordered = np.sort(cells, axis=1)
    repeated = np.flatnonzero((ordered[:, 1:] == ordered[:, :-1]).any(axis=1))
    if len(repeated):
        raise ValueError(f"cell {int(repeated[0])} names a node twice ({len(repeated)} such cell(s)): it has no volume")
    if len(cells):
        _check_no_overlap(mesh, points, cells)
    return points, cells, kept


def _apart(pairs: np.ndarray, cells: np.ndarray, n_nodes: int) -> np.ndarray:
    """The node pairs no cell holds both of: those leave cells unconnected. (Two nodes of
    one cell at one position make that cell flat, which Body reports by cell.)"""
    if len(pairs) == 0:
        return pairs
    rows = np.repeat(np.arange(len(cells)), cells.shape[1])
    incidence = sp.csr_matrix((np.ones(cells.size), (cells.ravel(), rows)), shape=(n_nodes, len(cells)))
    shared = np.asarray(incidence[pairs[:, 0]].multiply(incidence[pairs[:, 1]]).sum(axis=1)).ravel()
    return pairs[shared == 0]


def _cell_faces(cell_type: str) -> np.ndarray:
    """(f, c) corner nodes of each face of a cell, outward (the core's cell-type table)."""
    from .mesh import _CELL_TYPES

    return np.asarray(_CELL_TYPES[cell_type]["faces"], dtype=np.int64)


def _check_no_overlap(mesh: Mesh, points: np.ndarray, cells: np.ndarray) -> None:
    """ValueError if two cells lie on the same side of a shared face, a face belongs to
    more than two cells, or the cells' volumes exceed the volume their boundary encloses."""
    from .mesh import Mesh

    checked = mesh if points is mesh.points and cells is mesh.cells else _unchecked(Mesh, points, cells, mesh.cell_type)
    volumes = checked.cell_volumes()
    local = _cell_faces(mesh.cell_type)
    faces = cells[:, local]  # (m, f, c), outward for a positive cell
    faces[volumes < 0] = faces[volumes < 0][:, :, ::-1]  # outward for an inverted cell too
    faces = faces.reshape(-1, local.shape[1])
    owner = np.repeat(np.arange(len(cells)), local.shape[0])
    keep = np.repeat(volumes != 0, local.shape[0])  # flat cells have no side; Body names them
    faces, owner = faces[keep], owner[keep]
    group, counts, _ = _row_groups(np.sort(faces, axis=1))
    crowded = np.flatnonzero(counts[group] > 2)
    if len(crowded):
        shared = owner[group == group[crowded[0]]]
        raise ValueError(
            f"cells {', '.join(map(str, shared.tolist()))} share one face {faces[crowded[0]].tolist()}: a face "
            "belongs to at most two cells, these overlap"
        )
    # Two cells on opposite sides run the shared face in opposite directions: the node
    # after the face's lowest node differs.
    lowest = np.argmin(faces, axis=1)
    after = faces[np.arange(len(faces)), (lowest + 1) % faces.shape[1]]
    order = np.argsort(group, kind="stable")
    pair = order[np.flatnonzero(counts[group[order]] == 2)].reshape(-1, 2)
    same_side = pair[after[pair[:, 0]] == after[pair[:, 1]]]
    if len(same_side):
        a, b = owner[same_side[0]].tolist()
        inverted = [c for c in (a, b) if volumes[c] < 0]
        note = f"; cell {inverted[0]} is inverted" if inverted else ""
        raise ValueError(
            f"cells {a} and {b} lie on the same side of their shared face {faces[same_side[0, 0]].tolist()}: the mesh "
            f"is tangled (overlapping cells; {len(same_side)} such face(s){note})"
        )
    if (volumes == 0).any():
        return  # a flat cell's faces were left out above, so the boundary has holes; Body names the cell
    outer = faces[counts[group] == 1]
    enclosed = _enclosed_volume(points, outer)
    total = float(np.abs(_corner_cell_volumes(mesh.cell_type, points, cells)).sum())
    if total > enclosed * (1 + 1e-6) + 1e-300:
        raise ValueError(
            f"the cells' volumes add up to {total:.6g} but the boundary encloses {enclosed:.6g}: cells overlap "
            f"(the mesh is tangled; {int((volumes < 0).sum())} of {len(cells)} cells are inverted)"
        )


def _corner_cell_volumes(cell_type: str, points: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Volumes of the cells spanned by their corners alone (the linear element of the same
    reference domain): the solid the flat corner faces of _enclosed_volume bound exactly,
    where a quadratic cell with curved edges has a slightly different volume of its own."""
    from . import _core
    from .mesh import _CELL_TYPES

    facts = _CELL_TYPES[cell_type]
    linear = next(
        name
        for name, f in _CELL_TYPES.items()
        if f["order"] == 1 and f["dim"] == facts["dim"] and f["domain"] == facts["domain"]
    )
    return np.asarray(_core.cell_volumes(linear, points, cells[:, : facts["num_corners"]]))


def _unchecked(
    mesh_class: type[Mesh],
    points: np.ndarray,
    cells: np.ndarray,
    cell_type: str,
    cell_regions: np.ndarray | None = None,
) -> Mesh:
    """A Mesh holding the arrays without running the checks again (for its geometry, or a
    mesh joined from checked parts)."""
    mesh = mesh_class.__new__(mesh_class)
    mesh.points, mesh.cells, mesh.cell_type, mesh.cell_regions = points, cells, cell_type, cell_regions
    return mesh


def _enclosed_volume(points: np.ndarray, faces: np.ndarray) -> float:
    """Volume enclosed by outward triangles or bilinear quads (divergence theorem; a
    quad's flux is the mean of its two diagonal splits, exact for a bilinear patch)."""
    x = points[faces] - points.mean(axis=0)  # about the middle: less cancellation

    def cone(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> float:
        return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6)

    if faces.shape[1] == 3:
        return cone(x[:, 0], x[:, 1], x[:, 2])
    split_02 = cone(x[:, 0], x[:, 1], x[:, 2]) + cone(x[:, 0], x[:, 2], x[:, 3])
    split_13 = cone(x[:, 1], x[:, 2], x[:, 3]) + cone(x[:, 1], x[:, 3], x[:, 0])
    return 0.5 * (split_02 + split_13)
