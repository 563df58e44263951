"""Tests for corotate.mesh and corotate.output (pure Python, no C++ core)."""

import base64
import re
import struct
import warnings
import xml.etree.ElementTree as ET
from collections import Counter
from itertools import combinations
from pathlib import Path

import meshio
import numpy as np
import pytest

from corotate.mesh import (
    SOLID_ELEMENTS,
    SUPPORTED_CELL_TYPES,
    VOLUME_CELL_TYPES,
    Mesh,
    beam,
    box,
    cell_types,
    read_mesh,
    write_mesh,
)
from corotate.output import TimeSeriesWriter

DATA = Path(__file__).resolve().parents[2] / "shared" / "data"
ARMADILLO = DATA / "armadillo_4k"
needs_armadillo = pytest.mark.skipif(
    not (ARMADILLO.with_suffix(".vtu").exists() and ARMADILLO.with_suffix(".ele").exists()),
    reason="shared/data/armadillo_4k.* not present beside the checkout",
)

ELEMENTS = SOLID_ELEMENTS  # every registered solid (the core's cell-type table)
FACTS = {facts["generator_name"]: facts for facts in cell_types().values()}
SIZE = (2.0, 0.7, 1.3)
CELLS = (3, 2, 4)


def unit_tet():
    return Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], [[0, 1, 2, 3]], "tetra")


# -- generators -------------------------------------------------------------


@pytest.mark.parametrize("element", ELEMENTS)
def test_box_volumes_sum_and_positive(element):
    m = box(SIZE, CELLS, element, origin=(-1.0, 2.0, 0.5))
    v = m.cell_volumes()
    assert np.all(v > 0)
    assert v.sum() == pytest.approx(np.prod(SIZE), rel=1e-12)
    assert m.points.min(axis=0) == pytest.approx([-1.0, 2.0, 0.5])
    assert m.points.max(axis=0) == pytest.approx([1.0, 2.7, 1.8])


@pytest.mark.parametrize("element", ELEMENTS)
def test_box_counts_and_array_layout(element):
    nx, ny, nz = CELLS
    m = box(SIZE, CELLS, element)
    corners = (nx + 1) * (ny + 1) * (nz + 1)
    edges = nx * (ny + 1) * (nz + 1) + (nx + 1) * ny * (nz + 1) + (nx + 1) * (ny + 1) * nz
    simplex, quadratic = FACTS[element]["domain"] == "simplex", FACTS[element]["order"] == 2
    if quadratic and simplex:  # the tets' edges also cross every face and cuboid: all half steps
        expected_nodes = (2 * nx + 1) * (2 * ny + 1) * (2 * nz + 1)
    else:
        expected_nodes = corners + edges if quadratic else corners
    assert m.n_nodes == expected_nodes
    assert m.n_cells == nx * ny * nz * (6 if simplex else 1)
    assert m.points.dtype == np.float64 and m.points.flags.c_contiguous
    assert m.cells.dtype == np.int64 and m.cells.flags.c_contiguous
    # No duplicated nodes and every node used.
    assert len(np.unique(m.points.round(12), axis=0)) == m.n_nodes
    assert np.array_equal(np.unique(m.cells), np.arange(m.n_nodes))


def test_box_is_deterministic():
    a, b = box(SIZE, CELLS, "hex20"), box(SIZE, CELLS, "hex20")
    assert np.array_equal(a.points, b.points) and np.array_equal(a.cells, b.cells)


def test_tet4_is_conforming():
    nx, ny, nz = CELLS
    m = box(SIZE, CELLS, "tet4")
    faces = Counter(tuple(sorted(f)) for tet in m.cells.tolist() for f in combinations(tet, 3))
    assert set(faces.values()) <= {1, 2}
    boundary = [f for f, c in faces.items() if c == 1]
    # Each boundary square of the box surface is split into two triangles.
    assert len(boundary) == 2 * 2 * (nx * ny + ny * nz + nx * nz)
    lo, hi = m.points.min(axis=0), m.points.max(axis=0)
    for f in boundary:
        p = m.points[list(f)]
        on_plane = np.isclose(p, lo).all(axis=0) | np.isclose(p, hi).all(axis=0)
        assert on_plane.any(), f"face {f} is unmatched but not on the box surface"
    interior = sum(1 for c in faces.values() if c == 2)
    assert 2 * interior + len(boundary) == 4 * m.n_cells


def test_tet4_six_tets_share_a_diagonal_mirrored_between_neighbours():
    m = box(SIZE, CELLS, "tet4")
    per_cube = m.cells.reshape(-1, 6, 4)
    for ijk, cube in zip(np.ndindex(*CELLS), per_cube):
        p = m.points[cube.ravel()]
        lo, hi = p.min(axis=0), p.max(axis=0)
        # the diagonal's ends: the corners whose coordinate flips with the cube's parity
        odd = np.array(ijk) % 2 == 1
        start, end = np.where(odd, hi, lo), np.where(odd, lo, hi)
        i_start = np.flatnonzero(np.all(np.isclose(m.points, start), axis=1))
        i_end = np.flatnonzero(np.all(np.isclose(m.points, end), axis=1))
        assert len(i_start) == len(i_end) == 1
        assert all(i_start[0] in t and i_end[0] in t for t in cube)


@pytest.mark.parametrize("axis", [0, 1, 2])
def test_tet4_box_with_even_cell_counts_is_mirror_symmetric(axis):
    # Mirroring about the mid-plane maps the set of tets onto itself, so a symmetric load
    # gives a symmetric answer (one diagonal direction everywhere would twist a beam).
    m = box((2.0, 1.0, 1.0), (4, 2, 2), "tet4")
    mirrored = m.points.copy()
    mirrored[:, axis] = m.points[:, axis].max() - m.points[:, axis]
    key = {tuple(np.round(p, 9)): i for i, p in enumerate(m.points)}
    image = np.array([key[tuple(np.round(p, 9))] for p in mirrored])
    tets = {tuple(sorted(t)) for t in m.cells.tolist()}
    assert {tuple(sorted(t)) for t in image[m.cells].tolist()} == tets


@pytest.mark.parametrize("element", ["hex8", "hex20"])
def test_hex_corner_ordering_is_vtk(element):
    m = box(SIZE, CELLS, element)
    h = np.array(SIZE) / np.array(CELLS)
    signs = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]])
    corners = m.points[m.cells[:, :8]]
    assert np.allclose(corners - corners[:, :1], signs * h)


def test_hex20_mid_nodes_at_edge_midpoints():
    m = box(SIZE, CELLS, "hex20")
    edges = [(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4), (0, 4), (1, 5), (2, 6), (3, 7)]
    x = m.points[m.cells]
    for mid, (a, b) in enumerate(edges, start=8):
        assert np.allclose(x[:, mid], 0.5 * (x[:, a] + x[:, b]), atol=1e-14)


def test_beam_is_box_from_origin():
    m = beam(length=4.0, width=0.5, height=0.25, cells=(8, 1, 1), element="hex8")
    assert np.allclose(m.points.min(axis=0), 0.0)
    assert np.allclose(m.points.max(axis=0), [4.0, 0.5, 0.25])
    assert m.cell_volumes().sum() == pytest.approx(0.5, rel=1e-12)


def test_generator_argument_errors():
    with pytest.raises(ValueError, match=rf"unknown element 'tet11'; choose one of {', '.join(SOLID_ELEMENTS)}$"):
        box(element="tet11")
    with pytest.raises(ValueError, match="cells must be three integers >= 1"):
        box(cells=(1, 0, 1))
    with pytest.raises(ValueError, match="size must be finite and positive"):
        box(size=(1, -1, 1))


# -- Mesh validation and helpers ---------------------------------------------


def test_cell_volume_signs():
    assert unit_tet().cell_volumes() == pytest.approx([1 / 6])
    flipped = Mesh(unit_tet().points, [[0, 2, 1, 3]], "tetra")
    assert flipped.cell_volumes() == pytest.approx([-1 / 6])
    # Unit cube with corner 6 moved by (a, 0, 0) and corner 1 by (0, b, 0):
    # x = xi + a xi eta zeta, y = eta + b xi (1 - eta)(1 - zeta), z = zeta.
    # det J is quadratic in zeta, and integrating it over [0, 1]^3 by hand
    # gives the exact volume 1 + (a - b) / 4 - a b / 12. The map is trilinear, so
    # hex20, its every node placed by it (curved edges), has the same volume.
    a, b = 0.3, 0.4

    def trilinear(p):
        xi, eta, zeta = p.T
        return np.column_stack([xi + a * xi * eta * zeta, eta + b * xi * (1 - eta) * (1 - zeta), zeta])

    for element in ("hex8", "hex20"):
        m = box((1, 1, 1), (1, 1, 1), element)
        m.points[:] = trilinear(m.points)
        assert m.cell_volumes()[0] == pytest.approx(1 + (a - b) / 4 - a * b / 12, rel=1e-14)


def test_mesh_rejects_nan_point():
    pts = unit_tet().points
    pts[2, 1] = np.nan
    with pytest.raises(ValueError, match="NaN at node 2"):
        Mesh(pts, [[0, 1, 2, 3]], "tetra")


def test_mesh_rejects_out_of_range_index():
    with pytest.raises(ValueError, match=r"cell 1 has node index 7 out of range \[0, 4\)"):
        Mesh(unit_tet().points, [[0, 1, 2, 3], [0, 1, 7, 3]], "tetra")
    with pytest.raises(ValueError, match="cell 0 has node index -1"):
        Mesh(unit_tet().points, [[0, 1, -1, 3]], "tetra")


def test_mesh_rejects_bad_shapes_and_types():
    with pytest.raises(ValueError, match=r"points must have shape \(n, 3\)"):
        Mesh(np.zeros((4, 2)), [[0, 1, 2, 3]], "tetra")
    with pytest.raises(ValueError, match=r"must have shape \(m, 8\)"):
        Mesh(unit_tet().points, [[0, 1, 2, 3]], "hexahedron")
    with pytest.raises(
        ValueError, match=rf"unsupported cell type 'quad'; supported: {', '.join(SUPPORTED_CELL_TYPES)}"
    ):
        Mesh(unit_tet().points, [[0, 1, 2, 3]], "quad")


def test_node_selection():
    m = box((2, 1, 1), (4, 2, 2), "hex8")
    left = m.nodes_on_plane("x", 0.0)
    assert left.dtype == np.int64 and len(left) == 3 * 3
    assert np.array_equal(left, m.nodes_on_plane(0, 0.0))
    assert np.allclose(m.points[left, 0], 0.0)
    top = m.nodes_on_plane(2, 1.0 + 1e-12)
    assert len(top) == 5 * 3
    inside = m.nodes_in_box([0.9, -1, -1], [1.6, 2, 0.5])  # x in {1.0, 1.5}, z in {0, 0.5}
    assert len(inside) == 2 * 3 * 2
    assert np.array_equal(m.nodes_where(lambda p: p[:, 0] > 1.9), m.nodes_on_plane("x", 2.0))
    assert m.nearest_node([2.1, 1.1, 0.9]) == int(np.flatnonzero(np.all(m.points == [2, 1, 1], axis=1))[0])
    with pytest.raises(ValueError, match="axis must be"):
        m.nodes_on_plane("w", 0.0)
    with pytest.raises(ValueError, match="predicate must return a mask of shape"):
        m.nodes_where(lambda p: p[:3, 0] > 0)
    with pytest.raises(ValueError, match=r"upper .* is below lower"):
        m.nodes_in_box([1, 1, 1], [0, 2, 2])


# -- reading and writing -------------------------------------------------------


@pytest.mark.parametrize("element", ELEMENTS)
def test_vtu_round_trip(tmp_path, element):
    m = box(SIZE, (2, 1, 2), element)
    f = tmp_path / f"box_{element}.vtu"
    write_mesh(f, m, point_data={"temperature": np.arange(m.n_nodes, dtype=float)})
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        r = read_mesh(f)
    assert r.cell_type == m.cell_type
    assert np.array_equal(r.points, m.points)
    assert np.array_equal(r.cells, m.cells)
    assert np.array_equal(meshio.read(f).point_data["temperature"], np.arange(m.n_nodes))


def test_write_mesh_rejects_bad_point_data(tmp_path):
    with pytest.raises(ValueError, match="point_data\\['t'\\] must have one row per node"):
        write_mesh(tmp_path / "x.vtu", unit_tet(), point_data={"t": np.zeros(3)})


@needs_armadillo
def test_armadillo_vtu_and_tetgen_agree():
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the file is positively oriented
        a = read_mesh(ARMADILLO.with_suffix(".vtu"))
        b = read_mesh(ARMADILLO.with_suffix(".node"))
        c = read_mesh(str(ARMADILLO.with_suffix(".ele")))
    assert (a.n_nodes, a.n_cells, a.cell_type) == (1180, 3717, "tetra")
    for other in (b, c):
        assert np.array_equal(a.points, other.points)
        assert np.array_equal(a.cells, other.cells)
    assert a.cell_volumes().sum() == pytest.approx(1.8596, rel=1e-4)


def write_tetgen(stem, points, tets, base):
    lines = [f"# test file\n{len(points)} 3 0 0"]
    lines += [f"{i + base} {x!r} {y!r} {z!r}  # node" for i, (x, y, z) in enumerate(np.asarray(points).tolist())]
    Path(f"{stem}.node").write_text("\n".join(lines) + "\n")
    lines = [f"{len(tets)} 4 1", ""]
    lines += [f"{i + base} " + " ".join(str(v + base) for v in t) + " 7" for i, t in enumerate(tets)]
    Path(f"{stem}.ele").write_text("\n".join(lines) + "\n")


@pytest.mark.parametrize("base", [0, 1])
def test_tetgen_indexing_base(tmp_path, base):
    m = box((1, 2, 3), (2, 1, 1), "tet4")
    write_tetgen(tmp_path / "b", m.points, m.cells, base)
    r = read_mesh(tmp_path / "b.ele")
    assert np.array_equal(r.points, m.points)
    assert np.array_equal(r.cells, m.cells)


def test_negative_tet_is_reordered_with_warning(tmp_path):
    m = box((1, 1, 1), (1, 1, 1), "tet4")
    cells = m.cells.copy()
    cells[[1, 4]] = cells[[1, 4]][:, [0, 2, 1, 3]]
    f = tmp_path / "inverted.vtu"
    meshio.write(f, meshio.Mesh(m.points, [("tetra", cells)]))
    with pytest.warns(UserWarning, match="reordered 2 of 6 tetra"):
        r = read_mesh(f)
    assert np.all(r.cell_volumes() > 0)
    assert np.array_equal(r.cells, m.cells)


def test_negative_hex20_is_mirrored(tmp_path):
    m = box((1, 2, 1), (1, 2, 1), "hex20")
    flip = [4, 5, 6, 7, 0, 1, 2, 3, 12, 13, 14, 15, 8, 9, 10, 11, 16, 17, 18, 19]
    cells = m.cells.copy()
    cells[0] = cells[0][flip]
    f = tmp_path / "inverted20.vtu"
    meshio.write(f, meshio.Mesh(m.points, [("hexahedron20", cells)]))
    with pytest.warns(UserWarning, match="reordered 1 of 2 hexahedron20"):
        r = read_mesh(f)
    assert np.array_equal(r.cells, m.cells)


def test_unused_nodes_are_an_error_or_removed_with_warning(tmp_path):
    pts = np.vstack([unit_tet().points[:2], [[5.0, 5.0, 5.0]], unit_tet().points[2:]])
    f = tmp_path / "unused.vtu"
    meshio.write(f, meshio.Mesh(pts, [("tetra", np.array([[0, 1, 3, 4]]))]))
    with pytest.raises(ValueError, match=r"unused\.vtu: 1 of 5 node\(s\) are used by no cell \(node 2 is the first\)"):
        read_mesh(f)
    with pytest.warns(UserWarning, match="removed 1 node"):
        r = read_mesh(f, remove_unused_nodes=True)
    assert np.array_equal(r.points, unit_tet().points)
    assert np.array_equal(r.cells, [[0, 1, 2, 3]])


def test_read_missing_file_names_path(tmp_path):
    missing = tmp_path / "nope.vtu"
    with pytest.raises(FileNotFoundError, match=r"nope\.vtu"):
        read_mesh(missing)
    (tmp_path / "half.node").write_text("1 3 0 0\n0 0 0 0\n")
    with pytest.raises(FileNotFoundError, match=r"half\.ele"):
        read_mesh(tmp_path / "half.node")


def test_read_surface_only_mesh_is_rejected(tmp_path):
    f = tmp_path / "surface.vtu"
    meshio.write(f, meshio.Mesh(unit_tet().points, [("triangle", np.array([[0, 1, 2], [0, 1, 3]]))]))
    with pytest.raises(ValueError, match=rf"no supported volume cells.*\['triangle'\].*{', '.join(VOLUME_CELL_TYPES)}"):
        read_mesh(f)


def test_read_mixed_volume_types_is_rejected(tmp_path):
    t, h = unit_tet(), box(element="hex8")
    pts = np.vstack([h.points, t.points])
    f = tmp_path / "mixed.vtu"
    meshio.write(f, meshio.Mesh(pts, [("hexahedron", h.cells), ("tetra", t.cells + 8)]))
    with pytest.raises(ValueError, match=r"mixes volume cell types.*one element type per body"):
        read_mesh(f)


def test_read_out_of_range_index_in_tetgen(tmp_path):
    write_tetgen(tmp_path / "bad", unit_tet().points, np.array([[0, 1, 2, 9]]), 0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the error comes first, no unused-node warning
        with pytest.raises(ValueError, match="cell 0 has node index 9 out of range"):
            read_mesh(tmp_path / "bad.node")


# -- hostile files and meshio objects ------------------------------------------


def test_vtu_without_cells_is_a_value_error(tmp_path):
    f = tmp_path / "empty.vtu"
    meshio.write(f, meshio.Mesh(unit_tet().points, []))
    with pytest.raises(ValueError, match=r"empty\.vtu has no cells.*no supported volume cells"):
        read_mesh(f)


def test_meshio_system_exit_becomes_value_error(tmp_path, monkeypatch):
    f = tmp_path / "x.vtu"
    write_mesh(f, unit_tet())

    def give_up(filename):
        raise SystemExit(1)

    monkeypatch.setitem(meshio._helpers.reader_map, "vtu", give_up)
    with pytest.raises(ValueError, match=r"x\.vtu.*sys\.exit\(1\)") as info:
        read_mesh(f)
    assert isinstance(info.value.__cause__, SystemExit)


def test_raw_reader_errors_name_the_file(tmp_path):
    f = tmp_path / "garbage.vtu"
    f.write_bytes(b"<VTKFile type='UnstructuredGrid'>\xff\xfe")
    with pytest.raises(ValueError, match=r"could not read mesh file .*garbage\.vtu") as info:
        read_mesh(f)
    assert info.value.__cause__ is not None
    with pytest.raises(ValueError, match=r"mesh\.unknownext"):
        (tmp_path / "mesh.unknownext").write_text("1 2 3")
        read_mesh(tmp_path / "mesh.unknownext")


def test_unknown_vtk_cell_type_is_an_error(tmp_path):
    m = box((1, 1, 1), (1, 1, 1), "tet4")
    f = tmp_path / "odd.vtu"
    meshio.write(f, m.to_meshio(), binary=False)
    text = f.read_text()
    head, rest = text.split('Name="types"', 1)
    attrs, rest = rest.split(">", 1)
    _body, tail = rest.split("<", 1)
    f.write_text(head + 'Name="types"' + attrs + ">\n" + " ".join(["10"] * 5 + ["99"]) + "\n<" + tail)
    with pytest.raises(ValueError, match=r"odd\.vtu: cell 5 has unknown VTK cell type 99"):
        read_mesh(f)
    # In binary (uncompressed) meshio skips such cells; the declared count catches that.
    meshio.write(f, m.to_meshio(), binary=True, compression=None)
    types = base64.b64encode(struct.pack("<I", 6 * 8) + struct.pack("<6q", *[10] * 5, 99)).decode()
    f.write_text(re.sub(r'(Name="types" format="binary">)[^<]*', lambda g: g.group(1) + types, f.read_text()))
    with pytest.raises(ValueError, match=r"odd\.vtu declares 6 cell\(s\) but meshio read 5"):
        read_mesh(f)
    bad = meshio.Mesh(m.points, [("tetra", m.cells[:5]), ("wedge", np.array([[0, 1, 2, 3, 4, 5]]))])
    meshio.write(f, bad)
    with pytest.raises(ValueError, match=r"cells corotate cannot use \(1 wedge\)"):
        read_mesh(f)


@pytest.mark.parametrize("fmt", ["gmsh22", "gmsh"])
def test_gmsh_node_tag_zero_is_an_error(tmp_path, fmt):
    m = box((1, 1, 1), (1, 1, 1), "tet4")
    cells = m.cells.copy()
    cells[2, 1] = -1  # written as node tag 0, which meshio would read as the last node
    ones = np.ones(m.n_cells, dtype=int)
    f = tmp_path / "zero.msh"
    meshio.write(
        f,
        meshio.Mesh(m.points, [("tetra", cells)], cell_data={"gmsh:physical": [ones], "gmsh:geometrical": [ones]}),
        file_format=fmt,
        binary=False,
    )
    with pytest.raises(ValueError, match=r"zero\.msh: an element refers to node tag 0"):
        read_mesh(f)


def test_lower_dimensional_cells_are_dropped_with_a_count(tmp_path):
    m = box((1, 1, 1), (1, 1, 1), "tet4")
    f = tmp_path / "with_faces.vtu"
    tris = np.array([[0, 1, 2], [1, 2, 3]])
    meshio.write(f, meshio.Mesh(m.points, [("triangle", tris), ("tetra", m.cells), ("vertex", np.array([[0]]))]))
    with pytest.warns(UserWarning, match=r"ignored 3 lower-dimensional cell\(s\) \(2 triangle, 1 vertex\)"):
        r = read_mesh(f)
    assert np.array_equal(r.cells, m.cells)


def test_tetgen_count_must_match_rows(tmp_path):
    m = box((1, 1, 1), (1, 1, 1), "tet4")
    write_tetgen(tmp_path / "c", m.points, m.cells, 1)
    ele = tmp_path / "c.ele"
    for count in (-1, m.n_cells - 1, m.n_cells + 1):
        lines = ele.read_text().split("\n")
        lines[0] = f"{count} 4 1"
        ele.write_text("\n".join(lines))
        with pytest.raises(ValueError, match=r"c\.ele"):
            read_mesh(ele)


def test_tetgen_comments_and_tabs(tmp_path):
    # meshio's own TetGen reader fails on both; they are legal TetGen.
    m = box((1, 2, 3), (1, 1, 1), "tet4")
    write_tetgen(tmp_path / "t", m.points, m.cells, 0)
    node = tmp_path / "t.node"
    lines = node.read_text().split("\n")
    lines[1] = lines[1].replace(" ", "\t")
    node.write_text("\n".join(lines))
    r = read_mesh(node)
    assert np.array_equal(r.cells, m.cells)
    node.write_bytes(node.read_bytes().replace(b"0.0", b"0\xff0", 1))
    with pytest.raises(ValueError, match=r"t\.node: could not parse numbers"):
        read_mesh(node)


def test_read_mesh_from_meshio_object_and_back():
    m = box(SIZE, (2, 1, 1), "hex20")
    mm = m.to_meshio(point_data={"t": np.arange(m.n_nodes)})
    assert isinstance(mm, meshio.Mesh) and mm.point_data["t"].shape == (m.n_nodes,)
    mm.cells[0].data[:] = 0  # a copy: the Mesh is unchanged
    assert np.array_equal(m.cells, box(SIZE, (2, 1, 1), "hex20").cells)
    r = read_mesh(m.to_meshio())
    assert np.array_equal(r.points, m.points) and np.array_equal(r.cells, m.cells)
    bad = meshio.Mesh(m.points, [("hexahedron20", np.where(m.cells == 3, -1, m.cells))])
    with pytest.raises(ValueError, match=r"meshio\.Mesh: hexahedron20 cell 0 has node index -1"):
        read_mesh(bad)


def test_to_pyvista_without_pyvista(monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "pyvista", None)
    with pytest.raises(ImportError, match="pip install pyvista"):
        unit_tet().to_pyvista()


# -- ParaView time series ---------------------------------------------------------


def read_pvd(path):
    root = ET.parse(path).getroot()
    assert root.tag == "VTKFile" and root.get("type") == "Collection"
    return [(float(d.get("timestep")), d.get("file")) for d in root.iter("DataSet")]


def test_time_series_writer(tmp_path):
    mesh = box((1, 1, 1), (2, 1, 1), "hex8")
    pvd = tmp_path / "out" / "run.pvd"
    times = [0.0, 0.01, 0.02]
    rng = np.random.default_rng(0)
    frames = [mesh.points + 0.1 * rng.standard_normal(mesh.points.shape) for _ in times]
    with TimeSeriesWriter(pvd, mesh) as w:
        for i, (t, x) in enumerate(zip(times, frames)):
            w.write(t, x, point_data={"speed": np.full(mesh.n_nodes, float(i)), "velocity": np.ones((mesh.n_nodes, 3))})
            # The index is valid and complete after every frame, before close().
            assert [tt for tt, _ in read_pvd(pvd)] == times[: i + 1]
    entries = read_pvd(pvd)
    assert [f for _, f in entries] == [f"run/frame_{i:05d}.vtu" for i in range(3)]
    for i, (_, rel) in enumerate(entries):
        frame = meshio.read(pvd.parent / rel)
        assert np.allclose(frame.points, frames[i])
        assert np.allclose(frame.point_data["displacement"], frames[i] - mesh.points)
        assert np.allclose(frame.point_data["speed"], i)
        assert frame.cells_dict["hexahedron"].tolist() == mesh.cells.tolist()
    with pytest.raises(RuntimeError, match="closed"):
        w.write(1.0, mesh.points)


def test_time_series_writer_validates(tmp_path):
    mesh = unit_tet()
    with TimeSeriesWriter(tmp_path / "s.pvd", mesh) as w:
        with pytest.raises(ValueError, match=r"positions must have shape \(4, 3\)"):
            w.write(0.0, np.zeros((3, 3)))
        with pytest.raises(ValueError, match="'displacement' is reserved"):
            w.write(0.0, mesh.points, {"displacement": np.zeros((4, 3))})
    assert read_pvd(tmp_path / "s.pvd") == []
