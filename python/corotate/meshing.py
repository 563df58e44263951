"""A simulation mesh for a render surface: :func:`tetrahedralize` fills a closed triangle
surface with tetrahedra through fTetWild (the optional extra ``corotate-fem[mesh]``, which
installs ``pytetwild``, MPL-2.0, and the ``pyvista`` it imports).

Why fTetWild: it accepts real-world surfaces (self-intersections, holes, slivers) and always
returns a valid tet mesh of a controllable size, which is what a coarse cage for an embedded
surface needs; it is MPL-2.0, usable from this MIT package. TetGen (the ``tetgen`` and
``meshpy`` wheels) is AGPL-3.0, and Gmsh is GPL-2.0+, both copyleft beyond what an optional
extra of an MIT package should impose on its users, and both need a clean, watertight input.
"""

from __future__ import annotations

import os
import tempfile
from typing import TYPE_CHECKING, Any

import numpy as np

from .mesh import Mesh

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["tetrahedralize", "mesher_available"]

_EXTRA = "tetrahedralize needs the optional extra: pip install 'corotate-fem[mesh]' (pytetwild, pyvista)"


def _pytetwild() -> Any:
    try:
        import pytetwild  # type: ignore[import-not-found,unused-ignore]
    except ImportError as e:
        raise ImportError(f"{_EXTRA} ({e})") from e
    return pytetwild


def mesher_available() -> bool:
    """True when pytetwild (the extra ``corotate-fem[mesh]``) can be imported."""
    try:
        _pytetwild()
    except ImportError:
        return False
    return True


def tetrahedralize(
    surface: Mesh | str | os.PathLike[str] | tuple[ArrayLike, ArrayLike],
    target_cells: int | None = 1000,
    edge_length: float | None = None,
    envelope: float = 2e-3,
    max_tries: int = 4,
    tolerance: float = 0.25,
) -> Mesh:
    """Fill a closed triangle surface with tetrahedra (fTetWild).

    surface       a triangle Mesh, a file meshio reads (.obj, .stl, .ply, ...), or
                  (vertices (nv, 3), triangles (nt, 3))
    target_cells  about how many tets (default 1000): the ideal edge length is guessed
                  from the enclosed volume and corrected from the count of each try,
                  until the count is within ``tolerance`` (relative) of the target or
                  ``max_tries`` runs are done (the closest is returned). None: use
                  ``edge_length`` as given.
    edge_length   ideal tet edge length [m] (with target_cells=None)
    envelope      how far the tet mesh's boundary may deviate from the surface,
                  relative to the bounding-box diagonal (fTetWild's epsilon); coarse
                  cages need some room (default 2e-3)
    returns       Mesh of positively oriented "tetra" cells (VTK order)

    Raises ImportError naming the extra when pytetwild is missing, ValueError for a
    surface that is not triangles, not finite, or encloses no volume.
    """
    from .embedding import read_surface

    if isinstance(surface, Mesh):
        tri_mesh = surface
    elif isinstance(surface, (str, os.PathLike)):
        tri_mesh = read_surface(surface)
    else:
        vertices, triangles = surface
        tri_mesh = Mesh(vertices, triangles, "triangle")
    if tri_mesh.cell_type != "triangle" or tri_mesh.n_cells == 0:
        raise ValueError("tetrahedralize needs a surface of triangles")
    if target_cells is None and (edge_length is None or not edge_length > 0):
        raise ValueError("give target_cells or a positive edge_length")
    if target_cells is not None and int(target_cells) < 1:
        raise ValueError(f"target_cells must be >= 1, got {target_cells}")
    if not 0 < envelope < 1:
        raise ValueError(f"envelope must be in (0, 1), got {envelope}")
    pytetwild = _pytetwild()

    x, tri = tri_mesh.points, tri_mesh.cells
    # Enclosed volume by the divergence theorem (orientation-independent: its magnitude).
    volume = abs(np.einsum("ij,ij->i", x[tri[:, 0]], np.cross(x[tri[:, 1]], x[tri[:, 2]])).sum()) / 6
    if not volume > 0:
        raise ValueError("the surface encloses no volume (is it closed?)")

    def run(length: float) -> tuple[np.ndarray, np.ndarray]:
        # fTetWild writes a scratch file (__tracked_surface.stl) into the working directory:
        # run it in a temporary one (the working directory is process-wide, so a concurrent
        # thread that uses relative paths would be affected while it runs).
        cwd = os.getcwd()
        with tempfile.TemporaryDirectory(prefix="corotate-tetwild-") as scratch:
            os.chdir(scratch)
            try:
                points, tets = pytetwild.tetrahedralize(
                    x, tri.astype(np.int32), edge_length_abs=float(length), epsilon=envelope, coarsen=True, quiet=True
                )
            finally:
                os.chdir(cwd)
        return np.asarray(points, dtype=np.float64), np.asarray(tets, dtype=np.int64)

    if target_cells is None:
        points, tets = run(float(edge_length))  # type: ignore[arg-type]
    else:
        # A regular tet of edge L has volume L^3 / (6 sqrt 2); meshes have ~1.5x smaller cells.
        length = (volume / target_cells * 6 * np.sqrt(2) * 1.5) ** (1 / 3)
        best: tuple[np.ndarray, np.ndarray] | None = None
        for _ in range(max(1, int(max_tries))):
            points, tets = run(length)
            if best is None or abs(len(tets) - target_cells) < abs(len(best[1]) - target_cells):
                best = (points, tets)
            ratio = len(tets) / target_cells
            if abs(ratio - 1) <= tolerance or len(tets) == 0:
                break
            length *= ratio ** (1 / 3)
        points, tets = best  # type: ignore[misc]
    if len(tets) == 0:
        raise ValueError("fTetWild returned no tetrahedra (is the surface closed?)")
    mesh = Mesh(points, tets, "tetra")
    negative = mesh.cell_volumes() < 0
    mesh.cells[negative] = mesh.cells[negative][:, [0, 2, 1, 3]]  # fTetWild's own order is mirrored
    return mesh
