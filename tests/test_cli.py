"""The command line's own options (the demo and scenes commands are tested with what they run)."""

from pathlib import Path

import pytest

import corotate as cr
from corotate import cli


def test_version_prints_the_version_file(capsys):
    with pytest.raises(SystemExit) as done:
        cli.main(["--version"])
    assert done.value.code == 0
    version = (Path(__file__).resolve().parents[1] / "VERSION").read_text().split()[0]
    assert capsys.readouterr().out.startswith(f"corotate {version}: CHOLMOD ")  # and the backends (test_build_info)
    assert cr.__version__ == version


def test_a_command_is_required(capsys):
    with pytest.raises(SystemExit) as done:
        cli.main([])
    assert done.value.code == 2
    assert "--version" in capsys.readouterr().err


def test_demo_gravity_and_damping_take_effect(tmp_path, capsys):
    """No gravity: nothing moves. Gravity along +y: the free end hardly moves along z. Damping:
    the fall is slower over the same time."""
    from corotate.cli import main

    base = ["demo", "--frames", "3", "--steps-per-frame", "5", "--cells", "1", "--out", str(tmp_path), "--no-picture"]

    def far_end(extra):
        assert main([*base, *extra]) == 0
        out = capsys.readouterr().out
        return float(out.split("far-end mean displacement z:")[1].split()[0]), out

    z, out = far_end(["--gravity", "0", "0", "0"])
    assert z == 0.0 and "gravity (0.0, 0.0, 0.0)" in out
    z_sideways, out = far_end(["--gravity", "0", "9.81", "0"])
    assert "gravity (0.0, 9.81, 0.0)" in out
    z_undamped, _ = far_end(["--damping", "0"])
    # sideways gravity moves the end sideways; along z only by mesh asymmetry
    assert abs(z_sideways) < 0.05 * abs(z_undamped)
    z_damped, out = far_end(["--damping", "50"])
    assert "damping 50.0 1/s" in out
    assert z_undamped < 0 and z_undamped < z_damped < 0  # heavily damped: falls more slowly


def test_demo_writes_a_picture_unless_told_not_to(tmp_path, capsys):
    pytest.importorskip("matplotlib", reason="the picture needs the plot extra (matplotlib)")
    from corotate.cli import main

    base = ["demo", "--frames", "2", "--steps-per-frame", "1", "--cells", "1"]
    assert main([*base, "--out", str(tmp_path / "a")]) == 0
    assert (tmp_path / "a" / "demo.png").stat().st_size > 10_000
    assert "demo.png (the surface at 3 instants)" in capsys.readouterr().out
    assert main([*base, "--out", str(tmp_path / "b"), "--no-picture"]) == 0
    assert not (tmp_path / "b" / "demo.png").exists()
