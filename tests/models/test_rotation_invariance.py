"""Co-rotational FEM under rigid motions: no forces from rotation (unlike linear
FEM, which grows under rotation: section 2.2.2 of the paper), frame
indifference, agreement with linear FEM at small strain, rotation extraction."""

import numpy as np
import pytest

import corotate as cr
from corotate import _core
from corotate.mesh import SOLID_ELEMENTS

ELEMENTS = SOLID_ELEMENTS  # every registered solid (the core's cell-type table)
E, NU, RHO = 1e6, 0.3, 1000.0
SIZE = (2.0, 1.0, 1.0)
CELLS = (4, 2, 2)
H = 0.5  # cell size
VOLUME = 2.0


def rotation(axis, angle):
    axis = np.asarray(axis, dtype=float)
    axis = axis / np.linalg.norm(axis)
    W = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * W + (1 - np.cos(angle)) * W @ W


Q90 = rotation((1.0, 2.0, 3.0), np.pi / 2)  # 90 degrees about an oblique axis
SHIFT = np.array([0.3, -1.7, 2.2])


def make_body(element, model):
    mesh = cr.box(SIZE, CELLS, element)
    return mesh, cr.Body(mesh, cr.Material(E=E, nu=NU, density=RHO), model=model)


def stretch_force_scale(element):
    """Largest nodal force of a 1% uniaxial stretch (the meaningful force scale)."""
    mesh, body = make_body(element, "linear")
    x = mesh.points.copy()
    x[:, 0] *= 1.01
    return np.abs(body.internal_forces(x)).max(), body.energy(x)


def deformed(mesh, seed=0, twist=np.pi / 4, noise=0.03):
    """A large deformation: twist about the x axis growing along x (45 degrees
    at the far end) plus random nodal noise of `noise` x cell size."""
    p = mesh.points
    out = np.empty_like(p)
    for i, (x, y, z) in enumerate(p):
        a = twist * x / SIZE[0]
        c, s = np.cos(a), np.sin(a)
        y0, z0 = y - 0.5, z - 0.5
        out[i] = (1.05 * x, 0.5 + c * y0 - s * z0, 0.5 + s * y0 + c * z0)
    rng = np.random.default_rng(seed)
    return out + noise * H * rng.uniform(-1, 1, p.shape)


# -- rigid motion ----------------------------------------------------------


@pytest.mark.parametrize("element", ELEMENTS)
def test_corotational_rigid_rotation_has_no_forces(element):
    mesh, body = make_body(element, "corotational")
    f_ref, e_ref = stretch_force_scale(element)
    assert f_ref > 1e-3 * E * H**2  # a 1% stretch gives forces ~ 0.01 E h^2
    x = mesh.points @ Q90.T + SHIFT
    f = body.internal_forces(x)
    assert np.all(np.isfinite(f))
    assert np.abs(f).max() < 1e-10 * f_ref
    # Energy vs that of a 1% stretch. With the translation the element
    # displacement R^T x - X equals the (large) shift, and u^T K u cancels only
    # to round-off ~ eps |K| |shift|^2, hence the looser bound; a rotation about
    # the origin leaves u at round-off and the energy at eps^2.
    assert abs(body.energy(x)) < 1e-9 * e_ref
    assert abs(body.energy(mesh.points @ Q90.T)) < 1e-20 * e_ref
    assert np.abs(body.internal_forces(mesh.points @ Q90.T)).max() < 1e-11 * f_ref
    # The rotated stiffness is Q K Q^T.
    K0 = body.stiffness_matrix().toarray()
    Kq = body.stiffness_matrix(x).toarray()
    big = np.kron(np.eye(mesh.n_nodes), Q90)
    np.testing.assert_allclose(Kq, big @ K0 @ big.T, rtol=0, atol=1e-10 * np.abs(K0).max())


@pytest.mark.parametrize("element", ELEMENTS)
def test_linear_model_grows_under_rigid_rotation(element):
    # Linear FEM sees u = (Q - I) X + t, whose strain sym(Q - I) = n n^T - I for
    # a 90 degree rotation about n: tr = -2, eps:eps = 2, so the spurious
    # energy is exactly V (lambda/2 * 4 + mu * 2), for every element type.
    mesh, body = make_body(element, "linear")
    x = mesh.points @ Q90.T + SHIFT
    lam = E * NU / ((1 + NU) * (1 - 2 * NU))
    mu = E / (2 * (1 + NU))
    assert body.energy(x) == pytest.approx(VOLUME * (2 * lam + 2 * mu), rel=1e-10)
    f = body.internal_forces(x)
    # Forces of the order of E h^2 (a strain of order one), ~100x a 1% stretch.
    f_ref, _ = stretch_force_scale(element)
    assert np.abs(f).max() > 0.1 * E * H**2 / (4 if element == "hex20" else 1)
    assert np.abs(f).max() > 30 * f_ref
    # Self-equilibrated nonetheless.
    assert np.abs(f.sum(axis=0)).max() < 1e-9 * np.abs(f).max()


@pytest.mark.parametrize("element", ELEMENTS)
def test_frame_indifference_of_deformed_body(element):
    mesh, body = make_body(element, "corotational")
    x = deformed(mesh)
    f = body.internal_forces(x)
    e = body.energy(x)
    K = body.stiffness_matrix(x).toarray()
    assert np.abs(f).max() > 0  # really deformed

    for Q, t in [(Q90, SHIFT), (rotation((-0.3, 0.2, 1.0), 2.5), np.array([10.0, 0.0, -3.0]))]:
        xq = x @ Q.T + t
        fq = body.internal_forces(xq)
        np.testing.assert_allclose(fq, f @ Q.T, rtol=0, atol=1e-9 * np.abs(f).max())
        assert body.energy(xq) == pytest.approx(e, rel=1e-9)
        big = np.kron(np.eye(mesh.n_nodes), Q)
        np.testing.assert_allclose(
            body.stiffness_matrix(xq).toarray(), big @ K @ big.T, rtol=0, atol=1e-9 * np.abs(K).max()
        )
    # Evaluating again at the first configuration gives the same answer (the
    # warm-started rotation iteration does not leave a trace).
    np.testing.assert_allclose(body.internal_forces(x), f, rtol=0, atol=1e-11 * np.abs(f).max())


# -- small deformation -----------------------------------------------------


@pytest.mark.parametrize("element", ELEMENTS)
def test_corotational_stiffness_at_rest_equals_linear(element):
    mesh, corot = make_body(element, "corotational")
    _, linear = make_body(element, "linear")
    Kc = corot.stiffness_matrix()
    Kl = linear.stiffness_matrix()
    assert Kc.shape == Kl.shape
    assert np.abs(Kc - Kl).max() <= 1e-14 * np.abs(Kl).max()
    # and at the rest positions passed explicitly
    assert np.abs(corot.stiffness_matrix(mesh.points) - Kl).max() <= 1e-14 * np.abs(Kl).max()
    assert np.abs(corot.internal_forces(mesh.points)).max() == 0.0
    assert corot.energy(mesh.points) == 0.0


@pytest.mark.parametrize("element", ELEMENTS)
def test_corotational_forces_approach_linear_quadratically(element):
    mesh, corot = make_body(element, "corotational")
    _, linear = make_body(element, "linear")
    rng = np.random.default_rng(5)
    # a smooth field with a rotation part (so R != I) plus nodal noise
    G = rng.normal(size=(3, 3))
    direction = mesh.points @ G.T + 0.3 * rng.uniform(-1, 1, mesh.points.shape)
    direction *= H / np.abs(direction).max()

    def gap(s):
        x = mesh.points + s * direction
        fl = linear.internal_forces(x)
        fc = corot.internal_forces(x)
        return np.abs(fc - fl).max(), np.abs(fl).max()

    g1, f1 = gap(1e-2)
    g2, f2 = gap(1e-3)
    g3, _f3 = gap(1e-4)
    assert f1 / f2 == pytest.approx(10, rel=1e-9)  # linear forces scale with u
    assert g1 / f1 < 0.01  # close already at 1% strain
    # the difference is second order: 10x smaller u -> 100x smaller gap
    assert 95 < g1 / g2 < 105
    assert 95 < g2 / g3 < 105


# -- rotation extraction ---------------------------------------------------


def numpy_polar(F):
    U, _s, Vt = np.linalg.svd(F)
    D = np.diag([1.0, 1.0, np.sign(np.linalg.det(U @ Vt))])
    return U @ D @ Vt


def random_deformation_gradients(n=300, seed=0):
    rng = np.random.default_rng(seed)
    out = []
    for k in range(n):
        kind = k % 4
        if kind == 0:
            F = rng.normal(size=(3, 3))  # about half inverted
        elif kind == 1:
            F = rotation(rng.normal(size=3), rng.uniform(0, np.pi)) @ (np.eye(3) + 0.1 * rng.normal(size=(3, 3)))
        elif kind == 2:
            # strongly anisotropic stretch, rotated
            S = np.diag(rng.uniform(0.05, 5.0, 3))
            F = rotation(rng.normal(size=3), rng.uniform(0, np.pi)) @ S @ rotation(rng.normal(size=3), 1.0)
        else:
            # inverted: a reflection through a plane times a rotation
            P = np.eye(3)
            P[2, 2] = -rng.uniform(0.1, 1.0)
            F = rotation(rng.normal(size=3), rng.uniform(0, np.pi)) @ P @ (np.eye(3) + 0.2 * rng.normal(size=(3, 3)))
        out.append(F * 10.0 ** rng.uniform(-3, 3))
    return out


def test_extract_rotation_matches_polar_decomposition():
    n_inverted = 0
    for F in random_deformation_gradients():
        R = np.asarray(_core.extract_rotation(F))
        Rp = np.asarray(_core.polar_rotation(F))
        np.testing.assert_allclose(R, Rp, rtol=0, atol=1e-12)
        np.testing.assert_allclose(Rp, numpy_polar(F), rtol=0, atol=1e-12)
        assert np.linalg.det(R) == pytest.approx(1.0, abs=1e-13)
        np.testing.assert_allclose(R.T @ R, np.eye(3), rtol=0, atol=1e-13)
        S = R.T @ F
        np.testing.assert_allclose(S, S.T, rtol=0, atol=1e-12 * np.abs(F).max())
        if np.linalg.det(F) > 0:
            assert np.linalg.eigvalsh(0.5 * (S + S.T)).min() > 0  # the stretch is SPD
        else:
            n_inverted += 1
            # smallest singular value carries the flip: exactly one negative eigenvalue
            ev = np.linalg.eigvalsh(0.5 * (S + S.T))
            assert ev[0] < 0 < ev[1]
    assert n_inverted > 50


def test_extract_rotation_of_pure_rotation_and_identity():
    assert np.array_equal(np.asarray(_core.extract_rotation(np.eye(3))), np.eye(3))
    for angle in (0.1, 1.0, np.pi / 2, 3.0):
        Q = rotation((0.2, -1.0, 0.7), angle)
        np.testing.assert_allclose(_core.extract_rotation(Q), Q, rtol=0, atol=1e-14)
        np.testing.assert_allclose(_core.extract_rotation(2.5 * Q), Q, rtol=0, atol=1e-14)


# -- inverted element ------------------------------------------------------


def test_step_with_inverted_element_stays_finite():
    mesh = cr.box((1, 1, 1), (2, 2, 2), "tet4")
    body = cr.Body(mesh, cr.Material(E=E, nu=NU, density=RHO))
    sim = cr.Simulation(body, dt=0.01, solver=cr.Direct())
    sim.fix(mesh.nodes_on_plane("z", 0.0))
    # Pick a free node and an element of it; mirror the node through the plane of
    # the opposite face, past it by 50%: that element is inverted.
    node = mesh.nearest_node((1.0, 1.0, 1.0))
    e = int(np.flatnonzero((mesh.cells == node).any(axis=1))[0])
    cell = mesh.cells[e]
    others = [i for i in cell if i != node]
    p = mesh.points
    normal = np.cross(p[others[1]] - p[others[0]], p[others[2]] - p[others[0]])
    normal /= np.linalg.norm(normal)
    dist = (p[node] - p[others[0]]) @ normal
    sim.positions[node] = p[node] - 2.5 * dist * normal
    x = sim.positions[cell]
    assert np.linalg.det(x[1:] - x[0]) < 0  # really inverted

    f = sim.internal_forces()
    assert np.all(np.isfinite(f)) and np.abs(f).max() > 0
    assert np.isfinite(sim.energy) and sim.energy > 0
    d = sim.positions[mesh.cells]
    inverted = int((np.linalg.det(d[:, 1:] - d[:, :1]) <= 0).sum())  # counted independently
    with pytest.warns(
        cr.SimulationWarning, match=rf"inverted or flat elements \(det F <= 0; {inverted} in the last one\)"
    ):
        sim.step(1)
    assert sim.time == pytest.approx(0.01)
    assert np.all(np.isfinite(sim.positions))
    assert np.all(np.isfinite(sim.velocities))
    # the inverted node is pushed back towards the side of the face it came from
    assert (sim.velocities[node] @ normal) * dist > 0
    # and PCG does the same without NaN
    sim2 = cr.Simulation(
        body,
        dt=0.01,
        solver=cr.PCG(preconditioner="block_jacobi", max_iterations=200, tolerance=1e-10),
        on_failure="ignore",  # reported above
    )
    sim2.fix(mesh.nodes_on_plane("z", 0.0))
    sim2.positions[node] = p[node] - 2.5 * dist * normal
    sim2.step(1)
    assert np.all(np.isfinite(sim2.positions)) and np.all(np.isfinite(sim2.velocities))
    np.testing.assert_allclose(sim2.velocities, sim.velocities, rtol=0, atol=1e-6 * np.abs(sim.velocities).max())
