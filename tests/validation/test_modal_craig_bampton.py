"""Craig-Bampton reduction against the full linear FE model of a Hex20 cantilever.

Beam 10 x 1 x 1 (hex20, 10 x 1 x 1 cells), nu = 0, clamped at x = 0: the model of
test_cantilever_frequency.py, whose full first frequency agrees with the Timoshenko beam.

* Statics with a constraint mode at the loaded node: the constraint modes span the static
  response to any load at the interface nodes, so the reduced answer is the full one (the
  test asks 1e-6; round-off gives ~1e-13).
* Normal modes only: the static error is the load's share in the modes left out. In the
  energy norm it is sum_{j > m} (phi_j^T f)^2 / omega_j^2 and can only shrink as m grows.
* Frequencies: a basis of normal modes only has exactly the full model's lowest
  eigenvalues; adding constraint modes gives Rayleigh-Ritz upper bounds.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse.linalg as sla
from cantilever_support import timoshenko_first_frequency

import corotate as cr
from corotate.modal import BasisWarning, craig_bampton

E, NU, RHO = 1.0e7, 0.0, 1000.0
L, B, H = 10.0, 1.0, 1.0


@pytest.fixture(scope="module")
def cantilever():
    mesh = cr.beam(L, B, H, cells=(10, 1, 1), element="hex20")
    body = cr.Body(mesh, cr.Material(E=E, nu=NU, density=RHO), model="linear")
    fixed = mesh.nodes_on_plane("x", 0.0)
    free = np.setdiff1d(np.arange(3 * mesh.n_nodes), (3 * fixed[:, None] + np.arange(3)).ravel())
    K = body.stiffness_matrix().tocsc()
    M = body.mass_matrix().tocsc()
    return mesh, body, fixed, free, K, M


def _full_static(K, free, f):
    u = np.zeros(K.shape[0])
    u[free] = sla.spsolve(K[free][:, free].tocsc(), f[free])
    return u


def _reduced_static(basis, f):
    return basis.vectors @ ((basis.vectors.T @ f) / basis.eigenvalues)


def test_basis_is_orthonormalised(cantilever):
    mesh, body, fixed, _free, K, M = cantilever
    tip = mesh.nearest_node((L, B, H))
    basis = craig_bampton(body, fixed, n_modes=6, interface_nodes=[tip])
    P = basis.vectors
    assert P.shape == (3 * mesh.n_nodes, 9) and P.flags.c_contiguous
    np.testing.assert_allclose(P.T @ M @ P, np.eye(9), atol=1e-10)
    np.testing.assert_allclose(P.T @ K @ P, np.diag(basis.eigenvalues), atol=1e-9 * basis.eigenvalues.max())
    assert np.all(np.diff(basis.eigenvalues) >= 0)
    assert np.all(P[basis.fixed_dofs] == 0.0)
    assert basis.interface_nodes.tolist() == [tip]


def test_constraint_modes_give_the_exact_static_deflection(cantilever):
    mesh, body, fixed, free, K, _M = cantilever
    tip = mesh.nearest_node((L, B / 2, H))
    f = np.zeros(3 * mesh.n_nodes)
    f[3 * tip : 3 * tip + 3] = (300.0, -200.0, -1000.0)
    u_full = _full_static(K, free, f)
    basis = craig_bampton(body, fixed, n_modes=4, interface_nodes=[tip])
    u_red = _reduced_static(basis, f)
    err = np.linalg.norm(u_red - u_full) / np.linalg.norm(u_full)
    assert err < 1e-6  # measured 3e-12


def test_normal_modes_only_converge_to_the_static_deflection(cantilever):
    mesh, body, fixed, free, K, _M = cantilever
    tip = mesh.nearest_node((L, B / 2, H))
    f = np.zeros(3 * mesh.n_nodes)
    f[3 * tip + 2] = -1000.0
    u_full = _full_static(K, free, f)
    energy_errors, tip_errors = [], []
    for m in (1, 2, 4, 8, 16, 32):
        basis = craig_bampton(body, fixed, n_modes=m)
        e = _reduced_static(basis, f) - u_full
        energy_errors.append(np.sqrt(e @ K @ e) / np.sqrt(u_full @ K @ u_full))
        tip_errors.append(abs(e[3 * tip + 2]) / abs(u_full[3 * tip + 2]))
    # The energy-norm error is the load's share in the omitted modes: it cannot grow.
    assert np.all(np.diff(energy_errors) < 0)
    # The first mode bends sideways (square section: the two bending modes are degenerate),
    # so one mode misses the tip deflection; the local point-load field needs many modes
    # (measured tip errors: 1 mode 89 %, 2 modes 3.1 %, 8 modes 0.23 %, 32 modes 0.075 %).
    assert tip_errors[0] > 10 * tip_errors[-1]
    assert tip_errors[-1] < 0.01


def test_reduced_frequencies_equal_the_full_lowest_ones(cantilever):
    mesh, body, fixed, free, K, M = cantilever
    lam_full = np.sort(sla.eigsh(K[free][:, free].tocsc(), k=8, M=M[free][:, free].tocsc(), sigma=0.0)[0])
    normal = craig_bampton(body, fixed, n_modes=8)
    np.testing.assert_allclose(normal.eigenvalues, lam_full, rtol=1e-9)
    # With constraint modes too: Rayleigh-Ritz upper bounds, the lowest ones close (the
    # normal modes are computed with the tip node held; measured +1.9e-4 for the first two).
    tip = mesh.nearest_node((L, B / 2, H))
    cb = craig_bampton(body, fixed, n_modes=6, interface_nodes=[tip])
    assert np.all(cb.eigenvalues[:6] >= lam_full[:6] * (1 - 1e-10))
    np.testing.assert_allclose(cb.eigenvalues[:2], lam_full[:2], rtol=5e-4)
    # The first bending frequency against the Timoshenko beam (see test_cantilever_frequency).
    f_eb = 1.8751040687119611**2 / (2 * np.pi) * np.sqrt(E * B * H**3 / 12 / (RHO * B * H * L**4))
    f_timo = timoshenko_first_frequency(E, NU, RHO, L, B, H, f_eb)
    assert normal.frequencies[0] == pytest.approx(f_timo, rel=0.003)
    assert normal.frequencies[0] == pytest.approx(f_eb, rel=0.01)


def test_dependent_extra_vectors_are_dropped(cantilever):
    _mesh, body, fixed, _free, _K, _M = cantilever
    first = craig_bampton(body, fixed, n_modes=3)
    with pytest.warns(BasisWarning, match=r"extra_vectors\[:, [01]\] is linearly dependent") as caught:
        again = craig_bampton(body, fixed, n_modes=3, extra_vectors=first.vectors[:, :2] * 5.0)
    assert len(caught) == 2
    assert again.size == 3 and again.n_extra == 0
    np.testing.assert_allclose(again.eigenvalues, first.eigenvalues, rtol=1e-9)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"n_modes": -1}, "n_modes"),
        ({"n_modes": 2.5}, "n_modes"),
        ({"n_modes": 2, "interface_nodes": [10**6]}, "out of range"),
        ({"n_modes": 2, "interface_nodes": [0]}, "also fixed"),
        ({"n_modes": 0}, "empty"),
        ({"n_modes": 2, "extra_vectors": np.ones((5, 1))}, "extra_vectors"),
        ({"n_modes": 2, "extra_vectors": "nan"}, "finite"),
        ({"n_modes": 2, "fixed_dofs": [-1]}, "fixed_dofs"),
    ],
)
def test_bad_input_is_refused(cantilever, kwargs, message):
    mesh, body, fixed, _free, _K, _M = cantilever
    if isinstance(kwargs.get("extra_vectors"), str):
        kwargs = {**kwargs, "extra_vectors": np.full((3 * mesh.n_nodes, 1), np.nan)}
    with pytest.raises(ValueError, match=message):
        craig_bampton(body, fixed, **kwargs)


def test_an_unheld_body_is_refused(cantilever):
    _mesh, body, *_ = cantilever
    with pytest.raises(RuntimeError, match="singular"):
        craig_bampton(body, [], n_modes=2)


def test_a_tet10_body_reduces_to_the_same_first_frequency():
    # Modal reduction needs nothing of the element: a Tet10 cantilever (10 x 1 x 1 cuboids,
    # comparable to the Hex20 one above) has the Timoshenko beam's first bending frequency
    # (measured +0.09 %).
    mesh = cr.beam(L, B, H, cells=(10, 1, 1), element="tet10")
    body = cr.Body(mesh, cr.Material(E=E, nu=NU, density=RHO), model="linear")
    basis = craig_bampton(body, mesh.nodes_on_plane("x", 0.0), n_modes=4)
    f_eb = 1.8751040687119611**2 / (2 * np.pi) * np.sqrt(E * B * H**3 / 12 / (RHO * B * H * L**4))
    f_timo = timoshenko_first_frequency(E, NU, RHO, L, B, H, f_eb)
    assert basis.frequencies[0] == pytest.approx(f_timo, rel=0.002)
