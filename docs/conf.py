"""Sphinx configuration of corotate's documentation (built by .ci/run with warnings as errors:
``sphinx-build -W --keep-going -b html docs <out>``; needs ``pip install '.[docs]'``)."""

from __future__ import annotations

import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
sys.path.insert(0, str(DOCS / "_ext"))

import corotate  # noqa: E402  (the installed package: the API reference is read from it)

project = "corotate"
author = "the corotate developers"
copyright = "the corotate developers, MIT licence"
release = version = corotate.__version__

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "corotate_docs",  # docs/_ext: the gallery's pictures, the CLI's help, plain-text docstrings
]
source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
root_doc = "index"
exclude_patterns = ["_build", "_generated/README.md"]
templates_path = ["_templates"]

myst_enable_extensions = ["dollarmath", "colon_fence"]
myst_heading_anchors = 3

autosummary_generate = True
autodoc_default_options = {"members": True, "member-order": "bysource"}
autodoc_typehints = "signature"
autodoc_class_signature = "separated"
# No napoleon: the docstrings are plain text in the libigl manner ("name  (n, 3) what it is"),
# which its numpy reader would mangle; docs/_ext/corotate_docs.py shows them as written.

html_theme = "furo"
html_title = f"corotate {release}"
html_static_path = ["_static"]
html_css_files = ["corotate.css"]
