"""The files and surfaces of issue 28 that crashed or hung the process, each by name.

Reads go through a child process with a time limit (child_reader.Reader), so a reader that
loops forever fails the test instead of hanging it. Every path that takes a file
(read_mesh, read_surface, EmbeddedSurface.from_file, tetrahedralize) gives the same answer.
"""

import struct

import meshio
import numpy as np
import pytest
from child_reader import Reader

import corotate as cr
from corotate import meshing
from corotate.surface_checks import check_closed_surface, enclosed_volume

PATHS = ["volume", "surface", "embedded", "tetrahedralize"]


@pytest.fixture(scope="module")
def reader():
    r = Reader()
    yield r
    r.stop()


def answers(reader, path, kinds=PATHS):
    return {kind: reader.read(kind, path) for kind in kinds}


def test_a_two_line_ply_header_is_refused_on_every_path(tmp_path, reader):
    f = tmp_path / "header.ply"
    f.write_text("ply\nformat ascii 1.0\n")  # meshio's reader loops forever looking for end_header
    got = answers(reader, f)
    message = f"could not read mesh file {f}: the PLY header has no 'end_header' line (truncated?)"
    assert got == {kind: {"status": "error", "type": "ValueError", "message": message} for kind in PATHS}


@pytest.mark.parametrize("empty", [".node", ".ele"])
def test_an_empty_tetgen_file_is_refused_on_every_path(tmp_path, reader, empty):
    mesh = cr.box()
    (tmp_path / "m.node").write_text(f"{mesh.n_nodes} 3 0 0\n" + "".join(f"{i} 0 0 {i}\n" for i in range(8)))
    (tmp_path / "m.ele").write_text("0 4 0\n")
    (tmp_path / f"m{empty}").write_text("")
    got = answers(reader, tmp_path / f"m{empty}")
    message = f"TetGen {empty} file {tmp_path / ('m' + empty)} is empty"
    assert got == {kind: {"status": "error", "type": "ValueError", "message": message} for kind in PATHS}


def test_a_binary_ply_declaring_10_to_the_8_faces_is_refused_at_once(tmp_path, reader):
    sphere = cr.sphere_surface(1.0, 20)
    f = tmp_path / "count.ply"
    meshio.write(f, meshio.Mesh(sphere.points, [("triangle", sphere.cells.astype(np.int32))]), binary=True)
    f.write_bytes(f.read_bytes().replace(b"element face 36", b"element face 99999999"))  # meshio: minutes
    got = reader.read("surface", f)
    assert got["status"] == "error"
    assert "declares 20 vertex, 99999999 face, at least 100000479 bytes, but 948 bytes follow it" in got["message"]


def test_an_off_header_alone_is_refused(tmp_path, reader):
    f = tmp_path / "lone.off"
    f.write_text("OFF\n")  # meshio's reader loops forever looking for the counts line
    assert reader.read("surface", f)["message"].endswith("the OFF header has no 'vertices faces edges' counts line")


def test_a_binary_stl_with_a_flipped_count_is_refused_without_allocating_100_gib(tmp_path, reader):
    sphere = cr.sphere_surface(1.0, 20)
    f = tmp_path / "count.stl"
    meshio.write(f, meshio.Mesh(sphere.points, [("triangle", sphere.cells)]), binary=True)
    data = bytearray(f.read_bytes())
    data[83] ^= 0x80  # n + 2^31 triangles: 50 (n + 2^31) wraps to 50 n in meshio's 32-bit size check
    f.write_bytes(bytes(data))
    got = reader.read("surface", f)
    assert got["status"] == "error"
    assert f"declares {36 + 2**31} triangles" in got["message"]


def sphere_with_outlier(factor: float) -> tuple[np.ndarray, np.ndarray]:
    sphere = cr.sphere_surface(1.0, 60)
    points = sphere.points.copy()
    points[7] *= factor
    return points, sphere.cells


@pytest.mark.parametrize("factor", [1e3, 1e4, 1e6, 1e8])
def test_a_vertex_pulled_far_out_is_named_before_meshing(factor):
    # fTetWild segfaults or aborts at 1e3 and 1e8 and runs for minutes at 1e4-1e6.
    with pytest.raises(ValueError, match=r"vertex 7 lies more than 100 times farther .*corrupt"):
        cr.tetrahedralize(sphere_with_outlier(factor))


def test_an_obj_vertex_at_1e308_is_named_on_the_tetrahedralize_path(tmp_path, reader):
    points, cells = sphere_with_outlier(1.0)
    points[12] = (1e308, 0.0, 0.0)
    f = tmp_path / "far.obj"
    meshio.write(f, meshio.Mesh(points, [("triangle", cells)]))
    got = reader.read("tetrahedralize", f)
    assert got["status"] == "error" and got["message"].startswith(f"{f}: vertex 12 lies more than 100 times")


def test_a_byte_flipped_stl_vertex_at_minus_1_5e23_is_named(tmp_path, reader):
    sphere = cr.sphere_surface(1.0, 60)
    f = tmp_path / "flipped.stl"
    meshio.write(f, meshio.Mesh(sphere.points, [("triangle", sphere.cells)]), binary=True)
    data = bytearray(f.read_bytes())
    start = 84 + 12  # the first triangle's first vertex, x
    data[start : start + 4] = struct.pack("<f", -1.5e23)
    f.write_bytes(bytes(data))
    got = reader.read("tetrahedralize", f)
    assert got["status"] == "error" and "lies more than 100 times farther" in got["message"]


def test_an_open_surface_is_not_filled():
    cube = cr.boundary_surface(cr.box())
    lower_half = cube.cells[cube.points[cube.cells].mean(axis=1)[:, 2] < 0.75]  # the top face removed
    with pytest.raises(ValueError, match=r"not closed: 4 edge\(s\) belong to one triangle only"):
        cr.tetrahedralize((cube.points, lower_half))


def test_a_non_manifold_surface_is_not_filled():
    cube = cr.boundary_surface(cr.box())
    twice = np.concatenate([cube.cells, cube.cells[:1]])
    with pytest.raises(ValueError, match="not manifold"):
        cr.tetrahedralize((cube.points, twice))


def test_a_half_truncated_obj_is_refused_by_from_file(tmp_path):
    sphere = cr.sphere_surface(0.4, 26, centre=(0.5, 0.5, 0.5))
    whole = tmp_path / "whole.obj"
    meshio.write(whole, meshio.Mesh(sphere.points, [("triangle", sphere.cells)]))
    lines = whole.read_text().splitlines(keepends=True)
    first_face = next(i for i, line in enumerate(lines) if line.startswith("f "))
    cut = tmp_path / "cut.obj"
    cut.write_text("".join(lines[: first_face + 3]))  # the vertices and 3 of 48 triangles
    with pytest.raises(ValueError, match=r"cut\.obj: \d+ of 26 vertices are used by no cell .*truncated"):
        cr.EmbeddedSurface.from_file(cr.box(), cut)
    assert cr.EmbeddedSurface.from_file(cr.box(), whole).n_triangles == 48
    kept = cr.read_surface(cut, remove_unused_vertices=True)
    assert kept.n_cells == 3 and kept.n_nodes == len(np.unique(sphere.cells[:3]))


def test_an_obj_face_cut_mid_record_is_refused(tmp_path):
    sphere = cr.sphere_surface(1.0, 20)
    f = tmp_path / "mid.obj"
    meshio.write(f, meshio.Mesh(sphere.points, [("triangle", sphere.cells)]))
    text = f.read_text().rstrip("\n")
    f.write_text(text[: text.rindex(" ")] + "\n")  # the last face loses its third vertex
    with pytest.raises(ValueError, match=r"mid\.obj: a face with 2 vertices \(is the file truncated or corrupt\?\)"):
        cr.read_surface(f)


def test_an_ascii_stl_cut_between_facets_is_refused(tmp_path):
    sphere = cr.sphere_surface(1.0, 20)
    f = tmp_path / "cut.stl"
    meshio.write(f, meshio.Mesh(sphere.points, [("triangle", sphere.cells)]), binary=False)
    text = f.read_text()
    f.write_text(text[: text.index("endfacet", len(text) // 2) + len("endfacet\n")])
    with pytest.raises(ValueError, match="does not end with 'endsolid'"):
        cr.read_surface(f)


# -- the mesher's child process: a crash or a hang is a RuntimeError, not the end of the caller


def fake_child(tmp_path, monkeypatch, body: str):
    script = tmp_path / "child.py"
    script.write_text("import os, signal, sys, time\n" + body)
    monkeypatch.setattr(meshing, "_CHILD_SCRIPT", script)


def test_a_crash_in_the_mesher_is_a_runtime_error(tmp_path, monkeypatch):
    fake_child(tmp_path, monkeypatch, "os.kill(os.getpid(), signal.SIGSEGV)\n")
    with pytest.raises(RuntimeError, match=r"fTetWild failed .*: its process was killed by SIGSEGV \(a crash\)"):
        meshing._run_in_child({"vertices": np.zeros((1, 3))}, time_limit=60.0)


def test_an_abort_in_the_mesher_is_a_runtime_error_with_its_message(tmp_path, monkeypatch):
    abort = "sys.stderr.write('double free or corruption\\n')\nsys.stderr.flush()\nos.abort()\n"
    fake_child(tmp_path, monkeypatch, abort)
    with pytest.raises(RuntimeError, match=r"(?s)killed by SIGABRT.*double free or corruption"):
        meshing._run_in_child({"vertices": np.zeros((1, 3))}, time_limit=60.0)


def test_a_mesher_running_past_its_time_limit_is_stopped(tmp_path, monkeypatch):
    fake_child(tmp_path, monkeypatch, "time.sleep(60)\n")
    with pytest.raises(RuntimeError, match=r"fTetWild failed \(time_limit=0\.5 s\): it did not finish within 0\.5 s"):
        meshing._run_in_child({"vertices": np.zeros((1, 3))}, time_limit=0.5)


def test_the_real_mesher_still_fills_a_sphere_through_the_child():
    pytest.importorskip("pytetwild", reason="the extra corotate-fem[mesh] (pytetwild) is not installed")
    sphere = cr.sphere_surface(1.0, 100)
    mesh = cr.tetrahedralize(sphere, target_cells=None, edge_length=0.5)
    assert mesh.n_cells > 0 and np.all(mesh.cell_volumes() > 0)
    assert mesh.cell_volumes().sum() == pytest.approx(enclosed_volume(sphere.points, sphere.cells), rel=0.02)


# -- formats the fuzz tests do not cover: read in a child process with a time limit ------------


def test_a_tecplot_file_missing_a_line_is_stopped_not_a_hang(tmp_path, monkeypatch):
    box = cr.box((1.0, 1.0, 1.0), (2, 1, 1))
    f = tmp_path / "short.dat"
    meshio.write(f, meshio.Mesh(box.points, [("tetra", box.cells)]), file_format="tecplot")
    lines = f.read_text().split("\n")
    f.write_text("\n".join(lines[:7] + lines[8:]))  # one cell fewer than ELEMENTS = 12: meshio loops forever
    monkeypatch.setenv("COROTATE_READ_TIME_LIMIT", "3")
    r = Reader(time_limit=60.0)  # a fresh worker, which reads the variable
    try:
        got = r.read("volume", f)
    finally:
        r.stop()
    assert got["status"] == "error"
    assert got["message"].startswith(f"could not read mesh file {f}: meshio's reader for '.dat' failed (it did not")
    assert "within 3 s and was stopped" in got["message"]


@pytest.mark.parametrize(("file_format", "suffix"), [("tecplot", ".dat"), ("medit", ".mesh"), ("nastran", ".bdf")])
def test_other_formats_still_read_exactly_through_the_child(tmp_path, file_format, suffix):
    box = cr.box((1.0, 1.0, 1.0), (2, 1, 1))
    f = tmp_path / f"box{suffix}"
    meshio.write(f, meshio.Mesh(box.points, [("tetra", box.cells)]), file_format=file_format)
    mesh = cr.read_mesh(f)
    assert np.allclose(mesh.points, box.points) and np.array_equal(mesh.cells, box.cells)


def test_a_corrupt_file_of_another_format_names_the_file(tmp_path):
    f = tmp_path / "broken.mesh"
    f.write_text("MeshVersionFormatted 1\nDimension\n")
    with pytest.raises(ValueError, match=r"broken\.mesh"):
        cr.read_mesh(f)


def test_a_closed_surface_with_split_vertices_is_closed():
    """Exporters give each face its own corners (a PLY per face corner): welded, it is closed."""
    cube = cr.boundary_surface(cr.box())
    split_points = cube.points[cube.cells].reshape(-1, 3)
    split_cells = np.arange(len(split_points)).reshape(-1, 3)
    check_closed_surface(split_points, split_cells)  # no error
    with pytest.raises(ValueError, match="not closed"):
        check_closed_surface(split_points, split_cells[2:])
