"""Triangle-mesh obstacles: exact signed distances from a bounding-volume hierarchy and
pseudonormals, refused when the surface is not closed, and a body resting on, landing on
and carried by one as it would on the analytic shape."""

import threading

import numpy as np
import pytest
from conftest import CELLS, CUBE, cube

import corotate as cr

ELEMENT = CUBE / CELLS


def box_surface(size, cells=(2, 3, 1), center=(0.0, 0.0, 0.0)):
    """A closed triangulated box (the boundary of a hexahedral mesh: flat faces, many
    triangles per face) whose exact distance is the analytic Box's."""
    size = np.asarray(size, dtype=float)
    grid = cr.box(tuple(size), cells, origin=tuple(np.asarray(center) - size / 2))
    surface = cr.boundary_surface(grid)
    return surface.points, surface.cells


def random_rotation(rng):
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q *= np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


def test_distance_equals_the_box_it_triangulates():
    rng = np.random.default_rng(1)
    size = (0.4, 0.3, 0.2)
    rotation, position = random_rotation(rng), rng.normal(size=3)
    mesh = cr.TriangleMesh(*box_surface(size), position=position, rotation=rotation)
    exact = cr.Box(position, size, rotation)
    # Points around and inside it: nearest to its faces, edges and corners.
    points = position + rng.uniform(-0.3, 0.3, (4000, 3)) @ rotation.T
    d, n = mesh.distance(points)
    d_exact, n_exact = exact.distance(points)
    np.testing.assert_allclose(d, d_exact, atol=1e-12)
    np.testing.assert_allclose(n, n_exact, atol=1e-9)
    assert (d < 0).sum() > 200  # inside points were tested too


def test_sphere_within_its_chord_error():
    """A triangulated sphere: the distance differs from the round sphere's by at most the
    facets' sag, and the sign is right everywhere outside that band."""
    rng = np.random.default_rng(2)
    surface = cr.sphere_surface(0.1, 1500)
    mesh = cr.TriangleMesh(surface.points, surface.cells)
    corners = surface.points[surface.cells]
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    sag = 0.1 - np.einsum("ij,ij->i", normals, corners[:, 0]).min()  # deepest facet plane
    points = rng.uniform(-0.15, 0.15, (5000, 3))
    d, n = mesh.distance(points)
    d_round = np.linalg.norm(points, axis=1) - 0.1
    assert np.abs(d - d_round).max() <= sag * (1 + 1e-9)
    clear = np.abs(d_round) > sag
    np.testing.assert_array_equal(np.sign(d[clear]), np.sign(d_round[clear]))
    # The normal is the distance's gradient: a step along it changes d by the step.
    step = 1e-7
    d_moved, _ = mesh.distance(points + step * n)
    far = np.abs(d) > 1e-4
    np.testing.assert_allclose((d_moved - d)[far] / step, 1.0, atol=1e-5)


def test_an_inward_wound_mesh_is_turned_outward():
    points, triangles = box_surface((0.2, 0.2, 0.2))
    outward = cr.TriangleMesh(points, triangles)
    inward = cr.TriangleMesh(points, triangles[:, ::-1])
    probe = np.random.default_rng(3).uniform(-0.2, 0.2, (500, 3))
    np.testing.assert_array_equal(inward.distance(probe)[0], outward.distance(probe)[0])
    corners = points[inward.triangles]
    volume = np.einsum("ij,ij->i", corners[:, 0], np.cross(corners[:, 1], corners[:, 2])).sum() / 6
    assert volume == pytest.approx(0.2**3, rel=1e-12)


def _hole(p, t):
    return p, t[1:]


def _fin(p, t):
    return p, np.vstack([t, t[:1]])


def _flipped_one(p, t):
    t = t.copy()
    t[0] = t[0, ::-1]
    return p, t


def _nan_vertex(p, t):
    p = p.copy()
    p[3, 1] = np.nan
    return p, t


def _index_out_of_range(p, t):
    t = t.copy()
    t[2, 0] = len(p)
    return p, t


def _zero_area(p, t):
    p = p.copy()
    a, b, c = t[0]
    p[c] = 0.5 * (p[a] + p[b])  # a sliver: its third corner on its first edge
    return p, t


def _flat(p, t):
    return np.column_stack([p[:, :2], np.zeros(len(p))]), t


@pytest.mark.parametrize(
    "spoil, match",
    [
        (_hole, r"not closed.*hole"),
        (_fin, "shared by 3 triangles"),
        (_flipped_one, "not consistently oriented"),
        (_nan_vertex, r"vertex 3 .* not finite"),
        (_index_out_of_range, "refers to vertex"),
        (_zero_area, "zero area"),
        (_flat, "zero area|encloses no volume"),
        (lambda p, t: (p, t.astype(float)), "integer"),
        (lambda p, t: (p[:, :2], t), r"shape \(n, 3\)"),
        (lambda p, t: (p, t[:, :2]), r"\(m, 3\)"),
        (lambda p, t: (p, t[:3]), "at least 4 triangles"),
    ],
)
def test_a_surface_that_is_not_closed_is_refused(spoil, match):
    with pytest.raises(ValueError, match=match):
        cr.TriangleMesh(*spoil(*box_surface((0.2, 0.2, 0.2))))


def test_read_from_a_file(tmp_path):
    meshio = pytest.importorskip("meshio")
    points, triangles = box_surface((0.2, 0.3, 0.4))
    meshio.write(tmp_path / "box.obj", meshio.Mesh(points, [("triangle", triangles)]))
    mesh = cr.TriangleMesh.read(tmp_path / "box.obj", position=(1.0, 0.0, 0.0))
    assert mesh.distance([[1.0, 0.0, 0.5]])[0][0] == pytest.approx(0.3)
    meshio.write(tmp_path / "open.obj", meshio.Mesh(points, [("triangle", triangles[1:])]))
    with pytest.raises(ValueError, match=r"open\.obj.*hole"):
        cr.TriangleMesh.read(tmp_path / "open.obj")
    with pytest.raises((FileNotFoundError, ValueError), match=r"missing\.stl"):
        cr.TriangleMesh.read(tmp_path / "missing.stl")
    (tmp_path / "garbage.stl").write_bytes(b"solid x\nfacet normal nan\n")
    with pytest.raises(ValueError, match=r"garbage\.stl"):
        cr.TriangleMesh.read(tmp_path / "garbage.stl")


def test_set_vertices_moves_the_surface_and_refuses_bad_input():
    points, triangles = box_surface((0.2, 0.2, 0.2))
    mesh = cr.TriangleMesh(points, triangles)
    shift = np.array([0.3, -0.1, 0.05])
    mesh.set_vertices(points + shift)
    probe = np.random.default_rng(4).uniform(-0.5, 0.5, (300, 3))
    np.testing.assert_allclose(mesh.distance(probe)[0], cr.Box(shift, (0.2, 0.2, 0.2)).distance(probe)[0], atol=1e-12)
    before = mesh.vertices
    bad = points.copy()
    bad[0, 0] = np.inf
    for args, match in [
        ((points[:-1],), "vertices"),
        ((bad,), "not finite"),
        ((points, np.full_like(points, np.nan)), "not finite"),
        ((points, points[:2]), "velocities"),
    ]:
        with pytest.raises(ValueError, match=match):
            mesh.set_vertices(*args)
        np.testing.assert_array_equal(mesh.vertices, before)


def test_distribute_keeps_force_and_moment():
    rng = np.random.default_rng(5)
    points, triangles = box_surface((0.2, 0.2, 0.2))
    rotation = random_rotation(rng)
    mesh = cr.TriangleMesh(points, triangles, position=(0.0, 0.0, 1.0), rotation=rotation)
    on_surface = (points[triangles[:40]] * rng.dirichlet([1, 1, 1], 40)[:, :, None]).sum(axis=1)
    at = on_surface @ rotation.T + (0.0, 0.0, 1.0)
    forces = rng.normal(size=(40, 3))
    spread = mesh.distribute(at, forces)
    world_vertices = points @ rotation.T + (0.0, 0.0, 1.0)
    np.testing.assert_allclose(spread.sum(axis=0), forces.sum(axis=0), atol=1e-12)
    np.testing.assert_allclose(
        np.cross(world_vertices, spread).sum(axis=0), np.cross(at, forces).sum(axis=0), atol=1e-12
    )
    with pytest.raises(ValueError, match="one force per point"):
        mesh.distribute(at, forces[:-1])
    with pytest.raises(ValueError, match="finite"):
        mesh.distribute(at, np.full_like(forces, np.nan))


def test_cube_rests_on_a_mesh_as_on_the_box():
    slab = box_surface((0.6, 0.6, 0.1), cells=(3, 3, 1), center=(0.0, 0.0, -0.05))
    finals = []
    for obstacle in (cr.TriangleMesh(*slab), cr.Box((0.0, 0.0, -0.05), (0.6, 0.6, 0.1))):
        _mesh, sim = cube(z0=0.03)
        sim.add_obstacle(obstacle, friction=0.5)
        deepest = 0.0
        for _ in range(150):
            sim.step()
            deepest = min(deepest, sim.positions[:, 2].min())
        assert deepest > -0.01 * ELEMENT
        np.testing.assert_allclose(sim.contact_force(obstacle), [0, 0, 9.81], atol=1e-4)
        finals.append(sim.positions.copy())
    # The same rest (to round-off that landing with friction amplifies).
    np.testing.assert_allclose(finals[0], finals[1], atol=1e-3 * ELEMENT)


def test_no_tunnelling_through_a_thin_mesh_at_10_m_per_s():
    slab = cr.TriangleMesh(*box_surface((1.0, 1.0, 0.002), cells=(4, 4, 1), center=(0.0, 0.0, -0.001)))
    _mesh, sim = cube(z0=0.02, E=1e6, solver=cr.PCG(tolerance=1e-8))
    sim.velocities[:, 2] = -10.0
    sim.add_obstacle(slab)
    for _ in range(30):
        sim.step()
        assert sim.positions[:, 2].min() > -0.01 * ELEMENT


@pytest.mark.parametrize("integrator", ["newton", "linearized"])
def test_a_conveyor_belt_carries_the_block_at_its_speed(integrator):
    """A surface that moves along itself (vertex velocities, positions unchanged): friction
    accelerates the block at mu g until it moves with the belt, then holds it there. (The
    linearised step's friction is the secant of the slip it starts with: while the slip
    shrinks within a step it pulls less than mu N, so only Newton's acceleration is checked.)"""
    belt_speed, mu, g, dt = 0.2, 0.5, 9.81, 0.01
    points, triangles = box_surface((2.0, 1.0, 0.1), cells=(8, 4, 1), center=(0.0, 0.0, -0.05))
    belt = cr.TriangleMesh(points, triangles)
    top = np.isclose(points[:, 2], 0.0)
    velocities = np.zeros_like(points)
    velocities[top, 0] = belt_speed
    belt.set_vertices(points, velocities)
    _mesh, sim = cube(z0=0.0, E=1e6, integrator=integrator)
    sim.add_obstacle(belt, friction=mu)
    sim.step(1)  # friction needs the normal force of a step
    v0, t0 = sim.velocities[:, 0].mean(), sim.time
    sim.step(3)
    acceleration = (sim.velocities[:, 0].mean() - v0) / (sim.time - t0)
    if integrator == "newton":
        assert acceleration == pytest.approx(mu * g, rel=0.02)
    assert sim.velocities[:, 0].mean() < belt_speed
    sim.step(int(belt_speed / (mu * g) / dt) + 30)
    np.testing.assert_allclose(sim.velocities[:, 0], belt_speed, rtol=1e-3)


def test_moving_the_mesh_from_another_thread_while_stepping():
    points, triangles = box_surface((0.6, 0.6, 0.1), cells=(3, 3, 1), center=(0.0, 0.0, -0.05))
    mesh = cr.TriangleMesh(points, triangles)
    _cube_mesh, sim = cube(z0=0.0)
    sim.add_obstacle(mesh, friction=0.3)
    stop = threading.Event()
    errors = []

    def wiggle():
        k = 0
        while not stop.is_set():
            try:
                mesh.set_vertices(points + np.array([0.0, 0.0, 1e-4 * (k % 2)]))
            except Exception as e:  # pragma: no cover - what the test is looking for
                errors.append(e)
            k += 1

    thread = threading.Thread(target=wiggle)
    thread.start()
    try:
        sim.step(100)
    finally:
        stop.set()
        thread.join()
    assert not errors
    assert np.all(np.isfinite(sim.positions))
    assert sim.positions[:, 2].min() > -0.01 * ELEMENT
