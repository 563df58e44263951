"""Fuzzing every file format the readers take, each read in a child process with a time limit.

A small tet mesh (cr.box) is written as ASCII VTU, legacy VTK, Gmsh 2.2, Abaqus .inp and a
TetGen .node/.ele pair and read back with read_mesh; a closed triangle sphere is written as
OBJ, binary and ASCII STL, ASCII and binary PLY and OFF and read back with read_surface.
Each file is mutated (byte flips, truncation, deleted, repeated or swapped lines, a number
replaced by 0, -1, 1e308, nan, a huge integer or a word, the first lines of the header
alone) or broken on purpose (a duplicate cell or triangle, also permuted; a tet soup; all
nodes but a third of the cells or faces; a binary STL one triangle short, an ASCII STL
without its endsolid; an empty file). 32 files per format, 352 in all. The contract, for
every file:

* no crash and no hang: the child process answers within child_reader.TIME_LIMIT (a dead
  or silent child is a failure; it is restarted for the next file);
* nothing escapes but ValueError / FileNotFoundError, whose message names the file;
* no silent misread: an accepted file gives the cell type, cell count (with the cells
  dropped under a warning that counts them) and node count that were written, except
  where the format declares no counts and the mutation changed the number of records (a
  deleted line in an OBJ is a different, valid surface); a file broken on purpose is never
  accepted.

Seeded: the same files every run (COROTATE_FUZZ_SEED picks others, COROTATE_FUZZ_FILE_CASES
sets the files per format).
"""

from __future__ import annotations

import os
import random
import re
import signal
from pathlib import Path

import meshio
import numpy as np
import pytest
from child_reader import Reader
from mutations import byte_flip, delete_line, pick_file, repeat_line, truncate

import corotate as cr

SEED = int(os.environ.get("COROTATE_FUZZ_SEED", "20261203"))
CASES_PER_FORMAT = int(os.environ.get("COROTATE_FUZZ_FILE_CASES", "32"))

VOLUME = cr.box((1.0, 1.0, 1.0), (2, 1, 1), "tet4")
SURFACE = cr.sphere_surface(1.0, 20)

# Formats without declared counts: a deleted, repeated or cut line is a different valid file.
COUNT_FREE = {"obj", "inp"}
RECORD_CHANGING = {"delete_line", "repeat_line", "truncate", "byte_flip", "swap_lines"}


# -- writers: format -> {suffix: bytes} -----------------------------------------------------


def write_format(tmp: Path, fmt: str, points: np.ndarray, cells: np.ndarray) -> dict[str, bytes]:
    f = tmp / "writer"
    cell_type = "tetra" if cells.shape[1] == 4 else "triangle"
    m = meshio.Mesh(points, [(cell_type, cells.astype(np.int32))])  # (PLY stores 32-bit indices)
    if fmt == "tetgen":
        node = [f"{len(points)} 3 0 0"] + [f"{i} {x!r} {y!r} {z!r}" for i, (x, y, z) in enumerate(points.tolist())]
        ele = [f"{len(cells)} 4 0"] + [f"{i} " + " ".join(map(str, c)) for i, c in enumerate(cells.tolist())]
        return {".node": ("\n".join(node) + "\n").encode(), ".ele": ("\n".join(ele) + "\n").encode()}
    suffix, options = {
        "vtu": (".vtu", {"binary": False}),
        "vtk": (".vtk", {"binary": False}),
        "msh": (".msh", {"file_format": "gmsh22", "binary": False}),
        "inp": (".inp", {}),
        "obj": (".obj", {}),
        "stl-binary": (".stl", {"binary": True}),
        "stl-ascii": (".stl", {"binary": False}),
        "ply-ascii": (".ply", {"binary": False}),
        "ply-binary": (".ply", {"binary": True}),
        "off": (".off", {}),
    }[fmt]
    if fmt == "msh":
        ones = np.ones(len(cells), dtype=int)
        m.cell_data = {"gmsh:physical": [ones], "gmsh:geometrical": [ones]}
    meshio.write(f.with_suffix(suffix), m, **options)
    return {suffix: f.with_suffix(suffix).read_bytes()}


VOLUME_FORMATS = ["vtu", "vtk", "msh", "inp", "tetgen"]
SURFACE_FORMATS = ["obj", "stl-binary", "stl-ascii", "ply-ascii", "ply-binary", "off"]


# -- random mutations: (files, rng) -> files -------------------------------------------------


def swap_lines(files, rng):
    k = pick_file(files, rng)
    lines = files[k].split(b"\n")
    i, j = rng.randrange(len(lines)), rng.randrange(len(lines))
    lines[i], lines[j] = lines[j], lines[i]
    return {**files, k: b"\n".join(lines)}


NUMBER = re.compile(rb"(?<![\w.+-])-?\d+(\.\d*)?([eE][-+]?\d+)?(?![\w.])")


def replace_number(files, rng):
    k = pick_file(files, rng)
    hits = list(NUMBER.finditer(files[k]))
    if not hits:
        return byte_flip(files, rng)
    h = rng.choice(hits)
    new = rng.choice(["0", "-1", "1e308", "-1.5e23", "nan", "inf", str(2**63), "99999999", "x", ""])
    return {**files, k: files[k][: h.start()] + new.encode() + files[k][h.end() :]}


def header_only(files, rng):
    k = pick_file(files, rng)
    lines = files[k].split(b"\n")
    return {**files, k: b"\n".join(lines[: rng.randrange(1, 4)]) + b"\n"}


MUTATIONS = [byte_flip, byte_flip, truncate, delete_line, repeat_line, swap_lines, replace_number, header_only]


# -- files broken on purpose: they must be refused ---------------------------------------------


def broken_volume(tmp: Path, fmt: str, rng: random.Random) -> tuple[str, dict[str, bytes]]:
    kind = rng.choice(["duplicate cell", "permuted duplicate", "tet soup", "cut in the cells", "empty"])
    points, cells = VOLUME.points, VOLUME.cells
    if kind == "duplicate cell":
        cells = np.concatenate([cells, cells[[rng.randrange(len(cells))]]])
    elif kind == "permuted duplicate":
        cells = np.concatenate([cells, cells[[rng.randrange(len(cells))]][:, [1, 0, 3, 2]]])
    elif kind == "tet soup":
        points, cells = points[cells].reshape(-1, 3), np.arange(4 * len(cells)).reshape(-1, 4)
    elif kind == "cut in the cells":
        cells = cells[: len(cells) // 3]  # what a cut file keeps: all nodes, a third of the cells
    files = write_format(tmp, fmt, points, cells)
    if kind == "empty":
        k = pick_file(files, rng)
        files = {**files, k: b""}
    return kind, files


def broken_surface(tmp: Path, fmt: str, rng: random.Random) -> tuple[str, dict[str, bytes]]:
    kind = rng.choice(["duplicate triangle", "cut in the faces", "empty"])
    cells = SURFACE.cells
    if kind == "duplicate triangle":
        cells = np.concatenate([cells, cells[[rng.randrange(len(cells))]][:, [1, 2, 0]]])
    elif kind == "cut in the faces" and not fmt.startswith("stl"):
        cells = cells[: len(cells) // 3]  # all vertices, a third of the faces
    files = write_format(tmp, fmt, SURFACE.points, cells)
    if kind == "empty":
        files = {k: b"" for k in files}
    elif kind == "cut in the faces" and fmt == "stl-binary":
        files = {".stl": files[".stl"][:-50]}  # one triangle fewer than the header declares
    elif kind == "cut in the faces" and fmt == "stl-ascii":
        text = files[".stl"]
        files = {".stl": text[: text.index(b"endfacet", len(text) // 2) + len(b"endfacet\n")]}  # no endsolid
    return kind, files


# -- the child process ---------------------------------------------------------------------------


@pytest.fixture(scope="module")
def reader():
    r = Reader()
    yield r
    r.stop()


def judge(result: dict, label: str, expected: tuple[str, int, int] | None, counts_may_change: bool) -> str | None:
    """None if the answer keeps the contract, else what broke. expected: (cell type, cells,
    nodes) for a file that may be accepted, None for one that must be refused."""
    status = result["status"]
    if status == "error":
        return None if "case" in result["message"] else f"{label}: message without the file name: {result}"
    if status != "ok":
        return f"{label}: {status} {result.get('type', '')} {result.get('message', '')}"
    if expected is None:
        return f"{label}: accepted a file broken on purpose: {result}"
    got = (result["cell_type"], result["n_cells"], result["n_nodes"])
    if counts_may_change:
        return None if got[0] == expected[0] else f"{label}: read {got}, wrote {expected}"
    if got[:2] != expected[:2] or (expected[2] >= 0 and got[2] != expected[2]):
        return f"{label}: silent misread: read {got}, wrote {expected}"
    return None


def run_cases(tmp: Path, reader: Reader, fmt: str, kind: str) -> list[str]:
    rng = random.Random(f"{SEED}-{fmt}")
    points, cells = (VOLUME.points, VOLUME.cells) if kind == "volume" else (SURFACE.points, SURFACE.cells)
    cell_type = "tetra" if kind == "volume" else "triangle"
    # STL keeps no vertex list: its vertex count is what the triangles share (checked exactly on
    # the clean file; a mutated coordinate splits a vertex).
    nodes = len(points)
    failures = []
    for case in range(CASES_PER_FORMAT):
        folder = tmp / f"{fmt}-{case}"
        folder.mkdir()
        if case % 4 == 3:
            label, files = (broken_volume if kind == "volume" else broken_surface)(tmp, fmt, rng)
            expected, may_change = None, False
        else:
            mutate = rng.choice(MUTATIONS)
            label, files = mutate.__name__, mutate(write_format(tmp, fmt, points, cells), rng)
            expected = (cell_type, len(cells), -1 if fmt.startswith("stl") else nodes)
            may_change = fmt.replace("-ascii", "").replace("-binary", "") in COUNT_FREE and label in RECORD_CHANGING
        for suffix, data in files.items():
            (folder / "case").with_suffix(suffix).write_bytes(data)
        target = (folder / "case").with_suffix(".ele" if ".ele" in files else next(iter(files)))
        problem = judge(reader.read(kind, target), f"{fmt} case {case} ({label})", expected, may_change)
        if problem:
            failures.append(problem)
    return failures


@pytest.mark.parametrize("fmt", VOLUME_FORMATS + SURFACE_FORMATS)
def test_corrupt_files_neither_crash_hang_nor_misread(tmp_path, reader, fmt):
    kind = "volume" if fmt in VOLUME_FORMATS else "surface"
    clean = write_format(
        tmp_path, fmt, *((VOLUME.points, VOLUME.cells) if kind == "volume" else (SURFACE.points, SURFACE.cells))
    )
    for suffix, data in clean.items():
        (tmp_path / "case").with_suffix(suffix).write_bytes(data)
    target = (tmp_path / "case").with_suffix(".ele" if ".ele" in clean else next(iter(clean)))
    written = VOLUME if kind == "volume" else SURFACE
    assert reader.read(kind, target) == {
        "status": "ok",
        "cell_type": written.cell_type,
        "n_cells": written.n_cells,
        "n_nodes": written.n_nodes,
    }, "the clean file must read exactly"
    failures = run_cases(tmp_path, reader, fmt, kind)
    assert not failures, f"{len(failures)} of {CASES_PER_FORMAT} cases broke the contract:\n" + "\n".join(failures)


def test_the_harness_reports_a_hang_and_a_crash(tmp_path):
    """A worker that never answers is a hang, one that dies is a crash; both are restarted."""
    ready = (
        'import json, os, signal, sys, time\nprint(json.dumps({"status": "ready"}), flush=True)\nsys.stdin.readline()\n'
    )
    hanging, crashing = tmp_path / "hang.py", tmp_path / "crash.py"
    hanging.write_text(ready + "time.sleep(60)\n")
    crashing.write_text(ready + "os.kill(os.getpid(), signal.SIGSEGV)\n")
    r = Reader(hanging, time_limit=1.0)
    try:
        assert r.read("volume", tmp_path / "x.vtu") == {"status": "hang"}
        r.worker = crashing
        assert r.read("volume", tmp_path / "x.vtu") == {"status": f"crash (exit status {-signal.SIGSEGV})"}
    finally:
        r.stop()
    assert "hang" in judge({"status": "hang"}, "x", ("tetra", 1, 4), False)
