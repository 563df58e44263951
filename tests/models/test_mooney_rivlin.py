"""Mooney-Rivlin (cpp/include/corotate/materials/mooney_rivlin.hpp) with both constants active:
stress and tangent are derivatives of the energy (law and assembled body), the material's
small-strain moduli, the uniaxial tension of the near-incompressible solid against the closed
form, and its parameter checks. (With a material given by E and nu it also runs through every
generic hyperelastic test of test_hyperelastic.py and tests/cpp/test_models.cpp.)"""

import numpy as np
import pytest
from derivative_support import gradient_fd, jacobian_fd, rel_err
from uniaxial_support import pull_bar

import corotate as cr
from corotate import _core

C10, C01 = 0.3e6, 0.1e6
MR = cr.Material(law="mooney_rivlin", C10=C10, C01=C01, bulk=5e6, density=1100.0)


def test_parameters_are_declared_by_the_law():
    names = [name for name, _ in cr.Material.law_parameters()["mooney_rivlin"]]
    assert names == ["C10", "C01", "bulk"]
    assert MR.law == "mooney_rivlin" and MR.parameters == (("C10", C10), ("C01", C01), ("bulk", 5e6))
    assert MR.density == 1100.0


def test_small_strain_moduli_are_the_laws():
    lam, mu = MR.lame
    assert mu == pytest.approx(2 * (C10 + C01), rel=1e-14)
    assert lam + 2 * mu / 3 == pytest.approx(5e6, rel=1e-14)  # bulk modulus
    assert MR.E == pytest.approx(9 * 5e6 * mu / (3 * 5e6 + mu), rel=1e-14)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_stress_and_tangent_are_derivatives_of_the_energy(seed):
    rng = np.random.default_rng(seed)
    F = np.eye(3) + 0.3 * rng.standard_normal((3, 3))
    assert np.linalg.det(F) > 0
    _, P, A = _core.constitutive_law("mooney_rivlin", F, MR._core())
    P_fd = gradient_fd(lambda G: _core.constitutive_law("mooney_rivlin", G, MR._core())[0], F, 1e-7)
    A_fd = jacobian_fd(lambda G: _core.constitutive_law("mooney_rivlin", G.T, MR._core())[1].T, F.T, 1e-7)
    assert rel_err(P, P_fd) < 1e-6
    assert rel_err(A, A_fd) < 1e-6


@pytest.mark.parametrize("element", ["tet4", "hex8"])
def test_body_forces_and_stiffness_are_derivatives_of_the_energy(element):
    mesh = cr.box((1.0, 0.8, 1.2), (1, 1, 1), element)
    body = cr.Body(mesh, MR, model="mooney_rivlin")
    rng = np.random.default_rng(4)
    x = mesh.points @ (np.eye(3) + 0.15 * rng.standard_normal((3, 3))).T + 0.05 * rng.uniform(-1, 1, mesh.points.shape)
    assert rel_err(body.internal_forces(x), -gradient_fd(body.energy, x, 1e-7)) < 1e-6
    K = body.stiffness_matrix(x).toarray()
    assert rel_err(K, -jacobian_fd(body.internal_forces, x, 1e-7)) < 1e-6
    np.testing.assert_array_equal(K, K.T)


@pytest.mark.parametrize("element", ["tet4", "hex8"])
def test_uniaxial_tension_of_the_nearly_incompressible_solid(element):
    """Incompressible uniaxial tension of stretch s: lateral stretch s^-1/2 and nominal stress
    P = 2 (s - s^-2) (C10 + C01 / s). A bulk modulus 1e4 times the shear modulus makes the
    solid nearly incompressible (volume change below 1e-4 here); the bar's deformation is
    homogeneous, so the mesh represents it exactly and the one difference is that volume
    change."""
    mu = 2 * (C10 + C01)
    material = cr.Material(law="mooney_rivlin", C10=C10, C01=C01, bulk=1e4 * mu, density=1000.0)
    L, w, h = 4.0, 1.0, 1.0
    body = cr.Body(cr.box((L, w, h), (4, 2, 2), element), material, model="mooney_rivlin")
    stretches = np.linspace(1.1, 2.0, 10)
    for s, x, force in pull_bar(body, L, w, stretches, 1e-9 * mu * w * h):
        expected = 2 * (s - s**-2) * (C10 + C01 / s) * w * h
        assert force == pytest.approx(expected, rel=1e-2)
        assert (x[:, 1].max() - x[:, 1].min()) / w == pytest.approx(s**-0.5, rel=1e-2)
    # C01 counts as C01 / s, not as a neo-Hookean's C01: at s = 2 that is 12 % of the force.
    neo_hookean = 2 * (s - s**-2) * (C10 + C01) * w * h
    assert abs(force - neo_hookean) > 0.1 * neo_hookean


def test_a_material_by_E_and_nu_becomes_the_neo_hookean_member():
    """E and nu give C10 = mu / 2, C01 = 0, bulk = lambda + 2 mu / 3: the same small-strain
    stiffness as the linear model, and the energy mu/2 (I1b - 3) + K/2 (J - 1)^2."""
    mat = cr.Material(E=1e6, nu=0.3, density=1000.0)
    lam, mu = mat.lame
    F = np.diag([1.3, 0.9, 1.1])
    W, _, _ = _core.constitutive_law("mooney_rivlin", F, mat._core())
    J = np.linalg.det(F)
    assert W == pytest.approx(mu / 2 * (J ** (-2 / 3) * np.sum(F**2) - 3) + (lam + 2 * mu / 3) / 2 * (J - 1) ** 2)


@pytest.mark.parametrize(
    ("parameters", "message"),
    [
        ({"C10": -1.0, "C01": 0.0, "bulk": 1e6}, r"C10 \(coefficient of the first isochoric invariant \[Pa\]\) must"),
        ({"C10": 1.0, "C01": -1.0, "bulk": 1e6}, r"C01 .* must be finite and >= 0"),
        ({"C10": 1.0, "C01": 0.0, "bulk": 0.0}, r"bulk .* must be finite and > 0"),
        ({"C10": 1.0, "C01": 0.0, "bulk": float("nan")}, "bulk"),
        ({"C10": 1.0, "bulk": 1e6}, r"parameter C01 .* is missing"),
        ({"C10": 1.0, "C01": 0.0, "bulk": 1e6, "C20": 1.0}, r"has no parameter 'C20'.*C10, C01, bulk"),
        ({"C10": 1.0, "C01": 0.0, "bulk": 1e7}, r"small-strain moduli of this 'mooney_rivlin' material.*0\.5"),
    ],
)
def test_bad_parameters_are_named(parameters, message):
    with pytest.raises(ValueError, match=message):
        cr.Material(law="mooney_rivlin", **parameters)


def test_a_law_material_goes_only_to_its_law_or_the_small_strain_models():
    mesh = cr.box((1.0, 1.0, 1.0), (1, 1, 1), "tet4")
    with pytest.raises(ValueError, match=r"'stvk' model needs a material given by E and nu.*'mooney_rivlin' param"):
        cr.Body(mesh, MR, model="stvk")
    # The linear model takes the law's small-strain moduli: the law's own stiffness at rest.
    K_law = cr.Body(mesh, MR, model="mooney_rivlin").stiffness_matrix().toarray()
    K_lin = cr.Body(mesh, MR, model="linear").stiffness_matrix().toarray()
    assert rel_err(K_law, K_lin) < 1e-12
    with pytest.raises(ValueError, match="no law 'neohookean' with parameters of its own"):
        cr.Material(law="neohookean", mu=1.0)
    with pytest.raises(ValueError, match=r"unknown material parameter.*C10.*law="):
        cr.Material(C10=1.0)
    with pytest.raises(ValueError, match="E and nu are derived"):
        cr.Material(E=1e6, law="mooney_rivlin", C10=1.0, C01=0.0, bulk=1e6)
