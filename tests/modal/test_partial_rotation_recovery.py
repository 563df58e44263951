"""Partial rotation in the C++ recovery path: equal, to round-off, to a plain NumPy/SciPy
statement of the method (Kabsch fit per domain, turn by half the blended rotation vector),
for every node and for a subset, through PartialRotation.apply and through ModalBody; and
bad input rejected with the state kept.

Two domains (the two ends of a Hex20 beam, 8 x 1 x 1 m) blended over 2 m between them; the
displacements are two bending modes scaled to turn the free end by 10-20 degrees.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import corotate as cr
from corotate.modal import ModalBody, PartialRotation, craig_bampton, least_squares_rotation


@pytest.fixture(scope="module")
def setup():
    mesh = cr.beam(8.0, 1.0, 1.0, cells=(8, 1, 1), element="hex20")
    body = cr.Body(mesh, cr.Material(E=1e7, nu=0.3, density=1000.0), model="linear")
    basis = craig_bampton(body, mesh.nodes_on_plane("x", 0.0), n_modes=6)
    X = mesh.points
    left, right = np.flatnonzero(X[:, 0] <= 3.0), np.flatnonzero(X[:, 0] >= 5.0)
    reps = [
        [mesh.nearest_node(p) for p in ((0, 0, 0), (0, 1, 1), (3, 0, 1), (3, 1, 0))],
        [mesh.nearest_node(p) for p in ((5, 0, 0), (5, 1, 1), (8, 0, 1), (8, 1, 0))],
    ]
    rotation = PartialRotation(X, [left, right], reps, blend_distance=2.0)
    q = np.zeros(basis.size)
    q[:2] = 1.0
    u = basis.vectors @ q
    q *= 1.5 / np.abs(u).max()  # the free end turns by 10-20 degrees
    return mesh, basis, rotation, reps, q


def kabsch(rest, moved):
    a, b = rest - rest.mean(axis=0), moved - moved.mean(axis=0)
    U, _, Vt = np.linalg.svd(a.T @ b)
    return Vt.T @ np.diag([1.0, 1.0, np.sign(np.linalg.det(Vt.T @ U.T))]) @ U.T


def reference(X, u, weights, reps):
    """The method in NumPy/SciPy: Kabsch per domain, blended rotation vectors, half angle."""
    rotvecs = np.array([Rotation.from_matrix(kabsch(X[p], X[p] + u[p])).as_rotvec() for p in reps])
    return Rotation.from_rotvec(0.5 * (weights @ rotvecs)).apply(u)


def test_core_equals_the_numpy_statement(setup):
    mesh, basis, rotation, reps, q = setup
    X, u = mesh.points, (basis.vectors @ q).reshape(-1, 3)
    expected = reference(X, u, rotation.weights, reps)
    got = rotation.apply(u)
    for p, R in zip(reps, rotation.rotations):
        np.testing.assert_allclose(least_squares_rotation(X[p], X[p] + u[p]), R, atol=1e-14)
    turned = np.degrees(np.linalg.norm(Rotation.from_matrix(rotation.rotations).as_rotvec(), axis=1))
    assert turned[0] > 2 and 10 < turned[1] < 20, turned
    assert np.abs(got - u).max() > 0.05 * np.abs(u).max()  # the rotation does something
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-13 * np.abs(u).max())
    assert np.any(np.count_nonzero(rotation.weights, axis=1) == 2)  # some nodes blend the two


def test_modal_body_recovers_rotated_displacements(setup):
    mesh, basis, rotation, _reps, q = setup
    plain = ModalBody(basis)
    plain.q[:] = q
    turned = ModalBody(basis, partial_rotation=rotation)
    turned.q[:] = q
    expected = rotation.apply(plain.displacements())
    out = np.empty((mesh.n_nodes, 3))
    assert turned.displacements(out=out) is out
    np.testing.assert_allclose(out, expected, rtol=0, atol=1e-14)
    subset = np.array([7, 0, mesh.n_nodes - 1, 40])
    part = np.empty((4, 3))
    turned.displacements(subset, out=part)
    np.testing.assert_allclose(part, expected[subset], rtol=0, atol=1e-14)
    fast = ModalBody(basis, recovery="float32", partial_rotation=rotation)
    fast.q[:] = q
    np.testing.assert_allclose(fast.displacements(subset), expected[subset], rtol=0, atol=1e-6 * np.abs(out).max())


def test_saved_body_keeps_its_partial_rotation(setup, tmp_path):
    _mesh, basis, rotation, _reps, q = setup
    body = ModalBody(basis, partial_rotation=rotation)
    body.save(tmp_path / "turned.npz")
    again = ModalBody.load(tmp_path / "turned.npz")
    assert again.partial_rotation is not None
    np.testing.assert_array_equal(again.partial_rotation.weights, rotation.weights)
    for b in (body, again):
        b.q[:] = q
    np.testing.assert_array_equal(again.displacements(), body.displacements())
    ModalBody(basis).save(tmp_path / "plain.npz")
    assert ModalBody.load(tmp_path / "plain.npz").partial_rotation is None


def test_bad_input_is_rejected(setup):
    mesh, basis, rotation, reps, q = setup
    X = mesh.points
    line = [mesh.nearest_node((x, 0, 0)) for x in (0.0, 1.0, 2.0, 3.0)]
    with pytest.raises(ValueError, match="one line"):
        PartialRotation(X, [np.arange(10)], [line])
    with pytest.raises(ValueError, match="one line"):
        PartialRotation(X, [np.arange(10)], [[3, 3, 3, 3]])
    with pytest.raises(ValueError, match="at least three"):
        PartialRotation(X, [np.arange(10)], [[0, 1]])
    with pytest.raises(ValueError, match="out of range"):
        PartialRotation(X, [np.arange(10)], [[0, 1, 2, mesh.n_nodes]])
    with pytest.raises(ValueError, match="finite"):
        PartialRotation(np.full(X.shape, np.nan), [np.arange(10)], [reps[0]])
    with pytest.raises(ValueError, match="shape"):
        rotation.apply(np.zeros((3, 3)))
    with pytest.raises(ValueError, match="shape"):
        least_squares_rotation(X[:4], X[:5])
    with pytest.raises(ValueError, match="finite"):
        least_squares_rotation(X[:4], np.full((4, 3), np.nan))
    with pytest.raises(ValueError, match="finite"):
        rotation.apply(np.full(X.shape, np.nan))
    body = ModalBody(basis, partial_rotation=rotation)
    other = PartialRotation(X[:20], [np.arange(10)], [[0, 1, 2, 13]])
    with pytest.raises(ValueError, match="nodes"):
        body.partial_rotation = other
    assert body.partial_rotation is rotation
    with pytest.raises(ValueError, match="nodes"):
        ModalBody(basis, partial_rotation=other)
    body.q[:] = q
    before = body.displacements()
    with pytest.raises(ValueError, match="out of range"):
        body.displacements([mesh.n_nodes])
    np.testing.assert_array_equal(body.displacements(), before)
    body.partial_rotation = None
    assert np.abs(body.displacements() - before).max() > 0
