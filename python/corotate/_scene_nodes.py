"""Where one body's nodes sit in a scene's simulation (``Scene.nodes(k)``: one contiguous range),
for what is made for one body of a scene (``Scene.embedded_surface``, ``Scene.haptic_feedback``)
and reads either the body's positions or the whole scene's."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from .body import Body
    from .joined_body import JoinedBody


@dataclass(frozen=True)
class SceneNodes:
    """Body k's nodes: rows start..stop of the scene's n_scene; scene_body the scene's joined
    body (what its simulations step)."""

    start: int
    stop: int
    n_scene: int
    scene_body: Body | JoinedBody

    def rows(self, x: np.ndarray) -> np.ndarray:
        """The body's rows of scene-wide (n_scene, ...) values: a view."""
        return x[self.start : self.stop]


def body_rows(x: np.ndarray, n_body: int, scene: SceneNodes | None, name: str) -> np.ndarray:
    """x as (n_body, 3) positions of the body: as given, or, for a scene's body, its rows of the
    scene's (n_scene, 3). ValueError naming the shapes that would do."""
    if scene is not None and x.shape == (scene.n_scene, 3):
        return scene.rows(x)
    if x.shape != (n_body, 3):
        also = f" or the scene's ({scene.n_scene}, 3)" if scene is not None else ""
        raise ValueError(f"{name} must have shape ({n_body}, 3){also}, got {x.shape}")
    return x
