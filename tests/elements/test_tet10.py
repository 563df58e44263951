"""The quadratic tetrahedron (meshio "tetra10", Gmsh's second-order tet) as a whole: an
embedded surface follows a quadratic field exactly, and a Gmsh order-2 file is read into VTK
order and simulated. (Its shape functions, faces, mirror map and volumes are checked with every
other element in test_cell_type_table.py; patch tests, rigid-motion invariance,
finite-difference forces and tangents in the element-generic tests of elements/ and models/;
its bending against Hex20 in validation/test_cantilever_static.py.)"""

import numpy as np
import pytest

import corotate as cr
import corotate._core as _core


def test_an_embedded_surface_follows_a_quadratic_field_exactly():
    mesh = cr.box((2.0, 1.0, 1.0), (2, 1, 1), "tet10")
    rng = np.random.default_rng(5)
    vertices = rng.uniform([0.05, 0.05, 0.05], [1.95, 0.95, 0.95], (40, 3))
    triangles = rng.integers(0, len(vertices), (20, 3))
    surface = cr.EmbeddedSurface(mesh, vertices, triangles)
    assert surface.report["outside"] == 0

    def field(p):  # a full quadratic map, well inside the element's space
        x, y, z = p.T
        return np.column_stack([x + 0.1 * x * y - 0.05 * z**2, y + 0.2 * x**2, z + 0.1 * y * z + 0.03 * x * z])

    surface.update(field(mesh.points), normals="none")
    np.testing.assert_allclose(surface.positions, field(vertices), rtol=0, atol=1e-13)
    # A linear tet mesh of the same cells cannot: it interpolates the field piecewise linearly.
    coarse = cr.box((2.0, 1.0, 1.0), (2, 1, 1), "tet4")
    linear = cr.EmbeddedSurface(coarse, vertices, triangles)
    linear.update(field(coarse.points), normals="none")
    assert np.abs(linear.positions - field(vertices)).max() > 1e-3


GMSH_TET10 = """$MeshFormat
2.2 0 8
$EndMeshFormat
$Nodes
10
1 0 0 0
2 1 0 0
3 0 1 0
4 0 0 1
5 0.5 0 0
6 0.5 0.5 0
7 0 0.5 0
8 0 0 0.5
9 0 0.5 0.5
10 0.5 0 0.5
$EndNodes
$Elements
1
1 11 2 1 1 1 2 3 4 5 6 7 8 9 10
$EndElements
"""


def test_a_gmsh_order_two_file_is_read_in_vtk_order_and_simulated(tmp_path):
    # Gmsh numbers the tet's last two mid-nodes (3,2) and (3,1); VTK (1,3) and (2,3).
    path = tmp_path / "tet10.msh"
    path.write_text(GMSH_TET10)
    mesh = cr.read_mesh(path)
    assert mesh.cell_type == "tetra10" and mesh.cells.shape == (1, 10)
    edges = cr.cell_types()["tetra10"]["edges"]
    p = mesh.points[mesh.cells[0]]
    for i, (a, b) in enumerate(edges):
        np.testing.assert_allclose(p[4 + i], 0.5 * (p[a] + p[b]))
    assert mesh.cell_volumes() == pytest.approx([1 / 6], rel=1e-14)


def test_a_gmsh_order_two_body_sags_under_gravity_to_its_static_answer(tmp_path):
    # meshio writes VTK's order back into Gmsh's: the file holds Gmsh's numbering.
    import meshio

    box = cr.box((1.0, 1.0, 2.0), (2, 2, 4), "tet10")
    path = tmp_path / "column.msh"
    meshio.write(path, meshio.Mesh(box.points, [("tetra10", box.cells)]), file_format="gmsh22", binary=False)
    assert "$Elements" in path.read_text()
    mesh = cr.read_mesh(path)
    np.testing.assert_array_equal(mesh.cells, box.cells)
    body = cr.Body(mesh, cr.Material(E=1e5, nu=0.3, density=1000.0))
    assert body.mass_matrix().sum() == pytest.approx(3 * 1000 * 2.0, rel=1e-12)

    def clamped(sim):
        sim.fix(mesh.nodes_on_plane("z", 0.0))
        return sim

    sim = clamped(cr.Simulation(body, dt=0.01, gravity=(0, 0, -9.81), solver=cr.Direct(), rayleigh=(5.0, 0.0)))
    sim.step(300)
    static = clamped(cr.Simulation(body, dt=0.01, gravity=(0, 0, -9.81), solver=cr.Direct()))
    static.solve_static()
    top = mesh.nodes_on_plane("z", 2.0)
    sag = static.displacements[top, 2].mean()
    # rho g L^2 / (2 E) for a column under its own weight, without the clamp's lateral restraint.
    assert sag == pytest.approx(-1000 * 9.81 * 4.0 / (2 * 1e5), rel=0.05)
    np.testing.assert_allclose(sim.displacements[top, 2], static.displacements[top, 2], rtol=1e-3)


def _barycentric_integral(powers):
    """int over a tet of volume V of L0^a L1^b L2^c L3^d, divided by V: a! b! c! d! 3! / (a+b+c+d+3)!."""
    from math import factorial

    return float(np.prod([factorial(p) for p in powers]) * 6 / factorial(sum(powers) + 3))


def _tet10_shape_polynomials():
    """Each Tet10 shape function as {barycentric exponents: coefficient}."""
    unit = np.eye(4, dtype=int)
    out = [{tuple(2 * unit[i]): 2.0, tuple(unit[i]): -1.0} for i in range(4)]
    out += [{tuple(unit[a] + unit[b]): 4.0} for a, b in cr.cell_types()["tetra10"]["edges"]]
    return out


def test_the_consistent_mass_of_a_straight_tet10_is_exact():
    # The mass rule must integrate N_a N_b (degree 4) exactly: compare with the closed
    # integrals of barycentric monomials, on a sheared straight-sided tet.
    corners = np.array([[0.0, 0, 0], [2, 0.3, 0], [0.4, 1.5, 0.2], [0.1, 0.2, 1.2]])
    edges = cr.cell_types()["tetra10"]["edges"]
    nodes = np.vstack([corners, [0.5 * (corners[a] + corners[b]) for a, b in edges]])
    volume = np.linalg.det(corners[1:] - corners[0]) / 6
    d = _core.element_matrices("tetra10", nodes, _core.Material(1e6, 0.3, 1000.0))
    N = _tet10_shape_polynomials()
    expected = np.array(
        [
            [
                sum(ca * cb * _barycentric_integral(np.add(pa, pb)) for pa, ca in Na.items() for pb, cb in Nb.items())
                for Nb in N
            ]
            for Na in N
        ]
    )
    np.testing.assert_allclose(d["mass"], 1000.0 * volume * expected, rtol=1e-12, atol=1e-12 * volume)
    # Corners carry negative row sums (int N_corner = -V/20): the lumped mass is HRZ, all positive.
    assert np.all(np.asarray(d["mass"]).sum(axis=1)[:4] < 0) and np.all(np.asarray(d["lumped_mass"]) > 0)
