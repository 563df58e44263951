"""A Scene of bodies of different cell types and force models: a JoinedBody, each body's part
computed by its own model. Apart, the bodies move exactly as each would alone; together, a
Neo-Hookean hex block rests on a co-rotated tet slab without passing into it."""

import numpy as np
import pytest
import scipy.sparse as sp

import corotate as cr

SOFT = cr.Material(E=1e5, nu=0.3, density=1000.0)
FIRM = cr.Material(E=4e5, nu=0.35, density=800.0)


def body(element, model, size, cells, origin, material=SOFT):
    mesh = cr.box(size, cells, element=element, origin=origin)
    return cr.Body(mesh, material, model=model)


def three_cantilevers():
    """A co-rotated Tet4 bar, a Neo-Hookean Hex8 bar and a St. Venant-Kirchhoff Hex20 bar,
    side by side 0.2 m apart, each clamped at x = 0."""
    return [
        body("tet4", "corotational", (0.4, 0.05, 0.05), (8, 1, 1), (0.0, 0.0, 0.0)),
        body("hex8", "neohookean", (0.4, 0.05, 0.05), (8, 1, 1), (0.0, 0.2, 0.0), FIRM),
        body("hex20", "stvk", (0.4, 0.05, 0.05), (4, 1, 1), (0.0, 0.4, 0.0)),
    ]


def clamped(mesh):
    return mesh.nodes_where(lambda p: p[:, 0] < 1e-9)


def test_bodies_apart_move_as_each_would_alone():
    """Three cantilevers of three cell types and models in one Scene sag under gravity for 30
    steps exactly as three simulations of one body each (a direct solve: the joined system is
    block diagonal, so one solve is three): to 1e-9 of the sag. (Every step assembles: one
    matrix kept for all three would be reassembled when any of them turns.)"""
    bodies = three_cantilevers()
    scene = cr.Scene(bodies)
    assert isinstance(scene.body, cr.JoinedBody) and scene.bodies == tuple(bodies)
    settings = {"gravity": (0, 0, -9.81), "solver": cr.Direct(), "dt": 0.01, "matrix_reuse_angle": 0.0}
    sim = scene.simulation(**settings)
    sim.fix(np.concatenate([scene.nodes(k, clamped(b.mesh)) for k, b in enumerate(bodies)]))
    sim.step(30)
    for k, b in enumerate(bodies):
        alone = cr.Simulation(b, **settings)
        alone.fix(clamped(b.mesh))
        alone.step(30)
        sag = np.abs(alone.displacements).max()
        assert sag > 0.01  # they really bend
        np.testing.assert_allclose(sim.positions[scene.nodes(k)], alone.positions, rtol=0, atol=1e-9 * sag)


def test_joined_body_answers_are_its_bodies_side_by_side():
    """Energy, forces, stiffness, tangent and mass of the joined body are the bodies' own,
    block-diagonally, at any positions."""
    bodies = three_cantilevers()
    joined = cr.JoinedBody(bodies)
    rng = np.random.default_rng(3)
    each = [b.mesh.points + 0.01 * rng.standard_normal(b.mesh.points.shape) for b in bodies]
    x = np.concatenate(each)
    assert joined.energy(x) == pytest.approx(sum(b.energy(p) for b, p in zip(bodies, each)), rel=1e-12)
    np.testing.assert_allclose(
        joined.internal_forces(x), np.concatenate([b.internal_forces(p) for b, p in zip(bodies, each)]), atol=1e-9
    )
    for method in ("stiffness_matrix", "tangent_matrix"):
        expected = sp.block_diag([getattr(b, method)(p) for b, p in zip(bodies, each)])
        assert abs(getattr(joined, method)(x) - expected).max() <= 1e-9 * abs(expected).max()
    expected_mass = sp.block_diag([b.mass_matrix(lumped=True) for b in bodies])
    assert abs(joined.mass_matrix(lumped=True) - expected_mass).max() <= 1e-12 * expected_mass.max()
    np.testing.assert_array_equal(joined.nodes(1), np.arange(bodies[0].n_nodes, bodies[0].n_nodes + bodies[1].n_nodes))
    assert joined.model == "joined" and joined.n_nodes == sum(b.n_nodes for b in bodies)
    np.testing.assert_array_equal(
        joined.stiffness_matrix().toarray(), sp.block_diag([b.stiffness_matrix() for b in bodies]).toarray()
    )


def test_a_neo_hookean_hex_block_rests_on_a_corotated_tet_slab():
    """A Neo-Hookean Hex8 block dropped 1 cm onto a co-rotated Tet4 slab lying on the floor:
    in 600 frames no corner of either body enters the other deeper than 1 % of an element;
    at rest the floor carries both weights and the slab the block's."""
    slab = body("tet4", "corotational", (0.3, 0.3, 0.05), (6, 6, 1), (-0.15, -0.15, 0.0))
    block = body("hex8", "neohookean", (0.1, 0.1, 0.1), (3, 3, 3), (-0.04, -0.06, 0.06), FIRM)
    scene = cr.Scene([slab, block])
    sim = scene.simulation(friction=0.3, gravity=(0, 0, -9.81))
    floor = cr.Plane()
    sim.add_obstacle(floor, friction=0.5)
    element = 0.05
    worst = 0.0
    for frame in range(600):
        sim.step()
        if frame % 5 == 0 or 5 <= frame <= 40:  # every frame of the landing
            worst = max(worst, deepest_inside(sim, scene))
    assert worst < 0.01 * element
    weights = [9.81 * b.mass_matrix(lumped=True).sum() / 3 for b in (slab, block)]
    np.testing.assert_allclose(sim.contact_force(floor), [0, 0, sum(weights)], atol=2e-3 * sum(weights))
    np.testing.assert_allclose(sim.part_contact_force(1, 0), [0, 0, weights[1]], atol=2e-3 * weights[1])
    # On the slab, not beside it or through it.
    assert sim.positions[scene.nodes(1), 2].min() == pytest.approx(0.05, abs=0.002)


def deepest_inside(sim, scene):
    """How deep the deepest surface vertex of either body is inside the other [m] (0: none)."""
    surfaces = []
    for k, b in enumerate(scene.bodies):
        outer = cr.boundary_surface(b.mesh)
        used = np.unique(b.mesh.boundary_faces())
        nodes = scene.nodes(k, used)
        surfaces.append((cr.TriangleMesh(sim.positions[nodes], outer.cells), nodes))
    deepest = 0.0
    for k, other in ((0, 1), (1, 0)):
        d, _ = surfaces[other][0].distance(sim.positions[surfaces[k][1]])
        deepest = max(deepest, -d.min())
    return deepest


def test_joined_body_bad_input():
    bodies = three_cantilevers()
    with pytest.raises(ValueError, match="at least one body"):
        cr.JoinedBody([])
    with pytest.raises(TypeError, match=r"not a corotate\.Body"):
        cr.JoinedBody([bodies[0], bodies[1].mesh])
    sheet = cr.Body(cr.rectangle((0.1, 0.1), (2, 2)), SOFT, model="stvk", thickness=0.001)
    with pytest.raises(ValueError, match="sheet"):
        cr.Scene([bodies[0], sheet])
    joined = cr.JoinedBody(bodies)
    with pytest.raises(ValueError, match="positions must have shape"):
        joined.energy(np.zeros((3, 3)))
    with pytest.raises(ValueError, match="out of range"):
        joined.nodes(3)
    with pytest.raises(AttributeError, match="read-only"):
        joined.bodies = ()
    # What needs one mesh says so: a render surface or a tool embeds in one body.
    with pytest.raises(TypeError, match="Body"):
        cr.EmbeddedSurface(joined, bodies[0].mesh.points, bodies[0].mesh.boundary_faces())
    with pytest.raises(TypeError, match="Body"):
        cr.HapticFeedback(joined, [0, 1])
    # A failed step leaves the state as it was.
    scene = cr.Scene(bodies)
    sim = scene.simulation(gravity=(0, 0, -9.81))
    sim.step(2)
    before = sim.positions.copy()
    sim.velocities[scene.nodes(1, [0])] = np.nan  # (node 36 of the scene)
    with pytest.raises(ValueError, match="velocity of node 36 is not finite"):
        sim.step()
    np.testing.assert_array_equal(sim.positions, before)


def test_a_probe_pressed_into_a_mixed_scene_feels_the_weight_it_lifts():
    """Weightless bodies, a Neo-Hookean hex block resting on a co-rotated tet slab fixed at its
    bottom: a sphere pressed 5 mm into the block from above, held still until the block comes
    to rest. The tool feels what it exerts (ToolFeedback's force is minus the contacts' force
    on the bodies), and the slab carries exactly what the probe pushes (the force through the
    part contact equals the probe's, to 1 %)."""
    slab = body("tet4", "corotational", (0.3, 0.3, 0.05), (6, 6, 1), (-0.15, -0.15, 0.0))
    block = body("hex8", "neohookean", (0.1, 0.1, 0.1), (4, 4, 4), (-0.05, -0.05, 0.05), FIRM)
    scene = cr.Scene([slab, block])
    sim = scene.simulation(friction=0.3, rayleigh=(5.0, 0.0))
    sim.fix(scene.nodes(0, slab.mesh.nodes_where(lambda p: p[:, 2] < 1e-9)))
    probe = cr.Sphere((0.0, 0.0, 0.17), 0.02)
    sim.add_obstacle(probe)
    feedback = cr.ToolFeedback(sim, probe)
    for frame in range(200):
        probe.move_to((0.0, 0.0, 0.17 - 0.005 * min(1.0, frame / 50)))
        sim.step()
        feedback.update()
    force, _ = feedback.query(probe.position)
    assert force[2] > 0.5  # pushed back up
    np.testing.assert_allclose(force, -sim.contact_force(probe), atol=1e-9)
    np.testing.assert_allclose(sim.part_contact_force(0, 1), -force, rtol=0, atol=0.01 * abs(force[2]))


def test_each_body_of_a_mixed_scene_carries_its_own_render_surface():
    """Scene.embedded_surface: a surface in the tet bar and one in the hex bar of a mixed scene
    follow their bodies: after the steps, each equals the same surface embedded in its body
    alone and updated with that body's nodes, to the bit; at rest they are the vertices given."""
    bodies = three_cantilevers()[:2]
    scene = cr.Scene(bodies)
    sim = scene.simulation(gravity=(0, 0, -9.81), solver=cr.Direct())
    sim.fix(np.concatenate([scene.nodes(k, clamped(b.mesh)) for k, b in enumerate(bodies)]))
    rng = np.random.default_rng(5)
    surfaces, alone = [], []
    for k, b in enumerate(bodies):
        low, high = b.mesh.points.min(axis=0), b.mesh.points.max(axis=0)
        vertices = low + (high - low) * rng.uniform(0.05, 0.95, size=(40, 3))  # inside the bar
        triangles = np.arange(39 * 3).reshape(-1, 3) % 40
        surfaces.append(scene.embedded_surface(k, vertices, triangles))
        alone.append(cr.EmbeddedSurface(b, vertices, triangles))
        np.testing.assert_array_equal(surfaces[k].positions, vertices)
    sim.step(10)
    for k, (surface, own) in enumerate(zip(surfaces, alone)):
        surface.update(sim)
        own.update(sim.positions[scene.nodes(k)])
        np.testing.assert_array_equal(surface.positions, own.positions)
        np.testing.assert_array_equal(surface.normals, own.normals)
        assert surface.positions[:, 2].min() < own.mesh.points[:, 2].min() - 1e-4  # they sagged
    surfaces[1].update(sim.positions)  # the scene's positions do too
    np.testing.assert_array_equal(surfaces[1].positions, alone[1].positions)
    with pytest.raises(ValueError, match="body 2 is out of range"):
        scene.embedded_surface(2, np.zeros((1, 3)), np.zeros((0, 3)))
    before = surfaces[0].positions.copy()
    with pytest.raises(ValueError, match=r"\(36, 3\) or the scene's \(72, 3\)"):
        surfaces[0].update(np.zeros((5, 3)))
    np.testing.assert_array_equal(surfaces[0].positions, before)
    with pytest.raises(ValueError, match="one body of a scene"):
        sim.set_contact_surface(surfaces[0])


def test_haptic_feedback_at_a_body_of_a_mixed_scene():
    """Scene.haptic_feedback: the averaged-stiffness feedback at the clamped end of the hex
    bar of a mixed scene answers from the scene's positions exactly as the same feedback of the
    bar alone answers from its own nodes, and its reaction forces in the scene's simulation are
    those of the bar simulated alone (to 1e-6: the two step the same to round-off)."""
    bodies = three_cantilevers()[:2]
    scene = cr.Scene(bodies)
    settings = {"gravity": (0, 0, -9.81), "solver": cr.Direct(), "dt": 0.01}
    sim = scene.simulation(**settings)
    sim.fix(np.concatenate([scene.nodes(k, clamped(b.mesh)) for k, b in enumerate(bodies)]))
    bar = bodies[1]
    alone = cr.Simulation(bar, **settings)
    alone.fix(clamped(bar.mesh))
    sim.step(10)
    alone.step(10)
    tool = clamped(bar.mesh)
    feedback = scene.haptic_feedback(1, tool)
    own = cr.HapticFeedback(bar, tool)
    np.testing.assert_array_equal(feedback.tool, tool)
    for got, expected in zip(feedback.query(sim.positions), own.query(sim.positions[scene.nodes(1)])):
        np.testing.assert_array_equal(got, expected)
    for got, expected in zip(feedback.query(sim.positions[scene.nodes(1)]), own.query(sim.positions[scene.nodes(1)])):
        np.testing.assert_array_equal(got, expected)
    reaction = own.reaction_forces(alone)
    assert np.abs(reaction[:, 2]).sum() > 1.0  # the clamp holds the bar up
    np.testing.assert_allclose(feedback.reaction_forces(sim), reaction, rtol=0, atol=1e-6 * np.abs(reaction).max())
    with pytest.raises(ValueError, match="its scene"):
        feedback.reaction_forces(alone)
    with pytest.raises(ValueError, match=r"\(36, 3\) or the scene's \(72, 3\)"):
        feedback.query(np.zeros((4, 3)))
    with pytest.raises(ValueError, match="body 5 is out of range"):
        scene.haptic_feedback(5, tool)
