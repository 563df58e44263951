"""Bad input raises the right error with a message naming the problem, and a
failing call leaves the simulation state as it was."""

import math

import meshio
import numpy as np
import pytest

import corotate as cr
from corotate import _core

MAT = cr.Material(E=1e6, nu=0.3, density=1000.0)


def unit_tet_points():
    return np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)


def small_sim(solver=None, element="tet4", **kw):
    mesh = cr.box((1.0, 1.0, 1.0), (2, 2, 2), element)
    sim = cr.Simulation(cr.Body(mesh, MAT), dt=0.01, solver=solver, gravity=(0, 0, -9.81), **kw)
    sim.fix(mesh.nodes_on_plane("x", 0.0))
    return mesh, sim


def snapshot(sim):
    return sim.positions.copy(), sim.velocities.copy(), sim.time, sim.stats["steps"]


def assert_state(sim, snap):
    x, v, t, steps = snap
    np.testing.assert_array_equal(sim.positions, x)
    np.testing.assert_array_equal(sim.velocities, v)
    assert sim.time == t
    assert sim.stats["steps"] == steps


# -- mesh files ------------------------------------------------------------


def test_missing_mesh_file(tmp_path):
    path = tmp_path / "no_such_mesh.vtu"
    with pytest.raises(FileNotFoundError, match=r"no_such_mesh\.vtu"):
        cr.read_mesh(path)
    with pytest.raises(FileNotFoundError, match=r"no_such_mesh\.node"):
        cr.read_mesh(tmp_path / "no_such_mesh.ele")


def test_mesh_file_with_only_triangles(tmp_path):
    path = tmp_path / "triangles.vtu"
    points = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], dtype=float)
    meshio.write(path, meshio.Mesh(points, [("triangle", np.array([[0, 1, 2], [1, 3, 2]]))]))
    with pytest.raises(
        ValueError, match=rf"no supported volume cells.*triangle.*supported: {', '.join(cr.mesh.VOLUME_CELL_TYPES)}"
    ):
        cr.read_mesh(path)


def test_unsupported_cell_type_elsewhere():
    with pytest.raises(ValueError, match="unsupported cell type 'wedge'"):
        cr.Mesh(np.zeros((6, 3)), [[0, 1, 2, 3, 4, 5]], "wedge")
    with pytest.raises(ValueError, match=r"element_matrices needs solid cells .*, not 'triangle'"):
        _core.element_matrices("triangle", np.zeros((3, 3)), MAT._core())
    with pytest.raises(ValueError, match="unsupported cell type 'pyramid'"):
        _core.ForceModel("linear", "pyramid", unit_tet_points(), np.array([[0, 1, 2, 3]]), MAT._core())


# -- elements --------------------------------------------------------------


def test_zero_volume_tet():
    p = unit_tet_points()
    p[3] = (0.3, 0.3, 0.0)  # all four nodes in the plane z = 0
    mesh = cr.Mesh(p, [[0, 1, 2, 3]], "tetra")
    with pytest.raises(ValueError, match=r"element 0 \(tetra\) has zero volume"):
        cr.Body(mesh, MAT)


def test_zero_volume_element_is_named_by_index():
    mesh = cr.box((1, 1, 1), (2, 1, 1), "tet4")
    p = mesh.points.copy()
    cell = mesh.cells[7]  # a tet of the second cuboid: flatten it onto its first three nodes' plane
    a, b, c, d = p[cell]
    n = np.cross(b - a, c - a)
    p[cell[3]] = d - ((d - a) @ n) / (n @ n) * n
    bad = cr.Mesh(p, mesh.cells, mesh.cell_type)
    # other tets that share the moved node may become degenerate or inverted
    # first; the first failing one is named. It must be one containing the node.
    with pytest.raises(ValueError, match=r"element \d+ \(tetra\)") as info:
        cr.Body(bad, MAT)
    e = int(str(info.value).split()[1])
    assert cell[3] in mesh.cells[e]


def test_zero_volume_hex():
    mesh = cr.box((1, 1, 1), (1, 1, 1), "hex8")
    p = mesh.points.copy()
    p[mesh.cells[0][4:]] = p[mesh.cells[0][:4]]  # top face onto the bottom face
    with pytest.raises(ValueError, match=r"element 0 \(hexahedron\) has zero volume"):
        cr.Body(cr.Mesh(p, mesh.cells, "hexahedron"), MAT)


@pytest.mark.parametrize(
    "element,flip",
    [
        ("hex8", [4, 5, 6, 7, 0, 1, 2, 3]),
        ("tet4", [0, 2, 1, 3]),
        ("hex20", [4, 5, 6, 7, 0, 1, 2, 3, 12, 13, 14, 15, 8, 9, 10, 11, 16, 17, 18, 19]),
    ],
)
def test_inverted_element(element, flip):
    mesh = cr.box((2, 1, 1), (2, 1, 1), element)
    cells = mesh.cells.copy()
    last = len(cells) - 1
    cells[last] = cells[last][flip]
    inverted = cr.Mesh(mesh.points, cells, mesh.cell_type)
    assert inverted.cell_volumes()[last] < 0
    with pytest.raises(ValueError, match=rf"element {last} \({mesh.cell_type}\) is inverted \(negative Jacobian"):
        cr.Body(inverted, MAT)
    with pytest.raises(ValueError, match="is inverted"):
        _core.element_matrices(mesh.cell_type, mesh.points[cells[last]], MAT._core())


# -- material --------------------------------------------------------------


@pytest.mark.parametrize("nu", [0.5, 0.7])
def test_poisson_ratio_too_large(nu):
    with pytest.raises(ValueError, match=rf"Poisson ratio must lie in \(-1, 0.5\), got nu = {nu}.*incompressible"):
        cr.Material(E=1e6, nu=nu, density=1000.0)


@pytest.mark.parametrize("nu", [-1.0, -1.5, float("nan")])
def test_poisson_ratio_too_small_or_nan(nu):
    with pytest.raises(ValueError, match="Poisson ratio"):
        cr.Material(E=1e6, nu=nu, density=1000.0)


@pytest.mark.parametrize("E", [0.0, -1.0, float("inf"), float("nan")])
def test_youngs_modulus_not_positive(E):
    with pytest.raises(ValueError, match="Young's modulus must be positive and finite, got E = "):
        cr.Material(E=E, nu=0.3, density=1000.0)


@pytest.mark.parametrize("rho", [0.0, -1000.0])
def test_density_not_positive(rho):
    with pytest.raises(ValueError, match="density must be positive and finite, got rho = "):
        cr.Material(E=1e6, nu=0.3, density=rho)


def test_valid_material_edges_accepted():
    m = cr.Material(E=1e6, nu=0.49, density=1.0)
    lam, mu = m.lame
    assert lam == pytest.approx(1e6 * 0.49 / (1.49 * 0.02))
    assert mu == pytest.approx(1e6 / 2.98)


# -- node indices ----------------------------------------------------------


@pytest.mark.parametrize("bad", [4, -1])
def test_mesh_cell_index_out_of_range(bad):
    with pytest.raises(ValueError, match=rf"cell 1 has node index {bad} out of range \[0, 4\)"):
        cr.Mesh(unit_tet_points(), [[0, 1, 2, 3], [0, 1, 2, bad]], "tetra")


def test_core_rejects_out_of_range_cells():
    with pytest.raises(ValueError, match="out of range"):
        _core.ForceModel("linear", "tetra", unit_tet_points(), np.array([[0, 1, 2, 4]]), MAT._core())


@pytest.mark.parametrize("bad", [27, 1000, -1])
def test_fix_index_out_of_range(bad):
    mesh, sim = small_sim()
    before = sim.fixed_nodes.copy()
    assert mesh.n_nodes == 27
    with pytest.raises(ValueError, match=rf"node index {bad} is out of range \[0, 27\)"):
        sim.fix([0, bad])
    # the previous constraints are kept
    np.testing.assert_array_equal(sim.fixed_nodes, before)
    snap = snapshot(sim)
    sim.step(1)
    np.testing.assert_array_equal(sim.positions[before], snap[0][before])
    assert np.abs(sim.positions - snap[0]).max() > 0


def test_fix_bad_mask_and_dtype():
    _mesh, sim = small_sim()
    with pytest.raises(ValueError, match="one entry per node"):
        sim.fix(np.ones(5, dtype=bool))
    with pytest.raises(ValueError, match="integers"):
        sim.fix([0.5, 1.0])


# -- non-finite state ------------------------------------------------------


@pytest.mark.parametrize("solver", [cr.PCG(tolerance=1e-12, max_iterations=200), cr.Direct()], ids=["pcg", "direct"])
def test_nan_position_rejected_and_state_kept(solver):
    _mesh, sim = small_sim(solver)
    sim.step(2)
    snap = snapshot(sim)
    good = sim.positions[13].copy()
    sim.positions[13, 1] = np.nan
    with pytest.raises(ValueError, match="position of node 13 is not finite"):
        sim.step(1)
    expected = snap[0].copy()
    expected[13, 1] = np.nan
    np.testing.assert_array_equal(sim.positions, expected)  # equal_nan is on by default
    np.testing.assert_array_equal(sim.velocities, snap[1])
    assert sim.time == snap[2] and sim.stats["steps"] == snap[3]
    with pytest.raises(ValueError, match="position of node 13 is not finite"):
        sim.solve_static()
    # restore: stepping works again and matches a run that never saw the NaN
    sim.positions[13] = good
    sim.step(1)
    assert sim.time == pytest.approx(snap[2] + 0.01)
    _, clean = small_sim(solver)
    clean.step(3)
    np.testing.assert_allclose(sim.positions, clean.positions, rtol=0, atol=1e-12)


def test_nan_velocity_and_force_rejected_and_state_kept():
    _mesh, sim = small_sim()
    sim.step(2)
    snap = snapshot(sim)
    sim.velocities[4, 0] = np.inf
    with pytest.raises(ValueError, match="velocity of node 4 is not finite"):
        sim.step(1)
    sim.velocities[4, 0] = snap[1][4, 0]
    assert_state(sim, snap)

    sim.external_forces[20] = (0.0, np.nan, 0.0)
    with pytest.raises(ValueError, match="external force of node 20 is not finite"):
        sim.step(3)
    assert_state(sim, snap)
    sim.external_forces[20] = 0.0
    sim.step(1)
    assert sim.time == pytest.approx(snap[2] + 0.01)


def test_step_that_overflows_restores_state():
    # A feather-light body under a huge (finite) force: the velocity update
    # overflows to inf. The step must fail with RuntimeError and leave
    # positions, velocities, time and statistics exactly as before.
    mesh = cr.box((1.0, 1.0, 1.0), (2, 2, 2), "tet4")
    body = cr.Body(mesh, cr.Material(E=1e6, nu=0.3, density=1e-10))
    sim = cr.Simulation(body, dt=1e-6, solver=cr.Direct())
    sim.fix(mesh.nodes_on_plane("x", 0.0))
    sim.external_forces[-1] = (0.0, 0.0, -1.0)
    sim.step(2)
    snap = snapshot(sim)
    assert np.abs(sim.velocities).max() > 0
    sim.external_forces[-1] = (0.0, 0.0, 1e308)
    with pytest.raises(RuntimeError, match=r"non-finite positions or velocities.*state was restored"):
        sim.step(3)
    assert_state(sim, snap)
    # and it carries on once the load is sane
    sim.external_forces[-1] = (0.0, 0.0, -1.0)
    sim.step(1)
    assert sim.stats["steps"] == snap[3] + 1
    assert np.all(np.isfinite(sim.positions))


def test_pcg_step_with_huge_finite_force_is_not_silently_skipped():
    mesh = cr.box((1.0, 1.0, 1.0), (2, 2, 2), "tet4")
    body = cr.Body(mesh, MAT)
    pcg = cr.PCG(preconditioner="jacobi", tolerance=1e-10, max_iterations=500)
    results = {}
    for name, solver in (("pcg", pcg), ("direct", cr.Direct())):
        sim = cr.Simulation(body, dt=0.01, solver=solver)
        sim.fix(mesh.nodes_on_plane("x", 0.0))
        sim.external_forces[-1] = (0.0, 0.0, 1e160)
        snap = snapshot(sim)
        try:
            sim.step(1)
        except RuntimeError:
            assert_state(sim, snap)  # failing loudly and cleanly is acceptable
            results[name] = None
            continue
        assert math.isfinite(sim.stats["residual"]) or not sim.stats["converged"]
        results[name] = sim.displacements
    if results["pcg"] is not None:
        # a step that claims success must move the body like the direct solve does
        d_ref = results["direct"]
        assert np.abs(d_ref).max() > 1e150
        np.testing.assert_allclose(results["pcg"], d_ref, rtol=0, atol=1e-6 * np.abs(d_ref).max())


def test_held_state_views_follow_the_state():
    _mesh, sim = small_sim(cr.Direct())
    pos, vel = sim.positions, sim.velocities
    sim.step(1)
    np.testing.assert_array_equal(pos, sim.positions)
    np.testing.assert_array_equal(vel, sim.velocities)
    # prescribing a fixed node's motion through the held view must take effect
    node = sim.fixed_nodes[0]
    pos[node] += (0.0, 0.0, 0.01)
    target = pos[node].copy()
    sim.step(1)
    np.testing.assert_array_equal(sim.positions[node], target)


# -- simulation parameters -------------------------------------------------


@pytest.mark.parametrize("dt", [0.0, -0.01, float("nan"), float("inf")])
def test_bad_time_step(dt):
    body = cr.Body(cr.box((1, 1, 1), (1, 1, 1), "tet4"), MAT)
    with pytest.raises(ValueError, match="time step must be positive and finite"):
        cr.Simulation(body, dt=dt)


def test_bad_rayleigh_and_mass_kind():
    body = cr.Body(cr.box((1, 1, 1), (1, 1, 1), "tet4"), MAT)
    with pytest.raises(ValueError, match="Rayleigh alpha"):
        cr.Simulation(body, rayleigh=(-1.0, 0.0))
    with pytest.raises(ValueError, match="Rayleigh beta"):
        cr.Simulation(body, rayleigh=(0.0, float("nan")))
    with pytest.raises(ValueError, match="unknown mass 'diagonal'"):
        cr.Simulation(body, mass="diagonal")


def test_unknown_model_and_preconditioner():
    mesh = cr.box((1, 1, 1), (1, 1, 1), "tet4")
    with pytest.raises(ValueError, match=r"unknown model 'neo-hookean'.*'linear', 'corotational'"):
        cr.Body(mesh, MAT, model="neo-hookean")
    with pytest.raises(ValueError, match="unknown model 'mooney-rivlin'"):
        _core.ForceModel("mooney-rivlin", "tetra", mesh.points, mesh.cells, MAT._core())
    body = cr.Body(mesh, MAT)
    with pytest.raises(ValueError, match="unknown preconditioner 'ilu'"):
        cr.Simulation(body, solver=cr.PCG(preconditioner="ilu"))
    with pytest.raises(ValueError, match="max_iterations"):
        cr.Simulation(body, solver=cr.PCG(max_iterations=0))
    with pytest.raises(TypeError, match="solver must be"):
        cr.Simulation(body, solver="direct")


def test_renamed_model_corotated_names_fixed_corotated():
    # "corotated" (Stomakhin's law) was one suffix away from "corotational" (the paper's model).
    mesh = cr.box((1, 1, 1), (1, 1, 1), "tet4")
    message = (
        "model 'corotated' was renamed 'fixed_corotated' (Stomakhin's fixed co-rotated law); "
        "'corotational' is the paper's co-rotated linear FEM"
    )
    assert "corotated" not in _core.model_names() and "fixed_corotated" in _core.model_names()
    with pytest.raises(ValueError) as body_error:
        cr.Body(mesh, MAT, model="corotated")
    assert str(body_error.value) == message
    with pytest.raises(ValueError) as core_error:
        _core.ForceModel("corotated", "tetra", mesh.points, mesh.cells, MAT._core())
    assert str(core_error.value) == message
    with pytest.raises(ValueError) as law_error:
        _core.constitutive_law("corotated", np.eye(3), MAT._core())
    assert str(law_error.value) == message
    cr.Body(mesh, MAT, model="fixed_corotated")  # the new name builds


def test_bad_gravity_and_step_count():
    _mesh, sim = small_sim()
    with pytest.raises(ValueError, match="gravity must be a 3-vector"):
        sim.gravity = (0.0, -9.81)
    with pytest.raises(ValueError, match="gravity must be finite"):
        sim.gravity = (0.0, 0.0, np.nan)
    np.testing.assert_array_equal(sim.gravity, [0.0, 0.0, -9.81])
    with pytest.raises(ValueError, match="step count must be non-negative"):
        sim.step(-1)
    assert sim.time == 0.0


def test_bad_positions_shape_for_body():
    mesh = cr.box((1, 1, 1), (1, 1, 1), "tet4")
    body = cr.Body(mesh, MAT)
    with pytest.raises(ValueError, match=r"positions must have shape \(8, 3\)"):
        body.internal_forces(np.zeros((7, 3)))
    x = mesh.points.copy()
    x[2, 2] = np.inf
    with pytest.raises(ValueError, match="position of node 2 is not finite"):
        body.internal_forces(x)


# -- statics ---------------------------------------------------------------


def test_static_solve_that_cannot_converge():
    # A slender soft cantilever under a tip load that bends it far (tip
    # rotation of tens of degrees, strains of a few percent): one Newton
    # iteration cannot reach equilibrium.
    L = 8.0
    mesh = cr.beam(L, 1.0, 1.0, cells=(8, 1, 1), element="hex8")
    body = cr.Body(mesh, cr.Material(E=1e5, nu=0.3, density=100.0))
    sim = cr.Simulation(body, dt=0.01, solver=cr.Direct())
    sim.fix(mesh.nodes_on_plane("x", 0.0))
    tip = mesh.nodes_on_plane("x", L)
    sim.external_forces[tip] = (0.0, 0.0, -200.0 / len(tip))
    sim.step(2)  # a non-rest state with velocities, to check both are kept
    snap = snapshot(sim)
    assert np.abs(sim.velocities).max() > 0
    with pytest.raises(
        RuntimeError, match=r"did not converge in 1 iterations at load step 1 of 1; relative residuals: \d\S* \d"
    ):
        sim.solve_static(load_steps=1, max_iterations=1)
    assert_state(sim, snap)
    with pytest.raises(ValueError, match="load_steps"):
        sim.solve_static(load_steps=0)
    with pytest.raises(ValueError, match="max_iterations"):
        sim.solve_static(max_iterations=0)
    with pytest.raises(ValueError, match="tolerance"):
        sim.solve_static(tolerance=-1.0)
    assert_state(sim, snap)
    # with load steps and enough iterations it converges, and the tip has gone
    # far down (a large deflection, so the failure above was a real one)
    result = sim.solve_static(load_steps=4, max_iterations=50)
    assert len(result["residual_history"]) == 4
    assert result["residual_history"][-1][-1] <= 1e-8
    assert np.abs(sim.velocities).max() == 0.0
    assert sim.displacements[tip, 2].mean() < -0.2 * L


def test_mesh_with_a_node_in_no_cell_is_rejected_by_name():
    points = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [5, 5, 5]], dtype=float)
    mesh = cr.Mesh(points, np.array([[0, 1, 2, 3]]), "tetra")
    with pytest.raises(ValueError, match="node 4 belongs to no cell"):
        cr.Body(mesh, MAT)
