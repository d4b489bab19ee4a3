"""The command line's help, written at build time from the parser itself.

`write_cli_help` writes ``docs/_generated/cli_help.rst``: the synopsis of
``slicelab --help`` and, for each command, its ``--help`` text in a literal
block under a heading, so the command-line page is what ``slicelab COMMAND
--help`` prints in this revision.
"""
from __future__ import annotations

import argparse
import os
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
OUT = ROOT / "docs" / "_generated"


def _literal(text: str) -> str:
    return ".. code-block:: text\n\n" + "".join(f"   {line}".rstrip() + "\n" for line in text.rstrip().splitlines())


def write_cli_help() -> None:
    from slicelab.cli import build_parser

    os.environ["COLUMNS"] = "100"    # argparse wraps to the terminal's width: the same page everywhere
    parser = build_parser()
    parser.prog = "slicelab"
    out = ["Synopsis\n--------\n\n", _literal(parser.format_help()), "\n"]
    actions = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    for action in actions:
        for name, sub in action.choices.items():
            title = f"slicelab {name}"
            out += [f"{title}\n{'-' * len(title)}\n\n", _literal(sub.format_help()), "\n"]
    OUT.mkdir(parents=True, exist_ok=True)
    text = "".join(out)
    path = OUT / "cli_help.rst"
    if not path.exists() or path.read_text() != text:
        path.write_text(text)
