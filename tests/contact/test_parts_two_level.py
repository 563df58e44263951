"""Contact between parts with the two-level preconditioner (the default above 6,000 unknowns):
its coarse level takes the coupling between the parts in contact (P^T C P, on a coarse pattern
grown by the aggregate pairs the contacts join) and its cycle's residuals the coupling's
product, so two stacked cubes at rest take a few tens of CG iterations per step instead of
hundreds; and a failed step restores that pattern too."""

import numpy as np
from conftest import interrupted_step

import corotate as cr

SOFT = cr.Material(E=1e5, nu=0.3, density=1000.0)


def stacked(solver, **settings):
    """Two soft 10 cm cubes of 6 x 6 x 6 cells (1,296 tets each), the upper one 5 mm above the
    lower one and off-centre, on the floor."""
    lower = cr.Body(cr.box((0.1, 0.1, 0.1), (6, 6, 6), origin=(-0.05, -0.05, 0.0)), SOFT)
    upper = cr.Body(cr.box((0.1, 0.1, 0.1), (6, 6, 6), origin=(-0.02, -0.04, 0.105)), SOFT)
    scene = cr.Scene([lower, upper])
    sim = scene.simulation(friction=0.3, gravity=(0, 0, -9.81), solver=solver, **settings)
    sim.add_obstacle(cr.Plane(), friction=0.5)
    return scene, sim


def test_stacked_cubes_at_rest_take_few_iterations_with_the_two_level_preconditioner():
    """After the landing, 50 steps at rest take fewer than 40 CG iterations per step (174 when
    the coarse level held each part to the ground where they touch, 85 with the coupling in the
    coarse matrix but not in the cycle's residuals), and the upper cube rests where a direct
    solve puts it (to 0.2 mm: the PCG's loose default tolerance)."""
    scene, sim = stacked(cr.PCG(preconditioner="two_level"))
    sim.step(100)
    sim.reset_stats()
    sim.step(50)
    assert sim.stats["iterations_per_step"] < 40
    _, direct = stacked(cr.Direct())
    direct.step(150)
    upper = scene.nodes(1)
    np.testing.assert_allclose(sim.positions[upper].mean(axis=0), direct.positions[upper].mean(axis=0), atol=2e-4)


def test_a_failed_step_restores_the_coarse_coupling():
    """A step interrupted while the upper cube lands (the coarse pattern grows with each new
    pair of aggregates in contact): state and contacts are as before, and the steps run again
    give, to the bit, what an uninterrupted twin gives. (Every step assembles: a kept matrix
    is not part of the restored state.)"""
    _, sim = stacked(cr.PCG(preconditioner="two_level"), matrix_reuse_angle=0.0)
    sim.step(3)  # just before the landing
    interrupted_step(sim, 6, after=4)
    sim.step(6)
    _, twin = stacked(cr.PCG(preconditioner="two_level"), matrix_reuse_angle=0.0)
    twin.step(9)
    assert (twin.contacts["parts"] >= 0).any()  # the landing happened in these steps
    np.testing.assert_array_equal(sim.positions, twin.positions)
