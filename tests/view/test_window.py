"""The polyscope window of ``corotate view`` on polyscope's mock backend (no display): the
mouse mapping grabs, drags and releases through the scene, and the CLI runs frames. Skipped
when the optional extra (polyscope) is not installed."""

from __future__ import annotations

import meshio
import numpy as np
import pytest

import corotate as cr
from corotate.cli import main
from corotate.view import InteractiveScene

pytest.importorskip("polyscope", reason="the optional extra corotate-fem[view] (polyscope) is not installed")

from corotate.view import Window


@pytest.fixture(scope="module")
def window():
    mesh = cr.beam(2.0, 0.5, 0.5, cells=(4, 1, 1))
    sim = cr.Simulation(cr.Body(mesh, cr.Material(E=1e6, nu=0.3, density=1000.0)), dt=0.01)
    sim.fix(mesh.nodes_on_plane("x", 0.0))
    return Window(InteractiveScene(sim), backend="openGL_mock")


def test_shift_press_grabs_drag_moves_the_target_and_letting_go_releases(window, monkeypatch):
    tip = window.scene.sim.positions[-1].copy()
    eye = tip + np.array([0.0, 0.0, 2.0])
    monkeypatch.setattr(window.ps, "screen_coords_to_world_position", lambda screen: tip)
    monkeypatch.setattr(window.ps, "screen_coords_to_world_ray", lambda screen: np.array([0.0, 0.6, -0.8]))
    monkeypatch.setattr(window, "eye", lambda: eye)
    window.mouse(shift=False, pressed=True, down=True, screen=(1, 1))  # plain press: the camera's
    assert window.scene.grabbed is None
    window.mouse(shift=True, pressed=True, down=True, screen=(1, 1))
    assert window.scene.grabbed == window.scene.sim.body.n_nodes - 1
    window.mouse(shift=True, pressed=False, down=True, screen=(2, 2))
    nodes, targets, _ = window.scene.sim.attachments
    np.testing.assert_allclose(targets[nodes == window.scene.grabbed][0], eye + 2.0 * np.array([0.0, 0.6, -0.8]))
    window.draw()
    assert window.spring is not None
    window.mouse(shift=False, pressed=False, down=False, screen=(2, 2))
    assert window.scene.grabbed is None


def test_frames_run_the_scene(window):
    # (The callback draws ImGui widgets: it may run only inside a polyscope frame.)
    time_before = window.scene.sim.time
    window.run_frames(3)
    assert window.scene.sim.time > time_before


def test_the_cli_runs_frames_on_the_mock_backend(capsys, tmp_path):
    assert main(["view", "--backend", "openGL_mock", "--frames", "2", "--cells", "1"]) == 0
    out = capsys.readouterr().out
    assert "grab stiffness" in out and "real time x" in out
    # A render surface from a file, embedded in the (5 x 1 x 1 m) beam.
    inner = cr.boundary_surface(cr.box((4.0, 0.6, 0.6), (4, 1, 1), origin=(0.5, 0.2, 0.2)))
    path = tmp_path / "inner.obj"
    meshio.write_points_cells(path, inner.points, [("triangle", inner.cells)])
    args = ["view", "--backend", "openGL_mock", "--frames", "2", "--cells", "1", "--surface", str(path)]
    assert main(args) == 0
    assert f"showing {path} ({inner.n_cells} triangles)" in capsys.readouterr().out
