"""The one file reader behind every path that takes a mesh or surface file
(:func:`corotate.read_mesh`, :func:`corotate.read_surface`,
:meth:`corotate.EmbeddedSurface.from_file`, :func:`corotate.tetrahedralize`), so that a
file gets the same answer whichever function reads it.

* TetGen .node/.ele pairs are read by :func:`corotate.mesh_io.read_tetgen` (strict,
  never meshio's reader, which loops forever on an empty file);
* headers that make a meshio reader loop forever are refused first: meshio's PLY reader
  skips to the next non-empty line until it finds ``end_header``, and its OFF reader
  until it finds the counts line, both without stopping at the end of the file (a
  two-line PLY header ``ply`` / ``format ascii 1.0`` hangs the process);
* a binary STL whose size does not match its triangle count is refused (meshio would
  trust a corrupt count, see :func:`_check_stl_size`);
* the formats the fuzz tests cover go to :func:`corotate.mesh_io.read_meshio_file` (meshio
  with every failure turned into a ValueError naming the file, cell counts checked);
* every other format is read the same way in a child process with a time limit: some
  meshio readers loop forever on a corrupt file (Nastran, Tecplot, MDPA files cut short).
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import Any

import numpy as np

from ._child_process import ChildFailed, run_script
from .mesh import _meshio
from .mesh_io import read_meshio_file, read_tetgen

__all__ = ["FUZZED_SUFFIXES", "READ_TIME_LIMIT", "TETGEN_SUFFIXES", "read_mesh_file"]

TETGEN_SUFFIXES = (".node", ".ele")
#: Formats whose meshio readers (with the guards here) the fuzz tests cover (tests/io/); any
#: other format is read in a child process stopped after READ_TIME_LIMIT seconds (the
#: environment variable COROTATE_READ_TIME_LIMIT sets it; default 300).
FUZZED_SUFFIXES = (".vtu", ".vtk", ".msh", ".inp", ".obj", ".stl", ".ply", ".off")
READ_TIME_LIMIT = float(os.environ.get("COROTATE_READ_TIME_LIMIT", "300"))
_READ_CHILD = Path(__file__).with_name("_read_child.py")


def read_mesh_file(path: Path) -> Any:
    """The file at path as a meshio.Mesh (TetGen pairs as one "tetra" block).

    Raises FileNotFoundError for a missing file, ValueError naming the file for one that
    cannot be read."""
    suffix = path.suffix.lower()
    if suffix in TETGEN_SUFFIXES:
        points, cells, cell_type = read_tetgen(path)
        return _meshio().Mesh(points, [(cell_type, cells)])
    if not path.is_file():
        raise FileNotFoundError(f"mesh file not found: {path}")
    if suffix == ".ply":
        _check_ply_header(path)
    elif suffix == ".off":
        _check_off_header(path)
    elif suffix == ".stl":
        _check_stl_size(path)
    if suffix not in FUZZED_SUFFIXES:
        return _read_in_child(path)
    return read_meshio_file(path)


def _read_in_child(path: Path) -> Any:
    """read_meshio_file(path) run in a child process (_read_child.py) stopped after
    READ_TIME_LIMIT seconds; every failure a ValueError naming the file."""
    with tempfile.TemporaryDirectory(prefix="corotate-read-") as scratch:
        answer = Path(scratch, "answer.npz")
        try:
            run_script(_READ_CHILD, [str(path), str(answer)], READ_TIME_LIMIT)
        except ChildFailed as e:
            raise ValueError(
                f"could not read mesh file {path}: meshio's reader for {path.suffix!r} failed ({e}); a corrupt file "
                "can make some readers loop forever"
            ) from None
        error = answer.with_suffix(".npz.txt")
        if error.exists():
            raise ValueError(error.read_text())
        with np.load(answer, allow_pickle=False) as data:
            blocks = [(str(t), data[f"cells_{i}"]) for i, t in enumerate(data["types"].tolist())]
            return _meshio().Mesh(data["points"], blocks)


def _significant_lines(path: Path, limit: int = 1 << 20) -> list[str]:
    """The stripped non-empty lines of the file's first `limit` bytes (a header is text
    even in a binary file; what follows it may decode as garbage, which is harmless)."""
    with path.open("rb") as f:
        head = f.read(limit)
    return [s for s in (line.strip() for line in head.decode("latin-1").splitlines()) if s]


def _check_ply_header(path: Path) -> None:
    lines = _significant_lines(path)
    if not lines or lines[0] != "ply":
        raise ValueError(f"could not read mesh file {path}: a PLY file starts with the line 'ply'")
    header_end = next((i for i, s in enumerate(lines) if s == "end_header"), None)
    if header_end is None:
        raise ValueError(f"could not read mesh file {path}: the PLY header has no 'end_header' line (truncated?)")
    if len(lines) > 1 and lines[1].startswith("format binary"):
        _check_ply_binary_size(path, lines[:header_end])


# Bytes of the PLY scalar types.
_PLY_SIZES = {
    **dict.fromkeys(("char", "uchar", "int8", "uint8"), 1),
    **dict.fromkeys(("short", "ushort", "int16", "uint16"), 2),
    **dict.fromkeys(("int", "uint", "int32", "uint32", "float", "float32"), 4),
    **dict.fromkeys(("double", "float64"), 8),
}


def _check_ply_binary_size(path: Path, header: list[str]) -> None:
    """The elements a binary PLY header declares must fit in the bytes after it (each row
    at least its scalar properties and its lists' counts): meshio walks a declared face
    count of 10^8 byte by byte in Python, for minutes, past the end of the data."""
    needed, declared = 0, []
    for line in header:
        words = line.split()
        if words[0] == "element" and len(words) == 3 and words[2].isdigit():
            declared.append((words[1], int(words[2])))
        elif words[0] == "property" and declared and len(words) >= 3:
            size = _PLY_SIZES.get(words[2] if words[1] == "list" else words[1])
            if size is None:
                return  # an unknown type: meshio names it
            needed += declared[-1][1] * size
    raw = path.read_bytes()
    end = raw.find(b"end_header")
    available = len(raw) - (raw.find(b"\n", end) + 1)
    if needed > available:
        counts = ", ".join(f"{n} {name}" for name, n in declared)
        raise ValueError(
            f"could not read mesh file {path}: the PLY header declares {counts}, at least {needed} bytes, but "
            f"{available} bytes follow it (a corrupt count or a truncated file)"
        )


def _check_off_header(path: Path) -> None:
    lines = [s for s in _significant_lines(path) if not s.startswith("#")]
    if not lines or lines[0] != "OFF":
        raise ValueError(f"could not read mesh file {path}: an OFF file starts with the line 'OFF'")
    if len(lines) < 2 or len(lines[1].split()) != 3:
        raise ValueError(f"could not read mesh file {path}: the OFF header has no 'vertices faces edges' counts line")


def _check_stl_size(path: Path) -> None:
    """A binary STL holds exactly 84 + 50 n bytes for the n triangles its header declares;
    anything else must be ASCII ("solid ..."). meshio compares the size in 32-bit
    arithmetic, so a flipped top bit of n (n + 2^31: 50 (n + 2^31) wraps to 50 n) passes
    its test and it allocates 100 GiB for the triangles."""
    size = path.stat().st_size
    with path.open("rb") as f:
        head = f.read(84)
    if size >= 84 and 84 + 50 * int.from_bytes(head[80:84], "little") == size:
        return
    if head.lstrip()[:5].lower() == b"solid" and all(32 <= c < 127 or c in b"\t\r\n" for c in head):
        with path.open("rb") as f:
            f.seek(max(0, size - 1024))
            tail = [line.strip() for line in f.read().splitlines() if line.strip()]
        if not tail or not tail[-1].lower().startswith(b"endsolid"):  # meshio would drop the cut facets
            raise ValueError(
                f"could not read mesh file {path}: the ASCII STL does not end with 'endsolid' (truncated?)"
            )
        return
    declared = int.from_bytes(head[80:84], "little") if size >= 84 else 0
    raise ValueError(
        f"could not read mesh file {path}: not an ASCII STL (which starts with 'solid') and not a binary STL "
        f"(its header declares {declared} triangles, {84 + 50 * declared} bytes, but the file has {size})"
    )
