"""Bodies that touch each other: a Scene's parts in one implicit system. Stacked cubes carry
each other's weight without passing through, a collision keeps momentum, friction between
two bodies holds and slides by Coulomb's law, and the potentials match finite differences."""

import numpy as np
import pytest
from conftest import CELLS, CUBE, check_contact_derivatives

import corotate as cr

ELEMENT = CUBE / CELLS
STEEL_FREE = cr.Material(E=1e5, nu=0.3, density=1000.0)  # a soft 1 kg cube


def cube_body(corner, cells=CELLS, size=CUBE, material=STEEL_FREE, element="tet4"):
    mesh = cr.box((size, size, size), (cells, cells, cells), element=element, origin=tuple(corner))
    return cr.Body(mesh, material)


def surface_of(sim, scene, k):
    """Body k's surface at the simulation's positions, as a triangle mesh."""
    mesh = scene.body.mesh
    nodes = scene.nodes(k)
    local = cr.Mesh(mesh.points[nodes], mesh.cells[np.isin(mesh.cells[:, 0], nodes)] - nodes[0], mesh.cell_type)
    outer = cr.boundary_surface(local)
    used = np.unique(local.boundary_faces())
    return cr.TriangleMesh(sim.positions[nodes][used], outer.cells), nodes[used]


def deepest_inside(sim, scene):
    """How deep the deepest surface vertex of either body is inside the other [m] (0: none)."""
    deepest = 0.0
    for k, other in ((0, 1), (1, 0)):
        surface, _ = surface_of(sim, scene, other)
        _, vertices = surface_of(sim, scene, k)
        d, _ = surface.distance(sim.positions[vertices])
        deepest = max(deepest, -d.min())
    return deepest


@pytest.mark.parametrize("integrator, frames", [("linearized", 1000), ("newton", 300)])
def test_stacked_cubes_carry_each_other_and_never_interpenetrate(integrator, frames):
    """One cube dropped on another on the floor (off-centre, corners onto a face): the floor
    carries both weights, the lower cube the upper's, and in 1,000 frames (300 with Newton,
    nearly at rest after 200) no surface vertex of either enters the other deeper than 1 % of
    an element."""
    scene = cr.Scene([cube_body((-0.05, -0.05, 0.0)), cube_body((-0.02, -0.04, 0.12))])
    # (Newton needs more than its default 20 iterations at a few of the landing steps, where
    # contacts come and go within the step.)
    sim = scene.simulation(friction=0.3, gravity=(0, 0, -9.81), integrator=integrator, newton_iterations=40)
    floor = cr.Plane()
    sim.add_obstacle(floor, friction=0.5)
    worst = 0.0
    fastest = []  # the fastest node's speed over the last 20 frames
    for frame in range(frames):
        sim.step()
        if frame % 10 == 0 or frame < 60:  # every frame of the landing, then every tenth
            worst = max(worst, deepest_inside(sim, scene))
        if frame >= frames - 20:
            fastest.append(np.abs(sim.velocities).max())
    assert worst < 0.01 * ELEMENT
    # The weights carried (to 1e-3: the upper cube still creeps on the lower one below the
    # smoothed friction's friction_velocity).
    np.testing.assert_allclose(sim.contact_force(floor), [0, 0, 2 * 9.81], atol=1e-3 * 2 * 9.81)
    np.testing.assert_allclose(sim.part_contact_force(1, 0), [0, 0, 9.81], atol=1e-3 * 9.81)
    np.testing.assert_allclose(sim.part_contact_force(0, 1), [0, 0, -9.81], atol=1e-3 * 9.81)
    # At rest up to a creep below friction_velocity, on average over the last frames: with
    # Newton the cubes still ring at a fraction of a mm/s after 300 frames, and one frame's
    # speed depends on the phase of that ringing (0.2-1.7 mm/s over the last 20).
    assert np.mean(fastest) < sim.contact_settings["friction_velocity"]
    # The upper cube rests on the lower one (its overhang drooping over the edge), not beside it.
    assert sim.positions[scene.nodes(1), 2].mean() > 1.45 * CUBE


@pytest.mark.parametrize("speed, gap, deepest", [(1.0, 0.02, 0.01), (5.0, 0.12, 0.1)])
def test_a_collision_keeps_momentum_and_pushes_the_other_body(speed, gap, deepest):
    """Weightless: a moving cube hits one at rest. Momentum before = after (the forces between
    them are equal and opposite inside one solve), they do not interpenetrate (at 5 m/s, 5 cm
    per step, the linearised impact step lets the corner in by 5 % of an element), and the one
    hit leaves with the momentum it received. At 5 m/s from 12 cm the first steps are out of
    the other body's reach (no nearest-point query) until the path per step can touch it."""
    scene = cr.Scene([cube_body((0.0, 0.0, 0.0)), cube_body((CUBE + gap, 0.01, 0.02))])
    sim = scene.simulation(solver=cr.Direct())
    a, b = scene.nodes(0), scene.nodes(1)
    sim.velocities[a, 0] = speed
    mass = sim.mass_matrix()

    def momentum():
        return (mass @ sim.velocities.reshape(-1)).reshape(-1, 3).sum(axis=0)

    p0 = momentum()
    worst = 0.0
    for _ in range(40):
        sim.step()
        np.testing.assert_allclose(momentum(), p0, atol=1e-9 * abs(p0[0]))
        worst = max(worst, deepest_inside(sim, scene))
    assert worst < deepest * ELEMENT
    pa = (mass @ np.where(np.isin(np.arange(sim.body.n_nodes), a)[:, None], sim.velocities, 0).reshape(-1)).reshape(
        -1, 3
    )
    # The cube hit left with what the other lost (equal masses: about half, as the implicit
    # step makes the soft collision inelastic).
    assert p0[0] - pa.sum(axis=0)[0] > 0.4 * p0[0]
    assert sim.velocities[b, 0].mean() > 0.4 * speed


@pytest.mark.parametrize("mu, theta_deg", [(0.5, 20.0), (0.2, 30.0)])
def test_friction_between_two_bodies(mu, theta_deg):
    """A block on a soft slab whose bottom is held, gravity tilted by theta: it sticks when
    tan(theta) < mu, else slides with g (sin - mu cos) within 2 %."""
    theta = np.deg2rad(theta_deg)
    g = 9.81
    slab = cr.Body(
        cr.box((0.4, 0.2, 0.04), (8, 4, 1), origin=(-0.2, -0.1, -0.04)), cr.Material(E=1e6, nu=0.3, density=1000.0)
    )
    block = cube_body((-0.05, -0.05, 0.0), cells=2, material=cr.Material(E=1e6, nu=0.3, density=1000.0))
    scene = cr.Scene([slab, block])
    sim = scene.simulation(
        friction=mu, gravity=(g * np.sin(theta), 0.0, -g * np.cos(theta)), integrator="newton", solver=cr.Direct()
    )
    bottom = scene.nodes(0)[np.isclose(slab.mesh.points[:, 2], -0.04)]
    sim.fix(bottom)
    top = scene.nodes(1)
    sim.step(10)  # settles (friction needs the normal force of a step)
    v0, t0 = sim.velocities[top, 0].mean(), sim.time
    sim.step(10)
    if np.tan(theta) < mu:
        assert abs(sim.velocities[top, 0].mean()) < 1e-3  # creeps at most at friction_velocity
    else:
        a = g * (np.sin(theta) - mu * np.cos(theta))
        measured = (sim.velocities[top, 0].mean() - v0) / (sim.time - t0)
        assert measured == pytest.approx(a, rel=0.02)


def test_part_potentials_match_finite_differences():
    """Energy, forces (on the node and on the triangle's corners) and the coupled Hessian
    e e^T (x) H of contacts between parts, sticking and sliding."""
    scene = cr.Scene([cube_body((0.0, 0.0, 0.0), cells=2), cube_body((0.01, 0.02, 0.101), cells=2)])
    sim = scene.simulation(friction=0.4, gravity=(0.5, 0.3, -9.81))
    sim.fix(scene.nodes(0)[np.isclose(scene.body.mesh.points[scene.nodes(0), 2], 0.0)])
    sim.step(40)
    contacts = sim.contacts
    assert (contacts["parts"] >= 0).sum() > 3
    rng = np.random.default_rng(7)
    for scale in (1e-7, 1e-3):  # sticking (within the slip width) and sliding
        y = sim.positions + scale * rng.normal(size=sim.positions.shape)
        check_contact_derivatives(sim, y, rng.normal(size=y.shape), 1e-8, internal=True)


def test_scene_bad_input():
    a = cube_body((0.0, 0.0, 0.0))
    with pytest.raises(TypeError, match=r"not a corotate\.Body"):
        cr.Scene([a, "cube"])
    with pytest.raises(ValueError, match="at least one body"):
        cr.Scene([])
    overlapping = cr.Scene([a, cube_body((0.03, 0.01, 0.01))])
    with pytest.raises(ValueError, match="starts inside part"):
        overlapping.simulation()
    scene = cr.Scene([a, cube_body((0.2, 0.0, 0.0))])
    with pytest.raises(ValueError, match="out of range"):
        scene.nodes(2)
    with pytest.raises(ValueError, match="has nodes"):
        scene.nodes(1, [0, 10_000])
    one = cr.Simulation(a)
    with pytest.raises(ValueError, match="at least two parts"):
        one.set_part_contact()
    sim = scene.simulation(friction=0.2)
    with pytest.raises(ValueError, match="friction"):
        sim.set_part_contact(friction=-1.0)
    assert sim.part_contact and sim._sim.part_friction == 0.2  # unchanged
    with pytest.raises(ValueError, match="solve_static"):
        sim.solve_static()
    sim.clear_part_contact()
    assert not sim.part_contact


def test_a_scene_keeps_each_body_s_materials():
    """Bodies of several regions each: every cell of the joined body has its own material."""
    mesh = cr.box((0.1, 0.1, 0.1), (2, 2, 2), origin=(0.0, 0.0, 0.0))
    two = cr.Body(
        mesh,
        {3: cr.Material(E=1e5, nu=0.3, density=1000.0), 7: STEEL_FREE},
        regions=np.arange(mesh.n_cells) % 2 * 4 + 3,
    )
    one = cube_body((0.2, 0.0, 0.0), cells=2, material=cr.Material(E=2e6, nu=0.25, density=500.0))
    scene = cr.Scene([two, one])
    lame = np.concatenate([np.column_stack(b.cell_lame()) for b in (two, one)])
    np.testing.assert_array_equal(np.column_stack(scene.body.cell_lame()), lame)
    np.testing.assert_allclose(
        scene.body.mass_matrix().sum(), 3 * (1000 * 0.1**3 / 2 + 1000 * 0.1**3 / 2 + 500 * 0.1**3)
    )
