"""The Newton implicit step with the hyperelastic models: quadratic convergence with the
exact Hessian, and inverting elements under Neo-Hookean without NaN."""

import numpy as np
import pytest

import corotate as cr

MAT = cr.Material(E=1e5, nu=0.3, density=1000.0)


def test_newton_converges_quadratically_with_the_exact_hessian():
    mesh = cr.beam(2.0, 0.4, 0.4, cells=(6, 2, 2), element="hex8")
    for model in ("stvk", "neohookean"):
        body = cr.Body(mesh, MAT, model=model)
        sim = cr.Simulation(
            body, dt=0.02, gravity=(0, 0, -9.81), integrator="newton", newton_tolerance=1e-13, newton_iterations=30
        )
        sim.fix(mesh.nodes_on_plane("x", 0.0))
        sim.step(15)  # well into a large sag, so the step is nonlinear
        res = np.array(sim.stats["newton_residuals"])
        assert res[-1] <= 1e-13
        assert len(res) <= 8, res
        # Quadratic: once below 1e-2, each residual is at most a modest constant times the
        # square of the previous one (a linearly converging method would fail this).
        tail = [(a, b) for a, b in zip(res[:-1], res[1:]) if a < 1e-2 and b > 1e-12]  # above round-off
        assert tail, res
        for a, b in tail:
            assert b <= 50 * a * a, (model, res)


def test_neohookean_step_through_inversion_stays_finite():
    # A cube hit hard enough that elements invert during the step: the stable Neo-Hookean
    # energy is defined for J <= 0 and the PSD-projected Newton step must stay finite.
    mesh = cr.box((1.0, 1.0, 1.0), (3, 3, 3), "tet4")
    body = cr.Body(mesh, cr.Material(E=1e4, nu=0.3, density=1000.0), model="neohookean", project_psd=True)
    # Projected Newton converges linearly once elements invert: allow it the iterations.
    sim = cr.Simulation(body, dt=0.05, integrator="newton", newton_iterations=150, newton_tolerance=1e-6)
    sim.fix(mesh.nodes_on_plane("z", 0.0))
    top = mesh.nodes_on_plane("z", 1.0)
    sim.velocities[top, 2] = -30.0  # 1.5 m of travel in one step for a 1 m cube
    sim.step(1)
    x = sim.positions
    assert np.all(np.isfinite(x)) and np.all(np.isfinite(sim.velocities))
    # The top went through the bottom: elements are inverted (signed volume <= 0).
    d = x[mesh.cells]
    signed = np.einsum("ij,ij->i", np.cross(d[:, 1] - d[:, 0], d[:, 2] - d[:, 0]), d[:, 3] - d[:, 0]) / 6
    assert (signed <= 0).sum() >= 10 and x[:, 2].min() < 0
    with pytest.warns(cr.SimulationWarning, match="inverted or flat elements"):
        sim.step(20)  # and it recovers without NaN, saying that it started inverted
    assert np.all(np.isfinite(sim.positions))
