"""Runs that go wrong without NaN say so: a stalled linear solve, inverted elements and a
run-away (energy growing while nothing drives the body) warn once, or raise with the state
restored under on_failure="raise"; healthy runs stay silent (pyproject.toml turns every
unexpected SimulationWarning in the test suite into an error)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import corotate as cr

MAT = cr.Material(E=1e7, nu=0.3, density=1000.0)


def beam_sim(solver, on_failure="warn", cells=(20, 4, 4)):
    mesh = cr.beam(5.0, 1.0, 1.0, cells=cells, element="tet4")
    sim = cr.Simulation(cr.Body(mesh, MAT), dt=0.01, gravity=(0, 0, -9.81), solver=solver, on_failure=on_failure)
    sim.fix(mesh.nodes_on_plane("x", 0.0))
    return mesh, sim


def snapshot(sim):
    return sim.positions.copy(), sim.velocities.copy(), sim.time, sim.stats["steps"]


def test_capped_warm_started_jacobi_runs_away_and_is_caught():
    # 6 warm-started Jacobi-PCG iterations per step: the tip swings plausibly, then the
    # motion grows without bound (1e36 m after 400 steps; 7 iterations stay bounded on this
    # mesh, 4 blow up at once). The checks see it long before the numbers become absurd:
    # a stalled solve (relative residual >= 1 at the cap) from about step 60, the energy
    # growing while nothing drives the body from about step 80.
    mesh, sim = beam_sim(cr.PCG(max_iterations=6, preconditioner="jacobi", tolerance=1e-10))
    tip = mesh.nodes_on_plane("x", 5.0)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", cr.SimulationWarning)
        for _ in range(15):
            sim.step(10)
            if sim.stats["energy_growth_steps"]:
                break
    messages = [str(w.message) for w in caught if issubclass(w.category, cr.SimulationWarning)]
    assert any("energy grew by more than 1 %" in m for m in messages), messages
    assert any("the linear solve stalled at its iteration cap" in m for m in messages), messages
    assert sim.stats["energy_growth_steps"] >= 1 and sim.stats["steps"] <= 150
    assert np.abs(sim.displacements[tip, 2]).max() < 5.0  # caught early: still a plausible state

    _, raising = beam_sim(cr.PCG(max_iterations=6, preconditioner="jacobi", tolerance=1e-10), on_failure="raise")
    with pytest.raises(RuntimeError, match=r"linear solve stalled|energy grew by .* while nothing drove the body"):
        for _ in range(300):
            before = snapshot(raising)
            raising.step(1)
    after = snapshot(raising)
    np.testing.assert_array_equal(after[0], before[0])
    np.testing.assert_array_equal(after[1], before[1])
    assert after[2:] == before[2:]


@pytest.mark.parametrize("solver", [cr.PCG(), cr.PCG(max_iterations=20, preconditioner="jacobi"), cr.Direct()])
def test_healthy_runs_stay_silent(solver):
    _, sim = beam_sim(solver, cells=(10, 2, 2))
    sim.step(300)  # a SimulationWarning would fail the test (pyproject.toml filterwarnings)
    assert sim.stats["energy_growth_steps"] == sim.stats["stalled_steps"] == sim.stats["inverted_steps"] == 0


def test_a_stalled_solve_warns_or_raises():
    _, sim = beam_sim(cr.PCG(max_iterations=2, preconditioner="jacobi", tolerance=1e-10))
    with pytest.warns(cr.SimulationWarning, match="stalled at its iteration cap"):
        sim.step(1)
    assert sim.stats["solver_stalled"] and sim.stats["residual"] >= 1
    _, raising = beam_sim(cr.PCG(max_iterations=2, preconditioner="jacobi", tolerance=1e-10), on_failure="raise")
    before = snapshot(raising)
    with pytest.raises(RuntimeError, match=r"stalled at its iteration cap \(relative residual"):
        raising.step(3)
    after = snapshot(raising)
    np.testing.assert_array_equal(after[0], before[0])
    assert after[2:] == before[2:]


def test_a_huge_load_that_inverts_elements_is_reported():
    mesh = cr.box((1, 1, 1), (3, 3, 3), "tet4")
    body = cr.Body(mesh, cr.Material(E=1e6, nu=0.3, density=1000.0))
    top = mesh.nearest_node((0.5, 0.5, 1.0))
    for policy in ("warn", "raise"):
        sim = cr.Simulation(body, dt=0.01, solver=cr.Direct(), on_failure=policy)
        sim.fix(mesh.nodes_on_plane("z", 0.0))
        sim.external_forces[top] = (0.0, 0.0, -1e9)
        if policy == "warn":
            with pytest.warns(cr.SimulationWarning) as record:
                sim.step(2)  # the first step inverts, the second starts from it
            assert any("inverted or flat elements" in str(w.message) for w in record)
            assert sim.stats["inverted_elements"] > 0
        else:
            before = snapshot(sim)
            with pytest.raises(RuntimeError, match="elements were inverted or flat"):
                sim.step(2)
            after = snapshot(sim)
            np.testing.assert_array_equal(after[0], before[0])
            assert after[2:] == before[2:]


def test_failure_policy_is_settable_and_checked():
    _, sim = beam_sim(cr.PCG(), cells=(2, 1, 1))
    assert sim.on_failure == "warn"
    sim.on_failure = "raise"
    assert sim.on_failure == "raise"
    with pytest.raises(ValueError, match="unknown failure policy 'sometimes'"):
        sim.on_failure = "sometimes"
    assert sim.on_failure == "raise"
