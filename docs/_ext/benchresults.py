"""``.. bench-result:: bench_io``: a benchmark's table as the script last wrote it for the docs.

A script run with ``--docs`` writes ``docs/performance/tables/NAME.rst``
(`scripts/benchlib.py`, ``docs_output``): what it printed, under the command,
the date, the commit and the machine. The directive puts the script's summary
line (the first line of its docstring) above that file, or, when the file is
absent, says that the table is not yet measured and how to measure it. The
figures on the performance pages are therefore always those a script printed,
never typed in by hand.
"""
from __future__ import annotations

import ast
from pathlib import Path

from docutils import nodes
from docutils.statemachine import StringList
from sphinx.util.docutils import SphinxDirective

ROOT = Path(__file__).resolve().parents[2]
SCRIPTS = ROOT / "scripts"
RESULTS = ROOT / "docs" / "performance" / "tables"


def summary(script: Path) -> str:
    """The first line of a script's docstring."""
    doc = ast.get_docstring(ast.parse(script.read_text())) or ""
    return doc.strip().splitlines()[0] if doc.strip() else ""


def writes_docs(script: Path) -> bool:
    """Whether the script takes ``--docs`` (it calls benchlib's ``docs_output``)."""
    return "docs_output(" in script.read_text()


def result_lines(name: str) -> list[str]:
    """The reST shown for benchmark `name` (a script ``scripts/NAME.py``)."""
    script = SCRIPTS / f"{name}.py"
    results = RESULTS / f"{name}.rst"
    lines = [f"``scripts/{name}.py``: {summary(script)}", ""]
    if results.exists():
        return lines + results.read_text().splitlines()
    if writes_docs(script):
        return lines + [f"*Not yet measured:* run ``python scripts/{name}.py --docs``.", ""]
    return lines + [f"*Not yet measured:* ``scripts/{name}.py`` does not write its table for the docs yet "
                    f"(the ``--docs`` flag of ``scripts/bench_io.py``, through ``benchlib.docs_output``, "
                    f"is the pattern); run ``python scripts/{name}.py --help`` for what it measures.", ""]


class BenchResult(SphinxDirective):
    required_arguments = 1
    has_content = False

    def run(self):
        name = self.arguments[0]
        script = SCRIPTS / f"{name}.py"
        if not script.exists():
            raise self.error(f"bench-result: no script scripts/{name}.py")
        self.env.note_dependency(str(script))
        self.env.note_dependency(str(RESULTS / f"{name}.rst"))
        container = nodes.container(classes=["bench-result"])
        source = str(RESULTS / f"{name}.rst")
        self.state.nested_parse(StringList(result_lines(name), source=source), self.content_offset, container)
        return [container]


def setup(app):
    app.add_directive("bench-result", BenchResult)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
