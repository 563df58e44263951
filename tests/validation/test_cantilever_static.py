"""Static cantilever validation against beam theory.

1. Small tip load, linear model: the mean tip deflection converges to the Timoshenko
   beam value for hex8 and hex20 meshes.
2. Large rotation (tip rotation ~40 degrees), co-rotational model: the tip position
   matches the inextensible elastica; the linear model is far off (it cannot shorten).
3. Tip rotation 80.5 degrees, co-rotated Hex8 and Hex20: Newton with the exact
   (non-symmetric) tangent converges quadratically in every load step, and the tip lands
   within 0.5% of the elastica (closed form by elliptic integrals, cross-checked against
   the boundary-value solve).

Conventions: beam x in [0, L], clamped by fixing every node of x = 0, tip load P in -z
applied as the consistent nodal load of a uniform traction on the face x = L. The
tip "displacement" is the load-weighted mean of the tip-face node displacements (the
displacement work-conjugate to P; for a rigidly rotated face it is the centroid's).
nu = 0 throughout the small-load comparison, so the 3D clamp has no Poisson
restraint and Timoshenko theory is the right reference (with nu = 0.3 the clamp makes
the converged 3D answer ~0.9% stiffer; see test_poisson_clamp_effect_is_small).
"""

from __future__ import annotations

import numpy as np
import pytest
from cantilever_support import elastica_tip, elastica_tip_elliptic, timoshenko_tip_deflection, tip_face_weights

import corotate as cr

E = 1.0e7
RHO = 1000.0


def _cantilever(L, b, h, cells, element, model, nu):
    mesh = cr.beam(L, b, h, cells=cells, element=element)
    body = cr.Body(mesh, cr.Material(E=E, nu=nu, density=RHO), model=model)
    sim = cr.Simulation(body, dt=0.01, solver=cr.Direct())
    sim.fix(mesh.nodes_on_plane("x", 0.0))
    tip, w = tip_face_weights(mesh, L)
    return mesh, sim, tip, w


def _tip_deflection_linear(L, b, h, cells, element, P, nu=0.0):
    """Downward tip deflection (load-weighted mean of the tip face) of the linear model."""
    _mesh, sim, tip, w = _cantilever(L, b, h, cells, element, "linear", nu)
    sim.external_forces[tip, 2] = -P * w
    # Linear model: one Newton step is exact. The residual floor is ~1e-9 relative here
    # (positions are stored absolutely, so x - X carries ~eps |X| round-off), hence 1e-6.
    result = sim.solve_static(load_steps=1, tolerance=1e-6, max_iterations=5)
    assert result["iterations"] == 1
    return -float(w @ sim.displacements[tip, 2])


# L/h = 10, square section; P gives a deflection of ~L/250 (magnitude is irrelevant to
# the linear model).
L, B, H, P = 10.0, 1.0, 1.0, 100.0


@pytest.mark.parametrize(
    "element, meshes, finest_tol",
    [
        # Fully integrated hex8 locks in shear: 33% too stiff with one element over the
        # height; refining along the beam (element aspect ratio) removes it slowly.
        ("hex8", [(10, 2, 2), (20, 2, 2), (40, 2, 2), (80, 2, 2)], 0.03),
        # hex20 (3x3x3 Gauss) is accurate in bending already on a single column of cells.
        ("hex20", [(5, 1, 1), (10, 1, 1), (20, 2, 2)], 0.005),
    ],
)
def test_small_load_tip_deflection_converges_to_timoshenko(element, meshes, finest_tol):
    nu = 0.0
    w_theory = timoshenko_tip_deflection(P, L, B, H, E, nu)  # 0.04024 (shear: 0.6%)
    errors = []
    for cells in meshes:
        w_fe = _tip_deflection_linear(L, B, H, cells, element, P, nu)
        errors.append((w_fe - w_theory) / w_theory)
    abs_err = np.abs(errors)
    # Errors shrink monotonically and the finest mesh is within the tolerance.
    # Measured: hex8 -33.4%, -11.2%, -3.1%, -0.87%; hex20 -0.38%, -0.12%, -0.008%.
    assert np.all(np.diff(abs_err) < 0), f"{element} errors not decreasing: {errors}"
    assert abs_err[-1] < finest_tol, f"{element} finest-mesh error {errors[-1]:.4%}"
    # Conforming displacement elements are stiff: they never overshoot the 3D answer,
    # which for nu = 0 is the Timoshenko value to well below these errors.
    assert max(errors) < 1e-3, errors


def test_tet10_cantilever_converges_to_the_hex20_answer_where_tet4_locks():
    hex20 = _tip_deflection_linear(L, B, H, (20, 2, 2), "hex20", P)
    # Tet10 on (10, 2, 2) cuboids has 525 nodes against Hex20's 621 on (20, 2, 2).
    # Measured: Tet10 -0.59 % on (5, 1, 1), -0.055 % on (10, 2, 2); Tet4 -42 % on (20, 2, 2).
    errors = [_tip_deflection_linear(L, B, H, cells, "tet10", P) / hex20 - 1 for cells in [(5, 1, 1), (10, 2, 2)]]
    assert abs(errors[-1]) < 0.01, errors
    assert abs(errors[-1]) < abs(errors[0]), errors
    # Linear tets on the finer grid lock in bending: far stiffer.
    tet4 = _tip_deflection_linear(L, B, H, (20, 2, 2), "tet4", P)
    assert tet4 / hex20 - 1 < -0.1, tet4 / hex20 - 1


def test_poisson_clamp_effect_is_small():
    """With nu = 0.3 the fully clamped face restrains the lateral Poisson contraction and
    the 3D answer is slightly stiffer than Timoshenko theory (measured -1.0% on a 20x2x2
    hex20 mesh); it stays within 3%."""
    nu = 0.3
    w_theory = timoshenko_tip_deflection(P, L, B, H, E, nu)
    w_fe = _tip_deflection_linear(L, B, H, (20, 2, 2), "hex20", P, nu)
    err = (w_fe - w_theory) / w_theory
    assert -0.03 < err < 0.0, err


# ---------------------------------------------------------------------------------
# Large rotation: slender cantilever (L/h = 20), tip rotation ~40 degrees.
# ---------------------------------------------------------------------------------
LR_L, LR_B, LR_H = 10.0, 0.5, 0.5
LR_ALPHA = 1.7  # P L^2 / (E I); elastica tip rotation 40.1 degrees
LR_I = LR_B * LR_H**3 / 12.0
LR_P = LR_ALPHA * E * LR_I / LR_L**2
LR_CELLS = (20, 1, 1)


@pytest.fixture(scope="module")
def elastica_reference():
    theta, x_tip, z_tip = elastica_tip(LR_ALPHA)
    # Tip displacement (u_x, u_z) of the centroid line: shortening and deflection (-z).
    return theta, np.array([(x_tip - 1.0) * LR_L, -z_tip * LR_L])


def _large_rotation(model, load_steps, element="hex20", cells=LR_CELLS, P=LR_P, tolerance=1e-6):
    mesh, sim, tip, w = _cantilever(LR_L, LR_B, LR_H, cells, element, model, 0.0)
    sim.external_forces[tip, 2] = -P * w  # dead load: stays in -z
    result = sim.solve_static(load_steps=load_steps, tolerance=tolerance, max_iterations=100)
    u = sim.displacements[tip]
    tip_u = np.array([w @ u[:, 0], w @ u[:, 2]])
    # Tip-face rotation about y from the deformed face's z-extent direction (the face
    # normal is the beam axis; the face's +z edge direction turns by the same angle).
    top = tip[np.isclose(mesh.points[tip, 2], LR_H)]
    bottom = tip[np.isclose(mesh.points[tip, 2], 0.0)]
    d = sim.positions[top].mean(axis=0) - sim.positions[bottom].mean(axis=0)
    rotation = np.arctan2(d[0], d[2])  # +z edge tilts towards +x when the tip dips
    return tip_u, rotation, result


def test_large_rotation_matches_elastica(elastica_reference):
    theta_ref, u_ref = elastica_reference
    assert np.degrees(theta_ref) == pytest.approx(40.1, abs=0.1)
    u_fe, rot_fe, result = _large_rotation("corotational", load_steps=10)
    scale = np.linalg.norm(u_ref)  # 4.65 = 0.465 L
    # Measured: u_fe = (-1.2932, -4.4751) vs elastica (-1.2923, -4.4682): 0.15% of |u_ref|.
    # Required 5%; asserted 1% (shear deformation and extension of this L/h = 20,
    # nu = 0 beam change the beam answer by ~0.15%).
    assert np.linalg.norm(u_fe - u_ref) < 0.01 * scale, (u_fe, u_ref)
    # Each component on its own: the shortening is ~28% of the deflection and is a
    # purely geometric (second-order) effect.
    assert u_fe[0] == pytest.approx(u_ref[0], rel=0.02)
    assert u_fe[1] == pytest.approx(u_ref[1], rel=0.01)
    assert rot_fe == pytest.approx(theta_ref, rel=0.02)
    # Newton with the exact tangent converges in every load step.
    assert len(result["residual_history"]) == 10
    assert all(h[-1] <= 1e-6 for h in result["residual_history"])


def test_linear_model_fails_at_large_rotation(elastica_reference):
    _, u_ref = elastica_reference
    u_lin, _, _ = _large_rotation("linear", load_steps=1)
    scale = np.linalg.norm(u_ref)
    # Linear FEM cannot shorten the beam ...
    assert abs(u_lin[0]) < 1e-6 * LR_L
    # ... and overshoots the deflection: it gives (nearly) P L^3 / 3EI = alpha L / 3.
    assert u_lin[1] == pytest.approx(-LR_ALPHA * LR_L / 3, rel=0.01)
    assert u_lin[1] < 1.2 * u_ref[1]  # > 20% too deep (measured 27%)
    # Position error ~38% of the elastica's displacement magnitude.
    assert np.linalg.norm(u_lin - u_ref) > 0.15 * scale


# ---------------------------------------------------------------------------------
# Tip rotation 80 degrees: alpha = 9, the same beam (L/h = 20, nu = 0). Mattiasson's
# (1981) table for alpha = 9: u/L = 0.53182, w/L = 0.79906, tip rotation 80.53 degrees.
# ---------------------------------------------------------------------------------
ALPHA_80 = 9.0
P_80 = ALPHA_80 * E * LR_I / LR_L**2


def test_elastica_closed_form_agrees_with_the_boundary_value_solve():
    for alpha in (0.5, 1.7, 5.0, ALPHA_80, 15.0):
        np.testing.assert_allclose(elastica_tip_elliptic(alpha), elastica_tip(alpha), rtol=0, atol=1e-10)
    theta, x_tip, z_tip = elastica_tip_elliptic(ALPHA_80)
    assert np.degrees(theta) == pytest.approx(80.53, abs=0.01)
    assert (1 - x_tip, z_tip) == pytest.approx((0.53182, 0.79906), abs=1e-5)  # Mattiasson
    assert elastica_tip_elliptic(10.0)[1:] == pytest.approx((1 - 0.55500, 0.81061), abs=1e-5)


def _assert_quadratic(history, tolerance):
    """The terminal iterations square the relative residual: from the last residual above
    1e-3 the tolerance is reached in at most three iterations, each with
    r_next <= 1e3 r^2 (pairs ending on the round-off floor, ~1e-10 here, are not judged).
    Linear convergence at a rate rho fails this below 1e-5 unless rho < 1e-2."""
    h = np.asarray(history)
    assert h[-1] <= tolerance, history
    k = np.flatnonzero(h >= 1e-3)[-1]
    tail = h[k:]
    assert len(tail) <= 4, history
    pairs = [(a, b) for a, b in zip(tail[:-1], tail[1:]) if b > 1e-9]
    assert pairs, history
    for a, b in pairs:
        assert b <= 1e3 * a * a, history


@pytest.fixture(scope="module")
def tips_at_80_degrees():
    # Meshes: Hex20 20 x 1 x 1 (within 0.08% of 40 x 2 x 2, measured) and Hex8 160 x 1 x 1
    # (fully integrated Hex8 locks in bending: 3.2%, 0.9%, 0.25% from Hex20 40 x 2 x 2 on 40,
    # 80, 160 cells along the beam). 10 load steps, tolerance 1e-9 (round-off floor ~1e-10).
    return {
        element: _large_rotation("corotational", 10, element, cells, P_80, tolerance=1e-9)
        for element, cells in (("hex20", (20, 1, 1)), ("hex8", (160, 1, 1)))
    }


@pytest.mark.parametrize("element", ["hex20", "hex8"])
def test_corotated_hexes_converge_quadratically_at_80_degrees(tips_at_80_degrees, element):
    _, _, result = tips_at_80_degrees[element]
    histories = result["residual_history"]
    assert len(histories) == 10
    for history in histories:
        _assert_quadratic(history, 1e-9)
    # Measured: 60 iterations in all (5 to 8 per step). With the R K R^T tangent this solve
    # stalled at load step 3 of 10 (step 28 of 100), the residual growing 2-3x per iteration.
    assert result["iterations"] <= 70, result["iterations"]


@pytest.mark.parametrize("element", ["hex20", "hex8"])
def test_corotated_hexes_match_the_elastica_at_80_degrees(tips_at_80_degrees, element):
    theta, x_tip, z_tip = elastica_tip_elliptic(ALPHA_80)
    u_ref = np.array([(x_tip - 1.0) * LR_L, -z_tip * LR_L])  # (-5.3182, -7.9906)
    u_fe, rotation, _ = tips_at_80_degrees[element]
    # Measured: Hex20 (-5.3238, -8.0181), 0.29% of |u_ref|; Hex8 (-5.3087, -8.0082), 0.21%.
    # The converged 3D beam is ~0.35% more flexible than the elastica (shear and extension
    # of L/h = 20); required 1%, asserted 0.5%.
    assert np.linalg.norm(u_fe - u_ref) < 0.005 * np.linalg.norm(u_ref), (u_fe, u_ref)
    assert u_fe[0] == pytest.approx(u_ref[0], rel=0.005)
    assert u_fe[1] == pytest.approx(u_ref[1], rel=0.005)
    assert rotation == pytest.approx(theta, rel=0.01)


def test_hex8_and_hex20_agree_at_80_degrees(tips_at_80_degrees):
    # Two element types, each on its own refined mesh, land on the same tip (measured 0.19%
    # apart): the meshes are converged to well below the 1% asked of the elastica match.
    u20, u8 = tips_at_80_degrees["hex20"][0], tips_at_80_degrees["hex8"][0]
    assert np.linalg.norm(u20 - u8) < 0.003 * np.linalg.norm(u20), (u20, u8)
