"""corotate.set_threads: the core's parallel loops (element sweep, SpMV, smoother) on n
threads; validated, process-wide, and the answer does not depend on it (bit for bit)."""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest

import corotate as cr


@pytest.fixture
def restore_threads():
    before = cr.threads()
    yield
    cr.set_threads(before)


def sagging_beam(steps: int) -> tuple[np.ndarray, dict]:
    mesh = cr.beam(5.0, 1.0, 1.0, cells=(24, 4, 4), element="tet4")  # 2,304 tets, 625 nodes
    sim = cr.Simulation(cr.Body(mesh, cr.Material(E=1e7, nu=0.3, density=1000.0)), dt=0.01, gravity=(0, 0, -9.81))
    sim.fix(mesh.nodes_on_plane("x", 0.0))
    sim.step(steps)
    return sim.positions.copy(), dict(sim.stats)


def test_default_is_one_thread_and_bad_counts_are_refused(restore_threads):
    assert cr.threads() >= 1 and cr.available_threads() >= 1
    cr.set_threads(1)
    for bad, error in ((0, ValueError), (-2, ValueError), (1.5, TypeError), (True, TypeError), ("2", TypeError)):
        with pytest.raises(error, match="thread count"):
            cr.set_threads(bad)
        assert cr.threads() == 1
    cr.set_threads(np.int64(1))
    if not cr.have_openmp():
        with pytest.raises(ValueError, match="without OpenMP"):
            cr.set_threads(2)


def test_two_threads_repeat_one_thread_to_the_bit(restore_threads):
    if not cr.have_openmp():
        pytest.skip("the core was built without OpenMP: one thread only")
    cr.set_threads(1)
    one, stats_one = sagging_beam(15)
    cr.set_threads(2)
    assert cr.threads() == 2
    two, stats_two = sagging_beam(15)
    assert (one[:, 2] - one[:, 2].max()).min() < -1e-3  # the beam sagged
    np.testing.assert_array_equal(one, two)
    assert stats_one["iterations_per_step"] == stats_two["iterations_per_step"]


def _threads_in_a_new_process(value: str) -> subprocess.CompletedProcess:
    code = "import warnings; warnings.simplefilter('always'); import corotate as cr; print(cr.threads())"
    env = {**os.environ, "COROTATE_THREADS": value}
    return subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120)


def test_the_environment_variable_sets_the_count_at_import():
    run = _threads_in_a_new_process("2" if cr.have_openmp() else "1")
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == ("2" if cr.have_openmp() else "1")
    assert "COROTATE_THREADS" not in run.stderr


@pytest.mark.parametrize(
    "value, reason", [("two", "not an integer"), ("0", "at least 1"), ("-3", "at least 1"), ("1.5", "not an integer")]
)
def test_a_bad_environment_value_warns_and_keeps_one_thread(value, reason):
    run = _threads_in_a_new_process(value)
    assert run.returncode == 0, run.stderr  # the import does not fail over it
    assert run.stdout.strip() == "1"
    assert f"COROTATE_THREADS={value!r} ignored" in run.stderr and reason in run.stderr


@pytest.mark.parametrize("chosen", [None, "active"])
def test_openmp_threads_sleep_at_barriers_unless_the_user_chose(chosen):
    """OMP_WAIT_POLICY is PASSIVE when corotate's core loads, unless it was set: spinning
    threads take the cores a busy machine's other processes need (bench/contention.py).
    libgomp reads it as it loads, so the value must be in place before the core imports."""
    env = {k: v for k, v in os.environ.items() if k != "OMP_WAIT_POLICY"}
    if chosen:
        env["OMP_WAIT_POLICY"] = chosen
    code = (
        "import sys, os, corotate\n"
        "loaded = [m for m in sys.modules if m.startswith('corotate')]\n"
        "print(os.environ['OMP_WAIT_POLICY'], loaded.index('corotate._wait_policy') < loaded.index('corotate._core'))"
    )
    run = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split() == [chosen or "PASSIVE", "True"]
