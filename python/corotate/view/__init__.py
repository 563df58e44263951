"""Watching a simulation live: ``corotate view``.

InteractiveScene (no display needed) runs the loop: frames paced to the wall clock, a node
grabbed and dragged with the mouse through an implicit attachment, pause, reset, gravity on
and off, the real-time ratio. Window draws it with polyscope (the optional extra
``corotate-fem[view]``). Any render surface with ``positions`` and ``triangles`` can be shown
instead of the body's boundary.
"""

from __future__ import annotations

from .scene import InteractiveScene
from .surface import BodySurface
from .window import Window

__all__ = ["BodySurface", "InteractiveScene", "Window"]
