"""Sphinx glue for corotate's site.

- The gallery: every script in examples/gallery/ runs before the pages are read and writes its
  picture into docs/_generated/gallery/<script>/ (rerun only when the script is newer than its
  picture), so the gallery page shows what the scripts make today.
- The command line: the help of ``corotate`` and each subcommand, written to
  docs/_generated/cli/<command>.txt for the CLI page to include.
- The guide's optional pages: docs/guide/sweeps.md joins the guide's toctree when it exists.
- Docstrings: the library's docstrings are plain text in the libigl manner (aligned
  "name  description" rows with the shapes of arrays). A paragraph that is not clean
  reStructuredText, or whose rows are aligned in columns, is shown as a plain-text block, as
  it reads in the source; clean prose stays prose.
"""

from __future__ import annotations

import io
import os
import re
import subprocess
import sys
from pathlib import Path
from typing import Any

from docutils.core import publish_doctree

DOCS = Path(__file__).resolve().parents[1]
REPO = DOCS.parent
GENERATED = DOCS / "_generated"
GALLERY = REPO / "examples" / "gallery"
OPTIONAL_GUIDE_PAGES = ("sweeps",)  # docs/guide/sweeps.md: the sweep guide, from the sweeps branch
GUIDE_LAST = "errors-and-threads"  # the last entry of docs/guide/index.md's toctree
ALIGNED = re.compile(r"\S {2,}\S")  # a run of spaces inside a line: aligned columns
UNDERLINE = re.compile(r"^([-=~^])\1{2,}\s*$")  # a numpy-style section's underline


def gallery_scripts() -> list[Path]:
    return sorted(p for p in GALLERY.glob("*.py") if not p.name.startswith("_"))


def run_gallery(_app: Any = None) -> None:
    """Run each gallery script into _generated/gallery/<name>/ unless its output is newer."""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in sys.path if p), MPLBACKEND="Agg")
    for script in gallery_scripts():
        out = GENERATED / "gallery" / script.stem
        pictures = list(out.glob("*.png"))
        if pictures and min(p.stat().st_mtime for p in pictures) > script.stat().st_mtime:
            continue
        out.mkdir(parents=True, exist_ok=True)
        done = subprocess.run(  # in its output folder: what it prints names its files as a user's run would
            [sys.executable, str(script), "--out", "."], cwd=out, env=env, capture_output=True, text=True, check=False
        )
        if done.returncode != 0:
            raise RuntimeError(f"gallery script {script.name} failed:\n{done.stdout}\n{done.stderr}")
        (out / "output.txt").write_text(done.stdout)


def write_cli_help(_app: Any = None) -> None:
    """docs/_generated/cli/<command>.txt: what ``corotate [command] --help`` prints."""
    from corotate.cli import build_parser

    parser = build_parser()
    out = GENERATED / "cli"
    out.mkdir(parents=True, exist_ok=True)
    os.environ["COLUMNS"] = "100"  # argparse wraps at the terminal's width: the same on every machine
    (out / "corotate.txt").write_text(parser.format_help())
    commands = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")
    for name, sub in commands.choices.items():
        (out / f"{name}.txt").write_text(sub.format_help())


def is_clean_prose(block: list[str], env: Any) -> bool:
    """True if the block is reStructuredText that parses without a message and is not laid out in columns."""
    if any(ALIGNED.search(line.strip()) or UNDERLINE.match(line) or line.startswith(" ") for line in block):
        return False
    messages = io.StringIO()
    settings = {"warning_stream": messages, "report_level": 1, "halt_level": 5, "env": env}
    publish_doctree("\n".join(block), settings_overrides=settings)
    return not messages.getvalue()


def plain_text_as_literal(lines: list[str], env: Any = None) -> list[str]:
    """Keep clean prose paragraphs, turn the rest into literal blocks (merging neighbours)."""
    blocks: list[list[str]] = []
    for line in lines:
        if line.strip():
            if not blocks or blocks[-1] == []:
                blocks.append([])
            blocks[-1].append(line)
        elif blocks and blocks[-1]:
            blocks.append([])
    blocks = [b for b in blocks if b]
    out: list[str] = []
    literal = False
    for block in blocks:
        if is_clean_prose(block, env):
            out += ["", *block] if out else block
            literal = False
        else:
            if not literal:
                start = [".. code-block:: text", ""]  # plain text: no syntax colours on prose
                out += ["", *start] if out else start
            else:
                out.append("")
            out += ["    " + line for line in block]
            literal = True
    return [*out, ""]


def process_docstring(app: Any, _what: str, _name: str, _obj: Any, _options: Any, lines: list[str]) -> None:
    lines[:] = plain_text_as_literal(lines, app.env)


def optional_guide_pages(_app: Any, docname: str, source: list[str]) -> None:
    """Guide pages written on other branches join the guide's table of contents once they exist."""
    if docname != "guide/index":
        return
    for page in OPTIONAL_GUIDE_PAGES:
        if (DOCS / "guide" / f"{page}.md").is_file():
            source[0] = source[0].replace(f"{GUIDE_LAST}\n```", f"{GUIDE_LAST}\n{page}\n```")


def setup(app: Any) -> dict[str, Any]:
    app.connect("source-read", optional_guide_pages)
    app.connect("builder-inited", run_gallery)
    app.connect("builder-inited", write_cli_help)
    app.connect("autodoc-process-docstring", process_docstring)
    return {"parallel_read_safe": True, "version": "1"}
