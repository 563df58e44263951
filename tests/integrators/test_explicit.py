"""Explicit integration of mass-spring systems: period and energy of one spring, damping
rate of eq. (2), the critical time step against a dense eigen solve, stability at 0.9x
and refusal or detected blow-up at 2x, sub-stepping and the NumPy views."""

import math

import numpy as np
import pytest

import corotate as cr

RNG = np.random.default_rng(11)
K_SPRING, MASS = 400.0, 0.25


def single_spring(damping=0.0, **kw):
    """Node 0 pinned at the origin, node 1 (mass MASS) on a spring of rest length 1 along x,
    released from x = 1.1: x'' = -(k/m) (x - 1) - (d/m) x'."""
    x = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    body = cr.MassSpringBody(x, [[0, 1]], stiffness=K_SPRING, masses=[1.0, MASS], damping=damping)
    sim = cr.ExplicitSimulation(body, **kw)
    sim.fix([0])
    sim.positions[1, 0] = 1.1
    return sim


def trajectory(sim, steps):
    out = np.empty(steps + 1)
    out[0] = sim.positions[1, 0] - 1.0
    for s in range(steps):
        sim.step(1)
        out[s + 1] = sim.positions[1, 0] - 1.0
    return out


def upward_crossings(u, dt):
    i = np.flatnonzero((u[:-1] < 0) & (u[1:] >= 0))
    return (i + u[i] / (u[i] - u[i + 1])) * dt  # linear interpolation


@pytest.mark.parametrize("integrator", ["verlet", "symplectic_euler"])
def test_single_spring_period_and_energy(integrator):
    period = 2 * math.pi * math.sqrt(MASS / K_SPRING)
    dt = period / 60
    sim = single_spring(dt=dt, integrator=integrator, on_unstable="raise")
    e0 = sim.energy + sim.kinetic_energy
    energies = []
    u = np.empty(20 * 60 + 2)
    u[0] = sim.positions[1, 0] - 1.0
    for s in range(1, u.size):
        sim.step(1)
        u[s] = sim.positions[1, 0] - 1.0
        energies.append(sim.energy + sim.kinetic_energy)
    crossings = upward_crossings(u, dt)
    assert crossings.size == 20
    measured = (crossings[-1] - crossings[0]) / (crossings.size - 1)
    assert measured == pytest.approx(period, rel=5e-3)
    # Leapfrog's period error is (w dt)^2 / 24 = 0.046 % here: check it is that small.
    assert abs(measured / period - 1) < 1e-3
    energies = np.array(energies)
    if integrator == "verlet":
        # Symplectic: the energy oscillates by O((w dt)^2) and does not drift.
        assert np.abs(energies / e0 - 1).max() < 3e-3
        first, last = energies[:60].mean(), energies[-60:].mean()
        assert abs(last / first - 1) < 1e-6
    assert sim.positions[0].tolist() == [0.0, 0.0, 0.0]  # the pin did not move


@pytest.mark.parametrize("integrator", ["verlet", "symplectic_euler"])
def test_damped_amplitude_decays_at_the_rate_of_eq2(integrator):
    """x'' + (d/m) x' + (k/m) x = 0: the envelope decays like exp(-d t / (2 m))."""
    d = 0.4  # damping ratio d / (2 sqrt(k m)) = 0.02
    rate = d / (2 * MASS)
    omega_d = math.sqrt(K_SPRING / MASS - rate**2)
    dt = 2 * math.pi / omega_d / 400
    sim = single_spring(damping=d, dt=dt, integrator=integrator)
    u = trajectory(sim, 400 * 8)
    t = np.arange(u.size) * dt
    peaks = np.flatnonzero((u[1:-1] > u[:-2]) & (u[1:-1] >= u[2:])) + 1
    slope = np.polyfit(t[peaks], np.log(u[peaks]), 1)[0]
    assert slope == pytest.approx(-rate, rel=1e-2)


def small_lattice(beta=0.0):
    body = cr.MassSpringBody.lattice((2, 2, 1), size=(1.0, 1.0, 0.5), E=1e5, density=500.0, beta=beta)
    base = np.flatnonzero(np.isclose(body.nodes[:, 2], 0.0))[:4]
    return body, base


def dense_lambda_max(body, x, free_nodes, matrix="stiffness"):
    A = (body.stiffness_matrix(x) if matrix == "stiffness" else body.damping_matrix(x)).toarray()
    free = np.repeat(free_nodes, 3) * 3 + np.tile([0, 1, 2], free_nodes.size)
    s = 1 / np.sqrt(np.repeat(body.masses, 3))[free]
    return np.linalg.eigvalsh(s[:, None] * A[np.ix_(free, free)] * s[None, :]).max()


@pytest.mark.parametrize("deformed", [False, True])
def test_critical_step_estimate_matches_dense_eigenvalue(deformed):
    body, pinned = small_lattice(beta=2e-4)
    sim = cr.ExplicitSimulation(body, policy="online")
    sim.fix(pinned)
    if deformed:
        sim.positions[:] += 0.08 * RNG.standard_normal(sim.positions.shape)
    free = np.setdiff1d(np.arange(body.n_nodes), pinned)
    lam = dense_lambda_max(body, sim.positions, free)
    est = sim.stability("configuration")
    assert est["lambda_max"] == pytest.approx(lam, rel=0.05)
    assert est["stiffness"]["ritz"] <= lam * (1 + 1e-9)  # a Ritz value never exceeds it
    c = dense_lambda_max(body, sim.positions, free, "damping")
    assert est["damping_rate"] == pytest.approx(c, rel=0.05)
    assert est["critical_step"] == pytest.approx((math.sqrt(c * c + 4 * lam) - c) / lam, rel=0.05)
    # The fixed policy's bound is larger (smaller step) in every configuration.
    bound = sim.stability("bound")
    assert bound["lambda_max"] >= lam
    assert bound["critical_step"] <= est["critical_step"]


def perturbed_lattice_sim(dt_factor, **kw):
    body, pinned = small_lattice()
    probe = cr.ExplicitSimulation(body)
    probe.fix(pinned)
    dt = dt_factor * probe.stability("configuration")["critical_step"]
    sim = cr.ExplicitSimulation(body, dt=dt, policy="online", **kw)
    sim.fix(pinned)
    sim.velocities[:] = 1e-3 * RNG.standard_normal(sim.velocities.shape)
    sim.velocities[pinned] = 0.0
    return sim


@pytest.mark.parametrize("integrator", ["verlet", "symplectic_euler"])
def test_run_at_0_9_of_the_critical_step_stays_bounded(integrator):
    sim = perturbed_lattice_sim(0.9, integrator=integrator, on_unstable="raise", safety=1.0)
    e0 = sim.kinetic_energy + sim.energy
    sim.step(10_000)
    assert sim.stats["substeps"] == 10_000  # no sub-stepping was needed
    assert np.isfinite(sim.positions).all()
    assert sim.kinetic_energy + sim.energy < 2.0 * e0
    assert np.abs(sim.displacements).max() < 1e-3


def test_run_at_twice_the_critical_step_is_refused_by_name():
    sim = perturbed_lattice_sim(2.0, on_unstable="raise", safety=1.0)
    x0, v0 = sim.positions.copy(), sim.velocities.copy()
    with pytest.raises(ValueError, match=r"time step dt = \S+ s exceeds the stable step \S+ s .*omega_max"):
        sim.step(10)
    np.testing.assert_array_equal(sim.positions, x0)
    np.testing.assert_array_equal(sim.velocities, v0)
    assert sim.time == 0.0


def test_run_at_twice_the_critical_step_blows_up_detected_never_nan():
    sim = perturbed_lattice_sim(2.0, on_unstable="allow")
    with pytest.warns(cr.SimulationWarning, match=r"2 times the critical step .*'allow' takes it anyway"):
        sim.step(5)  # grows but is finite yet (and says so once)
    x0, v0, t0 = sim.positions.copy(), sim.velocities.copy(), sim.time
    with pytest.raises(RuntimeError, match=r"non-finite positions or velocities.*state was restored"):
        sim.step(10_000)
    assert np.isfinite(sim.positions).all() and np.isfinite(sim.velocities).all()
    np.testing.assert_array_equal(sim.positions, x0)
    np.testing.assert_array_equal(sim.velocities, v0)
    assert sim.time == t0 and sim.stats["steps"] == 5


def test_twice_the_critical_step_is_substepped_and_stable():
    sim = perturbed_lattice_sim(2.0, safety=0.9)
    sim.step(2000)
    assert sim.stats["last_substeps"] == 3  # ceil(2 / 0.9)
    assert np.abs(sim.displacements).max() < 1e-3


def test_frame_substepping_converges_to_the_fine_answer():
    body, pinned = small_lattice()
    finals = []
    for dt in (1 / 60, None):
        sim = cr.ExplicitSimulation(body, dt=dt, gravity=(0, 0, -9.81), mass_damping=2.0)
        sim.fix(pinned)
        if dt is None:
            n = round((1 / 60) / sim.stable_time_step)
            sim.dt = (1 / 60) / n  # the same substep, taken one per call
            sim.step(10 * n)
        else:
            sim.step(10)
            assert sim.stats["last_substeps"] == math.ceil((1 / 60) / sim.stable_time_step)
        finals.append(sim.positions.copy())
    np.testing.assert_allclose(finals[0], finals[1], atol=1e-12)


def test_policies_and_views():
    body, pinned = small_lattice()
    sim = cr.ExplicitSimulation(body, dt=0.01, gravity=(0, 0, -9.81))
    sim.fix(pinned)
    view = sim.positions
    sim.step(3)
    assert sim.stats["estimates"] == 1  # fixed: estimated once
    assert np.shares_memory(view, sim.positions) and view[5, 2] == sim.positions[5, 2]
    assert view[5, 2] < body.nodes[5, 2]  # falling under gravity, seen through the old view
    np.testing.assert_array_equal(sim.positions[pinned], body.nodes[pinned])
    sim.policy = "online"
    sim.step(1)
    assert sim.stats["estimates"] == 2  # online: estimated at the current positions
    # No new estimate while no node has moved 5 % of the shortest rest length ...
    sim.gravity = (0, 0, 0)
    sim.velocities[:] = 0.0
    sim.step(3)
    assert sim.stats["estimates"] == 2
    # ... and a new one as soon as one has.
    shortest = body.rest_lengths.min()
    free = np.setdiff1d(np.arange(len(body.nodes)), pinned)[0]
    sim.positions[free, 0] += 0.06 * shortest
    sim.step(1)
    assert sim.stats["estimates"] == 3
    sim.gravity = (0, 0, -9.81)
    # Loads change between frames and act.
    top = np.flatnonzero(np.isclose(body.nodes[:, 2], 0.5))
    before = sim.positions[top, 2].mean()
    sim.gravity = (0, 0, 0)
    sim.velocities[:] = 0.0
    sim.external_forces[top] = (0.0, 0.0, 500.0)
    sim.step(5)
    assert sim.positions[top, 2].mean() > before


def test_bad_settings_and_state():
    body, _ = small_lattice()
    with pytest.raises(ValueError, match="time step dt must be positive"):
        cr.ExplicitSimulation(body, dt=-0.1)
    with pytest.raises(ValueError, match="unknown integrator 'rk4'"):
        cr.ExplicitSimulation(body, integrator="rk4")
    with pytest.raises(ValueError, match="unknown on_unstable 'ignore'"):
        cr.ExplicitSimulation(body, on_unstable="ignore")
    with pytest.raises(ValueError, match="unknown time-step policy"):
        cr.ExplicitSimulation(body, policy="sometimes")
    with pytest.raises(ValueError, match="safety factor"):
        cr.ExplicitSimulation(body, safety=1.5)
    sim = cr.ExplicitSimulation(body, dt=0.01)
    with pytest.raises(ValueError, match=r"node index 99 is out of range \[0, 18\)"):
        sim.fix([99])
    sim.external_forces[3, 1] = np.nan
    with pytest.raises(ValueError, match="external force of node 3 is not finite"):
        sim.step()
