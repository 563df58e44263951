"""Shared scenes of the contact tests."""

import numpy as np
import pytest

import corotate as cr

CUBE = 0.1  # [m] edge of the test cube
CELLS = 4  # cells per edge: the element size is CUBE / CELLS


def cube(z0: float = 0.0, E: float = 1e5, cells: int = CELLS, **simulation):
    """A soft 0.1 m cube (1 kg) whose bottom face is at height z0, under gravity."""
    mesh = cr.box((CUBE, CUBE, CUBE), (cells, cells, cells), origin=(-CUBE / 2, -CUBE / 2, z0))
    body = cr.Body(mesh, cr.Material(E=E, nu=0.3, density=1000.0))
    return mesh, cr.Simulation(body, gravity=(0.0, 0.0, -9.81), **simulation)


def bottom_nodes(mesh):
    return np.flatnonzero(np.isclose(mesh.points[:, 2], mesh.points[:, 2].min()))


def check_contact_derivatives(sim, y, direction, h, internal=False):
    """The contact potential's forces and Hessian at positions y are its derivatives (central
    differences along `direction`, step h), the Hessian is symmetric positive semi-definite,
    and, for contacts between nodes of the body alone (internal), the forces sum to zero."""
    _, forces, hessian = sim._sim.contact_system(y)
    e_plus, f_plus, _ = sim._sim.contact_system(y + h * direction)
    e_minus, f_minus, _ = sim._sim.contact_system(y - h * direction)
    np.testing.assert_allclose((e_plus - e_minus) / (2 * h), -(forces * direction).sum(), rtol=1e-5, atol=1e-9)
    np.testing.assert_allclose(
        ((f_plus - f_minus) / (2 * h)).reshape(-1), -hessian @ direction.reshape(-1), rtol=1e-4, atol=1e-4
    )
    np.testing.assert_allclose(hessian, hessian.T, atol=1e-9 * np.abs(hessian).max())
    assert np.linalg.eigvalsh(hessian).min() > -1e-9 * np.abs(hessian).max()
    if internal:  # equal and opposite
        np.testing.assert_allclose(forces.sum(axis=0), 0.0, atol=1e-9 * np.abs(forces).max())


def interrupted_step(sim, steps, after):
    """sim.step(steps) interrupted by its progress callback (KeyboardInterrupt) after `after`
    of them: the call fails, and the state (positions, velocities, time) and the contacts are
    what they were before it."""
    x, v, t = sim.positions.copy(), sim.velocities.copy(), sim.time
    before = {k: value.copy() for k, value in sim.contacts.items()}

    def interrupt(done, n):
        if done == after:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        sim.step(steps, progress=interrupt)
    np.testing.assert_array_equal(sim.positions, x)
    np.testing.assert_array_equal(sim.velocities, v)
    assert sim.time == t
    for key, value in sim.contacts.items():
        np.testing.assert_array_equal(value, before[key])
