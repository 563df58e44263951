"""Reading mesh files safely: the parts of :func:`corotate.read_mesh` that
deal with hostile or corrupt input.

meshio does the parsing of every format except TetGen, but it trusts its input:
on a file it cannot read it prints the error and calls ``sys.exit(1)``, other
corruptions surface as raw ``IndexError`` / ``UnicodeDecodeError`` / reshape
errors without the file name, and some are read silently as a different mesh
(unknown VTK cell types are skipped, a Gmsh node tag 0 indexes the last node).
So this module

* calls meshio's reader for the format directly, turns ``SystemExit`` and any
  exception into a ``ValueError`` naming the file (``from`` the original);
* counts, independently of meshio, the cells a VTU / legacy VTK / ASCII Gmsh
  file declares (and checks the Gmsh node tags and ASCII VTU offsets), then
  requires meshio to have returned exactly that many;
* checks every cell block of the result: integer indices in range, the right
  node count per cell, no unsupported volume cells; lower-dimensional cells
  (boundary triangles, lines, vertices) are dropped with a warning that counts
  them;
* reads TetGen .node/.ele pairs itself (see :func:`read_tetgen` for why).
"""

from __future__ import annotations

import re
import warnings
from collections import Counter
from pathlib import Path
from typing import Any

import numpy as np

from .mesh import SUPPORTED_CELL_TYPES, VOLUME_CELL_TYPES, _index_block, _meshio, _volume_list

# meshio cell types of dimension < 3. A body is made of volume cells, so these
# (boundary faces, edges, marker points) are dropped with a warning; any other
# type that is not a supported volume type is an error.
_LOWER_DIM_PREFIXES = (
    "vertex",
    "line",
    "triangle",
    "quad",
    "polygon",
    "pixel",
    "VTK_LAGRANGE_CURVE",
    "VTK_LAGRANGE_TRIANGLE",
    "VTK_LAGRANGE_QUADRILATERAL",
    "VTK_BEZIER_CURVE",
    "VTK_BEZIER_TRIANGLE",
    "VTK_BEZIER_QUADRILATERAL",
)


def _is_lower_dim(cell_type: str) -> bool:
    return cell_type.startswith(_LOWER_DIM_PREFIXES)


# --------------------------------------------------------------------------
# meshio files
# --------------------------------------------------------------------------


def read_meshio_file(path: Path) -> Any:
    """Read ``path`` with meshio; returns a meshio.Mesh with as many cells as
    the file declares (where that can be counted independently).

    Raises FileNotFoundError if the file is missing, ValueError (naming the
    file) for anything else that goes wrong.
    """
    if not path.is_file():
        raise FileNotFoundError(f"mesh file not found: {path}")
    meshio = _meshio()
    try:
        declared = _declared_cell_count(path)
        if declared == 0:
            raise ValueError(
                f"{path} has no cells; found cell types [], supported: {_volume_list()} (no supported volume cells)"
            )
        m = _call_reader(meshio, path)
    except ValueError as e:
        if str(path) in str(e):
            raise
        raise ValueError(f"could not read mesh file {path}: {e}") from e
    except SystemExit as e:
        # meshio.read ends the process when no reader accepts a file; the
        # reader's own message is in the exception chain where there is one.
        raise ValueError(f"could not read mesh file {path}: meshio gave up (sys.exit({e.code}))") from e
    except Exception as e:  # any reader failure is a bad file
        raise ValueError(f"could not read mesh file {path}: {type(e).__name__}: {e}") from e
    if declared is not None:
        got = sum(len(b.data) for b in m.cells)
        if got != declared:
            raise ValueError(
                f"{path} declares {declared} cell(s) but meshio read {got}; the file is corrupt "
                "or holds cell types meshio skips"
            )
    return m


def _call_reader(meshio: Any, path: Path) -> Any:
    """meshio's reader(s) for the file extension, called directly so that a
    failure raises instead of printing and calling sys.exit."""
    helpers = getattr(meshio, "_helpers", None)
    formats_of = getattr(helpers, "_filetypes_from_path", None)
    readers = getattr(helpers, "reader_map", None)
    if formats_of is None or not isinstance(readers, dict):  # pragma: no cover - other meshio versions
        return meshio.read(path)  # SystemExit is caught by the caller
    formats = formats_of(path)
    problems = []
    for fmt in formats:
        if fmt not in readers:
            problems.append(f"no meshio reader for format {fmt!r}")
            continue
        try:
            return readers[fmt](str(path))
        except meshio.ReadError as e:
            problems.append(f"as {fmt}: {e}" if str(e) else f"as {fmt}: corrupt or unsupported content")
    raise ValueError("; ".join(problems) or "unknown file format")


def _declared_cell_count(path: Path) -> int | None:
    """The number of cells the file says it holds, counted without meshio, or
    None for formats this module does not count. Raises ValueError for
    inconsistencies found on the way (Gmsh node tags, VTU offsets)."""
    suffix = path.suffix.lower()
    if suffix == ".vtu":
        return _vtu_cell_count(path)
    if suffix == ".vtk":
        return _vtk_cell_count(path)
    if suffix == ".msh":
        return _gmsh_cell_count(path)
    return None


def _vtk_tables() -> tuple[dict[int, str], dict[str, int]]:
    """meshio's VTK type numbers -> names and names -> nodes per cell (both
    empty if this meshio version hides them elsewhere)."""
    try:
        from meshio._common import num_nodes_per_cell
        from meshio._vtk_common import vtk_to_meshio_type
    except ImportError:  # pragma: no cover - other meshio versions
        return {}, {}
    return dict(vtk_to_meshio_type), dict(num_nodes_per_cell)


def _vtu_cell_count(path: Path) -> int | None:
    raw = path.read_bytes()
    head = raw.split(b"<AppendedData", 1)[0]
    pieces = re.findall(rb"<Piece\b[^>]*>", head)
    if not pieces:
        return None  # meshio will say what is wrong
    total = 0
    for tag in pieces:
        match = re.search(rb'NumberOfCells\s*=\s*"\s*([^"]*?)\s*"', tag)
        if match is None:
            raise ValueError(f"{path}: a <Piece> has no NumberOfCells")
        try:
            n = int(match.group(1))
        except ValueError:
            raise ValueError(f"{path}: bad NumberOfCells {match.group(1)!r}") from None
        if n < 0:
            raise ValueError(f"{path}: negative NumberOfCells {n}")
        total += n
    if len(raw) == len(head):
        _check_ascii_vtu_offsets(path, head)
    return total


def _check_ascii_vtu_offsets(path: Path, text: bytes) -> None:
    """In ASCII VTU cell arrays, each cell's offset step must be its type's
    node count: meshio takes the last k nodes before each offset, so a
    corrupted type would otherwise read a different cell."""
    vtk_types, per_cell = _vtk_tables()
    if not vtk_types:  # pragma: no cover
        return
    arrays: dict[bytes, list[np.ndarray]] = {b"types": [], b"offsets": []}
    for attrs, body in re.findall(rb"<DataArray\b([^>]*)>(.*?)</DataArray>", text, flags=re.S):
        name = re.search(rb'Name\s*=\s*"([^"]*)"', attrs)
        fmt = re.search(rb'format\s*=\s*"([^"]*)"', attrs)
        if name is None or name.group(1) not in arrays:
            continue
        if fmt is None or fmt.group(1).strip().lower() != b"ascii":
            return  # binary data: zlib checksums and meshio catch corruption
        try:
            arrays[name.group(1)].append(np.array(body.split(), dtype=np.int64))
        except (ValueError, OverflowError):
            raise ValueError(f"{path}: non-integer value in cell array {name.group(1).decode()!r}") from None
    for types, offsets in zip(arrays[b"types"], arrays[b"offsets"]):
        if len(types) != len(offsets):
            raise ValueError(f"{path}: {len(types)} cell types but {len(offsets)} offsets")
        steps = np.diff(np.concatenate([[0], offsets]))
        for i, (t, step) in enumerate(zip(types.tolist(), steps.tolist())):
            type_name = vtk_types.get(t)
            if type_name is None:
                raise ValueError(f"{path}: cell {i} has unknown VTK cell type {t}")
            k = per_cell.get(type_name)
            if k is not None and step != k:
                raise ValueError(f"{path}: cell {i} of type {type_name} has {step} node(s), expected {k}")


def _vtk_cell_count(path: Path) -> int | None:
    match = re.search(rb"^\s*CELL_TYPES\s+(\S+)", path.read_bytes(), flags=re.M)
    if match is None:
        return None
    try:
        n = int(match.group(1))
    except ValueError:
        raise ValueError(f"{path}: bad CELL_TYPES count {match.group(1)!r}") from None
    if n < 0:
        raise ValueError(f"{path}: negative CELL_TYPES count {n}")
    return n


# -- Gmsh ---------------------------------------------------------------------


def _gmsh_nodes_per_type() -> dict[int, int]:
    try:
        from meshio._common import num_nodes_per_cell
        from meshio.gmsh.common import _gmsh_to_meshio_type
    except ImportError:  # pragma: no cover - other meshio versions
        return {}
    return {int(t): num_nodes_per_cell[name] for t, name in _gmsh_to_meshio_type.items() if name in num_nodes_per_cell}


def _gmsh_sections(path: Path, lines: list[str]) -> dict[str, list[list[str]]]:
    """$Name ... $EndName sections as lists of token rows (blank rows dropped)."""
    sections: dict[str, list[list[str]]] = {}
    i = 0
    while i < len(lines):
        s = lines[i].strip()
        if s.startswith("$") and not s.startswith("$End"):
            name = s[1:]
            try:
                end = lines.index(f"$End{name}", i + 1)
            except ValueError:
                # Some writers pad the end marker; fall back to a stripped search.
                ends = [j for j in range(i + 1, len(lines)) if lines[j].strip() == f"$End{name}"]
                if not ends:
                    raise ValueError(f"{path}: section ${name} has no $End{name}") from None
                end = ends[0]
            if name in ("Nodes", "Elements", "MeshFormat") and name in sections:
                raise ValueError(f"{path}: more than one ${name} section")
            sections[name] = [row for row in (ln.split() for ln in lines[i + 1 : end]) if row]
            i = end + 1
        else:
            i += 1
    return sections


def _ints(path: Path, row: list[str], what: str) -> list[int]:
    try:
        return [int(v) for v in row]
    except ValueError:
        raise ValueError(f"{path}: non-integer value in {what}: {' '.join(row)!r}") from None


def _gmsh_cell_count(path: Path) -> int | None:
    """Cells declared by an ASCII Gmsh 2.2 / 4.1 file, after checking that the
    node tags are positive and unique, each element has its type's node count
    and refers only to existing node tags. None for binary or other versions."""
    text = path.read_bytes().decode("utf-8", errors="replace")
    lines = text.splitlines()
    sections = _gmsh_sections(path, lines)
    fmt = sections.get("MeshFormat")
    if not fmt or len(fmt[0]) < 2 or fmt[0][1] != "0":
        return None  # binary or unrecognisable: meshio decides
    version = fmt[0][0]
    if "Nodes" not in sections or "Elements" not in sections:
        raise ValueError(f"{path}: Gmsh file without $Nodes or $Elements section")
    per_type = _gmsh_nodes_per_type()
    if version.startswith("2"):
        tags, elements = _gmsh22_tables(path, sections, per_type)
    elif version.startswith("4.1"):
        tags, elements = _gmsh41_tables(path, sections, per_type)
    else:
        return None
    if len(tags) != len(set(tags)):
        dup = Counter(tags).most_common(1)[0][0]
        raise ValueError(f"{path}: node tag {dup} appears more than once")
    if tags and min(tags) < 1:
        raise ValueError(f"{path}: node tag {min(tags)} is not positive")
    if elements:
        refs = np.concatenate([np.asarray(e, dtype=np.int64) for e in elements])
        missing = ~np.isin(refs, np.asarray(tags, dtype=np.int64))
        if missing.any():
            raise ValueError(f"{path}: an element refers to node tag {int(refs[missing][0])}, which is not in $Nodes")
    return len(elements)


def _gmsh22_tables(
    path: Path, sections: dict[str, list[list[str]]], per_type: dict[int, int]
) -> tuple[list[int], list[list[int]]]:
    nodes = sections["Nodes"]
    n = _count_row(path, nodes, "$Nodes")
    if len(nodes) - 1 != n:
        raise ValueError(f"{path}: $Nodes announces {n} node(s) but has {len(nodes) - 1}")
    for row in nodes[1:]:
        if len(row) != 4:
            raise ValueError(f"{path}: node row {' '.join(row)!r} should have a tag and 3 coordinates")
    tags = _ints(path, [row[0] for row in nodes[1:]], "node tags")
    elems = sections["Elements"]
    n = _count_row(path, elems, "$Elements")
    if len(elems) - 1 != n:
        raise ValueError(f"{path}: $Elements announces {n} element(s) but has {len(elems) - 1}")
    elements = []
    for row in elems[1:]:
        v = _ints(path, row, "$Elements")
        if len(v) < 3 or v[2] < 0:
            raise ValueError(f"{path}: bad element row {' '.join(row)!r}")
        k = per_type.get(v[1])
        if k is None:
            raise ValueError(f"{path}: element {v[0]} has unknown Gmsh element type {v[1]}")
        if len(v) != 3 + v[2] + k:
            raise ValueError(f"{path}: element {v[0]} of type {v[1]} needs {k} node(s) after {v[2]} tag(s)")
        elements.append(v[3 + v[2] :])
    return tags, elements


def _gmsh41_tables(
    path: Path, sections: dict[str, list[list[str]]], per_type: dict[int, int]
) -> tuple[list[int], list[list[int]]]:
    rows = sections["Nodes"]
    head = _ints(path, rows[0], "$Nodes header") if rows else []
    if len(head) != 4 or min(head) < 0:
        raise ValueError(f"{path}: bad $Nodes header")
    n_blocks, n_nodes = head[0], head[1]
    tags: list[int] = []
    i = 1
    for _ in range(n_blocks):
        block = _ints(path, rows[i], "$Nodes block header") if i < len(rows) else []
        if len(block) != 4 or block[2] != 0 or block[3] < 0:
            raise ValueError(f"{path}: bad $Nodes block header (parametric nodes are not supported)")
        count = block[3]
        tag_rows, coord_rows = rows[i + 1 : i + 1 + count], rows[i + 1 + count : i + 1 + 2 * count]
        if len(coord_rows) != count or any(len(r) != 1 for r in tag_rows) or any(len(r) != 3 for r in coord_rows):
            raise ValueError(f"{path}: a $Nodes block does not hold {count} tags and {count} coordinate rows")
        tags += _ints(path, [r[0] for r in tag_rows], "node tags")
        i += 1 + 2 * count
    if i != len(rows) or len(tags) != n_nodes:
        raise ValueError(f"{path}: $Nodes announces {n_nodes} node(s) in {n_blocks} block(s), which does not match")
    rows = sections["Elements"]
    head = _ints(path, rows[0], "$Elements header") if rows else []
    if len(head) != 4 or min(head) < 0:
        raise ValueError(f"{path}: bad $Elements header")
    n_blocks, n_elems = head[0], head[1]
    elements = []
    i = 1
    for _ in range(n_blocks):
        block = _ints(path, rows[i], "$Elements block header") if i < len(rows) else []
        if len(block) != 4 or block[3] < 0:
            raise ValueError(f"{path}: bad $Elements block header")
        k = per_type.get(block[2])
        if k is None:
            raise ValueError(f"{path}: unknown Gmsh element type {block[2]}")
        count = block[3]
        body = rows[i + 1 : i + 1 + count]
        if len(body) != count or any(len(r) != 1 + k for r in body):
            raise ValueError(f"{path}: an $Elements block does not hold {count} element(s) of {k} node(s)")
        elements += [v[1:] for v in (_ints(path, r, "$Elements") for r in body)]
        i += 1 + count
    if i != len(rows) or len(elements) != n_elems:
        raise ValueError(
            f"{path}: $Elements announces {n_elems} element(s) in {n_blocks} block(s), which does not match"
        )
    return tags, elements


def _count_row(path: Path, rows: list[list[str]], what: str) -> int:
    if not rows or len(rows[0]) != 1:
        raise ValueError(f"{path}: {what} does not start with a count")
    (n,) = _ints(path, rows[0], what)
    if n < 0:
        raise ValueError(f"{path}: negative count {n} in {what}")
    return n


# --------------------------------------------------------------------------
# meshio.Mesh -> (points, cells, cell_type)
# --------------------------------------------------------------------------


def volume_cells(m: Any, source: str, stacklevel: int = 2) -> tuple[np.ndarray, np.ndarray, str]:
    """(points, cells, cell_type) of the one supported volume type in a
    meshio.Mesh, after checking every cell block.

    source      the file name (or "meshio.Mesh") for messages
    stacklevel  for the warning about dropped lower-dimensional cells
    """
    try:
        points = np.asarray(m.points)
        blocks = [(str(b.type), b.data) for b in m.cells]
    except Exception as e:  # not a meshio.Mesh after all
        raise ValueError(f"{source}: not a meshio.Mesh ({type(e).__name__}: {e})") from e
    if points.ndim != 2:
        raise ValueError(f"{source}: points must have shape (n, 3), got {points.shape}")
    n_points = len(points)
    found = sorted({t for t, _ in blocks})
    volume: dict[str, list[np.ndarray]] = {}
    dropped: Counter[str] = Counter()
    unsupported: Counter[str] = Counter()
    for cell_type, data in blocks:
        arr = _block_array(data, cell_type, n_points, source)
        if cell_type in VOLUME_CELL_TYPES:
            if arr is None:
                raise ValueError(f"{source}: {cell_type} cells are not an (m, k) integer array")
            volume.setdefault(cell_type, []).append(arr)
        elif arr is not None and _is_lower_dim(cell_type):
            dropped[cell_type] += len(arr)
        else:
            unsupported[cell_type] += len(data)
    if unsupported:
        what = ", ".join(f"{n} {t}" for t, n in sorted(unsupported.items()))
        raise ValueError(f"{source} holds cells corotate cannot use ({what}); supported volume cells: {_volume_list()}")
    if not volume:
        raise ValueError(
            f"{source} has no supported volume cells; found cell types {found}, supported: {_volume_list()}"
        )
    if len(volume) > 1:
        raise ValueError(
            f"{source} mixes volume cell types {sorted(volume)}; corotate needs "
            "one element type per body (split the file or convert the mesh)"
        )
    ((cell_type, arrays),) = volume.items()
    if dropped:
        what = ", ".join(f"{n} {t}" for t, n in sorted(dropped.items()))
        warnings.warn(
            f"{source}: ignored {sum(dropped.values())} lower-dimensional cell(s) ({what}); "
            f"the body is made of the {sum(len(a) for a in arrays)} {cell_type} cell(s)",
            stacklevel=stacklevel + 1,
        )
    # Formats such as Gmsh split cells into one block per physical group.
    return points, np.concatenate(arrays, axis=0), cell_type


#: Cell data names that hold region ids, in the order read_mesh looks for them (Gmsh physical
#: groups, what write_mesh writes, Medit references, DOLFINx/FEniCS entity ids).
REGION_DATA_NAMES = ("gmsh:physical", "cell_regions", "medit:ref", "CellEntityIds")


def volume_cell_regions(m: Any, cell_type: str, source: str) -> np.ndarray | None:
    """(m,) int64 region ids of the cell_type cells of a meshio.Mesh, in the order
    volume_cells concatenates them, from the first of REGION_DATA_NAMES its cell data has;
    None without one. ValueError for ids that are not integers."""
    data = getattr(m, "cell_data", None) or {}
    name = next((n for n in REGION_DATA_NAMES if n in data), None)
    if name is None:
        return None
    blocks = zip(m.cells, data[name])
    parts = [np.asarray(values).reshape(-1) for block, values in blocks if str(block.type) == cell_type]
    regions = np.concatenate(parts) if parts else np.zeros(0, dtype=np.int64)
    if not np.issubdtype(regions.dtype, np.integer):
        as_int = np.rint(regions) if np.issubdtype(regions.dtype, np.floating) else None
        if as_int is None or not np.array_equal(as_int, regions):
            raise ValueError(f"{source}: cell data {name!r} (region ids) must be integers")
        regions = as_int
    return regions.astype(np.int64)


def _block_array(data: Any, cell_type: str, n_points: int, source: str) -> np.ndarray | None:
    """A cell block as an (m, k) int64 array with all indices in range, or
    None for blocks of varying cell size (polygons, polyhedra)."""
    try:
        arr = np.asarray(data)
    except Exception:  # ragged lists
        return None
    if arr.dtype == object:
        return None
    if arr.size and arr.dtype.kind not in "iu":
        raise ValueError(f"{source}: {cell_type} cells hold non-integer node indices (dtype {arr.dtype})")
    k = SUPPORTED_CELL_TYPES.get(cell_type, arr.shape[-1] if arr.ndim == 2 else -1)
    if arr.size == 0:
        return np.zeros((0, max(k, 0)), dtype=np.int64)
    return _index_block(arr, k, n_points, f"{source}: {cell_type} cells", f"{source}: {cell_type} ")


# --------------------------------------------------------------------------
# TetGen
# --------------------------------------------------------------------------

# Why not meshio's TetGen reader (meshio 5.3): it reads the data with
# np.fromfile(sep=" "), which stops at a comment after the values on a line
# ("0 1.0 2.0 3.0  # corner"), legal in TetGen files, and then fails with a
# NumPy "could not be read to its end" error; it splits header lines on single
# spaces only (a tab-separated header is an int() error); it does not check the
# entry counts, the row lengths or the element numbers. The format is small,
# so it is read here, strictly, with every error naming the file.


def _tetgen_rows(path: Path, kind: str) -> tuple[list[int], list[list[str]]]:
    """Integer header and data rows of a TetGen file, comments and blanks
    removed; the data rows must be exactly as many as the header says."""
    if not path.is_file():
        raise FileNotFoundError(f"TetGen {kind} file not found: {path}")
    try:
        text = path.read_bytes().decode("utf-8", errors="replace")
    except OSError as e:
        raise ValueError(f"could not read TetGen {kind} file {path}: {e}") from e
    rows = [tokens for line in text.splitlines() if (tokens := line.split("#", 1)[0].split())]
    if not rows:
        raise ValueError(f"TetGen {kind} file {path} is empty")
    header, body = rows[0], rows[1:]
    try:
        values = [int(v) for v in header]
    except ValueError:
        raise ValueError(f"bad header in {path}: {' '.join(header)!r}") from None
    if any(v < 0 for v in values):
        raise ValueError(f"bad header in {path}: {' '.join(header)!r} (negative value)")
    if len(body) != values[0]:
        raise ValueError(f"{path} announces {values[0]} entries but has {len(body)}")
    return values, body


def _parse_table(rows: list[list[str]], ncols: int, dtype: Any, path: Path) -> np.ndarray:
    """rows (each exactly ncols values) as an array, with a clear error."""
    for i, r in enumerate(rows):
        if len(r) != ncols:
            raise ValueError(f"{path}: entry {i} has {len(r)} values, expected {ncols}")
    try:
        return np.array(rows, dtype=dtype).reshape(len(rows), ncols)
    except (ValueError, OverflowError) as e:
        raise ValueError(f"{path}: could not parse numbers ({e})") from None


def _numbered(ids: np.ndarray, path: Path, what: str) -> int:
    """The base (0 or 1) of consecutive entry numbers."""
    base = int(ids[0]) if len(ids) else 0
    if base not in (0, 1) or np.any(ids != base + np.arange(len(ids))):
        raise ValueError(f"{path}: {what} numbers must run consecutively from 0 or 1")
    return base


def read_tetgen(path: Path) -> tuple[np.ndarray, np.ndarray, str]:
    """(points, cells, "tetra") from a TetGen .node/.ele pair; node and
    element numbers may start at 0 or 1 (as the first node says). Attributes
    and boundary markers are checked to be numbers and otherwise ignored."""
    node_path, ele_path = path.with_suffix(".node"), path.with_suffix(".ele")
    header, rows = _tetgen_rows(node_path, ".node")
    dim, n_attr, n_marker = [*header, 3, 0, 0][1:4]
    if dim != 3:
        raise ValueError(f"{node_path} has dimension {dim}, expected 3")
    width = 4 + n_attr + n_marker
    table = _parse_table(rows, width, np.float64, node_path)
    ids = _parse_table([r[:1] for r in rows], 1, np.int64, node_path)[:, 0]
    base = _numbered(ids, node_path, "node")
    points = table[:, 1:4]

    header, rows = _tetgen_rows(ele_path, ".ele")
    per_tet, n_attr = [*header, 4, 0][1:3]
    if per_tet != 4:
        raise ValueError(
            f"{ele_path} has {per_tet}-node tets; only 4-node tets are "
            f"supported (supported volume cell types: {_volume_list()})"
        )
    _parse_table(rows, 5 + n_attr, np.float64, ele_path)  # attributes are numbers
    table = _parse_table([r[:5] for r in rows], 5, np.int64, ele_path)
    if len(table) and _numbered(table[:, 0], ele_path, "element") != base:
        raise ValueError(f"{ele_path}: element numbers start at {1 - base}, node numbers at {base}")
    return points, table[:, 1:5] - base, "tetra"
