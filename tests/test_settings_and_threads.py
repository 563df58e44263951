"""Settings take effect or refuse; reset(); step(n) takes integers only; ill-conditioned
materials are rejected; one call at a time per simulation (busy error from other threads);
Ctrl-C interrupts a long step(n) and restores the state."""

from __future__ import annotations

import math
import os
import signal
import threading
import time

import numpy as np
import pytest

import corotate as cr


def _body(cells=(6, 2, 2), **material):
    return cr.Body(
        cr.beam(3.0, 0.5, 0.5, cells=cells), cr.Material(**{"E": 1e6, "nu": 0.3, "density": 1000.0, **material})
    )


def _clamped(body, **kw):
    kw.setdefault("on_failure", "ignore")  # the capped solves below are deliberately poor
    sim = cr.Simulation(body, gravity=(0.0, 0.0, -9.81), **kw)
    sim.fix(body.mesh.points[:, 0] < 1e-9)
    return sim


# --- settings take effect or refuse ------------------------------------------------------
def test_assigning_a_solver_takes_effect():
    # (Every step assembles: which steps keep a matrix depends on the run's history.)
    body = _body()
    switched = _clamped(body, solver=cr.PCG(max_iterations=1, preconditioner="none"), matrix_reuse_angle=0.0)
    switched.step(2)
    switched.solver = cr.Direct()
    assert switched.solver == cr.Direct()
    reference = _clamped(body, solver=cr.PCG(max_iterations=1, preconditioner="none"), matrix_reuse_angle=0.0)
    reference.step(2)
    direct = _clamped(body, solver=cr.Direct(), matrix_reuse_angle=0.0)
    direct._sim.positions[:] = reference.positions  # same start, then direct solves
    direct._sim.velocities[:] = reference.velocities
    switched.step(3)
    direct.step(3)
    np.testing.assert_allclose(switched.positions, direct.positions, rtol=0, atol=1e-12)
    capped = _clamped(body, solver=cr.PCG(max_iterations=1, preconditioner="none"), matrix_reuse_angle=0.0)
    capped._sim.positions[:] = reference.positions
    capped._sim.velocities[:] = reference.velocities
    capped.step(3)
    assert np.abs(capped.positions - direct.positions).max() > 1e-8  # the switch mattered
    with pytest.raises(TypeError, match="solver must be"):
        switched.solver = "direct"  # type: ignore[assignment]
    assert switched.solver == cr.Direct()


def test_assigning_dt_takes_effect_and_is_validated():
    body = _body()
    sim = _clamped(body, dt=0.01)
    sim.dt = 0.005
    assert sim.dt == 0.005
    sim.step(4)
    assert sim.time == pytest.approx(0.02)
    fresh = _clamped(body, dt=0.005)
    fresh.step(4)
    np.testing.assert_allclose(sim.positions, fresh.positions, rtol=0, atol=1e-12)
    for bad in (0.0, -1.0, math.nan, math.inf):
        with pytest.raises(ValueError):
            sim.dt = bad
    assert sim.dt == 0.005


@pytest.mark.parametrize(
    ("name", "message"),
    [
        ("time", "read-only: it advances with step"),
        ("body", "read-only"),
        ("positions", r"sim.positions\[:\]"),
        ("stats", "read-only"),
        ("fixed_nodes", "fix"),
        ("sovler", "no attribute 'sovler'"),
    ],
)
def test_read_only_and_unknown_simulation_attributes_refuse(name, message):
    body = _body()
    for sim in (cr.Simulation(body), cr.ExplicitSimulation(body)):
        with pytest.raises(AttributeError, match=message):
            setattr(sim, name, 1.0)


def test_a_body_is_immutable():
    body = _body()
    for name, value in (("material", cr.Material(E=2e6)), ("mesh", body.mesh), ("model", "linear"), ("thickness", 1.0)):
        with pytest.raises(AttributeError, match="immutable"):
            setattr(body, name, value)
    with pytest.raises(AttributeError, match="no attribute"):
        body.materal = cr.Material()  # type: ignore[attr-defined]
    assert body.material == cr.Material() and body.model == "corotational"


def test_explicit_simulation_settings_still_settable():
    sim = cr.ExplicitSimulation(_body(), dt=1e-4)
    sim.dt = 2e-4
    sim.policy = "online"
    sim.on_failure = "raise"
    sim.gravity = (0.0, 0.0, -1.0)
    assert (sim.dt, sim.policy, sim.on_failure) == (2e-4, "online", "raise")
    np.testing.assert_array_equal(sim.gravity, (0.0, 0.0, -1.0))


# --- reset ----------------------------------------------------------------------------------
@pytest.mark.parametrize("kind", ["implicit", "newton", "explicit"])
def test_reset_goes_back_to_the_rest_state_and_repeats_a_fresh_run(kind):
    body = _body()

    def make():
        if kind == "explicit":
            sim = cr.ExplicitSimulation(body, dt=2e-4, gravity=(0.0, 0.0, -9.81))
        else:
            sim = cr.Simulation(
                body, gravity=(0.0, 0.0, -9.81), integrator="linearized" if kind == "implicit" else "newton"
            )
        sim.fix(body.mesh.points[:, 0] < 1e-9)
        return sim

    sim = make()
    sim.external_forces[-1] = (0.0, 0.0, -5.0)
    sim.step(6)
    assert sim.time > 0 and np.abs(sim.velocities).max() > 0
    fixed = sim.fixed_nodes.copy()
    sim.reset()
    np.testing.assert_array_equal(sim.positions, body.mesh.points)
    assert not sim.velocities.any() and not sim.external_forces.any() and not sim.accelerations.any()
    assert sim.time == 0.0 and sim.stats["steps"] == 0
    np.testing.assert_array_equal(sim.fixed_nodes, fixed)
    np.testing.assert_array_equal(sim.gravity, (0.0, 0.0, -9.81))
    sim.step(5)
    fresh = make()
    fresh.step(5)
    np.testing.assert_array_equal(sim.positions, fresh.positions)  # warm starts cleared too
    np.testing.assert_array_equal(sim.velocities, fresh.velocities)


# --- step(n) takes integers ----------------------------------------------------------------
@pytest.mark.parametrize("n", [2.7, 2.0, True, "3", np.float64(2.0), np.True_, None])
def test_step_count_must_be_an_integer(n):
    sim = cr.Simulation(_body(cells=(2, 1, 1)))
    with pytest.raises(TypeError, match="integer"):
        sim.step(n)
    assert sim.time == 0.0 and sim.stats["steps"] == 0


def test_numpy_integers_are_step_counts():
    sim = cr.ExplicitSimulation(_body(cells=(2, 1, 1)), dt=1e-4)
    sim.step(np.int64(2))
    sim.step(np.int32(1))
    assert sim.stats["steps"] == 3


# --- material validation ---------------------------------------------------------------------
@pytest.mark.parametrize(
    ("params", "message"),
    [
        ({"nu": math.nextafter(0.5, 0.0)}, "too close to 0.5: lambda/mu"),
        ({"nu": 0.49999999}, "lambda/mu"),
        ({"nu": math.nextafter(-1.0, 0.0)}, "too close to -1"),
        ({"E": 1e308}, "too large"),
        ({"E": 1e160}, "too large"),
        ({"E": math.inf}, "Young's modulus"),
        ({"nu": math.nan}, "Poisson ratio"),
        ({"density": math.nan}, "density"),
    ],
)
def test_ill_conditioned_or_overflowing_materials_are_rejected(params, message):
    with pytest.raises(ValueError, match=message):
        cr.Material(**params)


def test_nearly_incompressible_within_the_threshold_is_accepted():
    lam, mu = cr.Material(nu=0.499999).lame
    assert 4e5 < lam / mu < 1e6


# --- threads ---------------------------------------------------------------------------------
def _big_sim():
    body = cr.Body(cr.beam(4.0, 1.0, 1.0, cells=(40, 10, 5)), cr.Material(E=1e6, nu=0.3, density=1000.0))
    assert body.mesh.n_cells >= 10_000  # 12,000 tets
    sim = cr.Simulation(body, dt=0.01, gravity=(0.0, 0.0, -9.81))
    sim.fix(body.mesh.points[:, 0] < 1e-9)
    return sim


def test_calls_from_another_thread_during_a_step_raise_busy_or_succeed():
    sim = _big_sim()
    left = np.flatnonzero(sim.body.mesh.points[:, 0] < 1e-9)
    outcomes = {"ok": 0, "busy": 0}
    errors: list[BaseException] = []
    stop = threading.Event()

    def stepper():
        try:
            taken = 0
            while taken < 8:
                try:
                    sim.step(3)
                    taken += 1
                except RuntimeError as e:  # a hammer call held the simulation first: refused whole
                    if "the simulation is busy: step called" not in str(e):
                        raise
        except BaseException as e:
            errors.append(e)
        finally:
            stop.set()

    def hammer():
        k = 0
        while not stop.is_set():
            k += 1
            try:
                if k % 2:
                    sim.fix(left)
                else:
                    sim.gravity = (0.0, 0.0, -9.81 - 1e-3 * (k % 7))
                outcomes["ok"] += 1
            except RuntimeError as e:
                assert "the simulation is busy" in str(e) and "from another thread while a step runs" in str(e)
                outcomes["busy"] += 1

    threads = [threading.Thread(target=stepper), threading.Thread(target=hammer)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(timeout=120)
    assert not errors, errors
    assert outcomes["busy"] > 0  # the guard was hit: the calls did not race the steps
    assert sim.stats["steps"] == 24
    assert np.isfinite(sim.positions).all() and np.isfinite(sim.velocities).all()
    np.testing.assert_array_equal(sim.fixed_nodes, left)
    assert sim.positions[:, 2].min() < 0.0  # it sagged


def test_a_second_concurrent_step_raises_busy():
    sim = _big_sim()
    inside, tried = threading.Event(), threading.Event()
    result: list[BaseException | None] = []

    def hold_after_the_first_step(done: int, n: int) -> None:
        if done == 1:  # the worker is inside its call: a step from another thread now races it
            inside.set()
            assert tried.wait(60)

    def long_step():
        try:
            sim.step(3, progress=hold_after_the_first_step)
            result.append(None)
        except BaseException as e:
            result.append(e)

    t = threading.Thread(target=long_step)
    t.start()
    assert inside.wait(60)
    try:
        with pytest.raises(RuntimeError, match="the simulation is busy: step called from another thread"):
            sim.step(1)
    finally:
        tried.set()
    t.join()
    assert result == [None]
    assert sim.stats["steps"] == 3  # the refused call took no step


# --- progress ---------------------------------------------------------------------------------
def _small_sims():
    body = cr.Body(cr.beam(1.0, 0.2, 0.2, cells=(5, 1, 1)), cr.Material(E=1e6, nu=0.3, density=1000.0))
    implicit = cr.Simulation(body, dt=0.01, gravity=(0.0, 0.0, -9.81))
    explicit = cr.ExplicitSimulation(body, dt=1e-4, gravity=(0.0, 0.0, -9.81))
    for sim in (implicit, explicit):
        sim.fix(body.mesh.points[:, 0] < 1e-9)
    return implicit, explicit


@pytest.mark.parametrize("which", [0, 1], ids=["implicit", "explicit"])
def test_progress_reports_every_step_including_the_last(which):
    sim = _small_sims()[which]
    calls: list[tuple[int, int]] = []
    sim.step(4, progress=lambda done, n: calls.append((done, n)))
    assert calls == [(1, 4), (2, 4), (3, 4), (4, 4)]
    assert sim.stats["steps"] == 4


@pytest.mark.parametrize("which", [0, 1], ids=["implicit", "explicit"])
@pytest.mark.parametrize("steps,fail_at", [(5, 3), (1, 1)], ids=["third of five", "after a single step"])
def test_an_error_in_the_progress_callback_fails_the_call_and_restores_the_state(which, steps, fail_at):
    # (after a single step: the step has committed, only the callback can still fail)
    sim = _small_sims()[which]
    sim.step(2)
    before = (sim.positions.copy(), sim.velocities.copy(), sim.accelerations.copy(), sim.time)

    def fail(done, n):
        if done == fail_at:
            raise ValueError("stop here")

    with pytest.raises(ValueError, match="stop here"):
        sim.step(steps, progress=fail)
    np.testing.assert_array_equal(sim.positions, before[0])
    np.testing.assert_array_equal(sim.velocities, before[1])
    np.testing.assert_array_equal(sim.accelerations, before[2])
    assert (sim.time, sim.stats["steps"]) == (before[3], 2)


def test_solve_static_reports_each_load_step_and_an_error_in_it_restores_the_state():
    sim = _small_sims()[0]
    calls: list[tuple[int, int]] = []
    sim.solve_static(load_steps=3, progress=lambda done, n: calls.append((done, n)))
    assert calls == [(1, 3), (2, 3), (3, 3)]
    settled = sim.positions.copy()
    sim.gravity = (0.0, 0.0, -2 * 9.81)

    def stop_at_two(done, n):
        if done == 2:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        sim.solve_static(load_steps=3, progress=stop_at_two)
    np.testing.assert_array_equal(sim.positions, settled)
    with pytest.raises(TypeError, match="progress must be a callable"):
        sim.solve_static(progress="yes")  # type: ignore[arg-type]


def test_the_progress_callback_cannot_reenter_the_simulation():
    sim = _small_sims()[0]
    with pytest.raises(RuntimeError, match=r"the simulation is busy: .*progress callback"):
        sim.step(2, progress=lambda done, n: sim.positions.sum() + sim.stats["steps"])
    assert sim.stats["steps"] == 0


def test_a_progress_that_is_not_callable_is_refused_before_any_step():
    sim = _small_sims()[0]
    with pytest.raises(TypeError, match="progress must be a callable"):
        sim.step(2, progress=5)  # type: ignore[arg-type]
    assert sim.stats["steps"] == 0


# --- Ctrl-C ----------------------------------------------------------------------------------
@pytest.mark.skipif(threading.current_thread() is not threading.main_thread(), reason="signals need the main thread")
def test_ctrl_c_interrupts_a_long_step_and_restores_the_state():
    sim = _big_sim()
    sim.step(1)
    before = (sim.positions.copy(), sim.velocities.copy(), sim.time, sim.stats["steps"])
    stepping = threading.Event()

    def interrupt_once_stepping():
        assert stepping.wait(30)
        time.sleep(0.05)  # a few steps in
        os.kill(os.getpid(), signal.SIGINT)

    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        sender = threading.Thread(target=interrupt_once_stepping)
        sender.start()
        t0 = time.monotonic()
        with pytest.raises(KeyboardInterrupt):
            sim.step(100_000, progress=lambda done, n: stepping.set())  # minutes if not interrupted
            time.sleep(5)  # not reached; the interrupt must not land after the call
        elapsed = time.monotonic() - t0
        sender.join()
    finally:
        signal.signal(signal.SIGINT, previous)
    assert elapsed < 20
    np.testing.assert_array_equal(sim.positions, before[0])
    np.testing.assert_array_equal(sim.velocities, before[1])
    assert (sim.time, sim.stats["steps"]) == before[2:]
    sim.step(1)  # still usable: the call released the simulation
    assert sim.stats["steps"] == before[3] + 1
