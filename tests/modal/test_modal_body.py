"""ModalBody: stepping in modal coordinates, recovery, save/load and bad input.

A Hex20 cantilever (8 x 1 x 1 cells, 8 x 1 x 1 m) reduced to 6 normal modes and a
constraint mode set at a tip node.
"""

from __future__ import annotations

import threading

import numpy as np
import pytest

import corotate as cr
from corotate.modal import ModalBody, craig_bampton
from corotate.modal.modal_stress import linear_stress, modal_stresses


@pytest.fixture(scope="module")
def reduced():
    mesh = cr.beam(8.0, 1.0, 1.0, cells=(8, 1, 1), element="hex20")
    body = cr.Body(mesh, cr.Material(E=1e7, nu=0.3, density=1000.0), model="linear")
    tip = mesh.nearest_node((8.0, 0.5, 1.0))
    basis = craig_bampton(body, mesh.nodes_on_plane("x", 0.0), n_modes=6, interface_nodes=[tip])
    return mesh, body, basis, tip


def test_free_vibration_of_each_mode_is_backward_euler(reduced):
    _mesh, _body, basis, _tip = reduced
    w = np.sqrt(basis.eigenvalues[0])
    dt = 2 * np.pi / w / 100
    mb = ModalBody(basis, dt=dt)
    mb.q[0] = 1.0
    mb.step(100)
    # Backward Euler per mode: (x, v) <- [[1, -dt], [w^2 dt, 1]]^-1 (x, v); one period.
    state = np.array([1.0, 0.0])
    step = np.linalg.inv(np.array([[1.0, -dt], [w * w * dt, 1.0]]))
    for _ in range(100):
        state = step @ state
    assert mb.q[0] == pytest.approx(state[0], abs=1e-12)
    assert mb.modal_velocities[0] == pytest.approx(state[1], abs=1e-12)
    np.testing.assert_array_equal(mb.q[1:], 0.0)
    assert mb.time == pytest.approx(1 / basis.frequencies[0], rel=1e-12)


def test_damped_steps_settle_at_the_static_answer(reduced):
    mesh, body, basis, tip = reduced
    # Critical damping of the first mode (the slowest to settle): e^-30 after 20 s.
    mb = ModalBody(basis, dt=0.05, rayleigh=(2 * np.sqrt(basis.eigenvalues[0]), 0.0))
    mb.apply_forces([tip], [[0.0, 0.0, -100.0]])
    mb.step(400)
    settled = mb.displacements([tip])[0]
    mb.solve_static()
    static = mb.displacements([tip])[0]
    np.testing.assert_allclose(settled, static, rtol=1e-6, atol=1e-12)
    # The constraint modes make the reduced static answer the full linear one.
    sim = cr.Simulation(body)
    sim.fix(mesh.nodes_on_plane("x", 0.0))
    sim.external_forces[tip] = (0.0, 0.0, -100.0)
    sim.solve_static()
    np.testing.assert_allclose(static, sim.displacements[tip], rtol=1e-8, atol=1e-10 * np.abs(static).max())


def test_recovery_writes_into_given_arrays(reduced):
    mesh, _body, basis, tip = reduced
    mb = ModalBody(basis)
    rng = np.random.default_rng(1)
    mb.q[:] = rng.normal(size=mb.n_modes)
    full = np.empty((mesh.n_nodes, 3))
    assert mb.displacements(out=full) is full
    np.testing.assert_allclose(full.ravel(), basis.vectors @ mb.q, rtol=1e-13, atol=1e-15)
    nodes = np.array([tip, 0, 5])
    part = np.empty((3, 3))
    mb.displacements(nodes, out=part)
    np.testing.assert_array_equal(part, full[nodes])
    np.testing.assert_allclose(mb.positions(), mesh.points + full)
    with pytest.raises(ValueError, match="shape"):
        mb.displacements(nodes, out=np.empty((2, 3)))
    with pytest.raises(ValueError, match="float64"):
        mb.displacements(out=np.empty((mesh.n_nodes, 3), dtype=np.float32))
    with pytest.raises(ValueError, match="out of range"):
        mb.displacements([mesh.n_nodes])


def test_single_precision_recovery(reduced, tmp_path):
    _, _, basis, tip = reduced
    exact, fast = ModalBody(basis), ModalBody(basis, recovery="float32")
    q = np.random.default_rng(4).normal(size=basis.size)
    exact.set_state(q)
    fast.set_state(q)
    u, v = exact.displacements(), fast.displacements()
    assert 0 < np.abs(u - v).max() < 1e-6 * np.abs(u).max()  # float32 rounding of the basis
    np.testing.assert_array_equal(fast.displacements([tip, 3]), v[[tip, 3]])
    fast.save(tmp_path / "fast.npz")
    assert ModalBody.load(tmp_path / "fast.npz").recovery == "float32"
    with pytest.raises(ValueError, match="recovery"):
        ModalBody(basis, recovery="half")


def test_projection_matches_the_dense_product(reduced):
    mesh, _body, basis, tip = reduced
    mb = ModalBody(basis)
    f = np.zeros((mesh.n_nodes, 3))
    f[[tip, 7]] = [[1.0, -2.0, 3.0], [0.5, 0.0, -1.0]]
    mb.apply_forces([tip, 7], f[[tip, 7]])
    np.testing.assert_allclose(mb.modal_forces, basis.vectors.T @ f.ravel(), rtol=1e-13)


def test_save_and_load_run_without_the_mesh(reduced, tmp_path):
    mesh, _body, basis, tip = reduced
    mb = ModalBody(basis, dt=0.02, rayleigh=(1.0, 1e-3), mesh=mesh)
    mb.save(tmp_path / "beam.npz")
    again = ModalBody.load(tmp_path / "beam.npz")
    assert again.dt == 0.02 and again.rayleigh == (1.0, 1e-3)
    assert again.mesh is not None and again.mesh.cell_type == "hexahedron20"
    for m in (mb, again):
        m.apply_forces([tip], [0.0, 0.0, -50.0])
        m.step(30)
    np.testing.assert_array_equal(again.q, mb.q)
    np.testing.assert_array_equal(again.basis.interface_nodes, [tip])
    with cr.TimeSeriesWriter(tmp_path / "out.pvd", again.mesh) as series:
        again.write_frame(series)
    assert (tmp_path / "out" / "frame_00000.vtu").exists()
    np.savez(tmp_path / "other.npz", x=np.zeros(3))
    with pytest.raises(ValueError, match="not a corotate modal body"):
        ModalBody.load(tmp_path / "other.npz")


def test_bad_input_leaves_the_state(reduced):
    _mesh, _body, basis, tip = reduced
    mb = ModalBody(basis)
    mb.q[:] = 0.1
    before = mb.q.copy()
    with pytest.raises(ValueError, match="shape"):
        mb.set_state(q=np.zeros(mb.n_modes + 1))
    with pytest.raises(ValueError, match="finite"):
        mb.set_state(velocities=np.full(mb.n_modes, np.nan))
    with pytest.raises(ValueError, match="shape"):
        mb.apply_forces([tip], np.zeros((2, 3)))
    with pytest.raises(ValueError, match="out of range"):
        mb.apply_forces([-1], [0.0, 0.0, 1.0])
    with pytest.raises(ValueError, match="not finite"):
        mb.apply_forces([tip], [np.nan, 0.0, 0.0])
    with pytest.raises(ValueError, match="dt"):
        mb.dt = -1.0
    with pytest.raises(ValueError, match="quadratic"):
        ModalBody(basis, quadratic=np.zeros(5))
    with pytest.raises(TypeError):
        mb.step(1.5)
    mb.modal_velocities[0] = np.inf
    with pytest.raises(ValueError, match="not finite"):
        mb.step(1)
    np.testing.assert_array_equal(mb.q, before)
    assert mb.time == 0.0 and mb.dt == 0.01
    with pytest.raises(AttributeError, match="view"):
        mb.q = np.zeros(mb.n_modes)


def test_a_call_from_another_thread_while_stepping_raises_busy(reduced):
    # The core's step is replaced by one that waits for the main thread, so the other thread
    # is deterministically inside step() (GIL released, as the real one) when the calls come.
    _mesh, _body, basis, tip = reduced
    mb = ModalBody(basis)
    inside, finish = threading.Event(), threading.Event()

    class BlockingCore:
        def __init__(self, core):
            self._real = core

        def step(self, n):
            inside.set()
            finish.wait(timeout=10)
            self._real.step(n)

        def __getattr__(self, name):
            return getattr(self._real, name)

    real = mb._core
    mb._core = BlockingCore(real)
    mb.apply_forces([tip], [0.0, 0.0, -1.0])
    worker = threading.Thread(target=mb.step, args=(3,))
    worker.start()
    try:
        assert inside.wait(timeout=10)
        before = real.q.copy()
        for call in (
            lambda: mb.step(1),
            lambda: mb.displacements(),
            lambda: mb.set_state(q=np.zeros(mb.n_modes)),
            lambda: mb.reset(),
            lambda: setattr(mb, "dt", 0.02),
        ):
            with pytest.raises(RuntimeError, match="busy"):
                call()
        np.testing.assert_array_equal(real.q, before)
        assert mb.dt == 0.01
    finally:
        finish.set()
        worker.join(timeout=10)
    assert real.time == pytest.approx(0.03)  # the worker's three steps, nothing else
    mb.step(1)  # free again
    assert real.time == pytest.approx(0.04)


@pytest.mark.parametrize("element", ["tet4", "hex20"])
def test_modal_stress_of_an_affine_field_is_exact(element):
    # Patch test: u = A X has the constant strain sym(A) in every element.
    mesh = cr.box((2.0, 1.0, 1.0), cells=(2, 1, 1), element=element)
    body = cr.Body(mesh, cr.Material(E=2e5, nu=0.25, density=1.0), model="linear")
    A = np.array([[1e-3, 2e-4, 0.0], [0.0, -3e-4, 5e-4], [1e-4, 0.0, 2e-4]])
    sigma = linear_stress(body, mesh.points @ A.T)
    eps = 0.5 * (A + A.T)
    lam, mu = body.material.lame
    expected = lam * np.trace(eps) * np.eye(3) + 2 * mu * eps
    np.testing.assert_allclose(sigma, np.broadcast_to(expected, sigma.shape), atol=1e-12 * np.abs(expected).max())


def test_modal_stresses_superpose(reduced):
    mesh, body, basis, _tip = reduced
    S = modal_stresses(body, basis)
    assert S.shape == (basis.size, mesh.n_cells, 3, 3)
    q = np.linspace(-1.0, 1.0, basis.size)
    np.testing.assert_allclose(
        np.tensordot(q, S, axes=1), linear_stress(body, basis.vectors @ q), rtol=1e-10, atol=1e-12 * np.abs(S).max()
    )
    with pytest.raises(ValueError, match="displacement"):
        linear_stress(body, np.zeros(5))
