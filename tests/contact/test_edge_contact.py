"""Edge against edge: two square beams turned 45 degrees about their axes, one dropped across
the other, meet ridge on ridge, where no node of either lies inside the other. Without edge
contact the upper ridge sinks half an element into the lower beam before a node catches it;
with it the crossing holds to 1 % of an element, momentum is kept, and a plank laid across
two ridges rests on its edges with its weight carried."""

import numpy as np
import pytest
from conftest import check_contact_derivatives

import corotate as cr

WIDTH = 0.1  # [m] the beams' square section; one element across
LENGTH = 0.7  # seven elements long: no node at the crossing (x = y = 0)
SOFT = cr.Material(E=1e6, nu=0.3, density=1000.0)


def ridge_beam(along: str, lift: float, cells: int = 7, turned: bool = True, shift: float = 0.0):
    """A beam along x or y (moved by `shift` across), turned 45 degrees about its axis (a
    ridge on top and one below) or not, its bottom at height `lift`."""
    mesh = cr.box((LENGTH, WIDTH, WIDTH), (cells, 1, 1), origin=(-LENGTH / 2, -WIDTH / 2, -WIDTH / 2))
    c, s = (np.sqrt(0.5), np.sqrt(0.5)) if turned else (1.0, 0.0)
    turn = np.array([[1, 0, 0], [0, c, -s], [0, s, c]])  # 45 degrees about x
    points = mesh.points @ turn.T
    if along == "y":
        points = points @ np.array([[0.0, -1, 0], [1, 0, 0], [0, 0, 1]]).T  # a quarter turn about z
    points[:, 2] += lift - points[:, 2].min()
    points[:, 1 if along == "x" else 0] += shift
    return cr.Body(cr.Mesh(points, mesh.cells, mesh.cell_type), SOFT)


def ridge(positions, nodes, top):
    """The ridge polyline (top or bottom corner line) of a beam's nodes, in rest order."""
    z = positions[nodes, 2]
    return nodes[np.isclose(z, z.max() if top else z.min(), atol=1e-9)]


def crossing_gap(positions, upper, lower):
    """Height of the upper beam's lower ridge above the lower beam's upper ridge where they
    cross in plan (negative: sunk in) [m]."""
    for a, b in zip(upper[:-1], upper[1:]):
        for c, d in zip(lower[:-1], lower[1:]):
            p, q, r, s = (positions[k] for k in (a, b, c, d))
            m = np.array([[q[0] - p[0], r[0] - s[0]], [q[1] - p[1], r[1] - s[1]]])
            if abs(np.linalg.det(m)) < 1e-12:
                continue
            u, v = np.linalg.solve(m, (r - p)[:2])
            if 0 <= u <= 1 and 0 <= v <= 1:
                return (p + u * (q - p))[2] - (r + v * (s - r))[2]
    raise AssertionError("the ridges no longer cross")


def crossed_beams(
    edge_contact: bool, integrator: str = "linearized", gravity: float = -9.81, fixed: bool = True, self_contact=False
):
    """The lower beam along x (its ends fixed), the upper along y 5 mm above it, crossed."""
    lower = ridge_beam("x", 0.0)
    upper = ridge_beam("y", lower.mesh.points[:, 2].max() + 0.005)
    scene = cr.Scene([lower, upper])
    sim = scene.simulation(
        friction=0.3, gravity=(0, 0, gravity), integrator=integrator, solver=cr.Direct(), self_contact=self_contact
    )
    sim.contact_settings = {"edge_contact": edge_contact}
    if fixed:
        sim.fix(scene.nodes(0)[np.abs(lower.mesh.points[:, 0]) > LENGTH / 2 - 1e-9])
    lower_ridge = ridge(scene.body.mesh.points, scene.nodes(0), top=True)
    upper_ridge = ridge(scene.body.mesh.points, scene.nodes(1), top=False)
    upper_ridge = upper_ridge[np.argsort(scene.body.mesh.points[upper_ridge, 1])]
    lower_ridge = lower_ridge[np.argsort(scene.body.mesh.points[lower_ridge, 0])]
    return scene, sim, upper_ridge, lower_ridge


def momentum(sim, nodes):
    """(3,) the momentum of the given nodes (the consistent mass's rows)."""
    v = np.zeros_like(sim.velocities)
    v[nodes] = sim.velocities[nodes]
    return (sim.mass_matrix() @ v.reshape(-1)).reshape(-1, 3).sum(axis=0)


def test_without_edge_contact_the_ridges_pass_through_each_other():
    """The case edge contact is for: no node of either beam enters the other while the upper
    ridge sinks through the lower one by more than a third of an element."""
    _, sim, upper, lower = crossed_beams(edge_contact=False)
    deepest = 0.0
    for _ in range(40):
        sim.step()
        deepest = min(deepest, crossing_gap(sim.positions, upper, lower))
    assert deepest < -WIDTH / 3


@pytest.mark.parametrize("integrator, self_contact", [("linearized", False), ("newton", False), ("linearized", True)])
def test_crossed_ridges_hold_at_the_landing(integrator, self_contact):
    """Ridge on ridge: over the landing (the upper beam bounces on the one point where the
    ridges cross) the crossing never sinks by 1 % of an element, edge contacts carry it, and
    the upper beam's momentum changes by exactly the impulse of the reported contact forces and
    its weight. With self-contact on, each beam's edges are tested against its own too, away
    from their neighbourhoods: nothing changes (no edge of a straight beam touches its own)."""
    scene, sim, upper, lower = crossed_beams(edge_contact=True, integrator=integrator, self_contact=self_contact)
    upper_nodes = scene.nodes(1)
    mass = 1000.0 * LENGTH * WIDTH**2
    weight = np.array([0, 0, -9.81 * mass])
    p0 = momentum(sim, upper_nodes)
    impulse = np.zeros(3)
    deepest = 0.0
    for _ in range(50):  # (balanced on a point, it starts to tip later)
        sim.step()
        deepest = min(deepest, crossing_gap(sim.positions, upper, lower))
        impulse += sim.dt * (sim.part_contact_force(1, 0) + weight)
    assert deepest > -0.01 * WIDTH
    contacts = sim.contacts
    edge = contacts["edges"]
    assert edge.any()
    assert np.all((contacts["weights"][edge, :2] > 0) & (contacts["weights"][edge, :2] < 1))
    assert np.all(contacts["parts"] != sim.parts[contacts["nodes"]])  # between the beams only
    np.testing.assert_allclose(np.abs(contacts["normals"][edge, 2]), 1.0, atol=0.02)
    np.testing.assert_allclose(momentum(sim, upper_nodes) - p0, impulse, atol=1e-6 * mass)


@pytest.mark.parametrize("integrator", ["linearized", "newton"])
def test_a_plank_across_two_ridges_rests_on_its_edges(integrator):
    """A flat plank dropped across two ridged beams (no node of either under the other): it
    rests on the four points where its bottom edges cross the ridges, never sinking by 1 % of
    an element, held by edge contacts alone, and the ridges carry its weight (1 %)."""
    ridges = [ridge_beam("x", 0.0, cells=3, shift=y) for y in (-0.2, 0.2)]
    top = ridges[0].mesh.points[:, 2].max()
    plank = ridge_beam("y", top + 0.005, turned=False)
    scene = cr.Scene([*ridges, plank])
    sim = scene.simulation(friction=0.3, gravity=(0, 0, -9.81), integrator=integrator, solver=cr.Direct())
    sim.fix(np.concatenate([scene.nodes(k)[np.abs(ridges[k].mesh.points[:, 0]) > LENGTH / 2 - 1e-9] for k in (0, 1)]))
    points = scene.body.mesh.points
    plank_nodes = scene.nodes(2)
    bottom = plank_nodes[np.isclose(points[plank_nodes, 2], points[plank_nodes, 2].min())]
    rims = [bottom[np.isclose(points[bottom, 0], side)] for side in (-WIDTH / 2, WIDTH / 2)]
    rims = [rim[np.argsort(points[rim, 1])] for rim in rims]
    tops = [ridge(points, scene.nodes(k), top=True) for k in (0, 1)]
    tops = [t[np.argsort(points[t, 0])] for t in tops]
    deepest = 0.0
    forces = []
    for _ in range(150):
        sim.step()
        deepest = min(deepest, *(crossing_gap(sim.positions, rim, t) for rim in rims for t in tops))
        forces.append(sim.part_contact_force(2, 0) + sim.part_contact_force(2, 1))
    assert deepest > -0.01 * WIDTH
    assert sim.contacts["edges"].all() and len(sim.contacts["edges"]) == 4
    weight = 9.81 * 1000.0 * LENGTH * WIDTH**2
    np.testing.assert_allclose(np.mean(forces[-50:], axis=0), [0, 0, weight], atol=0.01 * weight)


def test_a_collision_edge_on_edge_keeps_momentum():
    """Weightless, both beams free: the upper one thrown ridge first onto the lower at 1 m/s.
    The total momentum stays what it was to 1e-9 (the edge contact's forces are equal and
    opposite inside one solve), the crossing holds to 1 % of an element, and the lower beam
    leaves with a share of the momentum."""
    scene, sim, upper, lower = crossed_beams(edge_contact=True, gravity=0.0, fixed=False)
    everything = np.arange(sim.body.n_nodes)
    sim.velocities[scene.nodes(1), 2] = -1.0
    p0 = momentum(sim, everything)
    deepest = 0.0
    for _ in range(30):
        sim.step()
        np.testing.assert_allclose(momentum(sim, everything), p0, atol=1e-9 * abs(p0[2]))
        deepest = min(deepest, crossing_gap(sim.positions, upper, lower))
    assert deepest > -0.01 * WIDTH
    assert momentum(sim, scene.nodes(0))[2] < 0.2 * p0[2]


def test_edge_contact_potentials_are_their_derivatives():
    """With edge contacts in the step: forces and Hessian match central differences, the
    Hessian is symmetric positive semi-definite and the forces sum to zero."""
    _, sim, *_ = crossed_beams(edge_contact=True)
    for _ in range(100):
        sim.step()
        if sim.contacts["edges"].any():
            break
    assert sim.contacts["edges"].any()
    rng = np.random.default_rng(3)
    y = sim.positions + 1e-4 * rng.standard_normal(sim.positions.shape)
    check_contact_derivatives(sim, y, rng.standard_normal(y.shape), 1e-7, internal=True)


def test_edge_contact_setting_rejects_what_is_not_a_bool():
    _, sim, *_ = crossed_beams(edge_contact=True)
    before = sim.contact_settings
    with pytest.raises(TypeError, match="edge_contact"):
        sim.contact_settings = {"edge_contact": "yes"}
    with pytest.raises(ValueError, match="unknown contact settings"):
        sim.contact_settings = {"edges": False}
    assert sim.contact_settings == before
