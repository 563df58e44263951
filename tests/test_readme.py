"""The README's examples run and print what the README says they print.

A ```python block followed by a ```text block whose introduction says "prints" is run in a
fresh folder, and its standard output must equal the text block line by line."""

import contextlib
import io
import re
from pathlib import Path

import pytest

README = Path(__file__).resolve().parents[1] / "README.md"
FENCE = re.compile(r"```(\w*)\n(.*?)```\n", re.S)


def examples_with_output():
    text = README.read_text()
    blocks = [(m.group(1), m.group(2), m.start(), m.end()) for m in FENCE.finditer(text)]
    pairs = []
    for (lang, code, _, end), (next_lang, expected, start, _) in zip(blocks, blocks[1:]):
        if lang == "python" and next_lang == "text" and "prints" in text[end:start]:
            first = code.strip().splitlines()[0]
            pairs.append(pytest.param(code, expected, id=f"line{text[:end].count(chr(10))}"))
            assert first
    return pairs


def test_the_readme_has_examples_with_output():
    assert len(examples_with_output()) >= 2


@pytest.mark.parametrize(("code", "expected"), examples_with_output())
def test_a_readme_example_prints_what_the_readme_says(code, expected, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(code, str(README), "exec"), {"__name__": "__readme__"})
    assert out.getvalue().splitlines() == expected.splitlines()
