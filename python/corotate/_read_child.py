"""A mesh file read by meshio in a child process (see mesh_files.read_mesh_file): for the
formats whose meshio readers have not been fuzzed here, some of which loop forever on a
corrupt file (Nastran, Tecplot and MDPA files cut short or missing a line).

Usage: python _read_child.py file answer.npz. Writes the points and the cell blocks
(types, cells_0, cells_1, ...) to answer.npz, or, when the file cannot be read, the
message of the ValueError to answer.npz.txt; blocks of cells of varying size (polygons,
polyhedra) are written as (m, 0) arrays: their type and count, which is all the readers
here use of them.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

import numpy as np


def main(argv: list[str]) -> int:
    from corotate.mesh_io import read_meshio_file

    path, answer = Path(argv[0]), Path(argv[1])
    try:
        mesh = read_meshio_file(path)
    except (ValueError, FileNotFoundError) as e:
        answer.with_suffix(".npz.txt").write_text(str(e))
        return 0
    arrays: dict[str, Any] = {"points": np.asarray(mesh.points, dtype=np.float64)}
    types = []
    for i, block in enumerate(mesh.cells):
        data = np.asarray(block.data) if not isinstance(block.data, list) else np.asarray(block.data, dtype=object)
        if data.dtype == object or data.ndim != 2:
            data = np.zeros((len(block.data), 0), dtype=np.int64)
        types.append(str(block.type))
        arrays[f"cells_{i}"] = data
    arrays["types"] = np.array(types, dtype=str)
    np.savez(answer, **arrays)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
