"""Every public name of corotate is in the API reference (docs/api/*.md): the names in
corotate.__all__ and in the __all__ of its public subpackages, corotate.modal,
corotate.sweep and corotate.view. A name counts when an autosummary entry of the reference resolves to the same
object (so corotate.Mesh documents corotate.mesh.Mesh too)."""

import importlib
import re
from pathlib import Path

import pytest

import corotate

API = Path(__file__).resolve().parents[2] / "docs" / "api"
PUBLIC = ["corotate", "corotate.modal", "corotate.sweep", "corotate.view"]


def documented_names() -> list[str]:
    """The fully qualified names of the reference's autosummary entries."""
    names = []
    for page in sorted(API.glob("*.md")):
        module = None
        in_summary = False
        for line in page.read_text().splitlines():
            current = re.match(r"\.\. currentmodule:: ([\w.]+)", line.strip())
            if current:
                module = current.group(1)
            elif line.strip().startswith(".. autosummary::"):
                in_summary = True
            elif in_summary and line.strip().startswith("```"):
                in_summary = False
            elif in_summary and line.strip() and not line.strip().startswith(":"):
                names.append(f"{module}.{line.strip()}")
    return names


def resolve(qualified: str):
    parts = qualified.split(".")
    for split in range(len(parts) - 1, 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:split]))
        except ImportError:
            continue
        for attribute in parts[split:]:
            obj = getattr(obj, attribute)
        return obj
    raise ImportError(qualified)


def test_every_reference_entry_resolves():
    names = documented_names()
    assert len(names) > 40
    for name in names:
        resolve(name)  # an entry that names nothing would be a broken page


@pytest.mark.parametrize("module", PUBLIC)
def test_every_public_name_is_in_the_reference(module):
    documented = {id(resolve(name)) for name in documented_names()}
    mod = importlib.import_module(module)
    missing = [name for name in mod.__all__ if id(getattr(mod, name)) not in documented]
    assert not missing, f"add to docs/api/*.md: {module}.{missing}"


def test_the_public_subpackages_are_the_ones_checked():
    packages = sorted(
        f"corotate.{p.name}"
        for p in Path(corotate.__file__).parent.iterdir()
        if p.is_dir() and (p / "__init__.py").exists() and not p.name.startswith("_")
    )
    assert packages == PUBLIC[1:], "a new public subpackage: add it to PUBLIC and to the reference"
