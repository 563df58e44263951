"""Several bodies simulated together: one Simulation of all of them, whose parts touch.

A scene joins its bodies' meshes into one body of several parts (each keeps its own
material, through regions) and steps them in one implicit system: every part's surface nodes
touch the other parts' surfaces, and the coupling between a node and the triangle it presses
on is part of the linear solve (contact/contact_set.hpp), so two bodies in contact are as
stable at the real-time step as one body on the floor, and momentum passes from one to the
other exactly. Fixing, attaching and loading take the simulation's node indices:
``scene.nodes(k)`` maps body k's own node indices to them.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, cast

import numpy as np

from ._scene_nodes import SceneNodes
from .body import Body
from .embedding import EmbeddedSurface
from .feedback import HapticFeedback
from .joined_body import JoinedBody, check_solid_bodies, node_offsets
from .mesh import Mesh
from .mesh_checks import _unchecked
from .simulation import Simulation

if TYPE_CHECKING:
    from collections.abc import Sequence

    from numpy.typing import ArrayLike

    from .choices import FeedbackMethod, ModelName


class Scene:
    """Bodies (``corotate.Body``, solids of any cell type and force model) simulated as one.

    bodies  the bodies, at their places in the world (their meshes' coordinates)

    Example::

        scene = cr.Scene([lower, upper])
        sim = scene.simulation(gravity=(0, 0, -9.81), friction=0.3)
        sim.add_obstacle(cr.Plane(), friction=0.5)
        sim.fix(scene.nodes(0, [0, 1, 2]))   # body 0's nodes 0, 1, 2
        sim.step(100)
        upper_positions = sim.positions[scene.nodes(1)]

    Bodies of one cell type and model are joined into one Body (one model sweeps them all);
    bodies that differ (a co-rotated tet organ on a Neo-Hookean hex pad) into a JoinedBody,
    each body's part computed by its own model. Rigid objects are obstacles
    (``sim.add_obstacle``), moved between frames. ValueError for sheets.
    """

    def __init__(self, bodies: Sequence[Body]) -> None:
        bodies = check_solid_bodies(bodies, "a scene")
        self._bodies = bodies
        self._offsets = node_offsets(bodies)
        first = bodies[0]
        alike = all(
            (b.mesh.cell_type, b.model, b.project_psd) == (first.mesh.cell_type, first.model, first.project_psd)
            for b in bodies
        )
        self._body: Body | JoinedBody = _one_body(bodies) if alike else JoinedBody(bodies)

    @property
    def body(self) -> Body | JoinedBody:
        """The joined body, the bodies' nodes one after the other: a Body (one mesh, each cell
        with its material) when the bodies share cell type and model, else a JoinedBody."""
        return self._body

    @property
    def bodies(self) -> tuple[Body, ...]:
        """The bodies, in the order given (body k's mesh: ``scene.bodies[k].mesh``)."""
        return self._bodies

    @property
    def n_bodies(self) -> int:
        return len(self._offsets) - 1

    def nodes(self, k: int, local: ArrayLike | None = None) -> np.ndarray:
        """The simulation's node indices of body k's nodes (all, or those listed in `local`,
        body k's own indices). ValueError for a body or node out of range."""
        if not 0 <= int(k) < self.n_bodies:
            raise ValueError(f"body {k} is out of range: the scene has {self.n_bodies} bodies")
        start, stop = int(self._offsets[k]), int(self._offsets[k + 1])
        if local is None:
            return np.arange(start, stop)
        i = np.asarray(local)
        if i.size and (not np.issubdtype(i.dtype, np.integer) or i.min() < 0 or i.max() >= stop - start):
            raise ValueError(f"body {k} has nodes 0..{stop - start - 1}; got {np.asarray(local).tolist()}")
        return i.astype(np.int64) + start

    def embedded_surface(
        self, k: int, vertices: ArrayLike, triangles: ArrayLike, max_outside_distance: float = 1.0
    ) -> EmbeddedSurface:
        """A render surface embedded in body k (``corotate.EmbeddedSurface`` of
        ``scene.bodies[k]``, any cell type): its ``update`` takes the scene's simulation (or
        its positions) and moves with body k's nodes. Each body of a scene, mixed cell types
        included, can carry its own. ValueError for a body out of range, or as
        EmbeddedSurface."""
        scene = self._scene_nodes(k)
        surface = EmbeddedSurface(self._bodies[k], vertices, triangles, max_outside_distance=max_outside_distance)
        surface._scene = scene
        return surface

    def haptic_feedback(self, k: int, tool: ArrayLike, method: FeedbackMethod = "averaged") -> HapticFeedback:
        """Force feedback at tool nodes of body k (``corotate.HapticFeedback`` of
        ``scene.bodies[k]``, any cell type; `tool`: body k's own node indices or mask): its
        ``query`` takes body k's positions or the scene's, and ``reaction_forces`` a simulation
        of the scene. ValueError for a body out of range, or as HapticFeedback."""
        scene = self._scene_nodes(k)
        feedback = HapticFeedback(self._bodies[k], tool, method)
        feedback._scene = scene
        return feedback

    def _scene_nodes(self, k: int) -> SceneNodes:
        nodes = self.nodes(k)  # (checks k)
        return SceneNodes(int(nodes[0]), int(nodes[-1]) + 1, int(self._offsets[-1]), self._body)

    def simulation(self, friction: float = 0.0, self_contact: bool = False, **settings: Any) -> Simulation:
        """A Simulation of the scene's bodies (settings: as ``cr.Simulation``'s: dt, solver,
        gravity, mass, rayleigh, integrator...) whose parts touch with Coulomb `friction`
        (and each its own surface too, with `self_contact`). Contact needs an implicit
        integrator (the default)."""
        sim = Simulation(self._body, **settings)
        if len(np.unique(sim.parts)) > 1 or self_contact:
            sim.set_part_contact(friction, self_contact=self_contact)
        return sim


def _one_body(bodies: Sequence[Body]) -> Body:
    """Bodies of one cell type and model as one Body: their meshes joined, each body's regions
    renumbered after the bodies' before it (one material per region). The fast path: one
    model sweeps every element (the co-rotated tets' float32 assembly included)."""
    first = bodies[0]
    offsets = node_offsets(bodies)
    points = np.concatenate([b.mesh.points for b in bodies])
    cells = np.concatenate([b.mesh.cells + offsets[k] for k, b in enumerate(bodies)])
    materials: dict[int, Any] = {}
    regions = []
    for body in bodies:
        ids = np.array(sorted(body.materials))
        own = body.regions if body.regions is not None else np.full(body.mesh.n_cells, ids[0])
        regions.append(len(materials) + np.searchsorted(ids, own))
        materials.update({len(materials) + i: body.materials[int(r)] for i, r in enumerate(ids)})
    # Each body's mesh was checked on its own; joined, the bodies' nodes may coincide where
    # they touch (a block placed on a slab), which in one mesh would read as a cell soup: the
    # parts are separate on purpose, so the joined mesh is not re-checked.
    mesh = _unchecked(Mesh, points, cells, first.mesh.cell_type)
    return Body(
        mesh,
        materials,
        model=cast("ModelName", first.model),
        project_psd=first.project_psd,
        regions=np.concatenate(regions),
        _parts_checked=True,
    )
