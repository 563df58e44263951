"""A cube dropped on the ground and on obstacles: it lands, rests at the right height with
the weight carried, never passes through, and does not tunnel through a thin slab at 10 m/s."""

import numpy as np
import pytest
from conftest import CELLS, CUBE, cube

import corotate as cr

ELEMENT = CUBE / CELLS


@pytest.mark.parametrize("integrator", ["linearized", "newton"])
def test_dropped_cube_comes_to_rest_on_the_ground(integrator):
    mesh, sim = cube(z0=0.05, integrator=integrator)
    sim.add_obstacle(cr.Plane())
    deepest = 0.0
    for _ in range(1000):
        sim.step()
        deepest = min(deepest, sim.positions[:, 2].min())
    # Never deeper than 1 % of an element, landing at 1 m/s included.
    assert deepest > -0.01 * ELEMENT
    # At rest: on the ground to round-off, carrying the weight (1 kg) exactly.
    assert abs(sim.positions[:, 2].min()) < 1e-9 * CUBE
    np.testing.assert_allclose(sim.contact_force(), [0, 0, 9.81], atol=1e-6)
    # Still vertically (without friction, the tet mesh's slight asymmetry leaves it gliding
    # sideways at a few um/s, as a frictionless body keeps its momentum).
    assert np.abs(sim.velocities[:, 2]).max() < 1e-6
    glide = sim.velocities[:, :2]
    assert np.abs(glide).max() < 1e-4  # of the 1 m/s it landed at
    assert np.ptp(glide, axis=0).max() < 1e-6  # as one rigid body
    # Its own weight squeezes the cube by rho g H^2 / (2 E) at the top (0.5 mm here): the
    # top face sits there, not lower (the ground took the weight) nor higher.
    top = mesh.points[:, 2] == mesh.points[:, 2].max()
    squeeze = 1000 * 9.81 * CUBE**2 / (2 * 1e5)
    assert abs((CUBE - sim.positions[top, 2].mean()) - squeeze) < 0.2 * squeeze


@pytest.mark.parametrize("integrator", ["linearized", "newton"])
@pytest.mark.parametrize("friction", [0.0, 0.5])
def test_a_cube_thrown_up_from_the_ground_leaves_it(integrator, friction):
    """A cube at rest on the ground, given 1 m/s upward, flies as it would with no ground
    (up 5 cm and back): the ground only pushes. (Its resting contacts once held it down with
    a pull of k times 1e-3 of the node's size each.)"""
    _mesh, sim = cube(z0=0.0, integrator=integrator)
    sim.add_obstacle(cr.Plane(), friction=friction)
    sim.step(100)
    free = cr.Simulation(sim.body, gravity=(0.0, 0.0, -9.81), integrator=integrator)
    free.positions[:] = sim.positions
    thrown = sim.velocities + np.array([0.0, 0.0, 1.0])
    for s in (sim, free):
        s.velocities[:] = thrown
    start = sim.positions[:, 2].mean()
    heights = []
    for _ in range(15):  # up to about the apex (0.1 s at 1 m/s)
        sim.step()
        free.step()
        heights.append((sim.positions[:, 2].mean(), free.positions[:, 2].mean()))
        # Off the ground, no force from it.
        np.testing.assert_allclose(sim.contact_force(), 0.0, atol=1e-9)
    on_ground, in_free_flight = np.array(heights).T
    rise = in_free_flight.max() - start
    assert rise > 0.04  # (the free cube's own rise: 1 / (2 g) less implicit Euler's damping)
    np.testing.assert_allclose(on_ground, in_free_flight, atol=1e-3 * rise)


def test_a_slender_block_tipped_over_falls_onto_its_side_as_the_newton_step_has_it():
    """A 5 x 5 x 30 cm block standing on its end, tipped at 2 rad/s about its bottom edge:
    both integrators let it fall onto its side. (The linearised step's resting contacts once
    held its foot down and kept it standing.)"""
    mesh = cr.box((0.05, 0.05, 0.3), (2, 2, 12), origin=(-0.025, -0.025, 0.0))
    body = cr.Body(mesh, cr.Material(E=1e6, nu=0.3, density=1000.0))
    heights = {}
    for integrator, solver in (("linearized", cr.PCG()), ("newton", cr.Direct())):
        sim = cr.Simulation(body, gravity=(0.0, 0.0, -9.81), integrator=integrator, solver=solver, newton_iterations=60)
        sim.add_obstacle(cr.Plane(), friction=0.8)
        sim.velocities[:] = np.cross([2.0, 0.0, 0.0], mesh.points - [0.0, 0.025, 0.0])
        sim.step(100)
        heights[integrator] = sim.positions[:, 2].mean()
        assert np.abs(sim.velocities).max() < 1e-3  # at rest again
    assert abs(heights["newton"] - 0.025) < 1e-3  # its centre half its width up: on its side
    assert abs(heights["linearized"] - heights["newton"]) < 1e-3


def test_contacts_report_the_planes_and_the_forces():
    mesh, sim = cube(z0=0.0)
    sim.add_obstacle(cr.Plane(), friction=0.3)
    sim.step(50)
    c = sim.contacts
    assert set(c["nodes"]) == set(np.flatnonzero(mesh.points[:, 2] == 0))
    np.testing.assert_allclose(c["normals"], np.tile([0, 0, 1], (len(c["nodes"]), 1)))
    np.testing.assert_allclose(c["forces"][:, 2].sum(), 9.81, rtol=1e-6)
    np.testing.assert_allclose(c["multipliers"], c["forces"][:, 2], rtol=1e-6, atol=1e-9)


def test_resting_on_a_tilted_box_top():
    """The weight goes along a tilted face's normal (and friction holds the rest)."""
    tilt = np.deg2rad(10)
    rot = np.array([[np.cos(tilt), 0, np.sin(tilt)], [0, 1, 0], [-np.sin(tilt), 0, np.cos(tilt)]])
    slab = cr.Box((0, 0, -0.05), (1.0, 1.0, 0.1), rot)
    _mesh, sim = cube(z0=0.03)
    sim.add_obstacle(slab, friction=0.8)
    sim.step(200)
    assert slab.distance(sim.positions)[0].min() > -0.01 * ELEMENT
    np.testing.assert_allclose(sim.contact_force(slab), [0, 0, 9.81], atol=1e-3)


@pytest.mark.parametrize("thickness", [0.002, 0.0005])
def test_no_tunnelling_through_a_thin_slab_at_10_m_per_s(thickness):
    """At 10 m/s a node moves 10 cm per 0.01 s step: 50-200 times the slab's thickness. An
    impact that stops the body in one step needs an accurate solve (the default PCG's 1e-2
    residual is for resting and sliding contact)."""
    accurate = cr.PCG(max_iterations=200, tolerance=1e-8)
    _mesh, sim = cube(z0=0.02, E=1e8, solver=accurate)  # stiff: a 10 m/s impact strains it by v / c = 3 %
    sim.velocities[:] = (0.0, 0.0, -10.0)
    slab = cr.Box((0, 0, -thickness / 2), (1.0, 1.0, thickness))
    sim.add_obstacle(slab)
    for _ in range(100):
        sim.step()
        assert sim.positions[:, 2].min() > -thickness / 2  # never through its middle
    assert sim.velocities[:, 2].max() > -1e-3  # stopped on top (inelastic: implicit Euler)
    assert sim.positions[:, 2].min() > -0.01 * ELEMENT


def test_sphere_pushed_into_a_cube_from_the_side_moves_it():
    """A kinematic probe moved between frames: its velocity comes from its displacement."""
    _mesh, sim = cube(z0=0.0)
    ground, probe = cr.Plane(), cr.Sphere((-0.1, 0, 0.05), 0.03)
    sim.add_obstacle(ground)
    sim.add_obstacle(probe)
    pushes = []
    for frame in range(60):
        probe.move_to((-0.1 + 0.001 * frame, 0, 0.05))
        sim.step()
        assert probe.distance(sim.positions)[0].min() > -0.01 * ELEMENT
        pushes.append(sim.contact_force(probe))
    pushes = np.array(pushes)
    # The probe reaches the cube's face (x = -0.05) at frame 20 and pushes it in +x (the
    # frictionless cube then glides ahead of it) ...
    assert np.all(pushes[:19] == 0)
    assert pushes[:, 0].max() > 1.0
    assert np.all(pushes[:, 0] >= 0)
    # ... by more than 5 mm, and the body pushes back on the probe with the opposite force.
    assert sim.positions[:, 0].min() > -0.05 + 0.005


@pytest.mark.parametrize("element", ["tet10", "hex20"])
def test_quadratic_cells_land_with_their_mid_edge_nodes(element):
    """The surface's mid-edge nodes are contact nodes too: a quadratic cube dropped on the
    floor rests with every node above it (to 1 % of an element) and the weight carried."""
    mesh = cr.box((CUBE, CUBE, CUBE), (2, 2, 2), element=element, origin=(-CUBE / 2, -CUBE / 2, 0.02))
    sim = cr.Simulation(cr.Body(mesh, cr.Material(E=1e5, nu=0.3, density=1000.0)), gravity=(0.0, 0.0, -9.81))
    floor = cr.Plane()
    sim.add_obstacle(floor)
    surface = np.unique(mesh.boundary_faces())
    assert len(sim.contact_nodes) > len(surface)  # the corners and the mid-edge nodes
    deepest = 0.0
    for _ in range(200):
        sim.step()
        deepest = min(deepest, sim.positions[:, 2].min())
    assert deepest > -0.01 * CUBE / 2
    np.testing.assert_allclose(sim.contact_force(floor), [0, 0, 9.81], atol=1e-4)
