"""The documentation site's sources, checked without running Sphinx (``make docs`` builds it).

Cheap checks that the pages follow the package: every subpackage has an API page, every
notebook is rendered, every page and benchmark a page names exists, and the guides'
examples run as written (doctest, in a scratch folder).
"""
from __future__ import annotations

import doctest
import re
import sys
from pathlib import Path

import pytest

import slicelab

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
sys.path.insert(0, str(DOCS / "_ext"))

import apipages  # noqa: E402  (docs/_ext: plain Python, no Sphinx needed)
import notebookcopies  # noqa: E402


def _pages() -> list[Path]:
    """The committed reST pages (generated ones are git-ignored and not looked at)."""
    generated = ("_build", "_generated", "notebooks", "generated")
    return sorted(p for p in DOCS.rglob("*.rst")
                  if not any(part in generated for part in p.relative_to(DOCS).parts)
                  and not p.name.startswith("slicelab.") and "tables" not in p.parts)


def _toctree_entries(page: Path) -> list[str]:
    entries, inside = [], False
    for line in page.read_text().splitlines():
        if line.startswith(".. toctree::"):
            inside = True
        elif inside and line and not line.startswith(" "):
            inside = False
        elif inside and line.strip() and not line.strip().startswith(":"):
            entries.append(line.strip())
    return entries


def test_every_subpackage_has_an_api_page():
    named = set(re.findall(r"``slicelab\.(\w+)``", slicelab.__doc__))
    assert named, "the package docstring's table of subpackages"
    assert named <= set(apipages.SUBPACKAGES), named - set(apipages.SUBPACKAGES)
    listed = _toctree_entries(DOCS / "api" / "index.rst")
    assert sorted(listed) == sorted(f"slicelab.{sub}" for sub in apipages.SUBPACKAGES)


def test_every_notebook_is_rendered():
    names = [p.name for p in notebookcopies.notebooks()]
    assert names == sorted(p.name for p in (ROOT / "notebooks").glob("*.ipynb")) and names
    assert "notebooks/*" in _toctree_entries(DOCS / "notebooks.rst")


def test_every_page_named_exists():
    """``:doc:`` targets and toctree entries name a page, a notebook or a generated API page."""
    api = {f"api/slicelab.{sub}" for sub in apipages.SUBPACKAGES}
    notebooks = {f"notebooks/{p.stem}" for p in notebookcopies.notebooks()}
    missing = []
    for page in _pages():
        here = page.parent.relative_to(DOCS)
        targets = re.findall(r":doc:`(?:[^`<]*<)?([^`>]+)>?`", page.read_text())
        targets += [t for t in _toctree_entries(page) if "*" not in t]
        for target in targets:
            name = target.lstrip("/") if target.startswith("/") else str((here / target).as_posix())
            name = name.removeprefix("./")
            if not ((DOCS / f"{name}.rst").exists() or name in api or name in notebooks):
                missing.append(f"{page.relative_to(DOCS)}: {target}")
    assert not missing, missing


def test_every_benchmark_named_exists():
    named = [(page, name) for page in _pages()
             for name in re.findall(r"^\.\. bench-result:: (\S+)", page.read_text(), re.M)]
    assert named
    assert all((ROOT / "scripts" / f"{name}.py").exists() for _, name in named), named
    for result in (DOCS / "performance" / "tables").glob("*.rst"):
        assert (ROOT / "scripts" / f"{result.stem}.py").exists(), result
        text = result.read_text()
        for field in (":Command:", ":Measured:", ":Machine:", ":Software:"):
            assert field in text, (result.name, field)


GUIDES = sorted(p for p in _pages() if ">>> " in p.read_text())


@pytest.mark.parametrize("page", GUIDES, ids=[str(p.relative_to(DOCS)) for p in GUIDES])
def test_the_examples_run(page, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    result = doctest.testfile(str(page), module_relative=False, report=True,
                              optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    assert result.attempted and not result.failed, f"{page.name}: {result.failed} failed"
