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


def test_scenes_come_to_rest_as_their_titles_say(tmp_path):
    # The cloth (pinned at the two corners of its y = 1 edge) ends hanging straight down below
    # that edge: a nearly inextensible 1 m sheet reaches z = -1 and sits under y = 1.
    cloth = scenes.hanging_cloth(tmp_path, n=8, frames=300)
    p = cloth.positions
    assert abs(p[:, 2].min() + 1.0) < 0.03
    assert abs(p[:, 1].mean() - 1.0) < 0.03
    # still swinging a little: damping 1.5 1/s leaves e^(-0.75 t) of the ~6 m/s first swing
    assert np.abs(cloth.velocities).max() < 0.3
    # The cube lands, squashes and settles a few percent lower without turning inside out.
    cube = scenes.dropped_cube(tmp_path, cells=4, frames=300)
    top = np.isclose(cube.body.nodes[:, 2], 0.5)
    settled = cube.positions[top, 2].mean()
    assert 0.40 < settled < 0.49
    assert np.abs(cube.velocities).max() < 0.05


def test_stvk_sheet_scene_swings_in_its_plane(tmp_path):
    sim = scenes.stvk_sheet(tmp_path, cells=6, frames=60)
    assert (tmp_path / "sheet.pvd").exists()
    p = sim.positions
    np.testing.assert_allclose(p[:, 1], 0.0, atol=1e-12)  # gravity in the plane: it stays plane
    assert p[:, 2].min() < -1.0  # hangs and stretches below its 1 m rest height
    assert np.all(np.isfinite(p))
