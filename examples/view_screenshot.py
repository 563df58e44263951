"""The screenshot of ``corotate view`` in the README: the demo cantilever (5 x 1 x 1 m, 1,920
tets, E = 1 MPa) sagging under gravity while its top tip node is dragged up and sideways through
the mouse spring, drawn by polyscope in a real OpenGL window. Scripted (no mouse): the drag
rises for two seconds of simulated time in frames of 0.05 s.

Needs the extra ``corotate-fem[view]`` and a display; on a machine without one, a virtual
X server with Mesa's software OpenGL does it:

    xvfb-run -s "-screen 0 1280x800x24" python examples/view_screenshot.py docs/_static/images/view.png
"""

from __future__ import annotations

import sys

import numpy as np

import corotate as cr
from corotate.view import InteractiveScene, Window


def main(path: str) -> None:
    mesh = cr.beam(5.0, 1.0, 1.0, cells=(20, 4, 4))
    sim = cr.Simulation(cr.Body(mesh, cr.Material(E=1e6, nu=0.3, density=1000.0)), dt=0.01, rayleigh=(1.0, 0.0))
    sim.fix(mesh.nodes_on_plane("x", 0.0))
    scene = InteractiveScene(sim)
    window = Window(scene, frame_time=0.05, use_mouse=False)
    window.ps.set_window_size(1000, 560)
    window.ps.set_build_default_gui_panels(False)  # only corotate's panel
    window.ps.look_at((5.5, -6.5, 3.0), (2.3, 0.5, 0.6))
    tip = mesh.nearest_node((5.0, 0.5, 1.0))
    eye = np.array([5.0, -6.0, 1.0])  # the mouse's camera: in front of the tip
    scene.grab(mesh.points[tip], eye)
    for frame in range(40):
        rise = min(frame / 30, 1.0)  # the mouse moves up and to the side, then holds
        scene.drag(eye, (0.1 * rise, 1.0, 0.3 * rise))
        window.run_frames(1)
    window.run_frames(2)  # polyscope shows a frame late
    window.screenshot(path)
    print(f"wrote {path}: {scene.status()}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "view.png")
