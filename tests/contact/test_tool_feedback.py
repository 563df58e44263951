"""Force feedback through contact: a rigid probe pressed 1 cm into a soft block. The force
the feedback predicts for the tool's next position (queried between two body steps, as a
haptic loop does) is the force the full simulation's contact exerts there, within 2 %."""

import threading

import numpy as np
import pytest
from conftest import CUBE, cube

import corotate as cr

RADIUS = 0.02


def pressed_block():
    mesh, sim = cube(z0=0.0, cells=8)
    sim.fix(np.flatnonzero(mesh.points[:, 2] == 0))  # glued to the table
    probe = cr.Sphere((0, 0, CUBE + RADIUS), RADIUS)  # touching the top face's centre
    sim.add_obstacle(probe)
    return sim, probe, cr.ToolFeedback(sim, probe)


def test_predicted_force_matches_the_simulation_within_2_percent():
    sim, probe, feedback = pressed_block()
    depth_per_step = 2.5e-4  # 1 cm in 40 steps of 0.01 s
    errors, jumps, touching_updates, touching_nodes, since_jump = [], [], 0, 0, 99
    for step in range(1, 41):
        position = np.array([0, 0, CUBE + RADIUS - depth_per_step * step])
        # Between the two steps, the haptic loop asks at the tool's coming position ...
        predicted, stiffness = feedback.query(position)
        probe.move_to(position)
        sim.step()
        feedback.update()
        actual = -sim.contact_force(probe)  # ... and the body's step then finds this
        # At its own step's position the feedback is the simulation's force exactly.
        np.testing.assert_allclose(feedback.query(position)[0], actual, rtol=1e-12, atol=1e-12)
        # The secant needs two steps in contact; the first contact's onset and the step in
        # which more of the mesh's nodes start to touch (here at 7.5 mm, when the probe
        # reaches the next ring of nodes 1.25 cm apart), with the next step whose secant
        # spans it, are kinks no secant anticipates: judged apart, within 10 %.
        now_touching = int(np.sum(sim.contacts["obstacles"] == 0))
        since_jump = 0 if now_touching != touching_nodes else since_jump + 1
        if touching_updates >= 3:
            error = np.linalg.norm(predicted - actual) / np.linalg.norm(actual)
            (jumps if since_jump <= 1 else errors).append(error)
        touching_updates += feedback.touching
        touching_nodes = now_touching
    assert len(errors) > 30 and len(jumps) == 2
    assert max(errors) < 0.02
    assert max(jumps) < 0.10
    force, stiffness = feedback.query(position)
    assert force[2] > 10.0  # 1 cm into a soft (1e5 Pa) block: tens of newtons
    assert stiffness[2, 2] < 0  # pushing deeper pushes back harder
    np.testing.assert_allclose(stiffness, stiffness.T, atol=1e-9 * abs(stiffness[2, 2]))


def test_a_tool_lifted_away_lets_go():
    """A contact that carried force holds in the linearised step only while it pushes: the
    tissue springs back towards its rest shape rather than following a tool lifted away."""
    sim, probe, _ = pressed_block()
    for step in range(1, 21):
        probe.move_to((0, 0, CUBE + RADIUS - 2.5e-4 * step))  # 5 mm in
        sim.step()
    top = np.argmin(np.linalg.norm(sim.body.mesh.points - (0, 0, CUBE), axis=1))
    dented = sim.positions[top, 2]
    assert dented < CUBE - 4e-3
    probe.move_to((0, 0, CUBE + 0.05))  # lifted 3.5 cm in one frame
    sim.step()
    assert not sim.contacts["nodes"].size or not sim.contact_force(probe).any()
    assert dented < sim.positions[top, 2] < CUBE + 1e-3  # springs back, not pulled up


def test_no_contact_no_feedback():
    sim, probe, feedback = pressed_block()
    probe.move_to((0, 0, 0.5))
    sim.step()
    feedback.update()
    assert not feedback.touching
    force, stiffness = feedback.query(np.array([0, 0, 0.5]))
    assert not force.any() and not stiffness.any()


def test_bad_input():
    sim, probe, feedback = pressed_block()
    with pytest.raises(ValueError, match="not an obstacle of this simulation"):
        cr.ToolFeedback(sim, cr.Sphere((0, 0, 1), 0.1))
    with pytest.raises(TypeError, match="tool must be a corotate obstacle"):
        cr.ToolFeedback(sim, "probe")
    for bad in ([0, 0, np.nan], [0, 0], [[0, 0, 0]]):
        with pytest.raises(ValueError, match="finite 3-vector"):
            feedback.query(bad)
    sim.remove_obstacle(probe)
    with pytest.raises(ValueError, match="not an obstacle of this simulation"):
        feedback.update()


def test_queries_from_a_haptic_thread_while_the_body_steps():
    sim, probe, feedback = pressed_block()
    stop = threading.Event()
    forces = []

    def haptic_loop():
        while not stop.is_set():
            forces.append(feedback.query(np.array([0, 0, CUBE + RADIUS - 2e-3]))[0])

    thread = threading.Thread(target=haptic_loop)
    thread.start()
    try:
        for step in range(1, 11):
            probe.move_to((0, 0, CUBE + RADIUS - 2e-4 * step))
            sim.step()
            feedback.update()
    finally:
        stop.set()
        thread.join()
    assert len(forces) > 10 and np.all(np.isfinite(forces))
