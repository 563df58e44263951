"""Every script of examples/gallery/ runs (small, with --small) and makes its picture, and the
gallery page shows each of them."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCRIPTS = sorted(p for p in (ROOT / "examples" / "gallery").glob("*.py") if not p.name.startswith("_"))


def test_the_gallery_page_shows_every_script():
    page = (ROOT / "docs" / "gallery" / "index.md").read_text()
    assert SCRIPTS
    for script in SCRIPTS:
        assert f"examples/gallery/{script.name}" in page, script.name
        assert f"_generated/gallery/{script.stem}/{script.stem}.png" in page, script.name


@pytest.mark.parametrize("script", SCRIPTS, ids=[s.stem for s in SCRIPTS])
def test_a_gallery_script_runs_and_makes_its_picture(script, tmp_path):
    pytest.importorskip("matplotlib")
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in sys.path if p), MPLBACKEND="Agg")
    done = subprocess.run(
        [sys.executable, str(script), "--out", str(tmp_path), "--small"],
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    picture = tmp_path / f"{script.stem}.png"
    assert picture.stat().st_size > 10_000
    assert f"wrote {picture}" in done.stdout
    assert "Warning" not in done.stderr, done.stderr
