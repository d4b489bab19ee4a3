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
            f".. autosummary::\n   :toctree: generated/\n   :nosignatures:\n\n{rows}\n")


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


def _documented() -> list[tuple[str, object]]:
    """(name, object) of every name the API pages document, in page order."""
    out = []
    for sub in SUBPACKAGES:
        module = importlib.import_module(f"slicelab.{sub}")
        shown = set()
        for name in getattr(module, "__all__", []):
            out.append((f"slicelab.{sub}.{name}", getattr(module, name)))
            shown.add(name)
        for nested in public_packages(PACKAGE / sub):
            nested_module = importlib.import_module(f"slicelab.{sub}.{nested}")
            for name in getattr(nested_module, "__all__", []):
                if name not in shown:
                    out.append((f"slicelab.{sub}.{nested}.{name}", getattr(nested_module, name)))
                    shown.add(name)
    return out


def _homeable(obj) -> bool:
    """Objects whose identity names them (not numbers or strings, which may be shared)."""
    return not isinstance(obj, (int, float, str, bytes, bool, type(None)))


def top_level_table() -> str:
    """A list-table of ``slicelab.__all__``: each top-level name and where its entry is."""
    import slicelab
    homes: dict[int, str] = {}
    for name, obj in _documented():
        if _homeable(obj):
            homes.setdefault(id(obj), name)
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


# --- Links to the page where an object is documented ------------------------------------------------
# A docstring or a guide names an object where it is defined (`slicelab.printing.roles.KINDS`), by a
# top-level alias (`slicelab.plan`) or bare (`PrintSettings`); the pages document it once, under the
# subpackage that exports it. A reference Sphinx does not find is sent to that entry: by the object's
# identity when the name imports, or by a bare name that one documented entry alone ends with.

_HOMES: dict | None = None


def _homes() -> dict:
    global _HOMES
    if _HOMES is None:
        by_id, by_tail, keep = {}, {}, []
        for name, obj in _documented():
            if _homeable(obj):
                by_id.setdefault(id(obj), name)
                keep.append(obj)
            by_tail.setdefault(name.rsplit(".", 1)[1], set()).add(name)
        _HOMES = {"id": by_id, "tail": by_tail, "keep": keep}
    return _HOMES


def _import(target: str):
    """The object a dotted name under slicelab names, or None."""
    parts = target.split(".")
    for cut in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:cut]))
        except ImportError:
            continue
        try:
            for attr in parts[cut:]:
                obj = getattr(obj, attr)
        except AttributeError:
            return None
        return obj
    return None


def home_of(target: str) -> str | None:
    """The documented name for `target`, when it is not documented under that name itself."""
    homes = _homes()
    target = target.lstrip("~.")
    if target.startswith("slicelab."):
        obj = _import(target)
        if obj is not None and _homeable(obj):
            home = homes["id"].get(id(obj))
            if home and home != target:
                return home
        return None
    if "." not in target:
        names = homes["tail"].get(target, set())
        if len(names) == 1:
            return next(iter(names))
    return None


def resolve_to_home(app, env, node, contnode):
    if node.get("refdomain") != "py":
        return None
    home = home_of(node.get("reftarget", ""))
    if home is None:
        return None
    domain = env.get_domain("py")
    for role in (node.get("reftype", "obj"), "obj"):
        found = domain.resolve_xref(env, node.get("refdoc"), app.builder, role, home, node, contnode)
        if found is not None:
            return found
    return None


def setup(app):
    app.connect("missing-reference", resolve_to_home)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
