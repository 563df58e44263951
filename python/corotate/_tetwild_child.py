"""The fTetWild run of :func:`corotate.tetrahedralize`, as a script for a child process.

fTetWild (C++) can crash (SIGSEGV, "double free or corruption") or run for minutes on
surfaces it dislikes; run here, in its own process started by meshing.py, neither takes
the caller down: the parent sees the exit signal or ends the process at its time limit.

Usage: python _tetwild_child.py request.npz answer.npz   (in a scratch working directory,
where fTetWild writes its __tracked_surface.stl). Imports only NumPy and pytetwild, not
corotate, so the child starts fast.

request.npz: vertices (nv, 3), triangles (nt, 3), envelope, and either edge_length or
target_cells, first_length, max_tries, tolerance. answer.npz: points (n, 3), tets (m, 4).
"""

from __future__ import annotations

import sys

import numpy as np


def _run(vertices: np.ndarray, triangles: np.ndarray, length: float, envelope: float) -> tuple[np.ndarray, np.ndarray]:
    import pytetwild  # type: ignore[import-not-found,unused-ignore]

    points, tets = pytetwild.tetrahedralize(
        vertices, triangles, edge_length_abs=float(length), epsilon=float(envelope), coarsen=True, quiet=True
    )
    return np.asarray(points, dtype=np.float64), np.asarray(tets, dtype=np.int64)


def _mesh(request: dict) -> tuple[np.ndarray, np.ndarray]:
    """One run at the given edge length, or runs that correct the length from each count
    until it is within tolerance of target_cells or max_tries are done (the closest wins)."""
    x, tri, envelope = request["vertices"], request["triangles"].astype(np.int32), float(request["envelope"])
    if "edge_length" in request:
        return _run(x, tri, float(request["edge_length"]), envelope)
    target, length = int(request["target_cells"]), float(request["first_length"])
    best: tuple[np.ndarray, np.ndarray] | None = None
    for _ in range(max(1, int(request["max_tries"]))):
        points, tets = _run(x, tri, length, envelope)
        if best is None or abs(len(tets) - target) < abs(len(best[1]) - target):
            best = (points, tets)
        ratio = len(tets) / target
        if abs(ratio - 1) <= float(request["tolerance"]) or len(tets) == 0:
            break
        length *= ratio ** (1 / 3)
    assert best is not None
    return best


def main(argv: list[str]) -> int:
    request_path, answer_path = argv
    with np.load(request_path, allow_pickle=False) as data:
        request = {key: data[key] for key in data.files}
    points, tets = _mesh(request)
    np.savez(answer_path, points=points, tets=tets)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
