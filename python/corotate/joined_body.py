"""Bodies of different cell types or force models as one: what a Scene of them simulates."""

from __future__ import annotations

from typing import TYPE_CHECKING, ClassVar

import numpy as np

import corotate._core as _core

from ._attributes import SettableOnly
from .body import Body, ModelQueries

if TYPE_CHECKING:
    from collections.abc import Sequence


def node_offsets(bodies: Sequence[Body]) -> np.ndarray:
    """Where each body's nodes start when the bodies' nodes are numbered one after another,
    and their total at the end (len(bodies) + 1 entries)."""
    return np.cumsum([0] + [b.n_nodes for b in bodies])


def check_solid_bodies(bodies: Sequence[Body], what: str) -> tuple[Body, ...]:
    """The bodies as a tuple; TypeError for one that is not a Body, ValueError for none or a
    sheet (sheets touch nothing yet)."""
    bodies = tuple(bodies)
    if not bodies:
        raise ValueError(f"{what} needs at least one body")
    for k, body in enumerate(bodies):
        if not isinstance(body, Body):
            raise TypeError(f"body {k} is a {type(body).__name__}, not a corotate.Body")
        if body.thickness is not None:
            raise ValueError(
                f"body {k} is a sheet (triangle cells): {what}'s bodies are solids; sheets touch nothing yet"
            )
    return bodies


class JoinedBody(ModelQueries, SettableOnly):
    """Several bodies side by side, their nodes one body after the other: one force model
    over all of them, each body's part computed by its own model (cell type, force model,
    materials), the bodies sharing no node. ``corotate.Scene`` builds one when its bodies
    differ in cell type or force model; a Simulation steps it like a Body.

    bodies  the corotate.Body objects (solids), in their order in the joined node numbering

    internal_forces, energy, stiffness_matrix, tangent_matrix, mass_matrix and
    geometric_stiffness answer for all nodes at once, as a Body's do. Each body's own mesh is
    ``joined.bodies[k].mesh``; its nodes are ``joined.nodes(k)`` (``Scene.nodes`` too).
    Immutable, as a Body.
    """

    _READ_ONLY_HINTS: ClassVar[dict[str, str]] = {
        name: "a JoinedBody is immutable after construction; create a new one"
        for name in ("bodies", "n_nodes", "model")
    }

    def __init__(self, bodies: Sequence[Body]) -> None:
        bodies = check_solid_bodies(bodies, "a joined body")
        self._bodies = bodies
        self._offsets = node_offsets(bodies)
        rest = np.concatenate([b.mesh.points for b in bodies])
        rest.flags.writeable = False
        self._rest = rest
        self._force_model = _core.ForceModel.joined([b._force_model for b in bodies])

    @property
    def bodies(self) -> tuple[Body, ...]:
        """The bodies joined, in order (read-only)."""
        return self._bodies

    @property
    def n_nodes(self) -> int:
        return int(self._offsets[-1])

    @property
    def model(self) -> str:
        """ "joined" (each body's own model: ``bodies[k].model``)."""
        return "joined"

    def nodes(self, k: int) -> np.ndarray:
        """The joined node indices of body k's nodes. ValueError for a body out of range."""
        if not 0 <= int(k) < len(self._bodies):
            raise ValueError(f"body {k} is out of range: the joined body has {len(self._bodies)} bodies")
        return np.arange(int(self._offsets[k]), int(self._offsets[k + 1]))

    @property
    def _rest_points(self) -> np.ndarray:
        return self._rest

    def _each(self, facts: Sequence[np.ndarray]) -> np.ndarray:
        """Node indices of each body (its own numbering) in the joined numbering."""
        return np.concatenate([np.asarray(f, dtype=np.int64) + self._offsets[k] for k, f in enumerate(facts)])

    def _boundary_triangles(self) -> np.ndarray:
        return self._each([b._boundary_triangles() for b in self._bodies])

    def _surface_nodes(self) -> np.ndarray:
        return self._each([b._surface_nodes() for b in self._bodies])

    def _parts(self) -> np.ndarray:
        # Each body's pieces, numbered after the pieces of the bodies before it.
        parts, first = [], 0
        for body in self._bodies:
            own = body._parts()
            parts.append(own + first)
            first += int(own.max()) + 1
        return np.concatenate(parts)
