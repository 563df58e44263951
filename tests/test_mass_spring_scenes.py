"""The mass-spring scenes write a readable ParaView series (quads for the cloth, hexahedra
for the cube) and the CLI runs them."""

import meshio
import numpy as np

from corotate import cli, scenes


def test_scenes_write_time_series(tmp_path):
    cloth = scenes.hanging_cloth(tmp_path, n=6, frames=3)
    cube = scenes.dropped_cube(tmp_path, cells=2, frames=3)
    for name, sim, cell_type in (("cloth", cloth, "quad"), ("cube", cube, "hexahedron")):
        assert (tmp_path / f"{name}.pvd").exists()
        last = meshio.read(tmp_path / name / "frame_00003.vtu")
        assert last.cells[0].type == cell_type
        np.testing.assert_allclose(last.points, sim.positions)
    assert cloth.positions[:, 2].min() < 0  # it fell


def test_scenes_cli(tmp_path, capsys):
    assert cli.main(["scenes", "cloth", "--out", str(tmp_path), "--frames", "2", "--cloth-size", "5"]) == 0
    assert "substeps per frame" in capsys.readouterr().out
    assert (tmp_path / "cloth.pvd").exists()
