"""The default solver (capped, warm-started two-level PCG) on bodies that turn far from the
configuration its coarse level was built at. The coarse level used to stay frozen at the rest
state: on a turned body its rigid-body modes and factorized coarse matrix were wrong, the
capped solves left more than half of the error, and the warm start fed it back (the run-away
of docs/notes/performance.md; the armadillo hanging from a point ran away under cr.PCG()). It now turns
each aggregate's coarse space with the body (two_level_preconditioner.hpp). Both scenes are
irregular meshes the project makes itself: a structured box with jittered interior nodes."""

import numpy as np
import pytest
from studies.scenes import SOFT, jittered_box

import corotate as cr

MAT = SOFT


def test_a_freely_spinning_body_does_not_run_away():
    # A 20 x 10 x 10 cm box spinning at 5.5 rad/s about a skew axis, no gravity, nothing
    # fixed: in 25 steps it turns by 80 degrees. Implicit Euler keeps the energy from rising
    # (after the first step, whose linearisation stretches the body by 10 % of its energy);
    # the default solver must do the same, with the positions of a direct solve of every
    # step. Measured: 1.7 iterations per step, energy +0.16 %, positions 0.3 % of the box
    # off; with the frozen coarse level 10 iterations, +55 % and 4.7 % (9 m after 100 steps).
    mesh = jittered_box((0.2, 0.1, 0.1), (8, 4, 4))
    body = cr.Body(mesh, MAT)
    runs = {}
    for name, solver in (("direct", cr.Direct()), ("default", cr.PCG())):
        # "ignore": the first step's energy jump is physical here, not a run-away
        sim = cr.Simulation(body, dt=0.01, gravity=(0, 0, 0), solver=solver, on_failure="ignore")
        sim.velocities[:] = np.cross([1.0, 2.0, 5.0], mesh.points - mesh.points.mean(axis=0))
        positions, energies = [], []
        for _ in range(25):
            sim.step(1)
            positions.append(sim.positions.copy())
            energies.append(sim.kinetic_energy + body.energy(sim.positions))
        runs[name] = (np.array(positions), np.array(energies), sim.stats["iterations_per_step"])
    reference, reference_energy, _ = runs["direct"]
    positions, energy, iterations = runs["default"]
    assert reference_energy.max() <= 1.002 * reference_energy[0]  # the converged motion's
    assert energy.max() <= 1.005 * energy[0], energy / energy[0]
    assert np.abs(positions - reference).max() < 0.01 * 0.2
    assert iterations <= 3


@pytest.mark.parametrize("preconditioner", ["auto", "two_level"])
def test_a_body_hanging_from_a_point_follows_the_converged_motion(preconditioner):
    # A 30 cm bar (1,920 jittered tets) hanging from three nodes at one end of its top edge
    # swings down through 90 degrees, like the armadillo of Table 1. The default solver
    # stays within 0.5 % of a direct solve (measured 0.11 %, with 1.9 iterations per step,
    # "auto" being the reference factor at this size); with the frozen coarse level it needed
    # 14 iterations per step, often the cap of 20, and was 0.85 % off. The two-level
    # preconditioner at its looser default tolerance (2e-2) as well: measured 0.125 %, 2.8
    # iterations (the reference factor at 2e-2 would be 0.71 % off: hence its 1e-2).
    mesh = jittered_box((0.3, 0.06, 0.06), (20, 4, 4), jitter=0.25)
    fixed = np.argsort(np.linalg.norm(mesh.points - [0.0, 0.03, 0.06], axis=1))[:3]
    body = cr.Body(mesh, MAT)
    runs = {}
    for name, solver in (("direct", cr.Direct()), ("default", cr.PCG(preconditioner=preconditioner))):
        sim = cr.Simulation(body, dt=0.01, gravity=(0, 0, -9.81), solver=solver)
        sim.fix(fixed)
        centroids = []
        for _ in range(150):
            sim.step(1)
            centroids.append(sim.positions.mean(axis=0))
        runs[name] = (np.array(centroids), sim.stats)
    reference, _ = runs["direct"]
    centroids, stats = runs["default"]
    travel = np.abs(reference - mesh.points.mean(axis=0)).max()
    assert travel > 0.1  # it really swings down
    assert np.abs(centroids - reference).max() < 5e-3 * travel
    assert stats["iterations_per_step"] <= 6
    assert stats["energy_growth_steps"] == stats["stalled_steps"] == 0
    assert stats["tolerance"] == (2e-2 if preconditioner == "two_level" else 1e-2)
