"""The surface of a volume mesh, and the picture of a run drawn from it."""

import numpy as np
import pytest

import corotate as cr
from corotate.mesh import SOLID_ELEMENTS
from corotate.picture import render_snapshots


def face_area_vectors(x, faces):
    if faces.shape[1] == 3:
        return 0.5 * np.cross(x[faces[:, 1]] - x[faces[:, 0]], x[faces[:, 2]] - x[faces[:, 0]])
    # a planar quad's area vector: half the cross product of its diagonals
    return 0.5 * np.cross(x[faces[:, 2]] - x[faces[:, 0]], x[faces[:, 3]] - x[faces[:, 1]])


@pytest.mark.parametrize("element", SOLID_ELEMENTS)
def test_boundary_faces_close_the_volume_outward(element):
    size, cells = (2.0, 0.7, 1.3), (3, 2, 4)
    m = cr.box(size, cells, element)
    faces = m.boundary_faces()
    quads = 2 * (cells[0] * cells[1] + cells[1] * cells[2] + cells[0] * cells[2])
    simplex = cr.cell_types()[m.cell_type]["domain"] == "simplex"
    assert faces.shape == ((2 * quads, 3) if simplex else (quads, 4))
    a = face_area_vectors(m.points, faces)
    centres = m.points[faces].mean(axis=1)
    np.testing.assert_allclose(a.sum(axis=0), 0.0, atol=1e-12)  # a closed surface
    # divergence theorem: the flux of x through the surface is 3 V, positive only if outward
    assert np.sum(a * centres) / 3 == pytest.approx(np.prod(size), rel=1e-12)
    interior = np.setdiff1d(np.arange(m.n_nodes), m.nodes_where(lambda p: np.isclose(p, 0).any(axis=1)))
    interior = interior[~np.isclose(m.points[interior], size).any(axis=1)]
    assert not np.isin(faces, interior).any()  # no face touches an interior node


def test_boundary_faces_refuse_a_sheet():
    with pytest.raises(ValueError, match="volume mesh"):
        cr.rectangle((1.0, 1.0), (2, 2)).boundary_faces()


def test_render_snapshots_draws_the_motion(tmp_path):
    pytest.importorskip("matplotlib", reason="pictures need the plot extra (matplotlib)")
    m = cr.beam(2.0, 0.5, 0.5, cells=(4, 1, 1))
    bent = m.points.copy()
    bent[:, 2] -= 0.2 * m.points[:, 0] ** 2
    rest_png = render_snapshots(tmp_path / "rest.png", m, [(0.0, m.points)])
    both_png = render_snapshots(tmp_path / "both.png", m, [(0.0, m.points), (1.0, bent)], title="bent")
    import matplotlib.image

    rest, both = matplotlib.image.imread(rest_png), matplotlib.image.imread(both_png)
    assert rest.shape == both.shape and rest.shape[2] in (3, 4)
    assert np.abs(rest - both).max() > 0.5  # the bent body adds strongly coloured pixels


def test_render_snapshots_refuses_bad_positions(tmp_path):
    m = cr.beam(2.0, 0.5, 0.5, cells=(2, 1, 1))
    with pytest.raises(ValueError, match="at least one"):
        render_snapshots(tmp_path / "x.png", m, [])
    with pytest.raises(ValueError, match="must have shape"):
        render_snapshots(tmp_path / "x.png", m, [(0.0, m.points[:-1])])
    bad = m.points.copy()
    bad[3, 1] = np.nan
    with pytest.raises(ValueError, match="not all finite"):
        render_snapshots(tmp_path / "x.png", m, [(0.5, bad)])
    assert not (tmp_path / "x.png").exists()


def test_the_up_axis_is_drawn_upward_by_a_proper_turn():
    from corotate.picture import _display_axes, _signs

    for up in ("+x", "-x", "+y", "-y", "+z", "-z"):
        turn = np.eye(3)[_display_axes(up)] * _signs(up)[:, None]  # model -> plot coordinates
        assert np.linalg.det(turn) == pytest.approx(1.0)  # no mirror image
        model_up = np.zeros(3)
        model_up["xyz".index(up[1])] = 1.0 if up[0] == "+" else -1.0
        np.testing.assert_array_equal(turn @ model_up, [0.0, 0.0, 1.0])
    m = cr.beam(2.0, 0.5, 0.5, cells=(2, 1, 1))
    with pytest.raises(ValueError, match="up must be one of"):
        render_snapshots("never.png", m, [(0.0, m.points)], up="y")
