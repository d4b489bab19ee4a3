"""API pages written at build time, one per subpackage, from each subpackage's ``__all__``.

The pages are generated (git-ignored) rather than committed so that they follow
``__all__`` as it changes: `write_pages` runs when ``conf.py`` is read, before
autosummary scans the sources for the stubs it generates. A page holds the
subpackage's docstring (its table of modules), an autosummary table of its
``__all__`` in that order, and a section per nested subpackage (its docstring,
and the names of its ``__all__`` that the parent does not re-export).

`SUBPACKAGES` is found on disk (every public package directory under
``slicelab/``), so a new subpackage gets a page without an edit here;
``docs/api/index.rst`` lists the pages in its toctree, and a page left out of
it fails the build (warnings are errors).
"""
from __future__ import annotations

import importlib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PACKAGE = ROOT / "slicelab"
API = ROOT / "docs" / "api"


def public_packages(parent: Path) -> list[str]:
    """Names of the public packages directly under `parent`, sorted."""
    return sorted(p.name for p in parent.iterdir()
                  if p.is_dir() and not p.name.startswith("_") and (p / "__init__.py").exists())


SUBPACKAGES = public_packages(PACKAGE)


def _underline(text: str, char: str) -> str:
    return f"{text}\n{char * len(text)}\n"


def _table(module: str, names: list[str]) -> str:
    rows = "".join(f"   {n}\n" for n in names)
    return (f".. currentmodule:: {module}\n\n"
            f".. autosummary::\n   :toctree: generated/\n\n{rows}\n")


def page(sub: str) -> str:
    """The reST of ``slicelab.<sub>``'s page."""
    name = f"slicelab.{sub}"
    module = importlib.import_module(name)
    names = list(getattr(module, "__all__", []))
    out = [_underline(name, "="), f"\n.. automodule:: {name}\n   :no-members:\n\n"]
    if names:
        out += [_underline("Public names", "-"),
                f"\nThe names of ``{name}.__all__``, in its order.\n\n", _table(name, names)]
    shown = set(names)
    for nested in public_packages(PACKAGE / sub):
        nested_name = f"{name}.{nested}"
        nested_module = importlib.import_module(nested_name)
        extra = [n for n in getattr(nested_module, "__all__", []) if n not in shown]
        shown |= set(extra)
        out += ["\n", _underline(nested_name, "-"), f"\n.. automodule:: {nested_name}\n   :no-members:\n\n"]
        if extra:
            out += [f"Names of ``{nested_name}.__all__`` not re-exported by ``{name}``:\n\n",
                    _table(nested_name, extra)]
    return "".join(out)


def top_level_table() -> str:
    """A list-table of ``slicelab.__all__``: each top-level name and where its entry is."""
    import slicelab
    homes: dict[int, str] = {}
    for sub in SUBPACKAGES:
        module = importlib.import_module(f"slicelab.{sub}")
        for n in getattr(module, "__all__", []):
            homes.setdefault(id(getattr(module, n)), f"slicelab.{sub}.{n}")
    rows = []
    for n in slicelab.__all__:
        obj = getattr(slicelab, n)
        home = homes.get(id(obj))
        where = f":obj:`{home}`" if home else "``slicelab.__version__``, the package's version string"
        rows.append(f"   * - ``slicelab.{n}``\n     - {where}\n")
    return (".. list-table::\n   :header-rows: 1\n   :widths: 30 70\n\n"
            "   * - name\n     - the same object, documented as\n" + "".join(rows))


def _write(path: Path, text: str) -> None:
    """Write `text` unless the file already holds it (Sphinx then keeps its parsed copy)."""
    if not path.exists() or path.read_text() != text:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)


def write_pages() -> list[str]:
    """Write ``docs/api/slicelab.<sub>.rst`` for every subpackage; return the page names."""
    for sub in SUBPACKAGES:
        _write(API / f"slicelab.{sub}.rst", page(sub))
    _write(ROOT / "docs" / "_generated" / "top_level.rst", top_level_table())
    return [f"slicelab.{sub}" for sub in SUBPACKAGES]
