"""The embedded surface touches the world: a coarse cage whose render skin sticks out 1 cm
below it lands on the skin (the cage floats 1 cm up), where with the cage's nodes the skin
sinks 1 cm into the floor; for every cell type and both integrators. The point potentials
match finite differences, a tool pressing the skin feels the force the skin exerts, and bad
input leaves the simulation as it was."""

import numpy as np
import pytest
from conftest import check_contact_derivatives

import corotate as cr

CAGE = 0.1  # [m] a cube of 2 x 2 x 2 cells...
ELEMENT = CAGE / 2
OVERHANG = 0.01  # ...inside a skin (a 6 x 6 x 6 box surface) 1 cm larger on every side
GRAVITY = (0.0, 0.0, -9.81)


def caged(element="hex8", bottom=0.02, **settings):
    """The cage with its skin's bottom at height `bottom`; a 1 kg soft cube."""
    cage = cr.box((CAGE, CAGE, CAGE), (2, 2, 2), element=element, origin=(-CAGE / 2, -CAGE / 2, bottom + OVERHANG))
    size = CAGE + 2 * OVERHANG
    skin = cr.boundary_surface(cr.box((size, size, size), (6, 6, 6), origin=(-size / 2, -size / 2, bottom)))
    body = cr.Body(cage, cr.Material(E=1e5, nu=0.3, density=1000.0))
    surface = cr.EmbeddedSurface(body, skin.points, skin.cells)
    return cage, surface, cr.Simulation(body, **settings)


@pytest.mark.parametrize(
    "element, integrator",
    [(e, "linearized") for e in ("tet4", "hex8", "hex20", "tet10")] + [("hex8", "newton")],
)
def test_the_skin_not_the_cage_lands_on_the_floor(element, integrator):
    """Dropped 2 cm: the skin's bottom comes to rest on the floor (never deeper than 1 % of an
    element below it), the cage 1 cm above it, and the floor carries the weight."""
    cage, surface, sim = caged(element, gravity=GRAVITY, integrator=integrator)
    sim.set_contact_surface(surface)
    assert sim.contact_surface is surface
    floor = cr.Plane()
    sim.add_obstacle(floor, friction=0.5)
    deepest = 0.0
    for _ in range(150):
        sim.step()
        surface.update(sim)
        deepest = max(deepest, -surface.positions[:, 2].min())
    assert deepest < 0.01 * ELEMENT
    bottom = surface.mesh.points[:, 2] < surface.mesh.points[:, 2].min() + 1e-9
    np.testing.assert_allclose(surface.positions[bottom, 2], 0.0, atol=1e-3 * ELEMENT)
    # The cage's bottom, 1 cm above the skin's, less its sag under the weight.
    cage_bottom = sim.positions[np.isclose(cage.points[:, 2], cage.points[:, 2].min()), 2]
    assert np.all(np.abs(cage_bottom - OVERHANG) < 0.05 * OVERHANG)
    weight = 9.81 * sim.mass_matrix().sum() / 3
    np.testing.assert_allclose(sim.contact_force(floor), [0, 0, weight], atol=1e-3 * weight)
    assert np.abs(sim.velocities).max() < 1e-3
    assert (sim.contacts["nodes"] < surface.n_vertices).all() and len(sim.contacts["nodes"]) >= 49


def test_with_the_cage_s_nodes_the_skin_sinks_into_the_floor():
    """The same drop on the cage's surface nodes (the default): the skin ends 1 cm deep."""
    _, surface, sim = caged(gravity=GRAVITY)
    sim.add_obstacle(cr.Plane(), friction=0.5)
    sim.step(100)
    surface.update(sim)
    assert surface.positions[:, 2].min() < -0.9 * OVERHANG


def test_point_potentials_match_finite_differences():
    """Energy, forces spread over the element's nodes by the point's weights, and the
    Hessian over their pairs, sticking and sliding (gravity tilted: the skin slides)."""
    _, surface, sim = caged(gravity=(1.0, 0.5, -9.81))
    sim.set_contact_surface(surface)
    sim.add_obstacle(cr.Plane(), friction=0.5)
    sim.step(30)
    assert len(sim.contacts["nodes"]) > 20
    rng = np.random.default_rng(1)
    for scale, h in ((1e-7, 1e-9), (1e-3, 1e-8)):
        y = sim.positions + scale * rng.normal(size=sim.positions.shape)
        check_contact_derivatives(sim, y, rng.normal(size=y.shape), h)


def test_a_tool_pressing_the_skin_feels_what_the_skin_exerts():
    """A probe lowered 5 mm into the skin's top (above the cage): the feedback force is the
    contact force on the tool, and the skin pushes it up."""
    _, surface, sim = caged(bottom=0.0)
    sim.fix(np.flatnonzero(np.isclose(sim.body.mesh.points[:, 2], OVERHANG)))  # the cage's bottom held
    sim.set_contact_surface(surface)
    top = OVERHANG + CAGE + OVERHANG
    probe = cr.Sphere(center=(0.0, 0.0, top + 0.02), radius=0.02)
    sim.add_obstacle(probe)
    feedback = cr.ToolFeedback(sim, probe)
    for frame in range(1, 11):
        probe.move_to((0.0, 0.0, top + 0.02 - 0.0005 * frame))
        sim.step()
        feedback.update()
    sim.step(20)
    feedback.update()
    force, _ = feedback.query(probe.position)
    np.testing.assert_allclose(force, -sim.contact_force(probe), atol=1e-9 * np.abs(force).max())
    assert force[2] > 1.0


def test_contact_surface_bad_input():
    _, surface, sim = caged(bottom=0.0, gravity=GRAVITY)
    floor = cr.Plane((0, 0, 0.005), (0, 0, 1))  # 5 mm above the skin's bottom, below the cage
    sim.add_obstacle(floor)
    with pytest.raises(ValueError, match="contact points start inside the plane"):
        sim.set_contact_surface(surface)
    assert sim.contact_surface is None and not sim._sim.contact_points_set  # nothing changed
    sim.step()  # on the cage's nodes, as before
    with pytest.raises(TypeError, match="EmbeddedSurface"):
        sim.set_contact_surface(surface.mesh)
    _, other, _ = caged(element="hex20")
    with pytest.raises(ValueError, match="embedded in a body of"):
        sim.set_contact_surface(other)
    sim.remove_obstacle(floor)
    sim.set_contact_surface(surface)
    with pytest.raises(ValueError, match="contact between parts needs the surface nodes"):
        sim.set_part_contact(self_contact=True)
    assert sim.contact_surface is surface
    sim.contact_nodes = [0, 1]  # back to nodes
    assert sim.contact_surface is None and not sim._sim.contact_points_set


def test_skin_does_not_tunnel_through_a_thin_slab_at_10_m_per_s():
    """Every skin vertex crosses 10 cm in a step, 50 times the slab's thickness: none passes
    (the detection skips only the elements no obstacle can reach within the step)."""
    _, surface, sim = caged(bottom=0.02, solver=cr.PCG(max_iterations=200, tolerance=1e-8))
    sim.set_contact_surface(surface)
    sim.velocities[:] = (0.0, 0.0, -10.0)
    slab = cr.Box((0, 0, -0.001), (1.0, 1.0, 0.002))
    sim.add_obstacle(slab)
    for _ in range(50):
        sim.step()
        surface.update(sim)
        assert surface.positions[:, 2].min() > -0.001  # never through its middle
    assert sim.velocities[:, 2].max() > -1e-2  # stopped on top
    assert surface.positions[:, 2].min() > -0.01 * ELEMENT
