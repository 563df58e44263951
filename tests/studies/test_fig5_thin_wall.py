"""Fig. 5 of the paper: the artificial growth of linear FEM under a large rotation, and its
absence in the co-rotational formulation (python -m studies.fig5_thin_wall)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import quad
from studies.fig5_thin_wall import main, thin_wall


def euler_bernoulli_growth(bending: float) -> float:
    """Relative length gain of the linear cantilever's deflection curve w = P x^2 (3L - x) / 6EI
    (L = 1, bending = P L^2 / EI): what linear FEM draws, as it moves points only vertically."""
    return quad(lambda x: np.sqrt(1 + (bending / 2 * (2 * x - x * x)) ** 2), 0, 1)[0] - 1


def test_linear_plate_grows_and_corotational_plate_keeps_its_length():
    result = thin_wall(out=None, cells=(12, 2), frames=4, bending=3.0)
    linear, corot = result.growth["linear"], result.growth["corotational"]
    # Linear FEM: the mid-line lengthens as Euler-Bernoulli's deflection curve does; a plate
    # 10x wider than thick is stiffer by up to 1 / (1 - nu^2) (plate bending), which bounds
    # the growth from below.
    upper, lower = euler_bernoulli_growth(3.0), euler_bernoulli_growth(3.0 * (1 - 0.3**2))
    assert lower - 0.005 < linear[-1] < upper + 0.005
    assert linear[-1] > 0.35
    # ... and the displacements grow in proportion to the load (a linear model).
    x0 = result.positions["linear"][0]
    np.testing.assert_allclose(
        result.positions["linear"][2] - x0, 0.5 * (result.positions["linear"][-1] - x0), rtol=0, atol=1e-8
    )
    # Co-rotational: the same load turns the tip by over 50 degrees and the mid-line keeps its
    # length (axial strain P / EA ~ 1e-5; what remains is the chord of the bent polyline).
    assert result.tip_rotation["corotational"] > 50
    assert np.all(np.abs(corot) < 1e-3)


def test_the_study_writes_both_series_its_numbers_and_a_picture(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    assert main(["--out", str(tmp_path), "--frames", "3"]) == 0
    for model in ("linear", "corotational"):
        assert (tmp_path / f"thinwall_{model}.pvd").read_text().count("<DataSet") == 4
    table = np.loadtxt(tmp_path / "thinwall.csv", delimiter=",", skiprows=1)
    assert table.shape == (4, 3)
    np.testing.assert_allclose(table[:, 0] / table[-1, 0], [0, 1 / 3, 2 / 3, 1])
    assert table[-1, 1] > 0.35 and abs(table[-1, 2]) < 1e-3  # linear grows, co-rotational does not
    assert (tmp_path / "thinwall.png").stat().st_size > 10_000
    assert "mid-line growth" in capsys.readouterr().out
