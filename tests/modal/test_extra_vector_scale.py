"""craig_bampton(extra_vectors=...) judges each extra vector against its own norm.

A steel plate 1 x 0.8 x 0.02 m (Hex20, 8 x 6 x 1 cells) held at its four corners, a 1 N load
at a surface node off the centre: its static shape u (about 1e-7 m) is the static-correction
vector a user appends to four normal modes. The basis must not depend on the scale at which
u is handed in: a dependency test against one threshold for all columns used to drop u at the
scale of a unit load (and the normal modes at the scale 1e8), silently.

What is checked, each against an exact expectation:

* the span: the principal angles between the bases built from u * s and from u are at
  round-off (measured ~2e-15 for s from 1e-8 to 1e8; the normal modes come from a fixed
  ARPACK start vector, so two calls give the same modes);
* the reduced static answer u_r = Phi diag(1/w^2) Phi^T f is the same for every s (measured
  <= 3e-11 of |u|: the reduced solve's round-off), and equals the full one, because the load's
  static shape is in the span (measured 1e-10 of |u|, the full sparse solve's own round-off);
* a vector that really is dependent (a mode plus another extra vector, at another scale) is
  left out with a BasisWarning naming its column; the others stay.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import scipy.linalg as la
import scipy.sparse.linalg as sla

import corotate as cr
from corotate.modal import BasisWarning, craig_bampton

LX, LY, T = 1.0, 0.8, 0.02
N_MODES = 4


@pytest.fixture(scope="module")
def plate():
    mesh = cr.box((LX, LY, T), cells=(8, 6, 1), element="hex20")
    p = mesh.points
    corner = (np.isclose(p[:, 0], 0.0) | np.isclose(p[:, 0], LX)) & (np.isclose(p[:, 1], 0.0) | np.isclose(p[:, 1], LY))
    fixed = np.flatnonzero(corner)
    body = cr.Body(mesh, cr.Material(E=2.1e11, nu=0.3, density=7850.0), model="linear")
    free = np.setdiff1d(np.arange(3 * mesh.n_nodes), (3 * fixed[:, None] + np.arange(3)).ravel())
    K = body.stiffness_matrix().tocsc()[free][:, free].tocsc()
    return mesh, body, fixed, free, K


def _load_and_static_shape(mesh, free, K, point):
    """A 1 N downward load at the surface node nearest point, and the full linear static shape."""
    f = np.zeros(3 * mesh.n_nodes)
    f[3 * mesh.nearest_node(point) + 2] = -1.0
    u = np.zeros_like(f)
    u[free] = sla.spsolve(K, f[free])
    return f, u


def _reduced_static(basis, f):
    return basis.vectors @ ((basis.vectors.T @ f) / basis.eigenvalues)


def _quietly(*args, **kwargs):
    """craig_bampton with every warning an error (nothing here may be dropped)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        return craig_bampton(*args, **kwargs)


@pytest.mark.parametrize("scale", [1e-8, 1e-4, 1e4, 1e8])
def test_extra_vectors_at_any_scale_give_the_same_basis_and_answer(plate, scale):
    mesh, body, fixed, free, K = plate
    f, u = _load_and_static_shape(mesh, free, K, (0.375, 0.4, T))
    assert 1e-8 < np.abs(u).max() < 1e-6  # the scale of a unit load's shape, as a user hands it in
    reference = _quietly(body, fixed, n_modes=N_MODES, extra_vectors=u[:, None])
    scaled = _quietly(body, fixed, n_modes=N_MODES, extra_vectors=scale * u[:, None])
    assert reference.size == scaled.size == N_MODES + 1
    assert reference.n_extra == scaled.n_extra == 1
    assert la.subspace_angles(reference.vectors, scaled.vectors).max() < 1e-10
    # The M-orthogonal projectors onto the two spans are the same matrix.
    M = body.mass_matrix().tocsc()
    projector = reference.vectors @ (reference.vectors.T @ M)
    np.testing.assert_allclose(projector @ scaled.vectors, scaled.vectors, atol=1e-10 * np.abs(scaled.vectors).max())
    np.testing.assert_allclose(scaled.eigenvalues, reference.eigenvalues, rtol=1e-10)
    u_ref = _reduced_static(reference, f)
    assert np.linalg.norm(_reduced_static(scaled, f) - u_ref) < 1e-10 * np.linalg.norm(u_ref)


def test_the_static_correction_vector_makes_the_reduced_answer_the_full_one(plate):
    # The case: four normal modes miss a few per cent of a point load's static shape; with
    # the shape appended (at the scale the load gives it) the load lies in the span, and the
    # reduced static answer is the full linear one to the full solve's round-off.
    mesh, body, fixed, free, K = plate
    f, u = _load_and_static_shape(mesh, free, K, (0.375, 0.4, T))
    modes_only = _quietly(body, fixed, n_modes=N_MODES)
    assert np.linalg.norm(_reduced_static(modes_only, f) - u) > 0.01 * np.linalg.norm(u)
    corrected = _quietly(body, fixed, n_modes=N_MODES, extra_vectors=u[:, None])
    assert np.linalg.norm(_reduced_static(corrected, f) - u) < 1e-9 * np.linalg.norm(u)


def test_a_truly_dependent_vector_is_dropped_with_a_warning_naming_it(plate):
    mesh, body, fixed, free, K = plate
    _f1, u1 = _load_and_static_shape(mesh, free, K, (0.375, 0.4, T))
    _f2, u2 = _load_and_static_shape(mesh, free, K, (0.75, 0.2, T))
    mode = _quietly(body, fixed, n_modes=N_MODES).vectors[:, 1]  # a normal mode, M-norm 1
    dependent = 1e6 * (0.3 * mode + 2e5 * u2)  # a mode plus the extra vector u2, at another scale
    independent = _quietly(body, fixed, n_modes=N_MODES, extra_vectors=np.column_stack([u1, u2]))
    with pytest.warns(BasisWarning, match=r"extra_vectors\[:, 2\] is linearly dependent") as caught:
        basis = craig_bampton(body, fixed, n_modes=N_MODES, extra_vectors=np.column_stack([u1, u2, dependent]))
    assert len(caught) == 1
    assert basis.size == N_MODES + 2 and basis.n_extra == 2
    assert la.subspace_angles(independent.vectors, basis.vectors).max() < 1e-10


def test_an_extra_vector_only_on_fixed_dofs_is_dropped_with_a_warning(plate):
    mesh, body, fixed, _free, _K = plate
    on_fixed = np.zeros((3 * mesh.n_nodes, 1))
    on_fixed[3 * fixed[0] + 2] = 1.0
    with pytest.warns(BasisWarning, match=r"extra_vectors\[:, 0\] is zero outside the fixed DOFs"):
        basis = craig_bampton(body, fixed, n_modes=N_MODES, extra_vectors=on_fixed)
    assert basis.size == N_MODES and basis.n_extra == 0
