"""What every study shares: its command line (--out), where the armadillo lives, matplotlib
for files only, and the CSV/JSON writers. A study writes its numbers and its picture into one
output folder and prints what it wrote."""

from __future__ import annotations

import argparse
import csv
import json
import os
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

from corotate.picture import _pyplot

REPO = Path(__file__).resolve().parents[1]
# The armadillo is shared data beside the clone (../shared/data), never copied into the repository.
ARMADILLO = REPO.parent / "shared" / "data" / "armadillo_4k.vtu"


def parser(doc: str | None, out: str) -> argparse.ArgumentParser:
    """An argument parser whose description is the study's docstring, with --out (default `out`)."""
    p = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", default=out, help=f"output folder for the numbers and the picture (default: {out})")
    return p


def output_folder(path: str | os.PathLike[str]) -> Path:
    """The output folder, created if needed."""
    out = Path(path)
    out.mkdir(parents=True, exist_ok=True)
    return out


def mesh_file(p: argparse.ArgumentParser, path: str | os.PathLike[str]) -> Path:
    """`path` if it is a file; else the parser exits with a message saying where the mesh was looked for."""
    path = Path(path)
    if not path.is_file():
        p.error(
            f"the armadillo mesh is not at {path}: this study reads armadillo_4k.vtu from the shared data "
            f"beside the clone ({ARMADILLO}); pass its path with --data"
        )
    return path


def pyplot() -> Any:
    """matplotlib.pyplot drawing into files only (Agg); ImportError naming the extra without matplotlib."""
    return _pyplot()


def save_figure(fig: Any, path: Path, dpi: int = 110) -> Path:
    """Lay the figure out, write it as a PNG at path and close it."""
    fig.tight_layout()
    fig.savefig(path, dpi=dpi)
    pyplot().close(fig)
    return path


def write_csv(path: Path, header: Sequence[str], rows: Iterable[Sequence[Any]]) -> Path:
    """One header row, then the rows (floats written with 9 significant digits)."""
    with path.open("w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        for row in rows:
            w.writerow([f"{v:.9g}" if isinstance(v, float) else v for v in row])
    return path


def write_json(path: Path, data: Any) -> Path:
    path.write_text(json.dumps(data, indent=1) + "\n")
    return path
