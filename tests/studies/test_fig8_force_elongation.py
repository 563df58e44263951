"""The paper's Fig. 8 and a bending counterpart on a coarse mesh: with the body simulated
co-rotationally, the averaged-stiffness feedback (eq. 5) is close to the full nonlinear
(StVK) reaction where the plain co-rotational one is far off."""

from __future__ import annotations

import numpy as np
import pytest
from studies.fig8_force_elongation import CURVES, force_curves, main


def distance(result, curve):
    return np.max(np.abs(result[curve] - result["stvk"])) / np.max(np.abs(result["stvk"]))


def test_pulled_end_fig8():
    r = force_curves("pull", cells=(10, 2, 2), levels=5)
    # Pure stretch: no rotation, so the co-rotational reaction is the linear one...
    np.testing.assert_allclose(r["corotational"], r["linear"], rtol=2e-2)
    # ...and misses StVK's stiffening (a factor of about 3 at double length),
    assert distance(r, "corotational") > 0.6
    # which the averaged stiffness recovers from the co-rotational configuration, up to the
    # lateral contraction that this configuration has from the linear law.
    assert distance(r, "averaged") < 0.1
    assert np.all(np.diff(r["averaged"]) > 0)


def test_bent_end():
    r = force_curves("bend", cells=(10, 2, 2), levels=5)
    assert distance(r, "linear") > 0.5  # no geometric stiffening at all
    assert distance(r, "corotational") > 0.1
    assert distance(r, "averaged") < 0.05
    assert distance(r, "averaged") < distance(r, "corotational") / 3


def test_the_study_writes_both_tables_and_the_picture(tmp_path):
    pytest.importorskip("matplotlib")
    assert main(["--out", str(tmp_path), "--cells", "5", "1", "1", "--levels", "2"]) == 0
    for case, full in (("pull", 5.0), ("bend", 2.0)):
        table = np.loadtxt(tmp_path / f"{case}.csv", delimiter=",", skiprows=1)
        assert table.shape == (2, 1 + len(CURVES))
        np.testing.assert_allclose(table[:, 0], [full / 2, full])
        np.testing.assert_allclose(table[1, 1], 2 * table[0, 1], rtol=1e-6)  # the linear reaction
    assert (tmp_path / "force_elongation.png").stat().st_size > 10_000
