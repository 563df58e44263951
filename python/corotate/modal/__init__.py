"""Modal flexible bodies (the paper's §3): Craig-Bampton reduction, a ModalBody stepped in
modal coordinates, geometric stiffness per load case and per mode, reduced StVK forces."""

from __future__ import annotations

from .modal_body import ModalBody
from .reduction import ModalBasis, craig_bampton

__all__ = ["ModalBasis", "ModalBody", "craig_bampton"]
