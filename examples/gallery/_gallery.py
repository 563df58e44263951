"""What the gallery's scripts share: their command line (--out, --small) and how a picture is
written. Pictures go to files only (matplotlib's Agg backend): no display is needed."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

import matplotlib.pyplot as plt

plt.switch_backend("Agg")


def arguments(doc: str | None) -> argparse.Namespace:
    """--out FOLDER (default: here) and --small (a coarse, short run, as the tests use)."""
    parser = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", default=".", help="folder for the picture (default: the current one)")
    parser.add_argument("--small", action="store_true", help="a coarse mesh and a short run (for the tests)")
    return parser.parse_args()


def save(fig: Any, out: str, name: str) -> Path:
    """Write the figure to OUT/<name>.png, close it and say so."""
    folder = Path(out)
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"{name}.png"
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)
    print(f"wrote {path}")
    return path
