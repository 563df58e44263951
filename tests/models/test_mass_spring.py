"""Mass-spring model: forces, damping, stiffness and energy agree with each other and with
eqs. (1)-(2); the stiffness rule of the builders gives what it promises; bad input is
refused by name."""

import numpy as np
import pytest

import corotate as cr

RNG = np.random.default_rng(7)


def random_system(n_cells=(2, 1, 1)):
    """A small lattice with random stiffness, damping and rest lengths (off their distances)."""
    base = cr.MassSpringBody.lattice(n_cells, size=(1.0, 0.7, 0.5), E=1e5)
    m = base.n_springs
    k = base.stiffness * RNG.uniform(0.5, 2.0, m)
    d = RNG.uniform(0.1, 3.0, m)
    l0 = base.rest_lengths * RNG.uniform(0.8, 1.2, m)
    body = cr.MassSpringBody(base.nodes, base.springs, k, RNG.uniform(0.5, 2.0, base.n_nodes), d, l0)
    x = base.nodes + 0.15 * RNG.standard_normal(base.nodes.shape)
    return body, x


def test_forces_are_minus_energy_gradient_and_balance():
    body, x = random_system()
    f = body.internal_forces(x)
    h = 1e-6
    grad = np.zeros_like(x)
    for i in range(x.shape[0]):
        for a in range(3):
            xp, xm = x.copy(), x.copy()
            xp[i, a] += h
            xm[i, a] -= h
            grad[i, a] = (body.energy(xp) - body.energy(xm)) / (2 * h)
    scale = np.abs(f).max()
    np.testing.assert_allclose(f, -grad, atol=1e-6 * scale)
    # Central forces: no net force and no net torque (momentum and angular momentum kept).
    np.testing.assert_allclose(f.sum(axis=0), 0.0, atol=1e-10 * scale)
    np.testing.assert_allclose(np.cross(x, f).sum(axis=0), 0.0, atol=1e-9 * scale)


def test_energy_and_force_of_one_spring_follow_eq1():
    x = np.array([[0.0, 0.0, 0.0], [3.0, 4.0, 0.0]])
    body = cr.MassSpringBody(x, [[0, 1]], stiffness=10.0, masses=1.0, rest_lengths=[4.0])
    f = body.internal_forces(x)
    np.testing.assert_allclose(f[0], 10.0 * (5.0 - 4.0) * np.array([0.6, 0.8, 0.0]), rtol=1e-14)
    np.testing.assert_allclose(f[1], -f[0], rtol=1e-14)
    assert body.energy(x) == pytest.approx(0.5 * 10.0 * 1.0**2, rel=1e-14)


def test_damping_forces_follow_eq2_and_dissipate():
    body, x = random_system()
    v = RNG.standard_normal(x.shape)
    fd = body.damping_forces(x, v)
    # Eq. (2) by hand, spring by spring.
    ref = np.zeros_like(x)
    for (i, j), d in zip(body.springs, body.damping):
        e = x[j] - x[i]
        F = d * e * (e @ (v[j] - v[i])) / (e @ e)
        ref[i] += F
        ref[j] -= F
    np.testing.assert_allclose(fd, ref, rtol=1e-12, atol=1e-12 * np.abs(ref).max())
    np.testing.assert_allclose(fd.sum(axis=0), 0.0, atol=1e-10 * np.abs(fd).max())
    assert (fd * v).sum() < 0  # damping only removes energy
    # Linear in v: f_d = -C v with the damping matrix at x.
    C = body.damping_matrix(x)
    np.testing.assert_allclose(fd.ravel(), -(C @ v.ravel()), rtol=1e-10, atol=1e-12 * np.abs(fd).max())
    # A rigid translation is not damped.
    assert np.abs(body.damping_forces(x, np.tile([1.0, -2.0, 0.5], (x.shape[0], 1)))).max() < 1e-9


def test_stiffness_is_minus_force_derivative():
    body, x = random_system()
    K = body.stiffness_matrix(x).toarray()
    h = 1e-6
    J = np.zeros_like(K)
    for c in range(K.shape[0]):
        xp, xm = x.copy(), x.copy()
        xp.flat[c] += h
        xm.flat[c] -= h
        J[:, c] = -(body.internal_forces(xp) - body.internal_forces(xm)).ravel() / (2 * h)
    np.testing.assert_allclose(K, J, atol=1e-6 * np.abs(K).max())
    np.testing.assert_allclose(K, K.T, atol=1e-12 * np.abs(K).max())


def test_stiffness_bound_dominates_every_configuration():
    body, _ = random_system()
    B = body.stiffness_bound().toarray()
    for scale in (0.0, 0.3, 1.0):  # rest, moderate and strongly compressed / stretched
        x = body.nodes + scale * RNG.standard_normal(body.nodes.shape)
        K = body.stiffness_matrix(x).toarray()
        assert np.linalg.eigvalsh(B - K).min() > -1e-9 * np.abs(B).max()


def isotropic_energy_density(eps, E, nu):
    lam, mu = E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))
    return 0.5 * lam * np.trace(eps) ** 2 + mu * np.sum(eps * eps)


@pytest.mark.parametrize("cells", [(1, 1, 1), (2, 2, 2), (3, 4, 2)])
def test_lattice_rule_is_isotropic_with_E_and_quarter_poisson_at_any_resolution(cells):
    h = 0.25
    E = 2e6
    body = cr.MassSpringBody.lattice(cells, size=tuple(h * c for c in cells), E=E)
    K = body.stiffness_matrix()
    V = h**3 * np.prod(cells)
    for _ in range(3):
        eps = RNG.standard_normal((3, 3))
        eps = 0.5 * (eps + eps.T)
        u = (body.nodes @ eps.T).ravel()
        energy = 0.5 * u @ (K @ u)
        assert energy == pytest.approx(V * isotropic_energy_density(eps, E, 0.25), rel=1e-12)


def test_cloth_rule_is_an_isotropic_membrane_with_E_t_and_third_poisson():
    E, t = 3e5, 2e-3
    for n in (2, 5, 9):
        body = cr.MassSpringBody.cloth(n, n, size=(0.8, 0.8), E=E, thickness=t, bending=0.0)
        K = body.stiffness_matrix()
        eps2 = RNG.standard_normal((2, 2))
        eps2 = 0.5 * (eps2 + eps2.T)
        eps = np.zeros((3, 3))
        eps[:2, :2] = eps2
        u = (body.nodes @ eps.T).ravel()
        nu = 1.0 / 3.0  # plane stress: W = E / (2 (1 - nu^2)) ((e11 + e22)^2 - 2 (1 - nu) (e11 e22 - e12^2))
        W = E / (2 * (1 - nu**2)) * (np.trace(eps2) ** 2 - 2 * (1 - nu) * np.linalg.det(eps2))
        assert 0.5 * u @ (K @ u) == pytest.approx(0.8 * 0.8 * t * W, rel=1e-12)


def test_lattice_uniaxial_tension_gives_E_at_two_resolutions():
    """Uniaxial stress on a unit cube (symmetry supports, face load lumped by area): the
    measured Young's modulus and Poisson ratio do not depend on the resolution."""
    import scipy.sparse.linalg as sla

    E, F = 1e6, 100.0
    for n in (2, 4):
        body = cr.MassSpringBody.lattice((n, n, n), size=(1.0, 1.0, 1.0), E=E)
        x = body.nodes
        fixed = np.zeros((x.shape[0], 3), bool)
        for a in range(3):
            fixed[np.isclose(x[:, a], 0.0), a] = True
        f = np.zeros_like(x)
        face = np.isclose(x[:, 0], 1.0)
        w = np.where(np.isclose(x[:, 1] % 1.0, 0.0), 0.5, 1.0) * np.where(np.isclose(x[:, 2] % 1.0, 0.0), 0.5, 1.0)
        f[face, 0] = F * w[face] / w[face].sum()
        free = ~fixed.ravel()
        K = body.stiffness_matrix().tocsc()[free][:, free]
        u = np.zeros(x.size)
        u[free] = sla.spsolve(K, f.ravel()[free])
        u = u.reshape(-1, 3)
        strain_x = u[face, 0].mean()
        assert F / strain_x == pytest.approx(E, rel=1e-9)
        top = np.isclose(x[:, 1], 1.0)
        assert -u[top, 1].mean() / strain_x == pytest.approx(0.25, rel=1e-9)


@pytest.mark.parametrize("element,diagonals", [("tet4", True), ("hex8", True), ("hex8", False)])
def test_mesh_rule_keeps_the_dilation_energy(element, diagonals):
    mesh = cr.box((1.0, 0.6, 0.4), (3, 2, 2), element)
    mesh.points[:] += 0.03 * RNG.standard_normal(mesh.points.shape)  # irregular elements
    mat = cr.Material(E=1e6, nu=0.25, density=800.0)
    body = cr.MassSpringBody.from_mesh(mesh, mat, diagonals=diagonals)
    V = mesh.cell_volumes().sum()
    assert body.total_mass == pytest.approx(800.0 * V, rel=1e-12)
    e = 1e-3
    u = e * mesh.points.ravel()
    K_bulk = 2.0 / 3.0 * mat.E
    assert 0.5 * u @ (body.stiffness_matrix() @ u) == pytest.approx(0.5 * K_bulk * (3 * e) ** 2 * V, rel=1e-9)


def test_builder_masses_and_damping():
    cloth = cr.MassSpringBody.cloth(5, 4, size=(2.0, 1.5), thickness=0.01, density=300.0, beta=0.01)
    assert cloth.total_mass == pytest.approx(2.0 * 1.5 * 0.01 * 300.0, rel=1e-12)
    np.testing.assert_allclose(cloth.damping, 0.01 * cloth.stiffness)
    assert set(np.unique(cloth.kinds)) == {0, 1, 2}
    lat = cr.MassSpringBody.lattice((2, 3, 1), size=(1.0, 1.5, 0.5), density=100.0)
    assert lat.total_mass == pytest.approx(0.75 * 100.0, rel=1e-12)
    # 3 x 4 x 2 nodes: 46 grid edges, 2 diagonals on each of 29 faces, 4 room diagonals per cube.
    assert lat.n_springs == 46 + 58 + 24
    # Per cell 12 edges + 12 face diagonals + 4 room diagonals, shared ones merged.
    one = cr.MassSpringBody.lattice((1, 1, 1))
    assert one.n_springs == 28


# -- bad input --------------------------------------------------------------


def two_nodes():
    return np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])


@pytest.mark.parametrize("mass", [0.0, -1.0, np.nan])
def test_bad_mass_is_named(mass):
    with pytest.raises(ValueError, match=r"mass of node 1 is .*positive"):
        cr.MassSpringBody(two_nodes(), [[0, 1]], stiffness=1.0, masses=[1.0, mass, 1.0])


def test_negative_stiffness_is_named():
    with pytest.raises(ValueError, match=r"spring 1 \(nodes 1, 2\) has stiffness k = -5"):
        cr.MassSpringBody(two_nodes(), [[0, 1], [1, 2]], stiffness=[1.0, -5.0], masses=1.0)


def test_negative_damping_and_rest_length_are_named():
    with pytest.raises(ValueError, match=r"spring 0 .* damping d = -1"):
        cr.MassSpringBody(two_nodes(), [[0, 1]], stiffness=1.0, masses=1.0, damping=-1.0)
    with pytest.raises(ValueError, match=r"spring 0 .* rest length l0 = -2"):
        cr.MassSpringBody(two_nodes(), [[0, 1]], stiffness=1.0, masses=1.0, rest_lengths=[-2.0])


def test_spring_between_coincident_nodes_is_refused():
    x = two_nodes()
    x[2] = x[1]
    with pytest.raises(ValueError, match=r"spring 1 \(nodes 1, 2\) joins coincident nodes: zero length"):
        cr.MassSpringBody(x, [[0, 1], [1, 2]], stiffness=1.0, masses=1.0)


def test_node_index_out_of_range_is_named():
    with pytest.raises(ValueError, match=r"spring 1 refers to node 7, out of range \[0, 3\)"):
        cr.MassSpringBody(two_nodes(), [[0, 1], [2, 7]], stiffness=1.0, masses=1.0)
    with pytest.raises(ValueError, match=r"spring 0 refers to node -1"):
        cr.MassSpringBody(two_nodes(), [[-1, 1]], stiffness=1.0, masses=1.0)
    with pytest.raises(ValueError, match=r"spring 0 joins node 2 to itself"):
        cr.MassSpringBody(two_nodes(), [[2, 2]], stiffness=1.0, masses=1.0)


def test_builder_bad_input():
    with pytest.raises(ValueError, match="at least 2 x 2 particles"):
        cr.MassSpringBody.cloth(1, 5)
    with pytest.raises(ValueError, match="Young's modulus"):
        cr.MassSpringBody.lattice((1, 1, 1), E=-1.0)
    with pytest.raises(ValueError, match="not 'hexahedron20'"):
        cr.MassSpringBody.from_mesh(cr.box((1, 1, 1), (1, 1, 1), "hex20"), cr.Material())
