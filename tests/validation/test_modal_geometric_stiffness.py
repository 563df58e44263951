"""Geometric stiffness in modal space and the reduced StVK polynomial forces.

* A pinned-pinned beam under axial tension T: its first bending frequency is the string-
  beam formula  w^2 = (pi/L)^4 EI/(rho A) + (pi/L)^2 T/(rho A)  (Euler-Bernoulli with a
  tension). The modal model with the load-based geometric stiffness (eqs 7-8) of the unit
  tension load case must give it within 1 %.
* Mode-based K_sigma (eqs 9-10) is the load-based one of the load that produces the mode
  (K phi_i): the same linear stress state. The paper's scaled-mode tangent is something else.
* The reduced StVK forces are the full StVK forces projected on the basis, exactly (the
  energy is a quartic polynomial in the displacement).
"""

from __future__ import annotations

import numpy as np
import pytest
from cantilever_support import tip_face_weights

import corotate as cr
from corotate.modal import ModalBody, craig_bampton
from corotate.modal.geometric_stiffness import (
    load_geometric_stiffness,
    mode_geometric_stiffness,
    scaled_mode_geometric_stiffness,
)
from corotate.modal.reduced_stvk import modal_derivatives, reduced_stvk_tensors

E, NU, RHO = 1.0e7, 0.0, 1000.0
L, B, H = 2.0, 0.1, 0.1


@pytest.fixture(scope="module")
def pinned_beam():
    """Pins: the line z = H/2 of the end faces, held in x, y, z at x = 0 and in y, z at x = L
    (free to rotate about y: bending in z is pinned-pinned)."""
    mesh = cr.beam(L, B, H, cells=(20, 2, 2), element="hex20")
    body = cr.Body(mesh, cr.Material(E=E, nu=NU, density=RHO), model="stvk")
    p = mesh.points
    mid = np.isclose(p[:, 2], H / 2)
    left = np.flatnonzero(mid & np.isclose(p[:, 0], 0.0))
    right = np.flatnonzero(mid & np.isclose(p[:, 0], L))
    fixed_dofs = np.concatenate([3 * right + 1, 3 * right + 2])
    basis = craig_bampton(body, left, n_modes=6, fixed_dofs=fixed_dofs)
    tip, w = tip_face_weights(mesh, L)
    unit_tension = np.zeros((mesh.n_nodes, 3))
    unit_tension[tip, 0] = w
    return mesh, body, basis, unit_tension


def test_tension_raises_the_bending_frequency_as_the_string_beam_formula(pinned_beam):
    _mesh, body, basis, unit_tension = pinned_beam
    A, I = B * H, B * H**3 / 12
    T = 3 * np.pi**2 * E * I / L**2  # three times the Euler load: the string term dominates
    loads, geometric = load_geometric_stiffness(body, basis, unit_tension[None])
    mb = ModalBody(basis)
    mb.set_load_cases(loads, geometric)
    f0 = np.sqrt(np.linalg.eigvalsh(mb.stiffness)[0]) / (2 * np.pi)
    mb.load_amplitudes = [T]
    np.testing.assert_allclose(mb.modal_forces, T * basis.vectors.T @ unit_tension.ravel(), atol=1e-12 * T)
    f = np.sqrt(np.linalg.eigvalsh(mb.stiffness)[0]) / (2 * np.pi)
    bending = (np.pi / L) ** 4 * E * I / (RHO * A)
    string = (np.pi / L) ** 2 * T / (RHO * A)
    f_eb = np.sqrt(bending) / (2 * np.pi)
    f_analytic = np.sqrt(bending + string) / (2 * np.pi)
    assert f0 == pytest.approx(f_eb, rel=0.01)  # measured -0.34 % (shear, rotary inertia)
    assert f == pytest.approx(f_analytic, rel=0.01)  # measured -0.09 %
    assert f / f0 == pytest.approx(2.0, rel=0.01)  # sqrt(1 + 3)


def test_mode_based_equals_load_based_for_the_load_that_makes_the_mode(pinned_beam):
    mesh, body, bending, _ = pinned_beam
    # Bending modes alone have stress antisymmetric through the depth: their K_sigma0 nearly
    # vanishes on bending shapes. Constraint modes of a tip node bring axial stretching in.
    tip = mesh.nearest_node((L, B / 2, H))
    left = np.flatnonzero(np.isin(np.arange(mesh.n_nodes), bending.fixed_dofs // 3) & (mesh.points[:, 0] == 0.0))
    right_dofs = bending.fixed_dofs[mesh.points[bending.fixed_dofs // 3, 0] == L]
    basis = craig_bampton(body, left, n_modes=3, interface_nodes=[tip], fixed_dofs=right_dofs)
    A = mode_geometric_stiffness(body, basis)
    K = body.stiffness_matrix()
    # The loads K phi_i (their reactions on the fixed DOFs do not enter the solve).
    loads = (K @ basis.vectors).T.reshape(basis.size, -1, 3)
    _, geometric = load_geometric_stiffness(body, basis, loads)
    scale = np.abs(A).max()
    np.testing.assert_allclose(np.moveaxis(A, 2, 0), geometric, atol=1e-9 * scale)
    # The paper's scaled-mode alternative (K_T - K_L)(X + s phi) / s is NOT K_sigma0 here: with
    # a StVK tangent it also holds the change of the material tangent with strain, of the same
    # order as the stress term (ABAQUS's hypoelastic tangent keeps the moduli constant). The
    # difference does not shrink with s (measured: 0.5 to 6.4 times the largest entry of a
    # mode's K_sigma0, the same for s = 1e-4 and 1e-5).
    small = scaled_mode_geometric_stiffness(body, basis, amplitude=1e-4)
    smaller = scaled_mode_geometric_stiffness(body, basis, amplitude=1e-5)
    assert np.abs(small - smaller).max() < 0.02 * np.abs(small).max()  # converged in s
    assert np.abs(small - A).max() > 0.5 * scale  # ... to something else


def test_reduced_stvk_forces_are_the_projected_full_forces():
    mesh = cr.beam(1.0, 0.2, 0.2, cells=(4, 1, 1), element="hex20")
    body = cr.Body(mesh, cr.Material(E=1e6, nu=0.3, density=1000.0), model="stvk")
    fixed = mesh.nodes_on_plane("x", 0.0)
    base = craig_bampton(body, fixed, n_modes=3)
    derivs = modal_derivatives(body, base.vectors, base.fixed_dofs, [(0, 0), (0, 1)])
    basis = craig_bampton(body, fixed, n_modes=3, extra_vectors=derivs)
    assert basis.size == 5
    A, Bt = reduced_stvk_tensors(body, basis)
    mb = ModalBody(basis, quadratic=A, cubic=Bt)
    rng = np.random.default_rng(3)
    P = basis.vectors
    for scale in (0.01, 0.1):
        q = scale * rng.normal(size=basis.size) / np.abs(P).max()  # tip displacements ~ scale
        x = mesh.points + (P @ q).reshape(-1, 3)
        f_full = P.T @ body.internal_forces(x).ravel()
        T_full = P.T @ body.tangent_matrix(x) @ P
        np.testing.assert_allclose(mb.internal_forces(q), f_full, atol=1e-8 * np.abs(f_full).max())
        np.testing.assert_allclose(mb.tangent(q), T_full, atol=1e-8 * np.abs(T_full).max())
        assert mb.energy(q) == pytest.approx(body.energy(x), rel=1e-8)
    # Modal derivatives solve K psi = -(dK/du[phi_j]) phi_i with the fixed DOFs held.
    assert np.all(derivs[base.fixed_dofs] == 0.0)


def test_bad_input_is_refused(pinned_beam):
    mesh, body, basis, _unit_tension = pinned_beam
    linear = cr.Body(mesh, body.material, model="linear")
    with pytest.raises(ValueError, match="stvk"):
        mode_geometric_stiffness(linear, basis)
    with pytest.raises(ValueError, match="loads"):
        load_geometric_stiffness(body, basis, np.zeros((1, 3, 3)))
    with pytest.raises(ValueError, match="out of range"):
        modal_derivatives(body, basis.vectors, basis.fixed_dofs, [(0, 99)])
    mb = ModalBody(basis)
    with pytest.raises(ValueError, match="modal_loads"):
        mb.set_load_cases(np.zeros((1, basis.size + 1)))
    mb.set_load_cases(np.zeros((1, basis.size)))
    with pytest.raises(ValueError, match="load_amplitudes"):
        mb.load_amplitudes = [np.nan]
    assert mb.load_amplitudes.tolist() == [0.0]
