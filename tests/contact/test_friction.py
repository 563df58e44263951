"""Coulomb friction on an incline: a block sticks below the friction angle and otherwise
slides with acceleration g (sin(theta) - mu cos(theta))."""

import numpy as np
import pytest
from conftest import CUBE

import corotate as cr

G = 9.81


def block_on_incline(theta, mu, integrator):
    """A stiff 0.1 m cube resting on a plane tilted by theta about y, in the plane's frame:
    the incline's coordinates are the world's, gravity tilted instead (the same physics)."""
    mesh = cr.box((CUBE, CUBE, CUBE), (2, 2, 2), origin=(-CUBE / 2, -CUBE / 2, 0.0))
    body = cr.Body(mesh, cr.Material(E=1e7, nu=0.3, density=1000.0))
    gravity = G * np.array([np.sin(theta), 0.0, -np.cos(theta)])  # downhill is +x
    solver = cr.Direct() if integrator == "newton" else cr.PCG()
    sim = cr.Simulation(body, gravity=gravity, integrator=integrator, solver=solver)
    sim.add_obstacle(cr.Plane(), friction=mu)
    return sim


@pytest.mark.parametrize("integrator", ["linearized", "newton"])
def test_a_block_below_the_friction_angle_sticks(integrator):
    theta, mu = np.deg2rad(20), 0.5  # tan(theta) = 0.36 < mu
    sim = block_on_incline(theta, mu, integrator)
    sim.step(100)
    start = sim.positions[:, 0].mean()
    sim.step(100)
    # It creeps at most at the smoothed law's friction_velocity (1 mm/s): one second of it
    # would be 1 mm; sliding would be g (sin - mu cos) t^2 / 2 = 0 here but 0.3 m at mu = 0.3.
    creep = sim.positions[:, 0].mean() - start
    assert abs(creep) < 1e-3 * 1.0
    np.testing.assert_allclose(sim.contact_force(), -sim.gravity_forces.sum(axis=0), rtol=1e-4, atol=1e-6)


@pytest.mark.parametrize("integrator", ["linearized", "newton"])
@pytest.mark.parametrize("mu", [0.0, 0.3])
def test_a_block_above_the_friction_angle_slides_at_the_coulomb_rate(integrator, mu):
    theta = np.deg2rad(30)
    sim = block_on_incline(theta, mu, integrator)
    times, x = [], []
    for _ in range(150):
        sim.step()
        times.append(sim.time)
        x.append(sim.positions[:, 0].mean())
    times, x = np.array(times), np.array(x)
    late = times >= 0.5  # after the landing transient: a parabola's second derivative
    acceleration = 2 * np.polyfit(times[late], x[late], 2)[0]
    expected = G * (np.sin(theta) - mu * np.cos(theta))
    assert abs(acceleration - expected) < 0.02 * expected
    assert abs(sim.positions[:, 2].min()) < 1e-6 * CUBE  # on the plane, not flying
