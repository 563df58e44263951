"""A cloth hanging from two corners comes to rest in a static equilibrium in which the
spring forces at the two pins carry the weight of the cloth.

A 1 x 1 m cloth of 12 x 12 particles, horizontal at the start, pinned at the two corners
of one edge, falls under gravity and is stepped explicitly (velocity Verlet, frames of
1/60 s sub-stepped at the conservative step) with spring damping (d = beta k) and a
little velocity damping until it is still. At rest the damping forces vanish, so every
free node balances its weight with spring forces, and since spring forces sum to zero the
forces of the springs on the pins add up to the weight of all free particles."""

import numpy as np

import corotate as cr


def test_cloth_hanging_from_two_corners_balances_gravity_at_the_pins():
    g = np.array([0.0, 0.0, -9.81])
    body = cr.MassSpringBody.cloth(
        12, 12, size=(1.0, 1.0), E=2e6, thickness=1e-3, density=200.0, bending=0.01, beta=2e-3
    )
    sim = cr.ExplicitSimulation(body, dt=1 / 60, gravity=g, mass_damping=2.0)
    pins = [body.n_nodes - 12, body.n_nodes - 1]  # the two corners of the edge y = 1
    sim.fix(pins)
    for _ in range(40):  # up to 40 s
        sim.step(60)
        if sim.kinetic_energy < 1e-14:
            break
    free = np.setdiff1d(np.arange(body.n_nodes), pins)
    weight = body.masses[free].sum() * g
    f = sim.internal_forces()
    # Static equilibrium of every free node (residual small against a node's own weight).
    residual = f[free] + body.masses[free, None] * g
    assert np.abs(residual).max() < 1e-4 * body.masses.min() * 9.81
    assert np.abs(sim.damping_forces()).max() < 1e-4 * body.masses.min() * 9.81
    # The springs pull the pins down by exactly the weight of what hangs from them.
    np.testing.assert_allclose(f[pins].sum(axis=0), weight, rtol=1e-6, atol=1e-6 * np.linalg.norm(weight))
    # It hangs: the free edge is far below the pins, symmetric about the cloth's middle.
    assert sim.positions[:, 2].min() < -0.5
    mirror = (np.arange(body.n_nodes) // 12) * 12 + 11 - np.arange(body.n_nodes) % 12
    np.testing.assert_allclose(sim.positions[:, 2], sim.positions[mirror, 2], atol=1e-6)
