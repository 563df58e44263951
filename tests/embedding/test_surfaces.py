"""Surfaces made by the project: a volume mesh's boundary, Loop subdivision, centroid split,
spheres; and tetrahedralize (skipped without the extra corotate-fem[mesh])."""

from __future__ import annotations

import numpy as np
import pytest

import corotate as cr
from corotate.mesh import SOLID_ELEMENTS


def enclosed_volume(s: cr.Mesh) -> float:
    x, t = s.points, s.cells
    return float(np.einsum("ij,ij->i", x[t[:, 0]], np.cross(x[t[:, 1]], x[t[:, 2]])).sum() / 6)


def area(s: cr.Mesh) -> float:
    x, t = s.points, s.cells
    return float(np.linalg.norm(np.cross(x[t[:, 1]] - x[t[:, 0]], x[t[:, 2]] - x[t[:, 0]]), axis=1).sum() / 2)


def edge_face_counts(s: cr.Mesh) -> np.ndarray:
    sides = np.sort(np.stack([s.cells, np.roll(s.cells, -1, axis=1)], axis=2).reshape(-1, 2), axis=1)
    return np.unique(sides, axis=0, return_counts=True)[1]


@pytest.mark.parametrize("element", SOLID_ELEMENTS)
def test_boundary_of_a_box_is_closed_outward_and_encloses_its_volume(element):
    mesh = cr.box(size=(2.0, 1.0, 0.5), cells=(4, 2, 2), element=element)
    s = cr.boundary_surface(mesh)
    assert np.all(edge_face_counts(s) == 2)  # closed, manifold
    assert enclosed_volume(s) == pytest.approx(1.0, rel=1e-12)  # positive: normals point out
    assert area(s) == pytest.approx(2 * (2 * 1 + 2 * 0.5 + 1 * 0.5), rel=1e-12)
    # The boundary's corner-grid nodes (hex20: only corners, its faces are straight): all of
    # the 5 x 3 x 3 grid but the 3 x 1 x 1 inside.
    assert s.n_nodes == 5 * 3 * 3 - 3 * 1 * 1


def test_loop_subdivision_counts_closedness_and_affine_invariance():
    sphere = cr.sphere_surface(1.0, 60)
    fine = cr.loop_subdivide(sphere)
    n_edges = 3 * sphere.n_cells // 2
    assert fine.n_nodes == sphere.n_nodes + n_edges and fine.n_cells == 4 * sphere.n_cells
    assert np.all(edge_face_counts(fine) == 2)
    # Loop's masks are affine combinations: subdividing commutes with any affine map.
    rng = np.random.default_rng(3)
    A, b = np.eye(3) + 0.3 * rng.standard_normal((3, 3)), rng.standard_normal(3)
    moved = cr.loop_subdivide(cr.Mesh(sphere.points @ A.T + b, sphere.cells, "triangle"))
    np.testing.assert_allclose(moved.points, fine.points @ A.T + b, atol=1e-13)
    # It smooths towards the limit surface: a convex polyhedron inscribed in the unit sphere
    # shrinks (the masks average), stays convex-ish and keeps its orientation.
    assert 0 < enclosed_volume(fine) < enclosed_volume(sphere)


def test_loop_subdivision_keeps_open_borders_and_a_flat_patch_flat():
    flat = cr.rectangle((1.0, 1.0), (3, 3))
    patch = cr.Mesh(np.column_stack([flat.points[:, :2], np.zeros(flat.n_nodes)]), flat.cells, "triangle")
    fine = cr.loop_subdivide(patch)
    assert np.all(fine.points[:, 2] == 0)
    border = np.isclose(patch.points[:, :2], 0).any(axis=1) | np.isclose(patch.points[:, :2], 1).any(axis=1)
    np.testing.assert_array_equal(fine.points[: patch.n_nodes][border], patch.points[border])


def test_centroid_split_keeps_the_surface():
    sphere = cr.sphere_surface(2.0, 50)
    split = cr.split_at_centroids(sphere)
    assert split.n_nodes == sphere.n_nodes + sphere.n_cells and split.n_cells == 3 * sphere.n_cells
    assert area(split) == pytest.approx(area(sphere), rel=1e-13)
    assert enclosed_volume(split) == pytest.approx(enclosed_volume(sphere), rel=1e-13)


def test_surface_helpers_reject_wrong_meshes():
    with pytest.raises(ValueError, match="volume mesh"):
        cr.boundary_surface(cr.rectangle())
    with pytest.raises(ValueError, match="triangle mesh"):
        cr.loop_subdivide(cr.box())
    with pytest.raises(ValueError, match="radius"):
        cr.sphere_surface(-1.0)


def test_tetrahedralize_fills_a_sphere_near_the_target_count(tmp_path, monkeypatch):
    pytest.importorskip("pytetwild", reason="the extra corotate-fem[mesh] (pytetwild) is not installed")
    monkeypatch.chdir(tmp_path)
    sphere = cr.sphere_surface(1.0, 300)
    mesh = cr.tetrahedralize(sphere, target_cells=400, envelope=1e-2)
    assert list(tmp_path.iterdir()) == []  # fTetWild's scratch file went elsewhere
    assert mesh.cell_type == "tetra"
    assert np.all(mesh.cell_volumes() > 0)
    assert 400 * 0.6 < mesh.n_cells < 400 * 1.6
    # It fills the sphere: the volume of the inscribed polyhedron to within the envelope.
    assert mesh.cell_volumes().sum() == pytest.approx(enclosed_volume(sphere), rel=0.05)
    cr.Body(mesh, cr.Material())  # a valid body
    # The surface it came from embeds with few vertices outside and none far.
    surface = cr.EmbeddedSurface(mesh, sphere.points, sphere.cells)
    assert surface.report["max_outside_distance"] < 0.2


def test_tetrahedralize_bad_input_and_a_missing_extra(monkeypatch):
    with pytest.raises(ValueError, match="triangles"):
        cr.tetrahedralize(cr.box())
    with pytest.raises(ValueError, match="target_cells"):
        cr.tetrahedralize(cr.sphere_surface(), target_cells=0)
    import builtins

    real_import = builtins.__import__

    def no_pytetwild(name, *args, **kwargs):
        if name == "pytetwild":
            raise ImportError("No module named 'pytetwild'")
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_pytetwild)
    with pytest.raises(ImportError, match=r"corotate-fem\[mesh\]"):
        cr.tetrahedralize(cr.sphere_surface())
