"""The paper's steel block (section 2.2.1): linear, co-rotational and full nonlinear (StVK)
answers agree at small load; at the full load the co-rotational one is the closer to the
full nonlinear one."""

import numpy as np
import pytest
from studies.fig4_steel_block import main, steel_block, write_table


@pytest.fixture(scope="module")
def curves():
    return steel_block(fractions=[0.01, 0.1, 1.0])


def test_all_three_agree_at_one_percent_of_the_load(curves):
    ref = curves["stvk"][0]
    for model in ("linear", "corotational"):
        assert np.linalg.norm(curves[model][0] - ref) < 0.01 * np.linalg.norm(ref), model


def test_corotational_is_closer_to_full_nonlinear_than_linear_at_full_load(curves):
    full = curves["stvk"][-1]
    lin, cor = curves["linear"][-1], curves["corotational"][-1]
    for axis in range(3):
        assert abs(cor[axis] - full[axis]) < abs(lin[axis] - full[axis]), axis
    # and the effect is real: the linear answer is several percent off at full load
    assert np.linalg.norm(lin - full) > 0.05 * np.linalg.norm(full)
    # The corner moves outwards and down, symmetrically in x and y (the mesh is symmetric).
    assert full[2] < 0 < full[0]
    assert full[0] == pytest.approx(full[1], rel=1e-9)


def test_linear_curve_is_linear_and_csv_round_trips(curves, tmp_path):
    lin = curves["linear"]
    np.testing.assert_allclose(lin[1], 10 * lin[0], rtol=1e-9)
    np.testing.assert_allclose(lin[2], 100 * lin[0], rtol=1e-9)
    path = write_table(curves, tmp_path / "block.csv")
    table = np.loadtxt(path, delimiter=",", skiprows=1)
    np.testing.assert_allclose(table[:, 0], curves["load"])
    np.testing.assert_allclose(table[:, 7:10], curves["stvk"], rtol=1e-8)


def test_the_study_writes_its_table_and_picture(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    assert main(["--out", str(tmp_path), "--cells", "3", "3", "1", "--levels", "2"]) == 0
    table = np.loadtxt(tmp_path / "steel_block.csv", delimiter=",", skiprows=1)
    np.testing.assert_allclose(table[:, 0], [0.65e10, 1.3e10])
    # linear: the second level's displacement is twice the first's
    np.testing.assert_allclose(table[1, 1:4], 2 * table[0, 1:4], rtol=1e-9)
    assert (tmp_path / "steel_block.png").stat().st_size > 10_000
    assert "54 tets" in capsys.readouterr().out
