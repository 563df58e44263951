"""First bending frequency of a cantilever: free vibration vs beam theory.

Beam L = 10, square section 1 x 1 (L/h = 10), nu = 0, clamped at x = 0, coarse hex20
mesh (10 x 1 x 1 cells), consistent mass.

Euler-Bernoulli: f1 = (1.8751^2 / 2 pi) sqrt(E I / (rho A L^4)) = 0.16154 Hz.
At L/h = 10 shear and rotary inertia lower it by 0.65% (Timoshenko beam with Cowper's
kappa = 5/6 for nu = 0: 0.16049 Hz, computed in cantilever_support by shooting); at
L/h = 20 the correction would be 0.16%. The FE results are compared with both.

Time domain: the beam is bent by a small static tip load, released, and stepped with the
library's linearised backward Euler at 200 steps per period. Backward Euler damps
(amplitude x ~0.74 after three periods here) and, for a single mode of angular frequency
w, rotates the phase by atan(w dt) per step instead of w dt: the period is long by
(w dt)^2 / 3 = 0.033% at 200 steps per period. The measured w_num is corrected exactly
by w = tan(w_num dt) / dt. The higher modes are damped far faster (w dt is 6x larger
for the second mode), so after the first half period the tip moves in the first mode.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse.linalg as sla
from cantilever_support import BETA1, timoshenko_first_frequency, tip_face_weights

import corotate as cr

E, NU, RHO = 1.0e7, 0.0, 1000.0
L, B, H = 10.0, 1.0, 1.0
CELLS = (10, 1, 1)
A = B * H
I = B * H**3 / 12.0
F_EB = BETA1**2 / (2 * np.pi) * np.sqrt(E * I / (RHO * A * L**4))
STEPS_PER_PERIOD = 200
PERIODS = 3


@pytest.fixture(scope="module")
def f_timoshenko():
    f = timoshenko_first_frequency(E, NU, RHO, L, B, H, F_EB)
    assert f / F_EB - 1 == pytest.approx(-0.0065, abs=0.0005)  # the correction quoted above
    return f


def _body(model):
    mesh = cr.beam(L, B, H, cells=CELLS, element="hex20")
    return mesh, cr.Body(mesh, cr.Material(E=E, nu=NU, density=RHO), model=model)


def _time_domain_frequency(model):
    mesh, body = _body(model)
    dt = 1.0 / (F_EB * STEPS_PER_PERIOD)
    sim = cr.Simulation(body, dt=dt, solver=cr.Direct(), mass="consistent")
    sim.fix(mesh.nodes_on_plane("x", 0.0))
    tip, w = tip_face_weights(mesh, L)
    # Static tip deflection of ~L/1000: small amplitude, so linear and co-rotational agree.
    P = 1e-3 * L * 3 * E * I / L**3
    sim.external_forces[tip, 2] = -P * w
    sim.solve_static(load_steps=1, tolerance=1e-8, max_iterations=20)
    z = [float(w @ sim.displacements[tip, 2])]
    assert z[0] == pytest.approx(-1e-3 * L, rel=0.01)
    sim.external_forces[:] = 0.0  # release
    for _ in range(PERIODS * STEPS_PER_PERIOD + 10):
        sim.step(1)
        z.append(float(w @ sim.displacements[tip, 2]))
    z = np.array(z)
    t = dt * np.arange(z.size)
    # Zero crossings of the tip deflection, linearly interpolated.
    i = np.flatnonzero(np.sign(z[:-1]) != np.sign(z[1:]))
    crossings = t[i] - z[i] * dt / (z[i + 1] - z[i])
    assert len(crossings) >= 2 * PERIODS - 1
    # Skip the first crossing (higher modes still present), average the rest.
    half_periods = np.diff(crossings[1:])
    assert np.ptp(half_periods) < 0.01 * half_periods.mean()  # a clean single mode
    omega_num = np.pi / half_periods.mean()
    omega = np.tan(omega_num * dt) / dt  # undo backward Euler's phase error
    # Backward Euler's numerical damping of this mode: |z| shrinks by (1 + (w dt)^2)^(-1/2)
    # per step. Compare successive half-wave peaks (after the first crossing).
    peaks = np.array([np.abs(z[a + 1 : b + 1]).max() for a, b in zip(i[1:-1], i[2:])])
    expected = (1 + (omega * dt) ** 2) ** (-0.25 * STEPS_PER_PERIOD)
    np.testing.assert_allclose(peaks[1:] / peaks[:-1], expected, rtol=2e-3)
    return omega / (2 * np.pi)


def _eigen_frequencies(k=4):
    mesh, body = _body("linear")
    fixed = mesh.nodes_on_plane("x", 0.0)
    fixed_dofs = (3 * fixed[:, None] + np.arange(3)).ravel()
    free = np.setdiff1d(np.arange(3 * mesh.n_nodes), fixed_dofs)
    K = body.stiffness_matrix()[free][:, free].tocsc()
    M = body.mass_matrix(lumped=False)[free][:, free].tocsc()
    lam = sla.eigsh(K, k=k, M=M, sigma=0.0, which="LM", return_eigenvectors=False)
    return np.sqrt(np.sort(lam)) / (2 * np.pi)


@pytest.mark.parametrize("model", ["linear", "corotational"])
def test_free_vibration_frequency_matches_beam_theory(model, f_timoshenko):
    f = _time_domain_frequency(model)
    # Measured: 0.16066 Hz (both models): +0.11% vs Timoshenko, -0.55% vs Euler-Bernoulli.
    assert f == pytest.approx(F_EB, rel=0.03)
    assert f == pytest.approx(f_timoshenko, rel=0.005)


def test_eigenproblem_agrees_with_time_domain(f_timoshenko):
    f_eig = _eigen_frequencies()
    # Square section: the y and z bending modes are degenerate.
    assert f_eig[1] == pytest.approx(f_eig[0], rel=1e-8)
    # Measured: 0.16064 Hz, +0.094% vs Timoshenko.
    assert f_eig[0] == pytest.approx(f_timoshenko, rel=0.003)
    assert f_eig[0] > f_timoshenko  # a displacement FE model is stiff: upper bound
    f_td = _time_domain_frequency("corotational")
    # Measured difference 0.015%; 1% required.
    assert f_td == pytest.approx(f_eig[0], rel=0.002)
