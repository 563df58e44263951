"""The paper's figures and tables, reproduced, and the investigations behind the library's
defaults: one script per figure, table or question, run as ``python -m studies.<name> --out
FOLDER`` from the repository's root; each writes its numbers (CSV, JSON or Markdown) and its
picture (PNG) into FOLDER. They need the extra ``corotate-fem[plot]`` (matplotlib); the
Table 1 study also needs ``[mesh]`` and the armadillo from the shared data."""

from __future__ import annotations
