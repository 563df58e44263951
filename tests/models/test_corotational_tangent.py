"""The exact tangent of co-rotated tets (rotation terms included) against finite differences
of the forces, and what it buys: quadratic Newton convergence in static solves."""

import numpy as np

import corotate as cr

MAT = cr.Material(E=1e6, nu=0.3, density=1000.0)


def deformed(mesh, seed=0):
    rng = np.random.default_rng(seed)
    x = mesh.points.copy()
    angle = 0.8 * x[:, 0]  # a twist of up to ~45 degrees plus noise: large rotations
    y, z = x[:, 1] - 0.5, x[:, 2] - 0.5
    x[:, 1], x[:, 2] = 0.5 + np.cos(angle) * y - np.sin(angle) * z, 0.5 + np.sin(angle) * y + np.cos(angle) * z
    return x + 0.03 * rng.standard_normal(x.shape)


def minus_force_jacobian_fd(body, x, h=1e-6):
    """-df/dx at x by central differences, one DOF at a time."""
    fd = np.empty((x.size, x.size))
    for d in range(x.size):
        xp, xm = x.copy(), x.copy()
        xp.flat[d] += h
        xm.flat[d] -= h
        fd[:, d] = -(body.internal_forces(xp) - body.internal_forces(xm)).ravel() / (2 * h)
    return fd


def test_tet_tangent_equals_the_derivative_of_the_forces():
    mesh = cr.box((1.0, 1.0, 1.0), (2, 2, 2), "tet4")
    body = cr.Body(mesh, MAT, model="corotational")
    x = deformed(mesh)
    K = body.tangent_matrix(x).toarray()
    fd = minus_force_jacobian_fd(body, x)
    assert np.abs(K - fd).max() < 1e-6 * np.abs(K).max()
    np.testing.assert_allclose(K, K.T, atol=1e-10 * np.abs(K).max())
    # The usual R K R^T stiffness is not this derivative at a rotated state.
    approx = body.stiffness_matrix(x).toarray()
    assert np.abs(approx - fd).max() > 1e-3 * np.abs(K).max()


def test_tangent_equals_stiffness_where_the_rotation_terms_vanish():
    mesh = cr.box((1.0, 1.0, 1.0), (2, 2, 2), "tet4")
    body = cr.Body(mesh, MAT, model="corotational")
    # at rest, and under a pure rigid rotation, the stress is zero and so are the extra terms
    np.testing.assert_allclose(body.tangent_matrix().toarray(), body.stiffness_matrix().toarray(), atol=1e-8)
    for element in ("hex8", "hex20"):
        hexes = cr.Body(cr.box((1.0, 1.0, 1.0), (2, 1, 1), element), MAT, model="corotational")
        R = rotation(0.9, (1.0, 2.0, 3.0))
        for x in (hexes.mesh.points, hexes.mesh.points @ R.T + (0.3, -0.2, 0.1)):
            Kh = hexes.stiffness_matrix(x).toarray()
            np.testing.assert_allclose(hexes.tangent_matrix(x).toarray(), Kh, rtol=0, atol=1e-9 * np.abs(Kh).max())


def rotation(angle, axis):
    """Rotation matrix about axis (Rodrigues)."""
    k = np.asarray(axis, float) / np.linalg.norm(axis)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


def test_hex_tangent_equals_the_derivative_of_the_forces_and_is_not_symmetric():
    # The co-rotated hex force -R K_e (R^T x - X), R the polar rotation at the centre, is not
    # a gradient, so its exact tangent is not symmetric; the assembled matrix keeps both halves.
    for element in ("hex8", "hex20"):
        mesh = cr.box((1.0, 1.0, 1.0), (2, 1, 1), element)
        body = cr.Body(mesh, MAT, model="corotational")
        x = deformed(mesh, seed=1)
        K = body.tangent_matrix(x).toarray()
        fd = minus_force_jacobian_fd(body, x)
        scale = np.abs(K).max()
        assert np.abs(K - fd).max() < 1e-6 * scale, element
        assert np.abs(K - K.T).max() > 1e-3 * scale, element
        assert np.abs(body.stiffness_matrix(x).toarray() - fd).max() > 1e-3 * scale, element


def test_static_newton_converges_quadratically_for_corotated_tets():
    # A cantilever under a tip load that bends it by 12 % of its length (about 20 degrees of
    # tip rotation): with the exact tangent each load step ends quadratically.
    mesh = cr.beam(5.0, 0.5, 0.5, cells=(20, 2, 2))
    body = cr.Body(mesh, cr.Material(E=1e7, nu=0.3, density=1000.0), model="corotational")
    sim = cr.Simulation(body)
    sim.fix(mesh.nodes_on_plane("x", 0.0))
    tip = mesh.nodes_on_plane("x", 5.0)
    sim.external_forces[tip] = (0.0, 0.0, -1500.0 / tip.size)
    result = sim.solve_static(load_steps=3, tolerance=1e-9)
    for history in result["residual_history"]:
        assert len(history) <= 8, history
        h = np.array(history)
        pairs = [(a, b) for a, b in zip(h[:-1], h[1:]) if a < 1e-1 and b > 1e-10]  # above round-off
        assert pairs, history
        for a, b in pairs:
            assert b <= 100 * a * a, history
    assert sim.displacements[tip, 2].mean() < -0.5  # a large deflection indeed
