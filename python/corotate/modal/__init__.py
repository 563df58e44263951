"""Modal flexible bodies (the paper's §3): Craig-Bampton reduction, a ModalBody stepped in
modal coordinates, geometric stiffness per load case and per mode, reduced StVK forces, partial rotation of
displacements, a floating frame of reference (FloatingBody) with geometric stiffening by
inertial loads, export to Exudyn."""

from __future__ import annotations

from .exudyn_export import ExudynBody, exudyn_fem, to_exudyn
from .floating_body import FloatingBody, FrameMotion
from .frame_stiffening import inertial_geometric_stiffness, inertial_load_fields
from .geometric_stiffness import (
    linear_geometric_stiffness,
    load_geometric_stiffness,
    mode_geometric_stiffness,
    scaled_mode_geometric_stiffness,
)
from .modal_body import ModalBody
from .modal_stress import linear_stress, modal_stresses
from .partial_rotation import PartialRotation, least_squares_rotation
from .reduced_stvk import modal_derivatives, reduced_stvk_tensors
from .reduction import BasisWarning, ModalBasis, craig_bampton

__all__ = [
    "BasisWarning",
    "ModalBasis",
    "ModalBody",
    "PartialRotation",
    "least_squares_rotation",
    "craig_bampton",
    "linear_stress",
    "modal_stresses",
    "linear_geometric_stiffness",
    "load_geometric_stiffness",
    "mode_geometric_stiffness",
    "scaled_mode_geometric_stiffness",
    "modal_derivatives",
    "reduced_stvk_tensors",
    "FloatingBody",
    "FrameMotion",
    "inertial_load_fields",
    "inertial_geometric_stiffness",
    "ExudynBody",
    "exudyn_fem",
    "to_exudyn",
]
