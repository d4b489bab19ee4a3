"""A batch's own files at the top of OUT: ``summary.csv`` and, for profiles, the rim-diameter chart.

``summary.csv`` has a row per file, in file order, and no timings (a rerun
writes the same file). Every number's unit is in its column's name
(`UNITS`: ``height_mm``, ``capacity_l``, ``span_deg``...), but for counts,
named by what they count (`COUNTS`), and rim and base EVE (estimated vessel
equivalents: a whole vessel is 1), ``rim_eve`` and ``base_eve``. For the
profile task the table is an EVE table (`slicelab.tasks.jobs` PROFILE's
columns): each piece's kind (``whole``, ``rim``, ``body``, ``base``), the
angle it spans, its rim EVE and rim diameter with its uncertainty, whether
its axis can be trusted and where up was taken from, then its measurements.
Cells are empty where a value does not apply (a body sherd has no rim EVE).

Beside it, for the profile task, ``rim_diameters.png`` and
``rim_diameters.csv`` (`slicelab.viz.rims`): the rim diameters weighted by
rim EVE, and the numbers drawn. They are written through a staging folder
and listed in OUT's manifest (`slicelab.files.atomic.StagedFolder`), so a
later batch of another task into the same OUT takes them away with it
rather than leaving a chart that no longer matches the summary. Their names
are reserved (`slicelab.tasks.outputs.RESERVED`): a folder of DIR on one of
them is mirrored under another name.
"""
from __future__ import annotations

import csv
from pathlib import Path

from ..files.atomic import StagedFolder, atomic_open
from .jobs import JOBS
from .outputs import output_names

__all__ = ["UNITS", "COUNTS", "summary_columns", "write_summary", "write_batch_files"]

_MM, _MM2, _MM3, _DEG, _PERCENT = (1.0, "mm"), (1.0, "mm2"), (1.0, "mm3"), (1.0, "deg"), (100.0, "percent")
#: Result -> (factor, unit) from its own unit (mm, mm^2, mm^3, degrees, a share of 1) to its column's
#: unit, which ends the column's name (``capacity`` in mm^3 -> ``capacity_l``).
UNITS = {"size_x": _MM, "size_y": _MM, "size_z": _MM, "volume": _MM3, "area": _MM2, "section_area": _MM2,
         "span": _DEG, "rim_diameter": _MM, "rim_diameter_sd": _MM, "axis_spread": _DEG,
         "up_confidence": _PERCENT, "kind_confidence": _PERCENT, "axis_confidence": _PERCENT, "height": _MM, "max_diameter": _MM,
         "base_diameter": _MM, "wall_thickness_min": _MM, "wall_thickness_mean": _MM, "wall_thickness_max": _MM,
         "base_thickness": _MM, "capacity": (1e-6, "l"), "clay_volume": (1e-3, "cm3"), "residual": _MM,
         "relative_residual": _PERCENT, "spread": _MM, "ovality": (1.0, "percent"), "noise": _MM}
#: Numbers without a unit: how many of what the column names (a list in the results: its length).
COUNTS = ("facets", "shells", "loops", "holes", "open_chains", "layers", "front_facets", "rear_facets",
          "cut_facets", "appendages")
_RENAMED = {"residual": "axis_residual", "relative_residual": "axis_residual"}  # what the residual is of
_FILE = ("file", "status", "reasons", "messages", "sha256", "facets", "watertight", "shells", "size_x", "size_y",
         "size_z", "volume")
#: The chart's files at the top of OUT (`slicelab.viz.rims`).
CHART = ("rim_diameters.png", "rim_diameters.csv")


def _column(key: str) -> str:
    """The column of result `key`: with its unit when it has one."""
    if key not in UNITS:
        return key
    return f"{_RENAMED.get(key, key)}_{UNITS[key][1]}"


def summary_columns(task: str) -> list[str]:
    """The columns of a batch's ``summary.csv`` for `task`.

    Examples
    --------
    >>> summary_columns("section")[8:]
    ['size_x_mm', 'size_y_mm', 'size_z_mm', 'volume_mm3', 'area_mm2', 'loops', 'holes', 'open_chains', 'report']
    >>> [c for c in summary_columns("profile") if "rim" in c or "capacity" in c]
    ['rim_eve', 'rim_diameter_mm', 'rim_diameter_sd_mm', 'capacity_l']
    """
    return [_column(k) for k in (*_FILE, *JOBS[task].columns)] + ["report"]


def _fmt(v) -> str:
    if v is None:
        return ""
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, float):
        return f"{v:.10g}"
    return str(v)


def _cell(key: str, value):
    """A result as its column shows it: a list counted, a number in the column's unit."""
    if isinstance(value, list):
        return len(value)
    if key in UNITS and isinstance(value, (int, float)) and not isinstance(value, bool):
        factor = UNITS[key][0]
        return float(value) * factor if factor != 1.0 else value
    return value


def write_summary(out, reports: list[dict], task: str, names: dict | None = None) -> Path:
    """Write ``summary.csv``: one row per file, in file order, no timings (reruns give the same file).

    `names` maps each report's file to its name under `out` (default:
    `slicelab.tasks.outputs.output_names` of the reports' files); the column
    ``report`` gives each report's path. The columns are `summary_columns`.

    Examples
    --------
    >>> import tempfile
    >>> p = write_summary(tempfile.mkdtemp(), [], "inspect")
    >>> p.read_text().splitlines()[0].split(",")[:3]
    ['file', 'status', 'reasons']
    """
    keys = [*_FILE, *JOBS[task].columns]
    path = Path(out) / "summary.csv"
    names = names if names is not None else output_names(r["file"] for r in reports)
    with atomic_open(path, "w", encoding="utf-8", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(summary_columns(task))
        for rep in sorted(reports, key=lambda r: r["file"]):
            chk = rep.get("check") or {}
            res = rep.get("results") or {}
            lo, hi = chk.get("bounds") or (None, None)
            size = [hi[k] - lo[k] for k in range(3)] if lo is not None else [None] * 3
            row = {"file": rep["file"], "status": rep["status"],
                   "reasons": ";".join(r["code"] for r in rep["reasons"]),
                   "messages": "; ".join(r["message"] for r in rep["reasons"]),
                   "sha256": (rep.get("input") or {}).get("sha256"), "facets": chk.get("n_facets"),
                   "watertight": chk.get("watertight"), "shells": chk.get("n_shells"),
                   "size_x": size[0], "size_y": size[1], "size_z": size[2], "volume": chk.get("volume")}
            row.update({c: res.get(c) for c in JOBS[task].columns})
            w.writerow([_fmt(_cell(k, row[k])) for k in keys] + [f"{names[rep['file']]}.json"])
    return path


def write_batch_files(out, reports: list[dict], task: str, names: dict | None = None) -> dict:
    """Write the batch's files beside ``summary.csv``: for the profile task the rim-diameter chart,
    ``rim_diameters.png``, and its numbers, ``rim_diameters.csv`` (`slicelab.viz.rims`); for
    another task none, and those of an earlier profile batch into `out` are taken away.

    Returns
    -------
    dict
        ``{"chart": path, "chart_data": path}`` for the profile task, else empty.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> out = pathlib.Path(tempfile.mkdtemp())
    >>> sorted(write_batch_files(out, [], "profile"))
    ['chart', 'chart_data']
    >>> write_batch_files(out, [], "inspect"), sorted(p.name for p in out.iterdir() if p.name[0] != ".")
    ({}, [])
    """
    out = Path(out)
    staged = StagedFolder(out, "batch")
    if task != "profile" and not staged.manifest.exists():  # no earlier chart to take away
        staged.discard()
        return {}
    written = {}
    try:
        if task == "profile":
            from ..viz.rims import rim_chart, rim_chart_png
            png, data = CHART
            chart = rim_chart((r["file"], (r.get("results") or {}).get("rim_diameter"),
                               (r.get("results") or {}).get("rim_eve"), (r.get("results") or {}).get("axis_trusted"))
                              for r in sorted(reports, key=lambda r: r["file"]) if r["status"] != "fail")
            rim_chart_png(chart, staged.staging / png)
            chart.to_csv(staged.staging / data)
            written = {"chart": out / png, "chart_data": out / data}
        staged.commit()
    except BaseException:
        staged.discard()
        raise
    return written
