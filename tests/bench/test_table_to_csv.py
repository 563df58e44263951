"""bench/table_to_csv.py turns the table corotate_bench prints into the CSV of bench/results/
(names with a space stay one cell; prose lines are dropped; no table is an error)."""

import csv
import io
import subprocess
import sys
from pathlib import Path

SCRIPT = Path(__file__).resolve().parents[2] / "bench" / "table_to_csv.py"
PRINTED = """scenario: corotational tets, E=1e7 nu=0.3 rho=1000, gravity -z, dt=0.01, 100 steps, 1 thread(s)
direct solver (config 'direct'): auto (auto: CHOLMOD from 4000 DOFs); two-level coarse solver: cholmod
mesh               elems config           precmp_ms  1st_step  ms/step stalled/growth
beam 10x2x2          240 reference              0.7       0.9    0.177 0/0
armadillo_4k.node   3717 default                7.5      21.0    3.580 0/1
"""


def run(text):
    return subprocess.run([sys.executable, str(SCRIPT)], input=text, capture_output=True, text=True, check=False)


def test_the_printed_table_becomes_csv():
    done = run(PRINTED)
    assert done.returncode == 0, done.stderr
    assert list(csv.reader(io.StringIO(done.stdout))) == [
        ["mesh", "elems", "config", "precmp_ms", "1st_step", "ms/step", "stalled/growth"],
        ["beam 10x2x2", "240", "reference", "0.7", "0.9", "0.177", "0/0"],
        ["armadillo_4k.node", "3717", "default", "7.5", "21.0", "3.580", "0/1"],
    ]


def test_the_results_files_have_one_cell_per_column():
    for path in (SCRIPT.parent / "results").glob("*.csv"):
        rows = list(csv.reader(path.read_text().splitlines()))
        assert len(rows) > 1 and {len(r) for r in rows} == {len(rows[0])}, path.name


def test_no_table_is_an_error():
    done = run("scenario: nothing was measured\n")
    assert done.returncode == 1
    assert "no benchmark table" in done.stderr
