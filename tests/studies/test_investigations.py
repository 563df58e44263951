"""The two investigations behind the solver's defaults, run small: the warm-start run-away
(studies/warm_start_runaway.py) and the tolerance per preconditioner
(studies/tolerance_per_preconditioner.py)."""

import numpy as np
import pytest
from studies import tolerance_per_preconditioner, warm_start_runaway


def test_warm_start_is_neutral_at_half_the_error_left_and_cold_start_always_stable(tmp_path):
    pytest.importorskip("matplotlib")
    assert warm_start_runaway.main(["--out", str(tmp_path), "--sizes", "1"]) == 0
    table = np.loadtxt(tmp_path / "spectral_radius.csv", delimiter=",", skiprows=1)
    _, q, cold, warm = table.T
    half = np.isclose(q, 0.5)
    assert half.sum() == len(warm_start_runaway.MODES)
    np.testing.assert_allclose(warm[half], 1.0, atol=1e-9)  # exactly neutral, for every mode
    assert np.all(warm[q > 0.55] > 1.0) and np.all(warm[(q > 0) & (q < 0.45)] < 1.0)
    assert np.all(cold < 1.0)
    tets, kappa, bound = np.loadtxt(tmp_path / "jacobi_condition.csv", delimiter=",", skiprows=1)
    assert tets == 240 and kappa > 1
    # The Chebyshev bound of 20 iterations, recomputed from kappa.
    assert bound == pytest.approx(1 / np.cosh(20 * np.arccosh((kappa + 1) / (kappa - 1))), rel=1e-8)
    assert (tmp_path / "spectral_radius.png").stat().st_size > 10_000


def test_default_tolerances_stay_within_one_percent_of_a_direct_solve(tmp_path):
    pytest.importorskip("matplotlib")
    argv = ["--out", str(tmp_path), "--steps", "20", "--tolerances", "1e-2"]
    assert tolerance_per_preconditioner.main(argv) == 0
    with (tmp_path / "tolerance.csv").open() as f:
        rows = [line.strip().split(",") for line in f][1:]
    assert [r[0] for r in rows] == ["two_level", "reference_factor"]
    for _, tolerance, deviation, iterations in rows:
        assert float(tolerance) == 1e-2
        assert 0 < float(deviation) < 1.0
        assert 1 <= float(iterations) <= 20
    assert (tmp_path / "tolerance.png").stat().st_size > 10_000
