"""A body that touches itself: a soft C-shaped body whose upper arm sags onto its lower arm
rests on it without passing through (and passes through without self-contact), the floor
carries exactly the weight, closing jaws keep momentum, the potentials match finite
differences, and a body that never folds gets no self-contacts."""

import numpy as np
import pytest
from conftest import check_contact_derivatives

import corotate as cr

ELEMENT = 0.01  # [m] the C's cells are 1 cm cubes (6 tets each)
GRAVITY = (0.0, 0.0, -9.81)


def c_shape():
    """A 20 x 4 x 6 cm block with a 2 cm slot cut 16 cm deep from its end (x > 4 cm, 2 < z <
    4 cm): two 2 cm arms joined at the back, lying on the floor."""
    full = cr.box((0.2, 0.04, 0.06), (20, 4, 6))
    centre = full.points[full.cells].mean(axis=1)
    keep = ~((centre[:, 2] > 0.02) & (centre[:, 2] < 0.04) & (centre[:, 0] > 0.04))
    used, cells = np.unique(full.cells[keep], return_inverse=True)
    return cr.Mesh(full.points[used], cells.reshape(-1, 4), "tetra")


MESH = c_shape()
CENTRES = MESH.points[MESH.cells].mean(axis=1)
ARM = CENTRES[:, 0] > 0.05  # the arms, clear of the back where they join


def arm(lower):
    """An arm's cells as its own closed surface: its vertices (node indices) and triangles."""
    cells = MESH.cells[ARM & ((CENTRES[:, 2] < 0.02) if lower else (CENTRES[:, 2] > 0.04))]
    used, local = np.unique(cells, return_inverse=True)
    piece = cr.Mesh(MESH.points[used], local.reshape(cells.shape), "tetra")
    return used[np.unique(piece.boundary_faces())], cr.boundary_surface(piece).cells


ARMS = (arm(lower=True), arm(lower=False))


def deepest_inside(positions):
    """How deep the deepest surface vertex of either arm is inside the other [m] (0: none)."""
    deepest = 0.0
    for (vertices, triangles), (others, _) in (ARMS, ARMS[::-1]):
        d, _ = cr.TriangleMesh(positions[vertices], triangles).distance(positions[others])
        deepest = max(deepest, -d.min())
    return deepest


def soft_c(self_contact=True, **settings):
    body = cr.Body(MESH, cr.Material(E=5000.0, nu=0.3, density=1000.0))  # soft: its arm sags 2 cm
    sim = cr.Simulation(body, **settings)
    if self_contact:
        sim.set_part_contact(friction=0.3, self_contact=True)
    return sim


def fold(sim, frames):
    """Steps the C on the floor; returns the deepest interpenetration of its arms."""
    worst = 0.0
    for _ in range(frames):
        sim.step()
        worst = max(worst, deepest_inside(sim.positions))
    return worst


@pytest.fixture(scope="module")
def folded():
    """The C on the floor, its upper arm fallen onto the lower one and at rest (300 frames),
    and the deepest interpenetration on the way."""
    sim = soft_c(gravity=GRAVITY)
    floor = cr.Plane()
    sim.add_obstacle(floor, friction=0.5)
    return sim, floor, fold(sim, 300)


def test_an_arm_that_sags_onto_its_own_body_rests_on_it(folded):
    """The upper arm falls 2 cm onto the lower one (its tip at 0.6 m/s) and comes to rest on
    it: no surface vertex of either arm ever enters the other by more than 1 % of an element,
    and the floor carries exactly the weight (the forces between the arms are internal)."""
    sim, floor, worst = folded
    assert worst < 0.01 * ELEMENT
    # The slot's faces, node above node at rest: closed at the tip.
    upper_face = MESH.nodes_in_box((0.05, -1, 0.039), (1, 1, 0.041))
    lower_face = MESH.nodes_in_box((0.05, -1, 0.019), (1, 1, 0.021))
    assert np.array_equal(MESH.points[upper_face, :2], MESH.points[lower_face, :2])
    gap = sim.positions[upper_face, 2] - sim.positions[lower_face, 2]
    assert gap[MESH.points[upper_face, 0] > 0.19].max() < 0.01 * ELEMENT  # it fell the 2 cm
    self_contacts = sim.contacts["parts"] == 0
    assert self_contacts.sum() > 20
    weight = 9.81 * sim.mass_matrix().sum() / 3
    np.testing.assert_allclose(sim.contact_force(floor), [0, 0, weight], atol=2e-3 * weight)
    np.testing.assert_allclose(sim.part_contact_force(0, 0), 0.0, atol=1e-12)
    assert np.abs(sim.velocities).max() < 2e-3


def test_without_self_contact_the_arm_passes_through():
    """The same fall without self-contact: the arm sinks into the lower one (the check above
    can fail)."""
    sim = soft_c(self_contact=False, gravity=GRAVITY)
    sim.add_obstacle(cr.Plane(), friction=0.5)
    assert fold(sim, 30) > 0.2 * ELEMENT


def test_closing_jaws_keep_momentum_and_do_not_interpenetrate():
    """Weightless, the upper arm swung shut at up to 1 m/s: the jaws close and hit; the forces
    between them are equal and opposite inside one solve, so the momentum stays what it was,
    and the arms never interpenetrate."""
    sim = soft_c(solver=cr.Direct())
    upper = MESH.points[:, 2] > 0.039
    swing = np.clip((MESH.points[:, 0] - 0.04) / 0.16, 0, 1)
    sim.velocities[upper, 2] = -1.0 * swing[upper]
    mass = sim.mass_matrix()

    def momentum():
        return (mass @ sim.velocities.reshape(-1)).reshape(-1, 3).sum(axis=0)

    p0 = momentum()
    worst, touched = 0.0, False
    for _ in range(60):
        sim.step()
        np.testing.assert_allclose(momentum(), p0, atol=1e-9 * np.abs(p0).max())
        worst = max(worst, deepest_inside(sim.positions))
        touched = touched or (sim.contacts["parts"] == 0).any()
    assert touched and worst < 0.01 * ELEMENT


def test_self_contact_potentials_match_finite_differences(folded):
    """Energy, forces (on the node and its triangle's corners, equal and opposite) and the
    coupled Hessian of the self-contacts of the folded C, sticking and sliding."""
    sim, _, _ = folded
    rng = np.random.default_rng(3)
    # (The floor's sticking friction, in its cubic stuck regime 1e-5 m wide, needs the
    # smaller difference step.)
    for scale, h in ((1e-7, 1e-9), (1e-3, 1e-8)):
        y = sim.positions + scale * rng.normal(size=sim.positions.shape)
        check_contact_derivatives(sim, y, rng.normal(size=y.shape), h)


def test_a_body_that_never_folds_gets_no_self_contacts():
    """A soft cube dropped on the floor, squashed and bouncing, and a cantilever bent far
    under its weight: their surfaces never meet themselves, and no node is taken for touching
    its own neighbourhood (the motion is the same with self-contact as without)."""
    cube = cr.box((0.1, 0.1, 0.1), (4, 4, 4), origin=(-0.05, -0.05, 0.02))
    runs = []
    for self_contact in (False, True):
        sim = cr.Simulation(cr.Body(cube, cr.Material(E=2e4, nu=0.3, density=1000.0)), gravity=GRAVITY)
        sim.add_obstacle(cr.Plane(), friction=0.5)
        if self_contact:
            sim.set_part_contact(self_contact=True)
        for _ in range(60):
            sim.step()
            assert (sim.contacts["parts"] < 0).all()
        runs.append(sim.positions.copy())
    np.testing.assert_allclose(runs[1], runs[0], atol=1e-12)

    beam = cr.box((0.3, 0.03, 0.03), (20, 2, 2))
    sim = cr.Simulation(cr.Body(beam, cr.Material(E=3e5, nu=0.3, density=1000.0)), gravity=GRAVITY)
    sim.fix(beam.nodes_on_plane("x", 0.0))
    sim.set_part_contact(self_contact=True)
    for _ in range(80):
        sim.step()
        assert len(sim.contacts["nodes"]) == 0
    assert sim.positions[:, 2].min() < -0.1  # bent far: its tip dropped more than a third of its length


def test_self_contact_bad_input():
    sim = cr.Simulation(cr.Body(cr.box((0.1, 0.1, 0.1), (2, 2, 2)), cr.Material(E=1e5, nu=0.3, density=1000.0)))
    with pytest.raises(ValueError, match="at least two parts"):
        sim.set_part_contact()
    with pytest.raises(TypeError, match="self_contact"):
        sim.set_part_contact(self_contact="yes")
    with pytest.raises(ValueError, match="friction"):
        sim.set_part_contact(friction=float("nan"), self_contact=True)
    assert not sim.part_contact and not sim.self_contact  # nothing changed
    sim.set_part_contact(friction=0.2, self_contact=True)
    assert sim.part_contact and sim.self_contact
    sim.clear_part_contact()
    assert not sim.part_contact and not sim.self_contact
    scene = cr.Scene([cr.Body(MESH, cr.Material(E=5000.0, nu=0.3, density=1000.0))])
    assert scene.simulation(self_contact=True).self_contact
