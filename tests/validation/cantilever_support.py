"""Shared helpers for the cantilever validation tests (not a test module).

* consistent nodal loads of a uniform traction on the tip face of a structured beam,
* Timoshenko static tip deflection of a rectangular cantilever,
* the inextensible elastica of a cantilever under a dead tip load, by a boundary-value
  solve and in closed form with elliptic integrals,
* the first bending frequency of a Timoshenko cantilever (shear + rotary inertia).
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_bvp, solve_ivp
from scipy.optimize import brentq
from scipy.special import ellipe, ellipeinc, ellipk, ellipkinc

# Euler-Bernoulli cantilever: first root of 1 + cos(b) cosh(b) = 0.
BETA1 = 1.8751040687119611


def face_shares(cell_type: str) -> np.ndarray:
    """(nf, k): the consistent nodal shares of a uniform unit traction on each boundary face
    of the reference cell, int N_a dA / area, from the element's own shape functions and
    faces (the core's cell-type table). Bilinear quads: 1/4 each; 8-node serendipity faces:
    -1/12 per corner and 1/3 per mid-edge node; 6-node triangles: 0 per corner, 1/3 per
    mid-edge node. The faces' shape functions have degree <= 2 per direction, which the
    4 x 4 Gauss rule integrates exactly."""
    import corotate as cr
    import corotate._core as _core

    facts = cr.cell_types()[cell_type]
    nodes = facts["reference_nodes"]
    g, w = np.polynomial.legendre.leggauss(4)
    u, v = np.meshgrid((g + 1) / 2, (g + 1) / 2, indexing="ij")
    wu = np.outer(w, w).ravel() / 4
    u, v = u.ravel(), v.ravel()
    out = []
    for face in facts["faces"]:
        c = nodes[face]
        if len(face) == 3:  # collapsed square onto the triangle: s = u, t = v (1 - u)
            s, t, weight = u, v * (1 - u), wu * (1 - u)
            points = c[0] + np.outer(s, c[1] - c[0]) + np.outer(t, c[2] - c[0])
        else:  # bilinear map of the unit square onto the (planar, square) reference face
            points = (
                np.outer((1 - u) * (1 - v), c[0])
                + np.outer(u * (1 - v), c[1])
                + np.outer(u * v, c[2])
                + np.outer((1 - u) * v, c[3])
            )
            weight = wu
        values, _ = _core.shape_functions(cell_type, points)
        out.append(weight @ values / weight.sum())
    return np.array(out)


def tip_face_weights(mesh, x_tip: float):
    """Nodes of the face x = x_tip and the consistent nodal shares of a uniform
    traction on that face (shares sum to 1), for any solid cell type (see face_shares).
    """
    import corotate as cr

    facts = cr.cell_types()[mesh.cell_type]
    shares = face_shares(mesh.cell_type)
    tip = mesh.nodes_on_plane("x", x_tip)
    weight = np.zeros(mesh.n_nodes)
    on_face = np.abs(mesh.points[:, 0] - x_tip) <= 1e-9
    for cell in mesh.cells:
        for f, face in enumerate(facts["faces"]):
            if not on_face[cell[face]].all():
                continue
            p = mesh.points[cell[face]]
            fan = sum(np.cross(p[i] - p[0], p[i + 1] - p[0]) for i in range(1, len(face) - 1))
            weight[cell] += shares[f] * 0.5 * np.linalg.norm(fan)
    w = weight[tip]
    assert np.isclose(w.sum(), np.ptp(mesh.points[:, 1]) * np.ptp(mesh.points[:, 2]))
    return tip, w / w.sum()


def rectangle_shear_coefficient(nu: float) -> float:
    """Cowper's shear coefficient of a rectangular section."""
    return 10.0 * (1.0 + nu) / (12.0 + 11.0 * nu)


def timoshenko_tip_deflection(P, L, b, h, E, nu):
    """Tip deflection of a clamped-free Timoshenko beam under an end load P."""
    I = b * h**3 / 12.0
    A = b * h
    G = E / (2.0 * (1.0 + nu))
    return P * L**3 / (3.0 * E * I) + P * L / (rectangle_shear_coefficient(nu) * G * A)


def elastica_tip(alpha: float):
    """Inextensible Euler-Bernoulli cantilever under a dead transverse tip load.

    alpha = P L^2 / (E I). In the arc length s in [0, 1] (units of L):
    theta'' = -alpha cos(theta), theta(0) = 0, theta'(1) = 0 (no end moment);
    x' = cos(theta), z' = sin(theta).
    Returns (tip rotation [rad], x_tip / L, z_tip / L) where z is the deflection
    magnitude in the load direction.
    """

    def rhs(s, y, a):
        return np.vstack([y[1], -a * np.cos(y[0]), np.cos(y[0]), np.sin(y[0])])

    def bc(ya, yb):
        return np.array([ya[0], yb[1], ya[2], ya[3]])

    # Continuation in equal steps of alpha <= 2, each from the previous solution (from the
    # linear solution the solver does not find the elastica beyond alpha ~ 5).
    steps = int(np.ceil(alpha / 2.0))
    a0 = alpha / steps
    s = np.linspace(0.0, 1.0, 101)
    y = np.zeros((4, s.size))
    y[0] = a0 * (s - s**2 / 2)  # the linear solution
    y[1] = a0 * (1 - s)
    y[2] = s
    for k in range(1, steps + 1):
        sol = solve_bvp(lambda s, y, a=k * a0: rhs(s, y, a), bc, s, y, tol=1e-10, max_nodes=100000)
        assert sol.success, sol.message
        s, y = sol.x, sol.y
    theta_tip, _, x_tip, z_tip = y[:, -1]
    return theta_tip, x_tip, z_tip


def elastica_tip_elliptic(alpha: float):
    """The elastica_tip answer in closed form (Bisshopp & Drucker 1945; the values tabulated
    by Mattiasson 1981). Returns (tip rotation theta0 [rad], x_tip / L, z_tip / L).

    The first integral of theta'' = -alpha cos(theta) with theta'(1) = 0 is
    theta'^2 = 2 alpha (sin theta0 - sin theta). Substituting 1 + sin theta = 2 k^2 sin^2 phi,
    k^2 = (1 + sin theta0) / 2, gives d theta / sqrt(sin theta0 - sin theta)
    = sqrt(2) d phi / sqrt(1 - k^2 sin^2 phi), phi from phi1 = asin(1 / (sqrt(2) k))
    (theta = 0) to pi / 2 (theta = theta0). With F, E the incomplete elliptic integrals of
    the first and second kind (parameter m = k^2) and K, E their complete values:
        sqrt(alpha) = K(m) - F(phi1, m)                          (fixes theta0),
        x_tip / L   = sqrt(2 sin(theta0) / alpha)                (integral of cos theta),
        z_tip / L   = 1 - 2 (E(m) - E(phi1, m)) / sqrt(alpha)    (sin theta = 1 - 2 dn^2).
    """

    def parts(theta0):
        m = (1.0 + np.sin(theta0)) / 2.0
        phi1 = np.arcsin(1.0 / np.sqrt(2.0 * m))
        return m, phi1

    def length_mismatch(theta0):
        m, phi1 = parts(theta0)
        return ellipk(m) - ellipkinc(phi1, m) - np.sqrt(alpha)

    theta0 = brentq(length_mismatch, 1e-12, np.pi / 2 - 1e-12, xtol=1e-15, rtol=1e-15)
    m, phi1 = parts(theta0)
    x_tip = np.sqrt(2.0 * np.sin(theta0) / alpha)
    z_tip = 1.0 - 2.0 * (ellipe(m) - ellipeinc(phi1, m)) / np.sqrt(alpha)
    return theta0, x_tip, z_tip


def timoshenko_first_frequency(E, nu, rho, L, b, h, f_guess):
    """First bending frequency [Hz] of a clamped-free Timoshenko beam (bending about
    the axis of the side b), with shear (Cowper's kappa) and rotary inertia.

    Harmonic motion w(x) e^{i w t}, psi(x) e^{i w t}:
        kGA (w'' - psi') + rho A w^2 w = 0
        EI psi'' + kGA (w' - psi) + rho I w^2 psi = 0
    clamped at x = 0 (w = psi = 0), free at x = L (EI psi' = 0, kGA (w' - psi) = 0).
    Shooting: the two clamped solutions (w'(0) = 1 or psi'(0) = 1) must combine to
    satisfy both free-end conditions; the 2x2 determinant vanishes at an eigenfrequency.
    """
    A = b * h
    I = b * h**3 / 12.0
    G = E / (2.0 * (1.0 + nu))
    kGA = rectangle_shear_coefficient(nu) * G * A

    def determinant(omega):
        def rhs(x, y):
            w, dw, psi, dpsi = y
            ddw = dpsi - rho * A * omega**2 / kGA * w
            ddpsi = -(kGA * (dw - psi) + rho * I * omega**2 * psi) / (E * I)
            return [dw, ddw, dpsi, ddpsi]

        rows = []
        for y0 in ([0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]):
            y = solve_ivp(rhs, (0.0, L), y0, method="DOP853", rtol=1e-11, atol=1e-13).y[:, -1]
            rows.append([y[3], y[1] - y[2]])
        return np.linalg.det(np.array(rows))

    w0 = 2 * np.pi * f_guess
    return brentq(determinant, 0.8 * w0, 1.01 * w0, xtol=1e-12, rtol=1e-12) / (2 * np.pi)
