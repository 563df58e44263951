"""Fuzzing read_mesh with corrupt files.

Small meshes made here (cr.box) are written as ASCII, binary (zlib) and
uncompressed binary VTU, Gmsh 2.2 and 4.1 ASCII, and TetGen .node/.ele (0-
and 1-based), then mutated (byte flips, truncation, deleted or repeated
lines, integers replaced by 0, -1, off-by-one, huge or non-numbers). Each
file is read in-process. The contract:

* read_mesh never ends the process (SystemExit is caught here and counted as
  a failure) and raises nothing but ValueError / FileNotFoundError, whose
  message names the file;
* a read that succeeds returns the cell type and the cell count that were
  written, less only cells dropped with a warning that counts them (a VTK
  type flipped from tetra to quad), with every index in range (the result
  passes Mesh validation);
* mutations known to break the file (a negative, zero-tag or out-of-range
  node reference, a changed count, an unknown cell type) always fail.

Seeded: the same cases every run. 630 cases, about 2 s.
"""

from __future__ import annotations

import os
import random
import re
import warnings
from pathlib import Path

import meshio
import numpy as np
import pytest
from mutations import byte_flip, delete_line, pick_file, repeat_line, truncate

import corotate as cr

# COROTATE_FUZZ_SEED / COROTATE_FUZZ_CASES run other or more cases by hand.
SEED = int(os.environ.get("COROTATE_FUZZ_SEED", "20240611"))
CASES_PER_FORMAT = int(os.environ.get("COROTATE_FUZZ_CASES", "90"))


def base_meshes() -> list[cr.Mesh]:
    return [
        cr.box((1.0, 2.0, 1.0), (2, 1, 1), "tet4"),
        cr.box((1.0, 1.0, 1.0), (2, 1, 1), "hex8"),
        cr.box((1.0, 1.0, 2.0), (1, 1, 1), "hex20"),
    ]


# -- writers: mesh -> {suffix: bytes} ------------------------------------------


def gmsh_mesh(m: cr.Mesh) -> meshio.Mesh:
    ones = np.ones(m.n_cells, dtype=int)
    return meshio.Mesh(
        m.points, [(m.cell_type, m.cells)], cell_data={"gmsh:physical": [ones], "gmsh:geometrical": [ones]}
    )


def write_files(tmp: Path, fmt: str, m: cr.Mesh, cells: np.ndarray | None = None) -> dict[str, bytes]:
    """The file(s) of mesh m in format fmt as bytes, keyed by suffix; cells
    replaces the connectivity (for out-of-range indices)."""
    c = m.cells if cells is None else cells
    f = tmp / "w"
    if fmt.startswith("vtu"):
        options = {"vtu-ascii": {"binary": False}, "vtu-binary": {}, "vtu-raw": {"compression": None}}[fmt]
        meshio.write(f.with_suffix(".vtu"), meshio.Mesh(m.points, [(m.cell_type, c)]), **options)
        return {".vtu": f.with_suffix(".vtu").read_bytes()}
    if fmt in ("gmsh22", "gmsh41"):
        mm = gmsh_mesh(m)
        mm.cells[0].data = c
        meshio.write(f.with_suffix(".msh"), mm, file_format="gmsh22" if fmt == "gmsh22" else "gmsh", binary=False)
        return {".msh": f.with_suffix(".msh").read_bytes()}
    assert fmt.startswith("tetgen")
    base = 1 if fmt == "tetgen1" else 0
    node = [f"# corner points\n{m.n_nodes} 3 1 1"]
    node += [f"{i + base} {x!r} {y!r} {z!r} 0.5 {i % 2}  # node {i}" for i, (x, y, z) in enumerate(m.points.tolist())]
    ele = [f"{len(c)} 4 1"]
    ele += [f"{i + base}  " + "  ".join(str(v + base) for v in t) + " 7" for i, t in enumerate(c.tolist())]
    return {".node": ("\n".join(node) + "\n").encode(), ".ele": ("\n".join(ele) + "\n# end\n").encode()}


FORMATS = ["vtu-ascii", "vtu-binary", "vtu-raw", "gmsh22", "gmsh41", "tetgen0", "tetgen1"]


# -- mutations: (files, rng) -> files -------------------------------------------


INT = re.compile(rb"(?<![\w.+-])-?\d+(?![\w.])")


def replace_integer(files, rng):
    """Replace one integer token (counts, tags, indices, types, attributes)."""
    k = pick_file(files, rng)
    hits = list(INT.finditer(files[k]))
    if not hits:
        return byte_flip(files, rng)
    h = rng.choice(hits)
    v = int(h.group())
    new = rng.choice([0, -1, v + 1, v - 1, -v, 10**6, 2**63, 10**30, "x", "1.5", ""])
    return {**files, k: files[k][: h.start()] + str(new).encode() + files[k][h.end() :]}


RANDOM_MUTATIONS = [byte_flip, byte_flip, truncate, delete_line, repeat_line, replace_integer, replace_integer]


def broken_on_purpose(tmp: Path, fmt: str, m: cr.Mesh, rng: random.Random) -> tuple[str, dict[str, bytes]]:
    """A mutation that must make read_mesh fail, and its name."""
    kind = rng.choice(["negative index", "index past the end", "count minus one", "count plus one", "unknown type"])
    if kind in ("negative index", "index past the end"):
        cells = m.cells.copy()
        cells[rng.randrange(m.n_cells), rng.randrange(cells.shape[1])] = -1 if kind == "negative index" else m.n_nodes
        return kind, write_files(tmp, fmt, m, cells)  # Gmsh: node tag 0 or a tag not in $Nodes
    files = write_files(tmp, fmt, m)
    if fmt.startswith("tetgen"):
        k = ".ele"
        lines = files[k].decode().split("\n")
        i = next(j for j, ln in enumerate(lines) if ln and not ln.startswith("#"))
        head = lines[i].split()
        n = int(head[0])
        head[0] = {"count minus one": n - 1, "count plus one": n + 1, "unknown type": -1}[kind]
        lines[i] = " ".join(map(str, head))
        return kind if kind != "unknown type" else "count -1", {**files, k: "\n".join(lines).encode()}
    if fmt.startswith("gmsh"):
        k = ".msh"
        lines = files[k].decode().split("\n")
        i = lines.index("$Elements") + 1
        if kind == "unknown type":
            j = i + 1  # 2.2: the first element row; 4.1: the first block header
            row = lines[j].split()
            row[1 if fmt == "gmsh22" else 2] = "99"
            lines[j] = " ".join(row)
        else:
            row = lines[i].split()
            d = -1 if kind == "count minus one" else 1
            row[0 if fmt == "gmsh22" else 1] = str(int(row[0 if fmt == "gmsh22" else 1]) + d)
            lines[i] = " ".join(row)
        return kind, {k: "\n".join(lines).encode()}
    text = files[".vtu"].decode("latin-1")
    if kind == "unknown type" and fmt == "vtu-ascii":
        start = text.index('Name="types"')
        start = text.index(">", start) + 1
        body = text[start:].split("<", 1)[0]
        vals = body.split()
        vals[rng.randrange(len(vals))] = rng.choice(["99", "5", "3", "11"])
        return kind, {
            ".vtu": (text[:start] + "\n" + " ".join(vals) + "\n" + text[start + len(body) :]).encode("latin-1")
        }
    n = m.n_cells
    new = n - 1 if kind == "count minus one" else n + 1
    return "changed NumberOfCells", {
        ".vtu": text.replace(f'NumberOfCells="{n}"', f'NumberOfCells="{new}"').encode("latin-1")
    }


# -- the test ---------------------------------------------------------------------


def read_outcome(path: Path):
    """('ok', (mesh, cells dropped with a warning)) or ('error', exception);
    anything else is returned as
    ('bad', exception) so that even SystemExit is reported, not obeyed."""
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            mesh = cr.read_mesh(path)
        # The one way to lose cells: lower-dimensional ones, with a warning
        # that counts them (a flipped VTK type 10 -> 9 makes a tet a quad).
        dropped = [re.search(r"ignored (\d+) lower-dimensional", str(w.message)) for w in caught]
        return "ok", (mesh, sum(int(d.group(1)) for d in dropped if d))
    except (ValueError, FileNotFoundError) as e:
        return "error", e
    except KeyboardInterrupt:
        raise
    except BaseException as e:  # SystemExit included on purpose
        return "bad", e


def check_case(tmp: Path, label: str, files: dict[str, bytes], m: cr.Mesh, must_fail: bool) -> str | None:
    """None if read_mesh keeps the contract on these files, else what broke."""
    for old in tmp.glob("case.*"):
        old.unlink()
    for suffix, data in files.items():
        (tmp / "case").with_suffix(suffix).write_bytes(data)
    target = (tmp / "case").with_suffix(".ele" if ".ele" in files else next(iter(files)))
    kind, result = read_outcome(target)
    if kind == "bad":
        return f"{label}: {type(result).__name__} escaped: {result!r}"
    if kind == "error":
        if "case" not in str(result):
            return f"{label}: message without the file name: {result}"
        return None
    mesh, dropped = result
    if must_fail:
        return f"{label}: read succeeded with {mesh}"
    if mesh.cell_type != m.cell_type or mesh.n_cells + dropped != m.n_cells:
        return f"{label}: read {mesh} (and dropped {dropped}), but {m.n_cells} {m.cell_type} cells were written"
    cr.Mesh(mesh.points, mesh.cells, mesh.cell_type)  # validation: indices in range, finite points
    return None


@pytest.mark.parametrize("fmt", FORMATS)
def test_read_mesh_survives_corrupt_files(tmp_path, fmt):
    rng = random.Random(f"{SEED}-{fmt}")
    meshes = base_meshes()
    if fmt.startswith("tetgen"):
        meshes = meshes[:1]
    failures = []
    for case in range(CASES_PER_FORMAT):
        m = meshes[case % len(meshes)]
        if case % 4 == 3:
            label, files = broken_on_purpose(tmp_path, fmt, m, rng)
            must_fail = True
        else:
            mutate = rng.choice(RANDOM_MUTATIONS)
            label, files = mutate.__name__, mutate(write_files(tmp_path, fmt, m), rng)
            must_fail = False
        problem = check_case(tmp_path, f"{fmt} case {case} ({m.cell_type}, {label})", files, m, must_fail)
        if problem:
            failures.append(problem)
    assert not failures, f"{len(failures)} of {CASES_PER_FORMAT} cases broke the contract:\n" + "\n".join(failures)


def test_fuzz_harness_catches_system_exit(tmp_path, monkeypatch):
    """The harness reports a SystemExit from the reader as a failure."""

    def leave(*args, **kwargs):
        raise SystemExit(1)

    monkeypatch.setattr(cr, "read_mesh", leave)
    m = base_meshes()[0]
    problem = check_case(tmp_path, "exit", write_files(tmp_path, "vtu-ascii", m), m, must_fail=False)
    assert problem is not None and "SystemExit escaped" in problem
