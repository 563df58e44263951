"""Contact under hostile input: each refusal names the problem and changes nothing, a failed
step restores the contacts and the obstacles' motion with the state, and a tool moved from
another thread while the body steps is read whole."""

import threading

import numpy as np
import pytest
from conftest import cube, interrupted_step

import corotate as cr


def test_a_body_that_starts_inside_is_refused():
    _mesh, sim = cube(z0=0.0)
    floor = cr.Plane((0, 0, 0.01))
    with pytest.raises(ValueError, match=r"contact nodes start inside the plane \(node \d+ by 0.01"):
        sim.add_obstacle(floor)
    assert sim.obstacles == []
    sim.step()  # still steps, without contact: it falls
    assert sim.positions[:, 2].min() < 0


@pytest.mark.parametrize("friction", [-0.1, float("nan"), float("inf")])
def test_a_bad_friction_is_refused(friction):
    _mesh, sim = cube(z0=0.0)
    ground = cr.Plane()
    with pytest.raises(ValueError, match="friction coefficient must be non-negative and finite"):
        sim.add_obstacle(ground, friction=friction)
    sim.add_obstacle(ground, friction=0.2)
    with pytest.raises(ValueError, match="friction coefficient"):
        sim.set_friction(ground, friction)
    assert sim.obstacles[0][1] == 0.2


def test_obstacle_misuse():
    _mesh, sim = cube(z0=0.0)
    ground = cr.Plane()
    with pytest.raises(TypeError, match="obstacle must be"):
        sim.add_obstacle("floor")
    sim.add_obstacle(ground)
    with pytest.raises(ValueError, match="was added already"):
        sim.add_obstacle(ground)
    with pytest.raises(ValueError, match="is not an obstacle of the simulation"):
        sim.remove_obstacle(cr.Sphere((0, 0, 1), 0.1))
    with pytest.raises(ValueError, match="not an obstacle of this simulation"):
        sim.contact_force(cr.Sphere((0, 0, 1), 0.1))
    with pytest.raises(ValueError, match="solve_static does not include contact"):
        sim.solve_static()
    with pytest.raises(ValueError, match="out of range"):
        sim.contact_nodes = [0, 10**6]
    with pytest.raises(ValueError, match="listed twice"):
        sim.contact_nodes = [0, 0]
    with pytest.raises(ValueError, match="stiffness_scale must be positive"):
        sim.contact_settings = {"stiffness_scale": 0.0}
    with pytest.raises(ValueError, match="friction_velocity must be positive"):
        sim.contact_settings = {"friction_velocity": float("nan")}
    with pytest.raises(ValueError, match="unknown contact settings"):
        sim.contact_settings = {"stiffnes_scale": 10.0}
    assert sim.contact_settings == {"stiffness_scale": 100.0, "friction_velocity": 1e-3, "edge_contact": True}
    sim.remove_obstacle(ground)
    assert sim.obstacles == []


def test_contact_needs_an_implicit_integrator():
    _mesh, sim = cube(z0=0.0)
    sim.add_obstacle(cr.Plane())
    with pytest.raises(ValueError, match="contact needs an implicit integrator"):
        sim._sim.settings = cr._core.IntegratorSettings(integrator="verlet", time_step=1e-4)


def test_a_failed_step_restores_the_contacts_and_the_tool_motion():
    # (Every step assembles: a kept matrix is not part of the restored state.)
    _mesh, sim = cube(z0=0.0, matrix_reuse_angle=0.0)
    ground, probe = cr.Plane(), cr.Sphere((-0.07, 0, 0.05), 0.02)
    sim.add_obstacle(ground, friction=0.3)
    sim.add_obstacle(probe)
    sim.step(5)
    probe.move_to((-0.065, 0, 0.05))
    interrupted_step(sim, 3, after=2)
    # The same step again gives what an uninterrupted run gives: the probe's motion (from
    # where the body last saw it) was restored too.
    sim.step(3)
    _mesh2, twin = cube(z0=0.0, matrix_reuse_angle=0.0)
    ground2, probe2 = cr.Plane(), cr.Sphere((-0.07, 0, 0.05), 0.02)
    twin.add_obstacle(ground2, friction=0.3)
    twin.add_obstacle(probe2)
    twin.step(5)
    probe2.move_to((-0.065, 0, 0.05))
    twin.step(3)
    np.testing.assert_array_equal(sim.positions, twin.positions)


def test_non_finite_state_with_contact_is_refused_and_restored():
    _mesh, sim = cube(z0=0.0)
    sim.add_obstacle(cr.Plane())
    sim.step(3)
    sim.velocities[4, 2] = np.nan
    with pytest.raises(ValueError, match="node 4"):
        sim.step()
    sim.velocities[4, 2] = 0.0
    sim.step()


def test_moving_a_tool_from_another_thread_while_stepping():
    """A haptic thread moves the probe at its own rate; every step reads one whole pose."""
    _mesh, sim = cube(z0=0.0)
    probe = cr.Sphere((-0.071, 0, 0.05), 0.02)  # up to 1 mm into the cube's face at x = -0.05
    sim.add_obstacle(cr.Plane())
    sim.add_obstacle(probe)
    stop = threading.Event()
    errors = []

    def haptic_loop():
        k = 0
        while not stop.is_set():
            k += 1
            try:
                probe.move_to((-0.071 + 1e-6 * (k % 1000), 0, 0.05))
            except Exception as e:  # pragma: no cover - reported below
                errors.append(e)

    thread = threading.Thread(target=haptic_loop)
    thread.start()
    try:
        for _ in range(50):
            sim.step()
    finally:
        stop.set()
        thread.join()
    assert errors == []
    assert np.all(np.isfinite(sim.positions))
    # The probe kept moving (up to 1 mm) after the last step read its pose; one more step with
    # it still, and the cube must hold it out to 1 % of an element.
    sim.step()
    assert probe.distance(sim.positions)[0].min() > -0.01 * 0.025
