"""The window of ``corotate view``: polyscope draws an InteractiveScene (view/scene.py) and
turns the mouse into grab, drag and release; a small panel has pause, reset, gravity and
the real-time ratio. Needs the optional extra: ``pip install 'corotate-fem[view]'``.

Why polyscope and not pyvista: polyscope is one small wheel (GLFW and Dear ImGui inside,
MIT) built for exactly this loop: a per-frame user callback, immediate-mode buttons, mouse
state and GPU picking of the point under the cursor, and a mock backend that runs the same
code with no display. pyvista drags in VTK (a wheel around ten times larger), its
interaction goes through VTK observers and timers, and a live drag needs a Qt window
(pyvistaqt) to stay responsive.
"""

from __future__ import annotations

import importlib
from typing import Any

import numpy as np

from .scene import InteractiveScene

HELP = "Shift + left drag: grab and pull the body.\nLeft drag: rotate, right drag: pan, wheel: zoom."
PROBE_HELP = "Ctrl + move: the probe sphere follows the mouse and pushes the body."


def polyscope() -> Any:
    """The polyscope module, or ImportError naming the extra that provides it."""
    try:
        return importlib.import_module("polyscope")
    except ImportError as e:
        raise ImportError("corotate view needs polyscope: pip install 'corotate-fem[view]'") from e


def _up_direction(gravity: np.ndarray) -> str:
    """polyscope's up direction: against gravity's largest component (z up without gravity)."""
    if not np.any(gravity):
        return "z_up"
    axis = int(np.argmax(np.abs(gravity)))
    return "xyz"[axis] + ("_up" if gravity[axis] < 0 else "_down")


class Window:
    """Draws a scene with polyscope and maps the mouse onto it.

    backend      polyscope's: "auto" for a window, "openGL_mock" for tests without a
                 display, "openGL3_egl" for headless rendering
    frame_time   None: frames follow the wall clock; a number [s]: every frame advances the
                 scene by that much (recordings, screenshots)
    use_mouse    False leaves the grab to the caller (scripted drags)
    """

    def __init__(
        self,
        scene: InteractiveScene,
        backend: str = "auto",
        title: str = "corotate view",
        frame_time: float | None = None,
        use_mouse: bool = True,
    ) -> None:
        self.frame_time = frame_time
        self.use_mouse = use_mouse
        self.ps = polyscope()
        self.imgui = importlib.import_module("polyscope.imgui")
        self.scene = scene
        self.ps.set_program_name(title)
        self.ps.set_use_prefs_file(False)  # no .polyscope.ini in the user's folder
        self.ps.set_user_gui_is_on_right_side(False)  # corotate's panel on the left, polyscope's on the right
        self.ps.set_up_dir(_up_direction(np.asarray(scene.sim.gravity)))
        self.ps.init(backend)
        self.ps.set_ground_plane_mode("shadow_only")
        surface = scene.surface
        self.mesh = self.ps.register_surface_mesh(
            "body", np.asarray(surface.positions), scene.triangles, color=(0.85, 0.55, 0.35)
        )
        self.mesh.set_edge_width(0.5)
        self.spring: Any = None  # the mouse spring, drawn while a node is held
        self.probe: Any = None  # the probe sphere, drawn when the scene has one
        if scene.probe is not None:
            self.probe = self.ps.register_point_cloud(
                "probe", np.asarray([scene.probe.position]), radius=scene.probe.radius, color=(0.2, 0.5, 0.9)
            )
            self.probe.set_radius(scene.probe.radius, relative=False)
        self.ps.set_user_callback(self.callback)

    def eye(self) -> np.ndarray:
        return np.asarray(self.ps.get_view_camera_parameters().get_position(), dtype=np.float64)

    def mouse(self, shift: bool, pressed: bool, down: bool, screen: tuple[float, float]) -> None:
        """One frame's mouse: shift + press grabs the surface point under the cursor, moving
        with the button down drags, letting go releases."""
        if self.scene.grabbed is None:
            if shift and pressed:
                point = np.asarray(self.ps.screen_coords_to_world_position(screen), dtype=np.float64)
                if np.all(np.isfinite(point)):  # the cursor is over the body
                    self.scene.grab(point, self.eye())
        elif down:
            self.scene.drag(self.eye(), self.ps.screen_coords_to_world_ray(screen))
        else:
            self.scene.release()
        # The camera keeps still while a node is held (and while shift asks for a grab).
        self.ps.set_do_default_mouse_interaction(self.scene.grabbed is None and not shift)

    def move_probe(self, ctrl: bool, screen: tuple[float, float]) -> None:
        """With Ctrl held, the probe follows the mouse (on the ray under the cursor)."""
        if ctrl and self.scene.probe is not None:
            self.scene.move_probe(self.eye(), self.ps.screen_coords_to_world_ray(screen))

    def panel(self) -> None:
        imgui, scene = self.imgui, self.scene
        imgui.TextUnformatted(scene.status().replace(" | ", "\n"))
        if imgui.Button("Resume" if scene.paused else "Pause"):
            scene.toggle_pause()
        imgui.SameLine()
        if imgui.Button("Reset"):
            scene.reset()
        imgui.SameLine()
        changed, on = imgui.Checkbox("gravity", scene.gravity_on)
        if changed:
            scene.set_gravity(on)
        imgui.TextUnformatted(HELP if scene.probe is None else HELP + "\n" + PROBE_HELP)

    def callback(self) -> None:
        """polyscope's per-frame callback: panel, mouse, one scene frame, new positions."""
        self.panel()
        io = self.imgui.GetIO()
        if self.use_mouse and not io.WantCaptureMouse:
            screen = tuple(self.imgui.GetMousePos())
            self.mouse(io.KeyShift, self.imgui.IsMouseClicked(0), self.imgui.IsMouseDown(0), screen)
            self.move_probe(io.KeyCtrl, screen)
        self.scene.frame(self.frame_time)
        self.draw()

    def draw(self) -> None:
        """Hand the new positions, and the mouse spring if a node is held, to polyscope."""
        self.mesh.update_vertex_positions(np.asarray(self.scene.surface.positions))
        if self.probe is not None:
            self.probe.update_point_positions(np.asarray([self.scene.probe.position]))
        if self.scene.grabbed is None:
            if self.spring is not None:
                self.spring.set_enabled(False)
            return
        nodes, targets, _ = self.scene.sim.attachments
        ends = np.vstack([self.scene.sim.positions[self.scene.grabbed], targets[nodes == self.scene.grabbed][0]])
        if self.spring is None:
            self.spring = self.ps.register_curve_network(
                "mouse spring", ends, np.array([[0, 1]]), color=(0.1, 0.3, 0.9), radius=0.004
            )
        else:
            self.spring.update_node_positions(ends)
        self.spring.set_enabled(True)

    def show(self) -> None:
        """Open the window and run until it is closed."""
        self.ps.show()

    def run_frames(self, frames: int) -> None:
        """Run a fixed number of frames (each one polyscope frame and one scene frame)."""
        for _ in range(frames):
            self.ps.frame_tick()

    def screenshot(self, path: str) -> None:
        """Write the current view to an image file (PNG)."""
        self.ps.screenshot(path, transparent_bg=False, include_UI=True)
