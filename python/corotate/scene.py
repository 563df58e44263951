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

from .body import Body
from .mesh import Mesh
from .mesh_checks import _unchecked
from .simulation import Simulation

if TYPE_CHECKING:
    from collections.abc import Sequence

    from numpy.typing import ArrayLike

    from .choices import ModelName


class Scene:
    """Bodies (``corotate.Body``, one cell type and one model for all) simulated as one.

    bodies  the bodies, at their places in the world (their meshes' coordinates)

    Example::

        scene = cr.Scene([lower, upper])
        sim = scene.simulation(gravity=(0, 0, -9.81), friction=0.3)
        sim.add_obstacle(cr.Plane(), friction=0.5)
        sim.fix(scene.nodes(0, [0, 1, 2]))   # body 0's nodes 0, 1, 2
        sim.step(100)
        upper_positions = sim.positions[scene.nodes(1)]

    Rigid objects are obstacles (``sim.add_obstacle``), moved between frames. ValueError for
    bodies of different cell types or models, or sheets.
    """

    def __init__(self, bodies: Sequence[Body]) -> None:
        bodies = list(bodies)
        if not bodies:
            raise ValueError("a scene needs at least one body")
        for k, body in enumerate(bodies):
            if not isinstance(body, Body):
                raise TypeError(f"body {k} is a {type(body).__name__}, not a corotate.Body")
        first = bodies[0]
        shared = {
            "cell_type": lambda b: b.mesh.cell_type,
            "model": lambda b: b.model,
            "project_psd": lambda b: b.project_psd,
        }
        for k, body in enumerate(bodies[1:], start=1):
            for name, of in shared.items():
                if of(body) != of(first):
                    raise ValueError(
                        f"body {k}'s {name} is {of(body)!r}, body 0's {of(first)!r}: a scene's bodies share it"
                    )
        if first.thickness is not None:
            raise ValueError("a scene's bodies are solids; sheets (triangle meshes) touch nothing yet")
        offsets = np.cumsum([0] + [b.n_nodes for b in bodies])
        points = np.concatenate([b.mesh.points for b in bodies])
        cells = np.concatenate([b.mesh.cells + offsets[k] for k, b in enumerate(bodies)])
        # Each body's regions, renumbered after the bodies before it: one material per region.
        materials: dict[int, Any] = {}
        regions = []
        for body in bodies:
            ids = np.array(sorted(body.materials))
            own = body.regions if body.regions is not None else np.full(body.mesh.n_cells, ids[0])
            regions.append(len(materials) + np.searchsorted(ids, own))
            materials.update({len(materials) + i: body.materials[int(r)] for i, r in enumerate(ids)})
        # Each body's mesh was checked on its own; joined, the bodies' nodes may coincide
        # where they touch (a block placed on a slab), which in one mesh would read as a
        # cell soup: the parts are separate on purpose, so the joined mesh is not re-checked.
        mesh = _unchecked(Mesh, points, cells, first.mesh.cell_type)
        self._offsets = offsets
        self._body = Body(
            mesh,
            materials,
            model=cast("ModelName", first.model),
            project_psd=first.project_psd,
            regions=np.concatenate(regions),
            _parts_checked=True,
        )

    @property
    def body(self) -> Body:
        """The joined body: the bodies' nodes one after the other, each cell with its material."""
        return self._body

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

    def simulation(self, friction: float = 0.0, self_contact: bool = False, **settings: Any) -> Simulation:
        """A Simulation of the scene's bodies (settings: as ``cr.Simulation``'s: dt, solver,
        gravity, mass, rayleigh, integrator...) whose parts touch with Coulomb `friction`
        (and each its own surface too, with `self_contact`). Contact needs an implicit
        integrator (the default)."""
        sim = Simulation(self._body, **settings)
        if len(np.unique(sim.parts)) > 1 or self_contact:
            sim.set_part_contact(friction, self_contact=self_contact)
        return sim
