"""The Newton variant of the implicit Euler step (integrator="newton")."""

import numpy as np
import pytest

import corotate as cr

MAT = cr.Material(E=1e6, nu=0.3, density=1000.0)


def cantilever(model="corotational", cells=(8, 2, 2), element="tet4"):
    # Tets: their co-rotated force is the exact gradient of the co-rotated energy (the rotation
    # terms vanish for the polar rotation of an isotropic element), so the line search on the
    # incremental potential is consistent with the gradient it drives to zero.
    mesh = cr.beam(4.0, 0.5, 0.5, cells=cells, element=element)
    return mesh, cr.Body(mesh, MAT, model=model)


def run(body, mesh, steps, **kw):
    sim = cr.Simulation(body, gravity=(0, 0, -9.81), **kw)
    sim.fix(mesh.nodes_on_plane("x", 0.0))
    sim.step(steps)
    return sim


def test_linear_model_newton_equals_the_linearised_step():
    # For linear FEM backward Euler is a linear system: Newton must reproduce the one-solve
    # step exactly, in a single iteration.
    mesh, body = cantilever("linear")
    a = run(body, mesh, 20, dt=0.01, solver=cr.Direct())
    b = run(body, mesh, 20, dt=0.01, integrator="newton")
    np.testing.assert_allclose(b.positions, a.positions, rtol=0, atol=1e-9)
    assert b.stats["newton_iterations"] == 1


def test_newton_converges_and_stays_close_to_the_linearised_step_for_small_steps():
    mesh, body = cantilever()
    sim = run(body, mesh, 30, dt=0.005, integrator="newton", newton_tolerance=1e-8)
    res = sim.stats["newton_residuals"]
    assert res[-1] <= 1e-8 and len(res) >= 2
    ref = run(body, mesh, 30, dt=0.005, solver=cr.Direct())
    tip = mesh.nodes_on_plane("x", 4.0)
    sag = ref.displacements[tip, 2].mean()
    assert sag < -0.05
    # Same scheme up to the linearisation error, O(dt^2) per step: well under 1 %.
    assert abs(sim.displacements[tip, 2].mean() - sag) < 0.01 * abs(sag)


def test_backward_euler_by_newton_never_gains_energy():
    # Free vibration (no gravity, no damping) from a bent shape: the converged backward Euler
    # step dissipates, so elastic + kinetic energy must not grow, even with large steps.
    mesh, body = cantilever()
    sim = cr.Simulation(body, dt=0.05, integrator="newton", newton_tolerance=1e-8)
    sim.fix(mesh.nodes_on_plane("x", 0.0))
    x = mesh.points
    sim.positions[:, 2] += 0.5 * (x[:, 0] / 4.0) ** 2  # bent upwards by 0.5 m at the tip
    energies = []
    for _ in range(40):
        energies.append(sim.energy + sim.kinetic_energy)
        sim.step(1)
    energies = np.array(energies)
    assert energies[0] > 0
    assert np.all(np.diff(energies) <= 1e-9 * energies[0]), np.diff(energies).max()
    assert energies[-1] < 0.9 * energies[0]  # and it does dissipate at this step size


def test_newton_failure_reports_residuals_and_restores_state():
    mesh, body = cantilever()
    sim = cr.Simulation(
        body, dt=0.05, gravity=(0, 0, -9.81), integrator="newton", newton_iterations=1, newton_tolerance=1e-14
    )
    sim.fix(mesh.nodes_on_plane("x", 0.0))
    before = sim.positions.copy()
    with pytest.raises(RuntimeError, match="Newton step did not converge in 1 iterations; relative gradient norms"):
        sim.step(3)
    np.testing.assert_array_equal(sim.positions, before)
    assert sim.time == 0.0


def test_newton_settings_are_checked():
    _mesh, body = cantilever()
    with pytest.raises(ValueError, match="Rayleigh beta"):
        cr.Simulation(body, integrator="newton", rayleigh=(0.0, 0.01))
    with pytest.raises(ValueError, match="newton_iterations must be at least 1"):
        cr.Simulation(body, integrator="newton", newton_iterations=0)
    with pytest.raises(ValueError, match="unknown integrator"):
        cr.Simulation(body, integrator="verlet")


def test_newton_steps_of_corotated_hexes_converge_quadratically_at_large_rotation():
    # A slender Hex8 cantilever (L/h = 20) swinging down under gravity in large steps (tip
    # below -3 m on a 4 m beam). Co-rotated hexes have no potential for their force, so the
    # step solves with their exact non-symmetric tangent (sparse LU) and line-searches on
    # |gradient|^2. Measured: 3 to 5 iterations per step; with the R K R^T tangent the same
    # steps took up to 25 iterations, and with the line search on Phi they stalled near 3e-5.
    mesh = cr.beam(4.0, 0.2, 0.2, cells=(20, 1, 1), element="hex8")
    body = cr.Body(mesh, MAT, model="corotational")
    sim = cr.Simulation(body, dt=0.05, gravity=(0, 0, -9.81), integrator="newton", newton_tolerance=1e-9)
    sim.fix(mesh.nodes_on_plane("x", 0.0))
    tip = mesh.nodes_on_plane("x", 4.0)
    lowest = 0.0
    for _ in range(20):
        sim.step()
        res = sim.stats["newton_residuals"]
        assert len(res) <= 6, res
        assert res[-1] <= 1e-9, res
        a, b = [r for r in res if r > 1e-11][-2:]  # the last step above round-off
        assert b <= 100 * a * a, res
        lowest = min(lowest, sim.positions[tip, 2].mean())
    assert lowest < -3.0


@pytest.mark.parametrize("mass", ["consistent", "lumped"])
def test_a_hub_turned_from_rest_converges_from_its_first_round_off_sized_step(mass):
    # The spin-up beam's hub starts as t^4: the first step turns a 10 m beam by 1e-13 m,
    # where the elastic forces' round-off is half the gradient, and with a lumped mass the free
    # DOFs have no load, momentum or stress to scale a tolerance by. Newton stops once its
    # increment is below what the positions resolve; the turning root's pull sets the scale.
    side, length, E, rho = 0.2, 10.0, 1e11, 1000.0
    mesh = cr.box((length, side, side), cells=(10, 1, 1), element="hex20", origin=(0.0, -side / 2, -side / 2))
    sim = cr.Simulation(
        cr.Body(mesh, cr.Material(E=E, nu=0.0, density=rho), model="stvk"), dt=2e-3, integrator="newton", mass=mass
    )
    root, tip = mesh.nodes_on_plane("x", 0.0), mesh.nodes_on_plane("x", length)
    sim.fix(root)

    def turned(points, angle):
        c, s = np.cos(angle), np.sin(angle)
        return points @ np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]).T

    for k in range(1, 251):
        target = turned(mesh.points[root], 0.5 * (k * sim.dt) ** 4)
        sim.velocities[root] = (target - sim.positions[root]) / sim.dt
        sim.step()
        sim.positions[root] = target
    # At 0.5 s the hub accelerates at 6 t^2 = 1.5 rad/s^2, slowly against the beam's first
    # frequency (20 rad/s): the beam lags quasi-statically under the load rho A alpha x,
    # linear along it, whose tip deflection is 11 q(L) L^4 / (120 EI).
    lag = turned(sim.positions[tip].mean(axis=0), -0.5 * sim.time**4)[1]
    q_tip = rho * side**2 * 6 * sim.time**2 * length
    expected = -11 * q_tip * length**4 / (120 * E * side**4 / 12)
    assert lag == pytest.approx(expected, rel=0.05)
