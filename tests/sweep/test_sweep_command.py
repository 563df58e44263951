"""`corotate sweep SPEC`: its help, its spec file, its errors; and `import corotate` stays free of Dask."""

import subprocess
import sys
import textwrap

import numpy as np
import pytest

from corotate import cli

SPEC = """
import corotate as cr
from corotate.sweep.scenes import cantilever

table = cr.ParameterTable.grid(E=[3e5, 6e5], nu=[0.3], tip_load=[-2.0, 2.0])
out = "results/cantilever.zarr"


def scene(E, nu, tip_load):
    return cantilever(E, nu, tip_load, frames=2)
"""


def test_help_names_the_spec_and_the_options(capsys):
    with pytest.raises(SystemExit) as done:
        cli.main(["sweep", "--help"])
    assert done.value.code == 0
    text = " ".join(capsys.readouterr().out.split())
    for words in ("SPEC", "defines scene", "table", "--scheduler", "--workers", "--threads-per-run", "--runs-per-task"):
        assert words in text


def test_a_spec_runs_into_its_folder_and_again_computes_nothing(tmp_path, capsys, client):
    pytest.importorskip("xarray", reason="the extra [sweep]")
    import corotate as cr
    from corotate.sweep.scenes import cantilever

    spec = tmp_path / "beam_sweep.py"
    spec.write_text(SPEC)
    address = client.scheduler.address
    assert cli.main(["sweep", str(spec), "--scheduler", address, "--no-progress"]) == 0
    out = capsys.readouterr().out
    assert f"4 runs in {tmp_path / 'results' / 'cantilever.zarr'}: 4 done, 0 failed" in out
    assert "found 0 finished, computed 4" in out
    ds = cr.open_sweep(tmp_path / "results" / "cantilever.zarr")
    for run, row in enumerate([(3e5, 0.3, -2.0), (3e5, 0.3, 2.0), (6e5, 0.3, -2.0), (6e5, 0.3, 2.0)]):
        assert np.array_equal(ds.tip.values[run], cantilever(*row, frames=2)["tip"][1])
    assert cli.main(["sweep", str(spec), "--scheduler", address, "--no-progress"]) == 0
    assert "found 4 finished, computed 0" in capsys.readouterr().out


@pytest.mark.parametrize(
    "text, message",
    [
        ("table = {'E': [1.0]}\n", "must define scene"),
        ("def scene(E):\n    return {}\n", "must define table"),
        ("def scene(E):\n    return {}\ntable = {'E': [1.0, float('nan')]}\n", "parameter 'E' is nan in run 1"),
    ],
)
def test_a_bad_spec_is_named(tmp_path, capsys, text, message):
    spec = tmp_path / "spec.py"
    spec.write_text(text)
    assert cli.main(["sweep", str(spec)]) == 2
    assert message in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["spec.py"]


def test_a_missing_spec_and_an_unreachable_scheduler_are_named(tmp_path, capsys):
    assert cli.main(["sweep", str(tmp_path / "nothing.py")]) == 2
    assert "no sweep spec file" in capsys.readouterr().err
    spec = tmp_path / "spec.py"
    spec.write_text(SPEC)
    args = ["sweep", str(spec), "--scheduler", "tcp://127.0.0.1:9", "--connect-timeout", "0.5"]
    assert cli.main(args) == 2
    assert "cannot reach the Dask scheduler at tcp://127.0.0.1:9" in capsys.readouterr().err
    assert not (tmp_path / "results").exists()


def test_importing_corotate_imports_no_dask_zarr_or_xarray():
    code = textwrap.dedent(
        """
        import sys
        import corotate
        import corotate.sweep
        corotate.ParameterTable.grid(E=[1.0, 2.0])
        print(sorted(m for m in ("dask", "distributed", "zarr", "xarray") if m in sys.modules))
        """
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "[]"
