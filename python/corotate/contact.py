"""Contact of a simulated body with rigid obstacles: the Simulation members that add,
remove and report them (the formulation: cpp/include/corotate/contact/contact_set.hpp)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

import corotate._core as _core

from ._numbers import real_number
from .obstacles import Obstacle

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from .embedding import EmbeddedSurface


class ContactMembers:
    """Mixed into Simulation (needs ``self._sim`` and ``self._body``)."""

    _sim: Any
    _body: Any
    _obstacles: list[Obstacle]
    _contact_nodes_set: bool
    _contact_surface: EmbeddedSurface | None
    _parts_cache: np.ndarray | None
    _node_list: Any  # DrivenBody's

    def add_obstacle(self, obstacle: Obstacle, friction: float = 0.0) -> None:
        """Let the body touch `obstacle` (Plane, Sphere, Box, Capsule, Cylinder, TriangleMesh) with Coulomb
        friction coefficient `friction` (>= 0).

        The contact nodes are the body's surface nodes unless ``contact_nodes`` was set. The
        contact is part of the implicit step (stable at the real-time step); its force is
        ``contact_settings["stiffness_scale"]`` times the node's own stiffness in the step,
        and a multiplier carried from step to step brings a resting contact's penetration to
        zero. Raises ValueError (nothing changed) for a negative or non-finite friction, an
        obstacle added twice, an explicit integrator, or surface nodes that start inside it.
        """
        if not isinstance(obstacle, Obstacle):
            raise TypeError(
                "obstacle must be a corotate Plane, Sphere, Box, Capsule, Cylinder or TriangleMesh, not "
                f"{type(obstacle).__name__}"
            )
        mu = real_number(friction, "friction")
        if not self._contact_nodes_set:
            self._sim.contact_nodes = self._body._surface_nodes()
            self._contact_nodes_set = True
        self._sim.add_obstacle(obstacle._core, mu)
        self._obstacles.append(obstacle)

    def remove_obstacle(self, obstacle: Obstacle) -> None:
        """Stop touching `obstacle` (ValueError when it was not added)."""
        if not isinstance(obstacle, Obstacle):
            raise TypeError(f"obstacle must be a corotate obstacle, not {type(obstacle).__name__}")
        self._sim.remove_obstacle(obstacle._core)
        self._obstacles.remove(obstacle)

    def set_friction(self, obstacle: Obstacle, friction: float) -> None:
        """A new friction coefficient (>= 0) between the body and `obstacle`."""
        self._sim.set_friction(obstacle._core, real_number(friction, "friction"))

    @property
    def obstacles(self) -> list[tuple[Obstacle, float]]:
        """(obstacle, friction) pairs, in the order they were added (read-only)."""
        frictions = [mu for _, mu in self._sim.obstacles]
        return list(zip(self._obstacles, frictions))

    @property
    def contact_nodes(self) -> np.ndarray:
        """The nodes that can touch obstacles (default: the surface's; unused while a contact
        surface is set). Settable to any set of node indices (ValueError for one out of range
        or listed twice); setting them replaces a contact surface."""
        if not self._contact_nodes_set:
            return self._body._surface_nodes()
        return np.asarray(self._sim.contact_nodes, dtype=np.int64)

    @contact_nodes.setter
    def contact_nodes(self, nodes: ArrayLike) -> None:
        self._sim.contact_nodes = self._node_list(nodes)
        self._contact_nodes_set = True
        self._contact_surface = None

    def set_contact_surface(self, surface: EmbeddedSurface) -> None:
        """Let an embedded surface's vertices touch the obstacles instead of the body's nodes,
        so that the detailed surface (a render mesh in a coarse cage), not the cage, lies on
        the floor and meets the tool.

        Each vertex is the fixed combination of its element's nodes the embedding found; it is
        detected and held like a node, and its contact force spreads over those nodes by the
        same weights (the Hessian over their pairs, within the element). ``contacts["nodes"]``
        then lists vertex indices. ``contact_nodes = ...`` goes back to nodes. ValueError
        (nothing changed) for a surface embedded in another body, vertices that start inside
        an obstacle, or contact between parts (which uses the parts' surface nodes)."""
        from .embedding import EmbeddedSurface

        if not isinstance(surface, EmbeddedSurface):
            raise TypeError(f"surface must be a corotate.EmbeddedSurface, not {type(surface).__name__}")
        if surface._n_body_nodes != self._body.n_nodes and surface._scene is not None:
            raise ValueError(
                "the surface is embedded in one body of a scene: a scene's bodies touch with their surface "
                "nodes (contact between parts), not with a render surface's vertices"
            )
        if surface._n_body_nodes != self._body.n_nodes:
            raise ValueError(
                f"the surface is embedded in a body of {surface._n_body_nodes} nodes, this one has {self._body.n_nodes}"
            )
        nodes, weights = surface._core.vertex_stencils
        self._sim.set_contact_points(nodes, weights)
        self._contact_surface = surface
        self._contact_nodes_set = True

    @property
    def contact_surface(self) -> EmbeddedSurface | None:
        """The embedded surface whose vertices are the contact points (``set_contact_surface``),
        or None when the contact points are nodes."""
        return self._contact_surface

    @property
    def contact_settings(self) -> dict[str, float | bool]:
        """{"stiffness_scale": contact stiffness over the node's own stiffness in the step
        (default 100), "friction_velocity": slip speed [m/s] below which friction sticks
        (default 1e-3; the smoothed Coulomb law's width), "edge_contact": whether the parts'
        surfaces also touch edge against edge, where two edges cross with no node inside the
        other surface (default True)}. Assign a dict with any of the keys."""
        s = self._sim.contact_settings
        return {
            "stiffness_scale": s.stiffness_scale,
            "friction_velocity": s.friction_velocity,
            "edge_contact": s.edge_contact,
        }

    @contact_settings.setter
    def contact_settings(self, settings: dict[str, float | bool]) -> None:
        known = ("stiffness_scale", "friction_velocity", "edge_contact")
        unknown = set(settings) - set(known)
        if unknown:
            raise ValueError(f"unknown contact settings {sorted(unknown)}; known: {', '.join(known)}")
        checked: dict[str, float | bool] = {}
        for key, value in settings.items():
            if key == "edge_contact":
                if not isinstance(value, (bool, np.bool_)):
                    raise TypeError(f"edge_contact must be True or False, not {value!r}")
                checked[key] = bool(value)
            else:
                checked[key] = real_number(value, key)
        merged = {**self.contact_settings, **checked}
        self._sim.contact_settings = _core.ContactSettings(
            float(merged["stiffness_scale"]), float(merged["friction_velocity"]), bool(merged["edge_contact"])
        )

    @property
    def contacts(self) -> dict[str, np.ndarray]:
        """The last step's contacts, one row each: "nodes" (the contact node, or the surface's
        vertex with ``set_contact_surface``), "obstacles" (indices into
        ``obstacles``), "normals" and "points" (the obstacle's tangent plane), "forces" (m, 3)
        the force each exerted on its node in the step (normal and friction; with the
        linearised step what it applied: a contact kept within its active set's band may pull
        a little),
        "multipliers" (the normal force carried to the next step) and "friction_limits"
        (mu N of the step, N the multiplier carried into it: a new contact has no friction
        in its first step). Between parts, "parts" is the part touched (-1: an obstacle) and
        "partners" the nodes of its triangle with the point's "weights" on them; an edge of one
        part against an edge of another ("edges" True) has its edge in "nodes" and
        "partners"[:, 0], the other edge in "partners"[:, 1:], and the points' parameters
        (s, t, 0) along them in "weights"."""
        return {k: np.asarray(v) for k, v in self._sim.contacts.items()}

    def contact_force(self, obstacle: Obstacle | None = None) -> np.ndarray:
        """(3,) the total force obstacles exerted on the body in the last step (of
        `obstacle` alone when given). The body pushes back on the obstacle with its negative."""
        c = self._sim.contacts
        forces = np.asarray(c["forces"]).reshape(-1, 3)
        if obstacle is not None:
            index = next((j for j, o in enumerate(self._obstacles) if o is obstacle), None)
            if index is None:
                raise ValueError(f"{obstacle!r} is not an obstacle of this simulation")
            forces = forces[np.asarray(c["obstacles"]) == index]
        return forces.sum(axis=0)

    # -- contact between the body's parts -------------------------------------------------

    def set_part_contact(self, friction: float = 0.0, *, self_contact: bool = False) -> None:
        """Let the body's parts (the separate pieces of its mesh: several bodies simulated as
        one, see ``corotate.Scene``) touch each other, with Coulomb friction `friction`.

        Each part's contact nodes (default: the surface's) cannot enter another part's closed
        surface; the force a node receives acts back on the corners of the triangle it
        presses on (momentum is kept), and the coupling between them is part of the implicit
        solve. With `self_contact`, each part's surface also touches itself (a soft arm
        folding onto the body, the sides of a squeezed slot), away from each node's own
        neighbourhood (the triangles with a corner that shares an element with it); a body of
        one piece may then use it too. ValueError (nothing changed) for a mesh of one piece
        without self_contact, a part whose boundary is not a closed surface, an explicit
        integrator, a bad friction, or parts that start inside each other."""
        mu = real_number(friction, "friction")
        if not isinstance(self_contact, (bool, np.bool_)):
            raise TypeError(f"self_contact must be True or False, not {self_contact!r}")
        if not self._contact_nodes_set:
            self._sim.contact_nodes = self._body._surface_nodes()
            self._contact_nodes_set = True
        self._sim.set_part_contact(self._body._boundary_triangles(), self.parts.tolist(), mu, bool(self_contact))

    def clear_part_contact(self) -> None:
        """The parts pass through each other again."""
        self._sim.clear_part_contact()

    @property
    def part_contact(self) -> bool:
        """Whether the body's parts touch each other (``set_part_contact``)."""
        return bool(self._sim.part_contact)

    @property
    def self_contact(self) -> bool:
        """Whether each part's surface also touches itself (``set_part_contact(self_contact=True)``)."""
        return bool(self._sim.self_contact)

    @property
    def parts(self) -> np.ndarray:
        """(n,) the part of each node: the connected pieces of the mesh, numbered in the order
        of their first node (a ``Scene``'s bodies, in the order given). Read-only."""
        parts = getattr(self, "_parts_cache", None)
        if parts is None:  # the body is immutable: found once
            parts = self._body._parts()
            parts.flags.writeable = False
            self._parts_cache = parts
        return parts

    def part_contact_force(self, part: int, other: int) -> np.ndarray:
        """(3,) the force part `other` exerted on part `part` in the last step
        (through both parts' contacts: the forces on part's nodes, less those part's surface
        gave other's nodes)."""
        c = self._sim.contacts
        nodes_part = self.parts[np.asarray(c["nodes"], dtype=np.int64)]
        touched = np.asarray(c["parts"])
        forces = np.asarray(c["forces"]).reshape(-1, 3)
        on_part = forces[(nodes_part == part) & (touched == other)].sum(axis=0)
        on_other = forces[(nodes_part == other) & (touched == part)].sum(axis=0)
        return on_part - on_other
