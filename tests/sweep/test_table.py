"""The parameter table: designs, and every bad entry named before a sweep starts."""

import math

import numpy as np
import pytest

from corotate.sweep import ParameterTable


def test_grid_is_every_combination_last_parameter_fastest():
    table = ParameterTable.grid(E=[1e6, 2e6], nu=[0.3, 0.4, 0.45])
    assert len(table) == 6 and table.names == ["E", "nu"]
    assert [table.row(i) for i in (0, 1, 3, 5)] == [
        {"E": 1e6, "nu": 0.3},
        {"E": 1e6, "nu": 0.4},
        {"E": 2e6, "nu": 0.3},
        {"E": 2e6, "nu": 0.45},
    ]
    assert table.columns["E"].dtype == np.float64


def test_a_list_of_runs_keeps_its_order_and_kinds():
    table = ParameterTable.from_runs([{"model": "linear", "cells": 2}, {"model": "corotational", "cells": 3}])
    assert table.row(1) == {"model": "corotational", "cells": 3}
    assert type(table.row(1)["cells"]) is int and table.columns["cells"].dtype == np.int64
    assert table.columns["model"].dtype.kind == "U"


def test_latin_hypercube_puts_one_sample_in_each_stratum():
    n = 50
    table = ParameterTable.latin_hypercube(n, {"E": (1e5, 1e7), "load": (0.0, 10.0)}, seed=3, log=["E"])
    load = table.columns["load"]
    log_E = np.log(table.columns["E"])
    # each of the n equal strata of each range holds exactly one sample
    assert sorted((load // (10.0 / n)).astype(int)) == list(range(n))
    strata = np.floor((log_E - math.log(1e5)) / ((math.log(1e7) - math.log(1e5)) / n)).astype(int)
    assert sorted(strata) == list(range(n))
    again = ParameterTable.latin_hypercube(n, {"E": (1e5, 1e7), "load": (0.0, 10.0)}, seed=3, log=["E"])
    assert again == table and again.fingerprint() == table.fingerprint()
    other = ParameterTable.latin_hypercube(n, {"E": (1e5, 1e7), "load": (0.0, 10.0)}, seed=4, log=["E"])
    assert other != table


@pytest.mark.parametrize(
    "columns, message",
    [
        ({"E": [1e6, float("nan")]}, "parameter 'E' is nan in run 1"),
        ({"E": [1e6, float("inf")]}, "parameter 'E' is inf in run 1"),
        ({"E": [1e6, None]}, "parameter 'E' is missing in run 1"),
        ({"E": [1e6, 2e6], "nu": [0.3]}, "differ in length"),
        ({"E": [1e6, "soft"]}, "mixes numbers and strings"),
        ({"E": [[1e6]]}, "values must be numbers or strings"),
        ({"not a name": [1.0]}, "Python identifiers"),
        ({}, "at least one parameter"),
        ({"E": []}, "no runs"),
    ],
)
def test_bad_tables_are_named(columns, message):
    with pytest.raises(ValueError, match=message):
        ParameterTable(columns)


def test_a_run_lacking_a_parameter_is_named():
    with pytest.raises(ValueError, match=r"run 2 of the parameter table lacks \['nu'\]"):
        ParameterTable.from_runs([{"E": 1.0, "nu": 0.3}, {"E": 2.0, "nu": 0.3}, {"E": 3.0}])
    with pytest.raises(ValueError, match=r"run 1 of the parameter table has parameters \['rho'\]"):
        ParameterTable.from_runs([{"E": 1.0}, {"E": 2.0, "rho": 3.0}])


def test_bad_designs_are_named():
    with pytest.raises(ValueError, match="'E' is sampled in log scale"):
        ParameterTable.latin_hypercube(4, {"E": (0.0, 1.0)}, log=["E"])
    with pytest.raises(ValueError, match="low < high"):
        ParameterTable.latin_hypercube(4, {"E": (2.0, 1.0)})
    with pytest.raises(ValueError, match="n >= 1"):
        ParameterTable.latin_hypercube(0, {"E": (1.0, 2.0)})
    with pytest.raises(ValueError, match="'nu' has no values"):
        ParameterTable.grid(E=[1.0], nu=[])
    with pytest.raises(TypeError, match="must be a ParameterTable"):
        ParameterTable.coerce(3.0)


def test_the_fingerprint_sees_every_value_and_kind():
    base = ParameterTable({"E": [1e6, 2e6]})
    assert ParameterTable({"E": [1e6, 2e6]}).fingerprint() == base.fingerprint()
    assert ParameterTable({"E": [1e6, 2e6 * (1 + 2**-52)]}).fingerprint() != base.fingerprint()
    assert ParameterTable({"E": [1, 2]}).fingerprint() != ParameterTable({"E": [1.0, 2.0]}).fingerprint()
    assert ParameterTable({"F": [1e6, 2e6]}).fingerprint() != base.fingerprint()
