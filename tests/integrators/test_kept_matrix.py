"""The linearised step keeps its system matrix while no element has turned by more than
matrix_reuse_angle since it was assembled (cpp/include/corotate/integrators/kept_system.hpp).
The force always uses the current rotations, so the body comes to the same rest; the motion
stays near that of a step that assembles every time; a body that turns faster than the angle
per step never keeps its matrix; and whatever else the matrix holds (fixed nodes, attachment
springs, contacts) makes the next step assemble it again."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import corotate as cr

MAT = cr.Material(E=1e6, nu=0.3, density=1000.0)


def cantilever(**kwargs) -> tuple[cr.Mesh, cr.Simulation]:
    mesh = cr.beam(2.0, 0.5, 0.5, cells=(8, 2, 2))
    sim = cr.Simulation(cr.Body(mesh, MAT), dt=0.01, gravity=(0, 0, -9.81), **kwargs)
    sim.fix(mesh.nodes_on_plane("x", 0.0))
    return mesh, sim


def tip_path(angle: float, steps: int = 100) -> tuple[np.ndarray, cr.Simulation]:
    mesh, sim = cantilever(solver=cr.Direct(), matrix_reuse_angle=angle)
    tip = mesh.nodes_on_plane("x", 2.0)
    path = []
    for _ in range(steps):
        sim.step(1)
        path.append(sim.displacements[tip].mean(axis=0))
    return np.array(path), sim


def test_the_swinging_cantilever_keeps_most_matrices_and_its_motion():
    # A soft cantilever released under gravity swings down by 1.06 m. With the matrix kept up
    # to 0.05 rad (84 of 100 steps) the tip's path stays within 0.05 % of the largest
    # displacement of the path that assembles every step (measured 0.034 %; 0.15 % without
    # turning the matrix with the body); 0.2 rad strays further (0.095 %).
    reference, _ = tip_path(0.0)
    largest = np.abs(reference).max()
    assert largest > 0.5
    deviations = {}
    for angle in (0.05, 0.2):
        path, sim = tip_path(angle)
        deviations[angle] = np.abs(path - reference).max() / largest
        assert sim.stats["kept_matrix_steps"] >= 50
    assert 0 < deviations[0.05] < 5e-4
    assert deviations[0.05] < deviations[0.2] < 2e-3


def test_a_swinging_pendulum_keeps_its_path():
    # A bar hinged along one top edge swings down as a whole (Table 1's cage on its anchor
    # does): the kept matrix is turned with the bar. Unturned, its stiffness resisted the
    # bar's rigid rotation and Table 1's cage strayed 19 % from its path.
    def swing(angle: float) -> tuple[np.ndarray, cr.Simulation]:
        mesh = cr.box((0.1, 0.1, 0.4), cells=(2, 2, 8))
        body = cr.Body(mesh, MAT)
        # ("ignore": the swing's first steps grow the energy by over 1 %, kept matrix or not)
        sim = cr.Simulation(
            body, dt=0.01, gravity=(0, -9.81, -9.81), solver=cr.Direct(), matrix_reuse_angle=angle, on_failure="ignore"
        )
        top = mesh.nodes_on_plane("z", 0.4)
        sim.fix(top[np.abs(mesh.points[top, 1] - 0.05) < 1e-9])
        path = []
        for _ in range(150):
            sim.step(1)
            path.append(sim.displacements.copy())
        return np.array(path), sim

    reference, _ = swing(0.0)
    path, sim = swing(0.05)
    largest = np.abs(reference).max()
    assert largest > 0.4 and sim.stats["kept_matrix_steps"] > 60
    assert np.abs(path - reference).max() < 3e-3 * largest  # measured 1.5e-3


def test_a_kept_matrix_comes_to_the_same_rest():
    # Damped, the sag settles where the forces balance: the static answer, whatever matrix the
    # last steps kept (6 s at alpha = 8: the swing decays to e^-24 of its start).
    _, static = cantilever()
    static.solve_static()
    _, sim = cantilever(rayleigh=(8.0, 0.0), solver=cr.Direct())
    sim.step(600)
    assert sim.stats["kept_matrix"] and sim.stats["kept_matrix_steps"] > 500
    np.testing.assert_allclose(sim.positions, static.positions, rtol=0, atol=1e-7 * np.abs(static.displacements).max())


def test_a_spinning_body_keeps_its_matrix_turned_with_it():
    # A box spinning freely at 1.2 rad/s about a skew axis: after the two steps that measure
    # how fast it turns, its elements turn with it and no further than its own rotation, so
    # the matrix turned with the box serves every step; the motion is that of a matrix
    # assembled at every step (the box is nearly rigid: the turned matrix nearly exact).
    runs = {}
    for angle in (0.0, 0.03):
        mesh = cr.box((0.2, 0.1, 0.1), cells=(4, 2, 2))
        # ("ignore": the first step's linearisation stretches the spinning box, a physical jump)
        body = cr.Body(mesh, MAT)
        sim = cr.Simulation(body, dt=0.01, solver=cr.Direct(), matrix_reuse_angle=angle, on_failure="ignore")
        axis = np.array([1.0, 2.0, 2.0]) / 3.0
        sim.velocities[:] = np.cross(1.2 * axis, mesh.points - mesh.points.mean(axis=0))
        sim.step(52)
        runs[angle] = sim
    assert runs[0.03].stats["kept_matrix_steps"] == 50 and runs[0.0].stats["kept_matrix_steps"] == 0
    moved = np.abs(runs[0.0].displacements).max()
    assert moved > 0.05  # turned by 36 degrees
    np.testing.assert_allclose(runs[0.03].positions, runs[0.0].positions, rtol=0, atol=1e-4 * moved)  # 2.2e-5


def test_a_linear_body_keeps_its_matrix_for_good_and_moves_the_same():
    runs = {}
    for angle in (0.0, 0.05):
        mesh = cr.beam(2.0, 0.5, 0.5, cells=(8, 2, 2))
        body = cr.Body(mesh, MAT, model="linear")
        sim = cr.Simulation(body, dt=0.01, gravity=(0, 0, -9.81), solver=cr.Direct(), matrix_reuse_angle=angle)
        sim.fix(mesh.nodes_on_plane("x", 0.0))
        sim.step(30)
        runs[angle] = sim
    # (after the first step: a constant stiffness measures no turn)
    assert runs[0.05].stats["kept_matrix_steps"] == 29 and runs[0.0].stats["kept_matrix_steps"] == 0
    sag = np.abs(runs[0.0].displacements).max()
    np.testing.assert_allclose(runs[0.05].positions, runs[0.0].positions, rtol=0, atol=1e-9 * sag)


def test_what_else_the_matrix_holds_makes_the_next_step_assemble():
    mesh, sim = cantilever()
    tip = mesh.nearest_node((2.0, 0.25, 0.5))
    sim.step(4)
    assert sim.stats["kept_matrix"]
    sim.attach([tip], sim.positions[[tip]], [1e4])  # a new spring: its stiffness is in A
    sim.step(1)
    assert not sim.stats["kept_matrix"]
    sim.step(2)
    assert sim.stats["kept_matrix"]
    sim.move_attachments([tip], sim.positions[[tip]] + 0.01)  # the same spring elsewhere: A holds
    sim.step(1)
    assert sim.stats["kept_matrix"]
    sim.fix(np.concatenate([mesh.nodes_on_plane("x", 0.0), [tip]]))  # new fixed rows and columns
    sim.step(1)
    assert not sim.stats["kept_matrix"]
    sim.dt = 0.005  # another dt: another A
    sim.step(1)
    assert not sim.stats["kept_matrix"]


def test_a_body_on_the_floor_keeps_its_matrix_and_takes_its_contacts_anew():
    # The kept matrix goes without contact terms; each step adds its own. Resting on the floor,
    # then falling once the floor is gone: with the kept matrix as with one assembled every
    # step (a stale contact term would hold the bottom nodes back as the body falls).
    runs = {}
    for angle in (0.0, 0.03):
        mesh = cr.box((0.2, 0.2, 0.1), cells=(4, 4, 2))
        sim = cr.Simulation(cr.Body(mesh, MAT), dt=0.01, gravity=(0, 0, -9.81), matrix_reuse_angle=angle)
        floor = cr.Plane(point=(0, 0, -0.001))
        sim.add_obstacle(floor, friction=0.3)
        sim.step(30)
        resting, kept_resting = len(sim.contacts["nodes"]), sim.stats["kept_matrix_steps"]
        sim.remove_obstacle(floor)
        sim.step(10)
        runs[angle] = (sim, resting, kept_resting)
    (every, resting, _), (kept, resting_kept, kept_resting) = runs[0.0], runs[0.03]
    assert resting == resting_kept == 25 and kept_resting >= 20
    assert kept.stats["kept_matrix_steps"] >= kept_resting + 8
    assert kept.displacements[:, 2].max() < -0.04  # fell
    moved = np.abs(every.displacements).max()
    np.testing.assert_allclose(kept.positions, every.positions, rtol=0, atol=1e-4 * moved)


def test_a_body_thrown_up_from_the_floor_flies_with_the_kept_matrix_as_with_every_one_assembled():
    # Its contacts let go in the step it is thrown (released in a second pass) and are gone
    # in flight: the kept matrix must hold none of them.
    runs = {}
    for angle in (0.0, 0.03):
        mesh = cr.box((0.2, 0.2, 0.1), cells=(4, 4, 2))
        sim = cr.Simulation(cr.Body(mesh, MAT), dt=0.01, gravity=(0, 0, -9.81), matrix_reuse_angle=angle)
        sim.add_obstacle(cr.Plane(point=(0, 0, -0.001)), friction=0.3)
        sim.step(30)
        sim.velocities[:, 2] += 1.0
        sim.step(10)
        runs[angle] = sim
    every, kept = runs[0.0], runs[0.03]
    assert kept.stats["kept_matrix_steps"] >= 30 and len(kept.contacts["nodes"]) == 0
    assert kept.displacements[:, 2].min() > 0.04  # up, as 1 m/s carries it in 0.1 s
    moved = np.abs(every.displacements).max()
    np.testing.assert_allclose(kept.positions, every.positions, rtol=0, atol=1e-4 * moved)


@pytest.mark.parametrize("bad", [-0.1, 0.6, float("nan"), float("inf")])
def test_a_reuse_angle_out_of_range_is_refused(bad):
    body = cr.Body(cr.box(), MAT)
    with pytest.raises(ValueError, match=r"matrix_reuse_angle must be in \[0, 0.5\] rad"):
        cr.Simulation(body, matrix_reuse_angle=bad)


@pytest.mark.parametrize("bad", [True, "0.05", None])
def test_a_reuse_angle_must_be_a_real_number(bad):
    with pytest.raises(TypeError, match="matrix_reuse_angle must be a real number"):
        cr.Simulation(cr.Body(cr.box(), MAT), matrix_reuse_angle=bad)


def test_the_guides_state_the_default_angle_the_settings_hold():
    default = cr._core.IntegratorSettings().matrix_reuse_angle
    docs = Path(__file__).resolve().parents[2] / "docs"
    for page in ("guide/stepping-and-solvers.md", "theory/implicit-step.md"):
        assert f"`matrix_reuse_angle` (default {default:g} rad)" in (docs / page).read_text(), page
