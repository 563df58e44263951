"""Force feedback at a tool (paper 2.2.3): forces equal the full model's internal forces at the
tool nodes, the stiffness is their derivative, and under uniaxial stretch each method gives its
closed form: the averaged stiffness (eq. 5) St. Venant-Kirchhoff's A0 E l (l^2 - 1) / 2, the
co-rotational one the linear E A0 (l - 1)."""

from __future__ import annotations

import numpy as np
import pytest

import corotate as cr
import corotate._core as _core
from corotate.mesh import SOLID_ELEMENTS

MAT = cr.Material(E=1e6, nu=0.3, density=1000.0)
BODY_MODEL = {"linear": "linear", "corotational": "corotational", "averaged": "stvk"}


def rotation(axis, angle):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


def deformed(points, seed):
    rng = np.random.default_rng(seed)
    return (points + 0.05 * rng.standard_normal(points.shape)) @ rotation((1, 2, 3), 0.9).T + 0.3


@pytest.mark.parametrize("element", SOLID_ELEMENTS)
@pytest.mark.parametrize("method", ["linear", "corotational", "averaged"])
def test_forces_are_the_full_models_forces_at_the_tool(element, method):
    mesh = cr.beam(2.0, 1.0, 1.0, cells=(4, 2, 2), element=element)
    tool = mesh.nodes_on_plane("x", 2.0)
    fb = cr.HapticFeedback(cr.Body(mesh, MAT), tool, method=method)
    x = deformed(mesh.points, 0)
    forces, _ = fb.query(x)
    full = cr.Body(mesh, MAT, model=BODY_MODEL[method]).internal_forces(x)[tool]
    np.testing.assert_allclose(forces, full, rtol=0, atol=1e-10 * np.abs(full).max())
    assert fb.num_elements < len(mesh.cells)  # only the elements around the tool


@pytest.mark.parametrize("element", ["tet4", "hex8"])
@pytest.mark.parametrize("method", ["linear", "corotational", "averaged"])
def test_stiffness_is_the_derivative_of_the_tool_forces(element, method):
    mesh = cr.beam(2.0, 1.0, 1.0, cells=(4, 2, 2), element=element)
    tool = mesh.nodes_on_plane("x", 2.0)
    fb = cr.HapticFeedback(cr.Body(mesh, MAT), tool, method=method)
    x = deformed(mesh.points, 1)
    _, K = fb.query(x)
    h = 1e-6
    K_fd = np.zeros_like(K)
    for a, node in enumerate(tool):
        for axis in range(3):
            xp, xm = x.copy(), x.copy()
            xp[node, axis] += h
            xm[node, axis] -= h
            K_fd[:, 3 * a + axis] = (fb.query(xp)[0] - fb.query(xm)[0]).ravel() / (2 * h)
    assert np.linalg.norm(K - K_fd) <= 1e-6 * np.linalg.norm(K_fd)


def test_uniaxial_stretch_closed_forms():
    """A bar stretched homogeneously by l along x with free lateral contraction m. Each method
    at its own equilibrium contraction: linear elasticity has m = 1 - nu (l - 1) and the end
    force E A0 (l - 1); StVK has E22 = -nu E11 (S22 = 0), m = sqrt(1 - nu (l^2 - 1)), and the
    end force A0 l S11 = A0 E l (l^2 - 1) / 2. The co-rotational force equals the linear one
    (no rotation: R = I, linear in the element frame); the averaged stiffness is StVK's secant
    form, so it gives StVK's force, while the co-rotational one misses the stiffening."""
    L, A0, E, nu = 2.0, 1.0, MAT.E, MAT.nu
    mesh = cr.beam(L, 1.0, 1.0, cells=(4, 2, 2), element="tet4")
    tool = mesh.nodes_on_plane("x", L)
    body = cr.Body(mesh, MAT)
    averaged = cr.HapticFeedback(body, tool, "averaged")
    corotational = cr.HapticFeedback(body, tool, "corotational")
    for stretch in (1.1, 1.5, 2.0):
        m_stvk = np.sqrt(1 - nu * (stretch**2 - 1))
        m_lin = 1 - nu * (stretch - 1)
        f_avg = -averaged.total_force(mesh.points * [stretch, m_stvk, m_stvk])[0]
        f_cor = -corotational.total_force(mesh.points * [stretch, m_lin, m_lin])[0]
        assert f_avg == pytest.approx(A0 * E * stretch * (stretch**2 - 1) / 2, rel=1e-2)
        assert f_cor == pytest.approx(E * A0 * (stretch - 1), rel=1e-9)
    # and at the same configuration, the co-rotational feedback is the linear one
    x = mesh.points * [1.5, 0.85, 0.85]
    linear = cr.HapticFeedback(body, tool, "linear")
    np.testing.assert_allclose(corotational.query(x)[0], linear.query(x)[0], rtol=1e-9, atol=1e-9)


def test_bad_input():
    mesh = cr.beam(2.0, 1.0, 1.0, cells=(2, 1, 1), element="tet4")
    body = cr.Body(mesh, MAT)
    with pytest.raises(ValueError, match="unknown feedback method 'secant'"):
        cr.HapticFeedback(body, [0], method="secant")
    with pytest.raises(ValueError, match="tool node 999 is out of range"):
        cr.HapticFeedback(body, [999])
    with pytest.raises(ValueError, match="listed twice"):
        cr.HapticFeedback(body, [1, 1])
    with pytest.raises(ValueError, match="at least one node"):
        cr.HapticFeedback(body, [])
    fb = cr.HapticFeedback(body, [0])
    x = mesh.points.copy()
    with pytest.raises(ValueError, match="positions must have shape"):
        fb.query(x[:-1])
    x[0, 0] = np.nan
    with pytest.raises(ValueError, match="not finite"):
        fb.query(x)
    assert _core.feedback_method_names() == ["linear", "corotational", "averaged"]


def test_reaction_forces_balance_momentum_in_dynamics():
    """A cantilever swinging under gravity, stepped by Newton (so M a = f_int + f_ext holds on
    the free DOFs at the end of each step): the forces the body exerts on its clamped nodes
    add up to the body's weight minus the rate of change of its momentum,
        sum over clamped (f_int + M g - M a) = sum over all (M g - M a),
    because the internal forces sum to zero; and they come from the clamp's elements only."""
    mesh = cr.beam(2.0, 0.4, 0.4, cells=(8, 2, 2), element="tet4")
    body = cr.Body(mesh, MAT)
    sim = cr.Simulation(body, dt=0.02, gravity=(0, 0, -9.81), integrator="newton", newton_tolerance=1e-10)
    clamp = mesh.nodes_on_plane("x", 0.0)
    sim.fix(clamp)
    fb = cr.HapticFeedback(body, clamp, "corotational")
    M = sim.mass_matrix()
    for _ in range(5):
        sim.step()
        reaction = fb.reaction_forces(sim).sum(axis=0)
        momentum_rate = (M @ sim.accelerations.ravel()).reshape(-1, 3).sum(axis=0)
        expected = sim.gravity_forces.sum(axis=0) - momentum_rate
        np.testing.assert_allclose(reaction, expected, rtol=0, atol=1e-6 * np.abs(sim.gravity_forces).sum())
        assert np.abs(momentum_rate).max() > 1e-2 * np.abs(expected).max()  # truly dynamic
    with pytest.raises(ValueError, match="simulation of this feedback's body"):
        fb.reaction_forces(cr.Simulation(cr.Body(mesh, MAT)))
