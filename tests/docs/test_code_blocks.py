"""The README's and the documentation's examples run, and print what the pages say they print.

Every ```python block of README.md and of docs/**/*.md runs, page by page in one namespace (a
page's later blocks build on its earlier ones), in a fresh folder. A block followed by a
```text block whose introduction says "prints" must print exactly that text. A block preceded
by an HTML comment "<!-- not run: reason -->" is skipped (it needs a display or data the tests
do not have), one preceded by "<!-- needs: module -->" where that module (an optional extra's)
is not installed."""

from __future__ import annotations

import contextlib
import importlib.util
import io
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
FENCE = re.compile(r"```(\w*)\n(.*?)```\n", re.S)
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("**/*.md"))]
PAGES = [p for p in PAGES if "_generated" not in p.parts and "_build" not in p.parts]


def examples(page: Path) -> list[tuple[str, str | None, int]]:
    """(code, expected output or None, line) of each python block of the page, in order."""
    text = page.read_text()
    blocks = [(m.group(1), m.group(2), m.start(), m.end()) for m in FENCE.finditer(text)]
    out = []
    for k, (lang, code, start, end) in enumerate(blocks):
        if lang != "python":
            continue
        before = text[blocks[k - 1][3] if k else 0 : start]
        if "<!-- not run:" in before:
            continue
        needs = re.search(r"<!-- needs: ([\w.]+) -->", before)
        if needs and importlib.util.find_spec(needs.group(1)) is None:
            continue
        expected = None
        if k + 1 < len(blocks):
            next_lang, next_code, next_start, _ = blocks[k + 1]
            if next_lang == "text" and "prints" in text[end:next_start]:
                expected = next_code
        out.append((code, expected, text[:start].count("\n") + 1))
    return out


def pages_with_code():
    return [pytest.param(p, id=str(p.relative_to(ROOT))) for p in PAGES if examples(p)]


def test_the_readme_has_examples_with_output():
    assert sum(expected is not None for _, expected, _ in examples(ROOT / "README.md")) >= 2


def test_the_readme_is_at_most_200_lines():
    assert len((ROOT / "README.md").read_text().splitlines()) <= 200


def test_a_block_needing_a_missing_module_is_skipped(tmp_path):
    page = tmp_path / "page.md"
    page.write_text(
        "<!-- needs: json -->\n```python\nkept = 1\n```\n\n"
        "<!-- needs: no_such_module_here -->\n```python\nskipped = 1\n```\n"
    )
    assert [code for code, _, _ in examples(page)] == ["kept = 1\n"]


def test_every_guide_page_shows_code_that_runs():
    for page in sorted((ROOT / "docs" / "guide").glob("*.md")):
        if page.name != "index.md":
            assert examples(page), f"{page.name} has no python example"


@pytest.mark.parametrize("page", pages_with_code())
def test_a_page_s_examples_print_what_the_page_says(page, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "__docs__"}
    for code, expected, line in examples(page):
        out = io.StringIO()
        with contextlib.redirect_stdout(out):
            exec(compile("\n" * (line) + code, str(page), "exec"), namespace)
        if expected is not None:
            assert out.getvalue().splitlines() == expected.splitlines(), f"{page.name}, the block at line {line}"
