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
    assert capsys.readouterr().out == f"corotate {version}\n"
    assert cr.__version__ == version


def test_a_command_is_required(capsys):
    with pytest.raises(SystemExit) as done:
        cli.main([])
    assert done.value.code == 2
    assert "--version" in capsys.readouterr().err
