"""Meshes that are silently wrong today get a clear verdict (corotate.mesh_checks): duplicate
cells, tet soups, tangled meshes, truncated files; and the documented repair (repair=True)
gives back exactly the mesh that was meant."""

import meshio
import numpy as np
import pytest

import corotate as cr
from corotate.mesh import SOLID_ELEMENTS
from corotate.mesh_checks import drop_duplicate_cells, duplicate_cells, merge_coincident_nodes

BOX = cr.box((1.0, 1.0, 1.0), (2, 2, 2))  # 48 tets, 1 m3


def mass(mesh: cr.Mesh) -> float:
    """Total mass [kg] of a body of density 1000 (the lumped mass matrix sums to 3 m)."""
    return cr.Body(mesh, cr.Material(density=1000.0)).mass_matrix(lumped=True).sum() / 3


def test_duplicate_cells_are_an_error_not_double_mass():
    cells = np.concatenate([BOX.cells, BOX.cells[5:8]])
    with pytest.raises(ValueError, match=r"cell 48 repeats cell 5 .*3 duplicate cell\(s\).*repair=True"):
        cr.Mesh(BOX.points, cells)


def test_duplicate_cells_with_permuted_nodes_from_a_vtu(tmp_path):
    cells = np.concatenate([BOX.cells, BOX.cells[[7]][:, [2, 3, 0, 1]]])  # same orientation, other order
    f = tmp_path / "twice.vtu"
    meshio.write(f, meshio.Mesh(BOX.points, [("tetra", cells)]))
    with pytest.raises(ValueError, match=r"twice\.vtu: cell 48 repeats cell 7 \(the same nodes, permuted"):
        cr.read_mesh(f)
    with pytest.warns(UserWarning, match=r"1 duplicate cell\(s\) dropped"):
        repaired = cr.read_mesh(f, repair=True)
    assert np.array_equal(repaired.cells, BOX.cells)
    assert mass(repaired) == pytest.approx(1000.0, rel=1e-12)


def test_a_tet_soup_is_an_error_and_repair_welds_it():
    soup_points = BOX.points[BOX.cells].reshape(-1, 3)  # each cell its own 4 nodes
    soup_cells = np.arange(4 * BOX.n_cells).reshape(-1, 4)
    with pytest.raises(ValueError, match=r"nodes 0 and \d+ are at the same position .*tet soup"):
        cr.Mesh(soup_points, soup_cells)
    with pytest.warns(UserWarning, match=rf"{4 * 48 - 27} coincident node\(s\) merged"):
        welded = cr.Mesh(soup_points, soup_cells, repair=True)
    assert welded.n_nodes == BOX.n_nodes == 27
    # The same cells on the same positions: each welded cell's corners are the box cell's.
    assert np.array_equal(welded.points[welded.cells], BOX.points[BOX.cells])
    assert len(cr.boundary_surface(welded).cells) == len(cr.boundary_surface(BOX).cells) == 48


def test_a_tangled_mesh_is_an_error_not_a_reordering_warning(tmp_path):
    points = BOX.points.copy()
    points[BOX.nearest_node((0.5, 0.5, 0.5))] = (0.5, 0.5, 2.0)  # the centre node pulled out through the top
    assert np.abs(_tet_volumes(points[BOX.cells])).sum() == pytest.approx(5 / 3)  # 1.667 m3 in a 1 m3 box
    f = tmp_path / "tangled.vtu"
    meshio.write(f, meshio.Mesh(points, [("tetra", BOX.cells)]))
    with pytest.raises(ValueError, match=r"tangled\.vtu: cells \d+ and \d+ lie on the same side .*tangled.*8 such"):
        cr.read_mesh(f)


def _tet_volumes(x):
    e = x[:, 1:] - x[:, :1]
    return np.linalg.det(e) / 6


def test_two_cells_overlapping_without_inversion_share_a_face_on_one_side():
    # A fourth node above the triangle of the first tet on the same side as its apex.
    points = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [0.1, 0.1, 0.5]], dtype=float)
    with pytest.raises(ValueError, match=r"cells 0 and 1 lie on the same side of their shared face"):
        cr.Mesh(points, [[0, 1, 2, 3], [0, 1, 2, 4]])


def test_a_consistently_mirrored_mesh_is_still_read_and_flipped(tmp_path):
    mirrored = BOX.cells[:, [0, 2, 1, 3]]
    f = tmp_path / "mirrored.vtu"
    meshio.write(f, meshio.Mesh(BOX.points, [("tetra", mirrored)]))
    with pytest.warns(UserWarning, match="reordered 48 of 48"):
        m = cr.read_mesh(f)
    assert np.array_equal(m.cells, BOX.cells)


def test_an_abaqus_file_cut_at_80_percent_is_an_error(tmp_path):
    whole = tmp_path / "whole.inp"
    meshio.write(whole, meshio.Mesh(BOX.points, [("tetra", BOX.cells)]))
    text = whole.read_text()
    cut = tmp_path / "cut.inp"
    cut.write_text(text[: text.rindex("\n", 0, int(0.8 * len(text))) + 1])
    with pytest.raises(ValueError, match=r"cut\.inp: \d+ of 27 node\(s\) are used by no cell .*truncated"):
        cr.read_mesh(cut)
    assert cr.read_mesh(whole).n_cells == 48


def test_unused_nodes_are_dropped_only_when_asked(tmp_path):
    points = np.vstack([BOX.points, [[5.0, 5.0, 5.0]]])
    f = tmp_path / "extra.vtu"
    meshio.write(f, meshio.Mesh(points, [("tetra", BOX.cells)]))
    with pytest.raises(ValueError, match=r"1 of 28 node\(s\) are used by no cell \(node 27 is the first\)"):
        cr.read_mesh(f)
    with pytest.warns(UserWarning, match="removed 1 node"):
        m = cr.read_mesh(f, remove_unused_nodes=True)
    assert np.array_equal(m.points, BOX.points)


def test_repair_helpers_on_arrays():
    cells, dropped = drop_duplicate_cells(np.array([[0, 1, 2, 3], [3, 2, 1, 0], [1, 2, 3, 4]]))
    assert dropped == 1 and cells.tolist() == [[0, 1, 2, 3], [1, 2, 3, 4]]
    points = np.array([[0, 0, 0], [1, 0, 0], [0, 0, 0], [0, 1, 0], [0, 0, 1], [7, 7, 7]], dtype=float)
    merged_points, merged_cells, merged = merge_coincident_nodes(points, np.array([[2, 1, 3, 4]]))
    assert merged == 1  # node 2 became node 0; the unused node 5 stays (read_mesh still reports it)
    assert merged_points.tolist() == [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [7, 7, 7]]
    assert merged_cells.tolist() == [[0, 1, 2, 3]]


def test_a_cell_naming_a_node_twice_is_an_error():
    with pytest.raises(ValueError, match="cell 1 names a node twice"):
        cr.Mesh(BOX.points, np.concatenate([BOX.cells[:1], [[0, 1, 1, 2]]]))


@pytest.mark.parametrize("element", SOLID_ELEMENTS)
def test_valid_meshes_pass_including_distorted_hexes(element):
    mesh = cr.box((1.0, 2.0, 1.5), (3, 2, 2), element)
    rng = np.random.default_rng(0)
    moved = mesh.points + 0.05 * rng.standard_normal(mesh.points.shape)  # non-planar hex faces
    checked = cr.Mesh(moved, mesh.cells, mesh.cell_type)
    assert np.array_equal(checked.points, moved) and np.array_equal(checked.cells, mesh.cells)


@pytest.mark.parametrize("largest_index", [10, 10**6])  # rows packed into one integer, or not
def test_duplicate_cells_found_with_any_node_numbers(largest_index):
    rng = np.random.default_rng(3)
    cells = rng.choice(largest_index, size=(200, 4), replace=True)
    cells[:, 3] = largest_index  # some rows share nodes, none repeats a node set by chance...
    cells = np.unique(np.sort(cells, axis=1), axis=0)  # ...once made unique
    doubled = np.concatenate([cells, cells[[4, 9]][:, ::-1]])
    assert duplicate_cells(doubled).tolist() == [[4, len(cells)], [9, len(cells) + 1]]
    assert len(duplicate_cells(cells)) == 0
