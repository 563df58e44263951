"""The embedded render surface (paper §2.2.2): exactness under linear fields of the cage,
rigid motions of positions and normals, vertices outside the cage, files, output, bad input."""

from __future__ import annotations

import meshio
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import corotate as cr
from corotate.embedding import EmbeddedSurface
from corotate.mesh import SOLID_ELEMENTS

ELEMENTS = SOLID_ELEMENTS  # every registered solid (the core's cell-type table)


def sphere_surface(radius: float, centre=(0.0, 0.0, 0.0), n: int = 400) -> tuple[np.ndarray, np.ndarray]:
    sphere = cr.sphere_surface(radius, n, centre)
    return sphere.points, sphere.cells


def wavy_cage(element: str, cells: int = 3) -> cr.Mesh:
    """A unit box whose nodes are moved by a smooth nonlinear map: curved Hex20 edges and
    non-parallelepiped Hex8s, so the inverse isoparametric map has real work to do."""
    mesh = cr.box(cells=(cells, cells, cells), element=element, origin=(-0.5, -0.5, -0.5))
    p = mesh.points
    moved = p + 0.04 * np.column_stack([np.sin(3 * p[:, 1]), np.sin(3 * p[:, 2]), np.sin(3 * p[:, 0])])
    return cr.Mesh(moved, mesh.cells, mesh.cell_type)


def ball_cage(cells: int = 4) -> cr.Mesh:
    """A tet ball of radius 1: a box's nodes pushed radially from the cube onto the ball."""
    mesh = cr.box(size=(2, 2, 2), cells=(cells,) * 3, element="tet4", origin=(-1, -1, -1))
    p = mesh.points
    r2 = np.linalg.norm(p, axis=1)
    scale = np.divide(np.abs(p).max(axis=1), r2, out=np.ones(len(p)), where=r2 > 0)
    return cr.Mesh(p * scale[:, None], mesh.cells, "tetra")


@pytest.mark.parametrize("element", ELEMENTS)
def test_linear_field_of_the_cage_moves_every_vertex_exactly(element):
    cage = wavy_cage(element)
    vertices, faces = sphere_surface(0.35)
    surface = EmbeddedSurface(cage, vertices, faces)
    assert surface.report["outside"] == 0
    rng = np.random.default_rng(1)
    A = np.eye(3) + 0.4 * rng.standard_normal((3, 3))
    b = np.array([0.3, -1.0, 2.0])
    surface.update(cage.points @ A.T + b)
    np.testing.assert_allclose(surface.positions, vertices @ A.T + b, rtol=0, atol=1e-13)


@pytest.mark.parametrize("element", ELEMENTS)
def test_rigid_rotation_moves_surface_rigidly_and_turns_its_normals(element):
    cage = wavy_cage(element, cells=2)
    vertices, faces = sphere_surface(0.3, centre=(0.05, 0.0, -0.02))
    surface = EmbeddedSurface(cage, vertices, faces)
    rest_normals = surface.normals.copy()
    # The rest normals of a sphere point outward (the check of the area weighting's sign).
    assert np.all(np.einsum("ij,ij->i", rest_normals, vertices - (0.05, 0.0, -0.02)) > 0.99 * 0.3)
    R = Rotation.from_rotvec([0.6, -1.1, 2.0]).as_matrix()
    t = np.array([1.0, 2.0, 3.0])
    x = cage.points @ R.T + t
    for mode in ("area", "rotated"):
        surface.update(x, normals=mode)
        np.testing.assert_allclose(surface.positions, vertices @ R.T + t, rtol=0, atol=1e-13)
        np.testing.assert_allclose(surface.normals, rest_normals @ R.T, rtol=0, atol=1e-12)


def test_area_weighted_normals_of_a_box_face_are_exact():
    """Vertex normals of a flat patch are the plane normal; of a cube corner the normalised sum
    of the three face normals weighted by the incident triangle areas."""
    cage = cr.box(element="tet4")
    vertices = np.array([[0.2, 0.2, 0.5], [0.8, 0.2, 0.5], [0.8, 0.8, 0.5], [0.2, 0.8, 0.5]])
    faces = np.array([[0, 1, 2], [0, 2, 3]])
    surface = EmbeddedSurface(cage, vertices, faces)
    np.testing.assert_allclose(surface.normals, np.tile([0.0, 0.0, 1.0], (4, 1)), atol=1e-15)
    # Stretch the cage by 2 in x and shear z by x: the patch tilts to z = 0.5 + 0.5 (x - 0.2)... exactly.
    x = cage.points.copy()
    x[:, 2] += 0.5 * x[:, 0]
    surface.update(x)
    expected = np.array([-0.5, 0.0, 1.0]) / np.sqrt(1.25)
    np.testing.assert_allclose(surface.normals, np.tile(expected, (4, 1)), atol=1e-15)


def test_sphere_slightly_larger_than_its_cage_is_assigned_by_the_criterion_and_follows():
    cage = ball_cage(cells=4)
    vertices, faces = sphere_surface(1.03, n=600)
    surface = EmbeddedSurface(cage, vertices, faces)
    report = surface.report
    # The cage is a polyhedron inscribed in the unit sphere: every vertex of the larger
    # sphere lies outside it, by 3 % of the radius to about 20 % (between the cage's nodes).
    assert report["outside"] == surface.n_vertices
    sizes = np.ptp(cage.points[cage.cells], axis=1).max(axis=1)  # element sizes as in the report
    assert 0.03 / sizes.max() < report["max_outside_distance"] < 0.5
    assert report["farthest_vertex"] == int(np.argmax(surface.outside_distances))

    # Plausible following: a smooth nonlinear field of the cage (a bend about the y axis)
    # moves the outside vertices like the field itself, to within the interpolation error
    # that vertices inside the cage have.
    def bend(p):
        angle = 0.4 * p[:, 0]
        return np.column_stack([np.sin(angle) * (p[:, 2] + 2.5), p[:, 1], np.cos(angle) * (p[:, 2] + 2.5) - 2.5])

    surface.update(bend(cage.points))
    error_outside = np.linalg.norm(surface.positions - bend(vertices), axis=1).max()
    inner_vertices, inner_faces = sphere_surface(0.9, n=600)
    inner = EmbeddedSurface(cage, inner_vertices, inner_faces)
    inner.update(bend(cage.points))
    error_inside = np.linalg.norm(inner.positions - bend(inner_vertices), axis=1).max()
    assert error_outside < 3 * error_inside
    assert error_outside < 0.05  # 5 % of the radius for a 1 m ball bent through +-0.4 rad


def test_coupling_uses_the_grid_and_agrees_with_brute_force_on_random_points():
    cage = ball_cage(cells=6)
    rng = np.random.default_rng(5)
    points = rng.uniform(-0.6, 0.6, size=(5000, 3))
    points = points[np.linalg.norm(points, axis=1) < 0.8]  # inside the faceted ball
    surface = EmbeddedSurface(cage, points, np.zeros((0, 3), dtype=int))
    assert surface.report["outside"] == 0
    tets = cage.points[cage.cells[surface.elements]]  # (n, 4, 3)
    D = np.transpose(tets[:, 1:] - tets[:, :1], (0, 2, 1))
    lam = np.linalg.solve(D, (points - tets[:, 0])[:, :, None])[:, :, 0]
    barycentric = np.column_stack([1 - lam.sum(axis=1), lam])
    assert barycentric.min() > -1e-12
    np.testing.assert_allclose(surface.local_coordinates, lam, atol=1e-12)
    assert np.all(surface.normals == 0)  # a point cloud has no normals


def test_surface_from_obj_stl_and_ply_files_and_its_own_paraview_series(tmp_path):
    cage = wavy_cage("hex8", cells=2)
    vertices, faces = sphere_surface(0.3, n=120)
    for ext in ("obj", "stl", "ply"):
        path = tmp_path / f"ball.{ext}"
        meshio.write(path, meshio.Mesh(vertices, [("triangle", faces)]), **({"binary": True} if ext == "stl" else {}))
        surface = EmbeddedSurface.from_file(cage, path)
        assert surface.n_triangles == len(faces)
        # The same geometry whatever the format did to the vertex order.
        np.testing.assert_allclose(np.sort(surface.mesh.points, axis=0), np.sort(vertices, axis=0), atol=1e-6)
    # Points whose float64 dtype is an equal but distinct object (as meshio reads a .vtu's
    # "<f8"): the surface still updates in place.
    explicit = vertices.astype(np.dtype(np.float64).newbyteorder("<"))
    assert explicit.dtype is not np.dtype(np.float64)
    surface = EmbeddedSurface(cage, explicit, faces)
    surface.update(cage.points)
    np.testing.assert_allclose(surface.positions, vertices, atol=1e-12)
    body = cr.Body(cage, cr.Material(E=1e5, nu=0.3, density=1000.0))
    sim = cr.Simulation(body, dt=0.01, gravity=(0, 0, -9.81))
    sim.fix(cage.nodes_on_plane("z", cage.points[:, 2].min()))
    surface = EmbeddedSurface(body, vertices, faces)
    positions_buffer, normals_buffer = surface.positions, surface.normals
    volume, skin = cr.TimeSeriesWriter(tmp_path / "body.pvd", cage), surface.series_writer(tmp_path / "skin.pvd")
    for _ in range(3):
        sim.step(5)
        surface.update(sim)
        volume.write(sim.time, sim.positions)
        surface.write_frame(skin, sim.time)
    volume.close()
    skin.close()
    assert surface.positions is positions_buffer and surface.normals is normals_buffer  # updated in place
    frame = meshio.read(tmp_path / "skin" / "frame_00002.vtu")
    np.testing.assert_allclose(frame.points, surface.positions)
    np.testing.assert_allclose(frame.point_data["normal"], surface.normals)
    assert "skin/frame_00002.vtu" in (tmp_path / "skin.pvd").read_text()


def test_bad_surfaces_raise_clear_errors_and_leave_the_body_alone():
    cage = cr.box(cells=(2, 2, 2), element="tet4")
    body = cr.Body(cage, cr.Material(E=1e5, nu=0.3, density=1000.0))
    rest = cage.points.copy()
    vertices, faces = sphere_surface(0.3, centre=(0.5, 0.5, 0.5), n=60)
    nan = vertices.copy()
    nan[7, 1] = np.nan
    cases = [
        ((nan, faces), "NaN at node 7"),
        ((np.zeros((0, 3)), np.zeros((0, 3), dtype=int)), "no vertices"),
        ((vertices[:, :2], faces), r"shape \(n, 3\)"),
        ((vertices, faces[:, :2]), r"shape \(m, 3\)"),
        ((vertices, faces + 1000), "out of range"),
        ((vertices + 50.0, faces), "element sizes outside the body"),
    ]
    for (v, f), message in cases:
        with pytest.raises(ValueError, match=message):
            EmbeddedSurface(body, v, f)
    with pytest.raises(ValueError, match="max_outside_distance"):
        EmbeddedSurface(body, vertices, faces, max_outside_distance=-1.0)
    with pytest.raises(ValueError, match="embeds in"):
        EmbeddedSurface(cr.rectangle(), vertices, faces)
    np.testing.assert_array_equal(cage.points, rest)

    surface = EmbeddedSurface(body, vertices, faces)
    before = surface.positions.copy(), surface.normals.copy()
    bad = rest.copy()
    bad[3, 0] = np.inf
    for x, message in [(bad, "node 3 is not finite"), (rest[:5], "shape"), (rest, "normals must be")]:
        for mode in ("area", "rotated"):
            with pytest.raises(ValueError, match=message):
                surface.update(x, normals=mode if message != "normals must be" else "flat")  # type: ignore[arg-type]
    np.testing.assert_array_equal(surface.positions, before[0])
    np.testing.assert_array_equal(surface.normals, before[1])
    # The core writes only into arrays it can write in place.
    core = surface._core
    with pytest.raises(ValueError, match="writable C-contiguous float64"):
        core.embed(rest, np.zeros((surface.n_vertices, 3), dtype=np.float32))
    with pytest.raises(ValueError, match="writable C-contiguous float64"):
        core.embed(rest, np.zeros((3, surface.n_vertices)).T)


@pytest.mark.parametrize("element", ["hex8", "hex20"])
def test_vertices_outside_a_hex_cage_get_the_exact_distance_and_follow_linear_fields(element):
    """A sphere of radius 0.56 around a cube [-0.5, 0.5]^3 of 3^3 hexes pokes out of every
    face. For an axis-aligned box the element point at the clamped natural coordinates is the
    nearest point of the cage, so the reported distance is exact: |max(|p| - 0.5, 0)| over
    the element size 1/3."""
    cage = cr.box(cells=(3, 3, 3), element=element, origin=(-0.5, -0.5, -0.5))
    vertices, faces = sphere_surface(0.56, n=500)
    surface = EmbeddedSurface(cage, vertices, faces)
    excess = np.linalg.norm(np.maximum(np.abs(vertices) - 0.5, 0), axis=1)
    assert surface.report["outside"] == int(np.count_nonzero(excess > 0))
    np.testing.assert_allclose(surface.outside_distances, 3 * excess, rtol=0, atol=1e-12)
    # The criterion (natural-coordinate excess) is then excess / (half the element size).
    local_excess = np.maximum(np.abs(surface.local_coordinates) - 1, 0).sum(axis=1)
    np.testing.assert_allclose(local_excess, 6 * np.maximum(np.abs(vertices) - 0.5, 0).sum(axis=1), atol=1e-12)
    A = np.array([[1.2, 0.3, 0.0], [-0.2, 0.9, 0.4], [0.1, 0.0, 1.1]])
    surface.update(cage.points @ A.T)
    np.testing.assert_allclose(surface.positions, vertices @ A.T, rtol=0, atol=1e-13)
