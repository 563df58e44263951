"""Force feedback at a tool: the force a body exerts on a few prescribed nodes, and its local
stiffness, from only the elements that touch them (paper section 2.2.3), fast enough for a
haptic loop at 1 kHz while the body steps at 100-500 Hz.

    fb = cr.HapticFeedback(body, tool_nodes, method="averaged")
    for step in range(...):
        sim.positions[tool_nodes] = device_position(...)   # the device moves the tool
        sim.step()
        for _ in range(10):                                 # haptic rate: 10 queries per step
            forces, stiffness = fb.query(sim.positions)
            render(forces.sum(axis=0), stiffness)

Methods: "linear" (f = -K (x - X)), "corotational" (the paper's eq. 3: right under rotation,
linear in the element frame) and "averaged" (eq. 5, the averaged stiffness: the secant form
of St. Venant-Kirchhoff, exact under rotation and large stretch). The derivation is in
cpp/include/corotate/feedback/haptic_feedback.hpp.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

import corotate._core as _core

from ._scene_nodes import SceneNodes, body_rows
from .body import Body
from .choices import FEEDBACK_METHODS, FeedbackMethod, check_choice
from .driven_body import DrivenBody

if TYPE_CHECKING:
    from numpy.typing import ArrayLike


class HapticFeedback:
    """Force feedback at the tool nodes of a body.

    body    Body (its mesh and material(s), each element's own; the model used for the
            feedback is `method`, with the small-strain moduli E, nu of the materials)
    tool    node indices (int array or boolean mask) of the tool: the nodes the device moves
    method  "averaged" (default), "corotational" or "linear"

    The elements around the tool are copied once into a small model of their own; each query
    reads only their nodes.
    """

    def __init__(self, body: Body, tool: ArrayLike, method: FeedbackMethod = "averaged") -> None:
        if not isinstance(body, Body):
            raise TypeError("body must be a corotate.Body")
        check_choice(method, FEEDBACK_METHODS, "feedback method")
        nodes = np.asarray(tool)
        if nodes.dtype == bool:
            if nodes.shape != (body.n_nodes,):
                raise ValueError("a boolean tool mask needs one entry per node")
            nodes = np.flatnonzero(nodes)
        if nodes.size and not np.issubdtype(nodes.dtype, np.integer):
            raise ValueError("tool node indices must be integers")
        mesh = body.mesh
        self.body = body
        self._scene: SceneNodes | None = None  # set by Scene.haptic_feedback
        self._core = _core.HapticFeedback(
            mesh.cell_type,
            mesh.points,
            mesh.cells,
            body._core_materials(),
            [int(i) for i in nodes.ravel()],
            method,
            thickness=1.0 if body.thickness is None else body.thickness,
        )

    @property
    def tool(self) -> np.ndarray:
        """(k,) the tool's node indices."""
        return np.array(self._core.tool, dtype=np.int64)

    @property
    def method(self) -> str:
        return str(self._core.method)

    @property
    def num_elements(self) -> int:
        """Elements that touch the tool (the ones each query evaluates)."""
        return int(self._core.num_elements)

    def query(self, positions: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """At the body's positions (n, 3) (for a scene's body, ``Scene.haptic_feedback``, also
        the scene's): (forces (k, 3), the force the body exerts on each tool node, i.e. its
        internal elastic force there; stiffness (3k, 3k), dF/dx with respect to the tool
        nodes' positions, DOF 3*a + axis)."""
        x = body_rows(np.asarray(positions, dtype=np.float64), self.body.n_nodes, self._scene, "positions")
        forces, stiffness = self._core.query(np.ascontiguousarray(x))
        return np.asarray(forces), np.asarray(stiffness)

    def reaction_forces(self, sim: DrivenBody) -> np.ndarray:
        """(k, 3) the force the body of `sim` exerts on each tool node at its current state,
        inertia included: f_int + f_ext + M g - (M a) on the tool's rows, with f_int from the
        tool's elements (this feedback's method), a the last step's acceleration and M the
        simulation's mass. In statics (a = 0) the supports' reactions; in dynamics, by momentum
        balance, what holds the tool on its prescribed motion. For a scene's body, `sim` is a
        simulation of the scene."""
        body = self.body if self._scene is None else self._scene.scene_body
        if not isinstance(sim, DrivenBody) or sim.body is not body:
            whose = " (its scene)" if self._scene is not None else ""
            raise ValueError(f"sim must be a simulation of this feedback's body{whose}")
        forces, _ = self.query(sim.positions)
        tool = self.tool + (self._scene.start if self._scene is not None else 0)  # the simulation's nodes
        dofs = (3 * tool[:, None] + np.arange(3)).ravel()
        inertia = (sim.mass_matrix()[dofs] @ sim.accelerations.ravel()).reshape(-1, 3)
        return forces + sim.external_forces[tool] + sim.gravity_forces[tool] - inertia

    def total_force(self, positions: ArrayLike) -> np.ndarray:
        """(3,) the resultant force the body exerts on the tool."""
        return self.query(positions)[0].sum(axis=0)


class ToolFeedback:
    """Force feedback through contact: the force a body exerts on a rigid tool (an obstacle
    of the simulation that the hand moves) and its stiffness, at haptic rate.

        probe = cr.Sphere(center, 0.01)
        sim.add_obstacle(probe)
        feedback = cr.ToolFeedback(sim, probe)
        for frame in ...:
            probe.move_to(device_position())   # the body's step sees the tool here
            sim.step()
            feedback.update()                  # force on the tool now, secant stiffness
            for _ in range(10):                # 1 kHz between two 100 Hz steps
                force, stiffness = feedback.query(device_position())

    ``query(p)`` returns F0 + K (p - p0) and K = dF/dp: F0 is the force the contacts exerted
    on the tool at the last step (the negative of the force on the body, friction included),
    p0 the tool's position then, and K the secant of the force along the tool's own motion,
    updated at every step (Powell's symmetric secant update): where the tissue deforms
    largely, the paper's averaged stiffness of the whole body under the tool. Zero while the
    tool touches nothing. ``query`` is thread-safe, releases the GIL and allocates nothing in
    C++ (cpp/include/corotate/feedback/tool_feedback.hpp); call ``update`` from the thread
    that steps the body.
    """

    def __init__(self, sim: DrivenBody, tool: Any) -> None:
        from .obstacles import Obstacle

        if not isinstance(tool, Obstacle):
            raise TypeError(f"tool must be a corotate obstacle (Sphere, Capsule, ...), not {type(tool).__name__}")
        if not any(o is tool for o, _ in getattr(sim, "obstacles", [])):
            raise ValueError(f"{tool!r} is not an obstacle of this simulation: add it with sim.add_obstacle first")
        self._sim = sim
        self._tool = tool
        self._core = _core.ToolFeedback(tool._core)
        self._core.update(sim._sim)

    def update(self) -> None:
        """Take the force on the tool after the simulation's last step, and update the
        stiffness along the tool's motion since the last update."""
        self._core.update(self._sim._sim)

    def query(self, position: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """(force on the tool (3,), dF/dp (3, 3)) with the tool at `position` (3,)."""
        p = np.asarray(position, dtype=float)
        if p.shape != (3,) or not np.all(np.isfinite(p)):
            raise ValueError(f"position must be a finite 3-vector, got {p!r}")
        force, stiffness = self._core.query(p)
        return np.asarray(force), np.asarray(stiffness)

    @property
    def touching(self) -> bool:
        """Whether the tool touched the body at the last update."""
        return bool(self._core.touching)
