"""Where a batch puts each input's report and outputs: a name of its own under OUT, extension kept.

An input at ``DIR/a/pot.stl`` gets the name ``a/pot.stl``: its outputs go to
the folder ``OUT/a/pot.stl/`` (under the job's own file names, the same as
on the command line: ``OUT/a/pot.stl/section.svg``) and its report to
``OUT/a/pot.stl.json``, so ``pot.stl`` and ``pot.obj`` never share a
folder. Names are compared casefolded, as a case-insensitive file system
(macOS, Windows) would: of two inputs whose names differ only by case
(``dup.stl``, ``dup.STL``), or whose folder or report would land on a
folder mirrored from DIR or on ``summary.csv``, the later one in sorted
order gets a suffix, ``~2`` (``dup.stl~2/``, ``dup.stl~2.json``), then
``~3``. The names depend only on the inputs' paths under DIR: the same
inputs get the same names on every run, so a rerun finds its reports.
"""
from __future__ import annotations

from pathlib import PurePosixPath

__all__ = ["RESERVED", "output_names"]

#: Names the batch itself writes at the top of OUT.
RESERVED = ("summary.csv", "rim_diameters.png", "rim_diameters.csv")  # casefolded


def output_names(files) -> dict[str, str]:
    """Each input's name under OUT: its folder of outputs, and with ``.json`` its report.

    Parameters
    ----------
    files : iterable of str
        The inputs' POSIX paths relative to DIR.

    Returns
    -------
    dict
        Input path -> its name (a POSIX path relative to OUT).

    Examples
    --------
    >>> output_names(["pot.stl", "pot.obj", "dup.stl", "dup.STL", "summary.csv.stl"])["pot.stl"]
    'pot.stl'
    >>> sorted(output_names(["dup.stl", "dup.STL"]).values())  # 'dup.STL' sorts first
    ['dup.STL', 'dup.stl~2']
    >>> output_names(["x.stl.json/a.stl", "x.stl"])["x.stl"]  # the folder x.stl.json/ holds a's outputs
    'x.stl~2'
    """
    files = sorted(set(files))
    dirs = sorted({PurePosixPath(rel).parts[:-1] for rel in files} - {()})
    top = {d[0].casefold() for d in dirs}
    # A folder mirrored from DIR keeps its name, but for one on a name the batch writes itself.
    moved = {}
    for d in dirs:
        if d[0].casefold() in RESERVED and d[0] not in moved:
            moved[d[0]] = _free(d[0], top | set(RESERVED) | {m.casefold() for m in moved.values()})

    def folder(parts) -> str:  # where the outputs of the files of a folder under DIR go, under OUT
        return "/".join((moved.get(parts[0], parts[0]), *parts[1:])) if parts else ""

    taken: dict[str, set[str]] = {"": set(RESERVED)}  # folder under OUT (casefolded) -> names in it
    for d in dirs:  # the mirrored folders come first: other inputs' names go in them
        for k in range(len(d)):
            taken.setdefault(folder(d[:k]).casefold(), set()).add(folder(d[:k + 1]).rpartition("/")[2].casefold())
    names = {}
    for rel in files:
        path = PurePosixPath(rel)
        parent = folder(path.parts[:-1])
        here = taken.setdefault(parent.casefold(), set())
        name = _free(path.name, here, ".json")
        here.update((name.casefold(), f"{name}.json".casefold()))
        names[rel] = f"{parent}/{name}" if parent else name
    return names


def _free(name: str, taken: set, *endings: str) -> str:
    """`name`, or ``name~2``, ``name~3``...: the first that is free in `taken`, with each of `endings` too."""
    candidate, k = name, 1
    while any(f"{candidate}{e}".casefold() in taken for e in ("", *endings)):
        k += 1
        candidate = f"{name}~{k}"
    return candidate
