"""Hyperelastic force models ("stvk", "neohookean", "fixed_corotated" on tets and hexes; "stvk"
membranes on triangles): forces are minus the energy gradient and the stiffness is the
Hessian (central differences on random deformed elements), rigid motions are free, at rest
every model has the linear FEM stiffness, the StVK tangent splits as K_0 + K_u + K_sigma,
the PSD projection, the StVK uniaxial-stretch closed form, and bad input."""

import numpy as np
import pytest
from derivative_support import gradient_fd, jacobian_fd, rel_err
from uniaxial_support import pull_bar

import corotate as cr
from corotate import _core
from corotate.mesh import SOLID_ELEMENTS

MAT = cr.Material(E=1e6, nu=0.3, density=1000.0)
LAMBDA, MU = MAT.lame
SOLIDS = SOLID_ELEMENTS  # every registered solid (the core's cell-type table)
# Every hyperelastic law the core registers (models/registry.hpp): a new law is tested here
# without editing this file.
LAWS = [m for m in _core.model_names() if m not in ("linear", "corotational")]
THICKNESS = 0.01


def rotation(axis, angle):
    axis = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    W = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * W + (1 - np.cos(angle)) * W @ W


def solid(element, law, **kw):
    """One cube (six tets, one hex8 or one hex20) of a slightly irregular rest shape."""
    mesh = cr.box((1.0, 0.8, 1.2), (1, 1, 1), element)
    return mesh, cr.Body(mesh, MAT, model=law, **kw)


def sheet(**kw):
    """A square sheet of two triangles, tilted out of the z = 0 plane."""
    flat = cr.rectangle((1.0, 0.7), (1, 1))
    mesh = cr.Mesh(flat.points @ rotation((1.0, 0.3, 0.0), 0.4).T, flat.cells, "triangle")
    return mesh, cr.Body(mesh, MAT, model="stvk", thickness=THICKNESS, **kw)


def random_deformed(points, seed, amplitude=0.2):
    """A random rotation, a moderate homogeneous stretch and nodal noise."""
    rng = np.random.default_rng(seed)
    A = rotation(rng.standard_normal(3), 1.0) @ (np.eye(3) + 0.15 * rng.standard_normal((3, 3)))
    return points @ A.T + amplitude * rng.uniform(-1, 1, points.shape) * 0.5


def all_bodies():
    cases = [(e, law) for e in SOLIDS for law in LAWS] + [("triangle", "stvk")]
    return pytest.mark.parametrize("element,law", cases)


def make(element, law, **kw):
    return sheet(**kw) if element == "triangle" else solid(element, law, **kw)


# -- derivatives -----------------------------------------------------------


@all_bodies()
@pytest.mark.parametrize("seed", [0, 1])
def test_forces_are_minus_energy_gradient(element, law, seed):
    mesh, body = make(element, law)
    x = random_deformed(mesh.points, seed)
    f = body.internal_forces(x)
    g = gradient_fd(body.energy, x, 1e-6)
    assert rel_err(f, -g) < 1e-6


@all_bodies()
@pytest.mark.parametrize("seed", [0, 1])
def test_stiffness_is_the_energy_hessian(element, law, seed):
    mesh, body = make(element, law)
    x = random_deformed(mesh.points, seed)
    K = body.stiffness_matrix(x).toarray()
    K_fd = -jacobian_fd(body.internal_forces, x, 1e-6)
    assert rel_err(K, K_fd) < 1e-6
    np.testing.assert_array_equal(K, K.T)


@pytest.mark.parametrize("law", LAWS)
def test_constitutive_laws_stress_and_tangent(law):
    """P = dW/dF and dP/dF, law by law, at a random F (and an inverted one)."""
    rng = np.random.default_rng(3)
    for F in (np.eye(3) + 0.3 * rng.standard_normal((3, 3)), np.diag([1.1, 0.9, -0.5]) @ rotation((1, 1, 0), 0.3)):
        if law == "stvk" and np.linalg.det(F) < 0:
            continue  # same polynomial; nothing new
        W, P, A = _core.constitutive_law(law, F, MAT._core())
        if np.linalg.det(F) < 0 and not np.isfinite(W):
            # A law undefined under inversion must say so: infinite energy, NaN stress and
            # tangent (so a step into inversion fails loudly), never finite wrong values.
            assert W == np.inf and np.isnan(P).all() and np.isnan(A).all()
            continue
        P_fd = gradient_fd(lambda G: _core.constitutive_law(law, G, MAT._core())[0], F, 1e-7)
        A_fd = jacobian_fd(lambda G: _core.constitutive_law(law, G.T, MAT._core())[1].T, F.T, 1e-7)
        assert rel_err(P, P_fd) < 1e-6
        assert rel_err(A, A_fd) < 1e-6  # column-major vec: transposes turn it into row-major DOFs


# -- rigid motion and the rest state ---------------------------------------


@all_bodies()
def test_rigid_motion_gives_no_force_and_no_energy(element, law):
    mesh, body = make(element, law)
    Q = rotation((1.0, 2.0, 3.0), 2.0)
    x = mesh.points @ Q.T + np.array([0.3, -1.7, 2.2])
    stretched = mesh.points.copy()
    stretched[:, 0] *= 1.01
    force_scale = np.abs(body.internal_forces(stretched)).max()
    energy_scale = body.energy(stretched)
    assert np.abs(body.internal_forces(x)).max() < 1e-10 * force_scale
    assert abs(body.energy(x)) < 1e-10 * energy_scale
    assert abs(body.energy(mesh.points)) < 1e-12 * energy_scale


@pytest.mark.parametrize("element", SOLIDS)
@pytest.mark.parametrize("law", LAWS)
def test_rest_stiffness_equals_linear_fem(element, law):
    mesh = cr.box((2.0, 1.0, 1.0), (2, 1, 1), element)
    K_lin = cr.Body(mesh, MAT, model="linear").stiffness_matrix().toarray()
    K = cr.Body(mesh, MAT, model=law).stiffness_matrix().toarray()
    assert rel_err(K, K_lin) < 1e-12


def plane_stress_stiffness(points, cells, thickness):
    """Linear plane-stress stiffness t A B^T D B of flat triangles in the z = 0 plane."""
    E, nu = MAT.E, MAT.nu
    D = E / (1 - nu**2) * np.array([[1, nu, 0], [nu, 1, 0], [0, 0, (1 - nu) / 2]])
    n = len(points)
    K = np.zeros((3 * n, 3 * n))
    for tri in cells:
        X = points[tri, :2]
        Dm = np.column_stack([X[1] - X[0], X[2] - X[0]])
        G = np.array([[-1, -1], [1, 0], [0, 1]]) @ np.linalg.inv(Dm)  # dN_a/dX
        area = 0.5 * abs(np.linalg.det(Dm))
        B = np.zeros((3, 9))
        for a in range(3):
            B[0, 3 * a] = G[a, 0]
            B[1, 3 * a + 1] = G[a, 1]
            B[2, 3 * a], B[2, 3 * a + 1] = G[a, 1], G[a, 0]
        dofs = np.ravel([[3 * i, 3 * i + 1, 3 * i + 2] for i in tri])
        K[np.ix_(dofs, dofs)] += thickness * area * B.T @ D @ B
    return K


def test_membrane_rest_stiffness_is_plane_stress():
    mesh = cr.rectangle((2.0, 1.0), (3, 2))
    body = cr.Body(mesh, MAT, model="stvk", thickness=THICKNESS)
    K = body.stiffness_matrix().toarray()
    assert rel_err(K, plane_stress_stiffness(mesh.points, mesh.cells, THICKNESS)) < 1e-12


def test_membrane_mass():
    mesh = cr.rectangle((2.0, 1.0), (3, 2))
    body = cr.Body(mesh, MAT, model="stvk", thickness=THICKNESS)
    total = MAT.density * THICKNESS * 2.0
    for lumped in (False, True):
        M = body.mass_matrix(lumped=lumped)
        ones = np.tile([1.0, 0.0, 0.0], mesh.n_nodes)
        assert ones @ (M @ ones) == pytest.approx(total, rel=1e-12)
    # One triangle: consistent m/12 [[2,1,1],[1,2,1],[1,1,2]] per axis, lumped m/3.
    one = cr.Body(cr.Mesh(mesh.points[[0, 3, 4]], [[0, 1, 2]], "triangle"), MAT, model="stvk", thickness=THICKNESS)
    m = MAT.density * THICKNESS * mesh.cell_volumes()[0]
    assert mesh.cell_volumes()[0] == pytest.approx(1 / 6)
    np.testing.assert_allclose(
        one.mass_matrix().toarray()[::3, ::3], m / 12 * (np.ones((3, 3)) + np.eye(3)), rtol=1e-12
    )
    np.testing.assert_allclose(one.mass_matrix(lumped=True).toarray()[::3, ::3], m / 3 * np.eye(3), rtol=1e-12)


# -- K_T = K_0 + K_u + K_sigma (paper eq. 6) -----------------------------------------


def hex8_gradients(X):
    """dN/dX (8, 3) and weight x det J at the 2x2x2 Gauss points of a Hex8 with nodes X (8, 3)."""
    s = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1], [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]])
    g = 1 / np.sqrt(3)
    out = []
    for xi in np.array(np.meshgrid([-g, g], [-g, g], [-g, g])).reshape(3, -1).T:
        f = 1 + s * xi
        dN = np.column_stack([s[:, d] * np.prod(np.delete(f, d, axis=1), axis=1) / 8 for d in range(3)])
        J = X.T @ dN
        out.append((dN @ np.linalg.inv(J), np.linalg.det(J)))
    return out


def green_strain_B(F, G):
    """B_L (6, 24): Voigt (xx, yy, zz, yz, xz, xy, engineering shear) variation of the Green
    strain, dE_kl = sym(F^T dF)_kl with dF = sum_a dx_a G_a^T."""
    pairs = [(0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)]
    B = np.zeros((6, 3 * len(G)))
    for r, (k, l) in enumerate(pairs):
        for a in range(len(G)):
            for i in range(3):
                B[r, 3 * a + i] = F[i, k] * G[a, l] + (F[i, l] * G[a, k] if k != l else 0.0)
    return B


def test_stvk_hex_tangent_splits_into_K0_Ku_Ksigma():
    mesh = cr.box((1.0, 0.8, 1.2), (1, 1, 1), "hex8")
    body = cr.Body(mesh, MAT, model="stvk")
    x = random_deformed(mesh.points, 5)
    H = MAT._core().elasticity_matrix()
    K0 = np.zeros((24, 24))
    Ku = np.zeros((24, 24))
    for G, w in hex8_gradients(mesh.points[mesh.cells[0]]):
        F = x[mesh.cells[0]].T @ G
        B0, BL = green_strain_B(np.eye(3), G), green_strain_B(F, G)
        K0 += w * B0.T @ H @ B0
        Ku += w * (BL.T @ H @ BL - B0.T @ H @ B0)  # initial-displacement matrix
    order = np.ravel([[3 * i, 3 * i + 1, 3 * i + 2] for i in mesh.cells[0]])  # element DOFs, 3a + axis
    K_T = body.stiffness_matrix(x).toarray()[np.ix_(order, order)]
    K_sigma = body.geometric_stiffness(x).toarray()[np.ix_(order, order)]
    K_lin = cr.Body(mesh, MAT, model="linear").stiffness_matrix().toarray()[np.ix_(order, order)]
    assert rel_err(K0, K_lin) < 1e-12
    assert rel_err(K0 + Ku + K_sigma, K_T) < 1e-12
    assert np.abs(K_sigma).max() > 1e-2 * np.abs(K_T).max()  # a real stress state
    assert (
        np.abs(body.geometric_stiffness(mesh.points).toarray()).max() < 1e-12 * np.abs(K_lin).max()
    )  # no stress at rest


@pytest.mark.parametrize("element", ["hex20", "tet4", "triangle"])
def test_geometric_stiffness_scales_with_stress(element):
    """Under a uniform stretch F = s I, StVK's S = (3 lambda + 2 mu)(s^2 - 1)/2 I (plane-stress
    lambda for the sheet), so K_sigma = sum w (G S G^T) x I_3 is proportional to s^2 - 1 and
    positive semi-definite in tension."""
    mesh, body = make(element, "stvk")
    K1 = body.geometric_stiffness(1.1 * mesh.points).toarray()
    K2 = body.geometric_stiffness(1.2 * mesh.points).toarray()
    np.testing.assert_allclose(K2 * (1.1**2 - 1), K1 * (1.2**2 - 1), rtol=1e-12, atol=1e-9 * np.abs(K1).max())
    assert np.linalg.eigvalsh(K1).min() > -1e-9 * np.abs(K1).max()


def test_geometric_stiffness_needs_a_hyperelastic_model():
    mesh = cr.box((1, 1, 1), (1, 1, 1), "tet4")
    with pytest.raises(ValueError, match="'corotational' model has no separate geometric stiffness"):
        cr.Body(mesh, MAT).geometric_stiffness(mesh.points)


# -- PSD projection --------------------------------------------------------


@pytest.mark.parametrize("element", ["tet4", "hex8"])
def test_psd_projection(element):
    mesh = cr.box((1.0, 1.0, 1.0), (1, 1, 1), element)
    if element == "tet4":  # one element: K is the element matrix
        mesh = cr.Mesh(mesh.points[mesh.cells[0]], [[0, 1, 2, 3]], "tetra")
    exact = cr.Body(mesh, MAT, model="stvk")
    projected = cr.Body(mesh, MAT, model="stvk", project_psd=True)
    # Already PSD (rest, and a rotated stretch): the projection leaves K unchanged.
    for x in (mesh.points, 1.2 * mesh.points @ rotation((0, 1, 1), 0.7).T):
        np.testing.assert_array_equal(projected.stiffness_matrix(x).toarray(), exact.stiffness_matrix(x).toarray())
    # Compressed StVK is indefinite; the projection is the eigenvalue clamp of the exact K.
    # (At 20 % compression some modes have lost their stiffness, others not; beyond
    # 1/sqrt(3) every mode of a uniformly compressed StVK element is unstable.)
    x = 0.8 * mesh.points @ rotation((1, 0, 1), 0.3).T
    K = exact.stiffness_matrix(x).toarray()
    lam, V = np.linalg.eigh(K)
    assert lam.min() < -1e-2 * lam.max()
    Kp = projected.stiffness_matrix(x).toarray()
    assert np.linalg.eigvalsh(Kp).min() > -1e-9 * lam.max()
    np.testing.assert_allclose(Kp, V @ np.diag(np.maximum(lam, 0)) @ V.T, atol=1e-9 * lam.max())


# -- uniaxial stretch --------------------------------------------------------


def stvk_uniaxial_force(stretch, area):
    """Closed-form force of a StVK bar under uniaxial stretch with free lateral contraction.

    F = diag(l1, l2, l2); Green strain E11 = (l1^2 - 1)/2, E22 = E33 = (l2^2 - 1)/2.
    Second PK stress S = 2 mu E + lambda tr(E) I. Free lateral faces: S22 = 0, i.e.
        2 (lambda + mu) E22 + lambda E11 = 0  =>  E22 = -lambda / (2 (lambda + mu)) E11 = -nu E11,
    so l2 = sqrt(1 - nu (l1^2 - 1)), and then
        S11 = (2 mu + lambda) E11 + 2 lambda E22 = mu (3 lambda + 2 mu) / (lambda + mu) E11 = E_Young E11.
    The first PK stress P11 = l1 S11 is force per reference area, so the end force is
        f(l1) = A0 E_Young l1 (l1^2 - 1) / 2,
    softening relative to Hooke's A0 E (l1 - 1) only through the factor l1 (l1 + 1) / 2.
    """
    return area * MAT.E * stretch * (stretch**2 - 1) / 2


@pytest.mark.parametrize("element", ["tet4", "hex8"])
def test_stvk_uniaxial_stretch_matches_closed_form(element):
    """Static Newton solve (here, on Body's forces and stiffness) of a bar pulled by its end
    faces: x-displacement prescribed on both ends, lateral contraction free everywhere,
    rigid motions removed by three single-DOF supports."""
    L, w, h = 4.0, 1.0, 1.0
    body = cr.Body(cr.box((L, w, h), (4, 2, 2), element), MAT, model="stvk")
    for stretch, x, force in pull_bar(body, L, w, np.linspace(1.05, 1.5, 10), 1e-9 * MAT.E * w * h):
        assert force == pytest.approx(stvk_uniaxial_force(stretch, w * h), rel=1e-2)
        lateral = (x[:, 1].max() - x[:, 1].min()) / w
        assert lateral == pytest.approx(np.sqrt(1 - MAT.nu * (stretch**2 - 1)), rel=1e-2)


# -- robustness and bad input --------------------------------------------------------


def test_neohookean_and_fixed_corotated_stay_finite_when_inverted():
    mesh = cr.box((1.0, 1.0, 1.0), (1, 1, 1), "hex8")
    x = mesh.points * np.array([1.0, 1.0, -0.5])  # flipped through its bottom face
    for law in ("neohookean", "fixed_corotated"):
        body = cr.Body(mesh, MAT, model=law)
        f, K = body.internal_forces(x), body.stiffness_matrix(x).toarray()
        assert np.isfinite(body.energy(x)) and np.isfinite(f).all() and np.isfinite(K).all()
        assert body.energy(x) > 0


def test_zero_area_triangle_is_rejected_by_index():
    pts = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [2, 0, 0]]
    mesh = cr.Mesh(pts, [[0, 1, 2], [0, 1, 3]], "triangle")
    with pytest.raises(ValueError, match=r"element 1 \(triangle\) has zero area"):
        cr.Body(mesh, MAT, model="stvk", thickness=0.01)


def test_inverted_rest_tet_is_rejected_by_index():
    # The inverted tet stands apart: one sharing a face with the others would overlap them,
    # which the Mesh already refuses (corotate.mesh_checks).
    pts = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 1], [5, 0, 0], [6, 0, 0], [5, 1, 0], [5, 0, 1]]
    mesh = cr.Mesh(pts, [[0, 1, 2, 3], [1, 2, 3, 4], [5, 7, 6, 8]], "tetra")
    for law in LAWS:
        with pytest.raises(ValueError, match=r"element 2 \(tetra\) is inverted"):
            cr.Body(mesh, MAT, model=law)


def test_incompressible_material_is_rejected():
    with pytest.raises(ValueError, match=r"nu = 0.5.*incompressible"):
        cr.Material(E=1e6, nu=0.5)
    with pytest.raises(ValueError, match=r"nu = 0.6"):
        _core.Material(1e6, 0.6, 1000.0)  # the core's Material, which every model is built from, checks too


def test_triangle_options():
    mesh = cr.rectangle((1.0, 1.0), (2, 2))
    with pytest.raises(ValueError, match="needs thickness"):
        cr.Body(mesh, MAT, model="stvk")
    with pytest.raises(ValueError, match="thickness of the triangle sheet must be positive"):
        cr.Body(mesh, MAT, model="stvk", thickness=0.0)
    with pytest.raises(ValueError, match="'neohookean' is not available for triangle cells"):
        cr.Body(mesh, MAT, model="neohookean", thickness=0.01)
    with pytest.raises(ValueError, match="thickness applies to triangle sheets only"):
        cr.Body(cr.box((1, 1, 1), (1, 1, 1)), MAT, model="stvk", thickness=0.01)


def test_rectangle_generator():
    mesh = cr.rectangle((2.0, 1.0), (4, 3), origin=(1.0, -1.0))
    assert mesh.cell_type == "triangle" and mesh.n_nodes == 5 * 4 and mesh.n_cells == 2 * 12
    assert np.all(mesh.points[:, 2] == 0)
    np.testing.assert_allclose(mesh.points.min(axis=0), [1.0, -1.0, 0.0])
    np.testing.assert_allclose(mesh.points.max(axis=0), [3.0, 0.0, 0.0])
    assert mesh.cell_volumes().sum() == pytest.approx(2.0)
    x = mesh.points[mesh.cells]
    normals = np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0])
    assert np.all(normals[:, 2] > 0)  # counter-clockwise seen from +z
    with pytest.raises(ValueError, match="cells must be two integers"):
        cr.rectangle((1, 1), (0, 1))
