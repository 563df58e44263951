"""The screenshot of ``corotate view --contact`` in the viewer guide: a soft block (0.3 x 0.2 x
0.2 m, E = 200 kPa) dropped on the floor, then pushed from the side by the probe sphere the
mouse moves (scripted here: it comes in along the mouse ray over half a second and holds),
drawn by polyscope in a real OpenGL window; the panel shows the force the probe feels.

Needs the extra ``corotate-fem[view]`` and a display; on a machine without one:

    xvfb-run -s "-screen 0 1280x800x24" python examples/view_contact_screenshot.py docs/_static/images/view_contact.png
"""

from __future__ import annotations

import sys

import numpy as np

import corotate as cr
from corotate.view import InteractiveScene, Window


def main(path: str) -> None:
    mesh = cr.box((0.3, 0.2, 0.2), (12, 8, 8), origin=(-0.15, -0.1, 0.05))
    sim = cr.Simulation(cr.Body(mesh, cr.Material(E=2e5, nu=0.3, density=1000.0)), dt=0.01, rayleigh=(1.0, 0.0))
    sim.add_obstacle(cr.Plane(), friction=0.4)
    scene = InteractiveScene(sim, probe_radius=0.06)
    window = Window(scene, frame_time=0.05, use_mouse=False)
    window.ps.set_window_size(1000, 560)
    window.ps.set_build_default_gui_panels(False)  # only corotate's panel
    window.ps.look_at((-0.55, -0.75, 0.45), (-0.08, 0.0, 0.1))
    window.run_frames(12)  # it falls and settles
    eye = np.array([0.0, -1.0, 0.15])  # the mouse's camera, in front of the block
    for frame in range(40):
        # The cursor moves in from the left and keeps pushing the block's left end along.
        x = -0.3 + 0.005 * frame
        scene.move_probe(eye, np.array([x, 0.0, 0.12]) - eye)
        window.run_frames(1)
    window.screenshot(path)
    print(f"wrote {path}: {scene.status()}; probe force {np.round(scene.probe_force, 2).tolist()} N")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "view_contact.png")
