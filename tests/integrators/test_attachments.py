"""Implicit attachments (zero-rest-length springs to targets): the static answer of a spring in
series with the body, stability at any stiffness while dragging, explicit steps, cheap changes
of the fixed set, and bad input that changes nothing."""

from __future__ import annotations

import numpy as np
import pytest

import corotate as cr

MAT = cr.Material(E=1e6, nu=0.3, density=1000.0)


def cantilever(model="linear", **kwargs):
    mesh = cr.beam(2.0, 0.5, 0.5, cells=(8, 2, 2))
    sim = cr.Simulation(cr.Body(mesh, MAT, model=model), dt=0.01, **kwargs)
    sim.fix(mesh.nodes_on_plane("x", 0.0))
    return mesh, sim, mesh.nearest_node((2.0, 0.25, 0.5))  # top of the tip face


def compliance(model, node):
    """3 x 3 static compliance of one node of the clamped beam (columns: unit forces)."""
    columns = []
    for axis in range(3):
        _, sim, _ = cantilever(model)
        sim.external_forces[node, axis] = 1.0
        sim.solve_static()
        columns.append(sim.displacements[node])
    return np.column_stack(columns)


@pytest.mark.parametrize("ratio", [10.0, 1000.0])
@pytest.mark.parametrize("integrator", ["linearized", "newton"])
def test_a_dragged_node_settles_where_a_spring_in_series_with_the_body_puts_it(ratio, integrator):
    _, sim, tip = cantilever(rayleigh=(5.0, 0.0), integrator=integrator, solver=cr.Direct())
    C = compliance("linear", tip)
    k_body = 1.0 / C[2, 2]  # the tip's own stiffness along z
    k = ratio * k_body
    pull = np.array([0.0, 0.005, 0.02])  # target displacement
    sim.attach(tip, sim.positions[tip] + pull, k)
    # Spring (k I) and body (C^-1) in series: u = (C^-1 + k I)^-1 k pull = (I + k C)^-1 k C pull.
    expected = np.linalg.solve(np.eye(3) + k * C, k * C @ pull)
    for _ in range(1000):
        sim.step(1)
    assert np.all(np.isfinite(sim.positions))
    np.testing.assert_allclose(sim.displacements[tip], expected, rtol=1e-6, atol=1e-12)
    # The stiffer the spring, the closer the node comes to its target: the gap is about the
    # body's share of the series compliance, about 1 / (1 + ratio) (C is not diagonal: the
    # top node also twists the beam when pulled sideways).
    gap = np.linalg.norm(expected - pull) / np.linalg.norm(pull)
    assert 0.5 / (1 + ratio) < gap < 5 / (1 + ratio)


@pytest.mark.parametrize("ratio", [10.0, 1000.0])
def test_dragging_with_any_stiffness_stays_stable_with_the_default_solver(ratio):
    # The default PCG (capped at 20 iterations) and the co-rotational model; the target circles
    # the tip for 1,000 frames of 5 steps, without damping: no warning (pyproject.toml makes
    # them errors), the tip follows the target, the energy stays bounded.
    _, sim, tip = cantilever("corotational")
    k = ratio / compliance("linear", tip)[2, 2]
    rest = sim.positions[tip].copy()
    sim.attach([tip], rest[None, :], k)
    energies = []
    for frame in range(1000):
        angle = 2 * np.pi * frame / 200
        target = rest + 0.3 * np.array([0.0, np.sin(angle), 1.0 - np.cos(angle)])
        sim.move_attachments(tip, target)
        sim.step(5)
        energies.append(sim.energy + sim.kinetic_energy)
    assert np.all(np.isfinite(sim.positions))
    gap = np.linalg.norm(sim.positions[tip] - target)
    assert gap < (0.1 if ratio == 10 else 0.01) * 0.3
    assert max(energies) < 10 * np.median(energies)  # no growth, only the drag's work
    assert sim.stats["energy_growth_steps"] == sim.stats["stalled_steps"] == sim.stats["inverted_steps"] == 0


def test_release_lets_the_body_swing_back():
    _, sim, tip = cantilever("corotational", rayleigh=(5.0, 0.0))
    sim.attach(tip, sim.positions[tip] + (0.0, 0.0, 0.3), 1e6)
    sim.step(50)
    assert sim.displacements[tip, 2] > 0.2
    assert np.linalg.norm(sim.attachment_forces()) > 0
    sim.detach()
    assert sim.attachments[0].size == 0
    sim.step(500)
    assert abs(sim.displacements[tip, 2]) < 1e-3  # back at rest (no gravity)


def test_changing_the_fixed_set_mid_run_keeps_the_answer_of_a_direct_solve():
    # The PCG keeps its preconditioner hierarchy across fix/free (projected, not rebuilt):
    # run to a tight tolerance it must agree with a direct solve of the new system.
    runs = []
    for solver in (cr.PCG(max_iterations=2000, tolerance=1e-12), cr.Direct()):
        mesh, sim, tip = cantilever("corotational", solver=solver, gravity=(0, 0, -9.81))
        clamped = mesh.nodes_on_plane("x", 0.0)
        sim.step(20)
        sim.fix(np.append(clamped, tip))  # grab the tip by fixing it
        sim.velocities[tip] = (0.0, 0.0, 1.0)
        sim.step(20)
        sim.velocities[tip] = 0.0
        sim.fix(clamped)  # release
        sim.step(20)
        sim.attach(tip, sim.positions[tip] + 0.1, 1e5)
        sim.step(20)
        runs.append(sim.positions.copy())
    np.testing.assert_allclose(runs[0], runs[1], rtol=0, atol=1e-9)


def test_explicit_steps_include_the_springs_in_forces_and_stable_step():
    mesh = cr.beam(2.0, 0.5, 0.5, cells=(4, 1, 1))
    body = cr.Body(mesh, MAT, model="linear")
    sim = cr.ExplicitSimulation(body, dt=0.01, mass_damping=20.0)
    sim.fix(mesh.nodes_on_plane("x", 0.0))
    tip = mesh.nearest_node((2.0, 0.5, 0.5))
    free = sim.stability()
    assert free["attachment_rate"] == 0.0
    k = 1e5
    target = sim.positions[tip] + (0.0, 0.0, 0.01)
    sim.attach(tip, target, k)
    grabbed = sim.stability()
    m = sim.mass_matrix().diagonal()[3 * tip]
    assert grabbed["attachment_rate"] == pytest.approx(k / m, rel=1e-12)
    assert grabbed["omega_max"] ** 2 == pytest.approx(free["lambda_max"] + k / m, rel=1e-12)
    assert grabbed["critical_step"] < free["critical_step"]
    sim.step(300)  # 3 s, substepped below the new limit; damped to rest
    C = compliance_of(body, mesh, tip)
    expected = np.linalg.solve(np.eye(3) + k * C, k * C @ np.array([0.0, 0.0, 0.01]))
    np.testing.assert_allclose(sim.displacements[tip], expected, rtol=1e-6, atol=1e-12)


def compliance_of(body, mesh, node):
    columns = []
    for axis in range(3):
        sim = cr.Simulation(body)
        sim.fix(mesh.nodes_on_plane("x", 0.0))
        sim.external_forces[node, axis] = 1.0
        sim.solve_static()
        columns.append(sim.displacements[node])
    return np.column_stack(columns)


def test_attachment_bookkeeping():
    _, sim, tip = cantilever()
    sim.attach([1, tip], [[0.0, 0.0, 0.0], [1.0, 2.0, 3.0]], [10.0, 20.0])
    sim.attach(1, (0.5, 0.5, 0.5), 30.0)  # re-attach: replaced, not added
    nodes, targets, k = sim.attachments
    assert nodes.tolist() == [1, tip]
    np.testing.assert_array_equal(targets, [[0.5, 0.5, 0.5], [1.0, 2.0, 3.0]])
    np.testing.assert_array_equal(k, [30.0, 20.0])
    sim.move_attachments([tip], [[3.0, 2.0, 1.0]])
    np.testing.assert_array_equal(sim.attachment_forces()[1], 20.0 * (np.array([3.0, 2.0, 1.0]) - sim.positions[tip]))
    sim.detach(1)
    assert sim.attachments[0].tolist() == [tip]
    with pytest.raises(AttributeError, match="use attach"):
        sim.attachments = None


def state(sim):
    nodes, targets, k = sim.attachments
    return sim.positions.copy(), sim.velocities.copy(), nodes.copy(), targets.copy(), k.copy()


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda s: s.attach(10_000, (0, 0, 0), 1.0), "out of range"),
        (lambda s: s.attach(-1, (0, 0, 0), 1.0), "out of range"),
        (lambda s: s.attach([3, 3], [[0, 0, 0], [0, 0, 0]], 1.0), "listed twice"),
        (lambda s: s.attach(3, (np.nan, 0, 0), 1.0), "target of node 3 is not finite"),
        (lambda s: s.attach(3, (np.inf, 0, 0), 1.0), "target of node 3 is not finite"),
        (lambda s: s.attach(3, (0, 0, 0), -1.0), "positive and finite"),
        (lambda s: s.attach(3, (0, 0, 0), 0.0), "positive and finite"),
        (lambda s: s.attach(3, (0, 0, 0), np.nan), "positive and finite"),
        (lambda s: s.attach(3, (0, 0, 0), np.inf), "positive and finite"),
        (lambda s: s.attach([3, 4], (0, 0, 0), 1.0), r"targets must have shape \(2, 3\)"),
        (lambda s: s.attach(3, [[0, 0, 0], [1, 1, 1]], 1.0), r"targets must have shape \(1, 3\)"),
        (lambda s: s.attach([3, 4], np.zeros((2, 3)), [1.0, 2.0, 3.0]), "one number or 2 numbers"),
        (lambda s: s.attach(3.5, (0, 0, 0), 1.0), "must be integers"),
        (lambda s: s.move_attachments(4, (0, 0, 0)), "node 4 is not attached"),
        (lambda s: s.move_attachments(2, (np.nan, 0, 0)), "target of node 2 is not finite"),
        (lambda s: s.detach([2, 4]), "node 4 is not attached"),
        (lambda s: s.solve_static(), "does not include attachment springs"),
    ],
)
def test_bad_input_is_refused_and_changes_nothing(call, message):
    _, sim, _ = cantilever()
    sim.attach(2, (1.0, 1.0, 1.0), 5.0)
    sim.step(3)
    before = state(sim)
    with pytest.raises(ValueError, match=message):
        call(sim)
    for a, b in zip(before, state(sim)):
        np.testing.assert_array_equal(a, b)


def test_attaching_from_a_progress_callback_is_refused_as_busy():
    _, sim, tip = cantilever()
    calls = []

    def progress(done, n):
        calls.append(done)
        sim.attach(tip, (0.0, 0.0, 0.0), 1.0)

    before = state(sim)
    with pytest.raises(RuntimeError, match="busy: attaching nodes"):
        sim.step(2, progress)
    for a, b in zip(before, state(sim)):
        np.testing.assert_array_equal(a, b)


def test_the_drag_that_runs_away_through_external_forces_is_silent_through_attach():
    # The scene of test_loud_failures.py's external-force drag (dt^2 k / m about 1e5), which
    # inverts elements in its first step: the same spring as an attachment drags for 300
    # frames with no loud failure, and the node settles just below its target.
    mesh = cr.beam(1.0, 0.2, 0.2, cells=(10, 2, 2))
    sim = cr.Simulation(cr.Body(mesh, cr.Material(E=1e5, nu=0.3, density=1000.0)), dt=0.01, rayleigh=(2.0, 0.0))
    sim.fix(mesh.nodes_on_plane("x", 0.0))
    grab = mesh.nearest_node((1.0, 0.1, 0.1))
    target = mesh.points[grab] + (0.0, 0.0, 0.3)
    sim.attach(grab, target, 1e6)
    sim.step(300)
    assert sim.stats["inverted_steps"] == sim.stats["energy_growth_steps"] == sim.stats["stalled_steps"] == 0
    assert 0.0 < target[2] - sim.positions[grab, 2] < 1e-3


def test_fixing_more_nodes_keeps_the_explicit_stability_estimate_releasing_renews_it():
    # Fixing restricts M^-1 K to fewer DOFs, whose largest eigenvalue can only fall: a grab by
    # fixing needs no new (Lanczos) estimate. A release can raise it: estimated again.
    mesh = cr.beam(2.0, 0.5, 0.5, cells=(4, 1, 1))
    sim = cr.ExplicitSimulation(cr.Body(mesh, MAT), dt=1e-3)
    clamped = mesh.nodes_on_plane("x", 0.0)
    sim.fix(clamped)
    sim.step(2)
    assert sim.stats["estimates"] == 1
    sim.fix(np.append(clamped, mesh.nearest_node((2.0, 0.5, 0.5))))
    sim.step(2)
    assert sim.stats["estimates"] == 1
    sim.fix(clamped)
    sim.step(2)
    assert sim.stats["estimates"] == 2
