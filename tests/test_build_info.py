"""The build says what it has: backends and the instruction set of its hot loops."""

import subprocess
import sys

import corotate as cr
import corotate._core as _core


def test_build_info_reports_the_backends_the_core_uses():
    info = cr.build_info()
    assert info["version"] == cr.__version__
    assert info["openmp"] == cr.have_openmp()
    # CHOLMOD is reported as the direct solver's own backend choice sees it.
    assert isinstance(info["cholmod"], bool)
    assert info["instruction_set"] in ("x86-64-v4 (AVX-512)", "x86-64-v3 (AVX2, FMA)", "baseline")
    if not info["cpu_clones"]:
        assert info["instruction_set"] == "baseline"
    assert set(info) == {"version", "cholmod", "openmp", "cpu_clones", "instruction_set"}
    assert dict(_core.build_info())["openmp"] == info["openmp"]


def test_version_names_the_backends():
    out = subprocess.run([sys.executable, "-m", "corotate", "--version"], capture_output=True, text=True, check=True)
    line = out.stdout.strip()
    assert line.startswith(f"corotate {cr.__version__}: CHOLMOD ")
    assert cr.build_info()["instruction_set"] in line
