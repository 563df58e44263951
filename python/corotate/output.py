"""Simulation output as a ParaView time series (.pvd + one .vtu per frame)."""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING
from xml.sax.saxutils import quoteattr

import numpy as np

from .mesh import Mesh, _check_point_data, _meshio

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from .mass_spring import SpringGeometry

__all__ = ["TimeSeriesWriter"]


class TimeSeriesWriter:
    """Write frames of a simulation for ParaView.

    For ``path_pvd = "out/run.pvd"`` the frames go to ``out/run/frame_00000.vtu``,
    ``out/run/frame_00001.vtu``, ... and ``out/run.pvd`` indexes them with their
    times. The index is rewritten (atomically) after every frame, so it is
    valid even if the run stops early. Open the .pvd in ParaView.

    Each frame stores the current positions as the points and the point data
    "displacement" (n, 3) = positions - mesh.points, plus any extra point data.

    Parameters
    ----------
    path_pvd  path of the .pvd index; its folder is created if needed
    mesh      Mesh whose connectivity and rest positions (n, 3) all frames use

    Usable as a context manager; :meth:`close` is then called on exit.
    Frames from an earlier run in the same folder are overwritten one by one;
    any beyond the new run's last frame stay on disk but are not indexed.
    """

    def __init__(self, path_pvd: str | os.PathLike[str], mesh: Mesh | SpringGeometry) -> None:
        self.path = Path(os.fspath(path_pvd))
        if self.path.suffix.lower() != ".pvd":
            raise ValueError(f"path_pvd must end with .pvd, got {self.path}")
        self.mesh = mesh
        self.folder = self.path.with_suffix("")  # out/run.pvd -> out/run/
        self.folder.mkdir(parents=True, exist_ok=True)
        self._frames: list[tuple[float, str]] = []  # (time, path relative to .pvd)
        self._closed = False

    @property
    def n_frames(self) -> int:
        """Number of frames written so far."""
        return len(self._frames)

    def write(self, time: float, positions: ArrayLike, point_data: Mapping[str, ArrayLike] | None = None) -> Path:
        """Write one frame and update the .pvd index.

        time        simulation time of the frame (float)
        positions   (n, 3) current node positions
        point_data  optional dict name -> (n,) or (n, k) array, e.g.
                    {"velocity": v}; the name "displacement" is reserved
        returns     path of the .vtu written
        """
        if self._closed:
            raise RuntimeError(f"TimeSeriesWriter for {self.path} is closed")
        t = float(time)
        x = np.asarray(positions, dtype=np.float64)
        if x.shape != self.mesh.points.shape:
            raise ValueError(f"positions must have shape {self.mesh.points.shape}, got {x.shape}")
        data = _check_point_data(point_data, self.mesh.n_nodes)
        if "displacement" in data:
            raise ValueError("point_data name 'displacement' is reserved (added automatically)")
        data["displacement"] = x - self.mesh.points

        name = f"frame_{len(self._frames):05d}.vtu"
        vtu = self.folder / name
        meshio = _meshio()
        frame = meshio.Mesh(x, [(self.mesh.cell_type, self.mesh.cells)], point_data=data)
        meshio.write(vtu, frame)

        self._frames.append((t, f"{self.folder.name}/{name}"))
        self._write_index()
        return vtu

    def close(self) -> None:
        """Finish the series (rewrites the index; later writes raise)."""
        if not self._closed:
            self._write_index()
            self._closed = True

    def __enter__(self) -> TimeSeriesWriter:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def _write_index(self) -> None:
        """Write the .pvd via a temporary file + rename, so a reader never
        sees a half-written index."""
        lines = [
            '<?xml version="1.0"?>',
            '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">',
            "  <Collection>",
        ]
        for t, rel in self._frames:
            # repr keeps the float exact when ParaView (or a test) reads it back.
            lines.append(f'    <DataSet timestep={quoteattr(repr(t))} group="" part="0" file={quoteattr(rel)}/>')
        lines += ["  </Collection>", "</VTKFile>", ""]
        tmp = self.path.with_name(self.path.name + ".tmp")
        tmp.write_text("\n".join(lines))
        os.replace(tmp, self.path)
