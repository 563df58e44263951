"""The contact potentials' forces and Hessians against finite differences of their energy
(normal augmented Lagrangian and the smoothed friction, sticking and sliding), and the
multiplier update that brings a resting contact's gap to zero."""

import numpy as np
import pytest
from conftest import cube

import corotate as cr


def contact_scene(friction, tilt_deg=0.0):
    """A cube resting on a tilted plane after a few steps: contacts with carried force."""
    tilt = np.deg2rad(tilt_deg)
    _mesh, sim = cube(z0=0.0)
    sim.gravity = 9.81 * np.array([np.sin(tilt), 0.0, -np.cos(tilt)])
    sim.add_obstacle(cr.Plane(), friction=friction)
    sim.step(50)
    return sim


@pytest.mark.parametrize("friction, tilt, shift", [(0.0, 0.0, 0.0), (0.5, 10.0, 0.0), (0.5, 10.0, 3e-4)])
def test_forces_and_hessians_are_the_energy_derivatives(friction, tilt, shift):
    """shift moves every node along the plane: 0 probes the sticking regime, 3e-4 m sliding."""
    sim = contact_scene(friction, tilt)
    rng = np.random.default_rng(0)
    y = sim.positions.copy()
    y[:, 0] += shift
    y += 1e-6 * rng.normal(size=y.shape)
    energy, forces, hessians = sim._sim.contact_potential(y)
    nodes = sim.contacts["nodes"]
    assert len(nodes) == 25 and energy > 0
    h = 1e-8
    for k in range(0, len(nodes), 4):
        for axis in range(3):
            plus, minus = y.copy(), y.copy()
            plus[nodes[k], axis] += h
            minus[nodes[k], axis] -= h
            e_plus, f_plus, _ = sim._sim.contact_potential(plus)
            e_minus, f_minus, _ = sim._sim.contact_potential(minus)
            # force = -dE/dy; Hessian column = -d force / dy
            assert forces[k, axis] == pytest.approx(-(e_plus - e_minus) / (2 * h), rel=1e-5, abs=1e-9)
            column = -(f_plus[k] - f_minus[k]) / (2 * h)
            np.testing.assert_allclose(
                hessians[3 * k : 3 * k + 3, axis], column, rtol=1e-5, atol=1e-6 * np.abs(hessians).max()
            )
    # The Hessians are symmetric and positive semi-definite (the step's system stays SPD).
    blocks = hessians.reshape(-1, 3, 3)
    np.testing.assert_allclose(blocks, blocks.transpose(0, 2, 1), atol=1e-9 * np.abs(blocks).max())
    assert np.linalg.eigvalsh(blocks).min() > -1e-9 * np.abs(blocks).max()


def test_sliding_friction_is_mu_times_the_normal_force():
    sim = contact_scene(0.5, 10.0)
    y = sim.positions.copy()
    y[:, 0] += 1e-2  # far past the sticking width: every node slides in +x
    _, forces, _ = sim._sim.contact_potential(y)
    c = sim.contacts
    tangential = np.linalg.norm(forces[:, :2], axis=1)
    # mu times the normal force carried into the step (which the tilted cube still shifts by
    # 0.1 % per step between its nodes as it settles)
    np.testing.assert_allclose(c["friction_limits"], 0.5 * c["multipliers"], rtol=3e-3)
    np.testing.assert_allclose(tangential, c["friction_limits"], rtol=1e-12)
    assert np.all(forces[:, 0] < -0.99 * tangential)  # against the slip


def test_the_multiplier_closes_a_resting_contact_gap():
    """Without the carried multiplier the penalty would leave the weight / k of penetration."""
    sim = contact_scene(0.0)
    c = sim.contacts
    np.testing.assert_allclose(c["multipliers"].sum(), 9.81, rtol=1e-6)
    gaps = (sim.positions[c["nodes"]] - c["points"]) @ np.array([0, 0, 1.0])
    assert np.abs(gaps).max() < 1e-10
