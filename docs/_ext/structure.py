"""The package's floors drawn at build time, from the rules ``tests/test_layout.py`` enforces.

`write_structure` reads the floors and limits from ``tests/test_layout.py``
(``FLOORS``, ``MAX_LINES``, ``MAX_FUNCTION_LINES``, ``MAX_POSITIONAL``) and the
imports between subpackages from the package's source (every ``from ...
import``, at any level, as the test reads them), then writes into
``docs/_generated/`` (git-ignored):

- ``structure.svg``: a box per subpackage on its floor (its modules and lines),
  an arrow for each subpackage that imports from another;
- ``structure_floors.rst``: a table, floor by floor, of what each subpackage
  imports from;
- ``structure_rules.rst``: the limits, with their numbers as the test has them.

So the picture is the package as it is, and the rules are those tested.
"""
from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PACKAGE = ROOT / "slicelab"
LAYOUT_TEST = ROOT / "tests" / "test_layout.py"
OUT = ROOT / "docs" / "_generated"


# Used only for a name that tests/test_layout.py does not define (yet): the rules as planned.
PLANNED = {"FLOORS": [["_lazy", "_pools"], ["geometry"], ["files"], ["mesh"], ["samples", "slicing"],
                      ["printing", "artefacts"], ["gcode"], ["viz"], ["tasks"], ["cli"], ["__main__"]],
           "MAX_LINES": 600, "MAX_FUNCTION_LINES": 120, "MAX_POSITIONAL": 8}


def layout_rules() -> dict:
    """``FLOORS`` and the limits, as literals read from ``tests/test_layout.py``; ``"planned"``
    names those the test does not define, taken from `PLANNED`."""
    found = {}
    for node in ast.parse(LAYOUT_TEST.read_text()).body:
        if isinstance(node, ast.Assign) and len(node.targets) == 1 and isinstance(node.targets[0], ast.Name):
            name = node.targets[0].id
            if name in PLANNED:
                found[name] = ast.literal_eval(node.value)
    planned = sorted(set(PLANNED) - set(found))
    return {**PLANNED, **found, "planned": planned}


def _unit(module: str) -> str:
    """The floor unit a module belongs to: ``slicelab.printing.grid.raster`` -> ``printing``."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else ""


def modules() -> dict[str, Path]:
    out = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = list(path.relative_to(ROOT).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = path
    return out


def _target(module: str, path: Path, node: ast.ImportFrom) -> str | None:
    if node.level == 0:
        return node.module if node.module and node.module.split(".")[0] == "slicelab" else None
    package = module if path.name == "__init__.py" else module.rsplit(".", 1)[0]
    base = package.split(".")[: len(package.split(".")) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def unit_imports() -> dict[str, set[str]]:
    """Floor unit -> the units it imports from (itself and ``__version__`` from the root left out)."""
    graph: dict[str, set[str]] = {}
    for module, path in modules().items():
        unit = _unit(module)
        graph.setdefault(unit, set())
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom):
                target = _target(module, path, node)
                if target is None or (target == "slicelab" and [a.name for a in node.names] == ["__version__"]):
                    continue
                if _unit(target) != unit:
                    graph[unit].add(_unit(target))
    return graph


def direct_imports(graph: dict[str, set[str]], unit: str) -> set[str]:
    """The units `unit` imports that it does not also reach through another unit it imports (the
    transitive reduction, which keeps the picture readable; the table lists every import)."""
    def reach(start: str, seen: set[str]) -> set[str]:
        for nxt in graph.get(start, ()):
            if nxt not in seen:
                seen.add(nxt)
                reach(nxt, seen)
        return seen
    targets = graph.get(unit, set())
    implied = set()
    for t in targets:
        implied |= reach(t, set()) - {unit}
    return {t for t in targets if t not in implied}


def unit_sizes() -> dict[str, tuple[int, int]]:
    """Floor unit -> (modules, lines)."""
    sizes: dict[str, list[int]] = {}
    for module, path in modules().items():
        s = sizes.setdefault(_unit(module), [0, 0])
        s[0] += 1
        s[1] += len(path.read_text().splitlines())
    return {k: (v[0], v[1]) for k, v in sizes.items()}


def draw(floors: list[list[str]], graph: dict[str, set[str]], sizes: dict[str, tuple[int, int]], path: Path):
    """A box per unit on its floor; arrows for the imports of the transitive reduction (those into the
    floor right below drawn straight, longer ones along lanes beside the boxes), and in red any import
    that goes up a floor."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import FancyBboxPatch

    matplotlib.rcParams["svg.hashsalt"] = "slicelab-docs"   # the same file from the same package
    matplotlib.rcParams["svg.fonttype"] = "none"
    row, width, height, gap, middle = 1.0, 2.5, 0.62, 0.5, 4.6
    fig, ax = plt.subplots(figsize=(8.6, 0.66 * len(floors) + 0.6))
    boxes = {}      # unit -> (left x, centre y, side: -1 left, 0 alone, 1 right)
    for level, names in enumerate(floors):
        y = level * row
        total = len(names) * width + (len(names) - 1) * gap
        x0 = middle - total / 2
        ax.text(-1.4, y, f"floor {level}", va="center", ha="left", fontsize=9, color="#555555")
        for i, name in enumerate(names):
            x = x0 + i * (width + gap)
            n_mod, n_lines = sizes.get(name, (0, 0))
            ax.add_patch(FancyBboxPatch((x, y - height / 2), width, height, boxstyle="round,pad=0.02",
                                        fc="#dbe9f6" if not name.startswith("_") else "#eeeeee", ec="#2c5d8a",
                                        lw=1.0, zorder=2))
            title = name if name.startswith("_") else f"slicelab.{name}"
            ax.text(x + width / 2, y + 0.09, title, ha="center", va="center", fontsize=9.5, family="monospace",
                    zorder=3)
            ax.text(x + width / 2, y - 0.17, f"{n_mod} module{'s' if n_mod != 1 else ''}, {n_lines:,} lines",
                    ha="center", va="center", fontsize=7.5, color="#444444", zorder=3)
            side = 0 if len(names) == 1 else (-1 if i == 0 else 1)
            boxes[name] = (x, y, side)
    level_of = {name: level for level, names in enumerate(floors) for name in names}
    down = {u: {t for t in ts if level_of.get(t, -1) < level_of.get(u, -1)} for u, ts in graph.items()}
    edges = sorted((u, t) for u in graph if u in boxes
                   for t in direct_imports(down, u) | (graph[u] - down[u]) if t in boxes)
    lanes = {-1: 0, 1: 0}
    ports: dict[tuple[str, int], int] = {}

    def port(unit, end):
        """How many lines already leave or enter `unit`'s top (1) or bottom (-1) along a lane."""
        k = ports[(unit, end)] = ports.get((unit, end), -1) + 1
        return k % 4

    for u, t in edges:
        (xu, yu, su), (xt, yt, st) = boxes[u], boxes[t]
        up = level_of[t] >= level_of[u]         # against the rules: tests/test_layout.py fails on it
        style = dict(color="#c0392b" if up else "#7a7a7a", lw=1.4 if up else 0.8, zorder=4 if up else 1)
        arrow = dict(arrowstyle="-|>", mutation_scale=9, shrinkA=0, shrinkB=0, **style)
        if not up and level_of[u] - level_of[t] == 1:
            cu, ct = xu + width / 2, xt + width / 2
            aim = (ct - cu) * 0.35
            ax.annotate("", xy=(ct - aim, yt + height / 2 + 0.02), xytext=(cu + aim, yu - height / 2 - 0.02),
                        arrowprops=arrow)
            continue
        # Out of the box's bottom (top, going up) into the channel between the floors, along it to a
        # lane beside the boxes, along the lane to the channel next to the target, into the target.
        side = st or su or (1 if lanes[1] <= lanes[-1] else -1)
        lane_x = (middle + width + gap / 2 + 0.3 + 0.14 * lanes[side] if side > 0
                  else middle - width - gap / 2 - 0.3 - 0.14 * lanes[side])
        lanes[side] += 1
        toward = 1 if up else -1
        k_u, k_t = port(u, toward), port(t, -toward)
        x_from = xu + width / 2 + side * (0.5 + 0.15 * k_u)
        x_to = xt + width / 2 + side * (0.5 + 0.15 * k_t)
        y_out = yu + toward * (height / 2 + 0.02)
        y_in = yt - toward * (height / 2 + 0.02)
        ch_u = yu + toward * (row / 2 - 0.04 * k_u)
        ch_t = yt - toward * (row / 2 - 0.04 * k_t)
        ax.plot([x_from, x_from, lane_x, lane_x, x_to], [y_out, ch_u, ch_u, ch_t, ch_t], solid_capstyle="round",
                **style)
        ax.annotate("", xy=(x_to, y_in), xytext=(x_to, ch_t), arrowprops=arrow)
    ax.set_xlim(-1.5, 9.4)
    ax.set_ylim(-0.5, (len(floors) - 1) * row + 0.5)
    ax.axis("off")
    fig.tight_layout(pad=0.2)
    fig.savefig(path, format="svg", metadata={"Date": None})
    plt.close(fig)


def floors_table(floors, graph, sizes) -> str:
    level_of = {name: level for level, names in enumerate(floors) for name in names}
    rows = []
    for level, names in reversed(list(enumerate(floors))):
        for name in names:
            targets = sorted(graph.get(name, ()), key=lambda u: (-level_of.get(u, -1), u))
            imports = ", ".join(f"``{u}``" + (" (**up a floor**: the layout test fails)"
                                              if level_of.get(u, -1) >= level else "")
                                for u in targets) or "nothing of slicelab"
            n_mod, n_lines = sizes.get(name, (0, 0))
            rows.append(f"   * - {level}\n     - ``{name}``\n     - {n_mod}\n     - {n_lines:,}\n     - {imports}\n")
    return (".. list-table::\n   :header-rows: 1\n   :widths: 8 18 10 12 52\n\n"
            "   * - floor\n     - unit\n     - modules\n     - lines\n     - imports from\n" + "".join(rows))


def rules_text(rules: dict) -> str:
    order = " < ".join(", ".join(f"``{n}``" for n in names) for names in rules["FLOORS"])
    return (f"- **Floors.** {order}. A module imports only from its own subpackage or from a lower floor, "
            f"at any level: an import deferred into a function counts, since it is a dependency all the same "
            f"(``test_no_import_goes_up_a_floor``); every subpackage and root module is on a floor "
            f"(``test_every_subpackage_is_on_a_floor``).\n"
            f"- **No cycles.** Module-level imports form no cycle between modules "
            f"(``test_no_import_cycle_between_modules``).\n"
            f"- **No private names across modules.** A name starting with ``_`` is imported only inside its "
            f"own module (``test_no_private_name_is_imported_across_modules``), and no test imports one.\n"
            f"- **Small functions.** At most {rules['MAX_FUNCTION_LINES']} lines past the docstring and at "
            f"most {rules['MAX_POSITIONAL']} positional parameters (options are keyword-only); compiled "
            f"kernels, which take plain arrays, are exempt "
            f"(``test_functions_are_short_and_take_few_positional_arguments``).\n"
            f"- **Small modules.** At most {rules['MAX_LINES']} lines a module "
            f"(``test_no_module_is_over_600_lines``).\n"
            f"- **Public names.** Each subpackage lists its public names in ``__all__`` and documents its "
            f"modules in its docstring (``test_each_subpackage_exports_its_all``).\n"
            + (f"\n.. note::\n   ``tests/test_layout.py`` does not define "
               f"{', '.join(f'``{n}``' for n in rules['planned'])} in this revision: "
               f"the values shown for them are the planned ones, not yet tested.\n" if rules["planned"] else ""))


def _write(path: Path, text: str) -> None:
    if not path.exists() or path.read_text() != text:
        path.write_text(text)


def write_structure() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    rules = layout_rules()
    graph, sizes = unit_imports(), unit_sizes()
    floors = rules["FLOORS"]
    svg = OUT / "structure.svg"
    tmp = OUT / "structure.svg.new"
    draw(floors, graph, sizes, tmp)
    if svg.exists() and svg.read_bytes() == tmp.read_bytes():
        tmp.unlink()
    else:
        tmp.replace(svg)
    _write(OUT / "structure_floors.rst", floors_table(floors, graph, sizes))
    _write(OUT / "structure_rules.rst", rules_text(rules))
