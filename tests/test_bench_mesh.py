"""The C++ benchmark times the mesh a user gets: its beam is corotate.beam's, node for node
(both come from the core's one structured generator, meshes/structured_box.hpp)."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import corotate as cr
from corotate.mesh import SOLID_ELEMENTS

BENCH = Path(cr.__file__).parent / "bin" / "corotate_bench"


@pytest.mark.skipif(not BENCH.exists(), reason="the benchmark executable is installed by pip install . (not -e)")
@pytest.mark.parametrize("element", SOLID_ELEMENTS)
def test_the_benchmark_beam_is_the_beam_corotate_makes(element, tmp_path):
    out = tmp_path / "beam.txt"
    subprocess.run([str(BENCH), "--sizes", "1", "--element", element, "--write-mesh", str(out)], check=True)
    lines = out.read_text().split("\n")
    n, m, k = (int(v) for v in lines[0].split())
    points = np.loadtxt(lines[1 : 1 + n])
    cells = np.loadtxt(lines[1 + n : 1 + n + m], dtype=np.int64).reshape(m, k)
    beam = cr.beam(5.0, 1.0, 1.0, cells=(10, 2, 2), element=element)
    assert lines[1 + n + m] == beam.cell_type
    np.testing.assert_array_equal(points, beam.points)
    np.testing.assert_array_equal(cells, beam.cells)


@pytest.mark.skipif(not BENCH.exists(), reason="the benchmark executable is installed by pip install . (not -e)")
def test_the_benchmark_names_an_unknown_element():
    run = subprocess.run([str(BENCH), "--element", "tet5"], capture_output=True, text=True)
    assert run.returncode == 2
    assert "unknown element 'tet5'; choose one of 'tet4'" in run.stderr


@pytest.mark.skipif(not BENCH.exists(), reason="the benchmark executable is installed by pip install . (not -e)")
def test_the_benchmark_takes_any_mesh_read_mesh_reads(tmp_path):
    # The benchmark parses no mesh format of its own: `corotate bench --mesh` reads the file.
    source = tmp_path / "column.vtu"
    cr.write_mesh(source, cr.box((1.0, 1.0, 2.0), (1, 1, 2), "tet10"))
    out = tmp_path / "handed_over.txt"
    run = subprocess.run(
        [sys.executable, "-m", "corotate", "bench", "--", "--mesh", str(source), "--write-mesh", str(out)],
        capture_output=True,
        text=True,
    )
    assert run.returncode == 0, run.stderr
    lines = out.read_text().split("\n")
    n, m, k = (int(v) for v in lines[0].split())
    mesh = cr.read_mesh(source)
    np.testing.assert_array_equal(np.loadtxt(lines[1 : 1 + n]), mesh.points)
    np.testing.assert_array_equal(np.loadtxt(lines[1 + n : 1 + n + m], dtype=np.int64).reshape(m, k), mesh.cells)
    missing = subprocess.run(
        [sys.executable, "-m", "corotate", "bench", "--", "--mesh", str(tmp_path / "no.vtu")],
        capture_output=True,
        text=True,
    )
    assert missing.returncode == 2 and "no.vtu" in missing.stderr


@pytest.mark.skipif(not BENCH.exists(), reason="the benchmark executable is installed by pip install . (not -e)")
@pytest.mark.parametrize("policy, reported", [(None, "PASSIVE"), ("active", "active")])
def test_the_benchmark_s_threads_sleep_at_barriers_unless_told_otherwise(policy, reported):
    """As the Python package does at import: the executable sets OMP_WAIT_POLICY=PASSIVE
    (starting itself again, since OpenMP reads it as it loads) unless it was set."""
    import os

    env = {k: v for k, v in os.environ.items() if k != "OMP_WAIT_POLICY"}
    if policy is not None:
        env["OMP_WAIT_POLICY"] = policy
    run = subprocess.run([str(BENCH), "--sizes", "1", "--steps", "1"], capture_output=True, text=True, env=env)
    assert run.returncode == 0, run.stderr
    assert f"OMP_WAIT_POLICY={reported}" in run.stdout
