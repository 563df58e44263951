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
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ._child_process import ChildFailed, run_script
from .mesh import Mesh
from .surface_checks import check_closed_surface, enclosed_volume

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["tetrahedralize", "mesher_available"]

# fTetWild runs in a child process started from this script (see _run_in_child).
_CHILD_SCRIPT = Path(__file__).with_name("_tetwild_child.py")

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
    time_limit: float = 600.0,
) -> Mesh:
    """Fill a closed triangle surface with tetrahedra (fTetWild).

    surface       a triangle Mesh, a file (.obj, .stl, .ply, .off, ...; read as by
                  :func:`corotate.read_surface`), or (vertices (nv, 3), triangles (nt, 3))
    target_cells  about how many tets (default 1000): the ideal edge length is guessed
                  from the enclosed volume and corrected from the count of each try,
                  until the count is within ``tolerance`` (relative) of the target or
                  ``max_tries`` runs are done (the closest is returned). None: use
                  ``edge_length`` as given.
    edge_length   ideal tet edge length [m] (with target_cells=None)
    envelope      how far the tet mesh's boundary may deviate from the surface,
                  relative to the bounding-box diagonal (fTetWild's epsilon); coarse
                  cages need some room (default 2e-3)
    time_limit    seconds fTetWild may run (all tries together) before it is stopped
    returns       Mesh of positively oriented "tetra" cells (VTK order)

    The surface is checked first (see :func:`corotate.surface_checks.check_closed_surface`):
    closed, every edge on exactly two triangles, no vertex far off the rest (a corrupt
    coordinate would make fTetWild fill a huge box for minutes, or crash). fTetWild runs
    in a child process, so that a crash inside it cannot end the caller's process.

    Raises ImportError naming the extra when pytetwild is missing; ValueError for a
    surface that is not triangles, not finite, open, non-manifold, has outlier vertices
    (named) or encloses no volume; RuntimeError when fTetWild crashes (the signal is
    named) or exceeds time_limit.
    """
    if isinstance(surface, Mesh):
        tri_mesh, label = surface, "the surface"
    elif isinstance(surface, (str, os.PathLike)):
        from .embedding import read_surface

        tri_mesh, label = read_surface(surface), str(surface)
    else:
        vertices, triangles = surface
        tri_mesh, label = Mesh(vertices, triangles, "triangle"), "the surface"
    if tri_mesh.cell_type != "triangle" or tri_mesh.n_cells == 0:
        raise ValueError("tetrahedralize needs a surface of triangles")
    if target_cells is None and (edge_length is None or not edge_length > 0):
        raise ValueError("give target_cells or a positive edge_length")
    if target_cells is not None and int(target_cells) < 1:
        raise ValueError(f"target_cells must be >= 1, got {target_cells}")
    if not 0 < envelope < 1:
        raise ValueError(f"envelope must be in (0, 1), got {envelope}")
    if not time_limit > 0:
        raise ValueError(f"time_limit must be positive, got {time_limit}")
    x, tri = tri_mesh.points, tri_mesh.cells
    check_closed_surface(x, tri, label)
    _pytetwild()  # ImportError naming the extra, before the child process starts
    request: dict[str, Any] = {"vertices": x, "triangles": tri, "envelope": float(envelope)}
    if target_cells is None:
        request["edge_length"] = float(edge_length)  # type: ignore[arg-type]
    else:
        # A regular tet of edge L has volume L^3 / (6 sqrt 2); meshes have ~1.5x smaller cells.
        volume = abs(enclosed_volume(x, tri))
        request.update(
            target_cells=int(target_cells),
            first_length=(volume / target_cells * 6 * np.sqrt(2) * 1.5) ** (1 / 3),
            max_tries=int(max_tries),
            tolerance=float(tolerance),
        )
    points, tets = _run_in_child(request, float(time_limit))
    if len(tets) == 0:
        raise ValueError("fTetWild returned no tetrahedra (is the surface closed?)")
    mesh = Mesh(points, tets, "tetra")
    negative = mesh.cell_volumes() < 0
    mesh.cells[negative] = mesh.cells[negative][:, [0, 2, 1, 3]]  # fTetWild's own order is mirrored
    return mesh


def _run_in_child(request: dict[str, Any], time_limit: float) -> tuple[np.ndarray, np.ndarray]:
    """(points, tets) from _tetwild_child.py run in a child process in a scratch directory
    (fTetWild writes a scratch file into its working directory); RuntimeError naming what
    happened when it crashes, fails or runs past time_limit seconds."""
    with tempfile.TemporaryDirectory(prefix="corotate-tetwild-") as scratch:
        request_path, answer_path = Path(scratch, "request.npz"), Path(scratch, "answer.npz")
        np.savez(request_path, **request)
        try:
            run_script(_CHILD_SCRIPT, [str(request_path), str(answer_path)], time_limit, cwd=scratch)
        except ChildFailed as e:
            hint = "; a coarser target (fewer target_cells) or a cleaner surface may help" if "within" in str(e) else ""
            raise RuntimeError(f"fTetWild failed (time_limit={time_limit:g} s): {e}{hint}") from None
        with np.load(answer_path, allow_pickle=False) as answer:
            return np.asarray(answer["points"], dtype=np.float64), np.asarray(answer["tets"], dtype=np.int64)
