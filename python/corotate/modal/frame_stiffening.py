"""Geometric stiffening of a body on a moving frame by its inertial loads: twelve unit load
cases (centrifugal, Euler, translation and gravity), each one's modal geometric stiffness
precomputed once (the paper's eqs 7-8, as SIMPACK does for its flexible bodies), combined per
step in the C++ core with coefficients from the frame's motion:

    K_geo = sum_c c_c K_c,  c = (omega_0^2, omega_1^2, omega_2^2, omega_0 omega_1, omega_0 omega_2,
                                 omega_1 omega_2, alpha_0, alpha_1, alpha_2, (a - g)_0, (a - g)_1, (a - g)_2)

(omega, alpha: the frame's angular velocity and acceleration, a its origin's acceleration, g
gravity, all in the frame). The order and the fields are those of
cpp/include/corotate/modal/inertial_load_cases.hpp.

Why load cases rather than the reduced StVK forces: the stress that stiffens a spinning beam is
the axial tension of the centrifugal load, which a basis of bending modes cannot represent (its
axial displacement is second order in the modes); the load case computes that stress from the
full mesh once, for any basis.
"""

from __future__ import annotations

import numpy as np

from ..body import Body
from .geometric_stiffness import load_geometric_stiffness
from .reduction import ModalBasis

__all__ = ["inertial_load_fields", "inertial_geometric_stiffness"]

N_LOAD_CASES = 12


def inertial_load_fields(points: np.ndarray) -> np.ndarray:
    """The body force per unit mass of each unit inertial load case at the given points.

    points   (n, 3) positions in the frame, relative to its origin [m]
    returns  (12, n, 3): b_c such that the inertial body force -(a - g) - alpha x u -
             omega x (omega x u) equals sum_c c_c b_c with the coefficients above
    """
    X = np.asarray(points, dtype=np.float64)
    fields = np.zeros((N_LOAD_CASES, *X.shape))
    eye = np.eye(3)
    for a in range(3):  # omega_a^2: X without its component a
        fields[a] = X
        fields[a][:, a] = 0.0
    for c, (a, b) in enumerate(((0, 1), (0, 2), (1, 2)), start=3):  # omega_a omega_b
        fields[c][:, a] = -X[:, b]
        fields[c][:, b] = -X[:, a]
    for a in range(3):
        fields[6 + a] = -np.cross(eye[a], X)  # alpha_a
        fields[9 + a][:] = -eye[a]  # (a - g)_a
    return fields


def inertial_geometric_stiffness(body: Body, basis: ModalBasis, origin: np.ndarray) -> np.ndarray:
    """The modal geometric stiffness of each unit inertial load case.

    body     Body the basis was built on (any force model: the stress is computed on a St.
             Venant-Kirchhoff twin of its mesh and materials, whose linear stress it shares)
    basis    ModalBasis with fixed DOFs (they hold the body statically against each load)
    origin   (3,) the frame's origin in the mesh [m]
    returns  (12, r, r), case by case as inertial_load_fields

    Raises ValueError when the basis fixes nothing (a free body's static stress under an
    inertial load is not defined without inertia relief).
    """
    if len(basis.fixed_dofs) == 0:
        raise ValueError(
            "geometric stiffening needs a basis with fixed nodes (craig_bampton(fixed_nodes=...): the frame's "
            "support), which hold the body against the inertial loads; use stiffening=False for a free-free basis"
        )
    twin = body if body.model == "stvk" else Body(body.mesh, body.materials, model="stvk", regions=body.regions)
    fields = inertial_load_fields(body.mesh.points - np.asarray(origin, dtype=np.float64))
    M = body.mass_matrix(lumped=False)
    loads = np.stack([(M @ field.ravel()).reshape(-1, 3) for field in fields])
    _modal_loads, geometric = load_geometric_stiffness(twin, basis, loads)
    return geometric
