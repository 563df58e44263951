"""The cell-type table (corotate.cell_types(), bound from the C++ elements): every fact an
element declares is checked against its own shape functions and geometry, so a new element
registered in C++ is tested here without a line of this file changing."""

import numpy as np
import pytest

import corotate as cr
import corotate._core as _core

TABLE = cr.cell_types()
SOLIDS = [name for name, facts in TABLE.items() if facts["dim"] == 3]
REFERENCE_VOLUME = {"simplex": 1.0 / 6.0, "cube": 8.0}


def reference_points(name, count=7, seed=0):
    """Random points inside the reference cell of a cell type."""
    rng = np.random.default_rng(seed)
    if TABLE[name]["domain"] == "cube":
        return rng.uniform(-1, 1, (count, 3))
    p = rng.dirichlet(np.ones(4), count)  # barycentric
    return p[:, 1:]


@pytest.mark.parametrize("name", SOLIDS)
def test_shape_functions_interpolate_at_their_nodes_and_sum_to_one(name):
    nodes = TABLE[name]["reference_nodes"]
    values, _ = _core.shape_functions(name, nodes)
    np.testing.assert_allclose(values, np.eye(len(nodes)), atol=1e-14)
    values, gradients = _core.shape_functions(name, reference_points(name))
    np.testing.assert_allclose(values.sum(axis=1), 1.0, atol=1e-14)
    np.testing.assert_allclose(gradients.reshape(len(values), -1, 3).sum(axis=1), 0.0, atol=1e-13)


@pytest.mark.parametrize("name", SOLIDS)
def test_shape_gradients_are_the_derivatives_of_the_values(name):
    xi = reference_points(name, 3)
    k = TABLE[name]["num_nodes"]
    _, gradients = _core.shape_functions(name, xi)
    h = 1e-6
    for d in range(3):
        step = np.zeros(3)
        step[d] = h
        plus, _ = _core.shape_functions(name, xi + step)
        minus, _ = _core.shape_functions(name, xi - step)
        np.testing.assert_allclose((plus - minus) / (2 * h), gradients.reshape(-1, k, 3)[:, :, d], atol=1e-8)


@pytest.mark.parametrize("name", SOLIDS)
def test_shape_functions_reproduce_polynomials_of_the_element_order(name):
    # Interpolating x^a y^b z^c (a + b + c <= order) from the nodes gives it back exactly:
    # a complete polynomial of the element's degree is in its space (the basis of patch tests).
    facts = TABLE[name]
    nodes = facts["reference_nodes"]
    xi = reference_points(name, 9, seed=3)
    values, _ = _core.shape_functions(name, xi)
    for powers in np.ndindex(3, 3, 3):
        if sum(powers) > facts["order"]:
            continue
        field = lambda p: np.prod(p ** np.array(powers), axis=1)  # noqa: B023
        np.testing.assert_allclose(values @ field(nodes), field(xi), atol=1e-13)


@pytest.mark.parametrize("name", [n for n in TABLE if TABLE[n]["order"] == 2])
def test_a_quadratic_elements_extra_nodes_sit_in_the_middle_of_its_edges(name):
    facts = TABLE[name]
    nodes, corners = facts["reference_nodes"], facts["num_corners"]
    assert len(facts["edges"]) == facts["num_nodes"] - corners
    for i, (a, b) in enumerate(facts["edges"]):
        np.testing.assert_allclose(nodes[corners + i], 0.5 * (nodes[a] + nodes[b]), atol=1e-15)


@pytest.mark.parametrize("name", SOLIDS)
def test_the_reference_cell_has_its_volume_and_outward_faces(name):
    facts = TABLE[name]
    nodes = facts["reference_nodes"]
    cell = np.arange(facts["num_nodes"])[None]
    volume = _core.cell_volumes(name, nodes, cell)
    np.testing.assert_allclose(volume, REFERENCE_VOLUME[facts["domain"]], rtol=1e-14)
    centre = nodes[: facts["num_corners"]].mean(axis=0)
    for face in facts["faces"]:
        p = nodes[face]
        normal = np.cross(p[1] - p[0], p[2] - p[0])
        assert normal @ (p.mean(axis=0) - centre) > 0, f"{name} face {face} points inwards"


@pytest.mark.parametrize("name", SOLIDS)
def test_the_mirror_map_turns_a_cell_inside_out_and_keeps_it_the_same_element(name):
    facts = TABLE[name]
    mirror = np.asarray(facts["mirror"])
    assert sorted(mirror) == list(range(facts["num_nodes"]))
    rng = np.random.default_rng(1)
    A = np.eye(3) + 0.2 * rng.standard_normal((3, 3))
    points = facts["reference_nodes"] @ A.T + rng.standard_normal(3)
    cell = np.arange(facts["num_nodes"])[None]
    v = _core.cell_volumes(name, points, cell)[0]
    np.testing.assert_allclose(v, np.linalg.det(A) * REFERENCE_VOLUME[facts["domain"]], rtol=1e-12)
    np.testing.assert_allclose(_core.cell_volumes(name, points, cell[:, mirror]), -v, rtol=1e-12)
    # Still the same element: the mirrored numbering's edges are edges of the cell, so a
    # quadratic cell keeps each mid-node between the two corners it belongs to.
    corners = facts["num_corners"]
    for i, (a, b) in enumerate(facts["edges"]):
        if facts["order"] == 2:
            mid = points[mirror][corners + i]
            np.testing.assert_allclose(mid, 0.5 * (points[mirror][a] + points[mirror][b]), atol=1e-13)


@pytest.mark.parametrize("name", SOLIDS)
def test_the_generator_fills_a_box_with_positive_cells_and_closed_outward_faces(name):
    size, cells = np.array([2.0, 1.0, 0.5]), (3, 2, 2)
    element = TABLE[name]["generator_name"]
    mesh = cr.box(size, cells, element, origin=(1.0, -2.0, 0.5))
    assert mesh.cell_type == name
    volumes = mesh.cell_volumes()
    assert (volumes > 0).all()
    np.testing.assert_allclose(volumes.sum(), size.prod(), rtol=1e-13)
    faces = mesh.boundary_faces()
    p = mesh.points[faces]
    # Face areas add up to the box's surface, and the outward normals' flux of x is the volume.
    fan = [np.cross(p[:, i] - p[:, 0], p[:, i + 1] - p[:, 0]) for i in range(1, faces.shape[1] - 1)]
    area_vectors = 0.5 * np.sum(fan, axis=0)
    np.testing.assert_allclose(np.linalg.norm(area_vectors, axis=1).sum(), 2 * (2 * 1 + 2 * 0.5 + 1 * 0.5), rtol=1e-13)
    flux = np.sum(area_vectors[:, 0] * p[:, :, 0].mean(axis=1))
    np.testing.assert_allclose(flux, size.prod(), rtol=1e-12)
    # Every node is used, mid-edge nodes are shared: no two nodes coincide.
    assert np.unique(mesh.cells).size == mesh.n_nodes
    assert np.unique(np.round(mesh.points, 12), axis=0).shape[0] == mesh.n_nodes


def test_every_name_of_the_core_is_a_key_of_the_table_and_the_mesh_reads_the_table():
    assert list(TABLE) == _core.cell_type_names()
    assert cr.SUPPORTED_CELL_TYPES == {name: facts["num_nodes"] for name, facts in TABLE.items()}
    generators = ", ".join(TABLE[name]["generator_name"] for name in SOLIDS)
    with pytest.raises(ValueError, match=f"unknown element 'tet11'; choose one of {generators}$"):
        cr.box((1, 1, 1), (1, 1, 1), "tet11")
