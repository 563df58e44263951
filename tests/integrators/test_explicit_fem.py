"""Explicit integration of finite-element bodies: the explainer's StVK triangle sheet with
symplectic Euler (seeds/001), stepped by ExplicitSimulation with its lumped mass."""

import numpy as np
import pytest

import corotate as cr

MAT = cr.Material(E=5e4, nu=0.3, density=1000.0)


def sheet(cells=4, thickness=0.01):
    return cr.Body(cr.rectangle((1.0, 1.0), (cells, cells)), MAT, model="stvk", thickness=thickness)


def test_membrane_forces_are_the_explainers_formula():
    # One triangle in the x-y plane: f_1, f_2 = -A t P(F) Dm^-T, f_3 = -f_1 - f_2, with
    # P = F (2 mu E + lambda tr(E) I) and the plane-stress lambda of a thin sheet.
    mesh = cr.Mesh(np.array([[0.0, 0, 0], [1.0, 0.2, 0], [0.3, 0.9, 0]]), np.array([[0, 1, 2]]), "triangle")
    t = 0.01
    body = cr.Body(mesh, MAT, model="stvk", thickness=t)
    x = mesh.points.copy()
    x[:, :2] = x[:, :2] @ np.array([[1.2, 0.1], [-0.05, 0.9]]).T  # an in-plane deformation
    X = mesh.points[:, :2]
    Dm = np.column_stack([X[0] - X[2], X[1] - X[2]])
    Ds = np.column_stack([x[0, :2] - x[2, :2], x[1, :2] - x[2, :2]])
    F = Ds @ np.linalg.inv(Dm)
    E = 0.5 * (F.T @ F - np.eye(2))
    lam, mu = MAT.lame
    lam = 2 * lam * mu / (lam + 2 * mu)  # plane stress
    P = F @ (2 * mu * E + lam * np.trace(E) * np.eye(2))
    A = 0.5 * abs(np.linalg.det(Dm))
    f12 = -A * t * P @ np.linalg.inv(Dm).T
    expected = np.column_stack([f12, -f12.sum(axis=1)]).T
    got = body.internal_forces(x)
    np.testing.assert_allclose(got[:, :2], expected, rtol=1e-12, atol=1e-12 * np.abs(expected).max())
    np.testing.assert_allclose(got[:, 2], 0.0, atol=1e-12 * np.abs(expected).max())


def test_symplectic_euler_keeps_the_energy_bounded_below_the_stable_step():
    body = sheet()
    probe = cr.ExplicitSimulation(body, integrator="symplectic_euler")
    probe.positions[:, 0] *= 1.1  # released from a 10 % stretch, no gravity, nothing fixed
    probe.positions[:, 1] *= 0.95
    dt = 0.2 * probe.stability()["critical_step"]
    sim = cr.ExplicitSimulation(body, dt=dt, integrator="symplectic_euler", on_unstable="allow")
    sim.positions[:] = probe.positions
    e0 = sim.energy
    assert e0 > 0
    energies = []
    for _ in range(100):
        sim.step(100)  # 10,000 steps in all
        energies.append(sim.energy + sim.kinetic_energy)
    energies = np.array(energies)
    assert np.all(np.isfinite(sim.positions))
    # Symplectic Euler measures x and v half a step apart, so the energy computed from them
    # oscillates with an amplitude of order omega_max dt (here 0.4) of the high modes' share;
    # it must not drift, and the oscillation must stay bounded.
    assert np.abs(energies - e0).max() < 0.06 * e0, np.abs(energies - e0).max() / e0
    assert abs(energies[-10:].mean() - energies[:10].mean()) < 0.005 * e0
    # Momentum: no external force, nothing fixed, so the centre of mass does not move.
    assert np.abs(sim.velocities.mean(axis=0)).max() < 1e-9


def test_a_step_above_the_stable_limit_is_refused_or_caught():
    body = sheet()
    probe = cr.ExplicitSimulation(body, integrator="symplectic_euler")
    dt_crit = probe.stability()["critical_step"]
    sim = cr.ExplicitSimulation(
        body, dt=2 * dt_crit, integrator="symplectic_euler", on_unstable="raise", gravity=(0, 0, -9.81)
    )
    with pytest.raises(ValueError, match="exceeds the stable step"):
        sim.step(1)
    # Taken anyway, it blows up; the failure is reported and the state restored, never NaN.
    sim = cr.ExplicitSimulation(body, dt=2 * dt_crit, integrator="symplectic_euler", on_unstable="allow")
    sim.positions[:, 0] *= 1.05
    before = sim.positions.copy()
    with (
        pytest.raises(RuntimeError, match="non-finite"),
        pytest.warns(cr.SimulationWarning, match="times the critical step"),
    ):
        sim.step(2000)
    np.testing.assert_array_equal(sim.positions, before)
    # And sub-stepping makes the same request safe.
    sim = cr.ExplicitSimulation(body, dt=2 * dt_crit, integrator="symplectic_euler", on_unstable="substep")
    sim.positions[:, 0] *= 1.05
    sim.step(200)
    assert np.all(np.isfinite(sim.positions)) and sim.stats["last_substeps"] >= 3
