"""corotate.set_threads: the core's parallel loops (element sweep, SpMV, smoother) on n
threads; validated, process-wide, and the answer does not depend on it (bit for bit)."""

from __future__ import annotations

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
