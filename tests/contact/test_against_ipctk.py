"""The IPC toolkit (PyPI ``ipctk``) as an oracle for the two geometric pieces of corotate's
contact: the distance from a point to a triangle mesh, and the continuous collision
detection that finds where a node's path over a step first touches an obstacle (corotate
marches the path by the signed distance; ipctk's Tight-Inclusion CCD finds the time of
impact of a point against each moving triangle). corotate's own contact model (an
augmented-Lagrangian penalty inside its one-solve step) is not IPC's barrier: see the
contact guide's "Why not IPC's barrier" for the choice."""

import subprocess
import sys

import numpy as np
import pytest
from conftest import CELLS, CUBE, cube
from test_triangle_mesh import box_surface, random_rotation

import corotate as cr

ipctk = pytest.importorskip("ipctk")


def _ipctk_fails() -> str:
    """Why ipctk cannot run here ("" when it can), asked of a separate process: a wheel built
    for a newer instruction set than the CPU has (its Python 3.13 wheel uses instructions
    this AVX2 machine lacks) dies of an illegal instruction at its first call, which would
    take the test process with it."""
    probe = (
        "import numpy as np, ipctk; e = np.eye(3); "
        "ipctk.point_triangle_distance(np.ones(3), e[0], e[1], e[2]); "
        "ipctk.TightInclusionCCD().point_triangle_ccd(np.ones(3), e[0], e[1], e[2], -np.ones(3), e[0], e[1], e[2])"
    )
    run = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, timeout=120)
    return "" if run.returncode == 0 else f"ipctk {ipctk.__version__} fails on this machine (exit {run.returncode})"


_FAILS = _ipctk_fails()
pytestmark = pytest.mark.skipif(bool(_FAILS), reason=_FAILS)


def jittered_box_surface(rng, size, cells):
    """A closed surface of general triangles: a triangulated box whose vertices are moved
    at random by a fifth of a cell (it stays closed and consistently wound)."""
    points, triangles = box_surface(size, cells)
    cell = np.min(np.asarray(size) / np.asarray(cells))
    return points + rng.uniform(-0.2, 0.2, points.shape) * cell, triangles


def test_distances_equal_ipctk_point_triangle_distances():
    rng = np.random.default_rng(7)
    points, triangles = jittered_box_surface(rng, (0.4, 0.3, 0.2), (4, 3, 2))
    rotation, position = random_rotation(rng), rng.normal(size=3)
    mesh = cr.TriangleMesh(points, triangles, position=position, rotation=rotation)
    world = position + points @ rotation.T
    queries = position + rng.uniform(-0.25, 0.25, (300, 3)) @ rotation.T
    d, _normals = mesh.distance(queries)
    oracle = np.array(
        [np.sqrt(min(ipctk.point_triangle_distance(q, *(world[i] for i in t)) for t in triangles)) for q in queries]
    )
    np.testing.assert_allclose(np.abs(d), oracle, rtol=0, atol=1e-12)
    assert (d < 0).sum() > 30 and (d > 0).sum() > 30  # inside and outside both tested


def time_of_impact(start, end, triangles_start, triangles_end):
    """ipctk's earliest time of impact in [0, 1] of the point moving from start to end
    against triangles moving from triangles_start to triangles_end (k, 3, 3), or None."""
    ccd = ipctk.TightInclusionCCD()
    earliest = None
    for t0, t1 in zip(triangles_start, triangles_end):
        hit, toi = ccd.point_triangle_ccd(start, *t0, end, *t1)
        if hit and (earliest is None or toi < earliest):
            earliest = toi
    return earliest


def check_first_touch(sim, plate, plate_start, plate_end):
    """Steps sim once and compares each contact with ipctk's time of impact of the node's
    path over the step (x to its free flight x + dt v + dt^2 g, the path corotate marches)
    against the plate's triangles moving from plate_start to plate_end (world, (m, 3, 3)).
    Returns the largest distance between the two first-touch points over the length of the
    node's path relative to the plate."""
    x, v = sim.positions.copy(), sim.velocities.copy()
    ends = x + sim.dt * v + sim.dt**2 * np.asarray(sim.gravity)
    oracle = {}
    for i in sim.contact_nodes:
        toi = time_of_impact(x[i], ends[i], plate_start, plate_end)
        if toi is not None:
            oracle[int(i)] = toi
    sim.step()
    contacts = sim.contacts
    assert len(oracle) > 20  # the step has impacts to compare
    assert set(contacts["nodes"].tolist()) == set(oracle)
    # corotate reports the touching point on the surface at the plate's current (end) pose;
    # compare both in the plate's frame: the point minus where the plate was at that time.
    shift = plate_end[0, 0] - plate_start[0, 0]  # the plate translates
    worst = 0.0
    for node, point in zip(contacts["nodes"], contacts["points"]):
        toi, path = oracle[int(node)], ends[node] - x[node]
        touch_in_plate = x[node] + toi * path - toi * shift
        relative_path = np.linalg.norm(path - shift)  # the path corotate marches, in the plate's frame
        worst = max(worst, np.linalg.norm((point - shift) - touch_in_plate) / relative_path)
    print(f"{len(oracle)} contacts; first touch within {worst:.1e} of the path length of ipctk's")
    return worst


def tilted_plate(rng):
    """A thin triangulated plate (2 mm), tilted a little, whose top is near z = 0, and its
    triangles in the world (m, 3, 3)."""
    points, triangles = jittered_box_surface(rng, (0.6, 0.6, 0.002), (6, 6, 1))
    points[:, 2] = np.where(points[:, 2] > 0, 0.001, -0.001)  # keep it 2 mm thick
    tilt = cr.Plane((0, 0, 0), (0.05, -0.03, 1.0)).rotation
    plate = cr.TriangleMesh(points, triangles, rotation=tilt)
    return plate, (points @ tilt.T)[triangles]


def test_a_node_path_first_touches_where_ipctk_ccd_says_at_10_m_per_s():
    """The cube falls at 10 m/s: each node crosses 10 cm in the step, 50 times the plate's
    thickness. Every node whose path ipctk says hits the plate is a contact (and no other),
    touching where ipctk's time of impact puts it: corotate's march stops within 1e-3 of the
    path's length in front of the surface and reports the nearest surface point (ipctk's
    time is conservative by ~1e-4 of the step). Measured: 1.1e-3 of the path; 3e-3 allowed."""
    rng = np.random.default_rng(3)
    plate, world = tilted_plate(rng)
    _mesh, sim = cube(z0=0.03, E=1e6, solver=cr.PCG(tolerance=1e-8))
    sim.velocities[:, 2] = -10.0
    sim.add_obstacle(plate)
    worst = check_first_touch(sim, plate, world, world)
    assert worst < 3e-3
    assert plate.distance(sim.positions)[0].min() > -0.01 * CUBE / CELLS  # and nothing went through


def test_a_moving_plate_touches_where_ipctk_ccd_says():
    """The plate is moved up by 6 cm between two frames (a tool swung at 6 m/s) into a cube
    that rests above it: in the plate's moving frame every node's path is compared with
    ipctk's CCD of the node against the translating triangles. Measured: 1.8e-3 of the path
    relative to the plate; 3e-3 allowed."""
    rng = np.random.default_rng(5)
    plate, world = tilted_plate(rng)
    _mesh, sim = cube(z0=0.03, E=1e6, solver=cr.PCG(tolerance=1e-8))
    sim.add_obstacle(plate)
    sim.step()  # the plate is seen where it is (no contact yet)
    assert len(sim.contacts["nodes"]) == 0
    lift = np.array([0.0, 0.0, 0.06])
    plate.move_to(lift, plate.rotation)
    worst = check_first_touch(sim, plate, world, world + lift)
    assert worst < 3e-3
    assert plate.distance(sim.positions)[0].min() > -0.01 * CUBE / CELLS
