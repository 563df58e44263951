"""The live scene of ``corotate view`` driven headless by synthetic mouse events: a grabbed
node follows the mouse ray, release lets it go, pause freezes time, gravity switches, reset
goes back to rest, pacing follows the wall clock; and the boundary the viewer draws."""

from __future__ import annotations

import sys

import numpy as np
import pytest

import corotate as cr
from corotate.surfaces import boundary_triangles
from corotate.view import InteractiveScene


def cantilever_scene(**kwargs):
    mesh = cr.beam(2.0, 0.5, 0.5, cells=(8, 2, 2))
    sim = cr.Simulation(cr.Body(mesh, cr.Material(E=1e6, nu=0.3, density=1000.0)), dt=0.01, rayleigh=(2.0, 0.0))
    sim.fix(mesh.nodes_on_plane("x", 0.0))
    return mesh, InteractiveScene(sim, **kwargs)


def test_a_grabbed_node_follows_the_mouse_ray_and_is_let_go():
    mesh, scene = cantilever_scene(gravity=(0, 0, 0))
    tip = mesh.nearest_node((2.0, 0.25, 0.5))
    eye = np.array([2.0, 0.25, 3.0])  # looking down at the tip from 2.5 m above
    assert scene.grab(mesh.points[tip] + (0.01, 0.0, 0.0), eye) == tip
    assert scene.grabbed == tip
    # The mouse moves: a ray from the eye towards a point 0.3 m further along y.
    goal = mesh.points[tip] + (0.0, 0.3, 0.0)
    direction = goal - eye
    for _ in range(100):
        scene.drag(eye, direction)
        scene.frame(elapsed=0.05)
    # The grabbed node's target is on the ray at the grab's distance from the eye (2.5 m), the
    # node close to it; its neighbours within one edge length are held at their offsets.
    nodes, targets, k = scene.sim.attachments
    target = targets[nodes == tip][0]
    np.testing.assert_allclose(target, eye + 2.5 * direction / np.linalg.norm(direction), rtol=1e-12)
    assert np.linalg.norm(scene.sim.positions[tip] - target) < 0.01 * 0.3
    np.testing.assert_allclose(targets - target, mesh.points[nodes] - mesh.points[tip], atol=1e-12)
    assert 1 < len(nodes) < 10 and k.sum() == pytest.approx(scene.grab_stiffness)
    assert "dragging node" in scene.status()
    scene.release()
    assert scene.grabbed is None and scene.sim.attachments[0].size == 0
    for _ in range(200):
        scene.frame(elapsed=0.05)
    assert np.linalg.norm(scene.sim.displacements[tip]) < 1e-3  # springs back (damped, no gravity)


def test_frames_are_paced_to_the_wall_clock_and_pause_freezes_time():
    _, scene = cantilever_scene(max_steps=5)
    assert scene.frame(elapsed=0.02) == 2
    assert scene.frame(elapsed=0.015) == 1  # 0.005 s carried over
    assert scene.frame(elapsed=0.005) == 1
    assert scene.frame(elapsed=1.0) == 5  # a slow frame falls behind, at most 5 steps
    assert scene.sim.time == pytest.approx(0.09)
    scene.toggle_pause()
    assert scene.frame(elapsed=0.05) == 0 and scene.sim.time == pytest.approx(0.09)
    assert "PAUSED" in scene.status()
    scene.toggle_pause()
    assert scene.frame(elapsed=0.05) == 5
    # Simulated time per wall second over the frames that stepped: 0.14 s in 1.09 s.
    assert scene.real_time_ratio == pytest.approx(0.14 / 1.09)
    assert scene.capacity_ratio > 0


def test_gravity_switch_and_reset():
    mesh, scene = cantilever_scene()
    tip = mesh.nearest_node((2.0, 0.25, 0.5))
    for _ in range(10):
        scene.frame(elapsed=0.05)
    assert scene.sim.displacements[tip, 2] < -1e-3  # sags
    scene.set_gravity(False)
    np.testing.assert_array_equal(scene.sim.gravity, 0.0)
    assert "gravity off" in scene.status()
    scene.grab(mesh.points[tip], (2.0, 0.25, 3.0))
    scene.reset()
    assert scene.grabbed is None and scene.sim.attachments[0].size == 0
    assert scene.sim.time == 0.0
    np.testing.assert_array_equal(scene.sim.positions, mesh.points)
    scene.set_gravity(True)
    np.testing.assert_array_equal(scene.sim.gravity, (0.0, 0.0, -9.81))


def test_bad_mouse_input_is_refused():
    mesh, scene = cantilever_scene()
    with pytest.raises(ValueError, match="point must be a finite 3-vector"):
        scene.grab((np.nan, 0, 0), (0, 0, 1))
    scene.grab(mesh.points[0], (0, 0, 3))
    with pytest.raises(ValueError, match="direction must not be zero"):
        scene.drag((0, 0, 3), (0, 0, 0))
    with pytest.raises(ValueError, match="max_steps"):
        InteractiveScene(scene.sim, max_steps=0)
    with pytest.raises(TypeError, match="triangles"):
        InteractiveScene(scene.sim, surface=object())


class RenderSurface:
    """A stand-in for an embedded render surface: one triangle over three body nodes."""

    def __init__(self):
        self.triangles = np.array([[0, 1, 2]])
        self.positions = np.zeros((3, 3))
        self.updates = 0

    def update(self, body_positions):
        self.positions[:] = body_positions[[0, 5, 10]]
        self.updates += 1


def test_any_surface_with_positions_and_triangles_can_be_shown():
    surface = RenderSurface()
    _, scene = cantilever_scene(surface=surface)
    assert surface.updates == 1  # placed on the body at once
    scene.frame(elapsed=0.01)
    assert surface.updates == 2
    np.testing.assert_array_equal(surface.positions, scene.sim.positions[[0, 5, 10]])


def test_an_embedded_render_surface_is_shown_and_moves_with_the_body():
    # A box surface inside the cantilever, embedded: the scene updates it every frame, so a
    # drag of the tip moves the surface's far end with it.
    mesh = cr.beam(2.0, 0.5, 0.5, cells=(8, 2, 2))
    body = cr.Body(mesh, cr.Material(E=1e6, nu=0.3, density=1000.0))
    sim = cr.Simulation(body, dt=0.01, rayleigh=(2.0, 0.0))
    sim.fix(mesh.nodes_on_plane("x", 0.0))
    inner = cr.box((1.8, 0.3, 0.3), (6, 1, 1), origin=(0.1, 0.1, 0.1))
    surface = cr.EmbeddedSurface(body, inner.points, boundary_triangles(inner))
    scene = InteractiveScene(sim, surface=surface, gravity=(0, 0, 0))
    assert scene.triangles.shape == (surface.n_triangles, 3)
    tip = mesh.nearest_node((2.0, 0.25, 0.5))
    eye = (2.0, 3.0, 0.5)  # looking at the tip from the side (along -y)
    scene.grab(mesh.points[tip], eye)
    for _ in range(50):
        scene.drag(eye, (0.0, -1.0, 0.1))  # the mouse moved up: the target rises by about 0.27 m
        scene.frame(elapsed=0.05)
    far = surface.positions[:, 0] > 1.8
    assert scene.sim.displacements[tip, 2] > 0.05
    assert surface.positions[far, 2].mean() - inner.points[far, 2].mean() > 0.03


def test_corotate_view_without_the_extra_says_what_to_install(monkeypatch, capsys):
    from corotate.cli import main

    monkeypatch.setitem(sys.modules, "polyscope", None)  # as if not installed
    assert main(["view", "--frames", "1", "--cells", "1"]) == 2
    assert "corotate view needs polyscope: pip install 'corotate-fem[view]'" in capsys.readouterr().err


def test_a_probe_following_the_mouse_pushes_the_body_and_feels_it():
    """corotate view --contact: a cube resting on a floor, a probe swept sideways through it
    by the mouse: the cube is pushed the probe's way, the probe feels the cube push back
    (against its motion), and parking the probe lets go."""
    mesh = cr.box((0.1, 0.1, 0.1), (4, 4, 4), origin=(-0.05, -0.05, 0.0))
    sim = cr.Simulation(cr.Body(mesh, cr.Material(E=1e6, nu=0.3, density=1000.0)), dt=0.01)
    sim.add_obstacle(cr.Plane(), friction=0.5)
    scene = InteractiveScene(sim, probe_radius=0.03)
    assert scene.probe.position[2] > 0.1  # parked above the body
    scene.frame(0.05)
    assert np.allclose(scene.probe_force, 0.0)
    eye = np.array([0.0, 0.0, 2.0])  # looking down; the probe sweeps along x at the centre's depth
    pushed = []
    for x in np.linspace(-0.15, 0.03, 19):
        scene.move_probe(eye, np.array([x, 0.0, 0.05]) - eye)
        scene.frame(0.01)
        pushed.append(scene.probe_force[0])
    assert sim.positions[:, 0].mean() > 0.005  # the cube was shoved along +x
    assert min(pushed) < -0.1  # the probe felt it push back against the sweep
    assert "probe force" in scene.status()
    scene.park_probe()
    scene.frame(0.05)
    assert np.allclose(scene.probe_force, 0.0)
    with pytest.raises(ValueError, match="direction must not be zero"):
        scene.move_probe(eye, (0, 0, 0))
    with pytest.raises(ValueError, match="no probe"):
        cantilever_scene()[1].move_probe(eye, (0, 0, -1))
