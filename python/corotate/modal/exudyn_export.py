"""Hand a reduced body to Exudyn (a multibody engine, PyPI ``exudyn``, the ``[mbs]`` extra) as
its reduced-order floating-frame object, ObjectFFRFreducedOrder.

What Exudyn needs is what corotate has: the mesh's rest positions, the consistent mass and
the stiffness at rest (3n x 3n, DOF = 3*node + axis, the order Exudyn uses too) and a mode
basis that holds no rigid-body motion. Exudyn's FEMinterface carries them; its
ObjectFFRFreducedOrderInterface turns them into the object's inertia invariants (total mass,
centre of mass, inertia tensor about the frame's origin and the mass couplings of the modes
with the rigid motion, all precomputed once) and adds to the system a rigid-body node (the
floating frame: its position is where the mesh's origin goes, its rotation Euler
parameters), a node of the r modal coordinates and the object.

The frame is defined by the basis: a Craig-Bampton basis is zero on its fixed nodes, so those
nodes move with the frame (a joint there acts on the frame). Constraint modes at interface
nodes let another joint or load deform the body there exactly.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..body import Body
from ..surfaces import boundary_triangles
from .floating_basis import check_floating_basis
from .reduction import ModalBasis, node_dofs

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["ExudynBody", "exudyn_fem", "to_exudyn"]


def _exudyn(part: str = "") -> Any:
    """The exudyn module (or its submodule ``part``, e.g. ".FEM"), or ImportError naming the
    extra that provides it."""
    try:
        module = importlib.import_module("exudyn")  # first: a loaded submodule would hide its absence
    except ImportError as e:
        raise ImportError("exporting to Exudyn needs exudyn: pip install 'corotate-fem[mbs]'") from e
    return importlib.import_module("exudyn" + part) if part else module


def exudyn_fem(body: Body, basis: ModalBasis) -> Any:
    """Exudyn's FEMinterface holding a corotate body and its reduction basis.

    body     Body whose mesh the basis was built on (its stiffness at rest and its consistent
             mass are handed over; every force model has the same stiffness at rest)
    basis    ModalBasis without rigid-body motion (e.g. craig_bampton with fixed nodes)
    returns  exudyn.FEM.FEMinterface with nodes {"Position": (n, 3)}, massMatrix and
             stiffnessMatrix (3n x 3n scipy CSR), modeBasis {"matrix": (3n, r), "type":
             "HCBmodes"}, eigenValues (r,) omega^2 [1/s^2] and the boundary triangles as its
             surface (Exudyn draws them)

    Raises ImportError without exudyn, TypeError for other objects, ValueError when the
    basis belongs to another mesh or holds a rigid-body motion.
    """
    check_floating_basis(body, basis)
    fem_module = _exudyn(".FEM")
    fem = fem_module.FEMinterface()
    fem.nodes = {"Position": np.array(body.mesh.points, dtype=np.float64)}
    fem.massMatrix = body.mass_matrix(lumped=False).tocsr()
    fem.stiffnessMatrix = body.stiffness_matrix().tocsr()
    fem.modeBasis = {"matrix": np.array(basis.vectors), "type": "HCBmodes"}
    fem.eigenValues = np.array(basis.eigenvalues)
    if body.mesh.cell_type != "triangle":
        fem.surface = [{"Name": "boundary", "Trigs": boundary_triangles(body.mesh)}]
    return fem


@dataclass(frozen=True)
class ExudynBody:
    """A corotate body added to an Exudyn system as ObjectFFRFreducedOrder (see to_exudyn).

    mbs         the exudyn MainSystem it was added to
    object      index of the ObjectFFRFreducedOrder
    rigid_node  index of its rigid-body node: the floating frame (position of the mesh's
                origin, rotation as Euler parameters)
    modal_node  index of its NodeGenericODE2: the r modal coordinates q
    basis       the ModalBasis (nodal displacement in the frame = basis.vectors @ q)
    interface   Exudyn's ObjectFFRFreducedOrderInterface (its inertia invariants: totalMass,
                chiU, inertiaLocal, massMatrixReduced, ...)
    """

    mbs: Any
    object: int
    rigid_node: int
    modal_node: int
    basis: ModalBasis
    interface: Any

    def _mesh_nodes(self, nodes: ArrayLike) -> np.ndarray:
        return node_dofs(nodes, self.basis.rest_positions.shape[0], "nodes")[::3] // 3

    def rigid_marker(self, nodes: ArrayLike) -> int:
        """Add a MarkerSuperElementRigid on mesh nodes (equal weights): the position and
        rotation a joint acts on, at their centroid. nodes: int indices or a boolean mask,
        not all on one line. Returns the marker index."""
        idx = self._mesh_nodes(nodes)
        spread = self.basis.rest_positions[idx] - self.basis.rest_positions[idx].mean(axis=0)
        if idx.size < 3 or np.linalg.matrix_rank(spread, tol=1e-9 * max(np.abs(spread).max(), 1e-300)) < 2:
            raise ValueError(
                f"a rigid marker needs nodes that are not all on one line, got {idx.size} node(s) of rank "
                f"{np.linalg.matrix_rank(spread) if idx.size else 0}"
            )
        items = _exudyn(".itemInterface")
        weights = np.full(idx.size, 1.0 / idx.size)
        marker = items.MarkerSuperElementRigid(
            bodyNumber=self.object, meshNodeNumbers=idx.tolist(), weightingFactors=weights.tolist()
        )
        return int(self.mbs.AddMarker(marker))

    def position_marker(self, nodes: ArrayLike) -> int:
        """Add a MarkerSuperElementPosition on mesh nodes (equal weights: their mean
        position), for a load, a spherical joint or a sensor. Returns the marker index."""
        idx = self._mesh_nodes(nodes)
        if idx.size == 0:
            raise ValueError("a position marker needs at least one node")
        items = _exudyn(".itemInterface")
        weights = np.full(idx.size, 1.0 / idx.size)
        marker = items.MarkerSuperElementPosition(
            bodyNumber=self.object, meshNodeNumbers=idx.tolist(), weightingFactors=weights.tolist()
        )
        return int(self.mbs.AddMarker(marker))

    def positions(self, nodes: ArrayLike | None = None) -> np.ndarray:
        """(k, 3) world positions of mesh nodes (default all) in the system's current state:
        x = p + R (X + (Phi q)_node), p and R the frame's position and rotation."""
        exu = _exudyn()
        n = self.basis.rest_positions.shape[0]
        idx = np.arange(n) if nodes is None else self._mesh_nodes(nodes)
        p = np.asarray(self.mbs.GetNodeOutput(self.rigid_node, exu.OutputVariableType.Position))
        R = np.asarray(self.mbs.GetNodeOutput(self.rigid_node, exu.OutputVariableType.RotationMatrix)).reshape(3, 3)
        q = np.asarray(self.mbs.GetNodeOutput(self.modal_node, exu.OutputVariableType.Coordinates))
        rows = node_dofs(idx, n)
        local = self.basis.rest_positions[idx] + (self.basis.vectors[rows] @ q).reshape(-1, 3)
        return p + local @ R.T


def _add_gravity(mbs: Any, exudyn_object: int, mass: Any, gravity: np.ndarray) -> None:
    """Gravity on the object as the consistent nodal loads of the deformed body.

    The generalized force of a uniform acceleration g is sum_j m_j (dx_j/dq)^T g, m_j = sum_i
    M_ij the row sums of the consistent mass (negative at a Hex20's corners): the load m g on a
    marker at the mass-weighted mean of the nodes (weights m_j / m). Exudyn's own
    mass-proportional load (MarkerBodyMass) on ObjectFFRFreducedOrder is not that force once the
    body deforms: in the flexible pendulum study its run lost up to 0.8 % of the energy and lay
    1.8 % of the link's length from corotate's floating frame by 2 s, against 5e-6 of the energy
    and 3e-7 of the length with this load.
    """
    if not np.any(gravity):
        return
    items = _exudyn(".itemInterface")
    n = mass.shape[0] // 3
    row_sums = np.asarray(mass @ np.tile([1.0, 0.0, 0.0], n)).reshape(n, 3)[:, 0]
    total = float(row_sums.sum())
    marker = items.MarkerSuperElementPosition(
        bodyNumber=exudyn_object, meshNodeNumbers=list(range(n)), weightingFactors=(row_sums / total).tolist()
    )
    mbs.AddLoad(items.LoadForceVector(markerNumber=int(mbs.AddMarker(marker)), loadVector=(total * gravity).tolist()))


def to_exudyn(
    mbs: Any,
    body: Body,
    basis: ModalBasis,
    position: ArrayLike = (0.0, 0.0, 0.0),
    rotation: ArrayLike | None = None,
    velocity: ArrayLike = (0.0, 0.0, 0.0),
    angular_velocity: ArrayLike = (0.0, 0.0, 0.0),
    gravity: ArrayLike = (0.0, 0.0, 0.0),
    rayleigh: tuple[float, float] = (0.0, 0.0),
    name: str = "",
) -> ExudynBody:
    """Add a reduced corotate body to an Exudyn system as ObjectFFRFreducedOrder.

    mbs               exudyn MainSystem (``exu.SystemContainer().AddSystem()``)
    body, basis       as for exudyn_fem: the body and its basis without rigid-body motion
    position          (3,) world position of the mesh's origin (the frame's origin) [m]
    rotation          (3, 3) rotation of the frame, default identity
    velocity          (3,) initial velocity of the frame's origin [m/s]
    angular_velocity  (3,) initial angular velocity of the frame [rad/s]
    gravity           (3,) acceleration [m/s^2] on the whole body, as the consistent nodal loads
    rayleigh          (alpha, beta): damping alpha M_r + beta K_r on the modal coordinates
    name              Exudyn name of the object ("" = none)
    returns           ExudynBody: the object's and nodes' indices, markers on mesh nodes and
                      the recovered positions; assemble and solve the system with Exudyn

    Raises ImportError without exudyn, TypeError/ValueError as exudyn_fem, ValueError for
    vectors of the wrong shape or a rotation that is not one.
    """
    vectors = {}
    for label, value in (
        ("position", position),
        ("velocity", velocity),
        ("angular_velocity", angular_velocity),
        ("gravity", gravity),
    ):
        v = np.asarray(value, dtype=np.float64)
        if v.shape != (3,) or not np.all(np.isfinite(v)):
            raise ValueError(f"{label} must be 3 finite numbers, got {value!r}")
        vectors[label] = v
    R = np.eye(3) if rotation is None else np.asarray(rotation, dtype=np.float64)
    if R.shape != (3, 3) or not np.allclose(R.T @ R, np.eye(3), atol=1e-10) or np.linalg.det(R) <= 0:
        raise ValueError("rotation must be a proper rotation matrix (3 x 3, R^T R = I, det R = 1)")
    alpha, beta = (float(v) for v in rayleigh)
    if not (np.isfinite(alpha) and np.isfinite(beta) and alpha >= 0 and beta >= 0):
        raise ValueError(f"rayleigh must be two finite numbers >= 0, got {rayleigh!r}")
    fem = exudyn_fem(body, basis)
    fem_module = _exudyn(".FEM")
    interface = fem_module.ObjectFFRFreducedOrderInterface(fem)
    added = interface.AddObjectFFRFreducedOrder(
        mbs,
        positionRef=vectors["position"].tolist(),
        initialVelocity=vectors["velocity"].tolist(),
        rotationMatrixRef=R,
        initialAngularVelocity=vectors["angular_velocity"].tolist(),
        massProportionalDamping=alpha,
        stiffnessProportionalDamping=beta,
        gravity=[0.0, 0.0, 0.0],  # Exudyn's own mass-proportional load: see _add_gravity
        name=name,
    )
    _add_gravity(mbs, int(added["oFFRFreducedOrder"]), fem.massMatrix, vectors["gravity"])
    return ExudynBody(
        mbs=mbs,
        object=int(added["oFFRFreducedOrder"]),
        rigid_node=int(added["nRigidBody"]),
        modal_node=int(added["nGenericODE2"]),
        basis=basis,
        interface=interface,
    )
