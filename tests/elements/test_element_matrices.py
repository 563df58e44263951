"""Element matrices of every registered solid element (Tet4, Tet10, Hex8, Hex20) against theory.

Patch tests on distorted meshes, mass conservation (consistent and lumped), the
spectrum of K_e (exactly the six rigid modes in its null space) and closed forms
(the unit right tet, the uniaxially stretched cube).
"""

import numpy as np
import pytest
import scipy.sparse.linalg as spla

import corotate as cr
from corotate import _core
from corotate.mesh import SOLID_ELEMENTS

ELEMENTS = SOLID_ELEMENTS  # every registered solid (the core's cell-type table)
FACTS = {facts["generator_name"]: facts for facts in cr.cell_types().values()}
CELL_TYPE = {element: facts["name"] for element, facts in FACTS.items()}
NODES_PER_CELL = {element: facts["num_nodes"] for element, facts in FACTS.items()}

E, NU, RHO = 2.5e6, 0.3, 1200.0
SIZE = np.array([1.2, 1.0, 0.8])
CELLS = (3, 3, 3)  # 8 interior corner nodes (hex20: 44 interior nodes incl. mid-edge ones)


def material():
    return cr.Material(E=E, nu=NU, density=RHO)


def core_material():
    return _core.Material(E, NU, RHO)


def lame():
    lam = E * NU / ((1 + NU) * (1 - 2 * NU))
    mu = E / (2 * (1 + NU))
    return lam, mu


def distorted_box(element, seed=1, amount=0.1):
    """box(SIZE, CELLS) with every interior node moved randomly by up to
    `amount` x the cell size in each axis (for hex20 this curves the interior
    edges: the mid-edge nodes move independently; quadratic simplices keep
    their mid-edge nodes on straight edges, the cells their stiffness rule
    integrates exactly). Returns (mesh, interior)."""
    m = cr.box(SIZE, CELLS, element)
    p = m.points.copy()
    on_boundary = np.any(np.isclose(p, 0.0) | np.isclose(p, SIZE), axis=1)
    interior = np.flatnonzero(~on_boundary)
    h = (SIZE / np.array(CELLS)).min()
    rng = np.random.default_rng(seed)
    p[interior] += rng.uniform(-amount, amount, (len(interior), 3)) * h
    facts = FACTS[element]
    if facts["domain"] == "simplex" and facts["order"] == 2:
        corners = facts["num_corners"]
        for i, (a, b) in enumerate(facts["edges"]):
            p[m.cells[:, corners + i]] = 0.5 * (p[m.cells[:, a]] + p[m.cells[:, b]])
    return cr.Mesh(p, m.cells, m.cell_type), interior


def reference_element(element):
    """Rest nodes (k, 3) of one undistorted element: unit right tet or unit cube."""
    if element == "tet4":
        return np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
    m = cr.box((1, 1, 1), (1, 1, 1), element)
    return m.points[m.cells[0]]


def distorted_element(element, seed=3):
    """A single element: reference nodes under a random stretch/shear plus a
    random 10% perturbation of every node (hex20: curved edges)."""
    rng = np.random.default_rng(seed)
    x = reference_element(element)
    A = np.diag([1.3, 0.9, 0.7]) + 0.15 * rng.uniform(-1, 1, (3, 3))
    x = x @ A.T + rng.normal(size=3)
    x += 0.1 * rng.uniform(-1, 1, x.shape)
    return x


def rigid_modes(x):
    """(3k, 6): three translations and three infinitesimal rotations w x X
    about the centroid of nodes x (k, 3), DOF = 3*node + axis."""
    k = len(x)
    c = x - x.mean(axis=0)
    modes = []
    for axis in range(3):
        t = np.zeros((k, 3))
        t[:, axis] = 1.0
        modes.append(t.ravel())
    for axis in range(3):
        w = np.zeros(3)
        w[axis] = 1.0
        modes.append(np.cross(w, c).ravel())
    return np.array(modes).T


# -- patch test ------------------------------------------------------------


@pytest.mark.parametrize("element", ELEMENTS)
def test_patch_test_reproduces_linear_field(element):
    mesh, interior = distorted_box(element)
    assert np.all(mesh.cell_volumes() > 0)
    body = cr.Body(mesh, material(), model="linear")
    K = body.stiffness_matrix().tocsr()
    n = mesh.n_nodes
    assert K.shape == (3 * n, 3 * n)

    rng = np.random.default_rng(7)
    G = 1e-3 * rng.normal(size=(3, 3))
    a = 1e-3 * rng.normal(size=3)
    u_exact = (a + mesh.points @ G.T).ravel()

    free = (3 * interior[:, None] + np.arange(3)).ravel()
    bound = np.setdiff1d(np.arange(3 * n), free)
    K_ff = K[free][:, free].tocsc()
    K_fb = K[free][:, bound]
    u_free = spla.spsolve(K_ff, -(K_fb @ u_exact[bound]))

    err = np.abs(u_free - u_exact[free]).max() / np.abs(u_exact[free]).max()
    assert err < 1e-10, f"{element}: interior displacement off the linear field by {err:.2e} (relative)"


@pytest.mark.parametrize("element", ELEMENTS)
@pytest.mark.parametrize("model", ["linear", "corotational"])
def test_linear_field_has_no_interior_forces(element, model):
    # A homogeneous strain gives constant stress: every interior node is in
    # equilibrium, only boundary nodes carry (traction) forces. Small G, so the
    # co-rotational model's rotation is near identity but not identity.
    mesh, interior = distorted_box(element, seed=2)
    body = cr.Body(mesh, material(), model=model)
    rng = np.random.default_rng(11)
    G = 1e-3 * rng.normal(size=(3, 3))
    G = 0.5 * (G + G.T)  # pure strain: no rotation, so corotational == linear here
    x = mesh.points + 0.01 + mesh.points @ G.T
    f = body.internal_forces(x)
    boundary = np.setdiff1d(np.arange(mesh.n_nodes), interior)
    f_scale = np.abs(f[boundary]).max()
    h = (SIZE / np.array(CELLS)).min()
    # Boundary forces are of the order E |G| h^2: the test is not vacuous.
    assert f_scale > 0.05 * E * np.abs(G).max() * h**2
    assert np.abs(f[interior]).max() < 1e-10 * f_scale
    # Net force of the whole body vanishes (internal forces are self-equilibrated).
    assert np.abs(f.sum(axis=0)).max() < 1e-10 * f_scale


# -- mass ------------------------------------------------------------------


@pytest.mark.parametrize("element", ELEMENTS)
def test_element_mass_sums_to_rho_v(element):
    mesh, _ = distorted_box(element, seed=4)
    mat = core_material()
    volumes = []
    for e, cell in enumerate(mesh.cells):
        d = _core.element_matrices(CELL_TYPE[element], mesh.points[cell], mat)
        m, lumped, vol = np.asarray(d["mass"]), np.asarray(d["lumped_mass"]), d["volume"]
        k = NODES_PER_CELL[element]
        assert m.shape == (k, k) and lumped.shape == (k,)
        np.testing.assert_allclose(m, m.T, rtol=0, atol=1e-14 * np.abs(m).max())
        assert m.sum() == pytest.approx(RHO * vol, rel=1e-12)
        assert lumped.sum() == pytest.approx(RHO * vol, rel=1e-12)
        assert np.all(lumped > 0), f"element {e}: non-positive lumped mass {lumped.min()}"
        # The consistent mass is positive definite.
        assert np.linalg.eigvalsh(m).min() > 0
        volumes.append(vol)
    volumes = np.array(volumes)
    # Only interior nodes moved, so the element volumes still tile the box.
    assert volumes.sum() == pytest.approx(np.prod(SIZE), rel=1e-12)
    np.testing.assert_allclose(volumes, mesh.cell_volumes(), rtol=1e-12)


@pytest.mark.parametrize("element", ELEMENTS)
@pytest.mark.parametrize("lumped", [False, True])
def test_assembled_mass_totals_3_rho_v(element, lumped):
    mesh, _ = distorted_box(element, seed=5)
    body = cr.Body(mesh, material())
    M = body.mass_matrix(lumped=lumped)
    n = mesh.n_nodes
    assert M.shape == (3 * n, 3 * n)
    assert M.sum() == pytest.approx(3 * RHO * np.prod(SIZE), rel=1e-12)
    # Each axis carries the full mass and axes do not couple: M = m (x) I3.
    Md = M.toarray()
    for axis in range(3):
        assert Md[axis::3, axis::3].sum() == pytest.approx(RHO * np.prod(SIZE), rel=1e-12)
    for a in range(3):
        for b in range(3):
            if a != b:
                assert np.abs(Md[a::3, b::3]).max() == 0.0
    np.testing.assert_allclose(Md[0::3, 0::3], Md[1::3, 1::3], rtol=0, atol=0)
    if lumped:
        off_diagonal = Md - np.diag(np.diag(Md))
        assert np.abs(off_diagonal).max() == 0.0
        assert np.all(np.diag(Md) > 0)


def test_tet4_consistent_mass_closed_form():
    # m_ab = rho V / 20 (1 + delta_ab) for the linear tet; lumped = rho V / 4.
    x = distorted_element("tet4")
    vol = np.linalg.det(x[1:] - x[0]) / 6.0
    assert vol > 0
    d = _core.element_matrices("tetra", x, core_material())
    assert d["volume"] == pytest.approx(vol, rel=1e-13)
    expected = RHO * vol / 20.0 * (np.ones((4, 4)) + np.eye(4))
    np.testing.assert_allclose(d["mass"], expected, rtol=1e-13)
    np.testing.assert_allclose(d["lumped_mass"], np.full(4, RHO * vol / 4), rtol=1e-13)


def test_hex20_lumped_mass_is_hrz():
    # Row sums of the serendipity mass are negative at the corners, so the
    # lumped mass must be HRZ: the consistent diagonal scaled to the total.
    x = distorted_element("hex20")
    d = _core.element_matrices("hexahedron20", x, core_material())
    m = np.asarray(d["mass"])
    lumped = np.asarray(d["lumped_mass"])
    assert m.sum(axis=1)[:8].max() < 0  # why row-sum lumping cannot be used
    assert np.all(lumped > 0)
    expected = np.diag(m) * m.sum() / np.trace(m)
    np.testing.assert_allclose(lumped, expected, rtol=1e-12)
    assert lumped.sum() == pytest.approx(RHO * d["volume"], rel=1e-12)


@pytest.mark.parametrize("element", ["tet4", "hex8"])
def test_low_order_lumped_mass_is_row_sum(element):
    x = distorted_element(element)
    d = _core.element_matrices(CELL_TYPE[element], x, core_material())
    np.testing.assert_allclose(d["lumped_mass"], np.asarray(d["mass"]).sum(axis=1), rtol=1e-13)


# -- stiffness spectrum ----------------------------------------------------


@pytest.mark.parametrize("element", ELEMENTS)
def test_element_stiffness_has_exactly_six_rigid_zero_modes(element):
    x = distorted_element(element)
    d = _core.element_matrices(CELL_TYPE[element], x, core_material())
    K = np.asarray(d["stiffness"])
    k = NODES_PER_CELL[element]
    assert K.shape == (3 * k, 3 * k)
    assert np.array_equal(K, K.T)

    ev = np.linalg.eigvalsh(K)
    top = ev.max()
    assert ev.min() > -1e-10 * top  # positive semi-definite
    assert np.all(np.abs(ev[:6]) < 1e-10 * top), ev[:7] / top
    assert ev[6] > 1e-4 * top, f"a seventh (spurious) zero-energy mode: {ev[6] / top:.2e}"

    # The null space is spanned by the rigid modes.
    modes = rigid_modes(x)
    K_norm = np.abs(K).max()
    for j in range(6):
        r = K @ modes[:, j]
        assert np.abs(r).max() < 1e-11 * K_norm * np.abs(modes[:, j]).max()
    # ... and a non-rigid mode (a stretch) has energy.
    stretch = np.zeros_like(x)
    stretch[:, 0] = x[:, 0]
    assert stretch.ravel() @ K @ stretch.ravel() > 1e-3 * top


@pytest.mark.parametrize("element", ELEMENTS)
def test_element_stiffness_independent_of_rigid_placement(element):
    # K_e of a rigidly rotated element is Q K_e Q^T (block-wise).
    x = distorted_element(element)
    theta = 0.7
    axis = np.array([1.0, 2.0, -0.5]) / np.linalg.norm([1.0, 2.0, -0.5])
    W = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    Q = np.eye(3) + np.sin(theta) * W + (1 - np.cos(theta)) * W @ W
    K = np.asarray(_core.element_matrices(CELL_TYPE[element], x, core_material())["stiffness"])
    Kq = np.asarray(_core.element_matrices(CELL_TYPE[element], x @ Q.T + 5.0, core_material())["stiffness"])
    k = len(x)
    big = np.kron(np.eye(k), Q)
    np.testing.assert_allclose(Kq, big @ K @ big.T, rtol=0, atol=1e-11 * np.abs(K).max())


# -- closed forms ----------------------------------------------------------


def test_tet4_unit_right_tet_stiffness_closed_form():
    x = reference_element("tet4")
    d = _core.element_matrices("tetra", x, core_material())
    K = np.asarray(d["stiffness"])
    # Gradients of N0 = 1 - x - y - z, N1 = x, N2 = y, N3 = z.
    grads = np.array([[-1, -1, -1], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
    # Strain order here: xx, yy, zz, xy, yz, zx (engineering shear), a
    # different Voigt order from the library's on purpose.
    B = np.zeros((6, 12))
    for a, (gx, gy, gz) in enumerate(grads):
        c = 3 * a
        B[0, c] = gx
        B[1, c + 1] = gy
        B[2, c + 2] = gz
        B[3, c], B[3, c + 1] = gy, gx
        B[4, c + 1], B[4, c + 2] = gz, gy
        B[5, c], B[5, c + 2] = gz, gx
    lam, mu = lame()
    H = np.zeros((6, 6))
    H[:3, :3] = lam
    H[:3, :3] += 2 * mu * np.eye(3)
    H[3:, 3:] = mu * np.eye(3)
    V = 1.0 / 6.0
    expected = V * B.T @ H @ B
    assert d["volume"] == pytest.approx(V, rel=1e-14)
    np.testing.assert_allclose(K, expected, rtol=0, atol=1e-12 * np.abs(expected).max())
    np.testing.assert_allclose(d["centre_gradient"], grads, rtol=0, atol=1e-14)
    # Spot values: K[0,0] = V (lam + 2 mu + 2 mu) ... from the hand formula.
    assert K[0, 0] == pytest.approx(V * (lam + 2 * mu + mu + mu), rel=1e-13)
    assert K[3, 3] == pytest.approx(V * (lam + 2 * mu), rel=1e-13)


@pytest.mark.parametrize("cells", [(1, 1, 1), (2, 2, 2)])
def test_hex8_cube_uniaxial_stretch_gives_youngs_modulus(cells):
    # Unit cube, u_x = 0 on x = 0 and u_x = eps on x = 1, lateral faces free
    # (only rigid motions removed): uniaxial stress, exactly representable by
    # trilinear elements. Reaction on x = 1 is E eps A, lateral strain -nu eps.
    eps = 1e-3
    mesh = cr.box((1, 1, 1), cells, "hex8")
    body = cr.Body(mesh, material(), model="linear")
    K = body.stiffness_matrix().tocsr()
    n = mesh.n_nodes
    p = mesh.points
    x0 = mesh.nodes_on_plane("x", 0.0)
    x1 = mesh.nodes_on_plane("x", 1.0)
    origin = mesh.nearest_node((0, 0, 0))
    y_corner = mesh.nearest_node((0, 1, 0))
    prescribed = {}
    for i in x0:
        prescribed[3 * i] = 0.0
    for i in x1:
        prescribed[3 * i] = eps
    prescribed[3 * origin + 1] = 0.0
    prescribed[3 * origin + 2] = 0.0
    prescribed[3 * y_corner + 2] = 0.0  # stops the rotation about x
    fixed = np.array(sorted(prescribed))
    u_fixed = np.array([prescribed[d] for d in fixed])
    free = np.setdiff1d(np.arange(3 * n), fixed)
    u = np.zeros(3 * n)
    u[fixed] = u_fixed
    u[free] = spla.spsolve(K[free][:, free].tocsc(), -(K[free][:, fixed] @ u_fixed))

    f = (K @ u).reshape(n, 3)  # reactions = forces needed to hold u
    assert f[x1, 0].sum() == pytest.approx(E * eps * 1.0, rel=1e-10)
    assert f[x0, 0].sum() == pytest.approx(-E * eps * 1.0, rel=1e-10)
    # Uniaxial stress: every nodal force is along x.
    assert np.abs(f[:, 1:]).max() < 1e-10 * E * eps
    U = u.reshape(n, 3)
    # Lateral contraction -nu eps everywhere (free lateral faces).
    np.testing.assert_allclose(U[:, 1], -NU * eps * p[:, 1], rtol=0, atol=1e-12)
    np.testing.assert_allclose(U[:, 2], -NU * eps * p[:, 2], rtol=0, atol=1e-12)
    np.testing.assert_allclose(U[:, 0], eps * p[:, 0], rtol=0, atol=1e-12)
    # Energy = 1/2 E eps^2 V.
    assert 0.5 * u @ (K @ u) == pytest.approx(0.5 * E * eps**2, rel=1e-10)
