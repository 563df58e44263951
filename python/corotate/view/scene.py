"""The live scene of ``corotate view`` without a window: stepping paced to the wall clock,
grabbing and dragging a node with the mouse through an implicit attachment, a probe sphere
that follows the mouse and pushes the body through contact (with the force it feels),
pause, reset, gravity on and off, and the real-time ratio. A window (view/window.py) feeds it mouse rays
and draws what it returns; tests feed it synthetic events with no display."""

from __future__ import annotations

import time
from collections import deque
from typing import TYPE_CHECKING, Any

import numpy as np

from .surface import BodySurface

if TYPE_CHECKING:
    from numpy.typing import ArrayLike


class InteractiveScene:
    """One simulation shown live.

    sim              a corotate.Simulation (or ExplicitSimulation) of a Body; its dt is the step
    surface          what is drawn: None for the body's boundary, or a render surface:
                     a corotate.EmbeddedSurface, or any object with ``positions`` ((m, 3),
                     current) and ``triangles`` ((f, 3); or ``mesh.cells``); if it has
                     ``update(body_positions)``, that is called after every frame first
    max_steps        steps per frame at most (the paper's Table 1 takes 5 of 0.01 s)
    grab_stiffness   k [N/m] of the mouse spring, shared by the grabbed nodes; default
                     100 x E x (mean edge length), far stiffer than the body near the nodes,
                     so they follow the mouse
    grab_radius      nodes within this distance [m] of the grabbed node are held with it
                     (they move as one patch, so a soft body does not grow a spike); default
                     the mean edge length
    gravity          (3,) acceleration while gravity is on
    probe_radius     a radius [m] adds a probe: a sphere that ``move_probe`` places on the
                     mouse ray and that pushes the body through contact (``probe_force`` is
                     what it feels); None (default): no probe

    Frames are paced to the wall clock: each frame takes as many steps as the time since the
    last frame covers (at most max_steps: a slow machine falls behind instead of stalling).
    """

    def __init__(
        self,
        sim: Any,
        surface: Any = None,
        max_steps: int = 5,
        grab_stiffness: float | None = None,
        gravity: ArrayLike = (0.0, 0.0, -9.81),
        grab_radius: float | None = None,
        probe_radius: float | None = None,
    ) -> None:
        if not isinstance(max_steps, int) or max_steps < 1:
            raise ValueError(f"max_steps must be a positive integer, got {max_steps!r}")
        self.sim = sim
        self.surface = BodySurface(sim) if surface is None else surface
        triangles = getattr(self.surface, "triangles", None)
        if triangles is None and hasattr(self.surface, "mesh"):
            triangles = self.surface.mesh.cells  # an EmbeddedSurface
        if triangles is None or not hasattr(self.surface, "positions"):
            raise TypeError("surface must have positions ((m, 3) array) and triangles ((f, 3) node indices)")
        self.triangles = np.asarray(triangles)
        if hasattr(self.surface, "update"):
            self.surface.update(sim.positions)
        self.max_steps = max_steps
        self.dt = float(sim.dt)
        mesh = sim.body.mesh
        edge = float(np.linalg.norm(mesh.points[mesh.cells[:, 0]] - mesh.points[mesh.cells[:, 1]], axis=1).mean())
        stiffest = max(m.E for m in sim.body.materials.values())
        self.grab_stiffness = float(100.0 * stiffest * edge if grab_stiffness is None else grab_stiffness)
        if not (self.grab_stiffness > 0 and np.isfinite(self.grab_stiffness)):
            raise ValueError(f"grab_stiffness must be positive and finite, got {grab_stiffness}")
        self.grab_radius = float(edge if grab_radius is None else grab_radius)
        if not (self.grab_radius >= 0 and np.isfinite(self.grab_radius)):
            raise ValueError(f"grab_radius must be >= 0 and finite, got {grab_radius}")
        self._gravity = np.asarray(gravity, dtype=np.float64)
        if self._gravity.shape != (3,) or not np.all(np.isfinite(self._gravity)):
            raise ValueError("gravity must be a finite 3-vector")
        self.sim.gravity = self._gravity
        self.gravity_on = True
        self.paused = False
        self.grabbed: int | None = None  # the node under the mouse
        self._held = np.zeros(0, dtype=np.int64)  # it and its neighbours within grab_radius
        self._offsets = np.zeros((0, 3))  # their positions relative to it at the grab
        self._grab_depth = 0.0
        self._debt = 0.0  # wall time not yet simulated [s]
        self._frames: deque[tuple[float, float, float]] = deque(maxlen=60)  # (wall, simulated, stepping) s
        self._last_frame: float | None = None
        self.probe: Any = None  # a corotate.Sphere following the mouse, when asked for
        if probe_radius is not None:
            from ..obstacles import Sphere

            self.probe = Sphere(self._parking(float(probe_radius)), probe_radius)
            sim.add_obstacle(self.probe)

    # --- the controls --------------------------------------------------------------------
    def set_gravity(self, on: bool) -> None:
        """Gravity on (the scene's gravity vector) or off."""
        self.gravity_on = bool(on)
        self.sim.gravity = self._gravity if self.gravity_on else np.zeros(3)

    def toggle_pause(self) -> None:
        """Pause or resume; a paused scene still lets a node be grabbed and moves on resume."""
        self.paused = not self.paused
        self._last_frame = None

    def reset(self) -> None:
        """Back to the rest state; lets go of a grabbed node and parks the probe."""
        self.release()
        self.sim.reset()
        self.park_probe()
        self._debt = 0.0
        self._frames.clear()
        self._last_frame = None

    # --- the mouse -----------------------------------------------------------------------
    def grab(self, point: ArrayLike, eye: ArrayLike) -> int:
        """Grab the body node nearest to ``point`` (the surface point under the mouse) seen
        from ``eye`` (the camera position), with the free nodes within grab_radius of it:
        they are attached where they are, and later mouse rays drag them as one patch, the
        grabbed node at the same distance from the eye. Returns the grabbed node."""
        p = _finite_vector(point, "point")
        e = _finite_vector(eye, "eye")
        self.release()
        x = self.sim.positions
        node = int(np.argmin(np.einsum("ij,ij->i", x - p, x - p)))
        near = np.linalg.norm(x - x[node], axis=1) <= self.grab_radius
        near[self.sim.fixed_nodes] = False
        near[node] = True
        held = np.flatnonzero(near)
        self.sim.attach(held, x[held].copy(), self.grab_stiffness / len(held))
        self.grabbed, self._held, self._offsets = node, held, x[held] - x[node]
        self._grab_depth = float(np.linalg.norm(x[node] - e))
        return node

    def drag(self, eye: ArrayLike, direction: ArrayLike) -> None:
        """Move the grabbed node's target to the point on the mouse ray (from ``eye`` along
        ``direction``) at the grab's distance from the eye. No-op when nothing is grabbed."""
        if self.grabbed is None:
            return
        e = _finite_vector(eye, "eye")
        d = _finite_vector(direction, "direction")
        norm = np.linalg.norm(d)
        if norm == 0:
            raise ValueError("direction must not be zero")
        self.sim.move_attachments(self._held, e + self._grab_depth * d / norm + self._offsets)

    def move_probe(self, eye: ArrayLike, direction: ArrayLike) -> None:
        """Put the probe on the mouse ray (from ``eye`` along ``direction``) as far from the
        eye as the body's centre is: it sweeps through the body's middle as the mouse moves,
        and the contact pushes the body aside (a fast swipe too: contact follows the probe's
        whole path). ValueError without a probe."""
        if self.probe is None:
            raise ValueError("this scene has no probe (InteractiveScene(..., probe_radius=r))")
        e = _finite_vector(eye, "eye")
        d = _finite_vector(direction, "direction")
        norm = np.linalg.norm(d)
        if norm == 0:
            raise ValueError("direction must not be zero")
        depth = float(np.linalg.norm(self.sim.positions.mean(axis=0) - e))
        self.probe.move_to(e + depth * d / norm)

    def park_probe(self) -> None:
        """Take the probe out of the way (above the body) at once: it is lifted out of the
        scene and put back there, not swept there (a sweep would drag through the body)."""
        if self.probe is not None:
            friction = next(mu for o, mu in self.sim.obstacles if o is self.probe)
            self.sim.remove_obstacle(self.probe)
            self.probe.move_to(self._parking(self.probe.radius))
            self.sim.add_obstacle(self.probe, friction)

    @property
    def probe_force(self) -> np.ndarray:
        """(3,) the force the body exerted on the probe in the last step [N] (zero without
        contact or without a probe)."""
        if self.probe is None:
            return np.zeros(3)
        return -np.asarray(self.sim.contact_force(self.probe))

    def _parking(self, radius: float) -> np.ndarray:
        x = self.sim.positions
        up = -self._gravity / np.linalg.norm(self._gravity) if np.any(self._gravity) else np.array([0.0, 0.0, 1.0])
        top = float((x @ up).max())
        centre = x.mean(axis=0)
        return centre + (top - float(centre @ up) + 3.0 * radius + np.ptp(x, axis=0).max()) * up

    def release(self) -> None:
        """Let go of the grabbed node (if any)."""
        if self.grabbed is not None:
            self.sim.detach(self._held)
            self.grabbed = None

    # --- the loop ------------------------------------------------------------------------
    def frame(self, elapsed: float | None = None) -> int:
        """Advance by the wall time since the last frame (or by ``elapsed`` seconds, for tests
        and recordings), in whole steps, at most max_steps; nothing while paused. Then update
        the surface. Returns the number of steps taken."""
        now = time.perf_counter()
        if elapsed is None:
            elapsed = self.dt if self._last_frame is None else now - self._last_frame
        self._last_frame = now
        steps = 0
        if not self.paused:
            self._debt = min(self._debt + float(elapsed), self.max_steps * self.dt)
            steps = int(self._debt / self.dt + 1e-9)
            self._debt = max(self._debt - steps * self.dt, 0.0)
            start = time.perf_counter()
            if steps:
                self.sim.step(steps)
            self._frames.append((float(elapsed), steps * self.dt, time.perf_counter() - start))
        if hasattr(self.surface, "update"):
            self.surface.update(self.sim.positions)
        return steps

    @property
    def real_time_ratio(self) -> float:
        """Simulated time per wall second over the last 60 frames (1 when keeping pace)."""
        wall = sum(f[0] for f in self._frames)
        return sum(f[1] for f in self._frames) / wall if wall > 0 else 0.0

    @property
    def capacity_ratio(self) -> float:
        """Simulated time per second spent stepping over the last 60 frames: how much faster
        than real time the simulation alone runs."""
        busy = sum(f[2] for f in self._frames)
        return sum(f[1] for f in self._frames) / busy if busy > 0 else 0.0

    def status(self) -> str:
        """One line for the screen: time, real-time ratio, state of the controls."""
        parts = [
            f"t = {self.sim.time:.2f} s",
            f"real time x{self.real_time_ratio:.2f} (simulation alone x{self.capacity_ratio:.1f})",
            "gravity on" if self.gravity_on else "gravity off",
        ]
        if self.paused:
            parts.append("PAUSED")
        if self.grabbed is not None:
            parts.append(f"dragging node {self.grabbed}")
        if self.probe is not None:
            force = self.probe_force
            parts.append(f"probe force {np.linalg.norm(force):.3g} N")
        return " | ".join(parts)


def _finite_vector(v: ArrayLike, name: str) -> np.ndarray:
    a = np.asarray(v, dtype=np.float64)
    if a.shape != (3,) or not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be a finite 3-vector, got {v!r}")
    return a
