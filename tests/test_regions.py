"""Bodies of several materials (cr.Body(mesh, materials, regions=...)): the two-material bar
against the series springs (statics and a modal reduction), each cell's density in the mass,
one region equal to the homogeneous body bit for bit, per-cell modal stresses, the force
feedback's elements, regions read from mesh files, and the errors for regions without a
material."""

import meshio
import numpy as np
import pytest

import corotate as cr
from corotate.modal.modal_stress import linear_stress

SOFT = cr.Material(E=1e6, nu=0.0, density=1000.0)
STIFF = cr.Material(E=4e6, nu=0.0, density=3000.0)
L1, L2, WIDTH = 1.0, 1.5, 0.5


def two_material_bar(element="hex8", cells=(10, 2, 2)):
    """A bar [0, L1 + L2] x [0, WIDTH]^2: x < L1 region 0, the rest region 1 (the interface
    is a plane of nodes)."""
    mesh = cr.box((L1 + L2, WIDTH, WIDTH), cells, element)
    centres = mesh.points[mesh.cells].mean(axis=1)
    return mesh, (centres[:, 0] > L1).astype(np.int64)


@pytest.mark.parametrize("model", ["linear", "corotational", "stvk", "mooney_rivlin"])
def test_two_material_bar_in_tension_is_two_springs_in_series(model):
    """Left face clamped (nu = 0: nothing to restrain laterally), a force F spread uniformly
    over the right face: u = F L1 / (E1 A) + F L2 / (E2 A), exact for linear FEM (the
    displacement is piecewise linear in x) and, at a strain of 1e-6, for the others up to
    terms of the strain's order."""
    mesh, regions = two_material_bar()
    body = cr.Body(mesh, [SOFT, STIFF], model=model, regions=regions)
    sim = cr.Simulation(body, solver=cr.Direct())
    sim.fix(mesh.nodes_on_plane("x", 0.0))
    right = mesh.nodes_on_plane("x", L1 + L2)
    area = WIDTH**2
    force = (1e-3 if model == "linear" else 1e-6) * SOFT.E * area  # strain: any for linear FEM
    sim.external_forces[:] = tip_load(mesh, force)
    sim.solve_static()
    rel = 1e-10 if model == "linear" else 1e-5
    np.testing.assert_allclose(sim.displacements[right, 0], series_springs(force), rtol=rel)
    interface = mesh.nodes_on_plane("x", L1)
    np.testing.assert_allclose(sim.displacements[interface, 0], force * L1 / (SOFT.E * area), rtol=rel)


def tip_load(mesh, force):
    """(n, 3) nodal forces of a force along x spread uniformly over the right face (a 2 x 2
    grid of bilinear faces: corner 1/16, edge 1/8, centre 1/4)."""
    right = mesh.nodes_on_plane("x", L1 + L2)
    y, z = mesh.points[right, 1], mesh.points[right, 2]
    weight = np.where(np.isclose(y % WIDTH, 0), 0.5, 1.0) * np.where(np.isclose(z % WIDTH, 0), 0.5, 1.0)
    f = np.zeros_like(mesh.points)
    f[right, 0] = force * weight / weight.sum()
    return f


def series_springs(force):
    area = WIDTH**2
    return force * L1 / (SOFT.E * area) + force * L2 / (STIFF.E * area)


def test_modal_reduction_of_the_two_material_bar_keeps_its_static_answer():
    """A Craig-Bampton basis with the loaded face as interface holds the exact static
    response (its constraint modes are the static shapes), so the reduced tip displacement
    is the series-spring answer."""
    mesh, regions = two_material_bar()
    body = cr.Body(mesh, [SOFT, STIFF], model="linear", regions=regions)
    right = mesh.nodes_on_plane("x", L1 + L2)
    basis = cr.modal.craig_bampton(body, mesh.nodes_on_plane("x", 0.0), 2, interface_nodes=right)
    V = basis.vectors
    force = 1e-3 * SOFT.E * WIDTH**2
    q = np.linalg.solve(V.T @ (body.stiffness_matrix() @ V), V.T @ tip_load(mesh, force).ravel())
    u = (V @ q).reshape(-1, 3)
    np.testing.assert_allclose(u[right, 0], series_springs(force), rtol=1e-9)


def test_mass_takes_each_cells_density():
    mesh, regions = two_material_bar()
    body = cr.Body(mesh, {0: SOFT, 1: STIFF}, regions=regions)
    total = body.mass_matrix(lumped=True).diagonal().sum() / 3
    expected = (SOFT.density * L1 + STIFF.density * L2) * WIDTH**2
    assert total == pytest.approx(expected, rel=1e-13)
    consistent = body.mass_matrix().sum() / 3
    assert consistent == pytest.approx(expected, rel=1e-13)


@pytest.mark.parametrize("model", cr.choices.MODELS)
def test_one_region_is_the_homogeneous_body_bit_for_bit(model):
    mesh = cr.box((2.0, 1.0, 1.0), (2, 1, 1), "hex8")
    material = cr.Material(E=1e6, nu=0.3, density=1000.0)
    x = mesh.points + 0.05 * np.random.default_rng(0).standard_normal(mesh.points.shape)
    for materials, regions in (([material], np.zeros(mesh.n_cells, int)), ({7: material}, np.full(mesh.n_cells, 7))):
        # Both fresh: a co-rotational body's rotations are warm-started from its previous call.
        homogeneous = cr.Body(mesh, material, model=model)
        body = cr.Body(mesh, materials, model=model, regions=regions)
        np.testing.assert_array_equal(body.internal_forces(x), homogeneous.internal_forces(x))
        assert body.energy(x) == homogeneous.energy(x)
        assert (body.stiffness_matrix(x) != homogeneous.stiffness_matrix(x)).nnz == 0
        assert (body.mass_matrix() != homogeneous.mass_matrix()).nnz == 0


def test_regions_without_a_material_are_named():
    mesh, regions = two_material_bar()
    bad = regions.copy()
    bad[5] = 2
    with pytest.raises(ValueError, match=r"cell 5 has region 2, which has no material \(materials are given for"):
        cr.Body(mesh, [SOFT, STIFF], regions=bad)
    with pytest.raises(ValueError, match=r"cell 0 has region 0, which has no material.*region\(s\) 1, 2"):
        cr.Body(mesh, {1: SOFT, 2: STIFF}, regions=regions)
    bad[5] = -1
    with pytest.raises(ValueError, match="cell 5 has region -1, which has no material"):
        cr.Body(mesh, [SOFT, STIFF], regions=bad)
    with pytest.raises(ValueError, match="2 materials need the region of each cell"):
        cr.Body(mesh, [SOFT, STIFF])
    with pytest.raises(ValueError, match=r"regions must have shape \(40,\)"):
        cr.Body(mesh, [SOFT, STIFF], regions=regions[:-1])
    with pytest.raises(ValueError, match="region ids must be integers"):
        cr.Body(mesh, [SOFT, STIFF], regions=regions.astype(float))
    with pytest.raises(TypeError, match=r"material of region 1 must be a corotate\.Material"):
        cr.Body(mesh, [SOFT, "steel"], regions=regions)
    body = cr.Body(mesh, [SOFT, STIFF], regions=regions)
    with pytest.raises(ValueError, match="several materials"):
        _ = body.material
    assert body.materials == {0: SOFT, 1: STIFF}
    np.testing.assert_array_equal(body.regions, regions)


def test_the_core_checks_region_ids_too():
    mesh, regions = two_material_bar()
    core = cr._core.RegionMaterials([SOFT._core(), STIFF._core()], regions + 1)
    with pytest.raises(ValueError, match=r"cell \d+ has region id 2, which has no material \(2 material\(s\) given"):
        cr._core.ForceModel("linear", "hexahedron", mesh.points, mesh.cells, core)


def test_modal_stresses_take_each_cells_moduli():
    mesh, regions = two_material_bar()
    soft, stiff = cr.Material(E=1e6, nu=0.3, density=1.0), cr.Material(E=3e6, nu=0.2, density=1.0)
    body = cr.Body(mesh, [soft, stiff], regions=regions)
    strain = 1e-3
    u = np.zeros_like(mesh.points)
    u[:, 0] = strain * mesh.points[:, 0]  # uniform eps_xx
    sigma = linear_stress(body, u)
    for region, m in enumerate((soft, stiff)):
        lam, mu = m.lame
        np.testing.assert_allclose(sigma[regions == region, 0, 0], (lam + 2 * mu) * strain, rtol=1e-12)
        np.testing.assert_allclose(sigma[regions == region, 1, 1], lam * strain, rtol=1e-12)


@pytest.mark.parametrize("method", ["linear", "corotational"])
def test_feedback_at_the_interface_uses_each_elements_material(method):
    """The tool's force is the body's internal force at its nodes (only the tool's elements
    contribute there): at a node on the interface the elements of both materials count."""
    mesh, regions = two_material_bar()
    body = cr.Body(mesh, [SOFT, STIFF], model=method, regions=regions)
    tool = [mesh.nearest_node((L1, WIDTH / 2, WIDTH / 2))]
    feedback = cr.HapticFeedback(body, tool, method=method)
    x = mesh.points.copy()
    x[tool, :] += (0.01, 0.005, -0.002)
    forces, _ = feedback.query(x)
    expected = body.internal_forces(x)[tool]
    np.testing.assert_allclose(forces, expected, rtol=1e-9, atol=1e-12 * np.abs(expected).max())
    homogeneous = cr.HapticFeedback(cr.Body(mesh, SOFT, model=method), tool, method=method).query(x)[0]
    assert np.abs(forces - homogeneous).max() > 0.5 * np.abs(homogeneous).max()


def test_read_mesh_takes_regions_from_gmsh_physical_groups(tmp_path):
    mesh, regions = two_material_bar("tet4", cells=(5, 1, 1))
    first = regions == 0
    # As Gmsh writes them: one block per physical group, its ids in "gmsh:physical".
    blocks = [("tetra", mesh.cells[first]), ("tetra", mesh.cells[~first])]
    physical = [np.full(first.sum(), 11), np.full((~first).sum(), 12)]
    m = meshio.Mesh(mesh.points, blocks, cell_data={"gmsh:physical": physical})
    read = cr.read_mesh(m)
    np.testing.assert_array_equal(read.cell_regions, np.concatenate(physical))
    body = cr.Body(read, {11: SOFT, 12: STIFF})  # regions from the mesh
    np.testing.assert_array_equal(body.regions, read.cell_regions)
    # write_mesh keeps them, read_mesh reads them back.
    cr.write_mesh(tmp_path / "bar.vtu", read)
    np.testing.assert_array_equal(cr.read_mesh(tmp_path / "bar.vtu").cell_regions, read.cell_regions)
    assert cr.read_mesh(meshio.Mesh(mesh.points, [("tetra", mesh.cells)])).cell_regions is None
